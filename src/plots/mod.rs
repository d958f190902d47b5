//! SVG charts of engine results, drawn with plotters' SVG backend (no hand-written paths).

pub mod error;
pub mod kurtosis;
pub mod labels;
pub mod signal;
pub mod spectrum;
pub mod style;
pub mod trend;
pub mod work_precision;

pub use error::PlotError;
pub use kurtosis::kurtosis_svg;
pub use signal::{signal_svg, SignalTrace};
pub use spectrum::{spectra_grid_svg, spectrum_svg, Marker, Peak, SpectrumPanel};
pub use trend::{trend_svg, TrendSeries};
pub use work_precision::{work_precision_svg, WorkPrecisionSeries};
