//! Bearing presets: full simulation scenes (H7005C with its fault cases and the Table 2
//! groups) and kinematic-only geometries for analysing measurements (CWRU 6205).

use super::openapi::responses::NotFound;
use super::problem::{ApiResult, Problem};
use axum::extract::Path;
use axum::response::{IntoResponse, Response};
use axum::Json;
use bearing_core::scene::{
    fault_case_scene, preset_names, preset_scene, table2_groups, Fault, FaultCase, Scene,
    Table2Group,
};
use bearing_core::signal::frequencies::{
    kinematic_preset, kinematic_preset_names, KinematicGeometry,
};
use serde::Serialize;
use std::collections::BTreeMap;
use utoipa::ToSchema;

const FAULT_CASES: [(&str, FaultCase); 4] = [
    ("none", FaultCase::None),
    ("inner", FaultCase::Inner),
    ("outer", FaultCase::Outer),
    ("compound", FaultCase::Compound),
];

fn names() -> Vec<String> {
    let mut v: Vec<String> = preset_names().iter().map(|s| s.to_string()).collect();
    for k in kinematic_preset_names() {
        if !v.iter().any(|n| n == k) {
            v.push(k.to_string());
        }
    }
    v
}

/// A preset: a bearing geometry, and for simulation presets a full scene.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct PresetSummary {
    pub name: String,
    pub title: String,
    /// True for presets with a full scene (usable in `POST /v1/simulations`).
    pub simulation: bool,
    /// Fault cases of a simulation preset (empty for kinematic-only presets).
    pub fault_cases: Vec<FaultCase>,
    pub kinematics: KinematicGeometry,
    /// `self`.
    pub links: BTreeMap<String, String>,
}

/// A preset with its scene, the faults of each fault case and (H7005C) the Table 2 groups.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct Preset {
    #[serde(flatten)]
    pub summary: PresetSummary,
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(required = false, nullable = false)]
    pub scene: Option<Scene>,
    /// Per fault case: the scene name and its faults.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(required = false, nullable = false)]
    pub fault_case_faults: Option<BTreeMap<String, FaultCaseFaults>>,
    /// The nine fault-size groups of the paper's Table 2.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(required = false, nullable = false)]
    pub table2_groups: Option<Vec<Table2Group>>,
}

/// What a fault case changes in a preset.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct FaultCaseFaults {
    pub name: String,
    pub faults: Vec<Fault>,
}

/// Every preset.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct PresetList {
    pub items: Vec<PresetSummary>,
}

fn summary(name: &str) -> Option<PresetSummary> {
    let scene = preset_scene(name);
    let kinematics = kinematic_preset(name).or_else(|| {
        scene
            .as_ref()
            .map(|s| KinematicGeometry::from_bearing(&s.bearing))
    })?;
    Some(PresetSummary {
        name: name.to_string(),
        title: scene
            .as_ref()
            .map(|s| s.name.clone())
            .unwrap_or_else(|| name.to_uppercase()),
        simulation: scene.is_some(),
        fault_cases: if scene.is_some() {
            FAULT_CASES.iter().map(|c| c.1).collect()
        } else {
            vec![]
        },
        kinematics,
        links: BTreeMap::from([("self".to_string(), format!("/v1/presets/{name}"))]),
    })
}

/// Bearing presets
#[utoipa::path(
    get,
    path = "/v1/presets",
    tag = "models",
    operation_id = "listPresets",
    responses((status = 200, description = "Presets.", body = PresetList))
)]
pub async fn list() -> Response {
    let items = names().iter().filter_map(|n| summary(n)).collect();
    Json(PresetList { items }).into_response()
}

/// One preset with its scene, fault cases and (H7005C) Table 2 groups
#[utoipa::path(
    get,
    path = "/v1/presets/{name}",
    tag = "models",
    operation_id = "getPreset",
    params(("name" = String, Path, description = "Preset name.", example = "h7005c")),
    responses(
        (status = 200, description = "The preset.", body = Preset),
        (status = 404, response = NotFound),
    )
)]
pub async fn get(Path(name): Path<String>) -> ApiResult<Response> {
    let name = name.to_ascii_lowercase();
    let summary = summary(&name).ok_or_else(|| {
        Problem::not_found(format!(
            "no preset named '{name}'; presets: {}",
            names().join(", ")
        ))
    })?;
    let scene = preset_scene(&name);
    let fault_case_faults = scene.as_ref().map(|_| {
        FAULT_CASES
            .iter()
            .filter_map(|(label, case)| {
                fault_case_scene(&name, *case).map(|s| {
                    (
                        label.to_string(),
                        FaultCaseFaults {
                            name: s.name,
                            faults: s.faults,
                        },
                    )
                })
            })
            .collect()
    });
    let table2_groups = (name == "h7005c").then(table2_groups);
    Ok(Json(Preset {
        summary,
        scene,
        fault_case_faults,
        table2_groups,
    })
    .into_response())
}
