//! Vibration analysis: characteristic frequencies, envelope spectra, DTCWT, identification.
//!
//! Plain synchronous code (no async, HTTP or SQL). The main entry point is
//! [`analysis::analyze`]; the pieces are usable on their own:
//!
//! - [`frequencies`]: BPFO, BPFI, FTF, BSF from geometry and shaft speed (eq. 37);
//! - [`hilbert`]: FFT analytic signal and envelope;
//! - [`spectrum`]: envelope spectrum (Hann window, single-sided amplitude scaling);
//! - [`dtcwt`]: Kingsbury's dual-tree complex wavelet transform and per-level components;
//! - [`kurtosis`]: Pearson kurtosis;
//! - [`kurtogram`]: spectral kurtosis over a 1/3-binary tree of bands (Antoni's kurtogram);
//! - [`identify`]: peak search, sub-bin interpolation, prominence, detection;
//! - [`verdict`]: the fault types the spectra indicate, with the evidence;
//! - [`impulsiveness`]: whether a band's signal is impulsive (a defect strikes);
//! - [`summary`]: the verdict in one plain sentence;
//! - [`order_tracking`]: analysis at varying speed, resampled to constant shaft angle;
//! - [`recording`]: measured recordings (MAT-file, WAV, CSV/TSV, raw f32, JSON) read, listed
//!   and written, and the shaft angle from a tachometer channel or a speed profile;
//! - [`shaft_angle`]: the shaft's angle per sample, for order tracking.

pub mod dtcwt;

pub use dtcwt::{Dtcwt1d, DtcwtError, Pyramid};
pub mod analysis;
pub mod frequencies;
pub mod hilbert;
pub mod identify;
pub mod impulsiveness;
pub mod kurtogram;
pub mod kurtosis;
pub mod order_tracking;
pub mod order_tracking_report;
pub mod shaft_angle;
pub mod spectrum;
pub mod summary;
pub mod verdict;

pub use analysis::{
    analyze, analyze_with, AnalysisError, AnalysisOptions, AnalysisOutput, AnalysisReport,
    ComponentReport, Identification, LevelSpectra, Sideband, Spectrum,
};
pub use frequencies::{
    characteristic_frequencies, kinematic_preset, kinematic_preset_names,
    CharacteristicFrequencies, KinematicGeometry,
};
pub use order_tracking::analyze_tracked;
pub use order_tracking_report::OrderTracking;
pub use shaft_angle::ShaftAngle;
pub mod recording;
