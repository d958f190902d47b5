//! Measured recordings as labs keep them: MATLAB v5 `.mat`, WAV, CSV/TSV with or without a
//! header, raw f32le and JSON arrays. One reader for the command line, the API and the page.
//!
//! Reading never guesses: a file with several channels and no choice made, a sample rate
//! the file does not carry (or carries twice, differently), a channel that does not exist,
//! are errors that list what the file holds. Everything a file says about itself (channel
//! names, units, sample rate, shaft speed) is kept in a [`Recording`];
//! [`Recording::listing`] is what `inspect` shows.

mod contents;
mod delimited;
mod export;
mod listing;
mod mat_v5;
mod raw;
mod tachometer;
mod wav;

use std::path::Path;

pub use contents::{
    Channel, ChannelChoice, Recording, RecordingError, RecordingFormat, RecordingLimits, Skipped,
    Stated, FORMAT_NAMES,
};

pub use export::{write_csv, write_mat_v5, write_wav, ExportChannel, ExportFormat};
pub use listing::{ChannelListing, Listing, SkippedListing};
pub use tachometer::{
    angle_from_pulses, angle_from_speed_profile, parse_speed_profile, pulses_from_angle,
    PulseOptions,
};

/// Read `bytes` as `format`; `source_name` (a path or an uploaded file's name) prefixes
/// error messages.
pub fn read_recording(
    bytes: &[u8],
    format: RecordingFormat,
    source_name: &str,
    limits: &RecordingLimits,
) -> Result<Recording, RecordingError> {
    if bytes.len() > limits.max_bytes {
        return Err(RecordingError::new(
            source_name,
            "file",
            format!(
                "{} bytes is over the limit of {} bytes",
                bytes.len(),
                limits.max_bytes
            ),
        ));
    }
    let fail = |field, message: String| RecordingError::new(source_name, field, message);
    let rec = match format {
        RecordingFormat::Mat => mat_v5::read(bytes, limits),
        RecordingFormat::Wav => wav::read(bytes, limits),
        RecordingFormat::Csv => delimited::read(bytes, b',', limits),
        RecordingFormat::Tsv => delimited::read(bytes, b'\t', limits),
        RecordingFormat::F32le => raw::read_f32le(bytes, limits),
        RecordingFormat::Json => raw::read_json(bytes, limits),
    }
    .map_err(|(field, message)| fail(field, message))?;
    if rec.channels.is_empty() {
        let skipped = rec
            .skipped
            .iter()
            .map(|s| format!("{} ({})", s.name, s.reason))
            .collect::<Vec<_>>();
        return Err(fail(
            "file",
            if skipped.is_empty() {
                "holds no channel".into()
            } else {
                format!("holds no channel; skipped: {}", skipped.join("; "))
            },
        ));
    }
    for ch in &rec.channels {
        if ch.samples.is_empty() {
            return Err(fail(
                "samples",
                format!("channel '{}' holds no samples", ch.name),
            ));
        }
        if let Some(i) = ch.samples.iter().position(|x| !x.is_finite()) {
            return Err(fail(
                "samples",
                format!("channel '{}': sample {i} is not a finite number", ch.name),
            ));
        }
    }
    Ok(rec)
}

/// Read a file from disk; `format` `None` = from the extension.
pub fn read_recording_file(
    path: &Path,
    format: Option<RecordingFormat>,
    limits: &RecordingLimits,
) -> Result<Recording, RecordingError> {
    let name = path.display().to_string();
    let format = RecordingFormat::resolve(format, &name)?;
    let bytes = std::fs::read(path)
        .map_err(|e| RecordingError::new(&name, "file", format!("cannot read: {e}")))?;
    read_recording(&bytes, format, &name, limits)
}
