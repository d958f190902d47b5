//! What every chart shares: its colours and its legend box.

use super::error::PlotError;
use plotters::coord::CoordTranslate;
use plotters::prelude::*;

pub const INK: RGBColor = RGBColor(0, 0, 0);
pub const BLUE: RGBColor = RGBColor(31, 119, 180);
pub const RED: RGBColor = RGBColor(214, 39, 40);
pub const GREEN: RGBColor = RGBColor(44, 160, 44);
pub const PURPLE: RGBColor = RGBColor(148, 103, 189);
pub const ORANGE: RGBColor = RGBColor(255, 127, 14);
pub const BROWN: RGBColor = RGBColor(140, 86, 75);
pub const TEAL: RGBColor = RGBColor(23, 190, 207);

/// Curves in drawing order (the first, black, is the reference: eq. 37).
pub const SERIES_COLORS: [RGBColor; 8] = [INK, BLUE, RED, GREEN, PURPLE, ORANGE, BROWN, TEAL];
/// Characteristic-frequency markers: BPFO red, BPFI blue, then BSF, 2xBSF, FTF.
pub const MARKER_COLORS: [RGBColor; 5] = [RED, BLUE, GREEN, PURPLE, ORANGE];

/// The legend of the series drawn so far, in a bordered, nearly opaque box.
pub fn draw_legend<'a, 'b: 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, CT>,
    position: SeriesLabelPosition,
    font: u32,
) -> Result<(), PlotError> {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", font))
        .draw()
        .map_err(PlotError::from_display)
}
