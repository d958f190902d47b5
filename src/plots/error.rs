//! Why a chart could not be drawn.

/// A chart could not be drawn (plotters reports drawing-area errors as text).
#[derive(Debug, thiserror::Error)]
#[error("plot: {0}")]
pub struct PlotError(pub String);

impl PlotError {
    pub(crate) fn from_display(e: impl std::fmt::Display) -> Self {
        PlotError(e.to_string())
    }
}
