//! `bearing-sim bench fidelity`: each fidelity level against the full model on one scene:
//! run time, the identified fault frequencies, mean cage speed, band RMS and peak contact
//! loads.

use super::result::CliResult;
use bearing_core::scene::{fault_case_scene, FaultCase, Fidelity, Scene};
use bearing_core::signal::analysis::AnalysisOptions;
use bearing_core::simulation::{simulate, RunControl, SimResult};
use bearing_core::simulation_analysis::{analyze_simulation, steady_band_rms};

/// The scene of a comparison: the preset's fault case on the Table-1 ramp or at a
/// constant 10000 rpm, recording ball 0's contact loads.
pub fn comparison_scene(
    kind: &str,
    fault: FaultCase,
    duration: f64,
) -> Result<Scene, Box<dyn std::error::Error>> {
    let mut s = fault_case_scene("h7005c", fault).expect("preset");
    match kind {
        "table1" => {}
        "constant" => {
            s.operating.speed.initial_rpm = 10_000.0;
            s.operating.speed.ramp_time = 0.0;
        }
        other => return Err(format!("--scene: expected table1 or constant, got {other}").into()),
    }
    s.solver.duration = duration;
    s.outputs.contact_loads_ball = Some(0);
    Ok(s)
}

/// What the comparison reads from one run.
struct Reading {
    wall: f64,
    rhs: u64,
    cage: f64,
    band_rms: f64,
    /// Identified BPFO and BPFI (first harmonic, best component), Hz; NaN when absent.
    bpfo: f64,
    bpfi: f64,
    /// Largest inner and outer contact load of ball 0 in the steady window, N.
    peak_loads: [f64; 2],
}

fn read(scene: &Scene, r: &SimResult) -> Result<Reading, Box<dyn std::error::Error>> {
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
        rhs: r.summary.stats.rhs_evaluations,
        cage: r.summary.mean_cage_speed,
        band_rms: steady_band_rms(r, "outer_ring_accel_z", 20e3).expect("always recorded"),
        bpfo: line("BPFO"),
        bpfi: line("BPFI"),
        peak_loads: [peak("ball0_inner_load"), peak("ball0_outer_load")],
    })
}

pub fn fidelity(
    kind: &str,
    fault: FaultCase,
    duration: f64,
    levels: &[String],
    strips: Option<usize>,
    integrator: Option<&str>,
) -> CliResult {
    let base = comparison_scene(kind, fault, duration)?;
    let parse = |name: &str| -> Result<Fidelity, Box<dyn std::error::Error>> {
        serde_json::from_value(serde_json::Value::String(name.into()))
            .map_err(|_| format!("--levels: unknown fidelity level {name}").into())
    };
    let levels = levels
        .iter()
        .map(|l| parse(l).map(|f| (l.as_str(), f)))
        .collect::<Result<Vec<_>, _>>()?;
    eprintln!("reference: full fidelity");
    let full = simulate(&base.clone().validated()?, RunControl::default())?;
    let f = read(&base, &full)?;
    println!("| level | integrator | strips | wall time (s) | speed-up | RHS evaluations | BPFO (Hz) | BPFI (Hz) | cage speed (rad/s) | band RMS < 20 kHz (m/s^2) | peak inner / outer load, ball 0 (N) |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    let rel = |a: f64, b: f64| 100.0 * (a - b) / b;
    println!(
        "| full | {} | {} | {:.2} | 1 | {} | {:.2} | {:.2} | {:.3} | {:.3} | {:.1} / {:.1} |",
        serde_json::to_value(base.solver.integrator)?
            .as_str()
            .unwrap_or("?"),
        base.solver.traction_strips,
        f.wall,
        f.rhs,
        f.bpfo,
        f.bpfi,
        f.cage,
        f.band_rms,
        f.peak_loads[0],
        f.peak_loads[1]
    );
    for (name, level) in levels {
        let mut s = base.clone();
        s.solver.fidelity = level;
        if let Some(n) = strips {
            s.solver.traction_strips = n;
        }
        if let Some(name) = integrator {
            s.solver.integrator = serde_json::from_value(serde_json::Value::String(name.into()))
                .map_err(|_| format!("--integrator: unknown integrator {name}"))?;
        }
        eprintln!("{name}");
        let r = simulate(&s.clone().validated()?, RunControl::default())?;
        let g = read(&s, &r)?;
        println!(
            "| {name} | {} | {} | {:.2} | {:.1} | {} | {:.2} ({:+.3} %) | {:.2} ({:+.3} %) | {:.3} ({:+.3} %) | {:.3} ({:+.1} %) | {:.1} ({:+.1} %) / {:.1} ({:+.1} %) |",
            serde_json::to_value(s.solver.integrator)?.as_str().unwrap_or("?"),
            s.solver.traction_strips,
            g.wall,
            f.wall / g.wall,
            g.rhs,
            g.bpfo,
            rel(g.bpfo, f.bpfo),
            g.bpfi,
            rel(g.bpfi, f.bpfi),
            g.cage,
            rel(g.cage, f.cage),
            g.band_rms,
            rel(g.band_rms, f.band_rms),
            g.peak_loads[0],
            rel(g.peak_loads[0], f.peak_loads[0]),
            g.peak_loads[1],
            rel(g.peak_loads[1], f.peak_loads[1]),
        );
    }
    Ok(())
}
