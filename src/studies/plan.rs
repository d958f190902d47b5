//! A study request expanded into its points, each a validated scene: the one validation a
//! study gets before it is accepted. Every problem names its path from the request's root
//! (`design.factors[0].pointer`, `points[3].scene.operating.axial_load`).

use super::request::{DesignSpec, FactorSpec, NamedDesign, StudyBase, StudyRequest};
use super::scene_key::scene_key;
use crate::json_doc::{merge_patch, set_at_pointer};
use bearing_core::scene::{
    fault_case_scene, preset_names, Fault, FaultCase, Ring, Scene, ValidScene,
};
use bearing_core::study::{paper_trends, Factor, LubricantVariant, TABLE2_GROUPS};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use utoipa::ToSchema;

/// Most points one study may hold.
pub const MAX_POINTS: usize = 500;

/// One problem with a request, by path from the body's root.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanProblem {
    pub path: String,
    pub message: String,
}

fn problem(path: impl Into<String>, message: impl Into<String>) -> PlanProblem {
    PlanProblem {
        path: path.into(),
        message: message.into(),
    }
}

/// A factor of the design as tables and plots name it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct FactorInfo {
    /// Column and plot name.
    pub name: String,
    /// Axis label, with the unit when the design knows it.
    pub label: String,
    /// Scene fields the factor sets (empty when a named design sets several per point).
    pub pointers: Vec<String>,
}

/// The shape of a study's design, as stored with it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct DesignSummary {
    /// `grid`, `one_at_a_time`, `paper-trends` or `table2`.
    pub kind: String,
    pub factors: Vec<FactorInfo>,
    /// Each point moves one factor along a line (one-at-a-time and trend designs): the
    /// study has one trend plot per factor and fault case.
    pub lines: bool,
}

/// A factor's value at one point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct FactorValue {
    pub name: String,
    pub value: f64,
}

/// What one point is, as stored with the study (its scene is the point's job input).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
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

/// A point ready to queue.
#[derive(Debug, Clone)]
pub struct PlannedPoint {
    pub spec: PointSpec,
    pub scene: ValidScene,
    /// [`super::scene_key::scene_key`] of the scene: identical points share a run by it.
    pub key: String,
}

/// The expanded study.
#[derive(Debug, Clone)]
pub struct Plan {
    pub name: String,
    pub design: DesignSummary,
    pub points: Vec<PlannedPoint>,
}

/// A point before its scene is built: the fields it sets.
struct Draft {
    spec: PointSpec,
    set: Vec<(String, Value)>,
}

/// Expand and validate. All problems are returned, the first few hundred at most.
pub fn plan(req: &StudyRequest) -> Result<Plan, Vec<PlanProblem>> {
    let mut problems = Vec::new();
    check_base(&req.base, &mut problems);
    if let Some(n) = &req.name {
        if n.chars().count() > 200 {
            problems.push(problem("name", "at most 200 characters"));
        }
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    let base_case = req.base.fault_case;
    let (design, drafts) = match &req.design {
        DesignSpec::Grid {
            factors,
            fault_cases,
        } => grid(req, factors, fault_cases, &mut problems),
        DesignSpec::OneAtATime {
            factors,
            fault_cases,
        } => one_at_a_time(req, factors, fault_cases, &mut problems),
        DesignSpec::Named { name } => named(req, *name, &mut problems),
    };
    if !problems.is_empty() {
        return Err(problems);
    }
    if drafts.is_empty() {
        return Err(vec![problem("design", "the design has no points")]);
    }
    let mut points = Vec::with_capacity(drafts.len());
    for (i, mut d) in drafts.into_iter().enumerate() {
        let case = d.spec.fault_case.or(base_case);
        if req.base.preset.is_some() {
            // preset bases always have a fault case: name it on the point
            d.spec.fault_case = Some(case.unwrap_or(FaultCase::None));
        }
        match point_scene(&req.base, case, &d.set) {
            Ok(scene) => {
                d.spec.duration = scene.solver.duration;
                points.push(PlannedPoint {
                    spec: d.spec,
                    key: scene_key(&scene),
                    scene,
                });
            }
            Err(errs) => problems.extend(errs.into_iter().map(|(path, message)| PlanProblem {
                path: join(&format!("points[{i}]"), &path),
                message,
            })),
        }
        if problems.len() >= 200 {
            break;
        }
    }
    if !problems.is_empty() {
        return Err(problems);
    }
    // a preset base is named by the preset: its points may have different fault cases
    let base_name = req
        .base
        .preset
        .clone()
        .unwrap_or_else(|| points[0].scene.name.clone());
    let name = req
        .name
        .clone()
        .filter(|n| !n.trim().is_empty())
        .unwrap_or_else(|| format!("{} study of {base_name}", design.kind));
    Ok(Plan {
        name,
        design,
        points,
    })
}

fn join(prefix: &str, path: &str) -> String {
    if path.is_empty() || path == "." || path == "$" {
        prefix.to_string()
    } else if path.starts_with('[') {
        format!("{prefix}{path}")
    } else {
        format!("{prefix}.{path}")
    }
}

fn check_base(b: &StudyBase, problems: &mut Vec<PlanProblem>) {
    match (&b.scene, &b.preset) {
        (Some(_), Some(_)) => problems.push(problem(
            "base.preset",
            "give either scene or preset, not both",
        )),
        (None, None) => problems.push(problem(
            "base.scene",
            "required: a scene object, or a preset name",
        )),
        (Some(scene), None) => {
            if b.fault_case.is_some() {
                problems.push(problem("base.fault_case", "only allowed with preset"));
            }
            if b.overrides.is_some() {
                problems.push(problem("base.overrides", "only allowed with preset"));
            }
            if !scene.is_object() {
                problems.push(problem("base.scene", "must be an object"));
            }
        }
        (None, Some(p)) => {
            if !preset_names().contains(&p.as_str()) {
                problems.push(problem(
                    "base.preset",
                    format!(
                        "unknown preset '{p}'; simulation presets: {}",
                        preset_names().join(", ")
                    ),
                ));
            }
            if let Some(o) = &b.overrides {
                if !o.is_object() {
                    problems.push(problem(
                        "base.overrides",
                        "must be an object (a JSON merge patch)",
                    ));
                }
            }
        }
    }
}

/// The base scene as JSON, for a fault case (preset bases only).
fn base_value(b: &StudyBase, case: Option<FaultCase>) -> Value {
    if let Some(scene) = &b.scene {
        return scene.clone();
    }
    let preset = b.preset.as_deref().expect("checked: scene or preset");
    let scene =
        fault_case_scene(preset, case.unwrap_or(FaultCase::None)).expect("checked: a known preset");
    let mut v = serde_json::to_value(scene).expect("a scene serializes");
    if let Some(o) = &b.overrides {
        merge_patch(&mut v, o);
    }
    v
}

/// The point's scene: base, fields set, parsed, validated. Errors: (path, message).
fn point_scene(
    b: &StudyBase,
    case: Option<FaultCase>,
    set: &[(String, Value)],
) -> Result<ValidScene, Vec<(String, String)>> {
    let mut v = base_value(b, case);
    for (pointer, value) in set {
        if pointer == "/faults" {
            // a named design's defects replace the base's whatever it had
            if let Value::Object(m) = &mut v {
                m.insert("faults".into(), value.clone());
                continue;
            }
        }
        set_at_pointer(&mut v, pointer, value.clone())
            .map_err(|e| vec![("scene".to_string(), e.to_string())])?;
    }
    let scene: Scene = serde_path_to_error::deserialize(v)
        .map_err(|e| vec![(join("scene", &e.path().to_string()), e.inner().to_string())])?;
    ValidScene::new(scene).map_err(|e| {
        e.0.iter()
            .map(|f| (join("scene", &f.path), f.message.clone()))
            .collect()
    })
}

/// Default factor name: the pointer's last two segments.
fn factor_name(f: &FactorSpec) -> String {
    let segs: Vec<&str> = f.pointer.split('/').filter(|s| !s.is_empty()).collect();
    let tail = &segs[segs.len().saturating_sub(2)..];
    let name: String = tail
        .join("_")
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if name.is_empty() {
        "factor".into()
    } else {
        name
    }
}

/// The SI unit of a scene field, from its name's conventions (docs/reference/model.md: SI units,
/// speeds in rpm); `None` for a field the table does not know.
fn unit_of(pointer: &str) -> Option<&'static str> {
    let last = pointer.rsplit('/').next().unwrap_or("");
    let ends = |s: &str| last == s || last.ends_with(&format!("_{s}"));
    Some(if last.ends_with("_rpm") {
        "rpm"
    } else if ends("load") {
        "N"
    } else if ends("angle") {
        "rad"
    } else if ["width", "depth", "diameter", "clearance"]
        .iter()
        .any(|s| ends(s))
    {
        "m"
    } else if ends("duration") || ends("time") || ends("step") {
        "s"
    } else if ends("mass") {
        "kg"
    } else if last.starts_with("stiffness") {
        "N/m"
    } else if last.starts_with("damping_") {
        "N s/m"
    } else if ends("viscosity") {
        "Pa s"
    } else if ends("modulus") || ends("stress") {
        "Pa"
    } else if ends("rate") {
        "Hz"
    } else {
        return None;
    })
}

/// Whether a design of `total` points fits a study; a problem if not. Checked before the
/// points are built (a grid's product can be huge). The named designs are fixed and small.
fn fits(total: usize, problems: &mut Vec<PlanProblem>) -> bool {
    if total > MAX_POINTS {
        problems.push(problem(
            "design",
            format!("{total} points: a study holds at most {MAX_POINTS}"),
        ));
    }
    total <= MAX_POINTS
}

/// Check the factors and name them.
fn factor_infos(factors: &[FactorSpec], problems: &mut Vec<PlanProblem>) -> Vec<FactorInfo> {
    let mut infos: Vec<FactorInfo> = Vec::new();
    for (i, f) in factors.iter().enumerate() {
        let at = |field: &str| format!("design.factors[{i}].{field}");
        let name = f.name.clone().unwrap_or_else(|| factor_name(f));
        let valid_name = !name.is_empty()
            && name.len() <= 64
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
        if !valid_name {
            problems.push(problem(at("name"), "1-64 letters, digits, '_' or '-'"));
        } else if infos.iter().any(|x| x.name == name) {
            problems.push(problem(
                at("name"),
                format!("'{name}' names another factor too; give each a distinct name"),
            ));
        }
        for (k, p) in std::iter::once(&f.pointer).chain(&f.also).enumerate() {
            if !p.starts_with('/') {
                let field = if k == 0 {
                    at("pointer")
                } else {
                    at(&format!("also[{}]", k - 1))
                };
                problems.push(problem(
                    field,
                    format!("'{p}' is not a JSON pointer to a scene field (it starts with '/')"),
                ));
            }
        }
        if f.values.is_empty() {
            problems.push(problem(at("values"), "give at least one value"));
        }
        infos.push(FactorInfo {
            label: match unit_of(&f.pointer) {
                Some(unit) => format!("{name} ({unit}), {}", f.pointer),
                None => format!("{name}, {}", f.pointer),
            },
            name,
            pointers: std::iter::once(&f.pointer)
                .chain(&f.also)
                .cloned()
                .collect(),
        });
    }
    infos
}

fn cases(fault_cases: &[FaultCase]) -> Vec<Option<FaultCase>> {
    if fault_cases.is_empty() {
        vec![None]
    } else {
        fault_cases.iter().map(|c| Some(*c)).collect()
    }
}

fn need_preset_for_cases(req: &StudyRequest, fault_cases: &[FaultCase], p: &mut Vec<PlanProblem>) {
    if !fault_cases.is_empty() && req.base.preset.is_none() {
        p.push(problem(
            "design.fault_cases",
            "fault cases start from a preset: give base.preset (or set /faults as a factor)",
        ));
    }
}

/// Numbers read from the base scene at the factors' pointers (for one-at-a-time rows).
fn base_factor_values(req: &StudyRequest, infos: &[FactorInfo]) -> Vec<FactorValue> {
    let v = base_value(&req.base, req.base.fault_case);
    infos
        .iter()
        .map(|f| FactorValue {
            name: f.name.clone(),
            value: f
                .pointers
                .first()
                .and_then(|p| v.pointer(p))
                .and_then(Value::as_f64)
                .unwrap_or(f64::NAN),
        })
        .collect()
}

fn sets(f: &FactorSpec, value: f64) -> Vec<(String, Value)> {
    std::iter::once(&f.pointer)
        .chain(&f.also)
        .map(|p| (p.clone(), Value::from(value)))
        .collect()
}

fn grid(
    req: &StudyRequest,
    factors: &[FactorSpec],
    fault_cases: &[FaultCase],
    problems: &mut Vec<PlanProblem>,
) -> (DesignSummary, Vec<Draft>) {
    let infos = factor_infos(factors, problems);
    need_preset_for_cases(req, fault_cases, problems);
    if factors.is_empty() && fault_cases.is_empty() {
        problems.push(problem(
            "design.factors",
            "a grid needs at least one factor or fault case",
        ));
    }
    // saturating: a product of many factors must not wrap below the limit
    let total = factors
        .iter()
        .map(|f| f.values.len().max(1))
        .fold(fault_cases.len().max(1), usize::saturating_mul);
    let mut drafts = Vec::new();
    if fits(total, problems) && problems.is_empty() {
        for case in cases(fault_cases) {
            let mut combos: Vec<Vec<usize>> = vec![vec![]];
            for f in factors {
                combos = combos
                    .into_iter()
                    .flat_map(|c| {
                        (0..f.values.len()).map(move |k| {
                            let mut c = c.clone();
                            c.push(k);
                            c
                        })
                    })
                    .collect();
            }
            for combo in combos {
                let mut set = Vec::new();
                let mut values = Vec::new();
                for ((f, info), &k) in factors.iter().zip(&infos).zip(&combo) {
                    set.extend(sets(f, f.values[k]));
                    values.push(FactorValue {
                        name: info.name.clone(),
                        value: f.values[k],
                    });
                }
                drafts.push(Draft {
                    spec: PointSpec {
                        label: None,
                        fault_case: case,
                        // a one-factor grid is a line
                        line: (infos.len() == 1).then(|| infos[0].name.clone()),
                        factors: values,
                        duration: 0.0,
                    },
                    set,
                });
            }
        }
    }
    let lines = factors.len() == 1;
    (
        DesignSummary {
            kind: "grid".into(),
            factors: infos,
            lines,
        },
        drafts,
    )
}

fn one_at_a_time(
    req: &StudyRequest,
    factors: &[FactorSpec],
    fault_cases: &[FaultCase],
    problems: &mut Vec<PlanProblem>,
) -> (DesignSummary, Vec<Draft>) {
    let infos = factor_infos(factors, problems);
    need_preset_for_cases(req, fault_cases, problems);
    if factors.is_empty() {
        problems.push(problem("design.factors", "give at least one factor"));
    }
    let total: usize =
        factors.iter().map(|f| f.values.len()).sum::<usize>() * fault_cases.len().max(1);
    let mut drafts = Vec::new();
    if fits(total, problems) && problems.is_empty() {
        let at_base = base_factor_values(req, &infos);
        for case in cases(fault_cases) {
            for (f, info) in factors.iter().zip(&infos) {
                for &value in &f.values {
                    let mut values = at_base.clone();
                    for v in values.iter_mut().filter(|v| v.name == info.name) {
                        v.value = value;
                    }
                    drafts.push(Draft {
                        spec: PointSpec {
                            label: None,
                            fault_case: case,
                            line: Some(info.name.clone()),
                            factors: values,
                            duration: 0.0,
                        },
                        set: sets(f, value),
                    });
                }
            }
        }
    }
    (
        DesignSummary {
            kind: "one_at_a_time".into(),
            factors: infos,
            lines: true,
        },
        drafts,
    )
}

fn named(
    req: &StudyRequest,
    name: NamedDesign,
    problems: &mut Vec<PlanProblem>,
) -> (DesignSummary, Vec<Draft>) {
    match name {
        NamedDesign::PaperTrends => paper_trends_design(req, problems),
        NamedDesign::Table2 => table2_design(req),
    }
}

/// Figures 23-28 on the base scene: the engine's trend points (speeds, loads), each at
/// constant speed; lubricant, duration and the rest come from the base.
fn paper_trends_design(
    req: &StudyRequest,
    problems: &mut Vec<PlanProblem>,
) -> (DesignSummary, Vec<Draft>) {
    if req.base.preset.is_none() {
        problems.push(problem(
            "base.preset",
            "paper-trends runs single inner and outer faults: it needs a preset base",
        ));
    }
    let factor = |f: Factor| FactorInfo {
        name: f.name().into(),
        label: f.label().into(),
        pointers: vec![],
    };
    let design = DesignSummary {
        kind: NamedDesign::PaperTrends.name().into(),
        factors: [Factor::Speed, Factor::AxialLoad, Factor::RadialLoad]
            .into_iter()
            .map(factor)
            .collect(),
        lines: true,
    };
    let drafts = paper_trends(&LubricantVariant::paper(), 0.0)
        .into_iter()
        .map(|p| {
            let value = |f: Factor, v: f64| FactorValue {
                name: f.name().into(),
                value: v,
            };
            Draft {
                spec: PointSpec {
                    label: None,
                    fault_case: Some(p.fault),
                    line: Some(p.factor.name().into()),
                    factors: vec![
                        value(Factor::Speed, p.rpm),
                        value(Factor::AxialLoad, p.axial_load),
                        value(Factor::RadialLoad, p.radial_load),
                    ],
                    duration: 0.0,
                },
                set: vec![
                    ("/operating/speed/initial_rpm".into(), p.rpm.into()),
                    ("/operating/speed/steady_rpm".into(), p.rpm.into()),
                    ("/operating/speed/ramp_time".into(), 0.0.into()),
                    ("/operating/axial_load".into(), p.axial_load.into()),
                    ("/operating/radial_load".into(), p.radial_load.into()),
                ],
            }
        })
        .collect();
    (design, drafts)
}

/// Table 2: nine compound defects, each at the load zone's centre (the base's radial-load
/// angle), replacing the base's defects.
fn table2_design(req: &StudyRequest) -> (DesignSummary, Vec<Draft>) {
    let names = [
        ("inner_diameter", "inner defect diameter (m)"),
        ("inner_depth", "inner defect depth (m)"),
        ("outer_diameter", "outer defect diameter (m)"),
        ("outer_depth", "outer defect depth (m)"),
    ];
    let design = DesignSummary {
        kind: NamedDesign::Table2.name().into(),
        factors: names
            .iter()
            .map(|(n, l)| FactorInfo {
                name: (*n).into(),
                label: (*l).into(),
                pointers: vec!["/faults".into()],
            })
            .collect(),
        lines: false,
    };
    let base = base_value(&req.base, Some(FaultCase::Compound));
    let load_zone = base
        .pointer("/operating/radial_load_angle")
        .and_then(Value::as_f64)
        .unwrap_or(0.0);
    let case = req.base.preset.as_ref().map(|_| FaultCase::Compound);
    let drafts = TABLE2_GROUPS
        .iter()
        .enumerate()
        .map(|(k, g)| {
            let fault = |ring, width, depth| Fault {
                ring,
                angle: load_zone,
                width,
                depth,
            };
            let faults = vec![
                fault(Ring::Inner, g[0], g[1]),
                fault(Ring::Outer, g[2], g[3]),
            ];
            Draft {
                spec: PointSpec {
                    label: Some(format!("group {}", k + 1)),
                    fault_case: case,
                    line: None,
                    factors: names
                        .iter()
                        .zip(g)
                        .map(|((n, _), v)| FactorValue {
                            name: (*n).into(),
                            value: *v,
                        })
                        .collect(),
                    duration: 0.0,
                },
                set: vec![(
                    "/faults".into(),
                    serde_json::to_value(faults).expect("faults serialize"),
                )],
            }
        })
        .collect();
    (design, drafts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn request(v: Value) -> StudyRequest {
        serde_json::from_value(v).unwrap()
    }

    #[test]
    fn grids_multiply_and_one_at_a_time_adds() {
        let factors = json!([
            {"pointer": "/operating/axial_load", "values": [100.0, 200.0]},
            {"name": "speed", "pointer": "/operating/speed/steady_rpm", "also": ["/operating/speed/initial_rpm"], "values": [6000.0, 8000.0, 10000.0]}
        ]);
        let g = plan(&request(
            json!({"base": {"preset": "h7005c", "fault_case": "outer"},
            "design": {"type": "grid", "factors": factors, "fault_cases": ["inner", "outer"]}}),
        ))
        .unwrap();
        assert_eq!(g.points.len(), 2 * 2 * 3);
        let p = &g.points[4];
        assert_eq!(p.spec.fault_case, Some(FaultCase::Inner));
        assert_eq!(p.scene.operating.axial_load, 200.0);
        assert_eq!(p.scene.operating.speed.steady_rpm, 8000.0);
        assert_eq!(p.scene.operating.speed.initial_rpm, 8000.0);
        assert_eq!(g.design.factors[0].name, "operating_axial_load");
        assert_eq!(
            g.design.factors[0].label,
            "operating_axial_load (N), /operating/axial_load"
        );
        assert_eq!(
            g.design.factors[1].label,
            "speed (rpm), /operating/speed/steady_rpm"
        );
        let o = plan(&request(
            json!({"base": {"preset": "h7005c", "fault_case": "outer"},
            "design": {"type": "one_at_a_time", "factors": factors}}),
        ))
        .unwrap();
        assert_eq!(o.points.len(), 5);
        // the other factor stays at the base scene's value
        assert_eq!(
            o.points[3].spec.factors[0].value,
            o.points[3].scene.operating.axial_load
        );
        assert_eq!(o.points[3].spec.line.as_deref(), Some("speed"));
    }

    #[test]
    fn named_designs_expand_to_the_papers_points() {
        let t = plan(&request(json!({"base": {"preset": "h7005c"},
            "design": {"type": "named", "name": "table2"}})))
        .unwrap();
        assert_eq!(t.points.len(), 9);
        let g9 = &t.points[8].scene;
        assert_eq!(g9.faults.len(), 2);
        assert_eq!((g9.faults[0].width, g9.faults[0].depth), (0.3e-3, 0.15e-3));
        assert_eq!((g9.faults[1].width, g9.faults[1].depth), (0.1e-3, 0.10e-3));
        let p = plan(&request(
            json!({"base": {"preset": "h7005c", "overrides": {"solver": {"duration": 0.05}}},
            "design": {"type": "named", "name": "paper-trends"}}),
        ))
        .unwrap();
        assert_eq!(p.points.len(), 34);
        assert!(p
            .points
            .iter()
            .all(|q| q.spec.duration == 0.05 && q.scene.operating.speed.ramp_time == 0.0));
    }

    #[test]
    fn a_design_over_the_limit_is_refused_before_its_points_are_built() {
        // 40 factors of 10 values: 1e40 points, beyond usize; the count saturates
        let factors: Vec<Value> = (0..40)
            .map(|_| json!({"pointer": "/operating/axial_load", "values": [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0]}))
            .enumerate()
            .map(|(i, mut f)| {
                f["name"] = json!(format!("f{i}"));
                f
            })
            .collect();
        let e = plan(&request(json!({"base": {"preset": "h7005c"},
            "design": {"type": "grid", "factors": factors}})))
        .unwrap_err();
        assert_eq!(e.len(), 1, "{e:?}");
        assert_eq!(e[0].path, "design");
        assert!(e[0].message.contains("at most 500"), "{e:?}");
    }

    #[test]
    fn problems_name_the_point_and_the_field() {
        let e = plan(&request(json!({"base": {"preset": "h7005c"},
            "design": {"type": "grid", "factors": [{"pointer": "/operating/axial_load", "values": [100.0, -5.0]}]}})))
        .unwrap_err();
        assert_eq!(e.len(), 1, "{e:?}");
        assert!(e[0].path.starts_with("points[1].scene.operating"), "{e:?}");
        let e = plan(&request(json!({"base": {"preset": "h7005c"},
            "design": {"type": "grid", "factors": [{"pointer": "/operating/axial_lod", "values": [100.0]}]}})))
        .unwrap_err();
        assert_eq!(e[0].path, "points[0].scene", "{e:?}");
        assert!(e[0].message.contains("axial_lod"), "{e:?}");
        let e = plan(&request(json!({"base": {"scene": {}},
            "design": {"type": "grid", "fault_cases": ["inner"]}})))
        .unwrap_err();
        assert!(e.iter().any(|p| p.path == "design.fault_cases"), "{e:?}");
    }
}
