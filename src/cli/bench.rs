//! `bearing-sim bench`: time the engine on this machine.
//!
//! `bench cases` runs the preset's four fault cases (Table 1 scene) and prints wall time
//! and solver statistics; `bench work-precision` runs one scene at several tolerances
//! and reports run time against error relative to a tight reference.

use super::result::CliResult;
use bearing_core::scene::{fault_case_scene, FaultCase, Integrator, ValidScene, ValidationErrors};
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
    /// Run time against error for the compound-fault H7005C at a constant 10000 rpm.
    WorkPrecision {
        /// Simulated time per run, s.
        #[arg(long, default_value_t = 0.5)]
        duration: f64,
        /// Tolerances (rtol = atol) to test.
        #[arg(long, value_delimiter = ',', default_values_t = vec![1e-4, 1e-5, 1e-6, 1e-7])]
        tolerances: Vec<f64>,
    },
}

pub fn main(args: BenchArgs) -> CliResult {
    match args.what {
        BenchWhat::Cases { duration } => cases(duration),
        BenchWhat::WorkPrecision {
            duration,
            tolerances,
        } => work_precision(duration, &tolerances),
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

fn scene(duration: f64, tol: f64) -> Result<ValidScene, ValidationErrors> {
    let mut s = fault_case_scene("h7005c", FaultCase::Compound).expect("preset");
    s.operating.speed.initial_rpm = 10_000.0;
    s.operating.speed.ramp_time = 0.0;
    s.solver.duration = duration;
    s.solver.rtol = tol;
    s.solver.atol = tol;
    s.validated()
}

/// RMS of the pedestal Z acceleration below 20 kHz over the steady window, m/s^2.
fn band_rms(r: &SimResult) -> f64 {
    steady_band_rms(r, "outer_ring_accel_z", 20e3).expect("always recorded")
}

fn work_precision(duration: f64, tolerances: &[f64]) -> CliResult {
    let tightest = tolerances.iter().cloned().fold(f64::INFINITY, f64::min);
    eprintln!("reference: adaptive at {:.0e}", tightest / 100.0);
    let reference = simulate(&scene(duration, tightest / 100.0)?, RunControl::default())?;
    let mut fixed = scene(duration, 1e-6)?.into_scene();
    fixed.solver.integrator = Integrator::Rk4Fixed;
    fixed.solver.initial_step = 1e-6;
    let fixed = fixed.validated()?;
    eprintln!("second method: fixed-step RK4 at 1 us");
    let check = simulate(&fixed, RunControl::default())?;
    let (c_ref, r_ref) = (reference.summary.mean_cage_speed, band_rms(&reference));
    println!("| method | tolerance / step | wall time (s) | RHS evaluations | cage speed error | band RMS error |");
    println!("| --- | --- | --- | --- | --- | --- |");
    let row = |name: &str, tol: String, r: &SimResult| {
        println!(
            "| {name} | {tol} | {:.2} | {} | {:.2e} | {:.2e} |",
            r.summary.stats.wall_time,
            r.summary.stats.rhs_evaluations,
            (r.summary.mean_cage_speed - c_ref).abs() / c_ref,
            (band_rms(r) - r_ref).abs() / r_ref
        )
    };
    row(
        "reference (adaptive)",
        format!("{:.0e}", tightest / 100.0),
        &reference,
    );
    row("fixed RK4", "1e-6 s".into(), &check);
    for &t in tolerances {
        let r = simulate(&scene(duration, t)?, RunControl::default())?;
        row("adaptive RK4", format!("{t:.0e}"), &r);
    }
    Ok(())
}
