//! The budgets of a job, checked before it is queued: a scene whose estimated solver work
//! is over `--max-scene-evaluations`, or a simulation or analysis whose outputs would
//! store more than `--max-job-bytes`, is refused naming the fields that make it expensive.

use super::problem::{join_path, FieldProblem};
use crate::config::Config;
use bearing_core::scene::cost::estimate;
use bearing_core::scene::Scene;
use bearing_core::signal::analysis::AnalysisOptions;

/// Bytes a run of `scene` stores: each recorded channel as f32, and the envelope spectra
/// of its analysis (levels + 1 spectra of at most n/2 bins, f32).
pub fn simulation_bytes(scene: &Scene) -> f64 {
    let o = &scene.outputs;
    let channels = 2 // outer-ring acceleration y and z, always
        + 2 * usize::from(o.cage_speed) // speed and eccentricity
        + 3 * usize::from(o.inner_ring_displacement)
        + 2 * usize::from(o.contact_loads_ball.is_some())
        + 3 * usize::from(o.ball_pocket.is_some())
        + 1; // the shaft angle, kept for exports
    let samples = scene.solver.duration * scene.solver.sample_rate;
    4.0 * channels as f64 * samples + spectra_bytes(samples, AnalysisOptions::default().levels)
}

/// Bytes an analysis of `n` samples at `levels` levels stores: the samples (f64) and its
/// envelope spectra.
pub fn analysis_bytes(n: usize, levels: usize) -> f64 {
    8.0 * n as f64 + spectra_bytes(n as f64, levels)
}

/// `levels + 1` envelope spectra (raw and per level) of `n / 2 + 1` bins, f32.
fn spectra_bytes(n: f64, levels: usize) -> f64 {
    4.0 * (levels + 1) as f64 * (n / 2.0 + 1.0)
}

/// Problems (at `prefix`.field) when `scene` is over the configured budgets: solver work
/// (--max-scene-evaluations) and stored output (--max-job-bytes).
pub fn over_budget(scene: &Scene, config: &Config, prefix: &str) -> Vec<FieldProblem> {
    let mut problems = over_work(scene, config, prefix);
    problems.extend(over_bytes(
        simulation_bytes(scene),
        config,
        &["solver.duration", "solver.sample_rate"].map(|f| join_path(prefix, f)),
        "of channels and spectra",
        "shorten the run, lower the sample rate or record fewer outputs",
    ));
    problems
}

/// Problems naming `samples` and `options.levels` when an analysis of `n` samples at
/// `levels` levels would store more than --max-job-bytes.
pub fn over_analysis_budget(n: usize, levels: usize, config: &Config) -> Vec<FieldProblem> {
    over_bytes(
        analysis_bytes(n, levels),
        config,
        &["samples".into(), "options.levels".into()],
        &format!("of samples and spectra ({n} samples at {levels} levels)"),
        "send fewer samples or fewer levels",
    )
}

/// One problem per field in `paths` when `bytes` is over --max-job-bytes.
fn over_bytes(
    bytes: f64,
    config: &Config,
    paths: &[String],
    what: &str,
    remedy: &str,
) -> Vec<FieldProblem> {
    let limit = config.max_job_bytes as f64;
    if bytes <= limit {
        return Vec::new();
    }
    paths
        .iter()
        .map(|path| FieldProblem {
            path: path.clone(),
            message: format!(
                "the job would store {bytes:.3e} bytes {what}, over the limit of {limit:.3e} per job (--max-job-bytes); {remedy}"
            ),
        })
        .collect()
}

fn over_work(scene: &Scene, config: &Config, prefix: &str) -> Vec<FieldProblem> {
    let est = estimate(scene);
    let limit = config.max_scene_evaluations;
    if est.evaluations <= limit {
        return Vec::new();
    }
    est.fields
        .iter()
        .map(|f| FieldProblem {
            path: join_path(prefix, f),
            message: format!(
                "the scene is estimated at {:.3e} right-hand-side evaluations, over the budget of {limit:.3e} (--max-scene-evaluations); shorten solver.duration or take a larger step",
                est.evaluations
            ),
        })
        .collect()
}
