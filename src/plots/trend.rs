//! A fault-frequency trend as Figures 23-28 draw it: theoretical and simulated frequency on
//! the left axis, their error in % on the right axis, against one operating factor.

use super::error::PlotError;
use super::labels::tick_label;
use super::style::{draw_legend_below, legend_height, Key, LegendEntry, GRID, INK, SERIES_COLORS};
use plotters::prelude::*;

/// One curve of a trend chart.
#[derive(Debug, Clone)]
pub struct TrendSeries {
    /// Legend text.
    pub label: String,
    /// `(factor value, y)`; points with a non-finite y are left out.
    pub points: Vec<(f64, f64)>,
    /// Drawn against the right (error %) axis instead of the left (Hz) one.
    pub on_error_axis: bool,
}

fn range(values: impl Iterator<Item = f64>, include_zero: bool) -> std::ops::Range<f64> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if include_zero {
        lo = lo.min(0.0);
        hi = hi.max(0.0);
    }
    if !lo.is_finite() {
        return 0.0..1.0;
    }
    let pad = 0.08 * (hi - lo).max(1e-9 * hi.abs().max(1.0));
    (lo - pad)..(hi + pad)
}

/// Draw the chart, 800 x 500 px, and return the SVG text.
pub fn trend_svg(title: &str, x_label: &str, series: &[TrendSeries]) -> Result<String, PlotError> {
    let finite = |s: &&TrendSeries| s.points.iter().any(|p| p.1.is_finite());
    let all_x = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let x = range(all_x, false);
    let left = range(
        series
            .iter()
            .filter(|s| !s.on_error_axis)
            .flat_map(|s| s.points.iter().map(|p| p.1)),
        false,
    );
    let right = range(
        series
            .iter()
            .filter(|s| s.on_error_axis)
            .flat_map(|s| s.points.iter().map(|p| p.1)),
        true,
    );
    // the legend goes under the chart, never over its data
    let legend: Vec<LegendEntry> = series
        .iter()
        .filter(finite)
        .enumerate()
        .map(|(i, s)| LegendEntry {
            text: if s.on_error_axis {
                format!("{} (right axis)", s.label)
            } else {
                s.label.clone()
            },
            color: SERIES_COLORS[i % SERIES_COLORS.len()],
            key: Key::Line,
        })
        .collect();
    let lh = legend_height(&legend, 800, 13);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (800, 500 + lh)).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::from_display)?;
        let (top_area, below) = root.split_vertically(500);
        let mut chart = ChartBuilder::on(&top_area)
            .caption(title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .right_y_label_area_size(70)
            .build_cartesian_2d(x.clone(), left)
            .map_err(PlotError::from_display)?
            .set_secondary_coord(x, right);
        chart
            .configure_mesh()
            .bold_line_style(GRID)
            .light_line_style(TRANSPARENT)
            .x_desc(x_label)
            .y_desc("frequency (Hz)")
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 13).into_font().color(&INK))
            .draw()
            .map_err(PlotError::from_display)?;
        chart
            .configure_secondary_axes()
            .y_desc("error against eq. 37 (%)")
            .y_label_formatter(&|v| tick_label(*v))
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 13).into_font().color(&INK))
            .draw()
            .map_err(PlotError::from_display)?;
        for (i, s) in series.iter().filter(finite).enumerate() {
            let color = SERIES_COLORS[i % SERIES_COLORS.len()];
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|p| p.1.is_finite())
                .collect();
            let style = if s.on_error_axis {
                color.stroke_width(1)
            } else {
                color.stroke_width(2)
            };
            let marker = pts.clone();
            if s.on_error_axis {
                chart
                    .draw_secondary_series(LineSeries::new(pts, style))
                    .map_err(PlotError::from_display)?;
                chart
                    .draw_secondary_series(
                        marker
                            .into_iter()
                            .map(|p| TriangleMarker::new(p, 4, color.filled())),
                    )
                    .map_err(PlotError::from_display)?;
            } else {
                chart
                    .draw_series(LineSeries::new(pts, style))
                    .map_err(PlotError::from_display)?;
                chart
                    .draw_series(
                        marker
                            .into_iter()
                            .map(|p| Circle::new(p, 3, color.filled())),
                    )
                    .map_err(PlotError::from_display)?;
            }
        }
        draw_legend_below(&below, &legend, 13)?;
        root.present().map_err(PlotError::from_display)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_both_axes_and_every_series() {
        let svg = trend_svg(
            "BPFO against speed",
            "shaft speed (rpm)",
            &[
                TrendSeries {
                    label: "eq. 37".into(),
                    points: vec![(2000.0, 200.0), (12000.0, 1200.0)],
                    on_error_axis: false,
                },
                TrendSeries {
                    label: "simulated error".into(),
                    points: vec![(2000.0, -0.1), (12000.0, f64::NAN)],
                    on_error_axis: true,
                },
            ],
        )
        .unwrap();
        assert!(svg.starts_with("<svg"));
        assert!(svg.contains("frequency (Hz)") && svg.contains("error against eq. 37 (%)"));
        assert!(svg.contains("eq. 37") && svg.contains("simulated error (right axis)"));
        assert!(!svg.contains("NaN"));
    }
}
