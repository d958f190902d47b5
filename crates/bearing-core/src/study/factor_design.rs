//! Designs over factors named by JSON pointers: a `grid` (every combination) and
//! `one_at_a_time` (each factor alone, the others at the base's values).

use super::design::{
    base_value, problem, DesignSummary, Draft, FactorInfo, FactorValue, PlanProblem, PointSpec,
    MAX_POINTS,
};
use super::request::{FactorSpec, StudyRequest};
use crate::scene::FaultCase;
use serde_json::Value;

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

/// The factors checked and named, and the fault cases checked against the base.
fn checked_factors(
    req: &StudyRequest,
    factors: &[FactorSpec],
    fault_cases: &[FaultCase],
    problems: &mut Vec<PlanProblem>,
) -> Vec<FactorInfo> {
    let infos = factor_infos(factors, problems);
    if !fault_cases.is_empty() && req.base.preset.is_none() {
        problems.push(problem(
            "design.fault_cases",
            "fault cases start from a preset: give base.preset (or set /faults as a factor)",
        ));
    }
    infos
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

pub(super) fn grid(
    req: &StudyRequest,
    factors: &[FactorSpec],
    fault_cases: &[FaultCase],
    problems: &mut Vec<PlanProblem>,
) -> (DesignSummary, Vec<Draft>) {
    let infos = checked_factors(req, factors, fault_cases, problems);
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
                    put: vec![],
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

pub(super) fn one_at_a_time(
    req: &StudyRequest,
    factors: &[FactorSpec],
    fault_cases: &[FaultCase],
    problems: &mut Vec<PlanProblem>,
) -> (DesignSummary, Vec<Draft>) {
    let infos = checked_factors(req, factors, fault_cases, problems);
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
                        put: vec![],
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
