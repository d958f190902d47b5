//! Counts of a solver's steps and evaluations.

/// Integration statistics.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepStats {
    pub accepted: u64,
    pub rejected: u64,
    pub rhs_evals: u64,
    /// s.
    pub min_step: f64,
    /// s.
    pub max_step: f64,
}

impl StepStats {
    pub fn record(&mut self, h: f64) {
        self.accepted += 1;
        if self.accepted == 1 {
            self.min_step = h;
            self.max_step = h;
        } else {
            self.min_step = self.min_step.min(h);
            self.max_step = self.max_step.max(h);
        }
    }
}
