//! Analysis of a simulated signal: the glue above the simulation and the signal analysis
//! (neither knows the other).

use crate::scene::Scene;
use crate::signal::analysis::{analyze, AnalysisError, AnalysisOptions, AnalysisOutput};
use crate::signal::frequencies::KinematicGeometry;
use crate::signal::spectrum::band_rms;
use crate::simulation::SimResult;

/// Analyse `channel` of a simulation result: sample rate from the result, geometry from
/// the scene's bearing, shaft speed from the run's mean shaft speed (the steady rpm if
/// absent), and, unless `opts.window` is given, the engine's steady window (the window the
/// summary averages over: it is chosen once, by the run).
pub fn analyze_simulation(
    result: &SimResult,
    scene: &Scene,
    channel: &str,
    opts: &AnalysisOptions,
) -> Result<AnalysisOutput, AnalysisError> {
    let ch = result
        .channels
        .get(channel)
        .ok_or_else(|| AnalysisError::Invalid {
            field: "channel".into(),
            message: format!("no channel named '{channel}'"),
        })?;
    let fs = result.channels.sample_rate;
    let start = result.channels.start_time;
    let mean_speed = result.summary.mean_shaft_speed;
    let shaft_hz = if mean_speed > 0.0 {
        mean_speed / (2.0 * std::f64::consts::PI)
    } else {
        scene.operating.speed.steady_rpm / 60.0
    };
    let mut o = opts.clone();
    if o.window.is_none() {
        let duration = ch.data.len() as f64 / fs.max(f64::MIN_POSITIVE);
        let [s0, s1] = result.summary.steady_window;
        o.window = Some([(s0 - start).max(0.0), (s1 - start).min(duration)]);
    }
    analyze(
        &ch.data,
        fs,
        &KinematicGeometry::from_bearing(&scene.bearing),
        shaft_hz,
        &o,
    )
}

/// RMS of `channel` below `fmax` (Hz) over the summary's steady window, in the channel's
/// unit; `None` for a channel the run did not record.
pub fn steady_band_rms(result: &SimResult, channel: &str, fmax: f64) -> Option<f64> {
    let samples = result.steady_samples(channel)?;
    Some(band_rms(samples, result.channels.sample_rate, fmax))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::window::steady_window;
    use crate::simulation::{Channel, Channels, Summary};

    #[test]
    fn simulation_results_are_analysed_over_the_steady_window() {
        let mut scene = crate::scene::preset_scene("h7005c").unwrap();
        scene.operating.speed.ramp_time = 0.2;
        scene.solver.duration = 1.2;
        let fs = 20_000.0;
        // a huge transient during the ramp, then a steady tone
        let data: Vec<f64> = (0..24_000)
            .map(|i| {
                if i < 4_000 {
                    1e3
                } else {
                    (i as f64 * 0.3).sin()
                }
            })
            .collect();
        let result = SimResult {
            summary: Summary {
                steady_window: steady_window(0.2, 1.2),
                ..Summary::default()
            },
            channels: Channels {
                sample_rate: fs,
                start_time: 0.0,
                channels: vec![Channel {
                    name: "outer_ring_accel_y".into(),
                    unit: "m/s^2".into(),
                    data,
                }],
            },
        };
        let out = analyze_simulation(
            &result,
            &scene,
            "outer_ring_accel_y",
            &AnalysisOptions::default(),
        )
        .unwrap();
        // ramp end 0.2 s + min(25 % of the remaining 1.0 s, 0.1 s) -> [0.3, 1.2]
        assert!(
            (out.report.window[0] - 0.3).abs() < 1e-9 && (out.report.window[1] - 1.2).abs() < 1e-9
        );
        assert!((out.report.shaft_hz - scene.operating.speed.steady_rpm / 60.0).abs() < 1e-9);
        assert!(out.report.raw_kurtosis < 2.0, "ramp transient excluded");
        let e =
            analyze_simulation(&result, &scene, "nope", &AnalysisOptions::default()).unwrap_err();
        assert_eq!(e.to_string(), "channel: no channel named 'nope'");
    }
}
