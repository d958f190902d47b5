//! The step-size controller every controlled method uses.

/// Step-size factors from scaled error norms (accept when <= 1) for an error estimate of
/// order `q` (the estimate scales as `h^q`).
///
/// After an accepted step: a PI controller (Gustafsson) on the norms of this and the
/// previous accepted step, which keeps a stability-limited step from oscillating across
/// the limit; no growth right after a rejection. A step cut short to land on a point
/// ([`StepEnd::Cut`]) enters with its norm scaled to the step it was cut from. After a
/// rejection: the elementary controller, never above 0.9, and 0.1 for a non-finite error.
#[derive(Debug, Clone)]
pub struct Controller {
    /// `-0.7 / q`, `0.4 / q` and `-1 / q`.
    err_exp: f64,
    prev_exp: f64,
    elementary_exp: f64,
    prev_err: f64,
    just_rejected: bool,
    /// The estimate's order.
    q: f64,
}

/// How an accepted step's length was set, which says whether its error may serve as the PI
/// term's previous error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepEnd {
    /// The controller's proposal, or a steady limit below it (the method's own limit, the
    /// largest step): successive steps of about one length, whose errors the PI term compares.
    Chosen,
    /// Cut short to land on a point the problem sets (a defect's edge or centre) or on the
    /// run's end. Its norm, at a length nobody chose, is scaled to the step it was cut
    /// from, `err (chosen/taken)^q`, and the next step is a factor of that step, at most 1
    /// (the scaled norm extrapolates towards a point where the problem is not smooth).
    /// The scaled norm becomes the PI term's previous one only while the cut is at most
    /// [`MAX_SCALED_CUT`] and the norm not zero; past that, the memory keeps the last
    /// one's. Taken as it was, a sliver's norm (0.33 us against the 8.5 us around it: 3.8e-7
    /// against 0.083) read to the PI term as the error falling by five orders of magnitude
    /// and cut the next full step to 0.32 of its length; on the Table-1 compound case that
    /// cost 3 % of the right-hand sides (docs/lab/benchmarks.md).
    Cut {
        /// The step chosen before the cut over the step taken, > 1.
        chosen_over_taken: f64,
    },
}

/// Longest cut (chosen over taken step) whose scaled norm the PI term remembers. The
/// scaling holds where the log looked (the Table-1 case's 0.33 us sliver, 1/26 of its
/// step, scaled to 0.16 against its neighbours' 0.083), but `(chosen/taken)^q` also
/// magnifies the norm's rounding, ~1e-11 at a tolerance of 1e-5: to 1e-7 at 10, to ~2 at
/// the run's shortest cuts (1.2e-8 s of 8.5 us, 1/700). 10 keeps it far below the norms
/// the controller acts on, at the cost of what the longer slivers could have said.
pub const MAX_SCALED_CUT: f64 = 10.0;

impl Controller {
    pub fn new(q: u32) -> Self {
        let q = f64::from(q);
        Controller {
            err_exp: -0.7 / q,
            prev_exp: 0.4 / q,
            elementary_exp: -1.0 / q,
            prev_err: 1.0,
            just_rejected: false,
            q,
        }
    }

    /// Factor for the next step after an accepted one, which ended as `end` says, relative
    /// to the step taken.
    pub fn accept_factor(&mut self, err: f64, end: StepEnd) -> f64 {
        let ratio = match end {
            StepEnd::Chosen => 1.0,
            StepEnd::Cut { chosen_over_taken } => chosen_over_taken,
        };
        let e = (err * ratio.powf(self.q)).max(1e-10);
        let mut f = 0.9 * e.powf(self.err_exp) * self.prev_err.powf(self.prev_exp);
        if self.just_rejected || end != StepEnd::Chosen {
            f = f.min(1.0);
        }
        if ratio <= MAX_SCALED_CUT && (err > 0.0 || end == StepEnd::Chosen) {
            self.prev_err = e;
        }
        self.just_rejected = false;
        // relative to the chosen step, then to the step taken
        f.clamp(0.2, 4.0) * ratio
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

#[cfg(test)]
mod tests {
    use super::*;

    fn steady(c: &mut Controller) {
        for _ in 0..10 {
            c.accept_factor(0.1, StepEnd::Chosen);
        }
    }

    fn cut(ratio: f64) -> StepEnd {
        StepEnd::Cut {
            chosen_over_taken: ratio,
        }
    }

    /// A sliver (1/25 of the chosen step, past `MAX_SCALED_CUT`) with a tiny norm asks for
    /// the step it was cut from again, not more, and leaves the next full step's factor as
    /// the steady one's, as does a cut whose norm is exactly zero.
    #[test]
    fn a_sliver_leaves_the_controller_as_it_was() {
        for (ratio, err) in [(25.0, 0.1 / 25f64.powi(5)), (25.0, 0.0), (2.0, 0.0)] {
            let mut c = Controller::new(4);
            steady(&mut c);
            let f_steady = c.clone().accept_factor(0.1, StepEnd::Chosen);
            let f = c.accept_factor(err, cut(ratio));
            assert!((f / ratio - 1.0).abs() < 1e-12, "{ratio} {err}: {f}");
            let f_after = c.accept_factor(0.1, StepEnd::Chosen);
            assert!(
                (f_after / f_steady - 1.0).abs() < 1e-12,
                "{ratio} {err}: {f_after} {f_steady}"
            );
        }
    }

    /// A cut to half the step whose norm equals the steady steps' 0.1 enters as the step it
    /// was cut from would have erred, 0.1 2^4 = 1.6: the next chosen step is
    /// 0.9 1.6^-0.175 0.1^0.1 = 0.66 of that step (the old controller, taking 0.1 as it
    /// was, kept the proposal), and the chosen step after has 1.6 as its previous norm.
    #[test]
    fn a_cut_step_enters_as_the_step_it_was_cut_from() {
        let mut c = Controller::new(4);
        steady(&mut c);
        let f = c.accept_factor(0.1, cut(2.0));
        let expect = 0.9 * 1.6f64.powf(-0.175) * 0.1f64.powf(0.1);
        assert!((f / 2.0 / expect - 1.0).abs() < 1e-12, "{f} {expect}");
        let f_next = c.accept_factor(0.1, StepEnd::Chosen);
        let expect = 0.9 * 0.1f64.powf(-0.175) * 1.6f64.powf(0.1);
        assert!((f_next / expect - 1.0).abs() < 1e-12, "{f_next} {expect}");
    }
}
