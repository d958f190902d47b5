//! `openapi.yaml` is the committed output of the document the code generates: a hand
//! edit, or a handler or type change not regenerated, fails here.
//!
//! Regenerate with `BEARING_SIM_UPDATE_OPENAPI=1 cargo test --release --test checks openapi`.

use std::path::Path;

#[test]
fn committed_openapi_yaml_is_the_generated_document() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("openapi.yaml");
    let generated = bearing_sim::api::openapi::yaml();
    if std::env::var_os("BEARING_SIM_UPDATE_OPENAPI").is_some() {
        std::fs::write(&path, generated).unwrap();
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap();
    if committed != generated {
        let line = committed
            .lines()
            .zip(generated.lines())
            .position(|(a, b)| a != b)
            .unwrap_or_else(|| committed.lines().count().min(generated.lines().count()));
        panic!(
            "openapi.yaml differs from the document the code generates, first at line {}:\n  committed: {:?}\n  generated: {:?}\n\
             Edit the handlers' #[utoipa::path] annotations or the types, then regenerate:\n  \
             BEARING_SIM_UPDATE_OPENAPI=1 cargo test --release --test checks openapi",
            line + 1,
            committed.lines().nth(line).unwrap_or("<end of file>"),
            generated.lines().nth(line).unwrap_or("<end of file>"),
        );
    }
}

#[test]
fn the_document_names_its_problem_and_scene_schemas() {
    // The scene's sub-objects have real schemas (so fuzzers generate meaningful scenes).
    let doc = bearing_sim::api::openapi::document();
    let schemas = &doc.components.as_ref().unwrap().schemas;
    for name in [
        "Scene",
        "Bearing",
        "Cage",
        "Materials",
        "Lubricant",
        "Traction",
        "Operating",
        "SpeedProfile",
        "Pedestal",
        "Fault",
        "Solver",
        "Outputs",
        "Problem",
        "JobView",
        "SimulationResult",
        "SpectrumView",
        "AnalysisReport",
    ] {
        assert!(schemas.contains_key(name), "no schema {name}");
    }
}
