//! Results of succeeded jobs: the stored record, and envelope spectra with the
//! theoretical markers and the identified peaks. Records are read back as types.

use super::caller::Caller;
use super::extract::QueryParams;
use super::job_resource::succeeded;
use super::problem::{ApiResult, Problem};
use super::state::AppState;
use super::views::etag;
use crate::jobs::artifacts::spectrum_artifact_name;
use crate::jobs::record::{AnalysisJobRecord, AnalysisRecord, SimulationRecord};
use crate::store::blob::decode_f32le;
use crate::store::{ArtifactMeta, Job, JobKind};
use axum::http::{header, HeaderMap, HeaderValue};
use axum::response::{IntoResponse, Response};
use axum::Json;
use bearing_core::signal::analysis::{AnalysisReport, MAX_LEVELS};
use bearing_core::signal::frequencies::CharacteristicFrequencies;
use bearing_core::signal::Identification;
use serde::de::DeserializeOwned;
use serde::Serialize;
use utoipa::ToSchema;

/// `GET /v1/simulations/{id}/result`: the stored record with the job's id.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct SimulationResult {
    pub id: String,
    #[serde(flatten)]
    pub record: SimulationRecord,
}

/// `GET /v1/analyses/{id}/result`: the stored record with the job's id.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct AnalysisResult {
    pub id: String,
    #[serde(flatten)]
    pub record: AnalysisJobRecord,
}

/// `GET .../result`: the stored record of a succeeded job, with its id.
pub async fn result(
    state: AppState,
    caller: &Caller,
    kind: JobKind,
    id: String,
) -> ApiResult<Response> {
    let job = succeeded(&state, caller, kind, &id).await?;
    let mut res = match kind {
        JobKind::Simulation => Json(SimulationResult {
            id: job.id.clone(),
            record: record(&job)?,
        })
        .into_response(),
        JobKind::Analysis => Json(AnalysisResult {
            id: job.id.clone(),
            record: record(&job)?,
        })
        .into_response(),
    };
    if let Ok(v) = HeaderValue::from_str(&etag(&job)) {
        res.headers_mut().insert(header::ETAG, v);
    }
    Ok(res)
}

/// A job's stored record as its type; a record that does not parse is a server fault.
pub(super) fn record<T: DeserializeOwned>(job: &Job) -> ApiResult<T> {
    let value = job
        .result
        .clone()
        .ok_or_else(|| Problem::internal(format!("job {} has no stored result", job.id)))?;
    serde_json::from_value(value).map_err(|e| {
        Problem::internal(format!(
            "stored result of job {} does not parse: {e}",
            job.id
        ))
    })
}

/// The analysis stored with a succeeded job, or 409 saying why there is none.
pub(super) fn stored_analysis(job: &Job) -> ApiResult<AnalysisRecord> {
    match job.kind {
        JobKind::Analysis => Ok(record::<AnalysisJobRecord>(job)?.analysis),
        JobKind::Simulation => {
            let r: SimulationRecord = record(job)?;
            r.analysis.ok_or_else(|| {
                let why = r
                    .analysis_error
                    .unwrap_or_else(|| "no analysis was stored".into());
                Problem::conflict(
                    format!("job {} has no spectra: {why}", job.id),
                    Some(job.state.as_str()),
                )
            })
        }
    }
}

/// Which spectrum `GET .../spectra` asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum SpectrumChoice {
    Raw,
    BestComponent,
    Level(usize),
}

impl SpectrumChoice {
    fn kind(self) -> SpectrumKind {
        match self {
            SpectrumChoice::Raw => SpectrumKind::Raw,
            SpectrumChoice::BestComponent => SpectrumKind::BestComponent,
            SpectrumChoice::Level(_) => SpectrumKind::Level,
        }
    }
}

/// The query of `GET .../spectra`, parsed.
struct SpectraQuery {
    choice: SpectrumChoice,
    /// Hz.
    fmax: Option<f64>,
    /// Marker harmonics; default: the harmonics the analysis searched.
    harmonics: Option<usize>,
}

/// Most marker harmonics a request may ask for.
const MAX_HARMONICS: usize = 50;

fn parse_spectra_query(q: Option<&str>) -> ApiResult<SpectraQuery> {
    let q = QueryParams::parse(q)?;
    let level = q.get::<usize>("level")?;
    if let Some(l) = level {
        if !(1..=MAX_LEVELS).contains(&l) {
            return Err(Problem::bad_request(format!(
                "query parameter 'level' must be in 1..={MAX_LEVELS}"
            )));
        }
    }
    // `level` alone implies kind=level; with another kind it is ignored.
    let which = q
        .str("kind")
        .unwrap_or(if level.is_some() { "level" } else { "raw" });
    let fmax = q.f64("fmax")?;
    if let Some(f) = fmax {
        if f <= 0.0 {
            return Err(Problem::bad_request(
                "query parameter 'fmax' must be > 0 Hz",
            ));
        }
    }
    let harmonics = q.get::<usize>("harmonics")?;
    if let Some(h) = harmonics {
        if !(1..=MAX_HARMONICS).contains(&h) {
            return Err(Problem::bad_request(format!(
                "query parameter 'harmonics' must be in 1..={MAX_HARMONICS}"
            )));
        }
    }
    let choice = match which {
        "raw" => SpectrumChoice::Raw,
        "best_component" => SpectrumChoice::BestComponent,
        "level" => SpectrumChoice::Level(
            level
                .ok_or_else(|| Problem::field("level", "required with kind=level (1 = finest)"))?,
        ),
        other => {
            return Err(Problem::bad_request(format!(
                "query parameter 'kind' = '{other}': expected raw, best_component or level"
            )))
        }
    };
    Ok(SpectraQuery {
        choice,
        fmax,
        harmonics,
    })
}

/// An envelope spectrum with the theoretical lines and the peaks identified in it.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct SpectrumView {
    pub id: String,
    pub kind: SpectrumKind,
    /// DTCWT level (1 = finest), null for the raw spectrum.
    pub level: Option<usize>,
    /// Bin width, Hz: bin `k` is at `k df`.
    pub df: f64,
    /// Frequency of the last bin returned, Hz.
    pub fmax: f64,
    /// Amplitude per bin, unit of the analysed signal (Hann window, single-sided).
    pub amplitude: Vec<f64>,
    pub markers: Vec<Marker>,
    /// Identifications in this spectrum (those below `fmax`).
    pub peaks: Vec<Identification>,
}

/// Which envelope spectrum: of the raw signal, of the max-kurtosis DTCWT component, or of
/// one DTCWT level.
#[derive(Debug, Clone, Copy, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum SpectrumKind {
    Raw,
    BestComponent,
    Level,
}

impl SpectrumKind {
    fn as_str(self) -> &'static str {
        match self {
            SpectrumKind::Raw => "raw",
            SpectrumKind::BestComponent => "best_component",
            SpectrumKind::Level => "level",
        }
    }
}

/// One theoretical line on a spectrum plot.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct Marker {
    /// `bpfo`, `bpfi`, `ftf`, `bsf`, `bsf2` or `shaft`.
    pub name: &'static str,
    pub harmonic: usize,
    /// 0 for the line itself; -1 or +1 for a shaft-rate sideband of it (BPFI's harmonics
    /// only: an inner-race defect turns with the shaft through the load zone).
    pub sideband: i32,
    /// Hz.
    pub frequency: f64,
}

/// The request asks for CSV (`Accept: text/csv`).
pub(super) fn wants_csv(headers: &HeaderMap) -> bool {
    headers
        .get(header::ACCEPT)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|a| a.contains("text/csv"))
}

/// A spectrum as CSV: `frequency_hz,amplitude`, one row per bin from 0 Hz.
fn spectrum_csv(df: f64, amplitude: &[f64]) -> Response {
    let mut out = String::from("frequency_hz,amplitude\n");
    for (k, a) in amplitude.iter().enumerate() {
        out.push_str(&format!("{},{a}\n", k as f64 * df));
    }
    let mut res = out.into_response();
    res.headers_mut().insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static("text/csv; charset=utf-8"),
    );
    res
}

/// `GET .../spectra`: JSON, or with `Accept: text/csv` the amplitudes alone as CSV.
pub async fn spectra(
    state: AppState,
    caller: &Caller,
    kind: JobKind,
    id: String,
    q: Option<String>,
    headers: &HeaderMap,
) -> ApiResult<Response> {
    let query = parse_spectra_query(q.as_deref())?;
    let job = succeeded(&state, caller, kind, &id).await?;
    let analysis = stored_analysis(&job)?;
    let level = match query.choice {
        SpectrumChoice::Raw => None,
        SpectrumChoice::BestComponent => Some(analysis.report.best_component.level),
        SpectrumChoice::Level(l) => Some(l),
    };
    let peaks = identifications_of(&analysis.report, level);
    let which = query.choice.kind();
    // a spectrum is up to n/2 bins, held as f32 and then as JSON: a few at a time
    let _permit = state.large_transfer(caller.share_key()).await?;
    let Some(a) = state
        .store
        .get_artifact(&id, &spectrum_artifact_name(level))
        .await?
    else {
        return Err(Problem::not_found(format!(
            "job {id} has no spectrum {}{}",
            which.as_str(),
            level.map(|l| format!(" for level {l}")).unwrap_or_default()
        )));
    };
    let ArtifactMeta::Spectrum { df, .. } = a.meta else {
        return Err(Problem::internal(format!(
            "artifact {} of job {id} is not a spectrum",
            a.name
        )));
    };
    let mut amplitude = decode_f32le(&a.data);
    if let Some(f) = query.fmax {
        if df > 0.0 {
            amplitude.truncate(((f / df).floor() as usize + 1).min(amplitude.len()));
        }
    }
    if wants_csv(headers) {
        return Ok(spectrum_csv(df, &amplitude));
    }
    let f_top = df * amplitude.len().saturating_sub(1) as f64;
    let harmonics = query.harmonics.unwrap_or(analysis.options.harmonics).max(1);
    let markers = markers(&analysis.report.theory, harmonics, f_top);
    let peaks: Vec<Identification> = peaks
        .into_iter()
        .filter(|p| p.identified_hz <= f_top)
        .collect();
    Ok(Json(SpectrumView {
        id,
        kind: which,
        level,
        df,
        fmax: f_top,
        amplitude,
        markers,
        peaks,
    })
    .into_response())
}

/// The lines identified in the raw envelope spectrum (`None`) or in a DTCWT level's.
pub(super) fn identifications_of(
    report: &AnalysisReport,
    level: Option<usize>,
) -> Vec<Identification> {
    match level {
        None => report.raw.clone(),
        Some(l) => [&report.best_component, &report.runner_up_component]
            .into_iter()
            .chain(report.all_levels.iter())
            .find(|c| c.level == l)
            .map(|c| c.identifications.clone())
            .unwrap_or_default(),
    }
}

/// Theoretical characteristic frequencies and their harmonics up to `f_top` (Hz), named
/// as the stored `theory` object names them, and the shaft sidebands of BPFI's harmonics.
/// The page and the SVG endpoint both draw this list.
pub(super) fn markers(
    theory: &CharacteristicFrequencies,
    harmonics: usize,
    f_top: f64,
) -> Vec<Marker> {
    let lines = [
        ("bpfi", theory.bpfi),
        ("bpfo", theory.bpfo),
        ("bsf", theory.bsf),
        ("bsf2", theory.bsf2),
        ("ftf", theory.ftf),
        ("shaft", theory.shaft_hz),
    ];
    let mut out = vec![];
    for (name, f) in lines {
        // a NaN or non-positive line has no marker
        if f.is_nan() || f <= 0.0 {
            continue;
        }
        for h in 1..=harmonics {
            let fh = f * h as f64;
            if fh <= f_top {
                out.push(Marker {
                    name,
                    harmonic: h,
                    sideband: 0,
                    frequency: fh,
                });
            }
            // (a NaN shaft frequency has no sidebands either)
            if name != "bpfi" || theory.shaft_hz.is_nan() || theory.shaft_hz <= 0.0 {
                continue;
            }
            for side in [-1, 1] {
                let fs = fh + side as f64 * theory.shaft_hz;
                if fs > 0.0 && fs <= f_top {
                    out.push(Marker {
                        name,
                        harmonic: h,
                        sideband: side,
                        frequency: fs,
                    });
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markers_repeat_each_line_up_to_the_top_frequency() {
        let t = CharacteristicFrequencies {
            shaft_hz: 10.0,
            bpfo: 100.0,
            bpfi: 150.0,
            ftf: 4.0,
            bsf: 50.0,
            bsf2: 100.0,
        };
        let m = markers(&t, 5, 400.0);
        let bpfo: Vec<f64> = m
            .iter()
            .filter(|m| m.name == "bpfo")
            .map(|m| m.frequency)
            .collect();
        assert_eq!(bpfo, vec![100.0, 200.0, 300.0, 400.0]);
        assert_eq!(m.iter().filter(|m| m.name == "ftf").count(), 5);
        // BPFI 150, 300 Hz with sidebands 10 Hz either side; 450 Hz is past the top
        let sidebands: Vec<f64> = m
            .iter()
            .filter(|m| m.sideband != 0)
            .map(|m| m.frequency)
            .collect();
        assert_eq!(sidebands, vec![140.0, 160.0, 290.0, 310.0]);
        assert!(m.iter().all(|m| m.sideband == 0 || m.name == "bpfi"));
    }
}
