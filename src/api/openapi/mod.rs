//! The OpenAPI document, generated from the handlers' `#[utoipa::path]` annotations and the
//! types they read and write. `openapi.yaml` in the repository is its committed output
//! (`BEARING_SIM_UPDATE_OPENAPI=1 cargo test --test checks openapi` writes it); that test
//! fails when the two differ.

pub mod params;
pub mod responses;

use super::{
    analyses, ops, presets, quasi_static, recordings, simulation_plots, simulation_recording,
    simulations, studies,
};
use std::sync::OnceLock;
use utoipa::OpenApi;

/// Description of the whole API (the document's `info.description`).
const DESCRIPTION: &str = "\
Submit a scene (inline, or a preset with a fault case and a JSON merge patch of
overrides); the job is queued durably and run by a bounded worker pool. Poll the job
(cheaply, with `If-None-Match`), then read its result summary, sampled signals and
envelope spectra, or their plots as SVG. A parameter study (`POST /v1/studies`) queues a
design of simulations and gives a table and plots of the fault frequencies they show.
Measured signals can be analysed with `POST /v1/analyses`.

Every error is `application/problem+json` (RFC 9457). Validation problems list every
field with its path from the request body's root (`scene.bearing.ball_diameter`).
Status codes: 400 malformed JSON or query parameter; 404 unknown id or route;
405 wrong method; 408 request timeout; 409 invalid state transition (e.g. the result
of an unfinished job); 413 body too large; 415 wrong Content-Type; 422 invalid
content, or an `Idempotency-Key` reused with a different body; 429 queue full (with
`Retry-After`); 401 missing or unknown token, when the service is configured with
tokens (`Authorization: Bearer <token>`; each token sees only the jobs and studies it
created); 431 request headers too large; 503 over the connection bound or shutting
down; 507 the service's storage limit is reached (delete finished jobs).

Units are SI (m, kg, s, N, Pa, rad) unless a field name says otherwise (`*_rpm`:
rev/min, `*_hz`: Hz, `*_pct`: %, `*_db`: dB).
";

#[derive(OpenApi)]
#[openapi(
    info(
        title = "bearing-sim service",
        description = DESCRIPTION,
        license(name = "MIT OR Apache-2.0")
    ),
    servers((url = "http://127.0.0.1:8080", description = "The default bind address")),
    tags(
        (name = "simulations", description = "Dynamic simulations of a bearing scene, queued as jobs."),
        (name = "studies", description = "Parameter studies: designs of simulations, their table and plots."),
        (name = "analyses", description = "Diagnosis of measured signals."),
        (name = "models", description = "Presets and the quasi-static model, answered directly."),
        (name = "operations", description = "Health, readiness, metrics and this document.")
    ),
    paths(
        simulations::submit,
        simulations::list,
        simulations::get,
        simulations::delete,
        simulations::cancel,
        simulations::result,
        simulations::signals,
        simulation_recording::recording,
        simulations::spectra,
        simulation_plots::plot,
        studies::submit,
        studies::list,
        studies::get,
        studies::delete,
        studies::cancel,
        studies::table,
        studies::plot,
        analyses::submit,
        analyses::list,
        analyses::get,
        analyses::delete,
        analyses::cancel,
        analyses::result,
        analyses::spectra,
        recordings::inspect,
        quasi_static::solve,
        presets::list,
        presets::get,
        ops::healthz,
        ops::readyz,
        ops::metrics,
        ops::openapi,
    ),
    components(
        schemas(
            super::problem::Problem,
            params::AnalysisMode,
            params::RecordingExportFormat,
            crate::store::JobState,
            super::results::SpectrumKind,
        ),
        responses(
        responses::BadRequest,
        responses::NotFound,
        responses::Conflict,
        responses::TooLarge,
        responses::UnsupportedMediaType,
        responses::Invalid,
        responses::QueueFull,
        responses::Unavailable,
        responses::RequestTimeout,
        responses::Unauthorized,
        )
    ),
    modifiers(&BearerTokens)
)]
struct ApiDoc;

/// The optional bearer tokens: every `/v1` operation accepts a token (required when the
/// service is configured with tokens) and may answer 401.
struct BearerTokens;

impl utoipa::Modify for BearerTokens {
    fn modify(&self, doc: &mut utoipa::openapi::OpenApi) {
        use utoipa::openapi::security::{
            HttpAuthScheme, HttpBuilder, SecurityRequirement, SecurityScheme,
        };
        use utoipa::openapi::{Ref, RefOr};
        if let Some(c) = doc.components.as_mut() {
            c.add_security_scheme(
                "bearer",
                SecurityScheme::Http(HttpBuilder::new().scheme(HttpAuthScheme::Bearer).build()),
            );
        }
        for (path, item) in doc.paths.paths.iter_mut() {
            if !path.starts_with("/v1/") {
                continue;
            }
            for op in [
                item.get.as_mut(),
                item.post.as_mut(),
                item.delete.as_mut(),
                item.put.as_mut(),
                item.patch.as_mut(),
            ]
            .into_iter()
            .flatten()
            {
                // anonymous (a service without tokens) or a bearer token
                op.security = Some(vec![
                    SecurityRequirement::default(),
                    SecurityRequirement::new("bearer", Vec::<String>::new()),
                ]);
                op.responses.responses.insert(
                    "401".into(),
                    RefOr::Ref(Ref::from_response_name("Unauthorized")),
                );
            }
        }
    }
}

/// The document.
pub fn document() -> utoipa::openapi::OpenApi {
    ApiDoc::openapi()
}

/// The document as YAML (built once).
pub fn yaml() -> &'static str {
    static YAML: OnceLock<String> = OnceLock::new();
    YAML.get_or_init(|| {
        document()
            .to_yaml()
            .expect("the OpenAPI document serializes to YAML")
    })
}
