//! A scene that passed validation: the only input the engine accepts.

use super::definition::Scene;
use super::validate::ValidationErrors;
use serde::{Deserialize, Serialize};
use std::ops::Deref;

/// A [`Scene`] known to be valid. Only validation makes one ([`ValidScene::new`],
/// [`Scene::validated`], or deserializing, which validates what it parses), so code that
/// holds one never checks again.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(transparent)]
pub struct ValidScene(Scene);

impl ValidScene {
    /// Validate `scene`; every problem is reported at once with its field path.
    pub fn new(scene: Scene) -> Result<ValidScene, ValidationErrors> {
        scene.validate()?;
        Ok(ValidScene(scene))
    }

    /// Parse and validate a scene from JSON text.
    pub fn from_json(text: &str) -> Result<ValidScene, ValidationErrors> {
        let scene: Scene =
            serde_json::from_str(text).map_err(|e| ValidationErrors::from_serde(&e))?;
        ValidScene::new(scene)
    }

    pub fn scene(&self) -> &Scene {
        &self.0
    }

    /// Back to a plain scene, e.g. to edit it (it must be validated again to run).
    pub fn into_scene(self) -> Scene {
        self.0
    }
}

impl Deref for ValidScene {
    type Target = Scene;
    fn deref(&self) -> &Scene {
        &self.0
    }
}

impl Scene {
    /// A validated copy of this scene.
    pub fn validated(&self) -> Result<ValidScene, ValidationErrors> {
        ValidScene::new(self.clone())
    }

    /// Traction samples per contact: `solver.traction_strips`, or the lubricant's law's
    /// own when the scene names none (resolved here, not stored, so a scene whose law is
    /// changed takes the new law's).
    pub fn traction_strips(&self) -> usize {
        self.solver.traction_strips.unwrap_or_else(|| {
            self.lubricant
                .traction
                .default_strips(self.solver.traction_quadrature)
        })
    }
}

/// Stored scenes are parsed back through validation: storage is a boundary too.
impl<'de> Deserialize<'de> for ValidScene {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let scene = Scene::deserialize(d)?;
        ValidScene::new(scene).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_valid_scene_becomes_one() {
        let mut s = crate::scene::preset_scene("h7005c").unwrap();
        assert!(s.validated().is_ok());
        s.bearing.ball_diameter = -1.0;
        let errs = ValidScene::new(s.clone()).unwrap_err();
        assert!(
            errs.0.iter().any(|e| e.path == "bearing.ball_diameter"),
            "{errs}"
        );
        let text = serde_json::to_string(&s).unwrap();
        let err = serde_json::from_str::<ValidScene>(&text).unwrap_err();
        assert!(err.to_string().contains("bearing.ball_diameter"), "{err}");
    }

    #[test]
    fn round_trips_through_json() {
        let v = crate::scene::preset_scene("h7005c")
            .unwrap()
            .validated()
            .unwrap();
        let text = serde_json::to_string(&v).unwrap();
        assert_eq!(serde_json::from_str::<ValidScene>(&text).unwrap(), v);
        assert_eq!(ValidScene::from_json(&text).unwrap(), v);
    }

    /// A scene stored before `solver.traction_quadrature` existed reads as `gauss`;
    /// `equal_strips` round-trips; an unknown rule is refused naming the value.
    #[test]
    fn traction_quadrature_defaults_to_gauss_and_round_trips() {
        use crate::scene::TractionQuadrature;
        let s = crate::scene::preset_scene("h7005c").unwrap();
        let mut json = serde_json::to_value(&s).unwrap();
        let solver = json["solver"].as_object_mut().unwrap();
        assert_eq!(solver.remove("traction_quadrature").unwrap(), "gauss");
        let old = ValidScene::from_json(&json.to_string()).unwrap();
        assert_eq!(
            old.scene().solver.traction_quadrature,
            TractionQuadrature::Gauss
        );
        json["solver"]["traction_quadrature"] = "equal_strips".into();
        let eq = ValidScene::from_json(&json.to_string()).unwrap();
        assert_eq!(
            eq.scene().solver.traction_quadrature,
            TractionQuadrature::EqualStrips
        );
        let text = serde_json::to_string(&eq).unwrap();
        assert_eq!(ValidScene::from_json(&text).unwrap(), eq);
        json["solver"]["traction_quadrature"] = "simpson".into();
        let err = ValidScene::from_json(&json.to_string()).unwrap_err();
        assert!(err.to_string().contains("simpson"), "{err}");
    }
}
