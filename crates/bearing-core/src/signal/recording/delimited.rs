//! Columns of numbers separated by commas (CSV) or tabs (TSV), with or without a header
//! line. A header names the columns (`accel [g]` or `accel (g)` gives the unit); a column
//! named `time`, `t`, `time_s` or `t_s` (unit s, or ms) is the time axis: it gives the
//! sample rate and is not a channel. Every row must have as many fields as the first.

use super::contents::{
    check_channel_count, check_sample_count, stated, Channel, ReadResult, Recording,
    RecordingFormat, RecordingLimits, Stated,
};

const TIME_NAMES: &[&str] = &["time", "t", "time_s", "t_s", "time_ms", "t_ms"];

/// A header field split into its name and unit: `accel [g]` -> (`accel`, `g`).
fn name_and_unit(field: &str) -> (String, Option<String>) {
    let f = field.trim().trim_matches('"').trim();
    for (open, close) in [('[', ']'), ('(', ')')] {
        if let (Some(a), true) = (f.rfind(open), f.ends_with(close)) {
            let unit = f[a + 1..f.len() - 1].trim();
            if !unit.is_empty() && a > 0 {
                return (f[..a].trim().to_string(), Some(unit.to_string()));
            }
        }
    }
    (f.to_string(), None)
}

/// Seconds per unit of a time column, or `None` when the column is not one.
fn time_scale(name: &str, unit: Option<&str>) -> Option<f64> {
    let lower = name.to_ascii_lowercase();
    if !TIME_NAMES.contains(&lower.as_str()) {
        return None;
    }
    match (
        unit.map(str::to_ascii_lowercase).as_deref(),
        lower.ends_with("_ms"),
    ) {
        (Some("ms"), _) | (None, true) => Some(1e-3),
        (Some("s") | None, _) => Some(1.0),
        _ => None,
    }
}

/// The sample rate a time column implies; an error when it is not evenly spaced (no
/// sample more than half a period off the least-squares line).
fn rate_from_time(t: &[f64], name: &str) -> ReadResult<f64> {
    let n = t.len();
    if n < 2 || t[n - 1] <= t[0] {
        return Err((
            "sample_rate",
            format!("time column '{name}' does not increase"),
        ));
    }
    // the least-squares period: rounding in the printed times averages out
    let (k_mean, t_mean) = ((n - 1) as f64 / 2.0, t.iter().sum::<f64>() / n as f64);
    let (mut num, mut den) = (0.0, 0.0);
    for (k, tk) in t.iter().enumerate() {
        num += (k as f64 - k_mean) * (tk - t_mean);
        den += (k as f64 - k_mean).powi(2);
    }
    let dt = num / den;
    let t0 = t_mean - dt * k_mean;
    if let Some(k) = (0..n).find(|&k| (t[k] - (t0 + k as f64 * dt)).abs() > 0.5 * dt) {
        return Err((
            "sample_rate",
            format!(
                "time column '{name}' is not evenly spaced: row {} is at {} s, {} s expected from a period of {dt} s",
                k + 1,
                t[k],
                t0 + k as f64 * dt
            ),
        ));
    }
    Ok(1.0 / dt)
}

/// A number as written to CSV: the shortest text that reads back as the same f64.
pub(super) fn format_number(x: f64) -> String {
    format!("{x:?}")
}

pub(super) fn read(bytes: &[u8], sep: u8, limits: &RecordingLimits) -> ReadResult<Recording> {
    let text = std::str::from_utf8(bytes).map_err(|e| ("file", format!("not UTF-8 text: {e}")))?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let sep = sep as char;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let Some((_, first)) = lines.clone().next() else {
        return Err(("file", "holds no rows".into()));
    };
    let first_fields: Vec<&str> = first.split(sep).collect();
    let width = first_fields.len();
    check_channel_count(width, limits)?;
    let header = first_fields
        .iter()
        .any(|f| f.trim().parse::<f64>().is_err());
    let names: Vec<(String, Option<String>)> = if header {
        lines.next();
        first_fields.iter().map(|f| name_and_unit(f)).collect()
    } else {
        (0..width).map(|k| (format!("col{k}"), None)).collect()
    };
    let mut columns: Vec<Vec<f64>> = vec![Vec::new(); width];
    for (i, line) in lines {
        let fields: Vec<&str> = line.split(sep).collect();
        if fields.len() != width {
            return Err((
                "file",
                format!(
                    "line {}: {} fields, the {} has {width}",
                    i + 1,
                    fields.len(),
                    if header { "header" } else { "first row" }
                ),
            ));
        }
        check_sample_count(columns[0].len() + 1, limits)?;
        for (k, f) in fields.iter().enumerate() {
            let x = f.trim().parse::<f64>().map_err(|_| {
                // a lone column needs no name to be found
                let column = if width > 1 {
                    format!(", column '{}'", names[k].0)
                } else {
                    String::new()
                };
                (
                    "file",
                    format!("line {}{column}: '{}' is not a number", i + 1, f.trim()),
                )
            })?;
            columns[k].push(x);
        }
    }
    let mut sample_rate: Option<Stated> = None;
    let mut channels = Vec::new();
    for ((name, unit), values) in names.into_iter().zip(columns) {
        match time_scale(&name, unit.as_deref()) {
            Some(scale) if sample_rate.is_none() => {
                let t: Vec<f64> = values.iter().map(|v| v * scale).collect();
                let rate = rate_from_time(&t, &name)?;
                sample_rate = Some(stated(rate, format!("time column '{name}'")));
            }
            _ => channels.push(Channel {
                name,
                unit,
                samples: values,
            }),
        }
    }
    Ok(Recording {
        format: if sep == '\t' {
            RecordingFormat::Tsv
        } else {
            RecordingFormat::Csv
        },
        channels,
        sample_rate,
        shaft_rpm: None,
        skipped: vec![],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csv(s: &str) -> ReadResult<Recording> {
        read(s.as_bytes(), b',', &RecordingLimits::LOCAL)
    }

    #[test]
    fn header_time_column_and_units() {
        let r = csv("time [s],accel [g]\n0,0.5\n0.001,-1e-3\n0.002,2\n").unwrap();
        assert_eq!(r.channels.len(), 1);
        assert_eq!(r.channels[0].name, "accel");
        assert_eq!(r.channels[0].unit.as_deref(), Some("g"));
        assert_eq!(r.channels[0].samples, vec![0.5, -1e-3, 2.0]);
        assert!((r.sample_rate.unwrap().value - 1000.0).abs() < 1e-9);
        // one column, no header: today's single-column CSV
        let r = csv("1\n\n2\n3\n").unwrap();
        assert_eq!(r.channels[0].samples, vec![1.0, 2.0, 3.0]);
        assert!(r.sample_rate.is_none());
        // two columns, no header: both are channels, none is taken for time
        assert_eq!(csv("0,1\n1,2\n").unwrap().channels.len(), 2);
    }

    #[test]
    fn malformed() {
        let e = csv("a,b\n1,2\n3\n").err().unwrap();
        assert_eq!(e.1, "line 3: 1 fields, the header has 2");
        let e = csv("a,b\n1,2\nx,3\n").err().unwrap();
        assert_eq!(e.1, "line 3, column 'a': 'x' is not a number");
        let e = csv("a\n1\nx\n").err().unwrap();
        assert_eq!(e.1, "line 3: 'x' is not a number");
        // a gap of seven periods in a time column
        let e = csv("t,a\n0,1\n1,1\n2,1\n3,1\n10,1\n11,1\n12,1\n")
            .err()
            .unwrap();
        assert_eq!(e.0, "sample_rate");
        assert!(csv("").is_err());
    }
}
