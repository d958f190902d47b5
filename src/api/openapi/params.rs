//! Parameters shared by several operations, as documented in the OpenAPI document (the
//! handlers read them with `QueryParams`, which gives the error messages listed there).

use crate::store::JobState;
use bearing_core::signal::analysis::MAX_LEVELS;
use utoipa::IntoParams;

/// The job in the path.
#[derive(IntoParams)]
#[into_params(parameter_in = Path)]
pub struct JobId {
    /// Job id (a UUID).
    #[param(example = "019a4f7e-3c1b-7d2a-9f10-2b6c8e4d5a71")]
    pub id: String,
}

/// Listing filters and paging.
#[derive(IntoParams)]
#[into_params(parameter_in = Query)]
pub struct ListQuery {
    /// Only jobs in this state.
    pub state: Option<JobState>,
    /// Jobs per page (default 50).
    #[param(minimum = 1, maximum = 500)]
    pub limit: Option<i64>,
    /// The `next_cursor` of the previous page.
    #[param(pattern = "^[1-9][0-9]{0,17}$")]
    pub cursor: Option<String>,
}

/// Long poll.
#[derive(IntoParams)]
#[into_params(parameter_in = Query)]
pub struct WaitQuery {
    /// With `If-None-Match`, hold an unchanged answer up to this many seconds (default 0).
    #[param(minimum = 0.0, maximum = 60.0)]
    pub wait: Option<f64>,
}

/// Which envelope spectrum, how far, and how many marker harmonics.
#[derive(IntoParams)]
#[into_params(parameter_in = Query)]
pub struct SpectraQuery {
    /// Raw envelope, the max-kurtosis wavelet component, or one level (default raw).
    pub kind: Option<crate::api::results::SpectrumKind>,
    /// DTCWT level (1 = finest) for `kind=level`; given alone it implies `kind=level`, with
    /// another kind it is ignored.
    #[param(minimum = 1, maximum = 16)]
    pub level: Option<usize>,
    /// Highest frequency returned, Hz.
    #[param(exclusive_minimum = 0.0)]
    pub fmax: Option<f64>,
    /// Harmonics of each theoretical line to mark (default: the harmonics the analysis
    /// searched, 3 unless its options said otherwise).
    #[param(minimum = 1, maximum = 50)]
    pub harmonics: Option<usize>,
}

/// Window and decimation of a sampled channel.
#[derive(IntoParams)]
#[into_params(parameter_in = Query)]
pub struct SignalsQuery {
    /// Channel name, as listed in the result's `channels` (e.g. `outer_ring_accel_z`).
    #[param(example = "outer_ring_accel_z")]
    pub channel: String,
    /// Start of the window, s of simulated time.
    pub from: Option<f64>,
    /// End of the window, s of simulated time (a window ending before `from` is empty).
    pub to: Option<f64>,
    /// At most this many points (default 10000); longer windows keep every k-th sample.
    #[param(minimum = 1, maximum = 200000)]
    pub max_points: Option<usize>,
}

// The literal level bound of `SpectraQuery` must be the analysis' own.
const _: () = assert!(MAX_LEVELS == 16);

/// Idempotent submission.
#[derive(IntoParams)]
#[into_params(parameter_in = Header)]
pub struct IdempotencyKey {
    /// Makes the submission safe to retry; 1-255 visible ASCII characters.
    #[param(
        rename = "Idempotency-Key",
        nullable = false,
        min_length = 1,
        max_length = 255,
        pattern = r"^[\x21-\x7e]([\x20-\x7e]*[\x21-\x7e])?$"
    )]
    pub idempotency_key: Option<String>,
}

/// Conditional read.
#[derive(IntoParams)]
#[into_params(parameter_in = Header)]
pub struct IfNoneMatch {
    /// The ETag of the last response; 304 while unchanged.
    #[param(rename = "If-None-Match", nullable = false)]
    pub if_none_match: Option<String>,
}

/// Query parameters of `POST /v1/analyses` with a raw body (little-endian f32 samples).
#[derive(IntoParams)]
#[into_params(parameter_in = Query)]
pub struct RawAnalysisQuery {
    /// `auto` (default): small signals answered directly, large ones queued; `async`: queued.
    pub mode: Option<AnalysisMode>,
    /// A recording file as the body (with `format`): its name, whose extension tells the
    /// format (`.mat`, `.wav`, `.csv`, `.tsv`, `.f32le`, `.json`); a queued job keeps it as
    /// its label. Without `filename` or `format` an octet-stream body is raw f32 samples.
    pub filename: Option<String>,
    /// A recording file as the body: its format (`mat`, `wav`, `csv`, `tsv`, `f32le`,
    /// `json`), when the file name does not tell.
    pub format: Option<String>,
    /// A recording file: the channel to analyse, by name or 0-based index (required when
    /// the file holds several; `POST /v1/recordings/inspect` lists them).
    pub channel: Option<String>,
    /// Not yet taken over HTTP (422): order tracking by a tachometer channel is on the
    /// command line (`bearing-sim analyze --tacho-channel`).
    pub tacho_channel: Option<String>,
    /// Raw body, Hz (required there); a recording file only when it carries none (a WAV
    /// header, a CSV time column or a MAT-file's `fs` variable do; a different value is a 422).
    #[param(exclusive_minimum = 0.0)]
    pub sample_rate: Option<f64>,
    /// Raw body only; a kinematic preset (`cwru6205`, `h7005c`).
    pub preset: Option<String>,
    /// Raw body only, with ball_diameter, pitch_diameter and contact_angle instead of a preset.
    #[param(minimum = 0, maximum = 1000)]
    pub ball_count: Option<usize>,
    /// Raw body only, m.
    pub ball_diameter: Option<f64>,
    /// Raw body only, m.
    pub pitch_diameter: Option<f64>,
    /// Raw body only, rad.
    pub contact_angle: Option<f64>,
    /// Raw body only; shaft frequency, Hz (or shaft_rpm).
    pub shaft_hz: Option<f64>,
    /// Raw body, or a recording file that carries no speed (CWRU's `XnnnRPM` is read);
    /// shaft speed, rev/min.
    pub shaft_rpm: Option<f64>,
    /// Raw body only; DTCWT levels.
    #[param(minimum = 0, maximum = 1000)]
    pub levels: Option<usize>,
    /// Raw body only; harmonics searched per characteristic frequency.
    #[param(minimum = 0, maximum = 1000)]
    pub harmonics: Option<usize>,
    /// Raw body only; half-width of the peak search band, %.
    pub search_band_pct: Option<f64>,
    /// Raw body only; analysis window start, s from the first sample.
    pub window_from: Option<f64>,
    /// Raw body only; analysis window end, s.
    pub window_to: Option<f64>,
    /// Raw body only; band-pass low edge, Hz.
    pub band_low: Option<f64>,
    /// Raw body only; band-pass high edge, Hz.
    pub band_high: Option<f64>,
    /// Raw body only; level-1 filter set.
    pub biort: Option<String>,
    /// Raw body only; filter set of levels >= 2.
    pub qshift: Option<String>,
    /// Raw body only; choose the band by the kurtogram over this many levels (the verdict
    /// then reads that band instead of the DTCWT components).
    #[param(minimum = 1, maximum = 12)]
    pub kurtogram_levels: Option<usize>,
    /// Raw body only; false-alarm rate of the fault verdict per fault type, in (0, 0.5]
    /// (default 1e-3).
    #[param(exclusive_minimum = 0.0, maximum = 0.5)]
    pub false_alarm_rate: Option<f64>,
    /// Raw body only; harmonics of each fault family the verdict tests (default 4).
    #[param(minimum = 2, maximum = 20)]
    pub verdict_harmonics: Option<usize>,
}

/// How an analysis request is answered.
#[derive(serde::Serialize, utoipa::ToSchema)]
#[serde(rename_all = "snake_case")]
#[allow(dead_code)] // documents the values `mode` accepts
pub enum AnalysisMode {
    Auto,
    Async,
}

/// A raw analysis body: little-endian f32 samples, 4 bytes each.
#[derive(utoipa::ToSchema)]
#[schema(value_type = String, format = Binary)]
#[allow(dead_code)] // documents the octet-stream body
pub struct RawSamples(Vec<u8>);

/// Study id.
#[derive(IntoParams)]
#[into_params(parameter_in = Path)]
pub struct StudyId {
    /// Study id (a UUID).
    #[param(example = "019a4f7e-3c1b-7d2a-9f10-2b6c8e4d5a71")]
    pub id: String,
}

/// A plot's file name.
#[derive(IntoParams)]
#[into_params(parameter_in = Path)]
pub struct PlotName {
    /// e.g. `spectra.svg`, `speed-inner.svg` (studies); `signal.svg`, `spectrum.svg`,
    /// `kurtosis.svg` (simulations).
    #[param(example = "spectra.svg")]
    pub name: String,
}

/// Paging of studies.
#[derive(IntoParams)]
#[into_params(parameter_in = Query)]
pub struct StudyListQuery {
    /// Studies per page (default 20).
    #[param(minimum = 1, maximum = 100)]
    pub limit: Option<i64>,
    /// The `next_cursor` of the previous page.
    #[param(pattern = "^[1-9][0-9]{0,17}$")]
    pub cursor: Option<String>,
}

/// Options of a simulation's plots.
#[derive(IntoParams)]
#[into_params(parameter_in = Query)]
pub struct SimulationPlotQuery {
    /// `signal.svg`: channel (default the analysed one, e.g. `outer_ring_accel_z`).
    pub channel: Option<String>,
    /// `signal.svg`: start of the window, s (default: the analysis window's start).
    pub from: Option<f64>,
    /// `signal.svg`: end of the window, s (default: 0.1 s after its start, within the run).
    pub to: Option<f64>,
    /// `spectrum.svg`: DTCWT level (default: the raw envelope spectrum).
    #[param(minimum = 1, maximum = 16)]
    pub level: Option<usize>,
    /// `spectrum.svg`: highest frequency drawn, Hz (default 3.5 x BPFI).
    #[param(exclusive_minimum = 0.0)]
    pub fmax: Option<f64>,
}

/// A recording file to list.
#[derive(IntoParams)]
#[into_params(parameter_in = Query)]
#[allow(dead_code)] // documents the query the handler reads
pub struct InspectQuery {
    /// The file's name; its extension tells the format (`.mat`, `.wav`, `.csv`, `.tsv`,
    /// `.f32le`, `.json`).
    pub filename: Option<String>,
    /// The format, when the file name does not tell: `mat`, `wav`, `csv`, `tsv`, `f32le`, `json`.
    pub format: Option<String>,
    /// Up to this many samples of each channel in the listing (every k-th), to plot it.
    #[param(minimum = 0, maximum = 10000)]
    pub preview: Option<usize>,
}

/// The format of a run exported as a recording.
#[derive(IntoParams)]
#[into_params(parameter_in = Query)]
#[allow(dead_code)] // documents the query the handler reads
pub struct RecordingExportQuery {
    /// `wav` (32-bit float), `csv` (a time column and a named header) or `mat` (level-5
    /// MAT-file with `fs`).
    #[param(example = "mat")]
    pub format: RecordingExportFormat,
}

/// The file formats a run exports to.
#[derive(serde::Serialize, utoipa::ToSchema)]
#[serde(rename_all = "snake_case")]
#[allow(dead_code)] // documents the values `format` accepts
pub enum RecordingExportFormat {
    Wav,
    Csv,
    Mat,
}
