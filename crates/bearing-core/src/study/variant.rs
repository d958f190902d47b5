//! Lubricant variants as data: the physics a trend study runs under (docs/reference/model.md,
//! "Lubricant drag", "EHL rolling resistance", "Traction laws"), each a set of scene fields
//! a named design assigns over its base.

use crate::scene::{CavityDrag, Lubricant, RollingResistanceModel, Traction};
use serde::{Deserialize, Serialize};
use serde_json::Value;

/// The lubricant physics a point runs with. The seed paper's model is `paper`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LubricantVariant {
    /// Short name used in tables, labels and file names.
    pub name: String,
    pub cavity_drag: CavityDrag,
    pub rolling_resistance: RollingResistanceModel,
    /// Named by every variant, so a point runs the same law whatever the base's.
    pub traction: Traction,
}

impl LubricantVariant {
    /// Assign the variant's parts over a scene's lubricant.
    pub fn apply_to(&self, lubricant: &mut Lubricant) {
        lubricant.cavity_drag = self.cavity_drag;
        lubricant.rolling_resistance = self.rolling_resistance;
        lubricant.traction = self.traction;
    }

    /// The seed paper's lubricant: no drag, no rolling resistance, the eq. 15 curve (the
    /// base's integrator stays: the preset's `auto_etd`, where the paper's model as the
    /// lab docs ran it used `rk4_fsal`).
    pub fn paper() -> Self {
        LubricantVariant {
            name: "paper".into(),
            cavity_drag: CavityDrag::None,
            rolling_resistance: RollingResistanceModel::None,
            traction: Traction::PAPER_CURVE,
        }
    }

    /// The scene fields the variant sets, as (JSON pointer, value): whole members, so a
    /// traction law replaces the base's whatever its model.
    pub fn sets(&self) -> Vec<(String, Value)> {
        vec![
            (
                "/lubricant/cavity_drag".to_string(),
                value(&self.cavity_drag),
            ),
            (
                "/lubricant/rolling_resistance".to_string(),
                value(&self.rolling_resistance),
            ),
            ("/lubricant/traction".to_string(), value(&self.traction)),
        ]
    }
}

fn value<T: Serialize>(part: &T) -> Value {
    serde_json::to_value(part).expect("scene parts serialize")
}

/// Every named variant: the paper's model (its eq. 15 curve), the rheology law alone, with
/// rolling resistance (the preset's physics since 2026-11-29) and with drag as well, and
/// with each uncertain coefficient at the ends of its read range, the curve with each added
/// term alone, both together and a richer oil-air mixture, and the earlier film law's
/// variants (to reproduce its study). Every variant names its traction law, so what it
/// runs does not follow the preset's.
pub fn lubricant_variants() -> Vec<LubricantVariant> {
    let drag = |x| CavityDrag::OilAir { oil_fraction: x };
    let houpert = RollingResistanceModel::Houpert { factor: 1.0 };
    // the paper's curve with added terms, as these variants were run before the preset's
    // law changed
    let v = |name: &str, cavity_drag, rolling_resistance| LubricantVariant {
        name: name.into(),
        cavity_drag,
        rolling_resistance,
        traction: Traction::PAPER_CURVE,
    };
    // a traction law, alone or with drag (oil fraction 0.01) and rolling resistance
    let law = |name: &str, traction, with_drag: bool| {
        let (cavity_drag, rolling_resistance) = if with_drag {
            (drag(0.01), houpert)
        } else {
            (CavityDrag::None, RollingResistanceModel::None)
        };
        LubricantVariant {
            name: name.into(),
            cavity_drag,
            rolling_resistance,
            traction,
        }
    };
    let film = |name: &str, shear_modulus, eyring_stress, limiting_coefficient, with_drag| {
        let traction = Traction::Film {
            shear_modulus,
            eyring_stress,
            limiting_coefficient,
        };
        law(name, traction, with_drag)
    };
    let rheology = |name: &str, limiting_coefficient, roelands_z, with_drag| {
        let traction = Traction::Rheology {
            limiting_coefficient,
            roelands_z,
        };
        law(name, traction, with_drag)
    };
    vec![
        LubricantVariant::paper(),
        // the preset's law alone, with rolling resistance (the preset's physics) and with
        // drag too, and each uncertain coefficient at the ends of its read range
        // (Lambda: PAO 0.035 to naphthenic 0.053; Z: 0.60 mineral typical to 0.81, the
        // second spindle oil of Stachowiak & Batchelor's Table 2.3)
        rheology("rheology", 0.047, None, false),
        LubricantVariant {
            name: "rheology+rolling".into(),
            cavity_drag: CavityDrag::None,
            rolling_resistance: houpert,
            traction: Traction::RHEOLOGY,
        },
        rheology("rheology+drag+rolling", 0.047, None, true),
        rheology("rheology-L0.035", 0.035, None, false),
        rheology("rheology-L0.053", 0.053, None, false),
        rheology("rheology-Z0.60", 0.047, Some(0.60), false),
        rheology("rheology-Z0.81", 0.047, Some(0.81), false),
        v("drag", drag(0.01), RollingResistanceModel::None),
        v("rolling", CavityDrag::None, houpert),
        v("drag+rolling", drag(0.01), houpert),
        v("drag5+rolling", drag(0.05), houpert),
        film("film", 1e9, 5e6, 0.07, false),
        film("film+drag+rolling", 1e9, 5e6, 0.07, true),
        film("film-G0.3", 0.3e9, 5e6, 0.07, false),
        film("film-G2", 2e9, 5e6, 0.07, false),
        film("film-tau2", 1e9, 2e6, 0.07, false),
        film("film-tau10", 1e9, 10e6, 0.07, false),
        film("film-L0.05", 1e9, 5e6, 0.05, false),
        film("film-L0.10", 1e9, 5e6, 0.10, false),
    ]
}

/// The catalogue's variant of that name; the error lists the names.
pub fn lubricant_variant(name: &str) -> Result<LubricantVariant, String> {
    let all = lubricant_variants();
    let names: Vec<&str> = all.iter().map(|v| v.name.as_str()).collect();
    let names = names.join(", ");
    all.iter()
        .find(|v| v.name == name)
        .cloned()
        .ok_or_else(|| format!("unknown lubricant variant '{name}'; variants: {names}"))
}
