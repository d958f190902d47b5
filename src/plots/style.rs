//! What every chart shares with the lab page (src/api/web/plot.js: `PALETTE`, `SERIES`):
//! its colours, and its legend, drawn beside the data and never over it.

use super::error::PlotError;
use super::labels::text_width;
use plotters::coord::{CoordTranslate, Shift};
use plotters::prelude::*;

pub const INK: RGBColor = RGBColor(0x1d, 0x23, 0x29);
pub const BLUE: RGBColor = RGBColor(0x1f, 0x6f, 0xb5);
pub const RED: RGBColor = RGBColor(0xc0, 0x39, 0x2b);
pub const GREEN: RGBColor = RGBColor(0x14, 0x8f, 0x77);
pub const PURPLE: RGBColor = RGBColor(0x7d, 0x3c, 0x98);
pub const ORANGE: RGBColor = RGBColor(0xb9, 0x77, 0x0e);
pub const BROWN: RGBColor = RGBColor(0x8c, 0x56, 0x4b);
pub const GREY: RGBColor = RGBColor(0x5d, 0x6d, 0x7e);

/// Curves in drawing order (the first, the ink, is the reference: eq. 37).
pub const SERIES_COLORS: [RGBColor; 8] = [INK, BLUE, RED, GREEN, PURPLE, ORANGE, BROWN, GREY];

/// The page's grid colour: major lines only, light, under the data.
pub const GRID: RGBColor = RGBColor(0xee, 0xf1, 0xf3);

/// One colour per characteristic line, by its API name (`bpfo`, `bpfi`, `bsf`, `bsf2`,
/// `ftf`, `shaft`).
pub fn marker_color(name: &str) -> RGBColor {
    match name {
        "bpfo" => RED,
        "bpfi" => BLUE,
        "bsf" => PURPLE,
        "bsf2" => GREEN,
        "ftf" => ORANGE,
        _ => GREY,
    }
}

/// How a legend entry's key is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Key {
    Line,
    Dashed,
    Dotted,
    Dot,
    Bar,
}

/// One entry of a legend drawn under a chart.
#[derive(Debug, Clone)]
pub struct LegendEntry {
    pub text: String,
    pub color: RGBColor,
    pub key: Key,
}

const KEY_W: f64 = 22.0;
const GAP: f64 = 16.0;

/// Rows of entries that fit `width` px at `font` px.
fn rows(entries: &[LegendEntry], width: f64, font: f64) -> Vec<Vec<&LegendEntry>> {
    let mut out: Vec<Vec<&LegendEntry>> = vec![vec![]];
    let mut x = 0.0;
    for e in entries {
        let w = KEY_W + 4.0 + text_width(&e.text, font) + GAP;
        if x + w > width && !out.last().is_some_and(|r| r.is_empty()) {
            out.push(vec![]);
            x = 0.0;
        }
        if let Some(r) = out.last_mut() {
            r.push(e);
        }
        x += w;
    }
    out
}

/// Height, px, of the legend of `entries` under a chart `width` px wide.
pub fn legend_height(entries: &[LegendEntry], width: u32, font: u32) -> u32 {
    if entries.is_empty() {
        return 0;
    }
    let n = rows(entries, width as f64 - 24.0, font as f64).len() as u32;
    n * (font + 6) + 8
}

/// Draw the legend into `area` (a strip under the chart, [`legend_height`] tall).
pub fn draw_legend_below(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    entries: &[LegendEntry],
    font: u32,
) -> Result<(), PlotError> {
    let (w, _) = area.dim_in_pixel();
    let f = font as f64;
    for (r, row) in rows(entries, w as f64 - 24.0, f).iter().enumerate() {
        let y = 4 + r as i32 * (font as i32 + 6) + font as i32 / 2;
        let mut x = 12.0;
        for e in row {
            let x0 = x as i32;
            let style = e.color.stroke_width(2);
            let segments: Vec<(i32, i32)> = match e.key {
                Key::Line | Key::Bar | Key::Dot => vec![(0, KEY_W as i32)],
                Key::Dashed => (0..KEY_W as i32).step_by(7).map(|s| (s, s + 4)).collect(),
                Key::Dotted => (0..KEY_W as i32).step_by(4).map(|s| (s, s + 1)).collect(),
            };
            match e.key {
                Key::Dot => area
                    .draw(&Circle::new((x0 + 11, y), 4, e.color.stroke_width(2)))
                    .map_err(PlotError::from_display)?,
                Key::Bar => area
                    .draw(&Rectangle::new(
                        [(x0 + 4, y - 5), (x0 + 18, y + 5)],
                        e.color.filled(),
                    ))
                    .map_err(PlotError::from_display)?,
                _ => {
                    for (a, b) in segments {
                        area.draw(&PathElement::new([(x0 + a, y), (x0 + b, y)], style))
                            .map_err(PlotError::from_display)?;
                    }
                }
            }
            area.draw(&Text::new(
                e.text.clone(),
                (x0 + KEY_W as i32 + 4, y - font as i32 / 2),
                ("sans-serif", font).into_font().color(&INK),
            ))
            .map_err(PlotError::from_display)?;
            x += KEY_W + 4.0 + text_width(&e.text, f) + GAP;
        }
    }
    Ok(())
}

/// The legend of the series drawn so far, in a bordered, nearly opaque box (charts of the
/// command line's benchmarks; the service's charts put theirs under the data).
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
