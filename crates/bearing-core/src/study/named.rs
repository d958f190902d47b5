//! The designs shipped as data: the paper's Figures 23-28 (`paper-trends`), its Table 2
//! (`table2`) and the lubricant sensitivity design (`sensitivity`), each expanded over a
//! base scene and, optionally, lubricant variants ([`super::variant`]).

use super::design::{
    base_value, problem, DesignSummary, Draft, FactorInfo, FactorValue, PlanProblem, PointSpec,
};
use super::request::{NamedDesign, StudyRequest};
use super::variant::{lubricant_variant, lubricant_variants, LubricantVariant};
use crate::scene::{Fault, FaultCase, Ring};
use serde::{Deserialize, Serialize};
use serde_json::Value;

/// The operating quantity a trend point varies (one factor at a time, as Figures 23-28 do).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Factor {
    /// Shaft speed, rpm (Figures 23-24).
    Speed,
    /// Axial load, N (Figures 25-26).
    AxialLoad,
    /// Radial load, N (Figures 27-28).
    RadialLoad,
}

impl Factor {
    /// Axis label with its unit.
    pub fn label(self) -> &'static str {
        match self {
            Factor::Speed => "shaft speed (rpm)",
            Factor::AxialLoad => "axial load (N)",
            Factor::RadialLoad => "radial load (N)",
        }
    }

    /// Column and plot name.
    pub fn name(self) -> &'static str {
        match self {
            Factor::Speed => "speed",
            Factor::AxialLoad => "axial_load",
            Factor::RadialLoad => "radial_load",
        }
    }

    fn info(self) -> FactorInfo {
        FactorInfo {
            name: self.name().into(),
            label: self.label().into(),
            pointers: vec![],
        }
    }
}

/// Speeds of Figures 23-24, rpm (Fa 100 N, Fr 300 N).
pub const TREND_SPEEDS: [f64; 6] = [2000.0, 4000.0, 6000.0, 8000.0, 10000.0, 12000.0];
/// Axial loads of Figures 25-26, N (10000 rpm, Fr 300 N). 300 N is left out: like 200 N it
/// sets the paper's cage whirling on its land, where one point costs minutes of solver time.
pub const TREND_AXIAL_LOADS: [f64; 5] = [100.0, 200.0, 400.0, 600.0, 800.0];
/// Radial loads of Figures 27-28, N (10000 rpm).
pub const TREND_RADIAL_LOADS: [f64; 6] = [100.0, 200.0, 300.0, 400.0, 500.0, 600.0];
/// Axial load of the radial-load line, N. The paper keeps 100 N, but with the ring's tilt
/// locked no equilibrium exists above Fr ~ Fa / tan(alpha) = 373 N. At 400 N one exists up
/// to 600 N radial with a wide margin (Fr tan(alpha) = 161 N at the nominal angle, 195 N at
/// 18 deg), and every ball is loaded, so the cage runs quiet (measured e = 0.04).
pub const TREND_RADIAL_LINE_AXIAL_LOAD: f64 = 400.0;

/// Table 2 of the paper: the nine groups of its three-factor orthogonal design of compound
/// defects, each `[inner diameter, inner depth, outer diameter, outer depth]`, m.
pub const TABLE2_GROUPS: [[f64; 4]; 9] = [
    [0.1e-3, 0.05e-3, 0.1e-3, 0.05e-3],
    [0.1e-3, 0.10e-3, 0.2e-3, 0.10e-3],
    [0.1e-3, 0.15e-3, 0.3e-3, 0.15e-3],
    [0.2e-3, 0.05e-3, 0.3e-3, 0.10e-3],
    [0.2e-3, 0.10e-3, 0.1e-3, 0.15e-3],
    [0.2e-3, 0.15e-3, 0.2e-3, 0.05e-3],
    [0.3e-3, 0.05e-3, 0.2e-3, 0.15e-3],
    [0.3e-3, 0.10e-3, 0.3e-3, 0.05e-3],
    [0.3e-3, 0.15e-3, 0.1e-3, 0.10e-3],
];

/// One operating point of a trend line: the factor it moves, shaft speed (rpm, constant),
/// axial and radial load (N).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Operating {
    line: Factor,
    rpm: f64,
    axial_load: f64,
    radial_load: f64,
}

impl Operating {
    fn new(line: Factor, rpm: f64, axial_load: f64, radial_load: f64) -> Self {
        Operating {
            line,
            rpm,
            axial_load,
            radial_load,
        }
    }

    fn value(&self, f: Factor) -> FactorValue {
        FactorValue {
            name: f.name().into(),
            value: match f {
                Factor::Speed => self.rpm,
                Factor::AxialLoad => self.axial_load,
                Factor::RadialLoad => self.radial_load,
            },
        }
    }

    /// The point on its line for a fault case, with `factors`' values, a label and the
    /// members a variant puts.
    fn draft(
        &self,
        fault: FaultCase,
        factors: &[Factor],
        label: Option<String>,
        put: Vec<(String, Value)>,
    ) -> Draft {
        Draft {
            spec: PointSpec {
                label,
                fault_case: Some(fault),
                line: Some(self.line.name().into()),
                factors: factors.iter().map(|&f| self.value(f)).collect(),
                duration: 0.0,
            },
            put,
            set: self.sets(),
        }
    }

    /// The scene fields it sets: a constant speed (no ramp) and both loads.
    fn sets(&self) -> Vec<(String, Value)> {
        vec![
            ("/operating/speed/initial_rpm".into(), self.rpm.into()),
            ("/operating/speed/steady_rpm".into(), self.rpm.into()),
            ("/operating/speed/ramp_time".into(), 0.0.into()),
            ("/operating/axial_load".into(), self.axial_load.into()),
            ("/operating/radial_load".into(), self.radial_load.into()),
        ]
    }
}

/// Figures 23-28: the speed, axial-load and radial-load lines. Points shared by two lines
/// (10000 rpm / 100 N / 300 N) appear under each; a runner runs identical scenes once.
fn trend_lines() -> Vec<Operating> {
    let mut points: Vec<Operating> = TREND_SPEEDS
        .iter()
        .map(|&n| Operating::new(Factor::Speed, n, 100.0, 300.0))
        .collect();
    points.extend(
        TREND_AXIAL_LOADS
            .iter()
            .map(|&fa| Operating::new(Factor::AxialLoad, 10_000.0, fa, 300.0)),
    );
    points.extend(TREND_RADIAL_LOADS.iter().map(|&fr| {
        Operating::new(
            Factor::RadialLoad,
            10_000.0,
            TREND_RADIAL_LINE_AXIAL_LOAD,
            fr,
        )
    }));
    points
}

/// The sensitivity design's points: the speed and axial-load lines' end points (4000 /
/// 12000 rpm at Fa 100 N; 100 / 400 N axial at 10000 rpm; Fr 300 N). The radial line is
/// left out: it is flat in every run so far, and its far end (600 N) sets the cage
/// whirling, which costs minutes per point.
fn sensitivity_points() -> [Operating; 4] {
    [
        Operating::new(Factor::Speed, 4000.0, 100.0, 300.0),
        Operating::new(Factor::Speed, 12000.0, 100.0, 300.0),
        Operating::new(Factor::AxialLoad, 10_000.0, 100.0, 300.0),
        Operating::new(Factor::AxialLoad, 10_000.0, 400.0, 300.0),
    ]
}

/// Expand a named design over the request's base under the variants named.
pub(super) fn named(
    req: &StudyRequest,
    name: NamedDesign,
    variants: &[String],
    problems: &mut Vec<PlanProblem>,
) -> (DesignSummary, Vec<Draft>) {
    let mut chosen = Vec::new();
    for (i, v) in variants.iter().enumerate() {
        match lubricant_variant(v) {
            Ok(v) => chosen.push(v),
            Err(e) => problems.push(problem(format!("design.variants[{i}]"), e)),
        }
    }
    if name != NamedDesign::Sensitivity && variants.len() > 1 {
        problems.push(problem(
            "design.variants",
            format!("{} runs under one variant at most", name.name()),
        ));
    }
    if name != NamedDesign::Table2 && req.base.preset.is_none() {
        problems.push(problem(
            "base.preset",
            format!(
                "{} runs single inner and outer faults: it needs a preset base",
                name.name()
            ),
        ));
    }
    match name {
        NamedDesign::PaperTrends => paper_trends(chosen.first()),
        NamedDesign::Table2 => table2(req, chosen.first()),
        NamedDesign::Sensitivity => {
            if variants.is_empty() {
                chosen = lubricant_variants();
            }
            sensitivity(&chosen)
        }
    }
}

/// The fields a variant owns, and the label it gives its points.
fn variant_parts(v: Option<&LubricantVariant>) -> (Vec<(String, Value)>, Option<String>) {
    match v {
        Some(v) => (v.sets(), Some(v.name.clone())),
        None => (vec![], None),
    }
}

/// Figures 23-28 on the base scene for single inner and single outer faults, each point at
/// constant speed; lubricant (unless a variant sets it), duration and the rest come from
/// the base.
fn paper_trends(variant: Option<&LubricantVariant>) -> (DesignSummary, Vec<Draft>) {
    let factors = [Factor::Speed, Factor::AxialLoad, Factor::RadialLoad];
    let design = DesignSummary {
        kind: NamedDesign::PaperTrends.name().into(),
        factors: factors.iter().map(|f| f.info()).collect(),
        lines: true,
    };
    let (put, label) = variant_parts(variant);
    let mut drafts = Vec::new();
    for fault in [FaultCase::Inner, FaultCase::Outer] {
        for p in trend_lines() {
            drafts.push(p.draft(fault, &factors, label.clone(), put.clone()));
        }
    }
    (design, drafts)
}

/// Each trend line's end points for an outer fault under every variant; the variant labels
/// its points. No trend plots: the points of one line differ in lubricant.
fn sensitivity(variants: &[LubricantVariant]) -> (DesignSummary, Vec<Draft>) {
    let factors = [Factor::Speed, Factor::AxialLoad];
    let design = DesignSummary {
        kind: NamedDesign::Sensitivity.name().into(),
        factors: factors.iter().map(|f| f.info()).collect(),
        lines: false,
    };
    let mut drafts = Vec::new();
    for v in variants {
        for p in sensitivity_points() {
            drafts.push(p.draft(FaultCase::Outer, &factors, Some(v.name.clone()), v.sets()));
        }
    }
    (design, drafts)
}

/// Table 2: nine compound defects, each at the load zone's centre (the base's radial-load
/// angle), replacing the base's defects.
fn table2(req: &StudyRequest, variant: Option<&LubricantVariant>) -> (DesignSummary, Vec<Draft>) {
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
    let (lubricant, variant_name) = variant_parts(variant);
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
            let mut put = vec![(
                "/faults".to_string(),
                serde_json::to_value(faults).expect("faults serialize"),
            )];
            put.extend(lubricant.iter().cloned());
            Draft {
                spec: PointSpec {
                    label: Some(match &variant_name {
                        Some(v) => format!("group {} ({v})", k + 1),
                        None => format!("group {}", k + 1),
                    }),
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
                put,
                set: vec![],
            }
        })
        .collect();
    (design, drafts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{fault_case_scene, Scene};
    use crate::study::plan::plan;
    use crate::study::request::{DesignSpec, StudyBase};
    use serde_json::json;

    /// The scene of a trend point built field by field, as the engine's former design
    /// types did: the preset's fault case, a constant speed, both loads, the variant's
    /// lubricant parts and the duration.
    fn typed(p: &Operating, fault: FaultCase, v: &LubricantVariant, duration: f64) -> Scene {
        let mut s = fault_case_scene("h7005c", fault).unwrap();
        s.operating.speed.initial_rpm = p.rpm;
        s.operating.speed.steady_rpm = p.rpm;
        s.operating.speed.ramp_time = 0.0;
        s.operating.axial_load = p.axial_load;
        s.operating.radial_load = p.radial_load;
        v.apply_to(&mut s.lubricant);
        s.solver.duration = duration;
        s
    }

    fn request(name: NamedDesign, variants: &[&str], duration: f64) -> StudyRequest {
        StudyRequest {
            name: None,
            base: StudyBase {
                preset: Some("h7005c".into()),
                overrides: Some(json!({"solver": {"duration": duration}})),
                ..Default::default()
            },
            design: DesignSpec::Named {
                name,
                variants: variants.iter().map(|v| v.to_string()).collect(),
            },
        }
    }

    /// The designs as data give exactly the scenes the typed construction gives (the
    /// JSON pointers name the fields it sets, and a variant's traction law replaces the
    /// preset's), so a point's numbers do not depend on which of the two built it.
    #[test]
    fn named_designs_build_the_typed_scenes() {
        for variant in ["paper", "film", "drag+rolling"] {
            let v = lubricant_variant(variant).unwrap();
            let p = plan(&request(NamedDesign::PaperTrends, &[variant], 0.3)).unwrap();
            assert_eq!(p.points.len(), 2 * 17);
            let want = [FaultCase::Inner, FaultCase::Outer]
                .into_iter()
                .flat_map(|f| trend_lines().into_iter().map(move |o| (f, o)));
            for (point, (fault, o)) in p.points.iter().zip(want) {
                let mut got = point.scene.scene().clone();
                let want = typed(&o, fault, &v, 0.3);
                got.name = want.name.clone();
                assert_eq!(got, want, "{variant}: {:?}", point.spec);
                assert_eq!(point.spec.label.as_deref(), Some(variant));
                assert_eq!(point.spec.line.as_deref(), Some(o.line.name()));
            }
        }
        let all = lubricant_variants();
        let s = plan(&request(NamedDesign::Sensitivity, &[], 0.1)).unwrap();
        assert_eq!(s.points.len(), 4 * all.len());
        assert!(!s.design.lines);
        for (k, point) in s.points.iter().enumerate() {
            let (v, o) = (&all[k / 4], sensitivity_points()[k % 4]);
            let mut got = point.scene.scene().clone();
            let want = typed(&o, FaultCase::Outer, v, 0.1);
            got.name = want.name.clone();
            assert_eq!(got, want, "{}: {:?}", v.name, point.spec);
            assert_eq!(point.spec.label.as_deref(), Some(v.name.as_str()));
        }
    }

    #[test]
    fn variants_are_checked_by_name_and_count() {
        let e = plan(&request(NamedDesign::PaperTrends, &["paper", "flim"], 0.1)).unwrap_err();
        let paths: Vec<&str> = e.iter().map(|p| p.path.as_str()).collect();
        assert_eq!(paths, ["design.variants[1]", "design.variants"], "{e:?}");
        assert!(e[0].message.contains("film-G0.3"), "{e:?}");
        // Table 2 under the film law: the variant labels the groups and sets the traction
        let t = plan(&request(NamedDesign::Table2, &["film"], 0.1)).unwrap();
        assert_eq!(t.points[2].spec.label.as_deref(), Some("group 3 (film)"));
        assert!(matches!(
            t.points[2].scene.lubricant.traction,
            crate::scene::Traction::Film { .. }
        ));
        assert_eq!(t.points[2].scene.faults.len(), 2);
    }
}
