//! Defects are never stepped over: every step ends no later than the next point where a
//! ball meets a defect's profile change (its entry edge, its centre, its exit edge).

use crate::model::layout::ball;
use crate::model::Model;
use crate::physics::cpu::twice_compiled;
use crate::physics::defect::wrap_angle;
use std::f64::consts::TAU;

/// A ball within this fraction of a defect's half-angle of one of its points is taken to be
/// on it (the step that landed there extrapolated the orbit linearly), so the bound looks
/// to the next point instead of asking for a sliver step.
const ON_POINT: f64 = 1e-3;

twice_compiled! {
    /// Largest step after which no ball has passed the entry edge, the centre or the exit
    /// edge of any defect, at its present orbital rate relative to the defect's ring.
    ///
    /// Where the ball meets those points the defect's drop (eq. 34) has a kink and its load
    /// direction (eq. 36) a jump at the centre; a step that ends on them keeps each step's
    /// right-hand side smooth, so the error control sets the steps inside a crossing.
    ///
    /// Compiled twice (`physics::cpu`): the baseline copy's `trunc` and `mul_add` in
    /// [`rem_turn`](crate::physics::defect::rem_turn) are library calls, the AVX2 copy's
    /// one instruction each (the same numbers).
    pub fn defect_step_bound(m: &Model, t: f64, y: &[f64]) -> f64
        = step_bound_body, wide step_bound_avx2;
}

/// [`defect_step_bound`]'s body, in both copies.
#[inline(always)]
fn step_bound_body(m: &Model, t: f64, y: &[f64]) -> f64 {
    let mut bound = f64::INFINITY;
    let shaft = m.shaft_angle(t);
    let ws = m.shaft_speed(t);
    for (race, ring_angle, ring_speed) in [(&m.inner_race, shaft, ws), (&m.outer_race, 0.0, 0.0)] {
        for d in &race.defects {
            for j in 0..m.z {
                let b = m.layout.ball(j);
                let rel = y[b + ball::THETA_DOT] - ring_speed;
                if rel.abs() < 1e-9 {
                    continue;
                }
                // the ball's angle from the defect centre, along its motion
                let delta = wrap_angle(y[b + ball::THETA] - ring_angle - d.angle) * rel.signum();
                let near = ON_POINT * d.half_angle;
                let ahead = [-d.half_angle, 0.0, d.half_angle]
                    .into_iter()
                    .map(|p| within_a_turn(p - delta))
                    .filter(|&a| a > near && a < TAU - near)
                    .fold(f64::INFINITY, f64::min);
                bound = bound.min(ahead / rel.abs());
            }
        }
    }
    bound
}

/// `x.rem_euclid(TAU)` for `|x| < TAU`, to the bit, without its `fmod` (three a ball and
/// defect at every step, about 1 % of the Table-1 case's instructions): there `x % TAU` is
/// `x` exactly, so `rem_euclid` adds `TAU` to a negative `x` and returns the rest as they
/// are (`-0` too). The bound's arguments are a point (at most a half-angle, below pi, from
/// the centre) less a wrapped angle (at most pi): below `TAU` in size.
#[inline]
fn within_a_turn(x: f64) -> f64 {
    debug_assert!(x.is_nan() || x.abs() < TAU, "{x}");
    if x < 0.0 {
        x + TAU
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{fault_case_scene, FaultCase};

    /// Ball 0 orbiting at `rate` (rad/s) at `offset` half-angles from the outer defect's
    /// centre, every other ball at rest (so only ball 0 bounds the step); the bound in
    /// units of the time to cross one half-angle.
    fn bound_at(offset: f64) -> f64 {
        let s = fault_case_scene("h7005c", FaultCase::Outer).unwrap();
        let m = Model::new(&s.validated().unwrap());
        let d = m.outer_race.defects[0];
        let rate = 400.0;
        let mut y = vec![0.0; m.layout.len];
        let b = m.layout.ball(0);
        y[b + ball::THETA] = d.angle + offset * d.half_angle;
        y[b + ball::THETA_DOT] = rate;
        defect_step_bound(&m, 0.0, &y) * rate / d.half_angle
    }

    /// The copy this processor runs is the baseline copy to the bit (`physics::cpu`), over
    /// every ball at spread orbit angles (hundreds of radians, both signs), rates and
    /// shaft times, for each fault case.
    #[test]
    fn the_two_copies_agree_to_the_bit() {
        for case in [FaultCase::Inner, FaultCase::Outer, FaultCase::Compound] {
            let s = fault_case_scene("h7005c", case).unwrap();
            let m = Model::new(&s.validated().unwrap());
            let mut y = vec![0.0; m.layout.len];
            for k in 0..2000 {
                for j in 0..m.z {
                    let b = m.layout.ball(j);
                    let x = (k * m.z + j) as f64;
                    y[b + ball::THETA] = (x * 0.377).sin() * 900.0 + 0.013 * x;
                    y[b + ball::THETA_DOT] = 300.0 + (x * 0.71).cos() * 250.0;
                }
                let t = 1e-4 * k as f64;
                assert_eq!(
                    defect_step_bound(&m, t, &y).to_bits(),
                    step_bound_body(&m, t, &y).to_bits(),
                    "{case:?} {k}"
                );
            }
        }
    }

    /// `within_a_turn` is `rem_euclid(TAU)` to the bit over the arguments it takes: both
    /// signs of zero, the ends, and a spread in between.
    #[test]
    fn within_a_turn_is_rem_euclid() {
        // the largest number below a turn
        let below = f64::from_bits(TAU.to_bits() - 1);
        let mut xs = vec![
            0.0,
            -0.0,
            below,
            -below,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
        ];
        for k in 1..20000 {
            let x = below * k as f64 / 20000.0;
            xs.extend([x, -x, x * 1e-9, -x * 1e-9]);
        }
        for x in xs {
            assert_eq!(
                within_a_turn(x).to_bits(),
                x.rem_euclid(TAU).to_bits(),
                "{x}"
            );
        }
    }

    /// A step ends on the next of the entry edge, the centre and the exit edge; a ball on a
    /// point (within the landing tolerance) looks to the next one; past the exit the next
    /// point is the entry a turn later. Tolerance 1e-9: the bound is one division.
    #[test]
    fn steps_end_on_the_next_defect_point() {
        for (offset, expected) in [
            (-3.0, 2.0),
            (-1.0, 1.0),
            (-1.0 + 1e-5, 1.0 - 1e-5),
            (-0.25, 0.25),
            (0.0, 1.0),
            (0.5, 0.5),
        ] {
            let got = bound_at(offset);
            assert!(
                (got - expected).abs() < 1e-9,
                "at {offset} half-angles: {got}, expected {expected}"
            );
        }
        // past the exit edge: the entry a turn later
        let s = fault_case_scene("h7005c", FaultCase::Outer).unwrap();
        let half = Model::new(&s.validated().unwrap()).outer_race.defects[0].half_angle;
        for (offset, expected) in [
            (1.5, (TAU - 2.5 * half) / half),
            // on the exit edge (within the landing tolerance)
            (1.0 - 1e-4, (TAU - (2.0 - 1e-4) * half) / half),
        ] {
            let got = bound_at(offset);
            assert!(
                (got - expected).abs() < 1e-9 * expected,
                "at {offset} half-angles: {got}, expected {expected}"
            );
        }
    }
}
