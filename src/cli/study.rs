//! `bearing-sim study DESIGN --out DIR`: run a parameter study in-process and write its
//! table (CSV and JSON, as `GET /v1/studies/{id}/table` gives them) and plots (SVG, as
//! `/v1/studies/{id}/plots/{name}`).
//!
//! Every design is a study request (`bearing_core::study`): `paper-trends` (Figures 23-28),
//! `sensitivity` (each trend's end points under lubricant variants) and `table2` (the
//! paper's nine compound-fault sizes) are its named designs on the H7005C preset or
//! `--base`; `request` is any `POST /v1/studies` body. One plan, one runner: identical
//! scenes run once, `--workers` at a time.

use super::result::CliResult;
use crate::studies::charts::{draw, plot_names, row_keys, PointSpectrum};
use crate::studies::scene_key;
use bearing_core::json_doc::merge_patch;
use bearing_core::scene::ValidScene;
use bearing_core::simulation::{simulate, RunControl};
use bearing_core::simulation_analysis::{diagnose_run, first_non_finite};
use bearing_core::study::{
    plan, to_csv, DesignSpec, LineReading, NamedDesign, Plan, PointState, RunDigest, StudyBase,
    StudyRequest, StudyTable, StudyTableRow,
};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::json;
use std::collections::HashMap;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Simulated time per point of the trend designs on the preset, s: 0.3 s at constant
/// speed leaves a 0.225 s window (4.4 Hz bins) after the settling quarter.
const TREND_DURATION: f64 = 0.3;

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum Design {
    /// Figures 23-28: speed, axial and radial load lines for single inner and outer faults.
    PaperTrends,
    /// Each trend's end points (outer fault) under every lubricant variant given.
    Sensitivity,
    /// Table 2: the nine compound-fault sizes.
    Table2,
    /// The study request in `--request FILE` (a `POST /v1/studies` body).
    Request,
}

#[derive(clap::Args, Debug)]
pub struct StudyArgs {
    pub design: Design,
    /// Simulated time per point, s. Default: 0.3 for `paper-trends` and `sensitivity`
    /// without `--base`, else the base scene's (constant speed: the first quarter, at most
    /// 0.1 s, settles and is left out of the averages and spectra).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Lubricant variant for `paper-trends` and `table2` (docs/lab/paper-trends.md): paper,
    /// rheology, rheology+rolling (the preset's), rheology+drag+rolling, rheology-L0.035, ...,
    /// drag, rolling, drag+rolling, drag5+rolling (on the paper's curve), film,
    /// film+drag+rolling, film-G0.3, ... Default: the base scene's lubricant.
    #[arg(long)]
    pub lubricant: Option<String>,
    /// Lubricant variants for `sensitivity` (default: all).
    #[arg(long, value_delimiter = ',')]
    pub variants: Vec<String>,
    /// Wall-time budget per point, s: a point still running then is stopped and listed as
    /// failed (a whirling cage can cost minutes per simulated 0.1 s). 0 = no budget.
    #[arg(long, default_value_t = 300.0)]
    pub point_budget: f64,
    /// Points run at once (one thread each).
    #[arg(long, default_value_t = 2)]
    pub workers: usize,
    /// Base scene of a named design, as a JSON file: `{"preset": "h7005c", "fault_case":
    /// ..., "overrides": {...}}` or `{"scene": {...}}` (default: the H7005C preset).
    #[arg(long)]
    pub base: Option<std::path::PathBuf>,
    /// Study request file for the `request` design.
    #[arg(long)]
    pub request: Option<std::path::PathBuf>,
    /// Output directory (created).
    #[arg(long)]
    pub out: std::path::PathBuf,
}

pub fn main(args: StudyArgs) -> CliResult {
    if !(args.point_budget >= 0.0 && args.point_budget.is_finite()) {
        return Err(format!(
            "--point-budget {}: must be a finite number of seconds >= 0",
            args.point_budget
        )
        .into());
    }
    let budget = (args.point_budget > 0.0).then(|| Duration::from_secs_f64(args.point_budget));
    let req = request_of(&args)?;
    let plan = plan(&req).map_err(|ps| {
        let lines: Vec<String> = ps
            .iter()
            .map(|p| format!("  {}: {}", p.path, p.message))
            .collect();
        format!("the study is invalid:\n{}", lines.join("\n"))
    })?;
    std::fs::create_dir_all(&args.out).map_err(|e| format!("--out {}: {e}", args.out.display()))?;
    let started = Instant::now();
    let ran = run_plan(&plan, args.workers.max(1), budget);
    let elapsed = started.elapsed().as_secs_f64();
    let table = table_of(&plan, &ran);
    write_outputs(&args.out, &plan, &table, &ran)?;
    print_summary(&table, elapsed, ran.distinct());
    Ok(())
}

/// The study request the arguments describe.
fn request_of(args: &StudyArgs) -> Result<StudyRequest, String> {
    let named = match args.design {
        Design::Request => {
            if args.base.is_some()
                || args.lubricant.is_some()
                || !args.variants.is_empty()
                || args.duration.is_some()
            {
                return Err("a --request file carries its own base and design: give none of --base, --lubricant, --variants, --duration".into());
            }
            let path = args
                .request
                .as_deref()
                .ok_or("the request design needs --request FILE")?;
            return read_request(path);
        }
        Design::PaperTrends => NamedDesign::PaperTrends,
        Design::Sensitivity => NamedDesign::Sensitivity,
        Design::Table2 => NamedDesign::Table2,
    };
    let variants = match (named, &args.lubricant) {
        (NamedDesign::Sensitivity, Some(_)) => {
            return Err("sensitivity takes --variants, not --lubricant".into())
        }
        (NamedDesign::Sensitivity, None) => args.variants.clone(),
        (_, lubricant) if args.variants.is_empty() => lubricant.iter().cloned().collect(),
        _ => {
            return Err(format!(
                "{} takes --lubricant, not --variants",
                named.name()
            ))
        }
    };
    let mut base = match &args.base {
        Some(p) => read_base(p)?,
        None => StudyBase {
            preset: Some("h7005c".into()),
            ..Default::default()
        },
    };
    let trend = matches!(named, NamedDesign::PaperTrends | NamedDesign::Sensitivity);
    let duration = match args.duration {
        Some(d) if !(d > 0.0 && d.is_finite()) => {
            return Err(format!(
                "--duration {d}: must be a positive number of seconds"
            ))
        }
        Some(d) => Some(d),
        None if trend && args.base.is_none() => Some(TREND_DURATION),
        None => None,
    };
    if let Some(d) = duration {
        // a patch over the preset's overrides, or over the inline scene
        let patch = json!({"solver": {"duration": d}});
        match &mut base.scene {
            Some(scene) => merge_patch(scene, &patch),
            None => merge_patch(base.overrides.get_or_insert_with(|| json!({})), &patch),
        }
    }
    Ok(StudyRequest {
        name: None,
        base,
        design: DesignSpec::Named {
            name: named,
            variants,
        },
    })
}

fn read_base(p: &Path) -> Result<StudyBase, String> {
    let text = std::fs::read_to_string(p).map_err(|e| format!("--base {}: {e}", p.display()))?;
    serde_json::from_str(&text).map_err(|e| {
        format!(
            "--base {}: {e} (expected {{\"preset\": ..., \"fault_case\": ..., \"overrides\": ...}} or {{\"scene\": ...}})",
            p.display()
        )
    })
}

fn read_request(path: &Path) -> Result<StudyRequest, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// What the run of one distinct scene gave, as a study point's job would record it.
struct Ran {
    /// `Succeeded` when the run finished, even if it could not be analysed.
    state: PointState,
    /// Why the run failed, or why a finished run has no analysis.
    error: Option<String>,
    /// What the table reads of an analysed run.
    digest: Option<RunDigest>,
    /// The best component's envelope spectrum, for the spectra grid.
    spectrum: Option<PointSpectrum>,
}

/// The runs of a plan's distinct scenes, and which run each point reads.
struct PlanRuns {
    runs: Vec<Ran>,
    /// `slot[i]`: the run of point `i`.
    slot: Vec<usize>,
}

impl PlanRuns {
    fn of_point(&self, i: usize) -> &Ran {
        &self.runs[self.slot[i]]
    }

    fn distinct(&self) -> usize {
        self.runs.len()
    }
}

/// Run one scene and read it as a simulation job does (`jobs::simulation_job`, through
/// the same engine calls: `first_non_finite`, `diagnose_run`): a solver failure or a
/// non-finite sample fails the point with the job's failure kind in front (`numerical:`,
/// as the API's table writes a failed job's error); a finished run that cannot be
/// analysed succeeds with the reason as its error. A run still going after `budget` of
/// wall time is stopped and reported as over budget (a cage whirling on its land can hold
/// the explicit step near 1e-8 s).
fn run_scene(scene: &ValidScene, budget: Option<Duration>) -> Ran {
    let failed = |e: String| Ran {
        state: PointState::Failed,
        error: Some(e),
        digest: None,
        spectrum: None,
    };
    let started = Instant::now();
    let stop = AtomicBool::new(false);
    let mut reached = 0.0;
    let mut watch = |fraction: f64| {
        reached = fraction;
        if budget.is_some_and(|b| started.elapsed() > b) {
            stop.store(true, Ordering::Relaxed);
        }
    };
    let control = RunControl {
        cancel: Some(&stop),
        progress: Some(&mut watch),
    };
    let result = match simulate(scene, control) {
        Ok(r) => r,
        Err(e) if e.is_cancelled() => {
            let duration = scene.solver.duration;
            return failed(format!(
                "over the {:.0} s wall-time budget at t = {:.4} of {duration} s simulated",
                budget.unwrap_or_default().as_secs_f64(),
                reached * duration
            ));
        }
        Err(e) => return failed(format!("numerical: {e}")),
    };
    if let Some(message) = first_non_finite(&result) {
        return failed(format!("numerical: {message}"));
    }
    let out = match diagnose_run(&result, scene) {
        Ok((_, _, out)) => out,
        Err(message) => {
            return Ran {
                state: PointState::Succeeded,
                error: Some(message),
                digest: None,
                spectrum: None,
            }
        }
    };
    let level = out.report.best_component.level;
    let spectrum = out
        .level_spectra
        .get(level - 1)
        .and_then(Option::as_ref)
        .map(|s| PointSpectrum {
            df: s.df,
            amplitude: s.amplitude.clone(),
            level,
        });
    Ran {
        state: PointState::Succeeded,
        error: None,
        digest: Some(RunDigest::of_run(&result, scene, out.report)),
        spectrum,
    }
}

/// Run every distinct scene of the plan once, `workers` at a time.
fn run_plan(plan: &Plan, workers: usize, budget: Option<Duration>) -> PlanRuns {
    // each distinct scene once: `first_of[u]` is the first point of scene `u`
    let mut slot = Vec::with_capacity(plan.points.len());
    let mut first_of: Vec<usize> = Vec::new();
    let mut index: HashMap<String, usize> = HashMap::new();
    for (i, p) in plan.points.iter().enumerate() {
        let u = *index.entry(scene_key(&p.scene)).or_insert_with(|| {
            first_of.push(i);
            first_of.len() - 1
        });
        slot.push(u);
    }
    let distinct = first_of.len();
    let bar = ProgressBar::new(distinct as u64);
    bar.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} {msg}")
            .expect("static template"),
    );
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Ran>>> = Mutex::new((0..distinct).map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..workers.min(distinct) {
            s.spawn(|| loop {
                let u = next.fetch_add(1, Ordering::Relaxed);
                let Some(&i) = first_of.get(u) else { break };
                let p = &plan.points[i];
                let ran = run_scene(&p.scene, budget);
                let what = point_name(plan, i);
                let line = match (&ran.digest, &ran.error) {
                    (Some(d), _) => format!("{what}: {:.1} s", d.wall_time),
                    (None, Some(e)) => format!("{what}: {}: {e}", ran.state),
                    (None, None) => format!("{what}: {}", ran.state),
                };
                // one line per point: the log when stderr is not a terminal (the bar hides)
                bar.println(&line);
                if bar.is_hidden() {
                    eprintln!("[{}/{distinct}] {line}", u + 1);
                }
                bar.set_message(what);
                bar.inc(1);
                results.lock().expect("no worker panics while holding it")[u] = Some(ran);
            });
        }
    });
    bar.finish_and_clear();
    let runs = results
        .into_inner()
        .expect("workers joined")
        .into_iter()
        .map(|r| r.expect("every scene ran"))
        .collect();
    PlanRuns { runs, slot }
}

/// A point as a log line names it: its label, fault case and factor values.
fn point_name(plan: &Plan, i: usize) -> String {
    let spec = &plan.points[i].spec;
    let mut parts: Vec<String> = spec.label.iter().cloned().collect();
    if let Some(c) = spec.fault_case {
        parts.push(format!("{c:?} fault").to_lowercase());
    }
    parts.extend(
        spec.factors
            .iter()
            .map(|f| format!("{} {}", f.name, f.value)),
    );
    format!("point {i} ({})", parts.join(", "))
}

/// The study's table from its runs, as the API reads it from its jobs (no job ids).
fn table_of(plan: &Plan, runs: &PlanRuns) -> StudyTable {
    let rows = plan
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let ran = runs.of_point(i);
            StudyTableRow::new(
                i,
                &p.spec,
                None,
                ran.state,
                ran.error.clone(),
                ran.digest.as_ref(),
            )
        })
        .collect();
    StudyTable {
        id: String::new(),
        name: plan.name.clone(),
        factors: plan.design.factors.iter().map(|f| f.name.clone()).collect(),
        rows,
    }
}

/// `table.csv`, `table.json` and every plot of the study.
fn write_outputs(out: &Path, plan: &Plan, table: &StudyTable, runs: &PlanRuns) -> CliResult {
    let write = |name: &str, text: &str| {
        std::fs::write(out.join(name), text)
            .map_err(|e| format!("{}: {e}", out.join(name).display()))
    };
    write("table.csv", &to_csv(table))?;
    write(
        "table.json",
        &serde_json::to_string_pretty(table).map_err(|e| e.to_string())?,
    )?;
    let mut lookup = |r: &StudyTableRow| runs.of_point(r.index).spectrum.clone();
    for name in plot_names(&plan.design, row_keys(&table.rows)) {
        match draw(&plan.name, &plan.design, &table.rows, &name, &mut lookup) {
            Some(Ok(svg)) => write(&name, &svg)?,
            Some(Err(e)) => eprintln!("{name}: not drawn: {e}"),
            None => {}
        }
    }
    Ok(())
}

/// A markdown table: per point its factors, each line's eq. 37 value, the best component's
/// reading and the cage-speed error.
fn print_summary(table: &StudyTable, elapsed: f64, distinct: usize) {
    println!(
        "{}: {} points ({distinct} distinct scenes) in {elapsed:.1} s",
        table.name,
        table.rows.len()
    );
    println!();
    println!("| point | fault | {} | BPFO (Hz) | BPFO best (Hz) | BPFO best error (%) | BPFO detected | BPFO cage error (%) | BPFI (Hz) | BPFI best (Hz) | BPFI best error (%) | BPFI detected | BPFI cage error (%) | level | whirl | wall (s) |", table.factors.join(" | "));
    // point, fault, the factors (one empty cell when there are none), five cells per line,
    // level, whirl, wall
    println!("|{}", " --- |".repeat(table.factors.len().max(1) + 15));
    for r in &table.rows {
        let factors: Vec<String> = r.factors.iter().map(|f| format!("{}", f.value)).collect();
        let name = match &r.label {
            Some(l) => format!("{} {l}", r.index),
            None => r.index.to_string(),
        };
        let fault = r
            .fault_case
            .map(|c| format!("{c:?}").to_lowercase())
            .unwrap_or_default();
        match &r.result {
            Some(p) => {
                let cells = |l: &LineReading| {
                    format!(
                        "{:.2} | {:.2} | {:+.3} | {} | {:+.3}",
                        l.theory_hz, l.best.hz, l.best.error_pct, l.best.detected, l.cage_error_pct
                    )
                };
                println!(
                    "| {name} | {fault} | {} | {} | {} | {} | {} | {:.1} |",
                    factors.join(" | "),
                    cells(&p.bpfo),
                    cells(&p.bpfi),
                    p.bpfo.best_level,
                    p.cage.whirl.map(|w| w.to_string()).unwrap_or_default(),
                    p.wall_time
                );
            }
            None => println!(
                "| {name} | {fault} | {} | {}: {} |",
                factors.join(" | "),
                r.state,
                r.error.as_deref().unwrap_or("")
            ),
        }
    }
}
