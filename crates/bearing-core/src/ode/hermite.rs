//! Dense output: the cubic Hermite interpolant of one step from its end points and their
//! derivatives (4th order, continuous in value and slope across steps).

/// Cubic Hermite interpolation on a step: value at fraction `s` in [0, 1].
#[inline]
pub fn hermite(y0: f64, f0: f64, y1: f64, f1: f64, h: f64, s: f64) -> f64 {
    let s2 = s * s;
    let s3 = s2 * s;
    (2.0 * s3 - 3.0 * s2 + 1.0) * y0
        + (s3 - 2.0 * s2 + s) * h * f0
        + (-2.0 * s3 + 3.0 * s2) * y1
        + (s3 - s2) * h * f1
}

/// Time derivative of the cubic Hermite interpolant at fraction `s`.
#[inline]
pub fn hermite_derivative(y0: f64, f0: f64, y1: f64, f1: f64, h: f64, s: f64) -> f64 {
    let s2 = s * s;
    ((6.0 * s2 - 6.0 * s) * y0
        + (3.0 * s2 - 4.0 * s + 1.0) * h * f0
        + (-6.0 * s2 + 6.0 * s) * y1
        + (3.0 * s2 - 2.0 * s) * h * f1)
        / h
}

/// Integral of the cubic Hermite interpolant over time from fraction `s` to the step's
/// end. Over a whole step (`s` = 0) it is `h (y0 + y1) / 2 + h^2 (f0 - f1) / 12`, exact
/// for cubics.
#[inline]
pub fn hermite_integral(y0: f64, f0: f64, y1: f64, f1: f64, h: f64, s: f64) -> f64 {
    // antiderivatives of the four basis cubics, in the step's fraction
    let prim = |s: f64| {
        let (s2, s3, s4) = (s * s, s * s * s, s * s * s * s);
        (0.5 * s4 - s3 + s) * y0
            + (0.25 * s4 - 2.0 / 3.0 * s3 + 0.5 * s2) * h * f0
            + (s3 - 0.5 * s4) * y1
            + (0.25 * s4 - s3 / 3.0) * h * f1
    };
    h * (prim(1.0) - prim(s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hermite_is_exact_for_cubics() {
        let p = |t: f64| 1.0 + 2.0 * t - 3.0 * t * t + 0.5 * t * t * t;
        let dp = |t: f64| 2.0 - 6.0 * t + 1.5 * t * t;
        let (t0, h) = (0.3, 0.7);
        for s in [0.0, 0.25, 0.5, 0.9, 1.0] {
            let v = hermite(p(t0), dp(t0), p(t0 + h), dp(t0 + h), h, s);
            assert!((v - p(t0 + s * h)).abs() < 1e-13);
            let d = hermite_derivative(p(t0), dp(t0), p(t0 + h), dp(t0 + h), h, s);
            assert!((d - dp(t0 + s * h)).abs() < 1e-12);
        }
    }

    /// The integral of the same cubic over the step, whole and from 0.37 and 0.9 of the
    /// way: only rounding is left (values of order 1: 1e-13).
    #[test]
    fn hermite_integral_is_exact_for_cubics() {
        let p = |t: f64| 1.0 + 2.0 * t - 3.0 * t * t + 0.5 * t * t * t;
        let dp = |t: f64| 2.0 - 6.0 * t + 1.5 * t * t;
        let prim = |t: f64| t + t * t - t * t * t + 0.125 * t * t * t * t;
        let (t0, h) = (1.2, 0.4);
        for s in [0.0, 0.37, 0.9, 1.0] {
            let got = hermite_integral(p(t0), dp(t0), p(t0 + h), dp(t0 + h), h, s);
            let want = prim(t0 + h) - prim(t0 + s * h);
            assert!((got - want).abs() < 1e-13, "from {s}: {got} against {want}");
        }
    }
}
