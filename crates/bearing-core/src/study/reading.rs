//! One characteristic line (BPFO or BPFI) read from a run the way the paper reads it: its
//! eq. 37 value, the pure-rolling and cage-speed values, and the peak identified in the raw
//! and in the best DTCWT component's envelope spectra.

use crate::signal::analysis::AnalysisReport;
use crate::signal::identify::Identification;
use crate::simulation_analysis::FrequencyComparison;
use serde::{Deserialize, Serialize};

/// The two fault lines a study reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub enum FaultLine {
    /// Ball pass frequency, outer race.
    #[serde(rename = "BPFO")]
    Bpfo,
    /// Ball pass frequency, inner race.
    #[serde(rename = "BPFI")]
    Bpfi,
}

impl FaultLine {
    /// The name the analysis gives the line (`BPFO`, `BPFI`).
    pub fn name(self) -> &'static str {
        match self {
            FaultLine::Bpfo => "BPFO",
            FaultLine::Bpfi => "BPFI",
        }
    }
}

/// The fundamental's peak in one envelope spectrum (NaN and not detected when none).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct PeakReading {
    /// Identified frequency, Hz.
    #[serde(deserialize_with = "crate::json_float::f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub hz: f64,
    /// `(hz - theory) / theory` against eq. 37 at the nominal angle, %.
    #[serde(deserialize_with = "crate::json_float::f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub error_pct: f64,
    /// Peak over the local spectral median, dB.
    #[serde(deserialize_with = "crate::json_float::f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub prominence_db: f64,
    /// The analysis' detection flag (prominence, local maximum, no nearer line).
    pub detected: bool,
}

impl PeakReading {
    fn of(ids: &[Identification], line: FaultLine, theory_hz: f64) -> PeakReading {
        match ids
            .iter()
            .find(|i| i.name == line.name() && i.harmonic == 1)
        {
            Some(i) => PeakReading {
                hz: i.identified_hz,
                error_pct: 100.0 * (i.identified_hz - theory_hz) / theory_hz,
                prominence_db: i.prominence_db,
                detected: i.detected,
            },
            None => PeakReading {
                hz: f64::NAN,
                error_pct: f64::NAN,
                prominence_db: f64::NAN,
                detected: false,
            },
        }
    }
}

/// One line of one run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct LineReading {
    pub line: FaultLine,
    /// Eq. 37 at the nominal contact angle and the run's mean shaft speed, Hz.
    pub theory_hz: f64,
    /// The same at the loaded balls' contact angles (the actual angle), Hz.
    #[serde(deserialize_with = "crate::json_float::f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub loaded_theory_hz: f64,
    /// From the run's mean cage speed (`Z f_c` or `Z (f_s - f_c)`), Hz.
    #[serde(deserialize_with = "crate::json_float::f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub cage_hz: f64,
    /// `(cage_hz - theory_hz) / theory_hz`, %.
    #[serde(deserialize_with = "crate::json_float::f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub cage_error_pct: f64,
    /// In the raw envelope spectrum.
    pub raw: PeakReading,
    /// In the envelope spectrum of the largest-kurtosis DTCWT component.
    pub best: PeakReading,
    /// DTCWT level of that component.
    pub best_level: usize,
}

/// Read `line` from a run's frequency comparison and its envelope analysis.
pub fn read_line(
    line: FaultLine,
    freq: &FrequencyComparison,
    report: &AnalysisReport,
) -> LineReading {
    let (theory_hz, loaded_theory_hz, cage_hz) = match line {
        FaultLine::Bpfo => (freq.nominal.bpfo, freq.loaded.bpfo, freq.simulated.bpfo),
        FaultLine::Bpfi => (freq.nominal.bpfi, freq.loaded.bpfi, freq.simulated.bpfi),
    };
    LineReading {
        line,
        theory_hz,
        loaded_theory_hz,
        cage_hz,
        cage_error_pct: 100.0 * (cage_hz - theory_hz) / theory_hz,
        raw: PeakReading::of(&report.raw, line, theory_hz),
        best: PeakReading::of(&report.best_component.identifications, line, theory_hz),
        best_level: report.best_component.level,
    }
}
