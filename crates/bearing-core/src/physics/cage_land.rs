//! Cage-land interaction (eqs. 23-28).
//!
//! Above the critical film the guiding land is a short journal bearing (half-Sommerfeld
//! film), in its dynamic form: with eccentricity ratio `e`, whirl speed `phi'` of the cage
//! centre about the land centre, entraining speed `U = (w_cage + w_ring - 2 phi') R`
//! (eq. 27 with the whirl correction), width `L` and radial clearance `c`:
//! radial `eta U L^3 e^2 / (c^2 (1 - e^2)^2) + pi eta R L^3 (1 + 2 e^2) e' / (2 c^2 (1 - e^2)^2.5)`
//! (the second term is the squeeze film), tangential
//! `pi eta U L^3 e / (4 c^2 (1 - e^2)^1.5) + 2 eta R L^3 e e' / (c^2 (1 - e^2)^2)`, and the
//! viscous drag torque `2 pi eta R^3 L (w_cage - w_ring) / (c sqrt(1 - e^2))` (Petroff,
//! eccentric). For a cage that does not whirl these are eq. 26's forces (with Ocvirk's `e`
//! in the tangential term where the paper prints `e^2`); the whirl correction is what
//! keeps a nearly unloaded cage from whirling without bound (see docs/reference/model.md).
//! Below the critical film the cage touches the land: a line contact of stiffness
//! `(pi / 4) E' L` with damping and Coulomb friction. The film formulas are evaluated at
//! most at the critical eccentricity, so forces stay bounded and continuous.
//!
//! A tilted cage meets the land with a film that varies along the axis. The short-bearing
//! pressure is parabolic across the width, so the land is integrated over its width with
//! the two-point Gauss rule for that weight (stations at `+-L / (2 sqrt 5)`, half the force
//! each): an aligned cage gets exactly the forces above, a tilted one also the restoring
//! and damping moment of the film (`land_on_cage`).

use nalgebra::Vector3;
use std::f64::consts::PI;

/// Constant data of the cage-land pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LandParams {
    /// Radial clearance c, m.
    pub clearance: f64,
    /// Land (guiding surface) radius R, m.
    pub radius: f64,
    /// Cage width L, m.
    pub width: f64,
    /// Dynamic viscosity, Pa s.
    pub viscosity: f64,
    /// Critical film, m.
    pub critical_film: f64,
    /// Contact stiffness of the cage rim on the land, N/m.
    pub contact_stiffness: f64,
    /// Coulomb friction coefficient, -.
    pub friction: f64,
    /// Viscous damping of the rim contact, N s/m.
    pub contact_damping: f64,
}

/// Force (inertial) and axial torque on the cage from its guiding land.
#[derive(Debug, Clone, Copy, Default)]
pub struct LandResult {
    pub eccentricity_ratio: f64,
    pub force_on_cage: Vector3<f64>,
    /// Moment about the cage axis, N m.
    pub torque_on_cage: f64,
}

/// Axial station of the two-point Gauss rule for the parabolic pressure profile
/// `(L^2/4 - z^2)`, as a fraction of the width L: `1 / (2 sqrt 5)`.
pub const GAUSS_STATION: f64 = 0.223_606_797_749_979;

/// A body as the land sees it: centre, its velocity, its axis and its tilt rate (inertial).
#[derive(Debug, Clone, Copy)]
pub struct AxisMotion {
    /// Centre, m.
    pub centre: Vector3<f64>,
    /// Centre velocity, m/s.
    pub velocity: Vector3<f64>,
    /// Unit vector along the body axis (tilted X axis), -.
    pub axis: Vector3<f64>,
    /// Angular velocity without the spin about the axis, rad/s.
    pub tilt_rate: Vector3<f64>,
    /// Spin about the axis, rad/s.
    pub spin: f64,
}

/// Forces and moments of the land on the cage and on the guiding ring.
#[derive(Debug, Clone, Copy, Default)]
pub struct LandOnCage {
    /// Mean eccentricity ratio of the two stations, -.
    pub eccentricity_ratio: f64,
    /// Force on the cage, N (the ring gets the opposite).
    pub force_on_cage: Vector3<f64>,
    /// Moment on the cage about its centre from the film's axial distribution, N m.
    pub moment_on_cage: Vector3<f64>,
    /// Moment on the ring about its centre, N m.
    pub moment_on_ring: Vector3<f64>,
    /// Moment about the cage axis (drag and rim friction), N m.
    pub torque_on_cage: f64,
}

/// The land over its width: `land_force` at the two Gauss stations, half weight each.
#[inline]
pub fn land_on_cage(p: &LandParams, cage: &AxisMotion, ring: &AxisMotion) -> LandOnCage {
    let mut out = LandOnCage::default();
    for sign in [-1.0, 1.0] {
        let s = sign * GAUSS_STATION * p.width;
        let arm_c = s * cage.axis;
        let arm_r = s * ring.axis;
        let rel_pos = (cage.centre + arm_c) - (ring.centre + arm_r);
        let rel_vel = (cage.velocity + cage.tilt_rate.cross(&arm_c))
            - (ring.velocity + ring.tilt_rate.cross(&arm_r));
        let r = land_force(p, &rel_pos, &rel_vel, cage.spin, ring.spin);
        let f = 0.5 * r.force_on_cage;
        out.eccentricity_ratio += 0.5 * r.eccentricity_ratio;
        out.force_on_cage += f;
        out.moment_on_cage += arm_c.cross(&f);
        out.moment_on_ring -= arm_r.cross(&f);
        out.torque_on_cage += 0.5 * r.torque_on_cage;
    }
    out
}

/// `rel_pos`/`rel_vel`: cage centre relative to the guiding ring centre (only Y, Z used).
#[inline]
pub fn land_force(
    p: &LandParams,
    rel_pos: &Vector3<f64>,
    rel_vel: &Vector3<f64>,
    cage_spin: f64,
    ring_spin: f64,
) -> LandResult {
    let e = (rel_pos.y * rel_pos.y + rel_pos.z * rel_pos.z).sqrt();
    let c = p.clearance;
    let eps = e / c;
    let eps_crit = 1.0 - p.critical_film / c;
    let eh = eps.min(eps_crit);
    let one = 1.0 - eh * eh;
    let eta = p.viscosity;
    let (l, r) = (p.width, p.radius);
    let dw = cage_spin - ring_spin;
    // `one^1.5` and `one^2.5` below from this root: libm's `pow` twice a station, four times
    // a right-hand side, was 0.7 % of the Table-1 case's time
    let root = one.sqrt();
    let mut torque = -2.0 * PI * eta * r * r * r * l * dw / (c * root);
    let mut force = Vector3::zeros();
    if e > 1e-15 {
        let eh_hat = Vector3::new(0.0, rel_pos.y / e, rel_pos.z / e);
        let t_hat = Vector3::x().cross(&eh_hat);
        // whirl: angular speed of the cage centre about the land centre
        let whirl = t_hat.dot(rel_vel) / e;
        let u = (cage_spin + ring_spin - 2.0 * whirl) * r;
        let k0 = eta * l * l * l / (c * c);
        let de = eh_hat.dot(rel_vel) / c;
        let w_r = k0 * u * eh * eh / (one * one);
        let w_t = 0.25 * PI * k0 * u * eh / (one * root) + 2.0 * k0 * r * eh * de / (one * one);
        let w_sq = 0.5 * PI * k0 * r * (1.0 + 2.0 * eh * eh) * de / (one * one * root);
        force += -(w_r + w_sq) * eh_hat + w_t * t_hat;
        let pen = e - c * eps_crit;
        if pen > 0.0 {
            let fc = (p.contact_stiffness * pen + p.contact_damping * eh_hat.dot(rel_vel)).max(0.0);
            force -= fc * eh_hat;
            // cage rim slides on the land at (w_cage - w_ring) R along t_hat
            let slide = dw * r;
            let fr = -p.friction * fc * (slide / 1e-2).clamp(-1.0, 1.0);
            force += fr * t_hat;
            torque += fr * r;
        }
    }
    LandResult {
        eccentricity_ratio: eps,
        force_on_cage: force,
        torque_on_cage: torque,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> LandParams {
        // H7005C outer land: 0.1 mm radial clearance, 19.6 mm radius, 8 mm wide cage
        LandParams {
            clearance: 1e-4,
            radius: 19.635e-3,
            width: 8e-3,
            viscosity: 4.44e-3,
            critical_film: 3e-6,
            contact_stiffness: 4.6e8,
            friction: 0.08,
            contact_damping: 50.0,
        }
    }

    fn body(centre: Vector3<f64>, axis: Vector3<f64>, spin: f64) -> AxisMotion {
        AxisMotion {
            centre,
            velocity: Vector3::zeros(),
            axis: axis.normalize(),
            tilt_rate: Vector3::zeros(),
            spin,
        }
    }

    #[test]
    fn steady_offset_cage_gets_the_short_bearing_forces() {
        // Ocvirk's short-bearing load components written out independently:
        // radial eta U L^3 e^2 / (c^2 (1 - e^2)^2), tangential pi eta U L^3 e / (4 c^2 (1 - e^2)^1.5).
        let p = params();
        let eps: f64 = 0.4;
        let (wc, wr) = (450.0, 0.0);
        let r = land_force(
            &p,
            &Vector3::new(0.0, 0.0, eps * p.clearance),
            &Vector3::zeros(),
            wc,
            wr,
        );
        let u = (wc + wr) * p.radius;
        let k = p.viscosity * u * p.width.powi(3) / (p.clearance * p.clearance);
        let radial = k * eps * eps / (1.0 - eps * eps).powi(2);
        let tangential = 0.25 * PI * k * eps / (1.0 - eps * eps).powf(1.5);
        // displacement along +Z: radial pushes back along -Z, tangential along X x Z = -Y
        assert!((r.force_on_cage.z + radial).abs() < 1e-12 * radial);
        assert!((r.force_on_cage.y + tangential).abs() < 1e-12 * tangential);
        assert!((r.eccentricity_ratio - eps).abs() < 1e-15);
    }

    #[test]
    fn aligned_cage_over_the_width_equals_the_centre_formula() {
        let p = params();
        let cage = AxisMotion {
            velocity: Vector3::new(0.0, 1e-3, -2e-3),
            ..body(Vector3::new(0.0, 2e-5, 3e-5), Vector3::x(), 450.0)
        };
        let ring = body(Vector3::new(0.0, 1e-6, 0.0), Vector3::x(), 0.0);
        let w = land_on_cage(&p, &cage, &ring);
        let c = land_force(
            &p,
            &(cage.centre - ring.centre),
            &(cage.velocity - ring.velocity),
            cage.spin,
            ring.spin,
        );
        // same film at both stations: the halves add up to the centre formula (rounding)
        assert!((w.force_on_cage - c.force_on_cage).norm() < 1e-12 * c.force_on_cage.norm());
        assert!((w.torque_on_cage - c.torque_on_cage).abs() < 1e-12 * c.torque_on_cage.abs());
        assert!(w.moment_on_cage.norm() < 1e-12 * c.force_on_cage.norm() * p.width);
    }

    #[test]
    fn tilted_cage_touching_the_land_is_pushed_back() {
        // Centred cage tilted about Z by 0.07 rad: the stations (1.79 mm from the centre)
        // sit 0.125 mm off the land axis, beyond the 0.097 mm critical eccentricity, so the rim contact acts at both ends and
        // its moment opposes the tilt (negative about Z for a positive tilt).
        let p = params();
        let beta = 0.07_f64;
        let cage = body(Vector3::zeros(), Vector3::new(1.0, beta, 0.0), 0.0);
        let ring = body(Vector3::zeros(), Vector3::x(), 0.0);
        let w = land_on_cage(&p, &cage, &ring);
        let s = GAUSS_STATION * p.width;
        assert!(s * beta > p.clearance - p.critical_film);
        assert!(w.moment_on_cage.z < 0.0, "{:?}", w.moment_on_cage);
        // no net force: the two ends push in opposite directions
        assert!(w.force_on_cage.norm() < 1e-9 * w.moment_on_cage.norm() / s);
    }

    #[test]
    fn stations_carry_the_second_moment_of_the_parabolic_pressure() {
        // int z^2 (L^2/4 - z^2) dz / int (L^2/4 - z^2) dz over the width = L^2 / 20
        assert!((GAUSS_STATION * GAUSS_STATION - 1.0 / 20.0).abs() < 1e-15);
    }

    #[test]
    fn tilted_ring_and_aligned_cage_turn_towards_each_other() {
        // The guiding ring tilted 0.07 rad about Z, the cage aligned and centred: the rim
        // touches at both stations; the ring is turned back (negative about Z) and the
        // cage towards the ring (positive), with no net force.
        let p = params();
        let cage = body(Vector3::zeros(), Vector3::x(), 0.0);
        let ring = body(Vector3::zeros(), Vector3::new(1.0, 0.07, 0.0), 0.0);
        let w = land_on_cage(&p, &cage, &ring);
        assert!(w.moment_on_ring.z < 0.0, "{:?}", w.moment_on_ring);
        assert!(w.moment_on_cage.z > 0.0, "{:?}", w.moment_on_cage);
        assert!(w.force_on_cage.norm() < 1e-9 * w.moment_on_cage.norm() / p.width);
        // equally tilted cage and ring: no film change anywhere, nothing acts
        let both = land_on_cage(&p, &ring, &ring);
        assert_eq!(both.force_on_cage.norm() + both.moment_on_cage.norm(), 0.0);
    }

    #[test]
    fn tilting_cage_is_damped_by_the_squeeze_film() {
        // Non-rotating cage, slightly tilted about Z and tilting further: the squeeze film
        // resists the tilt rate (moment about Z opposite to the rate).
        let p = params();
        let cage = AxisMotion {
            tilt_rate: Vector3::new(0.0, 0.0, 0.5),
            ..body(Vector3::zeros(), Vector3::new(1.0, 1e-3, 0.0), 0.0)
        };
        let ring = body(Vector3::zeros(), Vector3::x(), 0.0);
        let w = land_on_cage(&p, &cage, &ring);
        assert!(w.moment_on_cage.z < 0.0, "{:?}", w.moment_on_cage);
    }
}
