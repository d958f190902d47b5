//! Envelope spectra with characteristic-frequency markers, BPFI's shaft sidebands and the
//! identified peaks with their error: one spectrum per chart (a simulation's), or a grid of
//! small ones (a fault-size study, as the paper's Figure 17). Drawn as the lab page draws
//! them (src/api/web/plot.js): the same colours, labels, label placement and legend.

use super::error::PlotError;
use super::labels::{line_name, marker_label, place, text_width, tick_label, TextBox};
use super::style::{draw_legend_below, legend_height, marker_color, Key, LegendEntry, GRID, INK};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// A vertical marker at a characteristic frequency, one of its harmonics, or a shaft
/// sideband of one.
#[derive(Debug, Clone)]
pub struct Marker {
    /// The line's API name: `bpfo`, `bpfi`, `bsf`, `bsf2`, `ftf` or `shaft`.
    pub name: &'static str,
    /// 1 = the fundamental.
    pub harmonic: usize,
    /// 0 for the line itself; -1 / +1 for the line minus / plus the shaft frequency.
    pub sideband: i32,
    /// Hz.
    pub hz: f64,
}

/// An identified peak: where it is and its error against theory.
#[derive(Debug, Clone)]
pub struct Peak {
    /// The line's API name (`bpfo` ...).
    pub name: &'static str,
    /// Hz.
    pub hz: f64,
    /// %.
    pub error_pct: f64,
    /// It stands above the noise (only detected peaks are labelled).
    pub detected: bool,
}

/// One envelope spectrum: bin `k` at `k * df`.
#[derive(Debug, Clone)]
pub struct SpectrumPanel {
    pub title: String,
    /// Bin spacing, Hz.
    pub df: f64,
    pub amplitude: Vec<f64>,
    pub markers: Vec<Marker>,
    pub peaks: Vec<Peak>,
    /// e.g. `envelope amplitude (m/s²)`.
    pub y_label: String,
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

/// Amplitude at `hz`: the nearest bin's.
fn amplitude_at(p: &SpectrumPanel, hz: f64) -> f64 {
    let k = (hz / p.df).round().max(1.0) as usize;
    p.amplitude.get(k).copied().unwrap_or(f64::NAN)
}

/// The legend of a spectrum's markers and peaks (plot.js: `spectrumLegend`).
pub fn spectrum_legend(p: &SpectrumPanel) -> Vec<LegendEntry> {
    let mut out: Vec<LegendEntry> = Vec::new();
    let mut seen: Vec<&str> = Vec::new();
    for m in p.markers.iter().filter(|m| m.sideband == 0) {
        if !seen.contains(&m.name) {
            seen.push(m.name);
            out.push(LegendEntry {
                text: format!(
                    "{} {} Hz and harmonics",
                    line_name(m.name),
                    tick_label(m.hz / m.harmonic as f64)
                ),
                color: marker_color(m.name),
                key: Key::Dashed,
            });
        }
    }
    if p.markers.iter().any(|m| m.sideband != 0) {
        out.push(LegendEntry {
            text: "BPFI ± shaft sidebands".into(),
            color: marker_color("bpfi"),
            key: Key::Dotted,
        });
    }
    if p.peaks.iter().any(|q| q.detected) {
        out.push(LegendEntry {
            text: "identified peak, labelled with its error against theory".into(),
            color: INK,
            key: Key::Dot,
        });
    }
    out
}

fn draw_panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    p: &SpectrumPanel,
    max_hz: f64,
    font: u32,
) -> Result<(), PlotError> {
    let pts = visible(p, max_hz);
    // headroom above the highest line for the marker labels' rows, as on the page
    let top = pts.iter().map(|q| q.1).fold(0.0_f64, f64::max).max(1e-30) * 1.3;
    let mut chart = ChartBuilder::on(area)
        .caption(&p.title, ("sans-serif", font + 2))
        .margin(8)
        .x_label_area_size(font * 3)
        .y_label_area_size(font * 5)
        .build_cartesian_2d(0.0..max_hz, 0.0..top)
        .map_err(PlotError::from_display)?;
    chart
        .configure_mesh()
        .bold_line_style(GRID)
        .light_line_style(TRANSPARENT)
        .x_desc("frequency (Hz)")
        .y_desc(&p.y_label)
        .x_labels(6)
        .y_labels(5)
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| tick_label(*v))
        .label_style(("sans-serif", font))
        .axis_desc_style(("sans-serif", font).into_font().color(&INK))
        .draw()
        .map_err(PlotError::from_display)?;
    let shown: Vec<&Marker> = p
        .markers
        .iter()
        .filter(|m| m.hz.is_finite() && m.hz > 0.0 && m.hz <= max_hz)
        .collect();
    for m in &shown {
        let color = marker_color(m.name);
        let (dash, gap) = if m.sideband == 0 { (4, 3) } else { (1, 3) };
        chart
            .draw_series(std::iter::once(DashedPathElement::new(
                [(m.hz, 0.0), (m.hz, top)],
                dash,
                gap,
                color.stroke_width(1),
            )))
            .map_err(PlotError::from_display)?;
    }
    chart
        .draw_series(LineSeries::new(pts, INK.stroke_width(1)))
        .map_err(PlotError::from_display)?;
    let peaks: Vec<(&Peak, f64)> = p
        .peaks
        .iter()
        .filter(|q| q.hz.is_finite() && q.hz <= max_hz)
        .map(|q| (q, amplitude_at(p, q.hz)))
        .filter(|(_, a)| a.is_finite())
        .collect();
    for (q, a) in &peaks {
        let c = marker_color(q.name);
        let style = if q.detected {
            c.filled()
        } else {
            c.stroke_width(1)
        };
        chart
            .draw_series(std::iter::once(Circle::new((q.hz, *a), 3, style)))
            .map_err(PlotError::from_display)?;
    }
    // labels, placed in pixels: fundamentals, then detected peaks' errors, then harmonics
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let bounds = TextBox {
        x: xr.start as f64,
        y: yr.start as f64,
        w: (xr.end - xr.start) as f64,
        h: (yr.end - yr.start) as f64,
    };
    let lf = font.saturating_sub(3).max(8) as f64;
    let h = lf + 2.0;
    let lanes: Vec<f64> = (0..4)
        .map(|k| bounds.y + 2.0 + k as f64 * (h + 1.0))
        .collect();
    struct Label {
        text: String,
        color: RGBColor,
        rank: f64,
        candidates: Vec<TextBox>,
    }
    let mut labels: Vec<Label> = Vec::new();
    for m in shown.iter().filter(|m| m.sideband == 0) {
        let text = marker_label(m.name, m.harmonic);
        let w = text_width(&text, lf);
        let x = chart.backend_coord(&(m.hz, 0.0)).0 as f64;
        let right = lanes.iter().map(|&y| TextBox {
            x: x + 2.0,
            y,
            w,
            h,
        });
        let left = lanes.iter().map(|&y| TextBox {
            x: x - 2.0 - w,
            y,
            w,
            h,
        });
        labels.push(Label {
            text,
            color: marker_color(m.name),
            rank: m.harmonic as f64,
            candidates: right.chain(left).collect(),
        });
    }
    for (q, a) in peaks.iter().filter(|(q, _)| q.detected) {
        let text = format!(
            "{}{} %",
            if q.error_pct >= 0.0 { "+" } else { "" },
            tick_label(q.error_pct)
        );
        let w = text_width(&text, lf);
        let (x, y) = chart.backend_coord(&(q.hz, *a));
        let (x, y) = (x as f64, y as f64);
        let above = [6.0, 18.0, 30.0].map(|d| TextBox {
            x: x - w / 2.0,
            y: y - d - h,
            w,
            h,
        });
        labels.push(Label {
            text,
            color: marker_color(q.name),
            rank: 1.5,
            candidates: above
                .into_iter()
                .chain([
                    TextBox {
                        x: x + 6.0,
                        y: y - h / 2.0,
                        w,
                        h,
                    },
                    TextBox {
                        x: x - 6.0 - w,
                        y: y - h / 2.0,
                        w,
                        h,
                    },
                ])
                .collect(),
        });
    }
    labels.sort_by(|a, b| a.rank.total_cmp(&b.rank));
    let cands: Vec<Vec<TextBox>> = labels.iter().map(|l| l.candidates.clone()).collect();
    for (l, spot) in labels.iter().zip(place(&cands, bounds)) {
        if let Some(b) = spot {
            area.draw(&Text::new(
                l.text.clone(),
                (b.x as i32 + 1, b.y as i32 + 1),
                ("sans-serif", lf).into_font().color(&l.color),
            ))
            .map_err(PlotError::from_display)?;
        }
    }
    Ok(())
}

/// One envelope spectrum, 800 px wide, from 0 to `max_hz`, with its markers and peaks, and
/// its legend under the chart.
pub fn spectrum_svg(panel: &SpectrumPanel, max_hz: f64) -> Result<String, PlotError> {
    let legend = spectrum_legend(panel);
    let lh = legend_height(&legend, 800, 12);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (800, 450 + lh)).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::from_display)?;
        let (chart, below) = root.split_vertically(450);
        draw_panel(&chart, panel, max_hz, 13)?;
        draw_legend_below(&below, &legend, 12)?;
        root.present().map_err(PlotError::from_display)?;
    }
    Ok(svg)
}

/// A grid of spectra, three per row, 800 px wide, each from 0 to `max_hz`, with one legend
/// (the first panel's) under the grid.
pub fn spectra_grid_svg(
    title: &str,
    panels: &[SpectrumPanel],
    max_hz: f64,
) -> Result<String, PlotError> {
    let cols = 3.min(panels.len().max(1));
    let rows = panels.len().div_ceil(cols).max(1);
    let legend = panels.first().map(spectrum_legend).unwrap_or_default();
    let lh = legend_height(&legend, 800, 12);
    let grid_h = 40 + 230 * rows as u32;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (800, grid_h + lh)).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::from_display)?;
        let (grid, below) = root.split_vertically(grid_h);
        let grid = grid
            .titled(title, ("sans-serif", 18))
            .map_err(PlotError::from_display)?;
        let areas = grid.split_evenly((rows, cols));
        for (area, p) in areas.iter().zip(panels) {
            draw_panel(area, p, max_hz, 10)?;
        }
        draw_legend_below(&below, &legend, 12)?;
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
            markers: [1, 2]
                .map(|h| Marker {
                    name: "bpfo",
                    harmonic: h,
                    sideband: 0,
                    hz: 200.0 * h as f64,
                })
                .to_vec(),
            peaks: vec![Peak {
                name: "bpfo",
                hz: 200.0,
                error_pct: 0.25,
                detected: true,
            }],
            y_label: "envelope amplitude (m/s²)".into(),
        }
    }

    #[test]
    fn single_and_grid_charts_carry_their_titles_markers_and_legend() {
        let svg = spectrum_svg(&panel("raw envelope spectrum"), 600.0).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("raw envelope spectrum"));
        assert!(svg.contains("BPFO×2") && svg.contains("frequency (Hz)"));
        assert!(svg.contains("+0.25 %") && svg.contains("BPFO 200 Hz and harmonics"));
        // the page's BPFO red
        assert!(svg.contains("#C0392B"));
        let grid =
            spectra_grid_svg("Table 2", &[panel("group 1"), panel("group 2")], 600.0).unwrap();
        assert!(grid.contains("group 1") && grid.contains("group 2") && grid.contains("Table 2"));
    }
}
