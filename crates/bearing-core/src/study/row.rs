//! One study point run and read the way the paper reads it: the fault's characteristic
//! frequency identified in the envelope spectra of the accelerometer signal, against eq. 37.

use super::design::{Factor, StudyPoint};
use super::reading::{read_line, FaultLine};
use crate::dynamics::CageState;
use crate::scene::{FaultCase, ValidationErrors};
use crate::signal::analysis::{AnalysisError, AnalysisOptions};
use crate::simulation::{simulate, RunControl, SimError};
use crate::simulation_analysis::{analyze_simulation, frequency_comparison};
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// The accelerometer channel the paper analyses (pedestal Z acceleration, m/s^2).
pub const STUDY_CHANNEL: &str = "outer_ring_accel_z";

/// One table row: the point, what the envelope spectra show, what the cage did.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyRow {
    pub factor: Factor,
    /// The factor's value (rpm or N).
    pub value: f64,
    pub fault: FaultCase,
    /// Lubricant variant name.
    pub lubricant: String,
    /// rpm.
    pub rpm: f64,
    /// N.
    pub axial_load: f64,
    /// N.
    pub radial_load: f64,
    /// `BPFI` for an inner fault, `BPFO` for an outer one.
    pub line: String,
    /// Eq. 37 at the nominal contact angle and the run's mean shaft speed, Hz.
    pub theory_hz: f64,
    /// The same with the loaded balls' contact angles (pure rolling of the load zone), Hz.
    pub loaded_theory_hz: f64,
    /// From the run's mean cage speed (`Z f_c` or `Z (f_s - f_c)`), Hz.
    pub cage_hz: f64,
    /// `(cage_hz - theory_hz) / theory_hz`, %.
    pub cage_error_pct: f64,
    /// Peak identified in the raw envelope spectrum, Hz (NaN when none).
    pub raw_hz: f64,
    /// `(raw_hz - theory_hz) / theory_hz`, %.
    pub raw_error_pct: f64,
    /// Peak over the local spectral median, dB.
    pub raw_prominence_db: f64,
    pub raw_detected: bool,
    /// DTCWT level of the largest-kurtosis component.
    pub best_level: usize,
    /// Peak identified in that component's envelope spectrum, Hz.
    pub best_hz: f64,
    /// %.
    pub best_error_pct: f64,
    /// dB.
    pub best_prominence_db: f64,
    pub best_detected: bool,
    /// Envelope spectrum resolution, Hz.
    pub df_hz: f64,
    /// Cage slip against the loaded balls' pure rolling, -.
    pub cage_slip: f64,
    pub cage_state: CageState,
    /// Mean cage eccentricity over the land clearance, -.
    pub cage_eccentricity: f64,
    /// Solver wall time, s.
    pub wall_time: f64,
    pub rhs_evaluations: u64,
}

/// Why a point produced no row.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PointError {
    #[error("invalid scene: {0}")]
    Scene(#[from] ValidationErrors),
    #[error(transparent)]
    Simulation(#[from] SimError),
    #[error("analysis: {0}")]
    Analysis(#[from] AnalysisError),
    /// Stopped at the wall-time budget.
    #[error(
        "over the {budget:.0} s wall-time budget at t = {reached:.4} of {duration} s simulated"
    )]
    OverBudget {
        /// s of wall time.
        budget: f64,
        /// Simulated time reached, s.
        reached: f64,
        /// Simulated time asked for, s.
        duration: f64,
    },
}

/// Simulate the point and identify its fault line in the raw and the best-component
/// envelope spectra (default analysis options: 5 levels, 5 % search band). A run still going
/// after `budget` of wall time is stopped and reported as over budget (a cage whirling on
/// its land can hold the explicit step near 1e-8 s).
pub fn run_point(point: &StudyPoint, budget: Option<Duration>) -> Result<StudyRow, PointError> {
    let scene = point.scene().validated()?;
    let started = Instant::now();
    let stop = AtomicBool::new(false);
    let mut reached = 0.0;
    let mut watch = |fraction: f64| {
        reached = fraction;
        if budget.is_some_and(|b| started.elapsed() > b) {
            stop.store(true, Ordering::Relaxed);
        }
    };
    let result = simulate(
        &scene,
        RunControl {
            cancel: Some(&stop),
            progress: Some(&mut watch),
        },
    );
    let result = match result {
        Err(e) if e.is_cancelled() => {
            return Err(PointError::OverBudget {
                budget: budget.unwrap_or_default().as_secs_f64(),
                reached: reached * point.duration,
                duration: point.duration,
            })
        }
        r => r?,
    };
    let out = analyze_simulation(
        &result,
        scene.scene(),
        STUDY_CHANNEL,
        &AnalysisOptions::default(),
    )?;
    let freq = frequency_comparison(&result, scene.scene());
    let line = match point.fault {
        FaultCase::Inner => FaultLine::Bpfi,
        _ => FaultLine::Bpfo,
    };
    let reading = read_line(line, &freq, &out.report);
    let (raw, best) = (reading.raw, reading.best);
    let s = &result.summary;
    Ok(StudyRow {
        factor: point.factor,
        value: point.value(),
        fault: point.fault,
        lubricant: point.lubricant.name.clone(),
        rpm: point.rpm,
        axial_load: point.axial_load,
        radial_load: point.radial_load,
        line: line.name().into(),
        theory_hz: reading.theory_hz,
        loaded_theory_hz: reading.loaded_theory_hz,
        cage_hz: reading.cage_hz,
        cage_error_pct: reading.cage_error_pct,
        raw_hz: raw.hz,
        raw_error_pct: raw.error_pct,
        raw_prominence_db: raw.prominence_db,
        raw_detected: raw.detected,
        best_level: reading.best_level,
        best_hz: best.hz,
        best_error_pct: best.error_pct,
        best_prominence_db: best.prominence_db,
        best_detected: best.detected,
        df_hz: out.report.df,
        cage_slip: s.cage_slip,
        cage_state: s.cage_motion.state,
        cage_eccentricity: s.cage_motion.mean_eccentricity,
        wall_time: s.stats.wall_time,
        rhs_evaluations: s.stats.rhs_evaluations,
    })
}
