//! Kurtosis of each DTCWT level's component as bars, the chosen (largest) one highlighted,
//! and the raw signal's kurtosis as a reference line.

use super::error::PlotError;
use super::labels::tick_label;
use super::style::{draw_legend_below, legend_height, Key, LegendEntry, BLUE, GRID, INK, RED};
use plotters::prelude::*;

/// 800 x 400 px. `levels[k]` is level `k + 1`; `best` is 1-based.
pub fn kurtosis_svg(
    title: &str,
    levels: &[f64],
    raw: f64,
    best: usize,
) -> Result<String, PlotError> {
    let top = levels
        .iter()
        .chain(std::iter::once(&raw))
        .copied()
        .filter(|v| v.is_finite())
        .fold(3.0_f64, f64::max)
        * 1.15;
    let n = levels.len().max(1);
    let (plain, chosen) = (BLUE, RED);
    let mut legend = vec![
        LegendEntry {
            text: "component kurtosis".into(),
            color: plain,
            key: Key::Bar,
        },
        LegendEntry {
            text: format!("level {best}: the largest, analysed"),
            color: chosen,
            key: Key::Bar,
        },
    ];
    if raw.is_finite() {
        legend.push(LegendEntry {
            text: format!("raw signal kurtosis ({})", tick_label(raw)),
            color: INK,
            key: Key::Line,
        });
    }
    let lh = legend_height(&legend, 800, 13);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (800, 400 + lh)).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::from_display)?;
        let (top_area, below) = root.split_vertically(400);
        let mut chart = ChartBuilder::on(&top_area)
            .caption(title, ("sans-serif", 16))
            .margin(12)
            .x_label_area_size(42)
            .y_label_area_size(60)
            .build_cartesian_2d(0.5..(n as f64 + 0.5), 0.0..top)
            .map_err(PlotError::from_display)?;
        chart
            .configure_mesh()
            .bold_line_style(GRID)
            .light_line_style(TRANSPARENT)
            .x_desc("DTCWT level (1 = highest frequencies)")
            .y_desc("kurtosis (-)")
            .x_labels(n + 1)
            .x_label_formatter(&|v| {
                if (v - v.round()).abs() < 1e-9 && *v >= 1.0 {
                    format!("{}", v.round() as i64)
                } else {
                    String::new()
                }
            })
            .y_label_formatter(&|v| tick_label(*v))
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 13).into_font().color(&INK))
            .draw()
            .map_err(PlotError::from_display)?;
        chart
            .draw_series(
                levels
                    .iter()
                    .enumerate()
                    .filter(|(_, k)| k.is_finite())
                    .map(|(i, k)| {
                        let x = (i + 1) as f64;
                        let c = if i + 1 == best { chosen } else { plain };
                        Rectangle::new([(x - 0.35, 0.0), (x + 0.35, *k)], c.filled())
                    }),
            )
            .map_err(PlotError::from_display)?;
        if raw.is_finite() {
            chart
                .draw_series(LineSeries::new(
                    [(0.5, raw), (n as f64 + 0.5, raw)],
                    INK.stroke_width(1),
                ))
                .map_err(PlotError::from_display)?;
        }
        draw_legend_below(&below, &legend, 13)?;
        root.present().map_err(PlotError::from_display)?;
    }
    Ok(svg)
}
