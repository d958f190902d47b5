//! The stepping loop: adaptive or fixed RK4 under the defect step bound, output
//! sampling, steady-window averages, progress and cancellation.

use super::averages::Averages;
use super::control::RunControl;
use super::error::DynError;
use super::error_scale::scales;
use super::integrator::{AdaptiveRk4, FixedRk4, StepStats};
use super::output::{SimResult, SolverStats};
use super::recorder::Recorder;
use super::rhs::{rhs, Diagnostics};
use super::step_bound::defect_step_bound;
use super::system::BearingSystem;
use super::window::steady_window;
use crate::model::Model;
use crate::scene::{Integrator, ValidScene};
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Integrate from the state `y0` at t = 0 to the scene's duration.
pub fn integrate(
    m: &Model,
    scene: &ValidScene,
    y0: Vec<f64>,
    ctl: RunControl<'_>,
) -> Result<SimResult, DynError> {
    let RunControl {
        cancel,
        mut progress,
    } = ctl;
    let sv = &scene.solver;
    let tend = sv.duration;
    let n = m.layout.len;
    let mut sys = BearingSystem { model: m };
    assert_eq!(y0.len(), n, "initial state of the wrong length");
    let mut y = y0;
    let mut f = vec![0.0; n];
    let mut y_next = vec![0.0; n];
    let mut f_next = vec![0.0; n];
    let mut diag = Diagnostics::new(m.z);
    let mut stats = StepStats::default();
    rhs(m, 0.0, &y, &mut f, Some(&mut diag));
    stats.rhs_evals += 1;

    let mut rec = Recorder::new(m, &scene.outputs, sv.sample_rate, tend);
    let [w0, _] = steady_window(m.speed.2, tend);
    let mut acc = Averages::new(m.z);

    let (scale, phase) = scales(m);
    let mut adaptive = AdaptiveRk4::new(n, sv.rtol, sv.atol, scale, phase);
    let mut fixed = FixedRk4::new(n);
    let is_fixed = sv.integrator == Integrator::Rk4Fixed;
    let mut h = sv.initial_step.min(tend);
    let h_min = 1e-14_f64.max(tend * 1e-13);
    let start = Instant::now();
    let mut last_report = Instant::now();
    let mut t = 0.0;
    rec.sample(m, t, 0.0, &y, &f, &y, &f);
    while t < tend {
        if let Some(c) = cancel {
            if c.load(Ordering::Relaxed) {
                return Err(DynError::Cancelled { at: t });
            }
        }
        let remaining = tend - t;
        let mut h_try = if is_fixed {
            sv.initial_step
        } else {
            h.min(sv.max_step).min(defect_step_bound(m, t, &y))
        };
        // land exactly on the end without a sliver step
        if h_try >= remaining * (1.0 - 1e-12) {
            h_try = remaining;
        } else if h_try > 0.5 * remaining {
            h_try = 0.5 * remaining;
        }
        let y_new: &[f64] = if is_fixed {
            fixed.step(&mut sys, t, &y, &f, h_try, &mut stats);
            &fixed.y_new
        } else {
            let err = adaptive.attempt(&mut sys, t, &y, &f, h_try, &mut stats);
            if !(err <= 1.0) {
                stats.rejected += 1;
                h = h_try * adaptive.reject_factor(err);
                if h < h_min {
                    return Err(DynError::StepUnderflow {
                        time: t,
                        step: h,
                        min_step: h_min,
                        error_norm: err,
                    });
                }
                continue;
            }
            h = h_try * adaptive.accept_factor(err);
            &adaptive.y_new
        };
        y_next.copy_from_slice(y_new);
        let t_new = if h_try == remaining { tend } else { t + h_try };
        rhs(m, t_new, &y_next, &mut f_next, Some(&mut diag));
        stats.rhs_evals += 1;
        if let Some(i) = y_next
            .iter()
            .chain(f_next.iter())
            .position(|v| !v.is_finite())
        {
            return Err(DynError::NonFinite {
                time: t_new,
                component: i % n,
                len: n,
                step: h_try,
            });
        }
        stats.record(h_try);
        rec.sample(m, t, h_try, &y, &f, &y_next, &f_next);
        if t_new > w0 {
            let wgt = t_new - t.max(w0);
            acc.add(m, t_new, wgt, &y_next, &diag);
        }
        std::mem::swap(&mut y, &mut y_next);
        std::mem::swap(&mut f, &mut f_next);
        t = t_new;
        if let Some(p) = progress.as_deref_mut() {
            if last_report.elapsed().as_millis() >= 10 {
                last_report = Instant::now();
                p(t / tend);
            }
        }
    }
    if let Some(p) = progress.as_deref_mut() {
        p(1.0);
    }
    let wall = start.elapsed().as_secs_f64();
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
