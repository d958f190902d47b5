//! Bearing presets: full simulation scenes (H7005C with its fault cases and the Table 2
//! groups) and kinematic-only geometries for analysing measurements (CWRU 6205).

use super::problem::{ApiResult, Problem};
use axum::extract::Path;
use axum::response::{IntoResponse, Response};
use axum::Json;
use bearing_core::scene::{fault_case_scene, preset_names, preset_scene, table2_groups, FaultCase};
use bearing_core::signal::frequencies::{
    kinematic_preset, kinematic_preset_names, KinematicGeometry,
};
use serde_json::{json, Value};

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

fn summary(name: &str) -> Option<Value> {
    let scene = preset_scene(name);
    let kin = kinematic_preset(name).or_else(|| {
        scene
            .as_ref()
            .map(|s| KinematicGeometry::from_bearing(&s.bearing))
    })?;
    Some(json!({
        "name": name,
        "title": scene.as_ref().map(|s| s.name.clone()).unwrap_or_else(|| name.to_uppercase()),
        "simulation": scene.is_some(),
        "fault_cases": if scene.is_some() { json!(FAULT_CASES.iter().map(|c| c.0).collect::<Vec<_>>()) } else { json!([]) },
        "kinematics": kin,
        "links": {"self": format!("/v1/presets/{name}")},
    }))
}

pub async fn list() -> Response {
    let items: Vec<Value> = names().iter().filter_map(|n| summary(n)).collect();
    Json(json!({ "items": items })).into_response()
}

pub async fn get(Path(name): Path<String>) -> ApiResult<Response> {
    let name = name.to_ascii_lowercase();
    let mut body = summary(&name).ok_or_else(|| {
        Problem::not_found(format!(
            "no preset named '{name}'; presets: {}",
            names().join(", ")
        ))
    })?;
    if let Some(scene) = preset_scene(&name) {
        body["scene"] = json!(scene);
        let mut cases = serde_json::Map::new();
        for (label, case) in FAULT_CASES {
            if let Some(s) = fault_case_scene(&name, case) {
                cases.insert(label.into(), json!({ "name": s.name, "faults": s.faults }));
            }
        }
        body["fault_case_faults"] = Value::Object(cases);
        if name == "h7005c" {
            body["table2_groups"] = json!(table2_groups());
        }
    }
    Ok(Json(body).into_response())
}
