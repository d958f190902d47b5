//! Run time against error (`bearing-sim bench work-precision --svg`): one panel per error
//! measure, log error against log run time, one curve per method and fidelity level.

use super::error::PlotError;
use super::style::{draw_legend, SERIES_COLORS};
use plotters::prelude::*;

/// One method (or method at a fidelity level): its runs at several tolerances.
#[derive(Debug, Clone)]
pub struct WorkPrecisionSeries {
    /// Legend text, e.g. `rk4_fsal` or `rk4_fsal, quasi_static_balls`.
    pub label: String,
    /// `(run time s, [error of each panel])` per tolerance; errors are relative, and a
    /// point whose error is zero or not finite is left out of that panel.
    pub points: Vec<(f64, Vec<f64>)>,
}

/// Bounds of the positive finite values, widened by a quarter decade each way.
fn log_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && *v > 0.0) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return 1e-9..1.0;
    }
    let pad = 10f64.powf(0.25);
    (lo / pad)..(hi * pad)
}

/// Draw one panel per name in `panels` (two per row, 520 x 460 px each) and return the
/// SVG text.
pub fn work_precision_svg(
    title: &str,
    panels: &[&str],
    series: &[WorkPrecisionSeries],
) -> Result<String, PlotError> {
    let cols = panels.len().clamp(1, 2);
    let rows = panels.len().div_ceil(2).max(1);
    let mut svg = String::new();
    {
        let size = (520 * cols as u32, 460 * rows as u32 + 40);
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::from_display)?;
        let root = root
            .titled(title, ("sans-serif", 18))
            .map_err(PlotError::from_display)?;
        let areas = root.split_evenly((rows, cols));
        let x = log_range(series.iter().flat_map(|s| s.points.iter().map(|p| p.0)));
        for (k, (area, name)) in areas.iter().zip(panels).enumerate() {
            let y = log_range(
                series
                    .iter()
                    .flat_map(|s| s.points.iter().map(move |p| p.1[k])),
            );
            let mut chart = ChartBuilder::on(area)
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(70)
                .build_cartesian_2d(x.clone().log_scale(), y.log_scale())
                .map_err(PlotError::from_display)?;
            chart
                .configure_mesh()
                .x_desc("run time (s)")
                .y_desc(format!("{name} error (relative)"))
                .label_style(("sans-serif", 13))
                .draw()
                .map_err(PlotError::from_display)?;
            for (i, s) in series.iter().enumerate() {
                let color = SERIES_COLORS[i % SERIES_COLORS.len()];
                let pts: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .map(|p| (p.0, p.1[k]))
                    .filter(|p| p.0 > 0.0 && p.1.is_finite() && p.1 > 0.0)
                    .collect();
                if pts.is_empty() {
                    continue;
                }
                // a dashed look for reduced levels would need a newer plotters; thinner
                // lines tell them apart instead
                let style = if s.label.contains(',') {
                    color.stroke_width(1)
                } else {
                    color.stroke_width(2)
                };
                chart
                    .draw_series(LineSeries::new(pts.clone(), style))
                    .map_err(PlotError::from_display)?
                    .label(s.label.clone())
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], style));
                chart
                    .draw_series(pts.into_iter().map(|p| Circle::new(p, 3, color.filled())))
                    .map_err(PlotError::from_display)?;
            }
            draw_legend(&mut chart, SeriesLabelPosition::UpperRight, 12)?;
        }
        root.present().map_err(PlotError::from_display)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_every_series_and_skips_zero_errors() {
        let series = vec![
            WorkPrecisionSeries {
                label: "rk4_fsal".into(),
                points: vec![(1.0, vec![1e-6, 1e-3]), (2.0, vec![0.0, 5e-4])],
            },
            WorkPrecisionSeries {
                label: "rk4_fsal, concentric_cage".into(),
                points: vec![(0.5, vec![3e-4, 1e-1])],
            },
        ];
        let svg = work_precision_svg("t", &["cage speed", "band RMS"], &series).unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..40]);
        assert!(svg.contains("rk4_fsal, concentric_cage"));
        assert!(svg.contains("band RMS error"));
        // 5 of the 6 points have a non-zero error: one circle each
        assert_eq!(svg.matches("<circle").count(), 5, "{svg}");
    }
}
