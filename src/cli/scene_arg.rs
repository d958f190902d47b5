//! Resolving the SCENE argument: a scene file or a preset name.

use bearing_core::scene::{fault_case_scene, preset_names, FaultCase, Scene, ValidScene};

/// Load a scene from a JSON file, or build a preset (with `fault` applied) by name. The
/// caller may still edit it; it is validated once more when it is made a `ValidScene`.
pub fn load_scene(
    arg: &str,
    fault: Option<FaultCase>,
) -> Result<Scene, Box<dyn std::error::Error>> {
    if preset_names().contains(&arg.to_ascii_lowercase().as_str()) {
        return Ok(fault_case_scene(arg, fault.unwrap_or(FaultCase::None)).expect("listed preset"));
    }
    let text = std::fs::read_to_string(arg).map_err(|e| {
        format!(
            "SCENE '{arg}' is neither a preset ({}) nor a readable file: {e}",
            preset_names().join(", ")
        )
    })?;
    let mut scene = ValidScene::from_json(&text)
        .map_err(|e| format!("{arg}: {e}"))?
        .into_scene();
    if let Some(f) = fault {
        if f != FaultCase::None || !scene.faults.is_empty() {
            return Err(
                "--fault only applies to preset scenes; edit the scene's `faults` instead".into(),
            );
        }
        scene.faults.clear();
    }
    Ok(scene)
}
