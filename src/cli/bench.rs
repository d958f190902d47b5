//! `bearing-sim bench`: time the engine on this machine.
//!
//! `bench cases` runs the preset's four fault cases (Table 1 scene) and prints wall time
//! and solver statistics; `bench work-precision` runs one scene at several tolerances
//! and reports run time against error relative to a tight reference; `bench stress` runs
//! the stability stress suite (`bench_stress.rs`).

use super::result::CliResult;
use bearing_core::scene::{fault_case_scene, FaultCase, Integrator, ValidScene};
use bearing_core::simulation::{simulate, RunControl, SimResult};
use bearing_core::simulation_analysis::steady_band_rms;

#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub what: BenchWhat,
}

#[derive(clap::Subcommand, Debug)]
pub enum BenchWhat {
    /// The four H7005C fault cases of Table 1 (1000 -> 10000 rpm in 0.1 s).
    Cases {
        /// Simulated time per case, s.
        #[arg(long, default_value_t = 0.5)]
        duration: f64,
    },
    /// Run time against error of every integrator on the compound-fault H7005C, against a
    /// tight reference checked by a second method.
    WorkPrecision {
        /// `table1` (1000 -> 10000 rpm in 0.1 s, as in the paper) or `constant` (10000 rpm).
        #[arg(long, default_value = "table1")]
        scene: String,
        /// Fault case of the preset: none, inner, outer or compound.
        #[arg(long, default_value = "compound")]
        fault: FaultCase,
        /// Simulated time per run, s.
        #[arg(long, default_value_t = 0.5)]
        duration: f64,
        /// Tolerances (rtol = atol) to test.
        #[arg(long, value_delimiter = ',', default_values_t = vec![1e-4, 1e-5, 1e-6])]
        tolerances: Vec<f64>,
        /// Integrators to test (snake_case names of `solver.integrator`).
        #[arg(long, value_delimiter = ',', default_values_t = vec!["rk4_adaptive".to_string(), "rk4_fsal".to_string(), "rosenbrock_w".to_string()])]
        methods: Vec<String>,
        /// Tolerance of the reference (adaptive RK4), checked by fixed RK4 at 1 us.
        #[arg(long, default_value_t = 1e-8)]
        reference: f64,
    },
    /// Each fidelity level against the full model on one scene: run time, identified
    /// BPFO/BPFI, mean cage speed, band RMS below 20 kHz and peak contact loads.
    Fidelity {
        /// `table1` (1000 -> 10000 rpm in 0.1 s, as in the paper) or `constant` (10000 rpm).
        #[arg(long, default_value = "table1")]
        scene: String,
        /// Fault case of the preset: none, inner, outer or compound.
        #[arg(long, default_value = "compound")]
        fault: FaultCase,
        /// Simulated time per run, s.
        #[arg(long, default_value_t = 0.5)]
        duration: f64,
        /// Levels to compare with `full` (snake_case names of `solver.fidelity`).
        #[arg(long, value_delimiter = ',', default_values_t = vec!["quasi_static_balls".to_string(), "concentric_cage".to_string()])]
        levels: Vec<String>,
        /// Traction strips for the reduced levels (default: the scene's).
        #[arg(long)]
        strips: Option<usize>,
        /// Integrator for the reduced levels (default: the scene's).
        #[arg(long)]
        integrator: Option<String>,
    },
    /// The stability stress suite: extreme scenes run with their invariants checked, or
    /// refused up front naming the field (bearing_core::stress).
    Stress {
        /// Simulated time per scene, s (the long run keeps its own 5 s unless --short).
        #[arg(long, default_value_t = 0.1)]
        duration: f64,
        /// Only these scenes (comma-separated names; default all).
        #[arg(long, value_delimiter = ',')]
        only: Vec<String>,
        /// Run the long run for --duration too.
        #[arg(long)]
        short: bool,
    },
}

pub fn main(args: BenchArgs) -> CliResult {
    match args.what {
        BenchWhat::Cases { duration } => cases(duration),
        BenchWhat::WorkPrecision {
            scene,
            fault,
            duration,
            tolerances,
            methods,
            reference,
        } => work_precision(&scene, fault, duration, &tolerances, &methods, reference),
        BenchWhat::Fidelity {
            scene,
            fault,
            duration,
            levels,
            strips,
            integrator,
        } => super::bench_fidelity::fidelity(
            &scene,
            fault,
            duration,
            &levels,
            strips,
            integrator.as_deref(),
        ),
        BenchWhat::Stress {
            duration,
            only,
            short,
        } => super::bench_stress::stress(duration, &only, short),
    }
}

fn cases(duration: f64) -> CliResult {
    println!("| case | wall time (s) | accepted | rejected | RHS evaluations | smallest step (s) | largest step (s) | mean cage speed (rad/s) | slip (%) |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for case in [
        FaultCase::None,
        FaultCase::Inner,
        FaultCase::Outer,
        FaultCase::Compound,
    ] {
        let mut s = fault_case_scene("h7005c", case).expect("preset");
        s.solver.duration = duration;
        let r = simulate(&s.validated()?, RunControl::default())?;
        let st = &r.summary.stats;
        let finite = r
            .channels
            .channels
            .iter()
            .all(|c| c.data.iter().all(|v| v.is_finite()));
        if !finite {
            return Err(format!("{case:?}: non-finite samples").into());
        }
        println!(
            "| {case:?} | {:.2} | {} | {} | {} | {:.2e} | {:.2e} | {:.3} | {:.3} |",
            st.wall_time,
            st.accepted_steps,
            st.rejected_steps,
            st.rhs_evaluations,
            st.min_step,
            st.max_step,
            r.summary.mean_cage_speed,
            100.0 * r.summary.cage_slip
        );
    }
    Ok(())
}

fn scene(
    kind: &str,
    fault: FaultCase,
    duration: f64,
    tol: f64,
    integrator: Integrator,
) -> Result<ValidScene, Box<dyn std::error::Error>> {
    let mut s = fault_case_scene("h7005c", fault).expect("preset");
    match kind {
        "table1" => {}
        "constant" => {
            s.operating.speed.initial_rpm = 10_000.0;
            s.operating.speed.ramp_time = 0.0;
        }
        other => return Err(format!("--scene: expected table1 or constant, got {other}").into()),
    }
    s.solver.integrator = integrator;
    s.solver.duration = duration;
    s.solver.rtol = tol;
    s.solver.atol = tol;
    Ok(s.validated()?)
}

fn parse_integrator(name: &str) -> Result<Integrator, Box<dyn std::error::Error>> {
    serde_json::from_value(serde_json::Value::String(name.into()))
        .map_err(|_| format!("--methods: unknown integrator {name}").into())
}

/// RMS of the pedestal Z acceleration below 20 kHz over the steady window, m/s^2.
fn band_rms(r: &SimResult) -> f64 {
    steady_band_rms(r, "outer_ring_accel_z", 20e3).expect("always recorded")
}

fn work_precision(
    kind: &str,
    fault: FaultCase,
    duration: f64,
    tolerances: &[f64],
    methods: &[String],
    tight: f64,
) -> CliResult {
    let methods = methods
        .iter()
        .map(|m| parse_integrator(m).map(|i| (m.as_str(), i)))
        .collect::<Result<Vec<_>, _>>()?;
    eprintln!("reference: adaptive RK4 at {tight:.0e}");
    let reference = simulate(
        &scene(kind, fault, duration, tight, Integrator::Rk4Adaptive)?,
        RunControl::default(),
    )?;
    let mut fixed = scene(kind, fault, duration, tight, Integrator::Rk4Fixed)?.into_scene();
    fixed.solver.initial_step = 1e-6;
    eprintln!("second method: fixed-step RK4 at 1 us");
    let check = simulate(&fixed.validated()?, RunControl::default())?;
    let (c_ref, r_ref) = (reference.summary.mean_cage_speed, band_rms(&reference));
    println!("| method | tolerance / step | wall time (s) | accepted steps | RHS evaluations | cage speed error | band RMS error |");
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    let row = |name: &str, tol: String, r: &SimResult| {
        println!(
            "| {name} | {tol} | {:.2} | {} | {} | {:.2e} | {:.2e} |",
            r.summary.stats.wall_time,
            r.summary.stats.accepted_steps,
            r.summary.stats.rhs_evaluations,
            (r.summary.mean_cage_speed - c_ref).abs() / c_ref,
            (band_rms(r) - r_ref).abs() / r_ref
        )
    };
    row(
        "reference: rk4_adaptive",
        format!("{tight:.0e}"),
        &reference,
    );
    row("check: rk4_fixed", "1e-6 s".into(), &check);
    for &(name, integrator) in &methods {
        for &t in tolerances {
            let r = simulate(
                &scene(kind, fault, duration, t, integrator)?,
                RunControl::default(),
            )?;
            row(name, format!("{t:.0e}"), &r);
        }
    }
    Ok(())
}
