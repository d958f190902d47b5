//! A time signal, drawn as its minimum and maximum per pixel column so impulses survive
//! any decimation.

use super::error::PlotError;
use super::labels::tick_label;
use super::style::{BLUE, GRID, INK};
use plotters::prelude::*;

/// Samples `x[k]` at `start_time + k / sample_rate`.
#[derive(Debug, Clone)]
pub struct SignalTrace<'a> {
    pub title: String,
    /// e.g. `outer_ring_accel_z (m/s^2)`.
    pub y_label: String,
    /// s.
    pub start_time: f64,
    /// Hz.
    pub sample_rate: f64,
    pub samples: &'a [f64],
}

/// 800 x 400 px; time axis in seconds.
pub fn signal_svg(trace: &SignalTrace<'_>) -> Result<String, PlotError> {
    let n = trace.samples.len();
    let columns = 1600usize;
    let per = n.div_ceil(columns).max(1);
    let mut pts = Vec::with_capacity(2 * n.div_ceil(per));
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (c, chunk) in trace.samples.chunks(per).enumerate() {
        let t = trace.start_time + (c * per) as f64 / trace.sample_rate;
        let mn = chunk.iter().copied().fold(f64::INFINITY, f64::min);
        let mx = chunk.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if mn.is_finite() && mx.is_finite() {
            pts.push((t, mn));
            pts.push((t, mx));
            lo = lo.min(mn);
            hi = hi.max(mx);
        }
    }
    if pts.is_empty() {
        return Err(PlotError("no finite samples to draw".into()));
    }
    let pad = 0.05 * (hi - lo).max(1e-12);
    let t0 = trace.start_time;
    let t1 = t0 + (n.max(2) - 1) as f64 / trace.sample_rate;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (800, 400)).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::from_display)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&trace.title, ("sans-serif", 16))
            .margin(12)
            .x_label_area_size(42)
            .y_label_area_size(80)
            .build_cartesian_2d(t0..t1, (lo - pad)..(hi + pad))
            .map_err(PlotError::from_display)?;
        chart
            .configure_mesh()
            .bold_line_style(GRID)
            .light_line_style(TRANSPARENT)
            .x_desc("time (s)")
            .y_desc(&trace.y_label)
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 13).into_font().color(&INK))
            .draw()
            .map_err(PlotError::from_display)?;
        chart
            .draw_series(LineSeries::new(pts, BLUE.stroke_width(1)))
            .map_err(PlotError::from_display)?;
        root.present().map_err(PlotError::from_display)?;
    }
    Ok(svg)
}
