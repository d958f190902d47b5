//! Analysis of a simulated signal: the glue above the simulation and the signal analysis
//! (neither knows the other).

use crate::model::Model;
use crate::scene::Scene;
use crate::signal::analysis::{
    analyze, AnalysisError, AnalysisOptions, AnalysisOutput, LevelSpectra,
};
use crate::signal::frequencies::{characteristic_frequencies, KinematicGeometry};
use crate::signal::order_tracking::{analyze_tracked, angle_speed_varies};
use crate::signal::shaft_angle::{ShaftAngle, ShaftAngleError};
use crate::signal::spectrum::band_rms;
use crate::simulation::SimResult;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Channels a simulated run is diagnosed from, in order of preference: the pedestal's
/// accelerometer (the outer ring's acceleration, eq. 36), vertical then horizontal. The
/// service's simulation jobs and the command line's in-process studies both read this
/// list, so a study point gives the same row either way.
pub const DIAGNOSIS_CHANNELS: [&str; 2] = ["outer_ring_accel_z", "outer_ring_accel_y"];

/// The first non-finite sample a run recorded, as a message naming its channel and index
/// (a NaN that slipped past the solver must fail the run, not poison its results).
pub fn first_non_finite(result: &SimResult) -> Option<String> {
    result.channels.channels.iter().find_map(|ch| {
        ch.data
            .iter()
            .position(|x| !x.is_finite())
            .map(|k| format!("channel {} has a non-finite sample at index {k}", ch.name))
    })
}

/// The shaft's angle at every sample of a run's channels, rad: the inner ring's speed is
/// prescribed by the scene's profile, so its angle is that profile's integral
/// ([`Model::shaft_angle`]), exactly what the run turned. Order tracking resamples by it.
pub fn run_shaft_angle(result: &SimResult, scene: &Scene) -> Result<ShaftAngle, String> {
    let valid = scene.validated().map_err(|e| e.to_string())?;
    let model = Model::new(&valid);
    let ch = &result.channels;
    let n = ch.channels.first().map_or(0, |c| c.data.len());
    let angles = (0..n)
        .map(|k| model.shaft_angle(ch.start_time + k as f64 / ch.sample_rate))
        .collect();
    ShaftAngle::new(angles, n).map_err(|e: ShaftAngleError| e.to_string())
}

/// The diagnosis of a run: the first of [`DIAGNOSIS_CHANNELS`] it recorded, analysed
/// over its steady window with the default options. `Err` says why there is none (the run
/// itself stands).
pub fn diagnose_run(
    result: &SimResult,
    scene: &Scene,
) -> Result<(&'static str, AnalysisOptions, AnalysisOutput), String> {
    let channel = DIAGNOSIS_CHANNELS
        .iter()
        .copied()
        .find(|n| result.channels.get(n).is_some())
        .ok_or_else(|| {
            format!(
                "no channel named {} to analyse",
                DIAGNOSIS_CHANNELS.join(" or ")
            )
        })?;
    let options = AnalysisOptions::default();
    let out = analyze_simulation(result, scene, channel, &options)
        .map_err(|e| format!("analysis of {channel} not possible: {e}"))?;
    Ok((channel, options, out))
}

/// Analyse `channel` of a simulation result: sample rate from the result, geometry from
/// the scene's bearing, shaft speed from the run's mean shaft speed (the steady rpm if
/// absent), and, unless `opts.window` is given, the engine's steady window (the window the
/// summary averages over: it is chosen once, by the run). When the speed varies over the
/// window (it lies in the ramp: a run that never settles), the signal is order tracked by
/// the run's own shaft angle ([`run_shaft_angle`]) and the report says so.
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
    let geometry = KinematicGeometry::from_bearing(&scene.bearing);
    // A window inside the speed ramp is order tracked: the run knows its shaft angle.
    if let Ok(angle) = run_shaft_angle(result, scene) {
        let (i0, i1) = window_samples(o.window, fs, ch.data.len());
        let theory = characteristic_frequencies(&geometry, shaft_hz);
        let highest = (o.verdict_harmonics as f64 + 0.5) * theory.bpfi.max(theory.bpfo);
        let within = &angle.radians()[i0..i1];
        // order tracking needs a revolution; a shorter window (a run of a few
        // milliseconds) is analysed at its mean speed, as it always was
        let turns = within
            .last()
            .zip(within.first())
            .map_or(0.0, |(b, a)| (b - a) / TAU);
        if i1 > i0 + 1 && turns >= 1.0 && angle_speed_varies(within, fs, highest) {
            return analyze_tracked(&ch.data, fs, &geometry, &angle, &o, None, LevelSpectra::All);
        }
    }
    analyze(&ch.data, fs, &geometry, shaft_hz, &o)
}

/// Samples `[i0, i1)` of a window `[t0, t1]` s (the whole record without one), as the
/// analysis rounds it.
fn window_samples(window: Option<[f64; 2]>, fs: f64, n: usize) -> (usize, usize) {
    match window {
        None => (0, n),
        Some([t0, t1]) => {
            let i0 = ((t0 * fs).round().max(0.0) as usize).min(n);
            let i1 = ((t1 * fs).round().max(0.0) as usize).min(n);
            (i0, i1.max(i0))
        }
    }
}

/// Cage and ball-pass frequencies, Hz.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct PassFrequencies {
    /// Fundamental train (cage) frequency, Hz.
    pub ftf: f64,
    /// Ball pass frequency, outer race: `Z ftf`, Hz.
    pub bpfo: f64,
    /// Ball pass frequency, inner race: `Z (f_shaft - ftf)`, Hz.
    pub bpfi: f64,
}

impl PassFrequencies {
    fn of_cage(cage_hz: f64, shaft_hz: f64, z: usize) -> Self {
        PassFrequencies {
            ftf: cage_hz,
            bpfo: z as f64 * cage_hz,
            bpfi: z as f64 * (shaft_hz - cage_hz),
        }
    }
}

/// A run's characteristic frequencies three ways: eq. 37 at the nominal contact angle (what
/// the paper's Figures 23-28 compare against), the pure rolling of the loaded balls, and the
/// cage speed the run produced.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct FrequencyComparison {
    /// Mean shaft frequency over the steady window, Hz.
    pub shaft_hz: f64,
    /// The bearing's nominal contact angle, rad.
    pub nominal_contact_angle: f64,
    /// Inner and outer contact angles of the load zone, load-weighted, rad.
    pub loaded_contact_angles: [f64; 2],
    /// Eq. 37 at the nominal angle, with `d_m = (bore + OD) / 2` as the paper takes it.
    pub nominal: PassFrequencies,
    /// Pure rolling of the loaded balls (outer-race control at the loaded angles, the pitch
    /// diameter of the groove centres): the summary's epicyclic cage speed.
    pub loaded: PassFrequencies,
    /// From the mean cage speed of the run.
    pub simulated: PassFrequencies,
    /// `(simulated - nominal) / nominal * 100` for BPFO, %.
    pub bpfo_error_pct: f64,
    /// `(simulated - nominal) / nominal * 100` for BPFI, %.
    pub bpfi_error_pct: f64,
}

/// Compare the run's cage speed with the nominal and the loaded-ball kinematics.
pub fn frequency_comparison(result: &SimResult, scene: &Scene) -> FrequencyComparison {
    let s = &result.summary;
    let z = scene.bearing.ball_count;
    let shaft_hz = s.mean_shaft_speed / TAU;
    let theory =
        characteristic_frequencies(&KinematicGeometry::from_bearing(&scene.bearing), shaft_hz);
    let nominal = PassFrequencies {
        ftf: theory.ftf,
        bpfo: theory.bpfo,
        bpfi: theory.bpfi,
    };
    let simulated = PassFrequencies::of_cage(s.mean_cage_speed / TAU, shaft_hz, z);
    let pct = |x: f64, x0: f64| 100.0 * (x - x0) / x0;
    FrequencyComparison {
        shaft_hz,
        nominal_contact_angle: scene.bearing.contact_angle,
        loaded_contact_angles: s.loaded_contact_angles,
        nominal,
        loaded: PassFrequencies::of_cage(s.epicyclic_cage_speed / TAU, shaft_hz, z),
        simulated,
        bpfo_error_pct: pct(simulated.bpfo, nominal.bpfo),
        bpfi_error_pct: pct(simulated.bpfi, nominal.bpfi),
    }
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

    /// The H7005C preset run up from 1000 to 10000 rpm over `ramp` s, simulated `duration` s.
    fn run_up_scene(ramp: f64, duration: f64) -> Scene {
        let mut scene = crate::scene::preset_scene("h7005c").unwrap();
        scene.operating.speed = crate::scene::SpeedProfile {
            initial_rpm: 1_000.0,
            steady_rpm: 10_000.0,
            ramp_time: ramp,
        };
        scene.solver.duration = duration;
        scene
    }

    /// A result holding one channel, `outer_ring_accel_y`, sampled at `fs` Hz from t = 0.
    fn accel_y_result(fs: f64, data: Vec<f64>, summary: Summary) -> SimResult {
        SimResult {
            summary,
            channels: Channels {
                sample_rate: fs,
                start_time: 0.0,
                channels: vec![Channel {
                    name: "outer_ring_accel_y".into(),
                    unit: "m/s^2".into(),
                    data,
                }],
            },
        }
    }

    /// [`analyze_simulation`] of that channel with the default options.
    fn analyze_accel_y(result: &SimResult, scene: &Scene) -> AnalysisOutput {
        analyze_simulation(
            result,
            scene,
            "outer_ring_accel_y",
            &AnalysisOptions::default(),
        )
        .unwrap()
    }

    #[test]
    fn frequencies_compare_the_cage_with_both_kinematics() {
        let scene = crate::scene::preset_scene("h7005c").unwrap();
        let w = 10_000.0 * TAU / 60.0;
        let result = SimResult {
            summary: Summary {
                mean_shaft_speed: w,
                // the paper's BPFO 1134.6 Hz at 10000 rpm is 16 x 70.91 Hz of cage
                mean_cage_speed: 1.001 * 1134.6 / 16.0 * TAU,
                epicyclic_cage_speed: 0.999 * 1134.6 / 16.0 * TAU,
                loaded_contact_angles: [0.27, 0.23],
                ..Summary::default()
            },
            channels: Channels::default(),
        };
        let c = frequency_comparison(&result, &scene);
        assert!((c.nominal.bpfo - 1134.6).abs() < 0.05, "{}", c.nominal.bpfo);
        assert!((c.nominal.bpfi - 1532.1).abs() < 0.05, "{}", c.nominal.bpfi);
        // BPFO + BPFI = Z f_shaft whatever the cage does
        for f in [c.nominal, c.loaded, c.simulated] {
            assert!((f.bpfo + f.bpfi - 16.0 * 10_000.0 / 60.0).abs() < 1e-9);
        }
        assert!(
            (c.bpfo_error_pct - 0.1).abs() < 0.01,
            "{}",
            c.bpfo_error_pct
        );
        assert!(c.bpfi_error_pct < 0.0 && c.loaded.bpfo < c.nominal.bpfo);
        assert_eq!(c.loaded_contact_angles, [0.27, 0.23]);
    }

    #[test]
    fn a_runs_shaft_angle_integrates_its_speed_ramp() {
        let scene = run_up_scene(0.2, 0.3);
        let fs = 10_000.0;
        let result = accel_y_result(fs, vec![0.0; 3_001], Summary::default());
        let angle = run_shaft_angle(&result, &scene).unwrap();
        // 1000 -> 10000 rpm over 0.2 s averages 5500 rpm: 18.33 rev; then 0.1 s at 10000
        // rpm: 16.67 rev. The profile is integrated exactly, so only rounding remains.
        assert!((angle.revolutions() - (5_500.0 * 0.2 + 10_000.0 * 0.1) / 60.0).abs() < 1e-9);
        assert_eq!(angle.radians()[0], 0.0);
    }

    /// A run shorter than a revolution inside its ramp (a study's few-millisecond point)
    /// cannot be order tracked; it is analysed at its mean speed, not refused.
    #[test]
    fn a_window_under_one_revolution_in_the_ramp_is_analysed_at_its_mean_speed() {
        // a 30 ms point of a study on the Table-1 scene
        let scene = run_up_scene(0.1, 0.03);
        let fs = 400_000.0;
        let data: Vec<f64> = (0..12_001).map(|i| (i as f64 * 0.37).sin()).collect();
        let result = accel_y_result(
            fs,
            data,
            Summary {
                steady_window: steady_window(0.1, 0.03),
                mean_shaft_speed: 1_300.0 * TAU / 60.0,
                ..Summary::default()
            },
        );
        // the whole run turns more than once (so it has a shaft angle), its window less
        let angle = run_shaft_angle(&result, &scene).unwrap();
        let [w0, w1] = result.summary.steady_window;
        let (i0, i1) = ((w0 * fs) as usize, (w1 * fs) as usize);
        let turns = (angle.radians()[i1.min(12_000)] - angle.radians()[i0]) / TAU;
        assert!(
            angle.revolutions() > 1.0 && turns < 1.0,
            "{turns} revolutions"
        );
        let out = analyze_accel_y(&result, &scene);
        assert!(out.report.order_tracking.is_none());
    }

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
        let result = accel_y_result(
            fs,
            data,
            Summary {
                steady_window: steady_window(0.2, 1.2),
                ..Summary::default()
            },
        );
        let out = analyze_accel_y(&result, &scene);
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
