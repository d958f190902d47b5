//! Ball-pocket interactions four at a time: what
//! [`pocket_contact`](super::cage_pocket::pocket_contact) gives each ball, to the bit, in
//! the lanes of [`F64x4`].
//!
//! Every lane takes the same operations in the same order as the scalar function (tested
//! bit for bit): the squeeze film, the Hertz load and the friction are computed in every
//! lane and each lane keeps its own branch's. Compiled twice, as the race contacts are
//! (`super::cpu`).

use super::cage_pocket::{CageMotion, PocketParams, PocketResult, FRICTION_REGULARIZATION};
use super::cpu::twice_compiled;
use super::frames::Azimuth;
use super::lanes::{F64x4, Vec3x4, LANES};
use super::race_contact::BallMotion;
use std::f64::consts::PI;

/// The interactions of `balls` with their pockets at inertial azimuths `pockets` on `cage`,
/// into `out` (all three as long): each
/// [`pocket_contact`](super::cage_pocket::pocket_contact)'s result, to the bit.
pub fn pocket_contacts(
    p: &PocketParams,
    cage: &CageMotion,
    pockets: &[Azimuth],
    balls: &[BallMotion],
    out: &mut [PocketResult],
) {
    debug_assert!(pockets.len() == balls.len() && balls.len() == out.len());
    let groups = pockets.chunks(LANES).zip(balls.chunks(LANES));
    for ((pockets, balls), out) in groups.zip(out.chunks_mut(LANES)) {
        pockets_of_group(p, cage, pockets, balls, out);
    }
}

twice_compiled! {
    /// One group, in the copy this processor runs (`super::cpu`).
    fn pockets_of_group(
        p: &PocketParams,
        cage: &CageMotion,
        pockets: &[Azimuth],
        balls: &[BallMotion],
        out: &mut [PocketResult],
    ) = group, wide group_avx2;
}

/// Up to [`LANES`] balls (a short group repeats its last ball in lanes not read).
#[inline(always)]
fn group(
    p: &PocketParams,
    cage: &CageMotion,
    pockets: &[Azimuth],
    balls: &[BallMotion],
    out: &mut [PocketResult],
) {
    let last = balls.len() - 1;
    let zero = F64x4::splat(0.0);
    let mut ball_centre = Vec3x4::ZERO;
    let mut ball_velocity = Vec3x4::ZERO;
    let mut ball_omega = Vec3x4::ZERO;
    let mut e_r = Vec3x4::ZERO;
    for l in 0..LANES {
        let b = &balls[l.min(last)];
        ball_centre.set_lane(l, &b.centre);
        ball_velocity.set_lane(l, &b.velocity);
        ball_omega.set_lane(l, &b.omega);
        e_r.set_lane(l, &pockets[l.min(last)].e_r());
    }
    // `pocket_centre_and_axis`
    let axis = e_r.rotated(&cage.rot);
    let cage_centre = Vec3x4::splat(&cage.centre);
    let centre = cage_centre + axis.scale(F64x4::splat(p.pocket_radius));
    // eqs. 19 and 21
    let w = ball_centre - centre;
    let w_perp = w - axis.scale(w.dot(axis));
    let dist = w_perp.norm_squared().sqrt();
    let film = F64x4::splat(p.clearance) - dist;
    let n = w_perp.divided(dist);
    let r_contact = n.scale(F64x4::splat(p.ball_radius));
    let point = ball_centre + r_contact;
    let v_cage_pt =
        Vec3x4::splat(&cage.velocity) + Vec3x4::splat(&cage.omega).cross(point - cage_centre);
    let v_ball_pt = ball_velocity + ball_omega.cross(r_contact);
    let dfilm = -n.dot(ball_velocity - v_cage_pt);
    let critical = F64x4::splat(p.critical_film);
    let h_eff = film.max(critical);
    let squeeze_coef = 6.0 * PI * p.viscosity * p.ball_radius * p.ball_radius;
    let squeeze = (squeeze_coef * -dfilm / h_eff).max(zero);
    let pen = critical - film;
    let penetrating = zero.lt(pen);
    // Hertz plus film damping, where the film is below the critical one (other lanes'
    // square roots of negative numbers are not kept)
    let sq = pen.sqrt();
    let k = p.hertz.k;
    let c = (2.0 * p.damping_ratio) * (((1.5 * k) * sq) * F64x4::splat(p.damping_mass)).sqrt();
    let hertz = F64x4::select(penetrating, (k * pen * sq + c * -dfilm).max(zero), zero);
    let normal = squeeze + hertz;
    let mut f_ball = n.scale(-normal);
    let mut m_ball = Vec3x4::ZERO;
    if p.friction > 0.0 {
        let v = v_ball_pt - v_cage_pt;
        let v = v - n.scale(v.dot(n));
        let sp = v.norm_squared().sqrt();
        let scale = p.friction
            * hertz
            * (sp / F64x4::splat(FRICTION_REGULARIZATION)).min(F64x4::splat(1.0))
            / sp;
        let fr = v.scale(-scale);
        let slipping: [bool; LANES] = std::array::from_fn(|l| hertz.0[l] > 0.0 && sp.0[l] > 0.0);
        f_ball = Vec3x4::select(slipping, f_ball + fr, f_ball);
        m_ball = Vec3x4::select(slipping, r_contact.cross(fr), Vec3x4::ZERO);
    }
    let on_cage = -f_ball;
    let moment_on_cage = (point - cage_centre).cross(on_cage);
    for (l, o) in out.iter_mut().enumerate() {
        *o = PocketResult {
            film: film.0[l],
            ..Default::default()
        };
        // as `pocket_contact` returns early: a ball on the pocket's axis, or no load
        if dist.0[l] < 1e-12 || normal.0[l] == 0.0 {
            continue;
        }
        o.normal = normal.0[l];
        o.force_on_ball = f_ball.lane(l);
        o.moment_on_ball = m_ball.lane(l);
        o.force_on_cage = on_cage.lane(l);
        o.moment_on_cage = moment_on_cage.lane(l);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::cage_pocket::{example_params, pocket_centre_and_axis, pocket_contact};
    use crate::physics::frames::cardan;
    use nalgebra::Vector3;

    /// Every lane is `pocket_contact`'s result to the bit: balls from the pocket's axis out
    /// past the clearance (squeeze only, Hertz with and without friction, no load, on the
    /// axis), at pockets all round a tilted, moving, spinning cage, in groups of one to four;
    /// and a ball pressed into a still cage's pocket without slip (Hertz with friction on,
    /// no slip speed). Both copies: the one this processor runs (`pocket_contacts`) and the
    /// baseline one (`group`, called directly).
    #[test]
    fn pockets_side_by_side_are_the_pockets_one_by_one() {
        let p = example_params();
        let cage = CageMotion {
            centre: Vector3::new(1e-6, -2e-5, 3e-5),
            velocity: Vector3::new(0.0, 1e-3, -2e-3),
            rot: cardan(0.0, 1e-3, -2e-3).transpose(),
            spin_angle: 0.3,
            omega: Vector3::new(440.0, 0.5, -0.2),
        };
        let mut kinds = [0usize; 5];
        for friction in [0.08, 0.0] {
            let p = PocketParams { friction, ..p };
            let mut pockets = Vec::new();
            let mut balls = Vec::new();
            for k in 0..64 {
                let pocket = Azimuth::new(0.3 + 0.39 * k as f64);
                let (centre, axis) = pocket_centre_and_axis(&p, &cage, &pocket);
                // across the axis: from on it to past the clearance
                let across = cage.rot * pocket.e_t();
                let offset = [0.0, 0.5, 0.9, 0.995, 0.9999, 1.002][k % 6] * p.clearance;
                let approach = [-0.02, 0.0, 0.03, -0.3][k % 4];
                balls.push(BallMotion {
                    centre: centre + offset * across + 1e-4 * axis,
                    velocity: Vector3::new(0.1, 9.0, -4.0) + approach * across,
                    omega: Vector3::new(-3000.0, 200.0 * (k as f64).sin(), 50.0),
                });
                pockets.push(pocket);
            }
            for size in 1..=LANES {
                for first in (0..pockets.len()).step_by(size) {
                    let end = (first + size).min(pockets.len());
                    let mut out = vec![PocketResult::default(); end - first];
                    pocket_contacts(
                        &p,
                        &cage,
                        &pockets[first..end],
                        &balls[first..end],
                        &mut out,
                    );
                    let mut baseline = vec![PocketResult::default(); end - first];
                    group(
                        &p,
                        &cage,
                        &pockets[first..end],
                        &balls[first..end],
                        &mut baseline,
                    );
                    let both = out.iter().zip(&baseline);
                    for (k, (got, got_baseline)) in (first..end).zip(both) {
                        let b = &balls[k];
                        let want = pocket_contact(
                            &p,
                            &cage,
                            &pockets[k],
                            &b.centre,
                            &b.velocity,
                            &b.omega,
                        );
                        let bits = |r: &PocketResult| {
                            let v = [
                                r.force_on_ball,
                                r.moment_on_ball,
                                r.force_on_cage,
                                r.moment_on_cage,
                            ];
                            (
                                r.film.to_bits(),
                                r.normal.to_bits(),
                                v.map(|v| v.map(f64::to_bits)),
                            )
                        };
                        assert_eq!(bits(got), bits(&want), "ball {k}: {got:?} {want:?}");
                        assert_eq!(bits(got_baseline), bits(&want), "ball {k}, baseline");
                        let kind = if want.normal == 0.0 {
                            // unloaded off the axis; on it (to rounding: the early return)
                            if p.clearance - want.film < 1e-12 {
                                4
                            } else {
                                0
                            }
                        } else if want.film > p.critical_film {
                            1
                        } else if want.moment_on_ball == Vector3::zeros() {
                            2
                        } else {
                            3
                        };
                        kinds[kind] += 1;
                    }
                }
            }
        }
        // no load, squeeze only, Hertz without and with friction, on the axis
        assert!(kinds.iter().all(|&n| n > 0), "{kinds:?}");
        // pressed into a still cage's pocket, at rest: Hertz load, friction on, no slip
        let still = CageMotion {
            centre: Vector3::zeros(),
            velocity: Vector3::zeros(),
            rot: cardan(0.0, 0.0, 0.0),
            spin_angle: 0.0,
            omega: Vector3::zeros(),
        };
        let pocket = Azimuth::new(0.0);
        let (centre, _) = pocket_centre_and_axis(&p, &still, &pocket);
        let across = still.rot * pocket.e_t();
        let ball = BallMotion {
            centre: centre + (p.clearance + 1e-6) * across,
            velocity: Vector3::zeros(),
            omega: Vector3::zeros(),
        };
        let want = pocket_contact(
            &p,
            &still,
            &pocket,
            &ball.centre,
            &ball.velocity,
            &ball.omega,
        );
        assert!(want.normal > 0.0 && want.moment_on_ball == Vector3::zeros());
        let mut got = [PocketResult::default()];
        pocket_contacts(&p, &still, &[pocket], &[ball], &mut got);
        assert_eq!(
            (
                got[0].normal.to_bits(),
                got[0].force_on_ball.map(f64::to_bits)
            ),
            (want.normal.to_bits(), want.force_on_ball.map(f64::to_bits))
        );
        assert_eq!(got[0].moment_on_ball, Vector3::zeros());
    }
}
