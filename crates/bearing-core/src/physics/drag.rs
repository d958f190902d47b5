//! Drag of the cavity medium (an oil-air mixture) on the balls and the cage.
//!
//! Not in the seed paper (its model has no churning terms). The cavity is a homogeneous
//! oil-air mixture of effective density and viscosity, this project's choice (an ADORE-style
//! code read likewise gives the cavity medium by ratios to the lubricant). Formulas and
//! sources: docs/reference/model.md, "Lubricant drag".

use nalgebra::Vector3;
use std::f64::consts::PI;

/// Density of air at 20 deg C and 1 atm, kg/m^3.
pub const AIR_DENSITY: f64 = 1.204;
/// Dynamic viscosity of air at 20 deg C, Pa s.
pub const AIR_VISCOSITY: f64 = 1.81e-5;

/// The homogeneous oil-air mixture filling the bearing cavity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CavityMedium {
    /// Effective density, kg/m^3.
    pub density: f64,
    /// Effective dynamic viscosity, Pa s.
    pub viscosity: f64,
}

impl CavityMedium {
    /// Mixture with oil volume fraction `x` (0..1): both properties weighted by volume
    /// (rho_eff = X rho_oil + (1 - X) rho_air, likewise mu; an assumption, see model.md).
    pub fn mixture(x: f64, oil_density: f64, oil_viscosity: f64) -> CavityMedium {
        CavityMedium {
            density: x * oil_density + (1.0 - x) * AIR_DENSITY,
            viscosity: x * oil_viscosity + (1.0 - x) * AIR_VISCOSITY,
        }
    }
}

/// Constants of the drag on one ball, derived once per model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BallDrag {
    pub medium: CavityMedium,
    /// Ball radius, m.
    pub radius: f64,
}

impl BallDrag {
    /// Drag force on a ball whose centre moves at `v` through a still medium, N.
    ///
    /// `F = -C_D(Re) (1/2) rho (pi R^2) |v| v` with White's sphere correlation
    /// `C_D = 24/Re + 6/(1 + sqrt Re) + 0.4` (Re < 2e5), `Re = rho |v| D / mu`. At small
    /// Re it reduces to Stokes' `-6 pi mu R v`, so the force is smooth through v = 0.
    #[inline]
    pub fn force(&self, v: &Vector3<f64>) -> Vector3<f64> {
        let speed = v.norm();
        let CavityMedium {
            density: rho,
            viscosity: mu,
        } = self.medium;
        let d = 2.0 * self.radius;
        let re = rho * speed * d / mu;
        // C_D |v| written so that speed = 0 gives the finite Stokes limit (24/Re |v| = 24 mu/(rho D)).
        let cd_speed = 24.0 * mu / (rho * d) + (6.0 / (1.0 + re.sqrt()) + 0.4) * speed;
        -(0.5 * rho * PI * self.radius * self.radius * cd_speed) * v
    }

    /// Drag moment on a ball spinning at `w` in a still medium, N m.
    ///
    /// `M = -C_M(Re_w) (1/2) rho R^5 |w| w`, `Re_w = rho |w| R^2 / mu`, with
    /// `C_M = max(16 pi / Re_w, 6.45 / sqrt(Re_w) + 32.1 / Re_w)`: Stokes' rotating sphere
    /// (`M = 8 pi mu R^3 w`) below Re_w ~ 10, the boundary-layer fit of Dennis, Singh &
    /// Ingham (1980) above; the two cross near Re_w = 10, so the moment is continuous.
    #[inline]
    pub fn moment(&self, w: &Vector3<f64>) -> Vector3<f64> {
        let rate = w.norm();
        let CavityMedium {
            density: rho,
            viscosity: mu,
        } = self.medium;
        let r = self.radius;
        let r2 = r * r;
        // C_M |w| written with Re_w expanded, finite at rate = 0.
        let stokes = 16.0 * PI * mu / (rho * r2);
        let re = rho * rate * r2 / mu;
        let layer = 6.45 * rate / re.sqrt().max(1e-300) + 32.1 * mu / (rho * r2);
        let cm_rate = if rate > 0.0 {
            stokes.max(layer)
        } else {
            stokes
        };
        -(0.5 * rho * r2 * r2 * r * cm_rate) * w
    }
}

/// Windage on the two annular faces of a cage turning at `w` (rad/s) in a still medium,
/// treated as a free rotating disc (laminar; coefficient as read in docs/reference/model.md,
/// "Lubricant drag"): `M = -C_M (1/2) rho w |w|
/// (R_o^5 - R_i^5)` per face pair with `C_M = 3.87 / sqrt(Re)`, `Re = rho |w| R_o^2 / mu`.
/// Returned as the torque about the cage axis, N m.
#[inline]
pub fn cage_windage_torque(medium: &CavityMedium, r_outer: f64, r_inner: f64, w: f64) -> f64 {
    let rate = w.abs();
    if rate == 0.0 {
        return 0.0;
    }
    let re = medium.density * rate * r_outer * r_outer / medium.viscosity;
    let cm = 3.87 / re.sqrt();
    let r5 = r_outer.powi(5) - r_inner.powi(5);
    -cm * 0.5 * medium.density * w * rate * r5
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ball() -> BallDrag {
        BallDrag {
            medium: CavityMedium::mixture(0.01, 870.0, 4.44e-3),
            radius: 2.778e-3,
        }
    }

    #[test]
    fn small_speeds_give_stokes_drag() {
        // Re = 1e-6: C_D = 24/Re within 1e-3 relative (the other terms are 6/(1+1e-3) + 0.4
        // against 24/Re = 2.4e7), so the force is 6 pi mu R v.
        let b = ball();
        let mu = b.medium.viscosity;
        let v = 1e-6 * mu / (b.medium.density * 2.0 * b.radius);
        let f = b.force(&Vector3::new(0.0, 0.0, v));
        let stokes = 6.0 * PI * mu * b.radius * v;
        assert!(
            (f.z + stokes).abs() / stokes < 1e-3,
            "{} vs {}",
            f.z,
            stokes
        );
        assert_eq!(b.force(&Vector3::zeros()), Vector3::zeros());
    }

    #[test]
    fn orbital_drag_at_10000_rpm_matches_the_hand_figure() {
        // H7005C at 10000 rpm: ball centre speed d_m w_c / 2 = 8.0 m/s, X = 0.01
        // (rho 9.893 kg/m^3, mu 6.232e-5 Pa s): Re = 7055, C_D = 0.4740 (White), so by hand
        // F = 0.4740 x 0.5 x 9.893 x pi (2.778e-3)^2 x 64 = 3.638e-3 N; 0.5 % covers the
        // rounding of the hand figures (the research note's recomputed 3.65e-3 N agrees).
        let b = ball();
        let f = b.force(&Vector3::new(0.0, 8.0, 0.0)).norm();
        assert!((f - 3.638e-3).abs() / 3.638e-3 < 5e-3, "F = {f}");
        // opposes the motion
        assert!(b.force(&Vector3::new(0.0, 8.0, 0.0)).y < 0.0);
    }

    #[test]
    fn spin_moment_is_stokes_at_low_re_and_continuous() {
        let b = ball();
        let (rho, mu, r) = (b.medium.density, b.medium.viscosity, b.radius);
        let w_of_re = |re: f64| re * mu / (rho * r * r);
        // Re_w = 0.1: Stokes branch, 8 pi mu R^3 w exactly.
        let w = w_of_re(0.1);
        let m = b.moment(&Vector3::new(w, 0.0, 0.0)).x;
        let stokes = 8.0 * PI * mu * r.powi(3) * w;
        assert!((m + stokes).abs() / stokes < 1e-12);
        // Re_w = 1e3: boundary-layer branch, 5-10x Stokes (research note, section 2a).
        let w = w_of_re(1e3);
        let m = -b.moment(&Vector3::new(0.0, w, 0.0)).y;
        let ratio = m / (8.0 * PI * mu * r.powi(3) * w);
        assert!(ratio > 3.0 && ratio < 10.0, "ratio {ratio}");
        // no jump where the branches meet: scan Re_w 1..100 in 0.1 % steps
        let mut prev = b.moment(&Vector3::new(w_of_re(1.0), 0.0, 0.0)).x;
        let mut re = 1.0;
        while re < 100.0 {
            re *= 1.001;
            let now = b.moment(&Vector3::new(w_of_re(re), 0.0, 0.0)).x;
            // a continuous M grows by ~0.1-0.2 % per step here; a branch jump would be >1 %
            assert!((now / prev - 1.0).abs() < 0.003, "jump at Re_w {re}");
            prev = now;
        }
    }

    #[test]
    fn cage_windage_opposes_rotation_and_is_small() {
        // H7005C cage (R_o 20.3 mm, R_i 16.8 mm) at 445 rad/s in air: Re ~ 1.2e4,
        // M ~ 1e-6..1e-5 N m (research note, section 2b: ~5e-6).
        let air = CavityMedium::mixture(0.0, 870.0, 4.44e-3);
        let m = cage_windage_torque(&air, 20.3e-3, 16.8e-3, 445.0);
        assert!(m < 0.0 && -m > 1e-6 && -m < 1e-5, "M = {m}");
        assert_eq!(cage_windage_torque(&air, 20.3e-3, 16.8e-3, -445.0), -m);
    }
}
