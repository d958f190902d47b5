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
//! keeps a nearly unloaded cage from whirling without bound (see docs/model.md).
//! Below the critical film the cage touches the land: a line contact of stiffness
//! `(pi / 4) E' L` with damping and Coulomb friction. The film formulas are evaluated at
//! most at the critical eccentricity, so forces stay bounded and continuous.

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
    let mut torque = -2.0 * PI * eta * r * r * r * l * dw / (c * one.sqrt());
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
        let w_t = 0.25 * PI * k0 * u * eh / one.powf(1.5) + 2.0 * k0 * r * eh * de / (one * one);
        let w_sq = 0.5 * PI * k0 * r * (1.0 + 2.0 * eh * eh) * de / one.powf(2.5);
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
