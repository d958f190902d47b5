//! Why a transform could not be made.

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
