//! Study designs as data: which operating points and lubricant variants a study runs.

use crate::scene::{
    fault_case_scene, CavityDrag, FaultCase, RollingResistanceModel, Scene, Traction,
};
use serde::{Deserialize, Serialize};

/// The operating quantity a point varies (one factor at a time, as Figures 23-28 do).
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

    pub fn name(self) -> &'static str {
        match self {
            Factor::Speed => "speed",
            Factor::AxialLoad => "axial_load",
            Factor::RadialLoad => "radial_load",
        }
    }
}

/// The lubricant physics a point runs with (docs/reference/model.md, "Lubricant drag", "EHL rolling
/// resistance", "Traction laws"). The seed paper's model is `paper`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LubricantVariant {
    /// Short name used in tables and file names.
    pub name: String,
    pub cavity_drag: CavityDrag,
    pub rolling_resistance: RollingResistanceModel,
    /// `None` keeps the preset's traction curve.
    pub traction: Option<Traction>,
}

impl LubricantVariant {
    /// The seed paper's model: no drag, no rolling resistance, the preset's traction curve.
    pub fn paper() -> Self {
        LubricantVariant {
            name: "paper".into(),
            cavity_drag: CavityDrag::None,
            rolling_resistance: RollingResistanceModel::None,
            traction: None,
        }
    }
}

/// The named lubricant variants a study may run: the paper's model, each added term alone,
/// both together, a richer oil-air mixture, and the elastic-plastic film traction law with
/// its defaults, with drag and rolling resistance, and with each coefficient at the ends of
/// its plausible range (the sensitivity table's rows).
pub fn lubricant_variants() -> Vec<LubricantVariant> {
    let drag = |x| CavityDrag::OilAir { oil_fraction: x };
    let houpert = RollingResistanceModel::Houpert { factor: 1.0 };
    let v = |name: &str, cavity_drag, rolling_resistance| LubricantVariant {
        name: name.into(),
        cavity_drag,
        rolling_resistance,
        traction: None,
    };
    let film = |name: &str, shear_modulus, eyring_stress, limiting_coefficient, with_drag| {
        let (cavity_drag, rolling_resistance) = if with_drag {
            (drag(0.01), houpert)
        } else {
            (CavityDrag::None, RollingResistanceModel::None)
        };
        LubricantVariant {
            name: name.into(),
            cavity_drag,
            rolling_resistance,
            traction: Some(Traction::Film {
                shear_modulus,
                eyring_stress,
                limiting_coefficient,
            }),
        }
    };
    vec![
        LubricantVariant::paper(),
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

/// One simulation of a study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyPoint {
    /// The factor this point belongs to (a point may also sit on another factor's line).
    pub factor: Factor,
    /// Single inner or single outer fault.
    pub fault: FaultCase,
    /// Constant shaft speed, rpm.
    pub rpm: f64,
    /// N.
    pub axial_load: f64,
    /// N.
    pub radial_load: f64,
    pub lubricant: LubricantVariant,
    /// Simulated time, s.
    pub duration: f64,
}

impl StudyPoint {
    /// The factor's value at this point, in the unit of [`Factor::label`].
    pub fn value(&self) -> f64 {
        match self.factor {
            Factor::Speed => self.rpm,
            Factor::AxialLoad => self.axial_load,
            Factor::RadialLoad => self.radial_load,
        }
    }

    /// The H7005C Table-1 scene with this point's fault, constant speed, loads and lubricant.
    pub fn scene(&self) -> Scene {
        let mut s = fault_case_scene("h7005c", self.fault).expect("h7005c is a preset");
        s.operating.speed.initial_rpm = self.rpm;
        s.operating.speed.steady_rpm = self.rpm;
        s.operating.speed.ramp_time = 0.0;
        s.operating.axial_load = self.axial_load;
        s.operating.radial_load = self.radial_load;
        s.lubricant.cavity_drag = self.lubricant.cavity_drag;
        s.lubricant.rolling_resistance = self.lubricant.rolling_resistance;
        if let Some(t) = self.lubricant.traction {
            s.lubricant.traction = t;
        }
        s.solver.duration = self.duration;
        s.name = format!(
            "{} at {} rpm, Fa {} N, Fr {} N ({})",
            s.name, self.rpm, self.axial_load, self.radial_load, self.lubricant.name
        );
        s
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

/// Figures 23-28: every factor's line for single inner and single outer faults, with one
/// lubricant variant. Points shared by two lines (10000 rpm / 100 N / 300 N and
/// 10000 rpm / 400 N / 300 N) appear under each factor; a runner may run identical scenes
/// once.
pub fn paper_trends(lubricant: &LubricantVariant, duration: f64) -> Vec<StudyPoint> {
    let mut points = Vec::new();
    for fault in [FaultCase::Inner, FaultCase::Outer] {
        let point = |factor, rpm, axial_load, radial_load| StudyPoint {
            factor,
            fault,
            rpm,
            axial_load,
            radial_load,
            lubricant: lubricant.clone(),
            duration,
        };
        points.extend(
            TREND_SPEEDS
                .iter()
                .map(|&n| point(Factor::Speed, n, 100.0, 300.0)),
        );
        points.extend(
            TREND_AXIAL_LOADS
                .iter()
                .map(|&fa| point(Factor::AxialLoad, 10_000.0, fa, 300.0)),
        );
        points.extend(TREND_RADIAL_LOADS.iter().map(|&fr| {
            point(
                Factor::RadialLoad,
                10_000.0,
                TREND_RADIAL_LINE_AXIAL_LOAD,
                fr,
            )
        }));
    }
    points
}

/// The sensitivity design: the speed and axial-load lines' end points (4000 / 12000 rpm at
/// Fa 100 N; 100 / 400 N axial at 10000 rpm; Fr 300 N) for an outer fault, under every
/// lubricant variant given. The radial line is left out: it is flat in every run so far, and
/// its far end (600 N) sets the cage whirling, which costs minutes per point.
pub fn sensitivity(variants: &[LubricantVariant], duration: f64) -> Vec<StudyPoint> {
    let mut points = Vec::new();
    for v in variants {
        let point = |factor, rpm, axial_load| StudyPoint {
            factor,
            fault: FaultCase::Outer,
            rpm,
            axial_load,
            radial_load: 300.0,
            lubricant: v.clone(),
            duration,
        };
        points.push(point(Factor::Speed, 4000.0, 100.0));
        points.push(point(Factor::Speed, 12000.0, 100.0));
        points.push(point(Factor::AxialLoad, 10_000.0, 100.0));
        points.push(point(Factor::AxialLoad, 10_000.0, 400.0));
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_trends_cover_figures_23_to_28_and_validate() {
        let p = paper_trends(&LubricantVariant::paper(), 0.05);
        assert_eq!(p.len(), 2 * 17);
        for point in &p {
            point
                .scene()
                .validated()
                .expect("every design point is a valid scene");
        }
        let outer_speed: Vec<f64> = p
            .iter()
            .filter(|q| q.fault == FaultCase::Outer && q.factor == Factor::Speed)
            .map(StudyPoint::value)
            .collect();
        assert_eq!(outer_speed, TREND_SPEEDS);
    }
}
