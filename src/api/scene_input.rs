//! The two ways a request names a scene: inline, or a preset with a fault case and a
//! merge patch of overrides.

use super::extract::{from_value, kind_of};
use super::merge_patch::merge_patch;
use super::problem::{FieldProblem, Problem};
use bearing_core::scene::{fault_case_scene, preset_names, FaultCase, Scene, ValidScene};
use serde_json::{Map, Value};

/// Resolve and validate the scene of a request body (the one validation a request gets).
/// `extra` lists the other top-level members the endpoint accepts; any member not known
/// is a 422.
pub fn resolve_scene(body: &mut Map<String, Value>, extra: &[&str]) -> Result<ValidScene, Problem> {
    let known = ["scene", "preset", "fault_case", "overrides"];
    let mut errors: Vec<FieldProblem> = body
        .keys()
        .filter(|k| !known.contains(&k.as_str()) && !extra.contains(&k.as_str()))
        .map(|k| FieldProblem {
            path: k.clone(),
            message: format!(
                "unknown member; expected one of {}",
                known
                    .iter()
                    .chain(extra)
                    .cloned()
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        })
        .collect();
    let scene_value = match (body.remove("scene"), body.remove("preset")) {
        (Some(_), Some(_)) => {
            errors.push(FieldProblem {
                path: "preset".into(),
                message: "give either scene or preset, not both".into(),
            });
            None
        }
        (None, None) => {
            errors.push(FieldProblem {
                path: "scene".into(),
                message: "required: a scene object, or a preset name".into(),
            });
            None
        }
        (Some(scene), None) => {
            for k in ["fault_case", "overrides"] {
                if body.contains_key(k) {
                    errors.push(FieldProblem {
                        path: k.into(),
                        message: "only allowed with preset".into(),
                    });
                }
            }
            Some(scene)
        }
        (None, Some(preset)) => preset_value(
            preset,
            body.remove("fault_case"),
            body.remove("overrides"),
            &mut errors,
        ),
    };
    if !errors.is_empty() {
        return Err(Problem::validation(errors));
    }
    let scene_value = scene_value.expect("set when there are no errors");
    if !scene_value.is_object() {
        return Err(Problem::field(
            "scene",
            format!("must be an object, got {}", kind_of(&scene_value)),
        ));
    }
    let scene: Scene = from_value(scene_value, "scene")?;
    ValidScene::new(scene).map_err(|e| Problem::scene_invalid("scene", &e))
}

fn preset_value(
    preset: Value,
    case: Option<Value>,
    overrides: Option<Value>,
    errors: &mut Vec<FieldProblem>,
) -> Option<Value> {
    let names = preset_names().join(", ");
    let Value::String(name) = preset else {
        errors.push(FieldProblem {
            path: "preset".into(),
            message: format!("must be a string, one of {names}"),
        });
        return None;
    };
    let case = match case {
        None => Some(FaultCase::None),
        Some(Value::String(c)) => match c.parse::<FaultCase>() {
            Ok(c) => Some(c),
            Err(m) => {
                errors.push(FieldProblem {
                    path: "fault_case".into(),
                    message: m,
                });
                None
            }
        },
        Some(other) => {
            errors.push(FieldProblem {
                path: "fault_case".into(),
                message: format!("must be a string, got {}", kind_of(&other)),
            });
            None
        }
    };
    let scene = fault_case_scene(&name, case.unwrap_or(FaultCase::None));
    if scene.is_none() {
        errors.push(FieldProblem {
            path: "preset".into(),
            message: format!("unknown preset '{name}'; simulation presets: {names}"),
        });
    }
    match &overrides {
        None | Some(Value::Object(_)) => {}
        Some(other) => errors.push(FieldProblem {
            path: "overrides".into(),
            message: format!(
                "must be an object (a JSON merge patch), got {}",
                kind_of(other)
            ),
        }),
    }
    case?;
    let mut v = serde_json::to_value(scene?).ok()?;
    if let Some(p @ Value::Object(_)) = &overrides {
        merge_patch(&mut v, p);
    }
    Some(v)
}
