//! A study's plots: a trend chart per factor line and fault case (Figures 23-28), and a
//! grid of the points' envelope spectra (Figure 17).

use crate::plots::{spectra_grid_svg, trend_svg, Marker, PlotError, SpectrumPanel, TrendSeries};
use bearing_core::scene::FaultCase;
use bearing_core::study::{DesignSummary, FaultLine, PointResult, StudyTableRow};

/// An envelope spectrum of one point: bin `k` at `k * df`.
#[derive(Debug, Clone)]
pub struct PointSpectrum {
    /// Hz.
    pub df: f64,
    pub amplitude: Vec<f64>,
    /// DTCWT level it belongs to (0 = the raw signal's).
    pub level: usize,
}

/// File name of the spectra grid.
pub const SPECTRA_PLOT: &str = "spectra.svg";

fn case_name(c: Option<FaultCase>) -> &'static str {
    match c {
        None => "base",
        Some(FaultCase::None) => "none",
        Some(FaultCase::Inner) => "inner",
        Some(FaultCase::Outer) => "outer",
        Some(FaultCase::Compound) => "compound",
    }
}

/// The trend plots a study has: `{factor}-{fault case}.svg` for each factor line (designs
/// with lines), then the spectra grid. Read from the points' line and fault case only, so
/// listing them needs no run's result.
pub fn plot_names<'a>(
    design: &DesignSummary,
    points: impl IntoIterator<Item = (Option<&'a str>, Option<FaultCase>)>,
) -> Vec<String> {
    let points: Vec<_> = points.into_iter().collect();
    let mut names = Vec::new();
    if design.lines {
        for f in &design.factors {
            for (_, case) in points.iter().filter(|(line, _)| *line == Some(&f.name)) {
                let n = format!("{}-{}.svg", f.name, case_name(*case));
                if !names.contains(&n) {
                    names.push(n);
                }
            }
        }
    }
    names.push(SPECTRA_PLOT.into());
    names
}

/// Line and fault case of each row, for [`plot_names`].
pub fn row_keys(rows: &[StudyTableRow]) -> impl Iterator<Item = (Option<&str>, Option<FaultCase>)> {
    rows.iter().map(|r| (r.line.as_deref(), r.fault_case))
}

/// Draw one of [`plot_names`]; `None` if the study has no such plot. `spectrum(i)` gives
/// point `i`'s best-component envelope spectrum.
pub fn draw(
    title: &str,
    design: &DesignSummary,
    rows: &[StudyTableRow],
    name: &str,
    spectrum: &mut dyn FnMut(&StudyTableRow) -> Option<PointSpectrum>,
) -> Option<Result<String, PlotError>> {
    if !plot_names(design, row_keys(rows)).iter().any(|n| n == name) {
        return None;
    }
    if name == SPECTRA_PLOT {
        return Some(spectra_grid(title, design, rows, spectrum));
    }
    let stem = name.strip_suffix(".svg")?;
    let (factor, case) = design.factors.iter().find_map(|f| {
        let case = stem.strip_prefix(&f.name)?.strip_prefix('-')?;
        Some((f, case))
    })?;
    let sel: Vec<&StudyTableRow> = rows
        .iter()
        .filter(|r| r.line.as_deref() == Some(&factor.name) && case_name(r.fault_case) == case)
        .collect();
    Some(trend(title, &factor.name, &factor.label, case, &sel))
}

fn trend(
    title: &str,
    factor: &str,
    x_label: &str,
    case: &str,
    rows: &[&StudyTableRow],
) -> Result<String, PlotError> {
    let mut rows: Vec<&StudyTableRow> = rows.to_vec();
    let x = |r: &StudyTableRow| {
        r.factors
            .iter()
            .find(|v| v.name == factor)
            .map(|v| v.value)
            .unwrap_or(f64::NAN)
    };
    rows.sort_by(|a, b| x(a).total_cmp(&x(b)));
    let fault = rows.first().and_then(|r| r.fault_case);
    let mut series = Vec::new();
    for &line in PointResult::lines_for(fault) {
        let s = |label: String, on_error_axis, f: &dyn Fn(&PointResult) -> f64| TrendSeries {
            label,
            points: rows
                .iter()
                .map(|r| (x(r), r.result.as_ref().map(f).unwrap_or(f64::NAN)))
                .collect(),
            on_error_axis,
        };
        let n = line.name();
        let get = move |p: &PointResult| *p.line(line);
        series.push(s(format!("{n}, eq. 37 (nominal angle)"), false, &|p| {
            get(p).theory_hz
        }));
        series.push(s(format!("{n}, raw envelope spectrum"), false, &|p| {
            get(p).raw.hz
        }));
        series.push(s(format!("{n}, best DTCWT component"), false, &|p| {
            get(p).best.hz
        }));
        series.push(s(format!("{n} error, raw spectrum"), true, &|p| {
            get(p).raw.error_pct
        }));
        series.push(s(format!("{n} error, from the cage speed"), true, &|p| {
            get(p).cage_error_pct
        }));
    }
    trend_svg(
        &format!("{title}: {factor} ({case} fault)"),
        x_label,
        &series,
    )
}

fn spectra_grid(
    title: &str,
    design: &DesignSummary,
    rows: &[StudyTableRow],
    spectrum: &mut dyn FnMut(&StudyTableRow) -> Option<PointSpectrum>,
) -> Result<String, PlotError> {
    let mut panels = Vec::new();
    let mut max_hz: f64 = 0.0;
    for r in rows {
        let (Some(p), Some(s)) = (&r.result, spectrum(r)) else {
            continue;
        };
        let mut markers = Vec::new();
        for (name, line) in [("bpfo", FaultLine::Bpfo), ("bpfi", FaultLine::Bpfi)] {
            let f = p.line(line).theory_hz;
            max_hz = max_hz.max(2.3 * f);
            for h in 1..=2 {
                markers.push(Marker {
                    name,
                    harmonic: h,
                    sideband: 0,
                    hz: h as f64 * f,
                });
            }
        }
        // a label, else the factor values while they fit a panel's title, else the index
        let mut t = match &r.label {
            Some(l) => l.clone(),
            None if design.factors.len() <= 2 => r
                .factors
                .iter()
                .map(|v| format!("{}={}", v.name, short(v.value)))
                .collect::<Vec<_>>()
                .join(", "),
            None => format!("point {}", r.index),
        };
        if let Some(c) = r.fault_case {
            t.push_str(&format!(" ({})", case_name(Some(c))));
        }
        let level = if s.level == 0 {
            "raw".to_string()
        } else {
            format!("level {}", s.level)
        };
        panels.push(SpectrumPanel {
            title: format!("{t}, {level}"),
            df: s.df,
            amplitude: s.amplitude,
            markers,
            peaks: vec![],
            y_label: "envelope amplitude (m/s²)".into(),
        });
    }
    if panels.is_empty() {
        return Err(PlotError(
            "no point has succeeded yet: the spectra grid has nothing to draw".into(),
        ));
    }
    // the grid's title shares one line with its subject at 800 px
    let short_title = if title.chars().count() > 48 {
        format!("{}...", title.chars().take(45).collect::<String>())
    } else {
        title.to_string()
    };
    spectra_grid_svg(
        &format!("{short_title}: best-component envelope spectra"),
        &panels,
        max_hz,
    )
}

fn short(v: f64) -> String {
    if v != 0.0 && v.abs() < 0.01 {
        format!("{:.2}e-3", v * 1e3)
    } else {
        format!("{v}")
    }
}
