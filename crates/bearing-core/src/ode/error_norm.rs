//! The scaled error norm every controlled method measures its local error estimate with.

/// Weighted RMS norm of a local error estimate: component `i` is measured against
/// `atol * scale[i] + rtol * max(|y_i|, |y_new_i|)`, or `(atol + rtol) * scale[i]` for a
/// component marked unbounded (a phase, whose size says nothing of its accuracy). The
/// problem supplies `scale`, each component's natural size.
#[derive(Debug, Clone)]
pub struct ErrorNorm {
    pub rtol: f64,
    pub atol: f64,
    scale: Vec<f64>,
    unbounded: Vec<bool>,
}

impl ErrorNorm {
    pub fn new(rtol: f64, atol: f64, scale: Vec<f64>, unbounded: Vec<bool>) -> Self {
        assert_eq!(
            scale.len(),
            unbounded.len(),
            "one scale and flag per component"
        );
        ErrorNorm {
            rtol,
            atol,
            scale,
            unbounded,
        }
    }

    /// The norm of the estimate `err` of a step from `y` to `y_new` (accept when <= 1).
    pub fn rms(&self, y: &[f64], y_new: &[f64], err: &[f64]) -> f64 {
        let n = y.len();
        assert!(y_new.len() == n && err.len() == n && self.scale.len() == n);
        let mut sum = 0.0;
        for i in 0..n {
            let mag = if self.unbounded[i] {
                self.scale[i]
            } else {
                y[i].abs().max(y_new[i].abs())
            };
            let sc = self.atol * self.scale[i] + self.rtol * mag;
            let e = err[i] / sc;
            sum += e * e;
        }
        (sum / n as f64).sqrt()
    }
}
