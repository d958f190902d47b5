//! A study's table: one row per point with its factor values, BPFO and BPFI read from its
//! run (eq. 37 at the nominal and at the loaded angle, the cage-speed value, the peaks
//! identified in the raw and best-component envelope spectra), the cage, and the run time.

use super::design::{FactorValue, PointSpec};
use super::reading::{read_line, FaultLine, LineReading};
use crate::dynamics::{CageMotion, CageState};
use crate::scene::{FaultCase, ValidScene};
use crate::signal::analysis::AnalysisReport;
use crate::simulation::SimResult;
use crate::simulation_analysis::{frequency_comparison, FrequencyComparison};
use serde::{Deserialize, Serialize};
use std::fmt::{self, Write};

// Where a point is: its simulation job's state in the service, succeeded or failed in a
// local run. The schema shares the name and values of the service's job state. (A plain
// comment: a doc comment would give this schema a description the job state's lacks.)
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema), schema(as = JobState))]
#[serde(rename_all = "snake_case")]
pub enum PointState {
    Queued,
    Running,
    Succeeded,
    Failed,
    Cancelled,
}

impl fmt::Display for PointState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            PointState::Queued => "queued",
            PointState::Running => "running",
            PointState::Succeeded => "succeeded",
            PointState::Failed => "failed",
            PointState::Cancelled => "cancelled",
        })
    }
}

/// What a table row needs of a finished run (from a stored record or a local run).
#[derive(Debug, Clone)]
pub struct RunDigest {
    pub frequencies: FrequencyComparison,
    pub report: AnalysisReport,
    /// Mean cage speed, rad/s.
    pub cage_speed: f64,
    /// Pure-rolling cage speed of the loaded balls, rad/s.
    pub epicyclic_speed: f64,
    /// 1 - mean / epicyclic, -.
    pub slip: f64,
    pub cage_motion: Option<CageMotion>,
    /// Solver wall time, s.
    pub wall_time: f64,
}

impl RunDigest {
    /// From a run in hand and its envelope analysis.
    pub fn of_run(result: &SimResult, scene: &ValidScene, report: AnalysisReport) -> RunDigest {
        let s = &result.summary;
        RunDigest {
            frequencies: frequency_comparison(result, scene),
            report,
            cage_speed: s.mean_cage_speed,
            epicyclic_speed: s.epicyclic_cage_speed,
            slip: s.cage_slip,
            cage_motion: Some(s.cage_motion),
            wall_time: s.stats.wall_time,
        }
    }
}

/// The cage over the steady window.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct CageReading {
    /// rad/s (null only for a degenerate run, as in a simulation's result).
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub mean_speed: f64,
    /// rad/s.
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub epicyclic_speed: f64,
    /// -.
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub slip: f64,
    /// The cage centre whirls on its land (null for records without the cage's motion).
    pub whirl: Option<bool>,
    /// Mean eccentricity over the land clearance, -.
    pub mean_eccentricity: Option<f64>,
}

/// The readings of a point whose run succeeded.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct PointResult {
    /// Mean shaft frequency, Hz.
    pub shaft_hz: f64,
    /// Envelope-spectrum resolution, Hz.
    pub df_hz: f64,
    pub bpfo: LineReading,
    pub bpfi: LineReading,
    pub cage: CageReading,
    /// Solver wall time, s.
    pub wall_time: f64,
}

impl PointResult {
    pub fn of(d: &RunDigest) -> PointResult {
        PointResult {
            shaft_hz: d.frequencies.shaft_hz,
            df_hz: d.report.df,
            bpfo: read_line(FaultLine::Bpfo, &d.frequencies, &d.report),
            bpfi: read_line(FaultLine::Bpfi, &d.frequencies, &d.report),
            cage: CageReading {
                mean_speed: d.cage_speed,
                epicyclic_speed: d.epicyclic_speed,
                slip: d.slip,
                whirl: d.cage_motion.map(|m| m.state == CageState::Whirling),
                mean_eccentricity: d.cage_motion.map(|m| m.mean_eccentricity),
            },
            wall_time: d.wall_time,
        }
    }

    /// The lines the point's fault case shows: BPFI for an inner fault, BPFO for an outer
    /// one, both otherwise.
    pub fn lines_for(case: Option<FaultCase>) -> &'static [FaultLine] {
        match case {
            Some(FaultCase::Inner) => &[FaultLine::Bpfi],
            Some(FaultCase::Outer) => &[FaultLine::Bpfo],
            _ => &[FaultLine::Bpfo, FaultLine::Bpfi],
        }
    }

    pub fn line(&self, l: FaultLine) -> &LineReading {
        match l {
            FaultLine::Bpfo => &self.bpfo,
            FaultLine::Bpfi => &self.bpfi,
        }
    }
}

/// One row of the table.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct StudyTableRow {
    /// Point index in the design, from 0.
    pub index: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
    /// The point's simulation job (absent in local runs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub job_id: Option<String>,
    pub state: PointState,
    /// Why the point has no result.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fault_case: Option<FaultCase>,
    /// The factor this point's line varies.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub line: Option<String>,
    pub factors: Vec<FactorValue>,
    /// Simulated time, s.
    pub duration: f64,
    /// Null unless the point succeeded.
    pub result: Option<PointResult>,
}

impl StudyTableRow {
    pub fn new(
        index: usize,
        spec: &PointSpec,
        job_id: Option<String>,
        state: PointState,
        error: Option<String>,
        digest: Option<&RunDigest>,
    ) -> StudyTableRow {
        StudyTableRow {
            index,
            label: spec.label.clone(),
            job_id,
            state,
            error,
            fault_case: spec.fault_case,
            line: spec.line.clone(),
            factors: spec.factors.clone(),
            duration: spec.duration,
            result: digest.map(PointResult::of),
        }
    }

    /// Both lines detected in the best component's envelope spectrum.
    pub fn both_detected(&self) -> bool {
        self.result
            .as_ref()
            .is_some_and(|r| r.bpfo.best.detected && r.bpfi.best.detected)
    }
}

/// The whole table as JSON.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct StudyTable {
    pub id: String,
    pub name: String,
    /// Factor names, in the order of each row's `factors`.
    pub factors: Vec<String>,
    pub rows: Vec<StudyTableRow>,
}

const LINE_COLUMNS: [&str; 13] = [
    "theory_hz",
    "loaded_theory_hz",
    "cage_hz",
    "cage_error_pct",
    "raw_hz",
    "raw_error_pct",
    "raw_prominence_db",
    "raw_detected",
    "best_level",
    "best_hz",
    "best_error_pct",
    "best_prominence_db",
    "best_detected",
];

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x}")
    } else {
        String::new()
    }
}

/// The table as CSV (RFC 4180): a header, then a row per point; empty cells where a point
/// has no value.
pub fn to_csv(table: &StudyTable) -> String {
    let mut out = String::new();
    let mut header: Vec<String> = ["index", "label", "job_id", "state", "fault_case", "line"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    header.extend(table.factors.iter().cloned());
    header.extend(["duration_s", "shaft_hz", "df_hz"].map(String::from));
    for l in ["bpfo", "bpfi"] {
        header.extend(LINE_COLUMNS.iter().map(|c| format!("{l}_{c}")));
    }
    header.extend(
        [
            "cage_speed_rad_s",
            "cage_epicyclic_rad_s",
            "cage_slip",
            "cage_whirl",
            "cage_eccentricity",
            "wall_time_s",
            "error",
        ]
        .map(String::from),
    );
    let _ = writeln!(
        out,
        "{}",
        header
            .iter()
            .map(|h| csv_field(h))
            .collect::<Vec<_>>()
            .join(",")
    );
    for r in &table.rows {
        let mut cells = vec![
            r.index.to_string(),
            csv_field(r.label.as_deref().unwrap_or("")),
            r.job_id.clone().unwrap_or_default(),
            r.state.to_string(),
            r.fault_case
                .map(|c| format!("{c:?}").to_lowercase())
                .unwrap_or_default(),
            csv_field(r.line.as_deref().unwrap_or("")),
        ];
        for f in &table.factors {
            let v = r.factors.iter().find(|v| &v.name == f).map(|v| v.value);
            cells.push(v.map(num).unwrap_or_default());
        }
        cells.push(num(r.duration));
        match &r.result {
            Some(p) => {
                cells.push(num(p.shaft_hz));
                cells.push(num(p.df_hz));
                for l in [&p.bpfo, &p.bpfi] {
                    cells.extend([
                        num(l.theory_hz),
                        num(l.loaded_theory_hz),
                        num(l.cage_hz),
                        num(l.cage_error_pct),
                        num(l.raw.hz),
                        num(l.raw.error_pct),
                        num(l.raw.prominence_db),
                        l.raw.detected.to_string(),
                        l.best_level.to_string(),
                        num(l.best.hz),
                        num(l.best.error_pct),
                        num(l.best.prominence_db),
                        l.best.detected.to_string(),
                    ]);
                }
                cells.extend([
                    num(p.cage.mean_speed),
                    num(p.cage.epicyclic_speed),
                    num(p.cage.slip),
                    p.cage.whirl.map(|w| w.to_string()).unwrap_or_default(),
                    p.cage.mean_eccentricity.map(num).unwrap_or_default(),
                    num(p.wall_time),
                ]);
            }
            // shaft and df, both lines' columns, the cage's five and the wall time
            None => cells.extend(std::iter::repeat_n(
                String::new(),
                2 + 2 * LINE_COLUMNS.len() + 6,
            )),
        }
        cells.push(csv_field(r.error.as_deref().unwrap_or("")));
        let _ = writeln!(out, "{}", cells.join(","));
    }
    out
}
