//! `bearing-sim analyze FILE [--channel C] [--fs HZ] [--rpm RPM] --bearing PRESET|FILE`:
//! the vibration-analysis pipeline on a recorded or simulated signal; prints a JSON report,
//! on a terminal after the verdict's plain sentence. The file is read by
//! [`super::signal_input`] (any recording format the engine reads).

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

use bearing_core::signal::{
    analyze_tracked, analyze_with, kinematic_preset, kinematic_preset_names, AnalysisOptions,
    KinematicGeometry, LevelSpectra,
};
use serde::{Deserialize, Serialize};

use super::result::CliResult;
use super::signal_input::SignalInputArgs;

#[derive(clap::Args, Debug)]
pub struct AnalyzeArgs {
    #[command(flatten)]
    pub input: SignalInputArgs,
    /// Bearing: a preset name (h7005c, cwru6205) or a JSON file with ball_count,
    /// ball_diameter (m), pitch_diameter (m), contact_angle (rad).
    #[arg(long)]
    pub bearing: String,
    /// DTCWT levels.
    #[arg(long, default_value_t = 5)]
    pub levels: usize,
    /// Analysis window T0,T1 in s from the first sample (default: whole signal).
    #[arg(long, value_parser = parse_pair)]
    pub window: Option<[f64; 2]>,
    /// Band-pass F0,F1 in Hz applied to the raw signal before its envelope.
    #[arg(long, value_parser = parse_pair)]
    pub band: Option<[f64; 2]>,
    /// Half-width of the peak search band, % of each target frequency.
    #[arg(long, default_value_t = 5.0)]
    pub search_band_pct: f64,
    /// Harmonics searched per characteristic frequency.
    #[arg(long, default_value_t = 3)]
    pub harmonics: usize,
    /// Detection threshold on the prominence, dB.
    #[arg(long, default_value_t = bearing_core::signal::identify::DEFAULT_THRESHOLD_DB)]
    pub threshold_db: f64,
    /// Level-1 wavelet filter set.
    #[arg(long, default_value = "near_sym_b")]
    pub biort: String,
    /// Wavelet filter set of levels >= 2.
    #[arg(long, default_value = "qshift_b")]
    pub qshift: String,
    /// Report the identifications of every DTCWT level, not only the best two.
    #[arg(long)]
    pub all_levels: bool,
    /// Also choose bands by Antoni's kurtogram over this many levels (1-12) and report what
    /// their envelope spectra show (`kurtogram`, and `kurtogram_runner_up` for the best band
    /// not overlapping it); the verdict then reads them instead of the DTCWT components.
    #[arg(long)]
    pub kurtogram_levels: Option<usize>,
    /// False-alarm rate of the fault verdict, per fault type (`verdict` in the report)
    #[arg(long, default_value_t = bearing_core::signal::verdict::DEFAULT_FALSE_ALARM_RATE)]
    pub false_alarm_rate: f64,
    /// Harmonics of each fault family the verdict tests (2-20)
    #[arg(long, default_value_t = bearing_core::signal::verdict::DEFAULT_VERDICT_HARMONICS)]
    pub verdict_harmonics: usize,
    /// Also write the envelope spectra (raw and per level) as JSON to this file.
    #[arg(long)]
    pub spectra_out: Option<PathBuf>,
}

fn parse_pair(s: &str) -> Result<[f64; 2], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 2 {
        return Err(format!(
            "expected two comma-separated numbers A,B (got '{s}')"
        ));
    }
    let num = |p: &str| {
        p.parse::<f64>()
            .map_err(|_| format!("'{p}' is not a number"))
    };
    Ok([num(parts[0])?, num(parts[1])?])
}

/// A bearing file: exactly the fields of [`KinematicGeometry`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BearingFile {
    ball_count: usize,
    ball_diameter: f64,
    pitch_diameter: f64,
    contact_angle: f64,
}

fn load_bearing(spec: &str) -> Result<KinematicGeometry, String> {
    if let Some(g) = kinematic_preset(spec) {
        return Ok(g);
    }
    let path = Path::new(spec);
    if !path.exists() {
        return Err(format!(
            "--bearing: '{spec}' is neither a preset ({}) nor an existing file",
            kinematic_preset_names().join(", ")
        ));
    }
    let text =
        std::fs::read_to_string(path).map_err(|e| format!("--bearing {spec}: cannot read: {e}"))?;
    let b: BearingFile = serde_json::from_str(&text).map_err(|e| {
        format!(
            "--bearing {spec}: {e} (expected {{\"ball_count\", \"ball_diameter\" m, \"pitch_diameter\" m, \"contact_angle\" rad}})"
        )
    })?;
    let g = KinematicGeometry {
        ball_count: b.ball_count,
        ball_diameter: b.ball_diameter,
        pitch_diameter: b.pitch_diameter,
        contact_angle: b.contact_angle,
    };
    g.validate()
        .map_err(|(f, m)| format!("--bearing {spec}: {f}: {m}"))?;
    Ok(g)
}

#[derive(Serialize)]
struct SpectraFile<'a> {
    raw: &'a bearing_core::signal::Spectrum,
    /// index 0 = level 1
    levels: &'a [Option<bearing_core::signal::Spectrum>],
}

pub fn main(args: AnalyzeArgs) -> CliResult {
    let geometry = load_bearing(&args.bearing)?;
    let signal = args.input.read()?;
    let opts = AnalysisOptions {
        levels: args.levels,
        window: args.window,
        band: args.band,
        search_band_pct: args.search_band_pct,
        harmonics: args.harmonics,
        biort: args.biort.clone(),
        qshift: args.qshift.clone(),
        detection_threshold_db: args.threshold_db,
        report_all_levels: args.all_levels,
        kurtogram_levels: args.kurtogram_levels,
        false_alarm_rate: args.false_alarm_rate,
        verdict_harmonics: args.verdict_harmonics,
    };
    // the report reads the best two levels' spectra; all are kept only to be written out
    let spectra = if args.spectra_out.is_some() {
        LevelSpectra::All
    } else {
        LevelSpectra::Chosen
    };
    // a tachometer channel or a speed profile: order tracked by the shaft angle it gives
    let out = match &signal.shaft_angle {
        Some(angle) => analyze_tracked(
            &signal.samples,
            signal.sample_rate,
            &geometry,
            angle,
            &opts,
            None,
            spectra,
        ),
        None => analyze_with(
            &signal.samples,
            signal.sample_rate,
            &geometry,
            signal.shaft_rpm / 60.0,
            &opts,
            None,
            spectra,
        ),
    }
    .map_err(|e| format!("{}: {e}", args.input.file.display()))?;
    if let Some(path) = &args.spectra_out {
        let f = SpectraFile {
            raw: &out.raw_spectrum,
            levels: &out.level_spectra,
        };
        std::fs::write(path, serde_json::to_vec(&f)?)
            .map_err(|e| format!("--spectra-out {}: {e}", path.display()))?;
    }
    let mut text = serde_json::to_string_pretty(&out.report)?;
    let mut stdout = std::io::stdout().lock();
    // A person at a terminal reads the verdict's sentence first; a pipe gets pure JSON
    // (the sentence is in it, at `verdict.summary`).
    if stdout.is_terminal() {
        if let Some(v) = &out.report.verdict {
            text = format!("{}\n\n{text}", v.summary);
        }
    }
    match writeln!(stdout, "{text}") {
        // the reader went away (e.g. `| head`): not an error of ours
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => Ok(r?),
    }
}
