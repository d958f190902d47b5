//! The budgets of a scene: a scene whose estimated solver work is over
//! `--max-scene-evaluations`, or whose output would store more than `--max-job-bytes`, is
//! refused before it is queued, naming the fields that make it expensive.

use super::problem::{join_path, FieldProblem};
use crate::config::Config;
use bearing_core::scene::cost::estimate;
use bearing_core::scene::Scene;
use bearing_core::signal::analysis::AnalysisOptions;

/// Bytes a run of `scene` stores: each recorded channel as f32, and the envelope spectra
/// of its analysis (levels + 1 spectra of at most n/2 bins, f32).
pub fn stored_bytes(scene: &Scene) -> f64 {
    let o = &scene.outputs;
    let channels = 2 // outer-ring acceleration y and z, always
        + 2 * usize::from(o.cage_speed) // speed and eccentricity
        + 3 * usize::from(o.inner_ring_displacement)
        + 2 * usize::from(o.contact_loads_ball.is_some());
    let samples = scene.solver.duration * scene.solver.sample_rate;
    let spectra = (AnalysisOptions::default().levels + 1) as f64 * (samples / 2.0 + 1.0);
    4.0 * (channels as f64 * samples + spectra)
}

/// Problems (at `prefix`.field) when `scene` is estimated over the configured budgets:
/// solver work (--max-scene-evaluations) and stored output (--max-job-bytes).
pub fn over_budget(scene: &Scene, config: &Config, prefix: &str) -> Vec<FieldProblem> {
    let mut problems = over_work(scene, config, prefix);
    let bytes = stored_bytes(scene);
    let limit = config.max_job_bytes as f64;
    if bytes > limit {
        for f in ["solver.duration", "solver.sample_rate"] {
            problems.push(FieldProblem {
                path: join_path(prefix, f),
                message: format!(
                    "the run would store {bytes:.3e} bytes of channels and spectra, over the limit of {limit:.3e} per job (--max-job-bytes); shorten the run, lower the sample rate or record fewer outputs"
                ),
            });
        }
    }
    problems
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
