//! The cost budget of a scene: a scene whose estimated solver work is over
//! `--max-scene-evaluations` is refused before it is queued, naming the fields that make
//! it expensive.

use super::problem::{join_path, FieldProblem};
use crate::config::Config;
use bearing_core::scene::cost::estimate;
use bearing_core::scene::Scene;

/// Problems (at `prefix`.field) when `scene` is estimated over the configured budget.
pub fn over_budget(scene: &Scene, config: &Config, prefix: &str) -> Vec<FieldProblem> {
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
