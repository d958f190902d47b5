//! What a design gives the plan: its summary (kind, factors, lines) and, per point, the
//! spec stored with it and the scene fields it sets over the base; and the problems found
//! on the way, by path from the request's root.

use super::request::StudyBase;
use crate::scene::{apply_overrides, fault_case_scene, FaultCase};
use serde::{Deserialize, Serialize};
use serde_json::Value;

/// Most points one study may hold.
pub const MAX_POINTS: usize = 500;

/// One problem with a request, by path from the body's root.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanProblem {
    pub path: String,
    pub message: String,
}

pub(super) fn problem(path: impl Into<String>, message: impl Into<String>) -> PlanProblem {
    PlanProblem {
        path: path.into(),
        message: message.into(),
    }
}

/// A factor of the design as tables and plots name it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct FactorInfo {
    /// Column and plot name.
    pub name: String,
    /// Axis label, with the unit when the design knows it.
    pub label: String,
    /// Scene fields the factor sets (empty when a named design sets several per point).
    pub pointers: Vec<String>,
}

/// The shape of a study's design, as stored with it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct DesignSummary {
    /// `grid`, `one_at_a_time`, or a named design: `paper-trends`, `table2`, `sensitivity`.
    pub kind: String,
    pub factors: Vec<FactorInfo>,
    /// Each point moves one factor along a line (one-at-a-time and trend designs): the
    /// study has one trend plot per factor and fault case.
    pub lines: bool,
}

/// A factor's value at one point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct FactorValue {
    pub name: String,
    pub value: f64,
}

/// What one point is, as stored with the study (its scene is the point's job input).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct PointSpec {
    /// A name for the point (e.g. `group 3` of Table 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
    /// The fault case the point's scene starts from (preset bases).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fault_case: Option<FaultCase>,
    /// The factor this point's line varies (designs with lines).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub line: Option<String>,
    /// Every factor's value at this point, in the design's order.
    pub factors: Vec<FactorValue>,
    /// Simulated time, s.
    pub duration: f64,
}

/// A point before its scene is built: the fields it sets.
pub(super) struct Draft {
    pub spec: PointSpec,
    /// Members a named design owns (defects, a lubricant variant's parts): put into their
    /// parent object whatever the base had there.
    pub put: Vec<(String, Value)>,
    /// Fields set by the design's factors: each must exist in the base (a typo is an error).
    pub set: Vec<(String, Value)>,
}

/// The base scene as JSON, for a fault case (preset bases only).
pub(super) fn base_value(b: &StudyBase, case: Option<FaultCase>) -> Value {
    if let Some(scene) = &b.scene {
        return scene.clone();
    }
    let preset = b.preset.as_deref().expect("checked: scene or preset");
    let scene =
        fault_case_scene(preset, case.unwrap_or(FaultCase::None)).expect("checked: a known preset");
    let mut v = serde_json::to_value(scene).expect("a scene serializes");
    if let Some(o) = &b.overrides {
        apply_overrides(&mut v, o);
    }
    v
}
