//! A simulation job: reload the valid scene, run the engine, analyse the outer-ring
//! acceleration over the run's steady window, and build the stored record and artifacts.

use super::artifacts::{channel_artifacts, shaft_angle_artifact, spectrum_artifacts};
use super::control::Control;
use super::outcome::{to_stored, JobFailure, JobOutput};
use super::record::{
    AnalysisRecord, CageRecord, ChannelInfo, ContactRecord, ContactUnits, MinMeanMax,
    SimulationRecord, SpeedRecord,
};
use crate::store::{Artifact, FailureKind};
use crate::studies::scene_key;
use bearing_core::scene::ValidScene;
use bearing_core::simulation::{simulate, BallSummary, RunControl, SimError, SimResult};
use bearing_core::simulation_analysis::{
    diagnose_run, first_non_finite, frequency_comparison, run_shaft_angle,
};

/// Written beside the slip in every record, so the number is never read without it.
const SLIP_DEFINITION: &str = "slip = 1 - mean cage speed / epicyclic speed, where the epicyclic speed is the pure rolling (outer-race control) of the loaded balls: the load zone's contact angles weighted by their contact loads";

pub fn execute(input: &serde_json::Value, ctl: &Control) -> Result<JobOutput, JobFailure> {
    // Parsing validates: a stored scene that no longer validates fails the job here.
    let scene: ValidScene = serde_json::from_value(input.clone()).map_err(|e| {
        JobFailure::new(
            FailureKind::Invalid,
            format!("stored scene does not parse: {e}"),
        )
    })?;
    let mut on_progress = |f: f64| ctl.set_progress(f);
    let run = simulate(
        &scene,
        RunControl {
            cancel: Some(&ctl.cancel),
            progress: Some(&mut on_progress),
        },
    );
    let result = run.map_err(|e| match e {
        e if e.is_cancelled() => JobFailure::new(FailureKind::Cancelled, e.to_string()),
        e @ (SimError::InitialState(_) | SimError::Dynamics(_)) => {
            JobFailure::new(FailureKind::Numerical, e.to_string())
        }
    })?;
    let stats = serde_json::to_value(&result.summary.stats).ok();
    // A NaN that slipped past the engine fails the job rather than poisoning stored results.
    if let Some(message) = first_non_finite(&result) {
        return Err(JobFailure {
            kind: FailureKind::Numerical,
            message,
            stats,
        });
    }
    let (record, artifacts) = summarize(&scene, &result);
    Ok(JobOutput {
        result: to_stored(&record)?,
        stats,
        artifacts,
        scene_key: Some(scene_key(&scene)),
    })
}

/// The stored record and artifacts of a successful run.
pub fn summarize(scene: &ValidScene, result: &SimResult) -> (SimulationRecord, Vec<Artifact>) {
    let s = &result.summary;
    let mut artifacts = channel_artifacts(&result.channels);
    // the shaft angle, for exporting the run as a measured recording with its tachometer
    // (not listed among the channels: it is the prescribed speed's integral, not an output)
    if let Ok(angle) = run_shaft_angle(result, scene) {
        artifacts.push(shaft_angle_artifact(&result.channels, angle.radians()));
    }
    let (analysis, analysis_error) = match diagnose_run(result, scene) {
        Ok((channel, options, out)) => {
            artifacts.extend(spectrum_artifacts(&out));
            let record = AnalysisRecord {
                report: out.report,
                options,
                channel: Some(channel.to_string()),
            };
            (Some(record), None)
        }
        Err(msg) => (None, Some(msg)),
    };
    let stat = |f: fn(&BallSummary) -> f64| MinMeanMax::of(s.balls.iter().map(f));
    let record = SimulationRecord {
        scene_name: scene.name.clone(),
        engine: bearing_core::ENGINE_DIGEST.to_string(),
        solver: s.stats.clone(),
        steady_window: s.steady_window,
        shaft_speed: SpeedRecord {
            mean: s.mean_shaft_speed,
            unit: "rad/s".into(),
        },
        cage: CageRecord {
            mean_speed: s.mean_cage_speed,
            epicyclic_speed: s.epicyclic_cage_speed,
            slip: s.cage_slip,
            slip_definition: Some(SLIP_DEFINITION.into()),
            motion: Some(s.cage_motion),
            unit: "rad/s".into(),
        },
        frequencies: Some(frequency_comparison(result, scene)),
        mean_inner_ring_reaction: s.mean_inner_ring_reaction,
        contact: ContactRecord {
            inner_load: stat(|b| b.inner_load),
            outer_load: stat(|b| b.outer_load),
            inner_contact_angle: stat(|b| b.inner_contact_angle),
            outer_contact_angle: stat(|b| b.outer_contact_angle),
            units: ContactUnits {
                load: "N".into(),
                angle: "rad".into(),
            },
        },
        balls: s.balls.clone(),
        channels: result
            .channels
            .channels
            .iter()
            .map(|c| ChannelInfo {
                name: c.name.clone(),
                unit: c.unit.clone(),
                samples: c.data.len(),
            })
            .collect(),
        sample_rate: result.channels.sample_rate,
        start_time: result.channels.start_time,
        analysis,
        analysis_error,
    };
    (record, artifacts)
}
