//! `bearing-sim study DESIGN --out DIR`: run a parameter study locally and write its table
//! (CSV and JSON) and plots (SVG).
//!
//! Designs: `paper-trends` (Figures 23-28: speed, axial and radial load for single inner
//! and outer faults) and `sensitivity` (each trend's end points under every lubricant
//! variant) on the H7005C scene with the lubricant variants of `docs/lab/paper-trends.md`;
//! `table2` (the paper's nine compound-fault sizes) and `request` (any `POST /v1/studies`
//! body), and `paper-trends` with `--base`, run as the service runs studies
//! ([`super::study_plan`]). Identical scenes are run once.

use super::result::CliResult;
use super::study_plan::{named_request, read_request, run_request};
use crate::plots::{trend_svg, TrendSeries};
use crate::studies::NamedDesign;
use bearing_core::scene::FaultCase;
use bearing_core::study::{
    lubricant_variants, paper_trends, run_point, sensitivity, Factor, StudyPoint, StudyRow,
};
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::HashMap;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Duration;

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum Design {
    /// Figures 23-28 with one lubricant variant.
    PaperTrends,
    /// Each trend's end points (outer fault) under every lubricant variant.
    Sensitivity,
    /// Table 2: the nine compound-fault sizes (on `--base`, default the H7005C preset).
    Table2,
    /// The study request in `--request FILE` (a `POST /v1/studies` body).
    Request,
}

#[derive(clap::Args, Debug)]
pub struct StudyArgs {
    pub design: Design,
    /// Simulated time per point for `paper-trends` and `sensitivity` without `--base`, s
    /// (the other designs take the base scene's duration) (constant speed; the first quarter, at most 0.1 s,
    /// settles and is left out of the averages and spectra).
    #[arg(long, default_value_t = 0.3)]
    pub duration: f64,
    /// Lubricant variant for `paper-trends`: paper, drag, rolling, drag+rolling,
    /// drag5+rolling.
    #[arg(long, default_value = "paper")]
    pub lubricant: String,
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
    /// Base scene for `table2` and `paper-trends`, as a JSON file: `{"preset": "h7005c",
    /// "fault_case": ..., "overrides": {...}}` or `{"scene": {...}}`. With it,
    /// `paper-trends` runs the service's design on that base (the lubricant is the base's).
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
    let request = match (args.design, &args.base) {
        (Design::Table2, base) => Some(named_request(NamedDesign::Table2, base.as_deref())?),
        (Design::PaperTrends, Some(base)) => {
            Some(named_request(NamedDesign::PaperTrends, Some(base))?)
        }
        (Design::Request, _) => {
            let path = args
                .request
                .as_deref()
                .ok_or("the request design needs --request FILE")?;
            Some(read_request(path)?)
        }
        _ => None,
    };
    if let Some(req) = request {
        return run_request(&req, args.workers, budget, &args.out);
    }
    let catalogue = lubricant_variants();
    let find = |name: &str| {
        catalogue
            .iter()
            .find(|v| v.name == name)
            .cloned()
            .ok_or_else(|| {
                let names: Vec<&str> = catalogue.iter().map(|v| v.name.as_str()).collect();
                format!(
                    "lubricant variant '{name}': expected one of {}",
                    names.join(", ")
                )
            })
    };
    if !(args.duration > 0.0 && args.duration.is_finite()) {
        return Err(format!(
            "--duration {}: must be a positive number of seconds",
            args.duration
        )
        .into());
    }
    let points = match args.design {
        Design::PaperTrends => paper_trends(&find(&args.lubricant)?, args.duration),
        Design::Table2 | Design::Request => unreachable!("run as study requests above"),
        Design::Sensitivity => {
            let variants = if args.variants.is_empty() {
                catalogue.clone()
            } else {
                args.variants
                    .iter()
                    .map(|n| find(n))
                    .collect::<Result<_, _>>()?
            };
            sensitivity(&variants, args.duration)
        }
    };
    std::fs::create_dir_all(&args.out).map_err(|e| format!("--out {}: {e}", args.out.display()))?;
    let (rows, failed) = run_points(&points, args.workers.max(1), budget)?;
    write_table(&args.out, &rows)?;
    write_failures(&args.out, &failed)?;
    if matches!(args.design, Design::PaperTrends) {
        write_trend_plots(&args.out, &rows)?;
    }
    print_markdown(&rows);
    if !failed.is_empty() {
        println!();
        println!("Points without a row:");
        println!();
        for f in &failed {
            println!(
                "- {:?} fault, {} rpm, Fa {} N, Fr {} N ({}): {}",
                f.point.fault,
                f.point.rpm,
                f.point.axial_load,
                f.point.radial_load,
                f.point.lubricant.name,
                f.error
            );
        }
    }
    Ok(())
}

/// A point that produced no row, and why.
#[derive(serde::Serialize)]
struct FailedPoint {
    point: StudyPoint,
    error: String,
}

fn write_failures(dir: &Path, failed: &[FailedPoint]) -> Result<(), String> {
    let path = dir.join("failed.json");
    let text = serde_json::to_string_pretty(failed).map_err(|e| e.to_string())?;
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Run every distinct scene once, `workers` at a time; rows come back in design order.
fn run_points(
    points: &[StudyPoint],
    workers: usize,
    budget: Option<Duration>,
) -> Result<(Vec<StudyRow>, Vec<FailedPoint>), String> {
    let mut unique: Vec<&StudyPoint> = Vec::new();
    let mut index_of: HashMap<String, usize> = HashMap::new();
    let mut slot = Vec::with_capacity(points.len());
    for p in points {
        let key = serde_json::to_string(&p.scene()).map_err(|e| e.to_string())?;
        let i = *index_of.entry(key).or_insert_with(|| {
            unique.push(p);
            unique.len() - 1
        });
        slot.push(i);
    }
    let bar = ProgressBar::new(unique.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} {msg}")
            .expect("static template"),
    );
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Result<StudyRow, String>>>> =
        Mutex::new(vec![None; unique.len()]);
    std::thread::scope(|s| {
        for _ in 0..workers.min(unique.len()) {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(p) = unique.get(i) else { break };
                let r = run_point(p, budget).map_err(|e| e.to_string());
                let what = format!(
                    "{:?} fault, {} rpm, Fa {} N, Fr {} N ({})",
                    p.fault, p.rpm, p.axial_load, p.radial_load, p.lubricant.name
                );
                let line = match &r {
                    Ok(row) => format!(
                        "{what}: cage error {:+.3} %, {:.1} s",
                        row.cage_error_pct, row.wall_time
                    ),
                    Err(e) => format!("{what}: failed: {e}"),
                };
                // one line per point: the log when stderr is not a terminal (the bar hides)
                bar.println(&line);
                if bar.is_hidden() {
                    eprintln!("[{}/{}] {line}", i + 1, unique.len());
                }
                bar.set_message(what);
                bar.inc(1);
                results.lock().expect("no worker panics while holding it")[i] = Some(r);
            });
        }
    });
    bar.finish_and_clear();
    let results = results.into_inner().expect("workers joined");
    let mut rows = Vec::with_capacity(points.len());
    let mut failed = Vec::new();
    for (p, &i) in points.iter().zip(&slot) {
        match results[i].as_ref().expect("every point ran") {
            Ok(row) => {
                let mut row = row.clone();
                // a shared scene is listed under each factor it belongs to
                row.factor = p.factor;
                row.value = p.value();
                rows.push(row);
            }
            Err(e) => failed.push(FailedPoint {
                point: p.clone(),
                error: e.clone(),
            }),
        }
    }
    Ok((rows, failed))
}

const CSV_HEADER: &str = "factor,value,fault,lubricant,rpm,axial_load_N,radial_load_N,line,theory_hz,loaded_theory_hz,cage_hz,cage_error_pct,raw_hz,raw_error_pct,raw_prominence_db,raw_detected,best_level,best_hz,best_error_pct,best_prominence_db,best_detected,df_hz,cage_slip,cage_state,cage_eccentricity,wall_time_s,rhs_evaluations";

fn csv_line(r: &StudyRow) -> String {
    format!(
        "{},{},{:?},{},{},{},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.2},{},{},{:.4},{:.4},{:.2},{},{:.4},{:.6},{:?},{:.4},{:.2},{}",
        r.factor.name(),
        r.value,
        r.fault,
        r.lubricant,
        r.rpm,
        r.axial_load,
        r.radial_load,
        r.line,
        r.theory_hz,
        r.loaded_theory_hz,
        r.cage_hz,
        r.cage_error_pct,
        r.raw_hz,
        r.raw_error_pct,
        r.raw_prominence_db,
        r.raw_detected,
        r.best_level,
        r.best_hz,
        r.best_error_pct,
        r.best_prominence_db,
        r.best_detected,
        r.df_hz,
        r.cage_slip,
        r.cage_state,
        r.cage_eccentricity,
        r.wall_time,
        r.rhs_evaluations
    )
}

fn write_table(dir: &Path, rows: &[StudyRow]) -> Result<(), String> {
    let mut csv = String::from(CSV_HEADER);
    csv.push('\n');
    for r in rows {
        csv.push_str(&csv_line(r));
        csv.push('\n');
    }
    let write = |name: &str, text: &str| {
        std::fs::write(dir.join(name), text)
            .map_err(|e| format!("{}: {e}", dir.join(name).display()))
    };
    write("table.csv", &csv)?;
    write(
        "table.json",
        &serde_json::to_string_pretty(rows).map_err(|e| e.to_string())?,
    )
}

/// One chart per factor and fault: eq. 37, the frequency identified in the raw and the
/// best-component envelope spectra and the cage-speed frequency (left axis), and the raw
/// spectrum's and the cage's errors (right axis).
fn write_trend_plots(dir: &Path, rows: &[StudyRow]) -> Result<(), String> {
    for fault in [FaultCase::Inner, FaultCase::Outer] {
        for factor in [Factor::Speed, Factor::AxialLoad, Factor::RadialLoad] {
            let sel: Vec<&StudyRow> = rows
                .iter()
                .filter(|r| r.fault == fault && r.factor == factor)
                .collect();
            if sel.is_empty() {
                continue;
            }
            let series = |label: &str, on_error_axis, f: &dyn Fn(&StudyRow) -> f64| TrendSeries {
                label: label.into(),
                points: sel.iter().map(|r| (r.value, f(r))).collect(),
                on_error_axis,
            };
            let line = &sel[0].line;
            let all = [
                series(&format!("{line}, eq. 37 (15 deg)"), false, &|r| r.theory_hz),
                series(&format!("{line}, raw envelope spectrum"), false, &|r| {
                    r.raw_hz
                }),
                series(&format!("{line}, best DTCWT component"), false, &|r| {
                    r.best_hz
                }),
                series("error, raw envelope spectrum", true, &|r| r.raw_error_pct),
                series("error, from the cage speed", true, &|r| r.cage_error_pct),
            ];
            let fault_name = match fault {
                FaultCase::Inner => "inner",
                _ => "outer",
            };
            let title = format!(
                "Single {fault_name}-ring fault: {line} against {} ({})",
                factor.label(),
                sel[0].lubricant
            );
            let svg = trend_svg(&title, factor.label(), &all).map_err(|e| e.to_string())?;
            let name = format!("{}-{fault_name}.svg", factor.name().replace('_', "-"));
            std::fs::write(dir.join(&name), svg)
                .map_err(|e| format!("{}: {e}", dir.join(&name).display()))?;
        }
    }
    Ok(())
}

fn print_markdown(rows: &[StudyRow]) {
    println!("| fault | factor | value | lubricant | eq. 37 (Hz) | raw (Hz) | raw error (%) | raw prominence (dB) | best level | best error (%) | cage error (%) | cage | e | wall (s) |");
    println!(
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    for r in rows {
        println!(
            "| {:?} | {} | {} | {} | {:.2} | {:.2} | {:+.3} | {:.1} | {} | {:+.3} | {:+.3} | {:?} | {:.2} | {:.1} |",
            r.fault,
            r.factor.name(),
            r.value,
            r.lubricant,
            r.theory_hz,
            r.raw_hz,
            r.raw_error_pct,
            r.raw_prominence_db,
            r.best_level,
            r.best_error_pct,
            r.cage_error_pct,
            r.cage_state,
            r.cage_eccentricity,
            r.wall_time
        );
    }
}
