//! Kingsbury's 1-D dual-tree complex wavelet transform (DTCWT).
//!
//! Written for this crate and checked against the Python `dtcwt` 0.14 package
//! (`Transform1d`, the reference implementation) by the golden fixtures in
//! `tests/fixtures/dtcwt/` (see `scripts/gen_signal_fixtures.py`). Defaults: `near_sym_b`
//! at level 1, `qshift_b` for deeper levels.
//!
//! Level `k` (1-based) of a signal sampled at `fs` covers roughly `fs / 2^(k+1) .. fs / 2^k`.

mod filters;
mod transform;

pub use filters::{biort, qshift, BiortFilters, QshiftFilters, BIORT_NAMES, QSHIFT_NAMES};
pub use transform::{min_length, Components, Dtcwt1d, Pyramid};

/// Why a transform could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DtcwtError {
    #[error("{field}: unknown filter set '{name}' (expected one of {})", expected.join(", "))]
    UnknownFilter {
        field: &'static str,
        name: String,
        expected: &'static [&'static str],
    },
    #[error("levels: must be >= 1 (got {levels})")]
    Levels { levels: usize },
    #[error("samples: {n} samples is too short for {levels} levels (need >= {need})")]
    TooShort {
        n: usize,
        levels: usize,
        need: usize,
    },
}

/// Nominal pass band of level `level` (1-based) for sample rate `fs`, Hz: `[fs/2^(k+1), fs/2^k]`.
pub fn nominal_band(level: usize, fs: f64) -> [f64; 2] {
    let hi = fs / 2f64.powi(level as i32);
    [hi / 2.0, hi]
}
