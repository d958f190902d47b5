//! The bearing model as an ODE system for the integrators.

use super::integrator::OdeSystem;
use super::rhs::rhs;
use crate::model::Model;

/// The model as an ODE system.
pub struct BearingSystem<'m> {
    pub model: &'m Model,
}

impl OdeSystem for BearingSystem<'_> {
    fn dim(&self) -> usize {
        self.model.layout.len
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        rhs(self.model, t, y, dy, None);
    }
}
