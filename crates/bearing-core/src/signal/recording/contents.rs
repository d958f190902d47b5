//! What a recording is once read, whatever its container: channels, the sample rate and
//! shaft speed the file states (and where), what was skipped; the limits reading keeps
//! to; and the rules that pick a channel, a sample rate and a shaft speed without guessing.
//! The format readers build these; `mod.rs` dispatches to them.

use std::path::Path;

/// The container formats read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RecordingFormat {
    /// MATLAB level-5 MAT-file (as MATLAB writes by default, compressed or not).
    Mat,
    /// RIFF WAVE: PCM 8/16/24/32-bit or 32-bit IEEE float, any channel count.
    Wav,
    /// Comma-separated columns, with or without a header line.
    Csv,
    /// Tab-separated columns, with or without a header line.
    Tsv,
    /// Raw little-endian IEEE-754 float32, one channel, no header.
    F32le,
    /// A JSON array of numbers, one channel.
    Json,
}

/// Format names accepted by [`RecordingFormat::from_str`], for error messages.
pub const FORMAT_NAMES: &str = "mat, wav, csv, tsv, f32le, json";

impl std::str::FromStr for RecordingFormat {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "mat" => Ok(Self::Mat),
            "wav" | "wave" => Ok(Self::Wav),
            "csv" | "txt" => Ok(Self::Csv),
            "tsv" | "tab" => Ok(Self::Tsv),
            "f32le" | "f32" | "raw" => Ok(Self::F32le),
            "json" => Ok(Self::Json),
            other => Err(format!(
                "unknown format '{other}' (expected {FORMAT_NAMES})"
            )),
        }
    }
}

impl RecordingFormat {
    /// From a file name's extension: `.mat`, `.wav`, `.csv/.txt`, `.tsv/.tab`,
    /// `.f32le/.f32/.raw/.bin`, `.json`.
    pub fn from_file_name(name: &str) -> Option<Self> {
        let ext = Path::new(name).extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "bin" => Some(Self::F32le),
            other => other.parse().ok(),
        }
    }

    /// The format a file name says, or `given` (which wins); an error when neither tells.
    pub fn resolve(given: Option<Self>, file_name: &str) -> Result<Self, RecordingError> {
        given
            .or_else(|| Self::from_file_name(file_name))
            .ok_or_else(|| {
                RecordingError::new(
                    file_name,
                    "format",
                    format!(
                        "cannot tell the format from the file name; give one of {FORMAT_NAMES}"
                    ),
                )
            })
    }
}

/// How much a recording may hold; reading stops with an error past any of them, before
/// the memory is spent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordingLimits {
    /// Bytes of the file.
    pub max_bytes: usize,
    /// Samples of one channel.
    pub max_samples: usize,
    /// Channels (or variables) in the file.
    pub max_channels: usize,
}

impl RecordingLimits {
    /// What the command line reads: files a workstation holds comfortably.
    pub const LOCAL: RecordingLimits = RecordingLimits {
        max_bytes: 1 << 30,
        max_samples: 100_000_000,
        max_channels: 1024,
    };
}

/// One channel of a recording.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    /// The name the file gives it (a header, a variable name), or `ch<k>` where it gives none.
    pub name: String,
    /// The unit, where the file says it (a CSV header `accel [g]` or `accel (g)`).
    pub unit: Option<String>,
    pub samples: Vec<f64>,
}

/// A value the file states about itself, and where in the file it was found.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Stated {
    pub value: f64,
    /// e.g. `WAV header`, `time column 'time_s'`, `variable X105RPM`.
    pub from: String,
}

/// Something in a file that is not a channel, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Skipped {
    pub name: String,
    pub reason: String,
}

/// A file read: its channels and what it says about them.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    pub format: RecordingFormat,
    pub channels: Vec<Channel>,
    /// Hz, where the file carries it (WAV header, a CSV time column, a `.mat` `fs` scalar).
    pub sample_rate: Option<Stated>,
    /// rev/min, where the file carries it (CWRU's `XnnnRPM`).
    pub shaft_rpm: Option<Stated>,
    /// Variables or columns that are not channels.
    pub skipped: Vec<Skipped>,
}

/// Which channel to take: by name, or by index (0-based) when the text is a number no
/// channel is named.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChannelChoice(pub String);

/// A problem with a recording: the file, the request field it concerns (`file`, `format`,
/// `channel`, `sample_rate`, `shaft_rpm`, `samples`, `channels`, `tachometer`) and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{source_name}: {message}")]
pub struct RecordingError {
    pub source_name: String,
    pub field: &'static str,
    pub message: String,
}

impl RecordingError {
    pub fn new(source_name: &str, field: &'static str, message: impl Into<String>) -> Self {
        RecordingError {
            source_name: source_name.to_string(),
            field,
            message: message.into(),
        }
    }
}

/// Limits on reading one format: `(field, message)` on failure, the caller adds the file.
pub(crate) type ReadResult<T> = Result<T, (&'static str, String)>;

/// The error when a file has more channels than allowed.
pub(crate) fn check_channel_count(n: usize, limits: &RecordingLimits) -> ReadResult<()> {
    if n > limits.max_channels {
        Err((
            "channels",
            format!("{n} channels is over the limit of {}", limits.max_channels),
        ))
    } else {
        Ok(())
    }
}

/// The error when a channel has more samples than allowed.
pub(crate) fn check_sample_count(n: usize, limits: &RecordingLimits) -> ReadResult<()> {
    if n > limits.max_samples {
        Err((
            "samples",
            format!(
                "{n} samples per channel is over the limit of {}",
                limits.max_samples
            ),
        ))
    } else {
        Ok(())
    }
}

impl Recording {
    fn names(&self) -> String {
        self.channels
            .iter()
            .enumerate()
            .map(|(i, c)| format!("{i}: {}", c.name))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The channel `choice` names; with no choice, the only channel. Several channels and
    /// no choice, or a choice that names none, is an error listing the channels.
    pub fn channel(
        &self,
        choice: Option<&ChannelChoice>,
        source_name: &str,
    ) -> Result<&Channel, RecordingError> {
        let fail = |m: String| RecordingError::new(source_name, "channel", m);
        match choice {
            None if self.channels.len() == 1 => Ok(&self.channels[0]),
            None => Err(fail(format!(
                "holds {} channels; choose one by name or index: {}",
                self.channels.len(),
                self.names()
            ))),
            Some(ChannelChoice(c)) => {
                if let Some(ch) = self.channels.iter().find(|ch| &ch.name == c) {
                    return Ok(ch);
                }
                match c.parse::<usize>().ok().and_then(|i| self.channels.get(i)) {
                    Some(ch) => Ok(ch),
                    None => Err(fail(format!(
                        "no channel '{c}'; the file holds {}",
                        self.names()
                    ))),
                }
            }
        }
    }

    /// The sample rate, Hz: the file's, or `given` where the file carries none. Both, and
    /// different, is an error; so is neither.
    pub fn sample_rate(
        &self,
        given: Option<f64>,
        source_name: &str,
    ) -> Result<f64, RecordingError> {
        let fail = |m: String| RecordingError::new(source_name, "sample_rate", m);
        match (&self.sample_rate, given) {
            (Some(s), Some(g)) if (s.value - g).abs() > 1e-9 * s.value.abs().max(g.abs()) => {
                Err(fail(format!(
                    "the sample rate given ({g} Hz) differs from the file's ({} Hz, from the {}); give none or the same",
                    s.value, s.from
                )))
            }
            (Some(s), _) => Ok(s.value),
            (None, Some(g)) => Ok(g),
            (None, None) => Err(fail(match self.format {
                RecordingFormat::Mat => "a MAT-file carries no sample rate unless it holds a scalar variable fs (Hz); give the sample rate (CWRU: 12000 for the 12k files, 48000 for the 48k drive-end files)".to_string(),
                _ => "the file carries no sample rate; give it (Hz), or for CSV add a time column".to_string(),
            })),
        }
    }

    /// The shaft speed, rev/min: `given`, else the file's; an error when neither.
    pub fn shaft_rpm(&self, given: Option<f64>, source_name: &str) -> Result<f64, RecordingError> {
        given
            .or(self.shaft_rpm.as_ref().map(|s| s.value))
            .ok_or_else(|| {
                RecordingError::new(
                    source_name,
                    "shaft_rpm",
                    "the file carries no shaft speed; give it (rev/min)",
                )
            })
    }
}

/// Where a rate or speed variable is found: a name as a [`Stated`] source.
pub(crate) fn stated(value: f64, from: impl Into<String>) -> Stated {
    Stated {
        value,
        from: from.into(),
    }
}
