//! `bearing-sim study table2|request` (and `paper-trends --base`): a study request run
//! in-process, with the same expansion, table and plots as `POST /v1/studies`.

use super::result::CliResult;
use crate::studies::charts::{draw, plot_names, row_keys, PointSpectrum};
use crate::studies::table::JobState;
use crate::studies::{
    plan, to_csv, DesignSpec, NamedDesign, RunDigest, StudyBase, StudyRequest, StudyTable,
    StudyTableRow,
};
use bearing_core::scene::ValidScene;
use bearing_core::signal::analysis::AnalysisOptions;
use bearing_core::simulation::{simulate, RunControl};
use bearing_core::simulation_analysis::{analyze_simulation, frequency_comparison};
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::HashMap;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Channels tried for the analysis, in order (as the service's simulation jobs do).
const CHANNELS: [&str; 2] = ["outer_ring_accel_z", "outer_ring_accel_y"];

/// A named design on a base read from a file (or the H7005C preset).
pub fn named_request(design: NamedDesign, base: Option<&Path>) -> Result<StudyRequest, String> {
    let base = match base {
        None => StudyBase {
            preset: Some("h7005c".into()),
            ..Default::default()
        },
        Some(p) => {
            let text =
                std::fs::read_to_string(p).map_err(|e| format!("--base {}: {e}", p.display()))?;
            serde_json::from_str(&text).map_err(|e| {
                format!(
                    "--base {}: {e} (expected {{\"preset\": ..., \"fault_case\": ..., \"overrides\": ...}} or {{\"scene\": ...}})",
                    p.display()
                )
            })?
        }
    };
    Ok(StudyRequest {
        name: None,
        base,
        design: DesignSpec::Named { name: design },
    })
}

pub fn read_request(path: &Path) -> Result<StudyRequest, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// What a local run of one distinct scene gave.
struct Ran {
    digest: Result<RunDigest, String>,
    spectrum: Option<PointSpectrum>,
}

fn run_scene(scene: &ValidScene, budget: Option<Duration>) -> Ran {
    let started = Instant::now();
    let stop = AtomicBool::new(false);
    let mut watch = |_f: f64| {
        if budget.is_some_and(|b| started.elapsed() > b) {
            stop.store(true, Ordering::Relaxed);
        }
    };
    let result = match simulate(
        scene,
        RunControl {
            cancel: Some(&stop),
            progress: Some(&mut watch),
        },
    ) {
        Ok(r) => r,
        Err(e) if e.is_cancelled() => {
            return Ran {
                digest: Err(format!(
                    "over the {:.0} s wall-time budget",
                    budget.unwrap_or_default().as_secs_f64()
                )),
                spectrum: None,
            }
        }
        Err(e) => {
            return Ran {
                digest: Err(e.to_string()),
                spectrum: None,
            }
        }
    };
    let Some(channel) = CHANNELS.iter().find(|c| result.channels.get(c).is_some()) else {
        return Ran {
            digest: Err(format!("no channel {} to analyse", CHANNELS.join(" or "))),
            spectrum: None,
        };
    };
    let out = match analyze_simulation(&result, scene, channel, &AnalysisOptions::default()) {
        Ok(o) => o,
        Err(e) => {
            return Ran {
                digest: Err(format!("analysis: {e}")),
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
    let s = &result.summary;
    Ran {
        digest: Ok(RunDigest {
            frequencies: frequency_comparison(&result, scene),
            report: out.report,
            cage_speed: s.mean_cage_speed,
            epicyclic_speed: s.epicyclic_cage_speed,
            slip: s.cage_slip,
            cage_motion: Some(s.cage_motion),
            wall_time: s.stats.wall_time,
        }),
        spectrum,
    }
}

/// Plan, run every distinct scene once (`workers` at a time), write the table and plots.
pub fn run_request(
    req: &StudyRequest,
    workers: usize,
    budget: Option<Duration>,
    out: &Path,
) -> CliResult {
    let plan = plan(req).map_err(|ps| {
        let lines: Vec<String> = ps
            .iter()
            .map(|p| format!("  {}: {}", p.path, p.message))
            .collect();
        format!("the study is invalid:\n{}", lines.join("\n"))
    })?;
    std::fs::create_dir_all(out).map_err(|e| format!("--out {}: {e}", out.display()))?;
    // each distinct scene once: `first_of[u]` is the first point of scene `u`
    let mut slot = Vec::with_capacity(plan.points.len());
    let mut first_of: Vec<usize> = Vec::new();
    let mut index: HashMap<&str, usize> = HashMap::new();
    for (i, p) in plan.points.iter().enumerate() {
        let u = *index.entry(p.key.as_str()).or_insert_with(|| {
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
    let started = Instant::now();
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Ran>>> = Mutex::new((0..distinct).map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..workers.max(1).min(distinct) {
            s.spawn(|| loop {
                let u = next.fetch_add(1, Ordering::Relaxed);
                let Some(&i) = first_of.get(u) else { break };
                let p = &plan.points[i];
                let ran = run_scene(&p.scene, budget);
                let what = p.spec.label.clone().unwrap_or_else(|| p.scene.name.clone());
                let line = match &ran.digest {
                    Ok(d) => format!("{what}: {:.1} s", d.wall_time),
                    Err(e) => format!("{what}: failed: {e}"),
                };
                bar.println(&line);
                if bar.is_hidden() {
                    eprintln!("[{}/{}] {line}", u + 1, distinct);
                }
                bar.inc(1);
                results.lock().expect("no worker panics while holding it")[u] = Some(ran);
            });
        }
    });
    bar.finish_and_clear();
    let elapsed = started.elapsed().as_secs_f64();
    let results = results.into_inner().expect("workers joined");
    let rows: Vec<StudyTableRow> = plan
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let ran = results[slot[i]].as_ref().expect("every scene ran");
            let (state, err, d) = match &ran.digest {
                Ok(d) => (JobState::Succeeded, None, Some(d)),
                Err(e) => (JobState::Failed, Some(e.clone()), None),
            };
            StudyTableRow::new(i, &p.spec, None, state, err, d)
        })
        .collect();
    let table = StudyTable {
        id: String::new(),
        name: plan.name.clone(),
        factors: plan.design.factors.iter().map(|f| f.name.clone()).collect(),
        rows,
    };
    let write = |name: &str, text: &str| {
        std::fs::write(out.join(name), text)
            .map_err(|e| format!("{}: {e}", out.join(name).display()))
    };
    write("table.csv", &to_csv(&table))?;
    write(
        "table.json",
        &serde_json::to_string_pretty(&table).map_err(|e| e.to_string())?,
    )?;
    let mut lookup = |r: &StudyTableRow| {
        results[slot[r.index]]
            .as_ref()
            .and_then(|ran| ran.spectrum.clone())
    };
    for name in plot_names(&plan.design, row_keys(&table.rows)) {
        match draw(&plan.name, &plan.design, &table.rows, &name, &mut lookup) {
            Some(Ok(svg)) => write(&name, &svg)?,
            Some(Err(e)) => eprintln!("{name}: not drawn: {e}"),
            None => {}
        }
    }
    print_summary(&table, elapsed, distinct);
    Ok(())
}

fn print_summary(table: &StudyTable, elapsed: f64, distinct: usize) {
    println!(
        "{}: {} points ({distinct} distinct scenes) in {elapsed:.1} s",
        table.name,
        table.rows.len()
    );
    println!();
    println!("| point | {} | BPFO (Hz) | BPFO best (Hz) | BPFO error (%) | BPFO detected | BPFI (Hz) | BPFI best (Hz) | BPFI error (%) | BPFI detected | level | wall (s) |", table.factors.join(" | "));
    println!("|{}", " --- |".repeat(table.factors.len() + 11));
    for r in &table.rows {
        let factors: Vec<String> = r.factors.iter().map(|f| format!("{}", f.value)).collect();
        let name = r.label.clone().unwrap_or_else(|| r.index.to_string());
        match &r.result {
            Some(p) => {
                let cells = |l: &bearing_core::study::LineReading| {
                    format!(
                        "{:.2} | {:.2} | {:+.3} | {}",
                        l.theory_hz, l.best.hz, l.best.error_pct, l.best.detected
                    )
                };
                println!(
                    "| {name} | {} | {} | {} | {} | {:.1} |",
                    factors.join(" | "),
                    cells(&p.bpfo),
                    cells(&p.bpfi),
                    p.bpfo.best_level,
                    p.wall_time
                );
            }
            None => println!(
                "| {name} | {} | failed: {} |",
                factors.join(" | "),
                r.error.as_deref().unwrap_or("")
            ),
        }
    }
}
