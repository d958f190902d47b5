//! Stiffness switching between an explicit Runge-Kutta method with a first-same-as-last
//! estimate and the Rosenbrock-W method.
//!
//! Measured on the bearing (docs/lab/benchmarks.md): on the Table-1 scenes the explicit
//! method is the cheaper at equal error, its step held near the stability limit of the
//! ball-race contact modes; when the cage whirls on its land film after a fast start, a
//! stiffer mode holds the explicit step some fifty times below that limit, where the
//! linearly implicit method, whose block Jacobian contains the cage, keeps steps of
//! ~1e-5 s. So: run explicitly, and go implicit while the explicit controller keeps
//! asking for steps below a tenth of the largest step it has ever accepted (its stability
//! limit in practice); come back when the implicit steps are no longer above that limit.
//! Each return demands a twice longer streak before the next, so a regime at the border
//! cannot make the methods alternate step by step.

use super::explicit_rk::ExplicitRk;
use super::method::Method;
use super::problem::JacobianSystem;
use super::rosenbrock::Rosenbrock;
use super::stats::StepStats;

/// Consecutive accepted steps that must agree before a switch.
const STREAK: u32 = 200;
/// Go implicit when explicit proposals stay below this fraction of the explicit limit.
const DOWN: f64 = 0.1;
/// Come back when implicit proposals stay below this fraction of the explicit limit.
const UP: f64 = 1.0;
/// Explicit steps not counted towards the limit: the first steps from an exact
/// equilibrium can exceed the stability limit before any unstable mode has grown.
const SETTLE: u64 = 50;

pub struct AutoSwitch {
    explicit: ExplicitRk,
    implicit: Rosenbrock,
    on_implicit: bool,
    /// Method to use from the next attempt (a switch waits until the solver has read the
    /// accepted step's result).
    pending: Option<bool>,
    last_h: f64,
    /// Largest step the explicit method has accepted after its first `SETTLE` steps, s.
    explicit_limit: f64,
    explicit_accepted: u64,
    streak: u32,
    /// Switches made so far (each return to the explicit method doubles the next streak).
    pub switches: u32,
}

impl AutoSwitch {
    /// `explicit` must be controlled through a first-same-as-last estimate (its step-end
    /// derivative is the solver's next first stage).
    pub fn new(explicit: ExplicitRk, implicit: Rosenbrock) -> Self {
        assert!(
            explicit.f_new().is_some(),
            "the explicit method must evaluate its step end (first same as last)"
        );
        AutoSwitch {
            explicit,
            implicit,
            on_implicit: false,
            pending: None,
            last_h: 0.0,
            explicit_limit: 0.0,
            explicit_accepted: 0,
            streak: 0,
            switches: 0,
        }
    }

    /// True while the implicit method is in use.
    pub fn implicit(&self) -> bool {
        self.on_implicit
    }

    fn needed_streak(&self) -> u32 {
        STREAK << (self.switches / 2).min(10)
    }
}

impl<S: JacobianSystem> Method<S> for AutoSwitch {
    fn attempt(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
        t_end: f64,
        stats: &mut StepStats,
    ) -> f64 {
        if let Some(to_implicit) = self.pending.take() {
            self.on_implicit = to_implicit;
            if to_implicit {
                self.implicit.refresh_jacobian();
            }
        }
        self.last_h = h;
        if self.on_implicit {
            self.implicit.attempt_step(sys, t, y, f0, h, stats)
        } else {
            self.explicit.attempt_step(sys, t, y, f0, h, t_end, stats)
        }
    }

    fn y_new(&self) -> &[f64] {
        if self.on_implicit {
            self.implicit.y_new()
        } else {
            self.explicit.y_new()
        }
    }

    fn f_new(&self) -> Option<&[f64]> {
        if self.on_implicit {
            None
        } else {
            self.explicit.f_new()
        }
    }

    fn accept_factor(&mut self, err: f64) -> f64 {
        let f = if self.on_implicit {
            self.implicit.accept_factor(err)
        } else {
            self.explicit_accepted += 1;
            if self.explicit_accepted > SETTLE {
                self.explicit_limit = self.explicit_limit.max(self.last_h);
            }
            Method::<S>::accept_factor(&mut self.explicit, err)
        };
        let proposal = self.last_h * f;
        let crossing = if self.on_implicit {
            proposal < UP * self.explicit_limit
        } else {
            proposal < DOWN * self.explicit_limit
        };
        self.streak = if crossing { self.streak + 1 } else { 0 };
        if self.streak >= self.needed_streak() {
            self.pending = Some(!self.on_implicit);
            self.streak = 0;
            self.switches += 1;
        }
        f
    }

    fn reject_factor(&mut self, err: f64) -> f64 {
        if self.on_implicit {
            self.implicit.reject_factor(err)
        } else {
            Method::<S>::reject_factor(&mut self.explicit, err)
        }
    }
}
