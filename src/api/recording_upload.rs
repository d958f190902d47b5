//! An uploaded recording file (the request body) read through the engine's one reader:
//! the format from `format=` or the `filename=` extension, the channel from `channel=`
//! (name or 0-based index), the sample rate and shaft speed from the file or the query
//! (never guessed); a tachometer (`tacho_channel=`) is not yet taken over HTTP. Every problem is a 422 naming the
//! query parameter at fault (`format`, `channel`, `sample_rate`, `shaft_rpm`, `file`,
//! `samples`, `channels`, `tacho_channel`).

use super::extract::QueryParams;
use super::problem::{ApiResult, Problem};
use crate::config::Config;
use bearing_core::signal::recording::{
    read_recording, ChannelChoice, Recording, RecordingError, RecordingFormat, RecordingLimits,
};

/// Channels one uploaded file may hold.
pub const MAX_UPLOAD_CHANNELS: usize = 64;

/// What an uploaded file may hold under this configuration: the body limit, and a channel
/// of at most half the body's bytes in samples (16-bit PCM, the densest common encoding;
/// a compressed MAT-file expanding past it is refused before it is inflated).
pub fn upload_limits(config: &Config) -> RecordingLimits {
    RecordingLimits {
        max_bytes: config.max_body_bytes,
        max_samples: config.max_body_bytes / 2,
        max_channels: MAX_UPLOAD_CHANNELS,
    }
}

/// A recording problem as a 422 naming the query parameter (`file` for the body).
pub fn recording_problem(e: RecordingError) -> Problem {
    Problem::field(e.field, format!("{}: {}", e.source_name, e.message))
}

/// True when the request carries a file to read rather than raw f32 samples.
pub fn is_upload(q: &QueryParams) -> bool {
    q.str("filename").is_some() || q.str("format").is_some()
}

/// The file's name (`upload` when none is given) and the recording read from `body`.
pub fn read_upload(
    q: &QueryParams,
    body: &[u8],
    config: &Config,
) -> ApiResult<(String, Recording)> {
    let name = q.str("filename").unwrap_or("upload").to_string();
    let format = match q.str("format") {
        None => None,
        Some(f) => Some(
            f.parse::<RecordingFormat>()
                .map_err(|m| Problem::field("format", m))?,
        ),
    };
    let format = RecordingFormat::resolve(format, &name).map_err(recording_problem)?;
    let rec =
        read_recording(body, format, &name, &upload_limits(config)).map_err(recording_problem)?;
    Ok((name, rec))
}

/// The signal an analysis of an upload reads.
pub struct UploadedSignal {
    pub name: String,
    pub samples: Vec<f64>,
    pub sample_rate: f64,
    /// Hz.
    pub shaft_hz: f64,
}

/// The channel, sample rate, shaft speed and tachometer of an uploaded recording.
pub fn uploaded_signal(
    q: &QueryParams,
    name: String,
    rec: &Recording,
) -> ApiResult<UploadedSignal> {
    let choice = q.str("channel").map(|c| ChannelChoice(c.to_string()));
    let channel = rec
        .channel(choice.as_ref(), &name)
        .map_err(recording_problem)?;
    let sample_rate = rec
        .sample_rate(q.f64("sample_rate")?, &name)
        .map_err(recording_problem)?;
    if q.str("tacho_channel").is_some() {
        // TRACKING: analysis jobs do not yet take a shaft angle (their stored input has
        // none), so a tachometer is refused rather than analysed at a mean speed that would
        // smear a run-up's lines; the command line order-tracks it
        return Err(Problem::field(
            "tacho_channel",
            "a tachometer is not yet analysed over HTTP; use `bearing-sim analyze --tacho-channel`",
        ));
    }
    let shaft_hz = match q.f64("shaft_hz")? {
        Some(hz) => hz,
        None => {
            rec.shaft_rpm(q.f64("shaft_rpm")?, &name)
                .map_err(recording_problem)?
                / 60.0
        }
    };
    Ok(UploadedSignal {
        name,
        samples: channel.samples.clone(),
        sample_rate,
        shaft_hz,
    })
}
