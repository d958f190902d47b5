//! `bearing-sim bench`: time the engine on this machine.
//!
//! `bench cases` runs the preset's four fault cases (Table 1 scene) and prints wall time
//! and solver statistics; `bench work-precision` runs one scene at several tolerances
//! and reports run time against error relative to a tight reference; `bench stress` runs
//! the stability stress suite (`bench_stress.rs`); `bench stiffness` the Jacobian's spectrum
//! at states of a run (`bench_stiffness.rs`).

use super::bench_comparison::{
    comparison_scene, parse_fidelity, parse_name, read, ComparisonArgs, Reading,
};
use super::result::CliResult;
use crate::plots::{work_precision_svg, WorkPrecisionSeries};
use bearing_core::scene::{fault_case_scene, FaultCase, Fidelity, Integrator, Scene};
use bearing_core::simulation::{simulate, RunControl};
use std::path::{Path, PathBuf};

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
        /// Rounds over the four cases (1-15). Each case's wall time is then the median of
        /// its rounds, with their range; each round starts one case further on, so the
        /// machine's drift over a long bench does not fall on one case
        /// (docs/lab/benchmarks.md). Every round must repeat its case's steps exactly.
        #[arg(long, default_value_t = 1)]
        runs: usize,
    },
    /// Run time against error of every integrator on the compound-fault H7005C, against a
    /// tight reference checked by a second method.
    WorkPrecision {
        #[command(flatten)]
        on: ComparisonArgs,
        /// Tolerances (rtol = atol) to test.
        #[arg(long, value_delimiter = ',', default_values_t = vec![1e-4, 1e-5, 1e-6])]
        tolerances: Vec<f64>,
        /// Integrators to test (snake_case names of `solver.integrator`).
        #[arg(long, value_delimiter = ',', default_values_t = vec!["rk4_adaptive".to_string(), "rk4_fsal".to_string(), "rosenbrock_w".to_string()])]
        methods: Vec<String>,
        /// Fidelity levels to run each method at (snake_case names of `solver.fidelity`).
        #[arg(long, value_delimiter = ',', default_values_t = vec!["full".to_string(), "quasi_static_balls".to_string(), "concentric_cage".to_string()])]
        levels: Vec<String>,
        /// Tolerance of the reference (adaptive RK4), checked by fixed RK4 at 1 us.
        #[arg(long, default_value_t = 1e-8)]
        reference: f64,
        /// Also write the work-precision chart (log error against log run time) here.
        #[arg(long)]
        svg: Option<PathBuf>,
        /// Runs per setting (1-9), the k-th from `solver.initial_step` times 1 - 0.1 k and
        /// the tolerances times 1 + 0.02 k, which changes the whole step sequence. Above 1 the errors are those of the ensemble
        /// means, with their standard errors: for physics whose single runs scatter by more
        /// than the tolerance moves them (the rheology law, docs/lab/benchmarks.md).
        #[arg(long, default_value_t = 1)]
        runs: usize,
    },
    /// Each fidelity level against the full model on one scene: run time, identified
    /// BPFO/BPFI, mean cage speed, band RMS below 20 kHz and peak contact loads.
    Fidelity {
        #[command(flatten)]
        on: ComparisonArgs,
        /// Levels to compare with `full` (snake_case names of `solver.fidelity`).
        #[arg(long, value_delimiter = ',', default_values_t = vec!["quasi_static_balls".to_string(), "concentric_cage".to_string()])]
        levels: Vec<String>,
        /// Traction strips for the reduced levels; several (comma-separated) run each
        /// level once per count (default: the scene's).
        #[arg(long, value_delimiter = ',')]
        strips: Vec<usize>,
        /// Integrator for the reduced levels (default: the scene's).
        #[arg(long)]
        integrator: Option<String>,
        /// Tolerances (rtol = atol) for the reduced levels; several (comma-separated) show
        /// how far a reduced level's readings move when only the step sequence changes
        /// (default: the scene's).
        #[arg(long, value_delimiter = ',')]
        tolerances: Vec<f64>,
        /// Traction quadratures for the reduced levels (`gauss`, `equal_strips`); several
        /// (comma-separated) run each level once per rule (default: the scene's). With
        /// `--levels full` this is a convergence study of the full model.
        #[arg(long, value_delimiter = ',')]
        quadratures: Vec<String>,
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
    /// Where the stiffness is: the largest eigenvalues of the Jacobian at states of a run,
    /// whole and with each ball's velocity block, each ball's block or every body's block
    /// taken out (as an integrator exact on them would), and RK4's stable step on each.
    // the scene's --duration is not read (--at is): hidden from the help
    #[command(mut_arg("duration", |a| a.hide(true)))]
    Stiffness {
        #[command(flatten)]
        on: ComparisonArgs,
        /// Times of the run to look at, 0 to 10 s (0: its initial state); each is reached by
        /// running the scene to it.
        #[arg(long, value_delimiter = ',', default_values_t = vec![0.05, 0.3])]
        at: Vec<f64>,
        /// Eigenvalues to print per part, largest magnitude first.
        #[arg(long, default_value_t = 4)]
        count: usize,
    },
}

pub fn main(args: BenchArgs) -> CliResult {
    match args.what {
        BenchWhat::Cases { duration, runs } => cases(duration, runs),
        BenchWhat::WorkPrecision {
            on,
            tolerances,
            methods,
            levels,
            reference,
            svg,
            runs,
        } => work_precision(
            &on,
            &tolerances,
            &methods,
            &levels,
            reference,
            svg.as_deref(),
            runs,
        ),
        BenchWhat::Fidelity {
            on,
            levels,
            strips,
            integrator,
            tolerances,
            quadratures,
        } => super::bench_fidelity::fidelity(
            &on,
            &levels,
            &strips,
            integrator.as_deref(),
            &tolerances,
            &quadratures,
        ),
        BenchWhat::Stress {
            duration,
            only,
            short,
        } => super::bench_stress::stress(duration, &only, short),
        BenchWhat::Stiffness { on, at, count } => {
            super::bench_stiffness::stiffness(&on, &at, count)
        }
    }
}

fn cases(duration: f64, runs: usize) -> CliResult {
    if !(1..=15).contains(&runs) {
        return Err(format!("--runs: must be 1 to 15 (got {runs})").into());
    }
    let cases = [
        FaultCase::None,
        FaultCase::Inner,
        FaultCase::Outer,
        FaultCase::Compound,
    ];
    let mut scenes = Vec::new();
    for case in cases {
        let mut s = fault_case_scene("h7005c", case).expect("preset");
        s.solver.duration = duration;
        scenes.push(s.validated()?);
    }
    // each case's first round's result, and every round's wall time
    let mut firsts: Vec<Option<_>> = (0..cases.len()).map(|_| None).collect();
    let mut walls = vec![Vec::new(); cases.len()];
    for round in 0..runs {
        if runs > 1 {
            eprintln!("round {} of {runs}", round + 1);
        }
        // each round starts one case further on, so no case is always the last
        for k in (0..cases.len()).map(|i| (i + round) % cases.len()) {
            let case = cases[k];
            let r = simulate(&scenes[k], RunControl::default())?;
            let st = &r.summary.stats;
            let finite = r
                .channels
                .channels
                .iter()
                .all(|c| c.data.iter().all(|v| v.is_finite()));
            if !finite {
                return Err(format!("{case:?}: non-finite samples").into());
            }
            walls[k].push(st.wall_time);
            let Some(first) = &firsts[k] else {
                firsts[k] = Some(r.summary);
                continue;
            };
            if (st.accepted_steps, st.rhs_evaluations)
                != (first.stats.accepted_steps, first.stats.rhs_evaluations)
            {
                return Err(format!(
                    "{case:?}: round {} took {} steps and {} evaluations, round 1 {} and {}: \
                     the run is not deterministic",
                    round + 1,
                    st.accepted_steps,
                    st.rhs_evaluations,
                    first.stats.accepted_steps,
                    first.stats.rhs_evaluations
                )
                .into());
            }
        }
    }
    println!("| case | wall time (s) | accepted | rejected | RHS evaluations | smallest step (s) | largest step (s) | mean cage speed (rad/s) | slip (%) |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for ((case, summary), w) in cases.iter().zip(&firsts).zip(&walls) {
        let summary = summary.as_ref().expect("every case ran");
        let st = &summary.stats;
        let wall = if runs == 1 {
            format!("{:.2}", w[0])
        } else {
            let (median, low, high) = median_and_range(w);
            format!("{median:.3} ({low:.3}-{high:.3})")
        };
        println!(
            "| {case:?} | {wall} | {} | {} | {} | {:.2e} | {:.2e} | {:.3} | {:.3} |",
            st.accepted_steps,
            st.rejected_steps,
            st.rhs_evaluations,
            st.min_step,
            st.max_step,
            summary.mean_cage_speed,
            100.0 * summary.cage_slip
        );
    }
    Ok(())
}

/// The median of `w` (of an even count, the mean of the middle two), its least and its
/// greatest.
fn median_and_range(w: &[f64]) -> (f64, f64, f64) {
    let mut w = w.to_vec();
    w.sort_by(f64::total_cmp);
    let n = w.len();
    (0.5 * (w[(n - 1) / 2] + w[n / 2]), w[0], w[n - 1])
}

fn scene(
    on: &ComparisonArgs,
    tol: f64,
    integrator: Integrator,
    fidelity: Fidelity,
) -> Result<Scene, Box<dyn std::error::Error>> {
    let mut s = comparison_scene(on)?;
    s.solver.integrator = integrator;
    s.solver.fidelity = fidelity;
    s.solver.rtol = tol;
    s.solver.atol = tol;
    Ok(s)
}

fn parse_integrator(name: &str) -> Result<Integrator, Box<dyn std::error::Error>> {
    parse_name("--methods", "integrator", name)
}

/// One setting's runs ([`BenchWhat::WorkPrecision`]'s `--runs`): their readings.
struct Ensemble {
    readings: Vec<Reading>,
}

impl Ensemble {
    fn mean(&self, f: impl Fn(&Reading) -> f64) -> f64 {
        self.readings.iter().map(&f).sum::<f64>() / self.readings.len() as f64
    }

    /// Standard error of the mean of `f`, in the unit of `f`; NaN for one run.
    fn standard_error(&self, f: impl Fn(&Reading) -> f64) -> f64 {
        let n = self.readings.len() as f64;
        let m = self.mean(&f);
        let var = self
            .readings
            .iter()
            .map(|g| (f(g) - m).powi(2))
            .sum::<f64>()
            / (n - 1.0);
        (var / n).sqrt()
    }
}

#[allow(clippy::too_many_arguments)]
fn work_precision(
    on: &ComparisonArgs,
    tolerances: &[f64],
    methods: &[String],
    levels: &[String],
    tight: f64,
    svg: Option<&Path>,
    runs: usize,
) -> CliResult {
    if !(1..=9).contains(&runs) {
        return Err(format!("--runs: must be 1 to 9 (got {runs})").into());
    }
    let methods = methods
        .iter()
        .map(|m| parse_integrator(m).map(|i| (m.as_str(), i)))
        .collect::<Result<Vec<_>, _>>()?;
    let levels = levels
        .iter()
        .map(|l| parse_fidelity(l).map(|f| (l.as_str(), f)))
        .collect::<Result<Vec<_>, _>>()?;
    let run = |s: &Scene| -> Result<Ensemble, Box<dyn std::error::Error>> {
        let mut e = Ensemble {
            readings: Vec::new(),
        };
        for k in 0..runs {
            let mut s = s.clone();
            s.solver.initial_step *= 1.0 - 0.1 * k as f64;
            // a method whose steps forget the first one (`etd_rk4`'s are soon held by its
            // alias bound) would run the same sequence every time: the tolerances move too
            let tol = 1.0 + 0.02 * k as f64;
            s.solver.rtol *= tol;
            s.solver.atol *= tol;
            let r = simulate(&s.clone().validated()?, RunControl::default())?;
            e.readings.push(read(&s, &r)?);
        }
        Ok(e)
    };
    let full = Fidelity::Full;
    eprintln!("reference: adaptive RK4 at {tight:.0e}");
    let reference = scene(on, tight, Integrator::Rk4Adaptive, full)?;
    let f = run(&reference)?;
    let mut fixed = scene(on, tight, Integrator::Rk4Fixed, full)?;
    fixed.solver.initial_step = 1e-6;
    eprintln!("second method: fixed-step RK4 at 1 us");
    let c = run(&fixed)?;
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    let readings: [fn(&Reading) -> f64; 4] = [|g| g.cage, |g| g.band_rms, |g| g.bpfo, |g| g.bpfi];
    let errors = |g: &Ensemble| {
        readings
            .iter()
            .map(|r| rel(g.mean(r), f.mean(r)))
            .collect::<Vec<_>>()
    };
    let spread = runs > 1;
    let (mean_of, extra_head, extra_rule) = if spread {
        (
            "mean ",
            " cage speed s.e. | band RMS s.e. |",
            " --- | --- |",
        )
    } else {
        ("", "", "")
    };
    println!("| method | fidelity | tolerance / step | {mean_of}wall time (s) | {mean_of}accepted steps | {mean_of}RHS evaluations | cage speed error | band RMS error | BPFO error | BPFI error |{extra_head}");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |{extra_rule}");
    let row = |name: &str, level: &str, tol: String, g: &Ensemble| {
        let e = errors(g);
        let extra = if spread {
            format!(
                " {:.1e} | {:.1e} |",
                g.standard_error(|g| g.cage) / f.mean(|g| g.cage),
                g.standard_error(|g| g.band_rms) / f.mean(|g| g.band_rms)
            )
        } else {
            String::new()
        };
        println!(
            "| {name} | {level} | {tol} | {:.2} | {:.0} | {:.0} | {:.2e} | {:.2e} | {:.2e} | {:.2e} |{extra}",
            g.mean(|g| g.wall),
            g.mean(|g| g.accepted as f64),
            g.mean(|g| g.rhs as f64),
            e[0],
            e[1],
            e[2],
            e[3]
        )
    };
    let tight_name = format!("{tight:.0e}");
    row("reference: rk4_adaptive", "full", tight_name, &f);
    row("check: rk4_fixed", "full", "1e-6 s".into(), &c);
    let mut series = Vec::new();
    for &(level_name, level) in &levels {
        for &(name, integrator) in &methods {
            let label = if level.is_full() {
                name.to_string()
            } else {
                format!("{name}, {level_name}")
            };
            let mut points = Vec::new();
            for &t in tolerances {
                eprintln!("{label} at {t:.0e}");
                let g = run(&scene(on, t, integrator, level)?)?;
                row(name, level_name, format!("{t:.0e}"), &g);
                points.push((g.mean(|g| g.wall), errors(&g)));
            }
            series.push(WorkPrecisionSeries { label, points });
        }
    }
    if let Some(path) = svg {
        let title = format!(
            "H7005C {:?} fault, {} scene, {} s: relative error against rk4_adaptive at {tight:.0e}",
            on.fault, on.scene, on.duration
        );
        let panels = ["cage speed", "band RMS", "BPFO", "BPFI"];
        let chart = work_precision_svg(&title, &panels, &series)?;
        std::fs::write(path, chart).map_err(|e| format!("--svg {}: {e}", path.display()))?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::median_and_range;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median_and_range(&[3.0, 1.0, 2.0]), (2.0, 1.0, 3.0));
        assert_eq!(median_and_range(&[4.0, 1.0, 3.0, 2.0]), (2.5, 1.0, 4.0));
        assert_eq!(median_and_range(&[1.5]), (1.5, 1.5, 1.5));
    }
}
