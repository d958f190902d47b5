//! Envelope spectra with characteristic-frequency markers: one spectrum per chart (a
//! simulation's), or a grid of small ones (a fault-size study, as the paper's Figure 17).

use super::error::PlotError;
use super::style::{draw_legend, MARKER_COLORS};
use plotters::coord::Shift;
use plotters::prelude::*;

/// A vertical marker at a characteristic frequency (or one of its harmonics).
#[derive(Debug, Clone)]
pub struct Marker {
    /// e.g. `BPFO`, `2xBPFI`.
    pub label: String,
    /// Hz.
    pub hz: f64,
    /// Index into the marker palette: one colour per characteristic line.
    pub family: usize,
}

/// One envelope spectrum: bin `k` at `k * df`.
#[derive(Debug, Clone)]
pub struct SpectrumPanel {
    pub title: String,
    /// Bin spacing, Hz.
    pub df: f64,
    pub amplitude: Vec<f64>,
    pub markers: Vec<Marker>,
}

/// Bins from 0 to `max_hz` (the DC bin left out: the envelope's mean dwarfs the lines).
fn visible(p: &SpectrumPanel, max_hz: f64) -> Vec<(f64, f64)> {
    p.amplitude
        .iter()
        .enumerate()
        .skip(1)
        .map(|(k, a)| (k as f64 * p.df, *a))
        .take_while(|(f, _)| *f <= max_hz)
        .filter(|(_, a)| a.is_finite())
        .collect()
}

fn draw_panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    p: &SpectrumPanel,
    max_hz: f64,
    font: u32,
    legend: bool,
) -> Result<(), PlotError> {
    let pts = visible(p, max_hz);
    let top = pts.iter().map(|q| q.1).fold(0.0_f64, f64::max).max(1e-30) * 1.12;
    let mut chart = ChartBuilder::on(area)
        .caption(&p.title, ("sans-serif", font + 2))
        .margin(8)
        .x_label_area_size(font * 3)
        .y_label_area_size(font * 5)
        .build_cartesian_2d(0.0..max_hz, 0.0..top)
        .map_err(PlotError::from_display)?;
    chart
        .configure_mesh()
        .x_desc("frequency (Hz)")
        .y_desc("envelope amplitude (m/s^2)")
        .x_labels(6)
        .y_labels(5)
        .y_label_formatter(&|v| format!("{v:.2e}"))
        .label_style(("sans-serif", font))
        .draw()
        .map_err(PlotError::from_display)?;
    chart
        .draw_series(LineSeries::new(pts, BLACK.stroke_width(1)))
        .map_err(PlotError::from_display)?;
    let mut labelled = Vec::new();
    for m in p
        .markers
        .iter()
        .filter(|m| m.hz.is_finite() && m.hz <= max_hz)
    {
        let color = MARKER_COLORS[m.family % MARKER_COLORS.len()];
        let style = color.mix(0.8).stroke_width(1);
        let series = chart
            .draw_series(std::iter::once(PathElement::new(
                [(m.hz, 0.0), (m.hz, top)],
                style,
            )))
            .map_err(PlotError::from_display)?;
        // one legend entry per characteristic line (the fundamental's label)
        if legend && !labelled.contains(&m.family) {
            labelled.push(m.family);
            series
                .label(m.label.clone())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], style));
        }
        chart
            .draw_series(std::iter::once(Text::new(
                m.label.clone(),
                (m.hz, top * 0.97),
                ("sans-serif", font.saturating_sub(2).max(8))
                    .into_font()
                    .color(&color),
            )))
            .map_err(PlotError::from_display)?;
    }
    if legend && !labelled.is_empty() {
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight, font)?;
    }
    Ok(())
}

/// One envelope spectrum, 800 x 450 px, from 0 to `max_hz`, with its markers and a legend.
pub fn spectrum_svg(panel: &SpectrumPanel, max_hz: f64) -> Result<String, PlotError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (800, 450)).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::from_display)?;
        draw_panel(&root, panel, max_hz, 13, true)?;
        root.present().map_err(PlotError::from_display)?;
    }
    Ok(svg)
}

/// A grid of spectra, three per row, 800 px wide, each from 0 to `max_hz`.
pub fn spectra_grid_svg(
    title: &str,
    panels: &[SpectrumPanel],
    max_hz: f64,
) -> Result<String, PlotError> {
    let cols = 3.min(panels.len().max(1));
    let rows = panels.len().div_ceil(cols).max(1);
    let height = 40 + 230 * rows as u32;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (800, height)).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::from_display)?;
        let root = root
            .titled(title, ("sans-serif", 18))
            .map_err(PlotError::from_display)?;
        let areas = root.split_evenly((rows, cols));
        for (area, p) in areas.iter().zip(panels) {
            draw_panel(area, p, max_hz, 10, false)?;
        }
        root.present().map_err(PlotError::from_display)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn panel(title: &str) -> SpectrumPanel {
        SpectrumPanel {
            title: title.into(),
            df: 2.0,
            amplitude: (0..500).map(|k| if k == 100 { 5.0 } else { 0.1 }).collect(),
            markers: vec![
                Marker {
                    label: "BPFO".into(),
                    hz: 200.0,
                    family: 0,
                },
                Marker {
                    label: "2xBPFO".into(),
                    hz: 400.0,
                    family: 0,
                },
            ],
        }
    }

    #[test]
    fn single_and_grid_charts_carry_their_titles_and_markers() {
        let svg = spectrum_svg(&panel("raw envelope spectrum"), 600.0).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("raw envelope spectrum"));
        assert!(svg.contains("2xBPFO") && svg.contains("frequency (Hz)"));
        let grid =
            spectra_grid_svg("Table 2", &[panel("group 1"), panel("group 2")], 600.0).unwrap();
        assert!(grid.contains("group 1") && grid.contains("group 2") && grid.contains("Table 2"));
    }
}
