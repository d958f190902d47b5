//! A study request expanded into its points, each a validated scene: the one validation a
//! study gets before it is accepted. Every problem names its path from the request's root
//! (`design.factors[0].pointer`, `points[3].scene.operating.axial_load`).

use super::design::{base_value, problem, DesignSummary, Draft, PlanProblem, PointSpec};
use super::factor_design::{grid, one_at_a_time};
use super::named::named;
use super::request::{DesignSpec, StudyBase, StudyRequest};
use crate::json_doc::{put_member, set_at_pointer};
use crate::scene::{preset_names, FaultCase, Scene, ValidScene};

/// A point ready to run (or to queue).
#[derive(Debug, Clone)]
pub struct PlannedPoint {
    pub spec: PointSpec,
    pub scene: ValidScene,
}

/// The expanded study.
#[derive(Debug, Clone)]
pub struct Plan {
    pub name: String,
    pub design: DesignSummary,
    pub points: Vec<PlannedPoint>,
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
        DesignSpec::Named { name, variants } => named(req, *name, variants, &mut problems),
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
        match point_scene(&req.base, case, &d) {
            Ok(scene) => {
                d.spec.duration = scene.solver.duration;
                points.push(PlannedPoint {
                    spec: d.spec,
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

/// The point's scene: base, the design's members put, fields set, parsed, validated.
/// Errors: (path, message).
fn point_scene(
    b: &StudyBase,
    case: Option<FaultCase>,
    d: &Draft,
) -> Result<ValidScene, Vec<(String, String)>> {
    let mut v = base_value(b, case);
    let pointer_problem =
        |e: crate::json_doc::PointerError| vec![("scene".to_string(), e.to_string())];
    for (pointer, value) in &d.put {
        put_member(&mut v, pointer, value.clone()).map_err(pointer_problem)?;
    }
    for (pointer, value) in &d.set {
        set_at_pointer(&mut v, pointer, value.clone()).map_err(pointer_problem)?;
    }
    let scene: Scene = serde_path_to_error::deserialize(v)
        .map_err(|e| vec![(join("scene", &e.path().to_string()), e.inner().to_string())])?;
    ValidScene::new(scene).map_err(|e| {
        e.0.iter()
            .map(|f| (join("scene", &f.path), f.message.clone()))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::{json, Value};

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
