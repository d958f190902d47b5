//! The signal a command analyses: a recording file read through the engine's one reader
//! (`bearing_core::signal::recording`), the channel chosen, the sample rate and shaft speed
//! from the file or the command line (never guessed), and, where a tachometer channel or a
//! speed profile is given, the shaft's angle per sample.

use std::path::PathBuf;

use bearing_core::signal::recording::{
    angle_from_speed_profile, parse_speed_profile, read_recording_file, ChannelChoice,
    PulseOptions, RecordingFormat, RecordingLimits,
};
use bearing_core::signal::shaft_angle::ShaftAngle;

#[derive(clap::Args, Debug)]
pub struct SignalInputArgs {
    /// Recording: MATLAB v5 .mat, WAV, CSV/TSV (with or without a header; a `time` column
    /// gives the sample rate), raw little-endian float32 (.f32le/.f32/.raw/.bin) or a JSON
    /// array (.json). `bearing-sim inspect FILE` lists its channels.
    pub file: PathBuf,
    /// Channel to analyse, by name or 0-based index (required when the file holds several).
    #[arg(long)]
    pub channel: Option<String>,
    /// Sample rate, Hz (required where the file does not carry one: raw, JSON, CSV without
    /// a time column, a .mat without an `fs` variable).
    #[arg(long)]
    pub fs: Option<f64>,
    /// Shaft (inner ring) speed, rev/min (default: the file's, e.g. CWRU's XnnnRPM).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// File format (default: from the file extension): mat, wav, csv, tsv, f32le, json.
    #[arg(long, value_parser = parse_format)]
    pub format: Option<RecordingFormat>,
    /// Tachometer channel in the same file (once- or n-per-revolution pulses): the shaft
    /// angle is taken from it.
    #[arg(long)]
    pub tacho_channel: Option<String>,
    /// Tachometer pulses per shaft revolution.
    #[arg(long, default_value_t = 1)]
    pub pulses_per_rev: usize,
    /// Tachometer threshold (default: midway between the channel's extremes).
    #[arg(long)]
    pub tacho_threshold: Option<f64>,
    /// A speed profile instead of a tachometer: a file of `time (s), rpm` rows.
    #[arg(long, conflicts_with = "tacho_channel")]
    pub speed_profile: Option<PathBuf>,
}

fn parse_format(s: &str) -> Result<RecordingFormat, String> {
    s.parse()
}

/// A signal ready to analyse.
pub struct SignalInput {
    pub samples: Vec<f64>,
    pub sample_rate: f64,
    /// rev/min; for a tracked signal, its mean over the signal.
    pub shaft_rpm: f64,
    /// Where a tachometer channel or a speed profile was given.
    pub shaft_angle: Option<ShaftAngle>,
}

impl SignalInputArgs {
    pub fn read(&self) -> Result<SignalInput, String> {
        if let Some(fs) = self.fs {
            if !(fs.is_finite() && fs > 0.0) {
                return Err(format!("--fs: must be a sample rate > 0 Hz (got {fs})"));
            }
        }
        if let Some(r) = self.rpm {
            if !(r.is_finite() && r > 0.0) {
                return Err(format!(
                    "--rpm: must be a shaft speed > 0 rev/min (got {r})"
                ));
            }
        }
        let name = self.file.display().to_string();
        let flag = |field: &str| match field {
            "sample_rate" => " (--fs)",
            "shaft_rpm" => " (--rpm)",
            "channel" => " (--channel)",
            "tachometer" => " (--tacho-channel)",
            "format" => " (--format)",
            _ => "",
        };
        let named =
            |e: bearing_core::signal::recording::RecordingError| format!("{e}{}", flag(e.field));
        let rec =
            read_recording_file(&self.file, self.format, &RecordingLimits::LOCAL).map_err(named)?;
        let choice = self.channel.clone().map(ChannelChoice);
        let channel = rec.channel(choice.as_ref(), &name).map_err(named)?;
        let sample_rate = rec.sample_rate(self.fs, &name).map_err(named)?;
        let n = channel.samples.len();
        let shaft_angle = if let Some(t) = &self.tacho_channel {
            let opts = PulseOptions {
                pulses_per_rev: self.pulses_per_rev,
                threshold: self.tacho_threshold,
                ..PulseOptions::default()
            };
            Some(
                rec.tachometer_angle(&ChannelChoice(t.clone()), &opts, n, &name)
                    .map_err(named)?,
            )
        } else if let Some(p) = &self.speed_profile {
            let text = std::fs::read_to_string(p)
                .map_err(|e| format!("--speed-profile {}: {e}", p.display()))?;
            let (t, rpm) = parse_speed_profile(&text)
                .map_err(|e| format!("--speed-profile {}: {e}", p.display()))?;
            Some(
                angle_from_speed_profile(&t, &rpm, sample_rate, n)
                    .map_err(|e| format!("--speed-profile {}: {e}", p.display()))?,
            )
        } else {
            None
        };
        let shaft_rpm = match &shaft_angle {
            Some(a) => 60.0 * a.revolutions() * sample_rate / (n - 1) as f64,
            None => rec.shaft_rpm(self.rpm, &name).map_err(named)?,
        };
        Ok(SignalInput {
            samples: channel.samples.clone(),
            sample_rate,
            shaft_rpm,
            shaft_angle,
        })
    }
}
