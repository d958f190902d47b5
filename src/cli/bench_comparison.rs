//! What the engine benchmarks compare on: the scene (`--scene`, `--fault`, `--duration`,
//! `--rpm`, `--lubricant`) and what they read from a run (identified BPFO/BPFI, cage speed, band RMS, peak loads).

use bearing_core::scene::{fault_case_scene, FaultCase, Fidelity, Scene};
use bearing_core::signal::analysis::AnalysisOptions;
use bearing_core::simulation::SimResult;
use bearing_core::simulation_analysis::{analyze_simulation, steady_band_rms};
use bearing_core::study::lubricant_variant;

/// The scene a comparison runs on.
#[derive(clap::Args, Debug)]
pub struct ComparisonArgs {
    /// `table1` (1000 -> 10000 rpm in 0.1 s, as in the paper) or `constant` (`--rpm`).
    #[arg(long, default_value = "table1")]
    pub scene: String,
    /// Fault case of the preset: none, inner, outer or compound.
    #[arg(long, default_value = "compound")]
    pub fault: FaultCase,
    /// Simulated time per run, s.
    #[arg(long, default_value_t = 0.5)]
    pub duration: f64,
    /// Shaft speed of the `constant` scene, rev/min.
    #[arg(long, default_value_t = 10_000.0)]
    pub rpm: f64,
    /// Lubricant variant (`bearing-sim study` names: `paper`, `rheology`, ...); default the
    /// preset's.
    #[arg(long)]
    pub lubricant: Option<String>,
}

/// The scene of a comparison: the preset's fault case on the Table-1 ramp or at a
/// constant speed (`--rpm`), with the lubricant variant asked for, recording ball 0's
/// contact loads.
pub fn comparison_scene(on: &ComparisonArgs) -> Result<Scene, Box<dyn std::error::Error>> {
    let mut s = fault_case_scene("h7005c", on.fault).expect("preset");
    match on.scene.as_str() {
        "table1" => {}
        "constant" => {
            if !(on.rpm.is_finite() && on.rpm > 0.0) {
                return Err(format!("--rpm: must be > 0 (got {})", on.rpm).into());
            }
            s.operating.speed.initial_rpm = on.rpm;
            s.operating.speed.steady_rpm = on.rpm;
            s.operating.speed.ramp_time = 0.0;
        }
        other => return Err(format!("--scene: expected table1 or constant, got {other}").into()),
    }
    if let Some(name) = &on.lubricant {
        lubricant_variant(name)
            .map_err(|e| format!("--lubricant: {e}"))?
            .apply_to(&mut s.lubricant);
    }
    s.solver.duration = on.duration;
    s.outputs.contact_loads_ball = Some(0);
    Ok(s)
}

/// A `--levels` name as a fidelity level.
pub fn parse_fidelity(name: &str) -> Result<Fidelity, Box<dyn std::error::Error>> {
    parse_name("--levels", "fidelity level", name)
}

/// A scene enum from its snake_case name on the command line (`flag` and `what` name it in
/// the error).
pub fn parse_name<T: serde::de::DeserializeOwned>(
    flag: &str,
    what: &str,
    name: &str,
) -> Result<T, Box<dyn std::error::Error>> {
    serde_json::from_value(serde_json::Value::String(name.into()))
        // serde's message lists the names it accepts
        .map_err(|e| format!("{flag}: unknown {what} {name} ({e})").into())
}

/// The snake_case name of a scene enum, as the tables print it.
pub fn name_of<T: serde::Serialize>(value: T) -> String {
    serde_json::to_value(value)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_else(|| "?".into())
}

/// What a comparison reads from one run.
pub struct Reading {
    pub wall: f64,
    pub accepted: u64,
    pub rhs: u64,
    pub cage: f64,
    pub band_rms: f64,
    /// Identified BPFO and BPFI (first harmonic, best component), Hz; NaN when absent.
    pub bpfo: f64,
    pub bpfi: f64,
    /// Largest inner and outer contact load of ball 0 in the steady window, N.
    pub peak_loads: [f64; 2],
}

pub fn read(scene: &Scene, r: &SimResult) -> Result<Reading, Box<dyn std::error::Error>> {
    let out = analyze_simulation(r, scene, "outer_ring_accel_z", &AnalysisOptions::default())?;
    let line = |name: &str| {
        out.report
            .best_component
            .identifications
            .iter()
            .find(|i| i.name == name && i.harmonic == 1)
            .map_or(f64::NAN, |i| i.identified_hz)
    };
    let fs = r.channels.sample_rate;
    let [w0, w1] = r.summary.steady_window;
    let peak = |name: &str| {
        r.channels.get(name).map_or(f64::NAN, |c| {
            let i0 = ((w0 - r.channels.start_time) * fs).max(0.0) as usize;
            let i1 = (((w1 - r.channels.start_time) * fs) as usize).min(c.data.len());
            c.data[i0.min(i1)..i1]
                .iter()
                .fold(0.0_f64, |a, &v| a.max(v))
        })
    };
    Ok(Reading {
        wall: r.summary.stats.wall_time,
        accepted: r.summary.stats.accepted_steps,
        rhs: r.summary.stats.rhs_evaluations,
        cage: r.summary.mean_cage_speed,
        band_rms: steady_band_rms(r, "outer_ring_accel_z", 20e3).expect("always recorded"),
        bpfo: line("BPFO"),
        bpfi: line("BPFI"),
        peak_loads: [peak("ball0_inner_load"), peak("ball0_outer_load")],
    })
}
