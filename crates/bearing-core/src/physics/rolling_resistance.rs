//! EHL hydrodynamic rolling resistance at a ball-race contact: the fully flooded,
//! isothermal fit of Biboulet & Houpert (Proc IMechE J 224, 2010, Part 2, eq. 32), in the
//! parametrisation attributed to Bălan et al. (Lubricants 3, 2015, eqs. 1-7; only its
//! abstract was read; it agrees with eq. 32 within 0.5 % on the H7005C's contacts:
//! docs/reference/model.md, "EHL rolling resistance").
//!
//! ```text
//! F_IVR = 2.9766 E' Rx^2 k^0.3316 W^(1/3) U^(2/3)     (isoviscous-rigid limit)
//! F_EHL = 7.5826 E' Rx^2 k^0.4055 W^(1/3) U^(3/4)     (piezoviscous-elastic limit)
//! M     = 0.5549 k^-0.6029 W U^-0.75
//! F_R   = (F_IVR - F_EHL) / (1 + M/6.6) + F_EHL
//! ```
//! with `k = Ry/Rx`, `U = eta0 u_m / (E' Rx)`, `W = Q / (E' Rx^2)` and `u_m` the mean
//! surface speed relative to the contact. `W^(1/3)` from the load's cube root and the powers
//! of `U` from `ln u_m`, which the contact computes once for all its laws (the cube root for
//! the ellipse's size, the logarithm for the rheology law's film too): two exponentials per
//! contact, where two cube roots and two square roots were out of line and 8.9 % of a
//! rheology-law run (perf, 2026-11-29, docs/lab/benchmarks.md).

use super::exp::exp;
use super::hertz::cube_root;
use super::lanes::F64x4;
use nalgebra::Vector3;

/// Below this entrainment speed (m/s) the force is scaled linearly to zero, so its
/// direction is never taken from a vanishing vector.
pub const ENTRAINMENT_REGULARIZATION: f64 = 1e-3;

/// Rolling-resistance constants of one ball-race pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RollingResistance {
    /// `2.9766 E' Rx^2 k^0.3316` times the film factor, N.
    c_ivr: f64,
    /// `7.5826 E' Rx^2 k^0.4055` times the film factor, N.
    c_ehl: f64,
    /// `0.5549 k^-0.6029 / 6.6`, -.
    c_m: f64,
    /// `W / Q = 1 / (E' Rx^2)`, 1/N.
    w_per_load: f64,
    /// `W^(1/3) / Q^(1/3)`, N^(-1/3).
    w13_per_q13: f64,
    /// `ln(U / u_m)`, `ln` of s/m.
    ln_u_per_speed: f64,
}

impl RollingResistance {
    /// Constants for effective modulus `e_prime` (Pa, `2 / sum((1 - nu^2)/E)`), principal
    /// relative radii `rx` (rolling direction) and `ry` (m), inlet viscosity `eta0` (Pa s),
    /// times a film reduction `factor` (-; 1 for a fully flooded, isothermal contact).
    pub fn new(e_prime: f64, rx: f64, ry: f64, eta0: f64, factor: f64) -> Self {
        let k = ry / rx;
        let scale = factor * e_prime * rx * rx;
        RollingResistance {
            c_ivr: 2.9766 * scale * k.powf(0.3316),
            c_ehl: 7.5826 * scale * k.powf(0.4055),
            c_m: 0.5549 * k.powf(-0.6029) / 6.6,
            w_per_load: 1.0 / (e_prime * rx * rx),
            w13_per_q13: cube_root(1.0 / (e_prime * rx * rx)),
            ln_u_per_speed: (eta0 / (e_prime * rx)).ln(),
        }
    }

    /// Rolling force at load `q` (N) and mean surface speed `um` (m/s), N.
    #[inline]
    pub fn force(&self, q: f64, um: f64) -> f64 {
        if q <= 0.0 || um <= 0.0 {
            return 0.0;
        }
        self.force_given(q, cube_root(q), um.ln())
    }

    /// [`RollingResistance::force`] at a positive load `q` (N) given its cube root `q13`
    /// and `ln_um`, the logarithm of the speed (m/s).
    #[inline(always)]
    fn force_given(&self, q: f64, q13: f64, ln_um: f64) -> f64 {
        let w = q * self.w_per_load;
        let w13 = q13 * self.w13_per_q13;
        let ln_u = ln_um + self.ln_u_per_speed;
        let u23 = exp((2.0 / 3.0) * ln_u);
        let u34 = exp(0.75 * ln_u);
        let f_ivr = self.c_ivr * w13 * u23;
        let f_ehl = self.c_ehl * w13 * u34;
        let m6 = self.c_m * w / u34;
        (f_ivr - f_ehl) / (1.0 + m6) + f_ehl
    }

    /// [`RollingResistance::force`] of four contacts at positive loads `q` (N) given
    /// their cube roots `q13` and `ln_um`, the logarithms of their speeds (m/s), N.
    #[inline(always)]
    pub fn force_lanes(&self, q: F64x4, q13: F64x4, ln_um: F64x4) -> F64x4 {
        let w = self.w_per_load * q;
        let w13 = self.w13_per_q13 * q13;
        let ln_u = ln_um + F64x4::splat(self.ln_u_per_speed);
        let u23 = ((2.0 / 3.0) * ln_u).exp();
        let u34 = (0.75 * ln_u).exp();
        let f_ivr = self.c_ivr * w13 * u23;
        let f_ehl = self.c_ehl * w13 * u34;
        let m6 = self.c_m * w / u34;
        (f_ivr - f_ehl) / (F64x4::splat(1.0) + m6) + f_ehl
    }

    /// `F_R e` with `e` the unit entrainment direction of `um` (m/s, tangent to the
    /// contact), N; linear in `um` below the regularization speed.
    #[inline]
    pub fn force_along(&self, q: f64, um: &Vector3<f64>) -> Vector3<f64> {
        let speed = um.norm();
        let floored = speed.max(ENTRAINMENT_REGULARIZATION);
        self.force_along_given(q, cube_root(q), um, floored, floored.ln())
    }

    /// [`RollingResistance::force_along`] at a positive load `q` (N) given its cube root
    /// `q13`, the speed `floored = max(|um|, ENTRAINMENT_REGULARIZATION)` (m/s) and its
    /// logarithm `ln_floored`, which the contact computes once for all its laws.
    #[inline(always)]
    pub fn force_along_given(
        &self,
        q: f64,
        q13: f64,
        um: &Vector3<f64>,
        floored: f64,
        ln_floored: f64,
    ) -> Vector3<f64> {
        if q <= 0.0 {
            return Vector3::zeros();
        }
        (self.force_given(q, q13, ln_floored) / floored) * um
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// H7005C inner contact: E' 228.6 GPa, Rx 2.364 mm, Ry 49.1 mm (k = 20.77),
    /// eta0 4.44 mPa s.
    fn inner() -> RollingResistance {
        RollingResistance::new(228.6e9, 2.364e-3, 49.1e-3, 4.44e-3, 1.0)
    }

    #[test]
    fn reproduces_the_published_fit_evaluated_by_hand() {
        // 10000 rpm (u_m 9.21 m/s), Q 1 N: U = 7.567e-11, W = 7.828e-7, so
        // F_IVR = 2.9766 x 228.6e9 x 5.588e-6 x 20.77^0.3316 x W^(1/3) x U^(2/3) = 1.71e-2 N,
        // F_EHL = 7.84e-3 N, M = 2.72 and F_R = 1.44e-2 N; at 100 N, F_R = 3.74e-2 N
        // (M = 272, close to the EHL limit). Evaluated independently with a calculator
        // script; 1 % covers the 3 significant figures kept.
        let r = inner();
        let f1 = r.force(1.0, 9.21);
        assert!((f1 - 1.44e-2).abs() / 1.44e-2 < 0.01, "F_R(1 N) = {f1}");
        let f100 = r.force(100.0, 9.21);
        assert!(
            (f100 - 3.74e-2).abs() / 3.74e-2 < 0.01,
            "F_R(100 N) = {f100}"
        );
        // the lightly loaded ball is braked relatively ~40x more than the loaded one
        assert!((f1 / 1.0) / (f100 / 100.0) > 30.0);
        // the blend tends to its limits: IVR at vanishing load, EHL at large M
        let (w, u): (f64, f64) = (1e-12, 7.567e-11);
        let q = w / r.w_per_load;
        let ivr = r.c_ivr * w.cbrt() * u.powf(2.0 / 3.0);
        assert!((r.force(q, 9.21) - ivr).abs() / ivr < 1e-3);
    }

    /// The force from the contact's cube root and logarithm is the fit's formula evaluated
    /// with `powf`, from 1 mN to 1 kN and from 1 mm/s to 100 m/s: 1e-14. `ln U` runs from
    /// -32 to -21 there, so its half-ulp rounding moves `U^(3/4)` by about
    /// `0.75 x 32 x 1.1e-16 = 2.7e-15`; the exponentials, `powf` and the sums add a few
    /// ulp.
    #[test]
    fn shared_logs_give_the_formula_evaluated_with_powers() {
        let r = inner();
        let mut worst: f64 = 0.0;
        for i in 0..=60 {
            let q = 1e-3 * 10f64.powf(i as f64 / 10.0);
            for j in 0..=50 {
                let um = 1e-3 * 10f64.powf(j as f64 / 10.0);
                // U / u_m = eta0 / (E' Rx) of `inner()`
                let (w, u) = (q * r.w_per_load, um * 4.44e-3 / (228.6e9 * 2.364e-3));
                let f_ivr = r.c_ivr * w.powf(1.0 / 3.0) * u.powf(2.0 / 3.0);
                let f_ehl = r.c_ehl * w.powf(1.0 / 3.0) * u.powf(0.75);
                let want = (f_ivr - f_ehl) / (1.0 + r.c_m * w * u.powf(-0.75)) + f_ehl;
                worst = worst.max((r.force(q, um) - want).abs() / want);
            }
        }
        assert!(worst < 1e-14, "worst relative difference {worst:e}");
    }

    #[test]
    fn vector_follows_entrainment_and_is_continuous() {
        let r = inner();
        let um = Vector3::new(0.0, 3.0, 4.0);
        let f = r.force_along(20.0, &um);
        assert!((f.norm() - r.force(20.0, 5.0)).abs() < 1e-12 * f.norm());
        assert!(f.dot(&um) > 0.0 && f.cross(&um).norm() < 1e-12 * f.norm() * 5.0);
        let s = ENTRAINMENT_REGULARIZATION;
        let below = r.force_along(20.0, &Vector3::new(s * (1.0 - 1e-9), 0.0, 0.0));
        let above = r.force_along(20.0, &Vector3::new(s * (1.0 + 1e-9), 0.0, 0.0));
        assert!((below - above).norm() < 1e-8 * above.norm());
        assert_eq!(r.force_along(20.0, &Vector3::zeros()), Vector3::zeros());
        assert_eq!(r.force(0.0, 5.0), 0.0);
    }
}
