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
}
