//! The two ways a request names a scene: inline, or a preset with a fault case and a
//! merge patch of overrides.

use super::extract::{from_value, kind_of};
use super::problem::{FieldProblem, Problem};
use bearing_core::scene::{
    apply_overrides, fault_case_scene, preset_names, FaultCase, Scene, ValidScene,
};
use serde::Deserialize;
use serde_json::{Map, Value};
use utoipa::ToSchema;

// What the OpenAPI document says a request naming a scene looks like. The handlers parse
// the body as JSON and resolve it with `resolve_scene` (for its merge patch and its error
// paths); tests check that these types and that function agree. Only the document and the
// tests read their fields.

/// An inline scene, or a preset with a fault case and merge-patch overrides.
#[derive(Deserialize, ToSchema)]
#[serde(untagged)]
#[allow(dead_code, clippy::large_enum_variant)] // parsed only in tests
pub enum SimulationRequest {
    Inline(InlineScene),
    Preset(PresetReference),
}

/// A complete scene.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[allow(dead_code)]
pub struct InlineScene {
    pub scene: Scene,
}

/// A preset scene, with a fault case and a JSON merge patch (RFC 7396) of overrides.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[allow(dead_code)]
pub struct PresetReference {
    pub preset: SimulationPreset,
    /// Default `none`.
    #[serde(default)]
    #[schema(nullable = false)]
    pub fault_case: Option<FaultCase>,
    /// JSON merge patch (RFC 7396) over the preset scene, e.g. `{"solver": {"duration": 0.02}}`.
    /// A lubricant model named anew replaces the preset's whole: `{"lubricant": {"traction":
    /// {"model": "abcd"}}}` is the paper's eq. 15 curve with its defaults.
    #[serde(default)]
    #[schema(value_type = Option<Object>, nullable = false, example = json!({"solver": {"duration": 0.02}}))]
    pub overrides: Option<Value>,
}

/// Presets with a full scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum SimulationPreset {
    H7005c,
}

/// A scene as for simulations (`scene`, or `preset` with optional `fault_case` and
/// `overrides`), and a shaft speed (default: the scene's steady speed).
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[allow(dead_code)]
pub struct QuasiStaticRequest {
    #[schema(nullable = false)]
    pub scene: Option<Scene>,
    #[schema(nullable = false)]
    pub preset: Option<SimulationPreset>,
    #[schema(nullable = false)]
    pub fault_case: Option<FaultCase>,
    #[schema(value_type = Option<Object>, nullable = false)]
    pub overrides: Option<Value>,
    /// Shaft speed, rev/min.
    #[schema(exclusive_minimum = 0.0, maximum = 100000.0, nullable = false)]
    pub shaft_rpm: Option<f64>,
    /// Also the cage speed by the pocket cycle (`pocket_cycle` in the answer), under the
    /// paper's curve and the preset's physics closer to a running cage than the steady
    /// balance: at 10000 rpm about 0.5 s under the paper's curve and 4-6 s under the preset's
    /// physics, longer at low speed (4.5 s at 1000 rpm under the curve; 9-17 s at 2000 rpm
    /// and 26-30 s at 1000 rpm under the preset's physics, which may exceed the request
    /// timeout).
    #[schema(nullable = false)]
    pub pocket_cycle: Option<bool>,
}

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
        apply_overrides(&mut v, p);
    }
    Some(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn the_documented_presets_are_the_simulation_presets() {
        for name in preset_names() {
            assert!(
                serde_json::from_value::<SimulationPreset>(json!(name)).is_ok(),
                "add {name} to SimulationPreset"
            );
        }
        // one variant: a preset removed from the engine must leave the document too
        assert_eq!(preset_names(), &["h7005c"]);
    }

    #[test]
    fn documented_request_shapes_resolve() {
        let preset = json!({"preset": "h7005c", "fault_case": "compound", "overrides": {"solver": {"duration": 0.02}}});
        assert!(serde_json::from_value::<SimulationRequest>(preset.clone()).is_ok());
        let mut body = preset.as_object().unwrap().clone();
        let scene = resolve_scene(&mut body, &[]).unwrap();
        assert_eq!(scene.solver.duration, 0.02);
        let inline = json!({"scene": scene.scene()});
        assert!(serde_json::from_value::<SimulationRequest>(inline.clone()).is_ok());
        assert!(resolve_scene(&mut inline.as_object().unwrap().clone(), &[]).is_ok());
        let qs = json!({"preset": "h7005c", "shaft_rpm": 10000.0});
        assert!(serde_json::from_value::<QuasiStaticRequest>(qs.clone()).is_ok());
        assert!(resolve_scene(&mut qs.as_object().unwrap().clone(), &["shaft_rpm"]).is_ok());
    }
}
