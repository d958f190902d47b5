//! Ball-cage pocket interaction (eqs. 19-22).
//!
//! Above the critical film the lubricant in the pocket acts as a squeeze film (Reynolds'
//! sphere-plane result `6 pi eta R^2 (-dh/dt) / h`, no tension: a separating ball feels
//! no suction); below it the contact is Hertzian with penetration `critical - h` plus
//! Coulomb friction. The squeeze term keeps acting with `h` held at the critical film, so
//! the force is continuous across the switch.

use super::frames::Azimuth;
use super::hertz::HertzContact;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// Constant data of the ball-pocket pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PocketParams {
    /// Radial clearance `(d_p - D) / 2`, m (eq. 21).
    pub clearance: f64,
    /// Radius of the circle of pocket centres in the cage frame, m.
    pub pocket_radius: f64,
    pub hertz: HertzContact,
    /// Critical film, m.
    pub critical_film: f64,
    /// Lubricant dynamic viscosity, Pa s.
    pub viscosity: f64,
    /// Ball radius, m.
    pub ball_radius: f64,
    /// Coulomb friction coefficient in Hertzian contact, -.
    pub friction: f64,
    /// Normal damping ratio of the Hertzian contact, -, and the mass it is scaled with, kg.
    pub damping_ratio: f64,
    pub damping_mass: f64,
}

/// Motion of the cage.
#[derive(Debug, Clone, Copy)]
pub struct CageMotion {
    /// Centre position, m.
    pub centre: Vector3<f64>,
    /// Centre velocity, m/s.
    pub velocity: Vector3<f64>,
    /// Body-to-inertial rotation for tilt.
    pub rot: Matrix3<f64>,
    /// Spin angle about the axis, rad.
    pub spin_angle: f64,
    /// Angular velocity, rad/s.
    pub omega: Vector3<f64>,
}

/// Result of one ball-pocket interaction (all inertial).
#[derive(Debug, Clone, Copy, Default)]
pub struct PocketResult {
    /// Film (clearance left) between ball and pocket wall, m (eq. 21).
    pub film: f64,
    /// Normal force, N.
    pub normal: f64,
    pub force_on_ball: Vector3<f64>,
    pub moment_on_ball: Vector3<f64>,
    pub force_on_cage: Vector3<f64>,
    /// About the cage centre, N m.
    pub moment_on_cage: Vector3<f64>,
}

/// Slip speed below which Coulomb friction is scaled down linearly, m/s.
pub(super) const FRICTION_REGULARIZATION: f64 = 1e-2;

/// The pocket at inertial azimuth `pocket` on `cage`: its centre (m) and its axis (unit,
/// radial in the cage's frame).
#[inline]
pub fn pocket_centre_and_axis(
    p: &PocketParams,
    cage: &CageMotion,
    pocket: &Azimuth,
) -> (Vector3<f64>, Vector3<f64>) {
    let axis = cage.rot * pocket.e_r();
    (cage.centre + p.pocket_radius * axis, axis)
}

/// Interaction of a ball with the pocket at inertial azimuth `pocket` (the cage's spin
/// angle plus the pocket's body angle).
#[inline]
pub fn pocket_contact(
    p: &PocketParams,
    cage: &CageMotion,
    pocket: &Azimuth,
    ball_centre: &Vector3<f64>,
    ball_velocity: &Vector3<f64>,
    ball_omega: &Vector3<f64>,
) -> PocketResult {
    let (centre, axis) = pocket_centre_and_axis(p, cage, pocket);
    // eq. 19: ball relative to the pocket; only the part across the pocket axis matters
    let w = ball_centre - centre;
    let w_perp = w - w.dot(&axis) * axis;
    let dist = w_perp.norm();
    // eq. 21
    let film = p.clearance - dist;
    let mut out = PocketResult {
        film,
        ..Default::default()
    };
    if dist < 1e-12 {
        return out;
    }
    let n = w_perp / dist;
    let r_contact = p.ball_radius * n;
    let point = ball_centre + r_contact;
    let v_cage_pt = cage.velocity + cage.omega.cross(&(point - cage.centre));
    let v_ball_pt = ball_velocity + ball_omega.cross(&r_contact);
    // film shrinks when the ball centre moves away from the pocket axis
    let dfilm = -n.dot(&(ball_velocity - v_cage_pt));
    let h_eff = film.max(p.critical_film);
    let squeeze =
        (6.0 * PI * p.viscosity * p.ball_radius * p.ball_radius * (-dfilm) / h_eff).max(0.0);
    let pen = p.critical_film - film;
    let hertz = if pen > 0.0 {
        // Hertz plus film damping on the approach speed (as for the race contacts)
        let sq = pen.sqrt();
        let c = 2.0 * p.damping_ratio * (1.5 * p.hertz.k * sq * p.damping_mass).sqrt();
        (p.hertz.k * pen * sq + c * (-dfilm)).max(0.0)
    } else {
        0.0
    };
    let normal = squeeze + hertz;
    if normal == 0.0 {
        return out;
    }
    let mut f_ball = -normal * n;
    let mut m_ball = Vector3::zeros();
    if hertz > 0.0 && p.friction > 0.0 {
        let mut v = v_ball_pt - v_cage_pt;
        v -= v.dot(&n) * n;
        let sp = v.norm();
        if sp > 0.0 {
            let scale = p.friction * hertz * (sp / FRICTION_REGULARIZATION).min(1.0) / sp;
            let fr = -scale * v;
            f_ball += fr;
            m_ball = r_contact.cross(&fr);
        }
    }
    out.normal = normal;
    out.force_on_ball = f_ball;
    out.moment_on_ball = m_ball;
    out.force_on_cage = -f_ball;
    out.moment_on_cage = (point - cage.centre).cross(&(-f_ball));
    out
}

/// A pocket of the Table-1 bearing's size, for the tests here and in
/// [`super::cage_pocket_lanes`].
#[cfg(test)]
pub(super) fn example_params() -> PocketParams {
    PocketParams {
        clearance: 0.167e-3,
        pocket_radius: 18e-3,
        hertz: HertzContact {
            k: 1.0e9,
            a_coef: 1e-4,
            b_coef: 1e-4,
        },
        critical_film: 0.8e-6,
        viscosity: 4.44e-3,
        ball_radius: 2.778e-3,
        friction: 0.08,
        damping_ratio: 0.05,
        damping_mass: 0.7e-3,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cage_at_rest() -> CageMotion {
        CageMotion {
            centre: Vector3::zeros(),
            velocity: Vector3::zeros(),
            rot: Matrix3::identity(),
            spin_angle: 0.0,
            omega: Vector3::zeros(),
        }
    }

    // Pocket 0 of a cage at rest has its axis along +Z and its centre at (0, 0, 18 mm).
    fn ball_at(offset: Vector3<f64>) -> Vector3<f64> {
        Vector3::new(0.0, 0.0, 18e-3) + offset
    }

    #[test]
    fn centred_ball_feels_nothing_and_radial_motion_changes_no_film() {
        let p = example_params();
        let z = Vector3::zeros();
        let r = pocket_contact(&p, &cage_at_rest(), &Azimuth::new(0.0), &ball_at(z), &z, &z);
        assert_eq!(r.normal, 0.0);
        // moving along the pocket axis (the bearing's radial direction) keeps the film
        let off = Vector3::new(0.0, 50e-6, 0.0);
        let a = pocket_contact(
            &p,
            &cage_at_rest(),
            &Azimuth::new(0.0),
            &ball_at(off),
            &z,
            &z,
        );
        let b = pocket_contact(
            &p,
            &cage_at_rest(),
            &Azimuth::new(0.0),
            &ball_at(off + Vector3::new(0.0, 0.0, 0.3e-3)),
            &z,
            &z,
        );
        assert!((a.film - (p.clearance - 50e-6)).abs() < 1e-15);
        assert!((a.film - b.film).abs() < 1e-15);
    }

    #[test]
    fn ball_past_the_critical_film_is_pushed_back_by_hertz() {
        // 1 um past the critical film, at rest: Q = K (1e-6)^1.5 = 1 N for K = 1e9 N/m^1.5
        let p = example_params();
        let z = Vector3::zeros();
        let off = Vector3::new(0.0, p.clearance - p.critical_film + 1e-6, 0.0);
        let r = pocket_contact(
            &p,
            &cage_at_rest(),
            &Azimuth::new(0.0),
            &ball_at(off),
            &z,
            &z,
        );
        assert!((r.normal - 1.0).abs() < 1e-9, "{}", r.normal);
        // on the ball towards the pocket axis (-Y), the opposite on the cage
        assert!((r.force_on_ball - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-9);
        assert!((r.force_on_cage + r.force_on_ball).norm() < 1e-15);
        // the cage is pushed at the contact point, 18 mm out along Z: moment -Y x Z... = +X
        let point = ball_at(off) + p.ball_radius * Vector3::y();
        let m = point.cross(&r.force_on_cage);
        assert!((r.moment_on_cage - m).norm() < 1e-15);
        assert!(r.moment_on_cage.x < 0.0);
    }

    #[test]
    fn squeeze_film_resists_approach_and_never_pulls() {
        // 20 um of film, ball approaching the wall at 0.1 m/s: F = 6 pi eta R^2 v / h
        let p = example_params();
        let z = Vector3::zeros();
        let h = 20e-6;
        let off = Vector3::new(0.0, p.clearance - h, 0.0);
        let v = Vector3::new(0.0, 0.1, 0.0);
        let r = pocket_contact(
            &p,
            &cage_at_rest(),
            &Azimuth::new(0.0),
            &ball_at(off),
            &v,
            &z,
        );
        let expect = 6.0 * PI * p.viscosity * p.ball_radius.powi(2) * 0.1 / h;
        assert!(
            (r.normal - expect).abs() < 1e-12 * expect,
            "{} vs {expect}",
            r.normal
        );
        assert!(r.force_on_ball.y < 0.0);
        let away = pocket_contact(
            &p,
            &cage_at_rest(),
            &Azimuth::new(0.0),
            &ball_at(off),
            &(-v),
            &z,
        );
        assert_eq!(away.normal, 0.0);
    }

    #[test]
    fn sliding_ball_in_contact_gets_coulomb_friction_against_its_slip() {
        // Ball spinning about X at 100 rad/s against the wall on +Y: surface speed 0.28 m/s
        // along Z at the contact, far above the 1 cm/s regularisation, so |F_t| = mu Q.
        let p = example_params();
        let off = Vector3::new(0.0, p.clearance - p.critical_film + 1e-6, 0.0);
        let w = Vector3::new(100.0, 0.0, 0.0);
        let r = pocket_contact(
            &p,
            &cage_at_rest(),
            &Azimuth::new(0.0),
            &ball_at(off),
            &Vector3::zeros(),
            &w,
        );
        let tangential = r.force_on_ball - r.force_on_ball.dot(&Vector3::y()) * Vector3::y();
        assert!((tangential.norm() - p.friction * r.normal).abs() < 1e-9);
        // w x (R e_y) = 100 R e_z: the surface slides along +Z, friction acts along -Z
        assert!(tangential.z < 0.0);
        // and it slows the spin: moment about X opposite to w
        assert!(r.moment_on_ball.x < 0.0);
    }
}
