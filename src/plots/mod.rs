//! SVG charts of engine results, drawn with plotters' SVG backend (no hand-written paths).

pub mod error;
pub mod trend;

pub use error::PlotError;
pub use trend::{trend_svg, TrendSeries};
