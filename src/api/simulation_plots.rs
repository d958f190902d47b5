//! `GET /v1/simulations/{id}/plots/{name}`: a simulation's time signal, envelope spectrum
//! with characteristic-frequency markers, and per-level kurtosis, as SVG.

use super::caller::Caller;
use super::extract::QueryParams;
use super::job_resource::succeeded;
use super::openapi::params::{JobId, PlotName, SimulationPlotQuery};
use super::openapi::responses::{BadRequest, Conflict, NotFound};
use super::problem::{ApiResult, Problem};
use super::results::{identifications_of, markers, record, stored_analysis};
use super::simulations::{load_channel, sample_window, StoredChannel};
use super::state::AppState;
use super::studies::svg_response;
use crate::jobs::artifacts::spectrum_artifact_name;
use crate::jobs::record::SimulationRecord;
use crate::plots::{
    kurtosis_svg, signal_svg, spectrum_svg, Marker, Peak, SignalTrace, SpectrumPanel,
};
use crate::store::blob::decode_f32le;
use crate::store::{ArtifactMeta, JobKind};
use axum::extract::{Path, RawQuery, State};
use axum::response::Response;

/// The plots every succeeded simulation has.
pub const SIMULATION_PLOTS: [&str; 3] = ["signal.svg", "spectrum.svg", "kurtosis.svg"];

/// Longest default signal window, s (an impulse train stays readable at 800 px).
const DEFAULT_WINDOW: f64 = 0.1;

/// A plot of a succeeded simulation, as SVG
///
/// `signal.svg`: a window of a channel (default the analysed accelerometer channel over
/// the first 0.1 s of the analysis window), drawn as min/max per pixel column.
/// `spectrum.svg`: the raw envelope spectrum (or `level`'s) with BPFO, BPFI, BSF, 2xBSF,
/// FTF and shaft markers at their first three harmonics, BPFI's shaft sidebands and the
/// identified peaks with their error, drawn as the lab page draws it. `kurtosis.svg`: each
/// DTCWT level's kurtosis, the chosen level highlighted, and the raw signal's.
#[utoipa::path(
    get,
    path = "/v1/simulations/{id}/plots/{name}",
    tag = "simulations",
    operation_id = "getSimulationPlot",
    params(JobId, PlotName, SimulationPlotQuery),
    responses(
        (status = 200, description = "The chart.", content_type = "image/svg+xml", body = String),
        (status = 400, response = BadRequest),
        (status = 404, response = NotFound),
        (status = 409, response = Conflict),
    )
)]
pub async fn plot(
    State(state): State<AppState>,
    caller: Caller,
    Path((id, name)): Path<(String, String)>,
    RawQuery(q): RawQuery,
) -> ApiResult<Response> {
    let q = QueryParams::parse(q.as_deref())?;
    if !SIMULATION_PLOTS.contains(&name.as_str()) {
        return Err(Problem::not_found(format!(
            "no plot '{name}'; simulations have {}",
            SIMULATION_PLOTS.join(", ")
        )));
    }
    let job = succeeded(&state, &caller, JobKind::Simulation, &id).await?;
    let rec: SimulationRecord = record(&job)?;
    let analysis = stored_analysis(&job)?;
    let report = &analysis.report;
    let title = |what: &str| format!("{what}: {}", rec.scene_name);
    let svg = match name.as_str() {
        "signal.svg" => {
            let channel = q
                .str("channel")
                .map(str::to_string)
                .or(analysis.channel.clone())
                .unwrap_or_else(|| "outer_ring_accel_z".into());
            let StoredChannel {
                data,
                sample_rate: fs,
                start_time: t0,
                unit,
            } = load_channel(&state, &id, &channel).await?;
            let t_end = t0 + data.len().saturating_sub(1) as f64 / fs;
            let from = q.f64("from")?.unwrap_or(rec.steady_window[0].max(t0));
            let to = q.f64("to")?.unwrap_or((from + DEFAULT_WINDOW).min(t_end));
            if !(from.is_finite() && to.is_finite() && to > from) {
                return Err(Problem::bad_request(
                    "query parameters 'from' and 'to' must be finite with from < to",
                ));
            }
            let (first, last) = sample_window(t0, fs, data.len(), Some(from), Some(to));
            if last - first < 2 {
                return Err(Problem::bad_request(format!(
                    "the window [{from}, {to}] s holds fewer than 2 samples (the channel spans [{t0}, {t_end}] s)"
                )));
            }
            signal_svg(&SignalTrace {
                title: title(&format!("{channel}, {from:.4}-{to:.4} s")),
                y_label: format!("{channel} ({unit})"),
                start_time: t0 + first as f64 / fs,
                sample_rate: fs,
                samples: &data[first..last],
            })
        }
        "spectrum.svg" => {
            let level = q.get::<usize>("level")?;
            if let Some(l) = level {
                if !(1..=report.level_kurtosis.len()).contains(&l) {
                    return Err(Problem::bad_request(format!(
                        "query parameter 'level' must be in 1..={}",
                        report.level_kurtosis.len()
                    )));
                }
            }
            let Some(a) = state
                .store
                .get_artifact(&id, &spectrum_artifact_name(level))
                .await?
            else {
                return Err(Problem::not_found(format!("simulation {id} has no such spectrum")));
            };
            let ArtifactMeta::Spectrum { df, .. } = a.meta else {
                return Err(Problem::internal(format!("artifact {} is not a spectrum", a.name)));
            };
            let t = &report.theory;
            // the page's default range
            let fmax = q.f64("fmax")?.unwrap_or((3.5 * t.bpfi.max(t.bpfo)).round());
            if !(fmax.is_finite() && fmax > 0.0) {
                return Err(Problem::bad_request("query parameter 'fmax' must be > 0 Hz"));
            }
            let markers = markers(t, 3, fmax)
                .into_iter()
                .map(|m| Marker {
                    name: m.name,
                    harmonic: m.harmonic,
                    sideband: m.sideband,
                    hz: m.frequency,
                })
                .collect();
            let peaks = identifications_of(report, level)
                .into_iter()
                .filter_map(|p| {
                    Some(Peak {
                        name: line_key(&p.name)?,
                        hz: p.identified_hz,
                        error_pct: p.error_pct,
                        detected: p.detected,
                    })
                })
                .collect();
            let which = level
                .map(|l| format!("level {l} envelope spectrum"))
                .unwrap_or_else(|| "raw envelope spectrum".into());
            spectrum_svg(
                &SpectrumPanel {
                    title: title(&which),
                    df,
                    amplitude: decode_f32le(&a.data),
                    markers,
                    peaks,
                    y_label: "envelope amplitude (m/s²)".into(),
                },
                fmax,
            )
        }
        _ => kurtosis_svg(
            &title("DTCWT component kurtosis"),
            &report.level_kurtosis,
            report.raw_kurtosis,
            report.best_component.level,
        ),
    }
    .map_err(|e| Problem::internal(e.to_string()))?;
    Ok(svg_response(svg))
}

/// The API name of a line as identifications name it (`2xBSF` -> `bsf2`).
fn line_key(name: &str) -> Option<&'static str> {
    Some(match name {
        "BPFO" => "bpfo",
        "BPFI" => "bpfi",
        "BSF" => "bsf",
        "2xBSF" => "bsf2",
        "FTF" => "ftf",
        _ => return None,
    })
}
