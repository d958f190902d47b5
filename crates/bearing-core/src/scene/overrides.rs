//! A preset's overrides: a JSON merge patch (RFC 7396) over the preset's scene, in which a
//! lubricant model named anew replaces the preset's whole
//! ([`crate::json_doc::merge_patch_tagged`]): `{"lubricant": {"traction": {"model":
//! "abcd"}}}` selects the paper's curve with its defaults, where a plain merge would keep the
//! preset's rheology law's fields and fail as unknown fields of the curve.

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
                "traction": {"model": "abcd"},
                "rolling_resistance": {"model": "none"},
                "density": 860.0
            }}),
        );
        let s: Scene = serde_json::from_value(v).expect("the patched scene parses");
        // the curve's own coefficients, not the rheology law's fields merged into it
        assert_eq!(s.lubricant.traction, Traction::PAPER_CURVE);
        assert_eq!(s.lubricant.rolling_resistance, RollingResistanceModel::None);
        assert_eq!(s.lubricant.density, 860.0);
        // with it the law's own traction samples (10 points; the preset's rheology law takes
        // 4 cell means), unless the overrides name a count
        assert_eq!(preset_scene("h7005c").unwrap().traction_strips(), 4);
        assert_eq!(s.solver.traction_strips, None);
        assert_eq!(s.traction_strips(), 10);
        let mut named = s.clone();
        named.solver.traction_strips = Some(4);
        assert_eq!(named.traction_strips(), 4);
        // 4 was measured for the rheology law's Gauss nodes only: its equal strips keep 10
        let mut equal = preset_scene("h7005c").unwrap();
        equal.solver.traction_quadrature = crate::scene::TractionQuadrature::EqualStrips;
        assert_eq!(equal.traction_strips(), 10);
        // the rest of the preset is untouched
        let preset = preset_scene("h7005c").unwrap();
        assert_eq!(s.bearing, preset.bearing);
        assert_eq!(
            s.lubricant.dynamic_viscosity,
            preset.lubricant.dynamic_viscosity
        );
    }

    /// The rule replaces any object whose `model` changes: only the tagged unions may have
    /// a member of that name (a plain field called `model` would be replaced, not merged).
    #[test]
    fn only_the_tagged_unions_have_a_model_member() {
        fn walk(v: &Value, path: String, out: &mut Vec<String>) {
            if let Value::Object(m) = v {
                if m.contains_key(VARIANT_TAG) {
                    out.push(path.clone());
                }
                for (k, x) in m {
                    walk(x, format!("{path}/{k}"), out);
                }
            } else if let Value::Array(a) = v {
                for (i, x) in a.iter().enumerate() {
                    walk(x, format!("{path}/{i}"), out);
                }
            }
        }
        let mut found = Vec::new();
        let scene = crate::scene::fault_case_scene("h7005c", crate::scene::FaultCase::Compound);
        walk(
            &serde_json::to_value(scene.unwrap()).unwrap(),
            String::new(),
            &mut found,
        );
        found.sort();
        assert_eq!(
            found,
            [
                "/lubricant/cavity_drag",
                "/lubricant/rolling_resistance",
                "/lubricant/traction"
            ]
        );
    }

    #[test]
    fn a_field_of_the_presets_own_law_still_merges() {
        let mut v = serde_json::to_value(preset_scene("h7005c").unwrap()).unwrap();
        apply_overrides(
            &mut v,
            &json!({"lubricant": {"traction": {"limiting_coefficient": 0.06}}}),
        );
        let s: Scene = serde_json::from_value(v).unwrap();
        let Traction::Rheology {
            limiting_coefficient,
            roelands_z,
        } = s.lubricant.traction
        else {
            panic!("still the rheology law: {:?}", s.lubricant.traction)
        };
        assert_eq!((limiting_coefficient, roelands_z), (0.06, None));
    }
}
