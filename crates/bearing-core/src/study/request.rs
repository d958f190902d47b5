//! What a study request says: a base scene and a design of points over it.

use crate::scene::FaultCase;
use serde::{Deserialize, Serialize};
use serde_json::Value;

/// A parameter study: every point is the base scene with some fields set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct StudyRequest {
    /// Label shown in listings and plot titles (default: the design's and the base scene's).
    #[serde(default)]
    #[cfg_attr(feature = "openapi", schema(max_length = 200))]
    pub name: Option<String>,
    pub base: StudyBase,
    pub design: DesignSpec,
}

/// The scene every point starts from: an inline `scene`, or a `preset` with an optional
/// `fault_case` and `overrides` (a JSON merge patch, RFC 7396), as for simulations.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct StudyBase {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "openapi", schema(value_type = Option<crate::scene::Scene>))]
    pub scene: Option<Value>,
    /// `h7005c`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "openapi", schema(example = "h7005c"))]
    pub preset: Option<String>,
    /// Default `none`; a design's `fault_cases` replace it point by point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fault_case: Option<FaultCase>,
    /// JSON merge patch over the preset scene, e.g. `{"solver": {"duration": 0.05}}`; a
    /// lubricant model named anew replaces the preset's whole, as for simulations.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Object>))]
    pub overrides: Option<Value>,
}

/// Which points a study runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum DesignSpec {
    /// Every combination of the factors' values (and of the fault cases, if given).
    Grid {
        #[serde(default)]
        factors: Vec<FactorSpec>,
        /// Run the design once per fault case (needs a `preset` base).
        #[serde(default)]
        fault_cases: Vec<FaultCase>,
    },
    /// Each factor varied alone, the others at the base scene's values (Figures 23-28).
    OneAtATime {
        factors: Vec<FactorSpec>,
        /// Run the design once per fault case (needs a `preset` base).
        #[serde(default)]
        fault_cases: Vec<FaultCase>,
    },
    /// A design shipped with the engine, optionally under lubricant variants.
    Named {
        name: NamedDesign,
        /// Lubricant variants to run the design under (docs/lab/paper-trends.md: `paper`,
        /// `drag`, `film`, `film-G0.3`, ...): each sets the base's cavity drag, rolling
        /// resistance and traction, and labels its points. `paper-trends` and `table2`
        /// take at most one; `sensitivity` runs every variant given (default: all).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        variants: Vec<String>,
    },
}

/// Designs shipped as data (docs/guide/studies.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub enum NamedDesign {
    /// Figures 23-28: shaft speed, axial load and radial load lines for single inner and
    /// single outer faults, at constant speed (17 points per fault).
    #[serde(rename = "paper-trends")]
    PaperTrends,
    /// Table 2: the nine compound-fault groups of inner and outer defect diameter and depth.
    #[serde(rename = "table2")]
    Table2,
    /// The speed and axial-load lines' end points (4000 / 12000 rpm at Fa 100 N; 100 / 400 N
    /// axial at 10000 rpm; Fr 300 N) for an outer fault, under each lubricant variant.
    #[serde(rename = "sensitivity")]
    Sensitivity,
}

impl NamedDesign {
    pub fn name(self) -> &'static str {
        match self {
            NamedDesign::PaperTrends => "paper-trends",
            NamedDesign::Table2 => "table2",
            NamedDesign::Sensitivity => "sensitivity",
        }
    }
}

/// One factor: scene fields named by JSON pointer (RFC 6901) set to each value in turn.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct FactorSpec {
    /// Column and plot name (default: the pointer's last two segments). Letters, digits,
    /// `_` and `-`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "openapi", schema(pattern = "^[A-Za-z0-9_-]{1,64}$"))]
    pub name: Option<String>,
    /// The scene field, e.g. `/operating/axial_load`.
    #[cfg_attr(feature = "openapi", schema(example = "/operating/axial_load"))]
    pub pointer: String,
    /// More fields set to the same value, e.g. `/operating/speed/initial_rpm` beside
    /// `/operating/speed/steady_rpm` for a constant speed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub also: Vec<String>,
    /// The values, in the field's unit (SI, rpm for speeds).
    #[cfg_attr(feature = "openapi", schema(min_items = 1, example = json!([100.0, 200.0, 400.0])))]
    pub values: Vec<f64>,
}
