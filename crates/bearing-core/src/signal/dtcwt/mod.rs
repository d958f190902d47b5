//! Kingsbury's 1-D dual-tree complex wavelet transform (DTCWT).
//!
//! Written for this crate and checked against the Python `dtcwt` 0.14 package
//! (`Transform1d`, the reference implementation) by the golden fixtures in
//! `crates/bearing-core/tests/fixtures/dtcwt/` (see `scripts/fixtures/gen_signal_fixtures.py`). Defaults: `near_sym_b`
//! at level 1, `qshift_b` for deeper levels.
//!
//! Level `k` (1-based) of a signal sampled at `fs` covers roughly `fs / 2^(k+1) .. fs / 2^k`.

mod band;
mod error;
mod filters;
mod transform;

pub use band::nominal_band;
pub use error::DtcwtError;
pub use filters::{biort, qshift, BiortFilters, QshiftFilters, BIORT_NAMES, QSHIFT_NAMES};
pub use transform::{min_length, Components, Dtcwt1d, Pyramid};
