//! Hertzian point contact (eq. 8): load-deflection constant and contact ellipse, by the
//! Hamrock-Brewe curve fits (fast, used in the model) and by exact elliptic integrals
//! (reference for tests).

use std::f64::consts::PI;

/// Effective modulus `E' = 2 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)`, Pa.
pub fn effective_modulus(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    2.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
}

/// Constants of one Hertzian contact, from its principal relative radii.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzContact {
    /// Load-deflection constant K in `Q = K delta^1.5`, N/m^1.5.
    pub k: f64,
    /// Semi-major axis per cube-root load: `a = a_coef * Q^(1/3)`, m/N^(1/3).
    pub a_coef: f64,
    /// Semi-minor axis per cube-root load: `b = b_coef * Q^(1/3)`, m/N^(1/3).
    pub b_coef: f64,
}

/// Hamrock-Brewe contact for radii `rx` (rolling direction, the smaller) and `ry`
/// (transverse), m, and effective modulus `e_prime`, Pa.
///
/// k = 1.0339 (Ry/Rx)^0.636, E = 1.0003 + 0.5968 Rx/Ry, F = 1.5277 + 0.6023 ln(Ry/Rx);
/// a = (6 k^2 E Q R / (pi E'))^(1/3), b = (6 E Q R / (pi k E'))^(1/3),
/// K = pi k E' sqrt(R E / (4.5 F^3)) with 1/R = 1/Rx + 1/Ry.
pub fn hamrock_brewe(rx: f64, ry: f64, e_prime: f64) -> HertzContact {
    let ratio = ry / rx;
    let kappa = 1.0339 * ratio.powf(0.636);
    let ell = 1.0003 + 0.5968 / ratio;
    let f = 1.5277 + 0.6023 * ratio.ln();
    let r = 1.0 / (1.0 / rx + 1.0 / ry);
    HertzContact {
        k: PI * kappa * e_prime * (r * ell / (4.5 * f * f * f)).sqrt(),
        a_coef: (6.0 * kappa * kappa * ell * r / (PI * e_prime)).cbrt(),
        b_coef: (6.0 * ell * r / (PI * kappa * e_prime)).cbrt(),
    }
}

/// Complete elliptic integrals K(m), E(m) of parameter m = e^2, by the arithmetic-
/// geometric mean (converges quadratically; 1e-16 after a few iterations).
pub fn elliptic_ke(m: f64) -> (f64, f64) {
    let mut a = 1.0;
    let mut b = (1.0 - m).sqrt();
    let mut c = m.sqrt();
    let mut sum = 0.5 * c * c;
    let mut pow2 = 0.5;
    for _ in 0..40 {
        if c.abs() < 1e-17 {
            break;
        }
        let an = 0.5 * (a + b);
        let bn = (a * b).sqrt();
        c = 0.5 * (a - b);
        a = an;
        b = bn;
        pow2 *= 2.0;
        sum += pow2 * c * c;
    }
    let k = PI / (2.0 * a);
    (k, k * (1.0 - sum))
}

/// Exact Hertz solution for radii `rx` < `ry`: the ellipticity relation is Biboulet & Houpert
/// (2010, Part 2, App. 2, eq. 43) with kappa inverted; the semi-axes and approach are the
/// classical closed forms, checked against an independent derivation from their definitions
/// (tests/engine_traction.rs) and ISO 16281's reference deflections (tests/engine_iso16281.rs).
///
/// The ellipticity kappa = a/b solves `Ry/Rx = (kappa^2 E(e) - K(e)) / (K(e) - E(e))`
/// with `e^2 = 1 - 1/kappa^2`; then `a^3 = 3 Q Ry (K - E) / (pi E* e^2)`,
/// `delta = 3 Q K(e) / (2 pi a E*)` with `E* = E'/2`.
pub fn exact(rx: f64, ry: f64, e_prime: f64) -> HertzContact {
    let target = ry / rx;
    let ratio_of = |kappa: f64| {
        let m = 1.0 - 1.0 / (kappa * kappa);
        let (k, e) = elliptic_ke(m);
        (kappa * kappa * e - k) / (k - e)
    };
    // ratio_of grows monotonically with kappa; bisect in log space.
    let (mut lo, mut hi) = (1.0f64 + 1e-9, 1e3f64);
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if ratio_of(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let kappa = (lo * hi).sqrt();
    let m = 1.0 - 1.0 / (kappa * kappa);
    let (kk, ee) = elliptic_ke(m);
    let e_star = 0.5 * e_prime;
    // For Q = 1 N:
    let a = (3.0 * ry * (kk - ee) / (PI * e_star * m)).cbrt();
    let b = a / kappa;
    let delta = 3.0 * kk / (2.0 * PI * a * e_star);
    HertzContact {
        k: 1.0 / delta.powf(1.5),
        a_coef: a,
        b_coef: b,
    }
}

/// Normal load for deflection `delta`, N (zero when not in contact).
#[inline]
pub fn load(k: f64, delta: f64) -> f64 {
    if delta > 0.0 {
        k * delta * delta.sqrt()
    } else {
        0.0
    }
}

/// Deflection carrying load `q`, m.
#[inline]
pub fn deflection(k: f64, q: f64) -> f64 {
    if q > 0.0 {
        (q / k).powf(2.0 / 3.0)
    } else {
        0.0
    }
}

/// Cube root of a positive finite `x` to within 2 ulp of `f64::cbrt`, in fewer
/// instructions: the contact's semi-axis `a = a_coef q^(1/3)` is taken twice per ball at
/// every evaluation, and the library's cube root was 5 % of the right-hand side's
/// instructions (callgrind). An exponent-thirding first guess (within ~10 %) and three
/// Halley steps `y (y^3 + 2x) / (2y^3 + x)` (cubic convergence; two leave 6e-15). Zero, negative, subnormal and non-finite inputs go to `f64::cbrt`.
#[inline]
pub fn cube_root(x: f64) -> f64 {
    if !(f64::MIN_POSITIVE..f64::INFINITY).contains(&x) {
        return x.cbrt();
    }
    let mut y = cube_root_start(x);
    for _ in 0..3 {
        let y3 = y * y * y;
        y *= (y3 + 2.0 * x) / (2.0 * y3 + x);
    }
    y
}

/// [`cube_root`]'s start for a positive normal `x`: a third of the biased exponent (and
/// mantissa bits), re-biased.
#[inline(always)]
pub(crate) fn cube_root_start(x: f64) -> f64 {
    f64::from_bits(x.to_bits() / 3 + 0x2A9F_7893_782D_A1CE)
}

#[cfg(test)]
mod tests {
    #[test]
    fn cube_root_matches_the_library_to_two_ulp() {
        // every decade a contact load can take (1e-12..1e6 N) and beyond, 2000 points each
        let mut worst: f64 = 0.0;
        for e in -300..300 {
            for k in 0..2000 {
                let x = (1.0 + k as f64 / 2000.0) * 10f64.powi(e);
                let (a, b) = (super::cube_root(x), x.cbrt());
                worst = worst.max(((a - b) / b).abs());
            }
        }
        assert!(
            worst <= 2.0 * f64::EPSILON,
            "worst relative difference {worst:e}"
        );
        for x in [0.0, -8.0, f64::INFINITY, f64::NAN, 1e-310] {
            let (a, b) = (super::cube_root(x), x.cbrt());
            assert!(a == b || (a.is_nan() && b.is_nan()), "{x}: {a} vs {b}");
        }
    }

    use super::*;

    #[test]
    fn elliptic_integrals_known_values() {
        // K(0) = E(0) = pi/2; K(0.5) = 1.854074677301372, E(0.5) = 1.350643881047675 (A&S table 17.1).
        let (k0, e0) = elliptic_ke(0.0);
        assert!((k0 - PI / 2.0).abs() < 1e-15 && (e0 - PI / 2.0).abs() < 1e-15);
        let (k, e) = elliptic_ke(0.5);
        assert!((k - 1.854074677301372).abs() < 1e-13);
        assert!((e - 1.350643881047675).abs() < 1e-13);
    }

    #[test]
    fn hamrock_brewe_within_2_percent_of_exact_for_h7005c() {
        // H7005C races: D = 5.556 mm, dm = 35.99 mm, 15 deg; fi = 0.53, fo = 0.536.
        // The brief asks for 2 %: Hamrock-Brewe's published accuracy for K is 2-3 % over
        // all conformities and better than 2 % in this range (engineering notes: 0.5-2.3 %).
        let d = 5.556e-3;
        let gamma = d * 15f64.to_radians().cos() / 35.9935e-3;
        let ep = effective_modulus(208e9, 0.3, 208e9, 0.3);
        for (rx, f) in [
            (0.5 * d * (1.0 - gamma), 0.53),
            (0.5 * d * (1.0 + gamma), 0.536),
        ] {
            let ry = f * d / (2.0 * f - 1.0);
            let hb = hamrock_brewe(rx, ry, ep);
            let ex = exact(rx, ry, ep);
            for (name, x, y) in [
                ("K", hb.k, ex.k),
                ("a", hb.a_coef, ex.a_coef),
                ("b", hb.b_coef, ex.b_coef),
            ] {
                let rel = (x - y).abs() / y;
                assert!(rel < 0.02, "{name}: HB {x:e} exact {y:e} rel {rel}");
            }
        }
    }

    #[test]
    fn exact_reduces_to_sphere_on_sphere() {
        // Rx = Ry = R: circle of radius a = (3 Q R / (4 E*))^(1/3), delta = a^2 / R.
        // kappa -> 1 is the bisection's lower bound, so allow 1e-4 relative.
        let (r, ep) = (2e-3, 200e9);
        let c = exact(r, r * (1.0 + 1e-9), ep);
        let a = (3.0 * r / (4.0 * 0.5 * ep)).cbrt();
        assert!((c.a_coef - a).abs() / a < 1e-4);
        let k = 1.0 / (a * a / r).powf(1.5);
        assert!((c.k - k).abs() / k < 1e-4);
    }
}
