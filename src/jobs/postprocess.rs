//! After a successful simulation: analyse the outer-ring acceleration and build the
//! stored result summary, channel and spectrum artifacts.

use super::analysis_job::{analysis_json, spectrum_artifacts};
use crate::store::blob::encode_f32le;
use crate::store::Artifact;
use bearing_sim::scene::Scene;
use bearing_sim::signal::analysis::{
    analyze_simulation, simulation_window, AnalysisOptions, AnalysisOutput,
};
use bearing_sim::simulation::{Channels, SimResult};
use serde_json::json;

/// Channels tried for the diagnosis, in order.
const ANALYSIS_CHANNELS: &[&str] = &["outer_ring_accel_z", "outer_ring_accel_y"];

pub fn summarize(scene: &Scene, result: &SimResult) -> (serde_json::Value, Vec<Artifact>) {
    let s = &result.summary;
    let mut artifacts = channel_artifacts(&result.channels);

    let (analysis, analysis_error) = match run_analysis(scene, result) {
        Ok((channel, out)) => {
            artifacts.extend(spectrum_artifacts(&out));
            let mut a = analysis_json(&out.report);
            a["channel"] = json!(channel);
            (a, None)
        }
        Err(msg) => (serde_json::Value::Null, Some(msg)),
    };

    let stat = |f: &dyn Fn(&bearing_sim::simulation::BallSummary) -> f64| {
        let v: Vec<f64> = s.balls.iter().map(f).collect();
        if v.is_empty() {
            return serde_json::Value::Null;
        }
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let min = v.iter().cloned().fold(f64::INFINITY, f64::min);
        let max = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        json!({"min": min, "mean": mean, "max": max})
    };
    let summary = json!({
        "scene_name": scene.name,
        "solver": s.stats,
        "steady_window": s.steady_window,
        "shaft_speed": {"mean": s.mean_shaft_speed, "unit": "rad/s"},
        "cage": {
            "mean_speed": s.mean_cage_speed,
            "epicyclic_speed": s.epicyclic_cage_speed,
            "slip": s.cage_slip,
            "unit": "rad/s"
        },
        "mean_inner_ring_reaction": s.mean_inner_ring_reaction,
        "contact": {
            "inner_load": stat(&|b| b.inner_load),
            "outer_load": stat(&|b| b.outer_load),
            "inner_contact_angle": stat(&|b| b.inner_contact_angle),
            "outer_contact_angle": stat(&|b| b.outer_contact_angle),
            "units": {"load": "N", "angle": "rad"}
        },
        "balls": s.balls,
        "channels": result.channels.channels.iter().map(|c| json!({
            "name": c.name, "unit": c.unit, "samples": c.data.len()
        })).collect::<Vec<_>>(),
        "sample_rate": result.channels.sample_rate,
        "start_time": result.channels.start_time,
        "analysis": analysis,
        "analysis_error": analysis_error,
    });
    (summary, artifacts)
}

fn channel_artifacts(ch: &Channels) -> Vec<Artifact> {
    ch.channels
        .iter()
        .map(|c| Artifact {
            name: format!("channel:{}", c.name),
            meta: json!({
                "name": c.name, "unit": c.unit, "sample_rate": ch.sample_rate,
                "start_time": ch.start_time, "samples": c.data.len()
            }),
            data: encode_f32le(&c.data),
        })
        .collect()
}

/// Shortest window worth analysing, s (a few shaft turns at spindle speeds).
const MIN_WINDOW: f64 = 0.005;

/// The engine's steady window when it has one, else the signal module's default after the
/// ramp; a run that ends before its ramp settles is analysed over its second half.
fn analysis_options(scene: &Scene, result: &SimResult) -> AnalysisOptions {
    let mut opts = AnalysisOptions::default();
    let [s0, s1] = result.summary.steady_window;
    if s1 - s0 < MIN_WINDOW {
        let t0 = result.channels.start_time;
        let duration = scene.solver.duration;
        let w = simulation_window(scene.operating.speed.ramp_time, duration);
        let w = if w[1] - w[0] >= MIN_WINDOW {
            w
        } else {
            [0.5 * duration, duration]
        };
        opts.window = Some([(w[0] - t0).max(0.0), (w[1] - t0).max(0.0)]);
    }
    opts
}

fn run_analysis(scene: &Scene, result: &SimResult) -> Result<(String, AnalysisOutput), String> {
    let channel = ANALYSIS_CHANNELS
        .iter()
        .find(|n| result.channels.get(n).is_some())
        .ok_or_else(|| {
            format!(
                "no channel named {} to analyse",
                ANALYSIS_CHANNELS.join(" or ")
            )
        })?;
    let out = analyze_simulation(result, scene, channel, &analysis_options(scene, result))
        .map_err(|e| format!("analysis of {channel} not possible: {e}"))?;
    Ok((channel.to_string(), out))
}
