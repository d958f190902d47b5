//! `bearing-sim inspect FILE [--format F] [--json]`: the channels of a recording, with
//! length, sample rate, units and shaft speed where the file carries them: what to pass
//! to `analyze --channel`.

use std::io::Write;
use std::path::PathBuf;

use bearing_core::signal::recording::{read_recording_file, RecordingFormat, RecordingLimits};

use super::result::CliResult;

#[derive(clap::Args, Debug)]
pub struct InspectArgs {
    /// Recording: .mat, .wav, .csv/.tsv, .f32le or .json.
    pub file: PathBuf,
    /// File format (default: from the file extension).
    #[arg(long, value_parser = |s: &str| s.parse::<RecordingFormat>())]
    pub format: Option<RecordingFormat>,
    /// Print the listing as JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn main(args: InspectArgs) -> CliResult {
    let rec = read_recording_file(&args.file, args.format, &RecordingLimits::LOCAL)?;
    let listing = rec.listing();
    let text = if args.json {
        serde_json::to_string_pretty(&listing)? + "\n"
    } else {
        listing.to_string()
    };
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(text.as_bytes()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => Ok(r?),
    }
}
