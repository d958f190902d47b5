//! A preset's overrides: a JSON merge patch (RFC 7396) over the preset's scene, in which a
//! lubricant model named anew replaces the preset's whole
//! ([`crate::json_doc::merge_patch_tagged`]): `{"lubricant": {"traction": {"model":
//! "rheology"}}}` selects the rheology law with its defaults, where a plain merge would
//! keep the curve's `a`..`d` and fail as unknown fields of the new law.

use crate::json_doc::merge_patch_tagged;
use serde_json::Value;

/// The member that names the variant of the scene's tagged unions (`lubricant.traction`,
/// `lubricant.cavity_drag`, `lubricant.rolling_resistance`).
pub const VARIANT_TAG: &str = "model";

/// Apply `overrides` to the scene document `scene`.
pub fn apply_overrides(scene: &mut Value, overrides: &Value) {
    merge_patch_tagged(scene, overrides, VARIANT_TAG);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{preset_scene, RollingResistanceModel, Scene, Traction};
    use serde_json::json;

    #[test]
    fn naming_another_law_selects_it_with_its_defaults() {
        let mut v = serde_json::to_value(preset_scene("h7005c").unwrap()).unwrap();
        apply_overrides(
            &mut v,
            &json!({"lubricant": {
                "traction": {"model": "rheology"},
                "rolling_resistance": {"model": "houpert"},
                "density": 860.0
            }}),
        );
        let s: Scene = serde_json::from_value(v).expect("the patched scene parses");
        assert_eq!(s.lubricant.traction, Traction::RHEOLOGY);
        assert_eq!(
            s.lubricant.rolling_resistance,
            RollingResistanceModel::Houpert { factor: 1.0 }
        );
        assert_eq!(s.lubricant.density, 860.0);
        // the rest of the preset is untouched
        let preset = preset_scene("h7005c").unwrap();
        assert_eq!(s.bearing, preset.bearing);
        assert_eq!(
            s.lubricant.dynamic_viscosity,
            preset.lubricant.dynamic_viscosity
        );
    }

    #[test]
    fn a_field_of_the_presets_own_law_still_merges() {
        let mut v = serde_json::to_value(preset_scene("h7005c").unwrap()).unwrap();
        apply_overrides(&mut v, &json!({"lubricant": {"traction": {"d": 0.03}}}));
        let s: Scene = serde_json::from_value(v).unwrap();
        let Traction::Abcd { a, d, .. } = s.lubricant.traction else {
            panic!("still the curve: {:?}", s.lubricant.traction)
        };
        assert_eq!((a, d), (-0.036, 0.03));
    }
}
