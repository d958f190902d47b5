//! Built-in scenes: the paper's H7005C (Table 1) and its Table 2 fault-size groups.
//!
//! Every value the paper does not give is chosen here, with its reason beside it; the
//! same list, longer, is in `docs/reference/model.md`.

use super::definition::*;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Names accepted by [`preset_scene`].
pub fn preset_names() -> &'static [&'static str] {
    &["h7005c"]
}

/// Fault cases of a preset: which of its defects are present.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum FaultCase {
    None,
    Inner,
    Outer,
    Compound,
}

impl std::str::FromStr for FaultCase {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "none" => Ok(FaultCase::None),
            "inner" => Ok(FaultCase::Inner),
            "outer" => Ok(FaultCase::Outer),
            "compound" => Ok(FaultCase::Compound),
            _ => Err(format!(
                "unknown fault case '{s}': expected none, inner, outer or compound"
            )),
        }
    }
}

/// One row of the paper's Table 2 (three-factor orthogonal design of defect sizes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct Table2Group {
    /// Serial number 1..=9.
    pub group: u32,
    /// Inner defect diameter, m.
    pub inner_width: f64,
    /// Inner defect depth, m.
    pub inner_depth: f64,
    /// Outer defect diameter, m.
    pub outer_width: f64,
    /// Outer defect depth, m.
    pub outer_depth: f64,
}

/// The nine fault-size groups of Table 2, converted from mm to m.
pub fn table2_groups() -> Vec<Table2Group> {
    const ROWS: [(u32, f64, f64, f64, f64); 9] = [
        (1, 0.1, 0.05, 0.1, 0.05),
        (2, 0.1, 0.1, 0.2, 0.1),
        (3, 0.1, 0.15, 0.3, 0.15),
        (4, 0.2, 0.05, 0.3, 0.1),
        (5, 0.2, 0.1, 0.1, 0.15),
        (6, 0.2, 0.15, 0.2, 0.05),
        (7, 0.3, 0.05, 0.2, 0.15),
        (8, 0.3, 0.1, 0.3, 0.05),
        (9, 0.3, 0.15, 0.1, 0.1),
    ];
    ROWS.iter()
        .map(|&(group, wi, hi, wo, ho)| Table2Group {
            group,
            inner_width: wi * 1e-3,
            inner_depth: hi * 1e-3,
            outer_width: wo * 1e-3,
            outer_depth: ho * 1e-3,
        })
        .collect()
}

/// A preset scene by name, with no defects.
pub fn preset_scene(name: &str) -> Option<Scene> {
    match name.to_ascii_lowercase().as_str() {
        "h7005c" => Some(h7005c()),
        _ => None,
    }
}

/// A preset scene with the defects of `case` (Table 1 sizes for H7005C).
pub fn fault_case_scene(name: &str, case: FaultCase) -> Option<Scene> {
    let mut scene = preset_scene(name)?;
    let load_zone = scene.operating.radial_load_angle;
    // Table 1: inner defect 0.2 mm diameter, 0.1 mm deep; outer defect depth 0.1 mm, its
    // diameter is blank in the table: 0.2 mm is taken (same as the inner one).
    let inner = Fault {
        ring: Ring::Inner,
        angle: load_zone,
        width: 0.2e-3,
        depth: 0.1e-3,
    };
    let outer = Fault {
        ring: Ring::Outer,
        angle: load_zone,
        width: 0.2e-3,
        depth: 0.1e-3,
    };
    scene.faults = match case {
        FaultCase::None => vec![],
        FaultCase::Inner => vec![inner],
        FaultCase::Outer => vec![outer],
        FaultCase::Compound => vec![inner, outer],
    };
    scene.name = format!(
        "{} {}",
        scene.name,
        match case {
            FaultCase::None => "no fault",
            FaultCase::Inner => "inner-ring fault",
            FaultCase::Outer => "outer-ring fault",
            FaultCase::Compound => "compound inner+outer fault",
        }
    );
    Some(scene)
}

/// Sum of groove curvature factors `fi + fo` implied by a diametral clearance and a
/// free contact angle: `cos(alpha) = 1 - Pd / (2 (fi + fo - 1) D)`.
pub fn curvature_sum_for(pd: f64, ball_diameter: f64, contact_angle: f64) -> f64 {
    1.0 + pd / (2.0 * ball_diameter * (1.0 - contact_angle.cos()))
}

/// H7005C spindle bearing, Table 1, with documented choices for what the table omits.
fn h7005c() -> Scene {
    let d_groove_i = 30.425e-3;
    let d_groove_o = 41.562e-3;
    let ball = 5.556e-3;
    let alpha = 15.0 * PI / 180.0;
    // Diametral clearance from the groove diameters: 41.562 - 30.425 - 2 * 5.556 = 0.025 mm.
    let pd = d_groove_o - d_groove_i - 2.0 * ball;
    // fi + fo - 1 = 0.066 follows from Pd and the 15 deg free contact angle; the split
    // fi = 0.53 is typical for spindle bearings (a tighter inner conformity than outer).
    let f_sum = curvature_sum_for(pd, ball, alpha);
    let fi = 0.53;
    let fo = f_sum - fi;
    Scene {
        name: "H7005C (Table 1)".into(),
        bearing: Bearing {
            bore_diameter: 25.0e-3,
            outer_diameter: 47.0e-3,
            width: 12.0e-3,
            inner_groove_diameter: d_groove_i,
            outer_groove_diameter: d_groove_o,
            ball_diameter: ball,
            ball_count: 16,
            contact_angle: alpha,
            inner_groove_curvature: fi,
            outer_groove_curvature: fo,
            // Inner shoulder below the 36 mm cage bore with 1.5 mm radial margin; outer land
            // 0.2 mm (diametral) above the 39.27 mm cage outside diameter it pilots.
            inner_land_diameter: 33.0e-3,
            outer_land_diameter: 39.47e-3,
            cage: Cage {
                inner_diameter: 36.0e-3,
                outer_diameter: 39.27e-3,
                pocket_diameter: 5.89e-3,
                // Two thirds of the 12 mm ring width, usual for a one-piece window cage.
                width: 8.0e-3,
                // Spindle bearings of this series carry an outer-ring-guided phenolic cage.
                guidance: CageGuidance::OuterLand,
                land_clearance: 0.2e-3,
            },
        },
        materials: Materials {
            // GCr15 (AISI 52100) bearing steel; density from Table 1.
            rings: Material {
                youngs_modulus: 208e9,
                poisson_ratio: 0.3,
                density: 7830.0,
            },
            balls: Material {
                youngs_modulus: 208e9,
                poisson_ratio: 0.3,
                density: 7830.0,
            },
            // Cotton-fabric phenolic laminate; density 1.3 g/cm^3 from Table 1.
            cage: Material {
                youngs_modulus: 7.0e9,
                poisson_ratio: 0.35,
                density: 1300.0,
            },
        },
        lubricant: Lubricant {
            // Table 1 gives 5.1 mm^2/s (a kinematic viscosity); times a base-oil density of
            // 870 kg/m^3 that is 4.44 mPa s. 5.1 mm^2/s is a hot spindle-grease base oil:
            // FAG's L252 high-speed spindle grease has 5 mm^2/s at 100 deg C (25 at 40);
            // base oils range 840 (PAO) to 900 kg/m^3 (naphthenic; Höglund 1999 as given by
            // Arana et al. 2019, Table 2). docs/lab/research/issue-33-traction-sources.md.
            dynamic_viscosity: 5.1e-6 * 870.0,
            // The rheology law (Roelands at each strip's Hertz pressure, Eyring thinning, a
            // limiting shear stress proportional to pressure, the Hamrock-Dowson film; the
            // film's elastic compliance left out): the law that gives the paper's cage lag
            // (BPFO below eq. 37, BPFI above), with `auto_etd` below taking its stiff slip
            // relaxation (docs/reference/model.md, "Traction laws"). The paper's eq. 15 curve is `Traction::PAPER_CURVE` (`abcd`).
            traction: Traction::RHEOLOGY,
            critical_film_ball_cage: 0.8e-6,
            critical_film_cage_land: 3.0e-6,
            cage_friction: 0.08,
            // EHL film damping of ball-race contacts, of the order measured for ball
            // bearings (0.02-0.1); without it ball-race modes (~40 kHz) never decay.
            contact_damping_ratio: 0.05,
            density: 870.0,
            // Pressure-viscosity coefficient of a light spindle oil: Stachowiak & Batchelor,
            // Table 2.3, "spindle oil" 16e-9 at 60 deg C and 13e-9 1/Pa at 100 deg C; with
            // the viscosity above it gives Roelands' Z = 0.69 (0.68-0.81 computed from the
            // same table's oils).
            pressure_viscosity: 1.5e-8,
            // No read source sizes the cavity drag for a greased spindle bearing: opt in with
            // `oil_air` (oil fraction 0.01 for a channelled grease). The rolling resistance is
            // the rolling force of the same fully flooded, isothermal film the traction law
            // shears (Biboulet & Houpert 2010, Part 2, eq. 32; factor 1, fully flooded), and
            // it removes the law's slow first cage regime; the paper's model has neither
            // (docs/reference/model.md, "EHL rolling resistance").
            cavity_drag: CavityDrag::None,
            rolling_resistance: RollingResistanceModel::Houpert { factor: 1.0 },
        },
        operating: Operating {
            speed: SpeedProfile {
                initial_rpm: 1000.0,
                steady_rpm: 10000.0,
                ramp_time: 0.1,
            },
            radial_load: 300.0,
            radial_load_angle: 0.0,
            axial_load: 100.0,
            inner_ring_tilt: TiltMode::Locked,
            // Share of the spindle carried with the inner ring in the paper's cantilever rig.
            shaft_mass: 0.5,
            applied_moment: [0.0, 0.0],
            // 0.3 kg (outer ring plus the housing mass that moves with it) on 2e8 N/m puts
            // the pedestal resonance at 4.1 kHz, inside the usual envelope-analysis band;
            // damping ratio 0.05 (c = 2 * 0.05 * sqrt(k m)).
            pedestal: Pedestal {
                mass: 0.3,
                stiffness_y: 2.0e8,
                stiffness_z: 2.0e8,
                damping_y: 2.0 * 0.05 * (2.0e8f64 * 0.3).sqrt(),
                damping_z: 2.0 * 0.05 * (2.0e8f64 * 0.3).sqrt(),
            },
        },
        faults: vec![],
        solver: Solver {
            duration: 0.5,
            // the law's slip relaxes in ~1e-7 s: `auto_etd` takes it implicitly where that
            // is cheaper (low speed), and elsewhere the contact oscillators, the spins' and
            // the cage's relaxations exactly, the contact modes never damped numerically,
            // the rest explicitly: about 0.7 of `auto_slip`'s time on the Table-1 case, its
            // band RMS within 1 % of a tight reference (docs/reference/model.md, "Solver and
            // integrators"; docs/lab/benchmarks.md)
            integrator: Integrator::AutoEtd,
            ..Solver::default()
        },
        outputs: Outputs::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn h7005c_reproduces_table1() {
        let s = preset_scene("h7005c").unwrap();
        let b = &s.bearing;
        assert_eq!(b.ball_count, 16);
        assert_eq!(b.ball_diameter, 5.556e-3);
        assert_eq!(b.inner_groove_diameter, 30.425e-3);
        assert_eq!(b.outer_groove_diameter, 41.562e-3);
        assert_eq!(b.cage.pocket_diameter, 5.89e-3);
        assert_eq!(s.operating.radial_load, 300.0);
        assert_eq!(s.operating.axial_load, 100.0);
        // fi + fo - 1 implied by Pd = 0.025 mm and 15 deg is 0.066 (brief), to 3 decimals.
        let b_total = b.inner_groove_curvature + b.outer_groove_curvature - 1.0;
        assert!((b_total - 0.066).abs() < 5e-4, "{b_total}");
        s.validate().unwrap();
    }

    #[test]
    fn fault_cases_place_defects_in_load_zone() {
        let s = fault_case_scene("h7005c", FaultCase::Compound).unwrap();
        assert_eq!(s.faults.len(), 2);
        assert!(s
            .faults
            .iter()
            .all(|f| f.angle == s.operating.radial_load_angle));
        assert!(fault_case_scene("h7005c", FaultCase::None)
            .unwrap()
            .faults
            .is_empty());
        assert_eq!(table2_groups().len(), 9);
    }
}
