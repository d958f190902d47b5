//! Quasi-static ball centres (the `quasi_static_balls` fidelity level): the axial and
//! radial position of a ball at which its two race contacts and its centrifugal force
//! balance, found by Newton's method at every evaluation of the right-hand side.
//!
//! The normal loads (Hertz with the contact damping, after any defect drop) and the
//! centrifugal force `m r thd^2` are evaluated at every Newton iterate; the axial and
//! radial components of the traction, rolling-resistance, pocket and drag forces enter as
//! they were at the last accepted step (one step of lag, ~1e-5 s, in forces that change
//! over a ball's passage through the load zone, ~1e-3 s). They are not small in their
//! effect: left out, they move the contact angles enough to change the mean cage speed
//! by 0.17 % at a constant 10000 rpm (docs/reference/model.md).

use crate::model::Model;
use crate::physics::frames::Azimuth;
use crate::physics::race_contact::{contact_geometry, defects_effect_at, Race, RingMotion};
use nalgebra::Vector3;

/// Newton iterations before the last iterate is taken as it is (quadratic convergence
/// from the previous step's position needs 2-4).
const MAX_ITERATIONS: usize = 30;
/// An update below this (m) is the last: with contact deformations of micrometres
/// (`delta` ~ 1e-6..1e-5 m), Newton's error after it is ~`size^2 / delta` <= 1e-12 m,
/// 1e-9 of the ball radius, which changes the loads by ~1e-6 of their size.
const QUADRATIC_RANGE: f64 = 1e-9;

/// Normal force of one contact on the ball in the ball's (axial, radial) plane (N), its
/// derivative with respect to the ball's axial and radial position (N/m), and whether the
/// contact is open (the derivative is then only the steering stiffness, not the force's).
#[inline]
fn contact_in_plane(
    race: &Race,
    ring: &RingMotion,
    centre: &Vector3<f64>,
    velocity: &Vector3<f64>,
    e_r: &Vector3<f64>,
    damping: (f64, f64),
    force_scale: f64,
) -> ([f64; 2], [[f64; 2]; 2], bool) {
    let g = contact_geometry(race, ring, centre);
    let u = [g.normal.x, g.normal.dot(e_r)];
    let outer = [[u[0] * u[0], u[0] * u[1]], [u[1] * u[0], u[1] * u[1]]];
    // Out of contact: no force, and a stiffness along the normal that only steers the
    // iteration back towards the race (the residual stays exact): the Hertz stiffness
    // 1.5 k delta^0.5 at the deformation that carries `force_scale`,
    // delta = (force_scale / k)^(2/3), so 1.5 k (force_scale / k)^(1/3).
    let free = || {
        let k = 1.5 * race.hertz.k * (force_scale / race.hertz.k).cbrt();
        let mut j = [[0.0; 2]; 2];
        for a in 0..2 {
            for b in 0..2 {
                j[a][b] = -k * outer[a][b];
            }
        }
        ([0.0; 2], j, true)
    };
    if g.delta <= 0.0 {
        return free();
    }
    let eff = defects_effect_at(race, ring, &g.azimuth);
    let delta = g.delta - eff.drop;
    if delta <= 0.0 {
        return free();
    }
    let k = race.hertz.k;
    let sq = delta.sqrt();
    let (ratio, mass) = damping;
    let ddelta = g.normal.dot(&(velocity - ring.velocity));
    let c_damp = 2.0 * ratio * (1.5 * k * sq * mass).sqrt();
    let q = (k * delta * sq + c_damp * ddelta).max(0.0);
    if q == 0.0 {
        return free();
    }
    // off a defect edge the load is normal (psi = 0 exactly), and cos(0) = 1 needs no libm call
    let cos_psi = if eff.psi == 0.0 { 1.0 } else { eff.psi.cos() };
    let fq = q * cos_psi;
    // d(-q u)/dp = -(dq/d delta) u u^T - (q / dist) (I - u u^T); u is the unit vector
    // from the curvature centre through the ball centre, dist their distance.
    let kn = 1.5 * k * sq * cos_psi;
    let dist = g.delta + race.free_distance;
    let kt = fq / dist;
    let mut j = [[0.0; 2]; 2];
    for a in 0..2 {
        for b in 0..2 {
            let id = if a == b { 1.0 } else { 0.0 };
            j[a][b] = -kn * outer[a][b] - kt * (id - outer[a][b]);
        }
    }
    ([-fq * u[0], -fq * u[1]], j, false)
}

/// Axial and radial position (m) of the ball at azimuth `az` orbiting at `orbit_rate`
/// (rad/s) in equilibrium between the rings, starting from `start` (the last accepted
/// position); `other` is the axial and radial force (N) of everything but the normal
/// loads and the centrifugal force, as it was at the last accepted step.
pub fn ball_equilibrium(
    m: &Model,
    inner: &RingMotion,
    outer: &RingMotion,
    az: &Azimuth,
    orbit_rate: f64,
    start: [f64; 2],
    other: [f64; 2],
) -> Equilibrium {
    let e_r = az.e_r();
    let e_t = az.e_t();
    let mass = m.ball_mass;
    let damping = (m.contact.damping_ratio, m.contact.ball_mass);
    let w2 = orbit_rate * orbit_rate;
    // a force scale: the centrifugal force, or 0.1 N for a ball at rest (a light preload)
    let f_ref = (mass * start[1] * w2).max(0.1);
    let residual = |p: [f64; 2]| {
        let centre = Vector3::new(p[0], 0.0, 0.0) + p[1] * e_r;
        let velocity = p[1] * orbit_rate * e_t;
        let (fi, ji, open_i) = contact_in_plane(
            &m.inner_race,
            inner,
            &centre,
            &velocity,
            &e_r,
            damping,
            f_ref,
        );
        let (fo, jo, open_o) = contact_in_plane(
            &m.outer_race,
            outer,
            &centre,
            &velocity,
            &e_r,
            damping,
            f_ref,
        );
        let r = [
            fi[0] + fo[0] + other[0],
            fi[1] + fo[1] + mass * p[1] * w2 + other[1],
        ];
        // `j` steers Newton (an open contact pulls towards its race); `slope` is the
        // residual's true derivative, without the steering
        let mut j = [[0.0; 2]; 2];
        let mut slope = [[0.0; 2]; 2];
        for a in 0..2 {
            for b in 0..2 {
                j[a][b] = ji[a][b] + jo[a][b];
                let ti = if open_i { 0.0 } else { ji[a][b] };
                let to = if open_o { 0.0 } else { jo[a][b] };
                slope[a][b] = ti + to;
            }
        }
        j[1][1] += mass * w2;
        slope[1][1] += mass * w2;
        (r, j, ji, jo, slope, [open_i, open_o])
    };
    let norm = |r: [f64; 2]| (r[0] * r[0] + r[1] * r[1]).sqrt();
    let mut p = start;
    let (mut r, mut j, mut ji, mut jo, mut slope, mut open) = residual(p);
    for _ in 0..MAX_ITERATIONS {
        if norm(r) == 0.0 {
            break;
        }
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        if det == 0.0 || !det.is_finite() {
            break;
        }
        let mut d = [
            -(j[1][1] * r[0] - j[0][1] * r[1]) / det,
            -(-j[1][0] * r[0] + j[0][0] * r[1]) / det,
        ];
        let size = (d[0] * d[0] + d[1] * d[1]).sqrt();
        if size <= QUADRATIC_RANGE {
            // Newton converges quadratically here: the error left after this update is
            // of order size^2 / delta (~1e-13 m), so the update is the last. The imbalance
            // after it is r + slope d to first order: nil with both contacts closed
            // (slope = j), the steering's share (~1e-2 N at most) with one open.
            p = [p[0] + d[0], p[1] + d[1]];
            r = [
                r[0] + slope[0][0] * d[0] + slope[0][1] * d[1],
                r[1] + slope[1][0] * d[0] + slope[1][1] * d[1],
            ];
            break;
        }
        // a long update may open or close a contact: backtrack while it makes the
        // imbalance worse, as long as a shorter update can help. A trial that opens or
        // closes a contact may be too long to meet the race: halve on. A failed trial in
        // the same contact state as `p` lies where the residual is smooth, and shorter
        // ones only help if the imbalance falls along `d` to first order (r . slope d <
        // 0). With both contacts closed that holds (slope = j, so it is -|r|^2); with one
        // open it may not: a ball that has left a race is held by one contact alone, in
        // no balance nearby (an unloaded ball), and twelve halvings cost twelve residuals
        // for nothing (a third of all residuals on the Table-1 case).
        let falls = {
            let sd = [
                slope[0][0] * d[0] + slope[0][1] * d[1],
                slope[1][0] * d[0] + slope[1][1] * d[1],
            ];
            r[0] * sd[0] + r[1] * sd[1] < 0.0
        };
        let mut accepted = None;
        for _ in 0..12 {
            let trial = [p[0] + d[0], p[1] + d[1]];
            let (rt, jt, jit, jot, st, ot) = residual(trial);
            if norm(rt) <= norm(r) {
                accepted = Some((trial, rt, jt, jit, jot, st, ot));
                break;
            }
            if !falls && ot == open {
                break;
            }
            d = [0.5 * d[0], 0.5 * d[1]];
        }
        let Some((trial, rt, jt, jit, jot, st, ot)) = accepted else {
            break;
        };
        p = trial;
        r = rt;
        j = jt;
        ji = jit;
        jo = jot;
        slope = st;
        open = ot;
    }
    // how the balance moves with the rings: a shift d of a ring's centre (in the ball's
    // plane) shifts that contact's force by -J_ring d, so the balance by J^-1 J_ring d
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    let solve = |m: [[f64; 2]; 2]| {
        if det == 0.0 || !det.is_finite() {
            return [[0.0; 2]; 2];
        }
        let mut out = [[0.0; 2]; 2];
        for c in 0..2 {
            out[0][c] = (j[1][1] * m[0][c] - j[0][1] * m[1][c]) / det;
            out[1][c] = (-j[1][0] * m[0][c] + j[0][0] * m[1][c]) / det;
        }
        out
    };
    Equilibrium {
        centre: p,
        imbalance: r,
        follows_inner: solve(ji),
        follows_outer: solve(jo),
    }
}

/// Where each quasi-static ball's balance stood at the last accepted step and how it
/// follows the rings, so that an evaluation inside the next step starts Newton from the
/// balance moved with the rings (the rings vibrate at kHz, and a ball orbits past their
/// offsets): the same root to the stopping rule's ~1e-12 m, found from a closer start.
#[derive(Debug, Clone, Default)]
pub struct BalanceTrack {
    /// Per ball: the inner ring centre's axial and radial position and the outer ring
    /// centre's radial position in the ball's plane at the last accepted step, m.
    pub rings: Vec<[f64; 3]>,
    /// Per ball: [`Equilibrium::follows_inner`] and [`Equilibrium::follows_outer`] there.
    pub follows: Vec<[[[f64; 2]; 2]; 2]>,
}

impl BalanceTrack {
    pub fn new(z: usize) -> Self {
        BalanceTrack {
            rings: vec![[0.0; 3]; z],
            follows: vec![[[[0.0; 2]; 2]; 2]; z],
        }
    }

    /// The rings' centres in the plane of a ball at `az`: inner axial, inner radial, outer
    /// radial, m.
    #[inline]
    pub fn rings_in_plane(inner: &RingMotion, outer: &RingMotion, az: &Azimuth) -> [f64; 3] {
        let e_r = az.e_r();
        [
            inner.centre.x,
            inner.centre.dot(&e_r),
            outer.centre.dot(&e_r),
        ]
    }

    /// Newton's start for ball `j` from its last accepted position `last` (m) with the
    /// rings now at `now` ([`BalanceTrack::rings_in_plane`]).
    #[inline]
    pub fn start(&self, j: usize, last: [f64; 2], now: [f64; 3]) -> [f64; 2] {
        let then = self.rings[j];
        let [a, b] = self.follows[j];
        let di = [now[0] - then[0], now[1] - then[1]];
        let dor = now[2] - then[2];
        [
            last[0] + a[0][0] * di[0] + a[0][1] * di[1] + b[0][1] * dor,
            last[1] + a[1][0] * di[0] + a[1][1] * di[1] + b[1][1] * dor,
        ]
    }
}

/// A ball's balance and how it follows the rings.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Equilibrium {
    /// Axial and radial position, m.
    pub centre: [f64; 2],
    /// The in-plane force left unbalanced at `centre` (N): nil once Newton converged, the
    /// last residual where it stopped short (a line search that found no decrease, ~2 % of
    /// the solves on the Table-1 case, or the iteration limit).
    pub imbalance: [f64; 2],
    /// Change of `centre` per change of the inner / outer ring centre's axial and radial
    /// position in the ball's plane, -.
    pub follows_inner: [[f64; 2]; 2],
    pub follows_outer: [[f64; 2]; 2],
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::preset_scene;
    use nalgebra::Matrix3;

    /// The preset's model with the inner ring pushed `axial` m along the axis (rings at rest
    /// otherwise), and a ball at azimuth 0 where the rings' free geometry puts it.
    fn setup(axial: f64) -> (Model, RingMotion, RingMotion, Azimuth, [f64; 2]) {
        let m = Model::new(&preset_scene("h7005c").unwrap().validated().unwrap());
        let inner = RingMotion::new(
            Vector3::new(axial, 0.0, 0.0),
            Matrix3::identity(),
            Vector3::zeros(),
            0.0,
            0.0,
        );
        let outer = RingMotion::new(
            Vector3::zeros(),
            Matrix3::identity(),
            Vector3::zeros(),
            0.0,
            0.0,
        );
        let start = [
            0.5 * (m.inner_race.centre_axial + m.outer_race.centre_axial),
            0.5 * m.pitch_diameter,
        ];
        (m, inner, outer, Azimuth::new(0.0), start)
    }

    /// Sum of the in-plane forces on the ball at `p` (N) and its Jacobian (N/m).
    fn balance(
        m: &Model,
        inner: &RingMotion,
        outer: &RingMotion,
        az: &Azimuth,
        w: f64,
        p: [f64; 2],
    ) -> ([f64; 2], [[f64; 2]; 2]) {
        let e_r = az.e_r();
        let centre = Vector3::new(p[0], 0.0, 0.0) + p[1] * e_r;
        let velocity = p[1] * w * az.e_t();
        let damping = (m.contact.damping_ratio, m.contact.ball_mass);
        let (fi, ji, _) =
            contact_in_plane(&m.inner_race, inner, &centre, &velocity, &e_r, damping, 1.0);
        let (fo, jo, _) =
            contact_in_plane(&m.outer_race, outer, &centre, &velocity, &e_r, damping, 1.0);
        let r = [fi[0] + fo[0], fi[1] + fo[1] + m.ball_mass * p[1] * w * w];
        let mut j = [[0.0; 2]; 2];
        for a in 0..2 {
            for b in 0..2 {
                j[a][b] = ji[a][b] + jo[a][b];
            }
        }
        j[1][1] += m.ball_mass * w * w;
        (r, j)
    }

    /// A push of the inner ring that loads both contacts of the ball (found below).
    fn loading_push() -> f64 {
        for push in [2e-5, -2e-5] {
            let (m, inner, outer, az, start) = setup(push);
            let p = ball_equilibrium(&m, &inner, &outer, &az, 0.0, start, [0.0; 2]).centre;
            let (r, _) = balance(&m, &inner, &outer, &az, 0.0, p);
            let e_r = az.e_r();
            let centre = Vector3::new(p[0], 0.0, 0.0) + p[1] * e_r;
            let gi = contact_geometry(&m.inner_race, &inner, &centre);
            if gi.delta > 0.0 && r[0].abs() < 1.0 {
                return push;
            }
        }
        panic!("neither axial push loads the ball");
    }

    /// The analytic Jacobian is what Newton's quadratic convergence rests on: it matches
    /// central differences (steps of 1e-9 m, ~1e-4 of the deformation: truncation error
    /// ~1e-8 relative) to 1e-5 of its largest entry.
    #[test]
    fn jacobian_matches_finite_differences() {
        let push = loading_push();
        let (m, inner, outer, az, start) = setup(push);
        let w = 1000.0;
        let p = ball_equilibrium(&m, &inner, &outer, &az, w, start, [0.0; 2]).centre;
        // a point off equilibrium, both contacts still loaded
        let p = [p[0] + 3e-7, p[1] - 2e-7];
        let (_, j) = balance(&m, &inner, &outer, &az, w, p);
        let h = 1e-9;
        let scale = j.iter().flatten().fold(0.0_f64, |a, v| a.max(v.abs()));
        for b in 0..2 {
            let mut plus = p;
            let mut minus = p;
            plus[b] += h;
            minus[b] -= h;
            let (rp, _) = balance(&m, &inner, &outer, &az, w, plus);
            let (rm, _) = balance(&m, &inner, &outer, &az, w, minus);
            for a in 0..2 {
                let fd = (rp[a] - rm[a]) / (2.0 * h);
                assert!(
                    (fd - j[a][b]).abs() < 1e-5 * scale,
                    "d r{a} / d p{b}: analytic {:.6e}, differences {fd:.6e}",
                    j[a][b]
                );
            }
        }
    }

    /// The balance follows the rings as `follows_inner` / `follows_outer` say, to first
    /// order: after the rings move by a step's worth of their vibration (~1e-7 m), the
    /// tracked start is a few per cent of the move from the new root (second-order terms,
    /// ~ move / (4 delta) with a light load's delta of a few tenths of a micrometre here),
    /// where the last position is the whole move away; halving the move quarters that
    /// error (0.3 allows for the third-order rest).
    #[test]
    fn the_tracked_start_follows_the_rings() {
        let push = loading_push();
        let (m, inner, outer, az, start) = setup(push);
        let w = 1000.0;
        let eq = ball_equilibrium(&m, &inner, &outer, &az, w, start, [0.0; 2]);
        let mut track = BalanceTrack::new(1);
        track.rings[0] = BalanceTrack::rings_in_plane(&inner, &outer, &az);
        track.follows[0] = [eq.follows_inner, eq.follows_outer];
        let dist =
            |a: [f64; 2], b: [f64; 2]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
        // (how far the root moved, how far the tracked start is from it), m
        let after = |size: f64| {
            let ring = |r: &RingMotion, d: Vector3<f64>| {
                RingMotion::new(
                    r.centre + d,
                    Matrix3::identity(),
                    Vector3::zeros(),
                    0.0,
                    0.0,
                )
            };
            let mi = ring(&inner, Vector3::new(size, 0.0, -size));
            let mo = ring(&outer, Vector3::new(0.0, 0.0, 0.5 * size));
            let root = ball_equilibrium(&m, &mi, &mo, &az, w, eq.centre, [0.0; 2]).centre;
            let now = BalanceTrack::rings_in_plane(&mi, &mo, &az);
            (
                dist(eq.centre, root),
                dist(track.start(0, eq.centre, now), root),
            )
        };
        let (moved, error) = after(1e-7);
        assert!(moved > 3e-8, "the balance moved {moved} m");
        assert!(
            error < 0.1 * moved,
            "tracked start {error:.3e} m off, move {moved:.3e} m"
        );
        let (_, error_half) = after(0.5e-7);
        assert!(
            error_half < 0.3 * error,
            "not second order: {error_half:.3e} m at half the move, {error:.3e} m"
        );
    }

    /// From a start 2 um away (a step's worth of ball motion many times over), Newton lands
    /// on the same position, where the forces balance to 1e-6 of the contact load (the
    /// stopping rule's ~1e-12 m error times a stiffness of ~1e8 N/m is ~1e-4 N on ~100 N).
    #[test]
    fn equilibrium_balances_the_forces() {
        let push = loading_push();
        let (m, inner, outer, az, start) = setup(push);
        let w = 1000.0;
        let p = ball_equilibrium(&m, &inner, &outer, &az, w, start, [0.0; 2]).centre;
        let q = ball_equilibrium(
            &m,
            &inner,
            &outer,
            &az,
            w,
            [p[0] + 2e-6, p[1] - 2e-6],
            [0.0; 2],
        )
        .centre;
        let (r, _) = balance(&m, &inner, &outer, &az, w, q);
        let e_r = az.e_r();
        let centre = Vector3::new(q[0], 0.0, 0.0) + q[1] * e_r;
        let gi = contact_geometry(&m.inner_race, &inner, &centre);
        let load = m.inner_race.hertz.k * gi.delta.powf(1.5);
        assert!(load > 1.0, "the ball is loaded: {load} N");
        assert!(
            (r[0] * r[0] + r[1] * r[1]).sqrt() < 1e-6 * load,
            "imbalance {r:?} N at a load of {load:.3} N"
        );
        assert!(
            (p[0] - q[0]).abs() < 1e-11 && (p[1] - q[1]).abs() < 1e-11,
            "{p:?} vs {q:?}"
        );
    }
}
