//! The run loop: the chosen method under the solver, output sampling, steady-window
//! averages, progress and cancellation.

use super::averages::Averages;
use super::error_scale::scales;
use super::output::{SimResult, SolverStats};
use super::recorder::Recorder;
use super::system::{
    ball_velocity_jacobian, bearing_jacobian, linear_part, BearingSystem, JacobianScope,
};
use super::window::steady_window;
use crate::model::Model;
use crate::ode::auto_switch::{AutoSwitch, SwitchRule};
use crate::ode::control::RunControl;
use crate::ode::error::SolveError;
use crate::ode::error_norm::ErrorNorm;
use crate::ode::etd_rk4::EtdRk4;
use crate::ode::explicit_rk::ExplicitRk;
use crate::ode::method::Method;
use crate::ode::rosenbrock::Rosenbrock;
use crate::ode::rosenbrock_tableau::Tableau;
use crate::ode::solver::{Solver, StepLimits};
use crate::ode::tableau::{CASH_KARP, CLASSICAL_RK4, RK4_FSAL};
use crate::scene::{Integrator, ValidScene};
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Integrate from the state `y0` at t = 0 to the scene's duration.
pub fn integrate(
    m: &Model,
    scene: &ValidScene,
    y0: Vec<f64>,
    ctl: RunControl<'_>,
) -> Result<SimResult, SolveError> {
    let sv = &scene.solver;
    let n = m.layout.len;
    let (scale, phase) = scales(m);
    let mut sys = BearingSystem::new(m, &scale);
    let limits = step_limits(scene, sv.duration);
    // the bearing's natural sizes scale the error norm (and the Jacobian's differences)
    let norm = ErrorNorm::new(sv.rtol, sv.atol, scale.clone(), phase);
    // one monomorphised loop per method
    match sv.integrator {
        Integrator::Rk4Adaptive => {
            let method = ExplicitRk::adaptive(&CASH_KARP, n, norm);
            let solver = Solver::new(&mut sys, method, y0, limits);
            drive(solver, &mut sys, scene, ctl)
        }
        Integrator::Rk4Fixed => {
            let method = ExplicitRk::fixed(&CLASSICAL_RK4, n);
            let solver = Solver::new(&mut sys, method, y0, limits);
            drive(solver, &mut sys, scene, ctl)
        }
        Integrator::Rk4Fsal => {
            let method = ExplicitRk::adaptive(&RK4_FSAL, n, norm);
            let solver = Solver::new(&mut sys, method, y0, limits);
            drive(solver, &mut sys, scene, ctl)
        }
        Integrator::Auto => {
            let explicit = ExplicitRk::adaptive(&RK4_FSAL, n, norm.clone());
            let implicit = Rosenbrock::new(n, norm, bearing_jacobian(m));
            let solver = Solver::new(&mut sys, AutoSwitch::new(explicit, implicit), y0, limits);
            drive(solver, &mut sys, scene, ctl)
        }
        Integrator::RosenbrockW => {
            let method = Rosenbrock::new(n, norm, bearing_jacobian(m));
            let solver = Solver::new(&mut sys, method, y0, limits);
            drive(solver, &mut sys, scene, ctl)
        }
        Integrator::SlipImplicit => {
            sys.scope = JacobianScope::BallVelocities;
            let method = slip_implicit(n, norm, m);
            let solver = Solver::new(&mut sys, method, y0, limits);
            drive(solver, &mut sys, scene, ctl)
        }
        Integrator::EtdRk4 => {
            let method = EtdRk4::new(n, norm, linear_part(m));
            let solver = Solver::new(&mut sys, method, y0, limits);
            drive(solver, &mut sys, scene, ctl)
        }
        Integrator::AutoEtd => {
            sys.scope = JacobianScope::BallVelocities;
            let explicit = EtdRk4::new(n, norm.clone(), linear_part(m));
            let implicit = slip_implicit(n, norm, m);
            let method = AutoSwitch::with_rule(explicit, implicit, SwitchRule::MeasuredCost);
            let solver = Solver::new(&mut sys, method, y0, limits);
            drive(solver, &mut sys, scene, ctl)
        }
        Integrator::AutoSlip => {
            sys.scope = JacobianScope::BallVelocities;
            let explicit = ExplicitRk::adaptive(&RK4_FSAL, n, norm.clone());
            let implicit = slip_implicit(n, norm, m);
            let method = AutoSwitch::with_rule(explicit, implicit, SwitchRule::MeasuredCost);
            let solver = Solver::new(&mut sys, method, y0, limits);
            drive(solver, &mut sys, scene, ctl)
        }
    }
}

/// The scene's step limits for a run to `t_end` (s): its initial and largest step, and an
/// underflow below 1e-13 of the run (at least 1e-14 s).
pub fn step_limits(scene: &ValidScene, t_end: f64) -> StepLimits {
    let sv = &scene.solver;
    StepLimits {
        t_end,
        initial_step: sv.initial_step,
        max_step: sv.max_step,
        min_step: 1e-14_f64.max(t_end * 1e-13),
    }
}

/// The method of `slip_implicit` (and `auto_slip`'s implicit one): implicit in each ball's
/// velocities, with ROS34PRw, whose explicit part is as stable on the imaginary axis as RK4,
/// which the contact's elastic modes (left explicit) need.
fn slip_implicit(n: usize, norm: ErrorNorm, m: &Model) -> Rosenbrock {
    Rosenbrock::new(n, norm, ball_velocity_jacobian(m)).with_tableau(Tableau::ros34prw())
}

fn drive<'m, M: for<'s> Method<BearingSystem<'s>>>(
    mut solver: Solver<M>,
    sys: &mut BearingSystem<'m>,
    scene: &ValidScene,
    ctl: RunControl<'_>,
) -> Result<SimResult, SolveError> {
    let RunControl {
        cancel,
        mut progress,
    } = ctl;
    let m = sys.model;
    let sv = &scene.solver;
    let tend = sv.duration;
    let mut rec = Recorder::new(m, &scene.outputs, sv.sample_rate, tend);
    let [w0, _] = steady_window(m.speed.2, tend);
    let mut acc = Averages::new(m.z, w0);
    let start = Instant::now();
    let mut last_report = Instant::now();
    rec.sample(
        m,
        0.0,
        0.0,
        solver.y(),
        solver.f(),
        solver.y(),
        solver.f(),
        Some(&sys.track),
        &|_, _| false,
    );
    while !solver.finished() {
        if let Some(c) = cancel {
            if c.load(Ordering::Relaxed) {
                return Err(SolveError::Cancelled { at: solver.t() });
            }
        }
        solver.step(sys)?;
        let last = solver.last_step();
        rec.sample(
            m,
            last.t,
            last.h,
            last.y0,
            last.f0,
            last.y1,
            last.f1,
            Some(&sys.track),
            &|s, out| solver.refine_dense::<BearingSystem<'m>>(s, out),
        );
        let t_new = solver.t();
        acc.add(m, &last, t_new, &sys.diag);
        if let Some(p) = progress.as_deref_mut() {
            if last_report.elapsed().as_millis() >= 10 {
                last_report = Instant::now();
                p(t_new / tend);
            }
        }
    }
    if let Some(p) = progress {
        p(1.0);
    }
    let wall = start.elapsed().as_secs_f64();
    let stats = solver.stats;
    let summary = acc.finish(
        m,
        [w0, tend],
        SolverStats {
            accepted_steps: stats.accepted,
            rejected_steps: stats.rejected,
            rhs_evaluations: stats.rhs_evals,
            min_step: stats.min_step,
            max_step: stats.max_step,
            wall_time: wall,
        },
    );
    Ok(SimResult {
        summary,
        channels: rec.finish(),
    })
}
