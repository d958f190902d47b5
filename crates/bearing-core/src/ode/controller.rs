//! The step-size controller every controlled method uses.

/// Step-size factors from scaled error norms (accept when <= 1) for an error estimate of
/// order `q` (the estimate scales as `h^q`).
///
/// After an accepted step: a PI controller (Gustafsson) on the norms of this and the
/// previous accepted step, which keeps a stability-limited step from oscillating across
/// the limit; no growth right after a rejection. After a rejection: the elementary
/// controller, never above 0.9, and 0.1 for a non-finite error.
#[derive(Debug, Clone)]
pub struct Controller {
    /// `-0.7 / q`, `0.4 / q` and `-1 / q`.
    err_exp: f64,
    prev_exp: f64,
    elementary_exp: f64,
    prev_err: f64,
    just_rejected: bool,
}

impl Controller {
    pub fn new(q: u32) -> Self {
        let q = f64::from(q);
        Controller {
            err_exp: -0.7 / q,
            prev_exp: 0.4 / q,
            elementary_exp: -1.0 / q,
            prev_err: 1.0,
            just_rejected: false,
        }
    }

    /// Factor for the next step after an accepted one.
    pub fn accept_factor(&mut self, err: f64) -> f64 {
        let e = err.max(1e-10);
        let mut f = 0.9 * e.powf(self.err_exp) * self.prev_err.powf(self.prev_exp);
        if self.just_rejected {
            f = f.min(1.0);
        }
        self.prev_err = e;
        self.just_rejected = false;
        f.clamp(0.2, 4.0)
    }

    /// Factor for the retry after a rejected step.
    pub fn reject_factor(&mut self, err: f64) -> f64 {
        self.just_rejected = true;
        if err.is_finite() {
            self.elementary_factor(err).min(0.9)
        } else {
            0.1
        }
    }

    /// The elementary (integral) controller's factor: the step that would bring the error
    /// norm to 0.9^q, at most 4x and at least 0.2x the last.
    pub fn elementary_factor(&self, err: f64) -> f64 {
        if err == 0.0 {
            4.0
        } else {
            (0.9 * err.powf(self.elementary_exp)).clamp(0.2, 4.0)
        }
    }
}
