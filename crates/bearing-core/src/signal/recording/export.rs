//! Writing channels the way a measured recording is kept, so a simulated run can be
//! analysed, plotted or shared like one: WAV (32-bit float), CSV with a time column, or a
//! level-5 MAT-file with an `fs` scalar. Each reads back through [`super::read_recording`]
//! with its sample rate and channel names (WAV keeps no names: channels are `ch0`, `ch1`, …
//! in the order given).

use super::delimited::format_number;
use super::mat_v5::{self, MatVariable};
use super::wav;

/// The formats a recording is written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExportFormat {
    Wav,
    Csv,
    Mat,
}

impl std::str::FromStr for ExportFormat {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "wav" => Ok(Self::Wav),
            "csv" => Ok(Self::Csv),
            "mat" => Ok(Self::Mat),
            other => Err(format!(
                "unknown export format '{other}' (expected wav, csv or mat)"
            )),
        }
    }
}

impl ExportFormat {
    /// The file extension (and the media type a server sends it as).
    pub fn extension(self) -> &'static str {
        match self {
            Self::Wav => "wav",
            Self::Csv => "csv",
            Self::Mat => "mat",
        }
    }

    pub fn media_type(self) -> &'static str {
        match self {
            Self::Wav => "audio/wav",
            Self::Csv => "text/csv",
            Self::Mat => "application/x-matlab-data",
        }
    }
}

/// One channel to write.
#[derive(Debug, Clone, Copy)]
pub struct ExportChannel<'a> {
    /// A name that is also a MATLAB identifier (letters, digits, `_`, a letter first).
    pub name: &'a str,
    pub unit: Option<&'a str>,
    pub samples: &'a [f64],
}

fn check(channels: &[ExportChannel], sample_rate: f64) -> Result<usize, String> {
    let n = channels
        .first()
        .map(|c| c.samples.len())
        .ok_or("no channel to write")?;
    if let Some(c) = channels.iter().find(|c| c.samples.len() != n) {
        return Err(format!(
            "channel '{}' has {} samples, the first {n}",
            c.name,
            c.samples.len()
        ));
    }
    if !(sample_rate.is_finite() && sample_rate > 0.0) {
        return Err(format!("sample rate {sample_rate} Hz must be > 0"));
    }
    if let Some(c) = channels.iter().find(|c| {
        !c.name.starts_with(|ch: char| ch.is_ascii_alphabetic())
            || !c
                .name
                .chars()
                .all(|ch| ch.is_ascii_alphanumeric() || ch == '_')
    }) {
        return Err(format!("channel name '{}' is not an identifier", c.name));
    }
    Ok(n)
}

/// WAV, 32-bit float: the sample rate must be a whole number of Hz (the header's field).
pub fn write_wav(channels: &[ExportChannel], sample_rate: f64) -> Result<Vec<u8>, String> {
    check(channels, sample_rate)?;
    if sample_rate.fract() != 0.0 || sample_rate > u32::MAX as f64 {
        return Err(format!(
            "a WAV header holds whole Hz; {sample_rate} Hz is not one"
        ));
    }
    let data: Vec<&[f64]> = channels.iter().map(|c| c.samples).collect();
    wav::write(&data, sample_rate as u32)
}

/// CSV: a header `time [s],name [unit],…` and one row per sample.
pub fn write_csv(channels: &[ExportChannel], sample_rate: f64) -> Result<Vec<u8>, String> {
    let n = check(channels, sample_rate)?;
    let mut out = String::from("time [s]");
    for c in channels {
        out.push(',');
        out.push_str(c.name);
        if let Some(u) = c.unit {
            out.push_str(&format!(" [{u}]"));
        }
    }
    out.push('\n');
    for k in 0..n {
        out.push_str(&format_number(k as f64 / sample_rate));
        for c in channels {
            out.push(',');
            out.push_str(&format_number(c.samples[k]));
        }
        out.push('\n');
    }
    Ok(out.into_bytes())
}

/// A level-5 MAT-file: one double column vector per channel, `fs` (Hz) and, when given,
/// `shaft_rpm` (a constant shaft speed; a run-up's is in its tachometer channel).
pub fn write_mat_v5(
    channels: &[ExportChannel],
    sample_rate: f64,
    shaft_rpm: Option<f64>,
) -> Result<Vec<u8>, String> {
    check(channels, sample_rate)?;
    let fs = [sample_rate];
    let rpm = shaft_rpm.map(|r| [r]);
    let mut vars: Vec<MatVariable> = channels
        .iter()
        .map(|c| MatVariable {
            name: c.name,
            values: c.samples,
        })
        .collect();
    vars.push(MatVariable {
        name: "fs",
        values: &fs,
    });
    if let Some(r) = &rpm {
        vars.push(MatVariable {
            name: "shaft_rpm",
            values: r,
        });
    }
    mat_v5::write(&vars)
}

#[cfg(test)]
mod tests {
    use super::super::contents::RecordingLimits;
    use super::super::delimited;
    use super::*;

    #[test]
    fn every_format_reads_back() {
        let a: Vec<f64> = (0..64).map(|k| (k as f64 * 0.2).sin()).collect();
        let b: Vec<f64> = (0..64).map(|k| k as f64).collect();
        let chans = [
            ExportChannel {
                name: "accel",
                unit: Some("m/s^2"),
                samples: &a,
            },
            ExportChannel {
                name: "tacho",
                unit: Some("V"),
                samples: &b,
            },
        ];
        let limits = RecordingLimits::LOCAL;
        for (r, f) in [
            (
                wav::read(&write_wav(&chans, 20000.0).unwrap(), &limits),
                "wav",
            ),
            (
                delimited::read(&write_csv(&chans, 20000.0).unwrap(), b',', &limits),
                "csv",
            ),
            (
                mat_v5::read(
                    &write_mat_v5(&chans, 20000.0, Some(1200.0)).unwrap(),
                    &limits,
                ),
                "mat",
            ),
        ] {
            let r = r.unwrap();
            assert_eq!(r.channels.len(), 2, "{f:?}");
            // 20 kHz back within the CSV time column's printed precision
            assert!(
                (r.sample_rate.unwrap().value - 20000.0).abs() < 1e-6,
                "{f:?}"
            );
            // f32 in WAV: 6e-8 relative
            for (x, y) in r.channels[1].samples.iter().zip(&b) {
                assert!((x - y).abs() <= 1e-6 * y.abs(), "{f:?}");
            }
        }
    }
}
