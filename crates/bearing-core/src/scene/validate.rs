//! Scene validation: every problem at once, each with the path of its field.

use super::definition::*;
use serde::Serialize;
use std::fmt;

/// One problem with one field.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FieldError {
    /// Dotted path of the field, e.g. `bearing.ball_diameter` or `faults[1].width`.
    pub path: String,
    /// What is wrong, e.g. `must be > 0 m`.
    pub message: String,
}

/// All problems found in a scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ValidationErrors(pub Vec<FieldError>);

impl fmt::Display for ValidationErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, e) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str("; ")?;
            }
            write!(f, "{}: {}", e.path, e.message)?;
        }
        Ok(())
    }
}

impl std::error::Error for ValidationErrors {}

impl ValidationErrors {
    /// A JSON parse or type error, reported against the field serde names.
    pub fn from_serde(e: &serde_json::Error) -> Self {
        ValidationErrors(vec![FieldError {
            path: "$".into(),
            message: e.to_string(),
        }])
    }
}

/// Most defects a scene may have.
pub const MAX_FAULTS: usize = 16;

/// Heaviest load a scene may put on its bearing, as a multiple of the bearing's reference
/// static capacity `15 MPa x Z x D^2` (ISO 76's `f0 Z D^2 cos(alpha)` with the largest `f0`
/// of ball bearings, about 15 N/mm^2). At the static capacity the heaviest contact is near
/// 4.2 GPa; contact pressure grows with the cube root of load, so 100x puts it near 19 GPa,
/// beyond any bearing material: a larger load (1e12 N used to give a 4.47 m displacement)
/// describes no bearing that exists.
pub const MAX_LOAD_PER_STATIC_CAPACITY: f64 = 100.0;

/// `f0` of [`MAX_LOAD_PER_STATIC_CAPACITY`], Pa.
const STATIC_CAPACITY_FACTOR: f64 = 15e6;

/// Longest scene name, in characters: a label for listings and plot titles (a study's name
/// has the same bound). Unbounded, ten 30 MiB names grew the database to 1 GB and one
/// job listing to 315 MB.
pub const MAX_NAME_CHARS: usize = 200;

struct Checker {
    errs: Vec<FieldError>,
}

impl Checker {
    fn push(&mut self, path: &str, message: impl Into<String>) {
        self.errs.push(FieldError {
            path: path.to_string(),
            message: message.into(),
        });
    }
    /// Finite and strictly positive.
    fn pos(&mut self, path: &str, v: f64, unit: &str) -> bool {
        if !v.is_finite() {
            self.push(path, "must be a finite number");
            false
        } else if v <= 0.0 {
            self.push(path, format!("must be > 0 {unit}"));
            false
        } else {
            true
        }
    }
    /// Finite and >= 0.
    fn nonneg(&mut self, path: &str, v: f64, unit: &str) -> bool {
        if !v.is_finite() {
            self.push(path, "must be a finite number");
            false
        } else if v < 0.0 {
            self.push(path, format!("must be >= 0 {unit}"));
            false
        } else {
            true
        }
    }
    fn finite(&mut self, path: &str, v: f64) -> bool {
        if !v.is_finite() {
            self.push(path, "must be a finite number");
            false
        } else {
            true
        }
    }
    fn range(&mut self, path: &str, v: f64, lo: f64, hi: f64, unit: &str) -> bool {
        if !v.is_finite() {
            self.push(path, "must be a finite number");
            false
        } else if v <= lo || v >= hi {
            self.push(path, format!("must be in ({lo}, {hi}) {unit}"));
            false
        } else {
            true
        }
    }
}

impl Scene {
    /// Check every field and every geometric compatibility; report all problems.
    pub fn validate(&self) -> Result<(), ValidationErrors> {
        let mut c = Checker { errs: Vec::new() };
        let name_chars = self.name.chars().count();
        if name_chars > MAX_NAME_CHARS {
            c.push(
                "name",
                format!("at most {MAX_NAME_CHARS} characters, got {name_chars}"),
            );
        }
        let b = &self.bearing;
        let mut geom_ok = true;
        geom_ok &= c.pos("bearing.bore_diameter", b.bore_diameter, "m");
        geom_ok &= c.pos("bearing.outer_diameter", b.outer_diameter, "m");
        geom_ok &= c.pos("bearing.width", b.width, "m");
        geom_ok &= c.pos(
            "bearing.inner_groove_diameter",
            b.inner_groove_diameter,
            "m",
        );
        geom_ok &= c.pos(
            "bearing.outer_groove_diameter",
            b.outer_groove_diameter,
            "m",
        );
        geom_ok &= c.pos("bearing.ball_diameter", b.ball_diameter, "m");
        geom_ok &= c.range(
            "bearing.contact_angle",
            b.contact_angle,
            -1e-12,
            0.5 * std::f64::consts::PI,
            "rad",
        );
        geom_ok &= c.pos("bearing.inner_land_diameter", b.inner_land_diameter, "m");
        geom_ok &= c.pos("bearing.outer_land_diameter", b.outer_land_diameter, "m");
        geom_ok &= c.pos("bearing.cage.inner_diameter", b.cage.inner_diameter, "m");
        geom_ok &= c.pos("bearing.cage.outer_diameter", b.cage.outer_diameter, "m");
        geom_ok &= c.pos("bearing.cage.pocket_diameter", b.cage.pocket_diameter, "m");
        geom_ok &= c.pos("bearing.cage.width", b.cage.width, "m");
        geom_ok &= c.nonneg("bearing.cage.land_clearance", b.cage.land_clearance, "m");
        if b.ball_count < 3 {
            c.push("bearing.ball_count", "must be >= 3");
            geom_ok = false;
        } else if b.ball_count > 200 {
            c.push("bearing.ball_count", "must be <= 200");
            geom_ok = false;
        }
        for (path, f) in [
            ("bearing.inner_groove_curvature", b.inner_groove_curvature),
            ("bearing.outer_groove_curvature", b.outer_groove_curvature),
        ] {
            if !f.is_finite() {
                c.push(path, "must be a finite number");
                geom_ok = false;
            } else if f <= 0.5 {
                c.push(
                    path,
                    "must be > 0.5 (groove radius larger than the ball radius)",
                );
                geom_ok = false;
            } else if f >= 1.0 {
                c.push(
                    path,
                    "must be < 1.0 (a groove that shallow cannot carry a ball)",
                );
                geom_ok = false;
            }
        }
        if geom_ok {
            check_geometry(&mut c, self);
        }

        for (name, m) in [
            ("rings", &self.materials.rings),
            ("balls", &self.materials.balls),
            ("cage", &self.materials.cage),
        ] {
            c.pos(
                &format!("materials.{name}.youngs_modulus"),
                m.youngs_modulus,
                "Pa",
            );
            c.range(
                &format!("materials.{name}.poisson_ratio"),
                m.poisson_ratio,
                -1.0,
                0.5,
                "-",
            );
            c.pos(&format!("materials.{name}.density"), m.density, "kg/m^3");
        }

        let l = &self.lubricant;
        c.pos("lubricant.dynamic_viscosity", l.dynamic_viscosity, "Pa s");
        c.pos(
            "lubricant.critical_film_ball_cage",
            l.critical_film_ball_cage,
            "m",
        );
        c.pos(
            "lubricant.critical_film_cage_land",
            l.critical_film_cage_land,
            "m",
        );
        c.nonneg("lubricant.cage_friction", l.cage_friction, "-");
        if c.nonneg(
            "lubricant.contact_damping_ratio",
            l.contact_damping_ratio,
            "-",
        ) && l.contact_damping_ratio > 1.0
        {
            c.push("lubricant.contact_damping_ratio", "must be <= 1");
        }
        c.nonneg("operating.shaft_mass", o_shaft_mass(self), "kg");
        if c.pos("lubricant.density", l.density, "kg/m^3") && l.density > 2000.0 {
            c.push(
                "lubricant.density",
                "must be <= 2000 kg/m^3 (lubricating oils are 800-1000)",
            );
        }
        if c.pos("lubricant.pressure_viscosity", l.pressure_viscosity, "1/Pa")
            && l.pressure_viscosity > 1e-7
        {
            c.push(
                "lubricant.pressure_viscosity",
                "must be <= 1e-7 1/Pa (lubricating oils are 0.5-4e-8)",
            );
        }
        if let CavityDrag::OilAir { oil_fraction } = l.cavity_drag {
            let path = "lubricant.cavity_drag.oil_fraction";
            if c.nonneg(path, oil_fraction, "-") && oil_fraction > 1.0 {
                c.push(path, "must be <= 1 (a volume fraction)");
            }
        }
        if let RollingResistanceModel::Houpert { factor } = l.rolling_resistance {
            let path = "lubricant.rolling_resistance.factor";
            if c.pos(path, factor, "-") && factor > 1.0 {
                c.push(
                    path,
                    "must be <= 1 (starvation and heating only reduce the force)",
                );
            }
        }
        match l.traction {
            Traction::Abcd { a, b, c: cc, d } => {
                let ok = c.finite("lubricant.traction.a", a)
                    & c.finite("lubricant.traction.b", b)
                    & c.nonneg("lubricant.traction.c", cc, "s/m")
                    & c.nonneg("lubricant.traction.d", d, "-");
                if ok && a + d < -1e-12 {
                    c.push(
                        "lubricant.traction.a",
                        "a + d (traction at zero slip) must be >= 0",
                    );
                }
            }
            Traction::Adore {
                mu0,
                mu_max,
                mu_inf,
                u_m,
            } => {
                let ok = c.nonneg("lubricant.traction.mu0", mu0, "-")
                    & c.pos("lubricant.traction.mu_max", mu_max, "-")
                    & c.nonneg("lubricant.traction.mu_inf", mu_inf, "-")
                    & c.pos("lubricant.traction.u_m", u_m, "m/s");
                if ok && !(mu_max > mu0 && mu_max > mu_inf) {
                    c.push(
                        "lubricant.traction.mu_max",
                        "must exceed mu0 and mu_inf (it is the peak of the curve)",
                    );
                }
            }
            Traction::Rheology {
                limiting_coefficient,
                roelands_z,
            } => {
                let path = "lubricant.traction.limiting_coefficient";
                if c.pos(path, limiting_coefficient, "-") && limiting_coefficient > 0.5 {
                    c.push(path, "must be <= 0.5 (EHL films limit near 0.03-0.1)");
                }
                if let Some(z) = roelands_z {
                    let path = "lubricant.traction.roelands_z";
                    if c.pos(path, z, "-") && z > 1.5 {
                        c.push(path, "must be <= 1.5 (oils range 0.4-0.8)");
                    }
                } else if l.dynamic_viscosity.is_finite() && l.dynamic_viscosity <= 6.31e-5 {
                    // Roelands' index from the viscosity needs eta0 above its reference
                    c.push(
                        "lubricant.dynamic_viscosity",
                        "must exceed 6.31e-5 Pa s for the rheology law (Roelands' reference viscosity)",
                    );
                }
            }
            Traction::Film {
                shear_modulus,
                eyring_stress,
                limiting_coefficient,
            } => {
                c.pos("lubricant.traction.shear_modulus", shear_modulus, "Pa");
                c.pos("lubricant.traction.eyring_stress", eyring_stress, "Pa");
                let path = "lubricant.traction.limiting_coefficient";
                if c.pos(path, limiting_coefficient, "-") && limiting_coefficient > 0.5 {
                    c.push(path, "must be <= 0.5 (EHL films limit near 0.03-0.1)");
                }
            }
        }

        let o = &self.operating;
        c.nonneg(
            "operating.speed.initial_rpm",
            o.speed.initial_rpm,
            "rev/min",
        );
        c.pos("operating.speed.steady_rpm", o.speed.steady_rpm, "rev/min");
        c.nonneg("operating.speed.ramp_time", o.speed.ramp_time, "s");
        for (path, rpm) in [
            ("operating.speed.steady_rpm", o.speed.steady_rpm),
            ("operating.speed.initial_rpm", o.speed.initial_rpm),
        ] {
            if rpm.is_finite() && rpm > 100_000.0 {
                c.push(path, "must be <= 100000 rev/min");
            }
        }
        c.nonneg("operating.radial_load", o.radial_load, "N");
        if geom_ok {
            check_loads(&mut c, self);
        }
        c.finite("operating.radial_load_angle", o.radial_load_angle);
        if c.nonneg("operating.axial_load", o.axial_load, "N")
            && o.axial_load == 0.0
            && o.radial_load == 0.0
        {
            c.push(
                "operating.axial_load",
                "radial and axial load cannot both be 0 N: the rings would be unloaded",
            );
        }
        for (i, m) in o.applied_moment.iter().enumerate() {
            if c.finite(&format!("operating.applied_moment[{i}]"), *m)
                && *m != 0.0
                && o.inner_ring_tilt == TiltMode::Locked
            {
                c.push(&format!("operating.applied_moment[{i}]"), "needs operating.inner_ring_tilt = free (a locked ring cannot take an applied moment)");
            }
        }
        let p = &o.pedestal;
        c.pos("operating.pedestal.mass", p.mass, "kg");
        c.pos("operating.pedestal.stiffness_y", p.stiffness_y, "N/m");
        c.pos("operating.pedestal.stiffness_z", p.stiffness_z, "N/m");
        c.nonneg("operating.pedestal.damping_y", p.damping_y, "N s/m");
        c.nonneg("operating.pedestal.damping_z", p.damping_z, "N s/m");

        // The cap first: a scene with 100 000 bad defects gets one error, not 200 001.
        if self.faults.len() > MAX_FAULTS {
            c.push(
                "faults",
                format!(
                    "at most {MAX_FAULTS} defects, got {} (the defects themselves were not checked)",
                    self.faults.len()
                ),
            );
        } else {
            for (i, f) in self.faults.iter().enumerate() {
                let base = format!("faults[{i}]");
                c.finite(&format!("{base}.angle"), f.angle);
                let w_ok = c.pos(&format!("{base}.width"), f.width, "m");
                if c.pos(&format!("{base}.depth"), f.depth, "m") && geom_ok {
                    check_depth(&mut c, &format!("{base}.depth"), f, b);
                }
                if w_ok && geom_ok {
                    // A defect wider than the raceway (the groove arc a ball can touch, taken as
                    // the ball diameter) is no longer a localized defect.
                    if f.width >= b.ball_diameter {
                        c.push(
                            &format!("{base}.width"),
                            format!(
                                "must be < the raceway width ({:.4e} m, the ball diameter)",
                                b.ball_diameter
                            ),
                        );
                    }
                    let r = 0.5
                        * match f.ring {
                            Ring::Inner => b.inner_groove_diameter,
                            Ring::Outer => b.outer_groove_diameter,
                        };
                    if f.width >= std::f64::consts::PI * r / b.ball_count as f64 {
                        c.push(
                            &format!("{base}.width"),
                            "must be shorter than half the ball spacing on its raceway",
                        );
                    }
                }
            }
        }

        let s = &self.solver;
        if c.pos("solver.duration", s.duration, "s") {
            if s.duration > 10.0 {
                c.push("solver.duration", "must be <= 10 s");
            } else if s.sample_rate.is_finite()
                && s.sample_rate > 0.0
                && s.duration * s.sample_rate < 1.0
            {
                // a run shorter than one output sample records nothing to look at
                c.push(
                    "solver.duration",
                    format!(
                        "must be at least one output sample, 1 / solver.sample_rate = {:.3e} s",
                        1.0 / s.sample_rate
                    ),
                );
            }
        }
        if c.pos("solver.initial_step", s.initial_step, "s") && s.initial_step > 1e-3 {
            c.push("solver.initial_step", "must be <= 1e-3 s");
        }
        if c.pos("solver.rtol", s.rtol, "-") && (s.rtol < 1e-12 || s.rtol > 1e-1) {
            c.push("solver.rtol", "must be in [1e-12, 0.1]");
        }
        if c.pos("solver.atol", s.atol, "-") && (s.atol < 1e-14 || s.atol > 1e-1) {
            c.push("solver.atol", "must be in [1e-14, 0.1]");
        }
        c.pos("solver.max_step", s.max_step, "s");
        if s.traction_strips.is_some_and(|n| !(1..=200).contains(&n)) {
            c.push("solver.traction_strips", "must be in 1..=200");
        }
        if c.pos("solver.sample_rate", s.sample_rate, "Hz") {
            if s.sample_rate > 1.0e6 {
                c.push("solver.sample_rate", "must be <= 1e6 Hz");
            } else if s.duration.is_finite() && s.duration * s.sample_rate > 5.0e6 {
                c.push(
                    "solver.sample_rate",
                    "duration * sample_rate must be <= 5e6 samples",
                );
            }
        }
        for (path, ball) in [
            (
                "outputs.contact_loads_ball",
                self.outputs.contact_loads_ball,
            ),
            ("outputs.ball_pocket", self.outputs.ball_pocket),
        ] {
            if let Some(k) = ball {
                if k >= b.ball_count {
                    c.push(
                        path,
                        format!("must be < bearing.ball_count ({})", b.ball_count),
                    );
                }
            }
        }

        if c.errs.is_empty() {
            Ok(())
        } else {
            Err(ValidationErrors(c.errs))
        }
    }
}

/// Loads and moments within [`MAX_LOAD_PER_STATIC_CAPACITY`] of the bearing's reference
/// static capacity (moments: that force at the pitch radius). Needs a valid geometry.
fn check_loads(c: &mut Checker, s: &Scene) {
    let b = &s.bearing;
    let o = &s.operating;
    let capacity = STATIC_CAPACITY_FACTOR * b.ball_count as f64 * b.ball_diameter.powi(2);
    let max_force = MAX_LOAD_PER_STATIC_CAPACITY * capacity;
    let why = format!(
        "{MAX_LOAD_PER_STATIC_CAPACITY}x this bearing's reference static capacity ({capacity:.3e} N = 15 MPa x Z x D^2): contact stresses beyond any bearing material"
    );
    for (path, f) in [
        ("operating.radial_load", o.radial_load),
        ("operating.axial_load", o.axial_load),
    ] {
        if f.is_finite() && f > max_force {
            c.push(path, format!("must be <= {max_force:.3e} N, {why}"));
        }
    }
    let pitch_radius = 0.25 * (b.inner_groove_diameter + b.outer_groove_diameter);
    let max_moment = max_force * pitch_radius;
    for (i, m) in o.applied_moment.iter().enumerate() {
        if m.is_finite() && m.abs() > max_moment {
            c.push(
                &format!("operating.applied_moment[{i}]"),
                format!("must be within +-{max_moment:.3e} N m (the largest load at the pitch radius), {why}"),
            );
        }
    }
}

/// A defect no deeper than a ball can feel: the ball's radius (defects are narrower than
/// the ball, so it cannot sink further) and the ring's wall below the groove (deeper would
/// cut through the ring). A 1 m deep defect used to be accepted.
fn check_depth(c: &mut Checker, path: &str, f: &Fault, b: &Bearing) {
    let wall = 0.5
        * match f.ring {
            Ring::Inner => b.inner_groove_diameter - b.bore_diameter,
            Ring::Outer => b.outer_diameter - b.outer_groove_diameter,
        };
    let ball_radius = 0.5 * b.ball_diameter;
    if f.depth > ball_radius.min(wall) {
        c.push(
            path,
            format!(
                "must be <= {:.4e} m: the ball radius ({ball_radius:.4e} m) and the ring wall under the groove ({wall:.4e} m) bound what a ball can feel",
                ball_radius.min(wall)
            ),
        );
    }
}

fn o_shaft_mass(s: &Scene) -> f64 {
    s.operating.shaft_mass
}

/// Compatibility checks that need every dimension to be valid on its own.
fn check_geometry(c: &mut Checker, s: &Scene) {
    let b = &s.bearing;
    let d = b.ball_diameter;
    let z = b.ball_count as f64;
    if b.bore_diameter >= b.inner_groove_diameter {
        c.push(
            "bearing.inner_groove_diameter",
            "must exceed bearing.bore_diameter",
        );
    }
    if b.outer_groove_diameter >= b.outer_diameter {
        c.push(
            "bearing.outer_groove_diameter",
            "must be below bearing.outer_diameter",
        );
    }
    let pd = b.outer_groove_diameter - b.inner_groove_diameter - 2.0 * d;
    // A clearance of zero written through the groove diameters rounds to a few ulps of the
    // groove diameter either side of zero (-7e-18 m on a 40 mm groove); a billionth of the
    // groove diameter is far below any made clearance and far above that rounding.
    if pd < -1e-9 * b.outer_groove_diameter {
        c.push(
            "bearing.ball_diameter",
            format!("balls do not fit between the grooves: diametral clearance {pd:.3e} m < 0"),
        );
        return;
    }
    let dm = 0.5 * (b.inner_groove_diameter + b.outer_groove_diameter);
    // Neighbouring balls on the pitch circle must not overlap: chord 2 (dm/2) sin(pi/Z) > D.
    if dm * (std::f64::consts::PI / z).sin() <= d {
        c.push(
            "bearing.ball_count",
            format!(
                "{} balls of {:.4e} m do not fit on the {:.4e} m pitch circle",
                b.ball_count, d, dm
            ),
        );
    }
    // Free contact angle implied by clearance and conformity must match the stated one.
    let bsum = b.inner_groove_curvature + b.outer_groove_curvature - 1.0;
    let cos_free = 1.0 - pd / (2.0 * bsum * d);
    let alpha_free = cos_free.clamp(-1.0, 1.0).acos();
    if (alpha_free - b.contact_angle).abs() > 0.5_f64.to_radians() {
        c.push(
            "bearing.contact_angle",
            format!(
                "{:.3} deg is inconsistent with the clearance {:.3e} m and curvature factors (fi + fo - 1 = {:.4}), which give a free contact angle of {:.3} deg (tolerance 0.5 deg)",
                b.contact_angle.to_degrees(), pd, bsum, alpha_free.to_degrees()
            ),
        );
    }
    let cg = &b.cage;
    if cg.pocket_diameter <= d {
        c.push(
            "bearing.cage.pocket_diameter",
            "must exceed bearing.ball_diameter (the ball must fit its pocket)",
        );
    }
    if cg.inner_diameter >= cg.outer_diameter {
        c.push(
            "bearing.cage.inner_diameter",
            "must be below bearing.cage.outer_diameter",
        );
    }
    // The pocket walls must reach the ball: the cage annulus has to overlap the ball's
    // radial span (H7005C's cage, 36-39.27 mm, sits just outside the 35.99 mm pitch circle).
    if cg.inner_diameter >= dm + d || cg.outer_diameter <= dm - d {
        c.push(
            "bearing.cage.inner_diameter",
            "the cage annulus does not overlap the balls radially",
        );
    }
    // Pockets must leave cage material between them on the cage bore.
    if 0.5 * cg.inner_diameter * 2.0 * (std::f64::consts::PI / z).sin() <= cg.pocket_diameter {
        c.push(
            "bearing.cage.pocket_diameter",
            "pockets overlap each other on the cage bore",
        );
    }
    if cg.width <= cg.pocket_diameter {
        c.push("bearing.cage.width", "must exceed the pocket diameter");
    }
    if cg.width > b.width {
        c.push("bearing.cage.width", "must not exceed bearing.width");
    }
    if b.inner_land_diameter <= b.inner_groove_diameter || b.inner_land_diameter >= dm {
        c.push(
            "bearing.inner_land_diameter",
            "must lie between the inner groove diameter and the pitch diameter",
        );
    }
    if b.outer_land_diameter >= b.outer_groove_diameter || b.outer_land_diameter <= dm {
        c.push(
            "bearing.outer_land_diameter",
            "must lie between the pitch diameter and the outer groove diameter",
        );
    }
    match cg.guidance {
        CageGuidance::OuterLand => {
            if cg.outer_diameter >= b.outer_land_diameter {
                c.push(
                    "bearing.cage.outer_diameter",
                    "must be below bearing.outer_land_diameter for an outer-land-guided cage",
                );
            } else if (b.outer_land_diameter - cg.outer_diameter - cg.land_clearance).abs() > 1e-6 {
                c.push(
                    "bearing.cage.land_clearance",
                    format!(
                        "must equal outer_land_diameter - cage.outer_diameter = {:.4e} m",
                        b.outer_land_diameter - cg.outer_diameter
                    ),
                );
            }
        }
        CageGuidance::InnerLand => {
            if cg.inner_diameter <= b.inner_land_diameter {
                c.push(
                    "bearing.cage.inner_diameter",
                    "must exceed bearing.inner_land_diameter for an inner-land-guided cage",
                );
            } else if (cg.inner_diameter - b.inner_land_diameter - cg.land_clearance).abs() > 1e-6 {
                c.push(
                    "bearing.cage.land_clearance",
                    format!(
                        "must equal cage.inner_diameter - inner_land_diameter = {:.4e} m",
                        cg.inner_diameter - b.inner_land_diameter
                    ),
                );
            }
        }
        CageGuidance::Ball => {}
    }
    if cg.outer_diameter >= b.outer_land_diameter && cg.guidance != CageGuidance::OuterLand {
        c.push(
            "bearing.cage.outer_diameter",
            "cage would interfere with the outer land",
        );
    }
    if cg.inner_diameter <= b.inner_land_diameter && cg.guidance != CageGuidance::InnerLand {
        c.push(
            "bearing.cage.inner_diameter",
            "cage would interfere with the inner land",
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> Scene {
        crate::scene::preset_scene("h7005c").unwrap()
    }

    #[test]
    fn reports_every_problem_with_its_path() {
        let mut s = scene();
        s.bearing.ball_diameter = -1.0;
        s.lubricant.dynamic_viscosity = f64::NAN;
        s.solver.duration = 0.0;
        let errs = s.validate().unwrap_err().0;
        let paths: Vec<_> = errs.iter().map(|e| e.path.as_str()).collect();
        assert!(paths.contains(&"bearing.ball_diameter"), "{paths:?}");
        assert!(paths.contains(&"lubricant.dynamic_viscosity"));
        assert!(paths.contains(&"solver.duration"));
        let e = errs
            .iter()
            .find(|e| e.path == "bearing.ball_diameter")
            .unwrap();
        assert_eq!(e.message, "must be > 0 m");
    }

    #[test]
    fn drag_and_rolling_resistance_inputs_are_checked() {
        let mut s = scene();
        s.lubricant.cavity_drag = CavityDrag::OilAir { oil_fraction: 1.5 };
        s.lubricant.rolling_resistance = RollingResistanceModel::Houpert { factor: 0.0 };
        s.lubricant.pressure_viscosity = 1e-6;
        let errs = s.validate().unwrap_err().0;
        let msg = |path: &str| {
            errs.iter()
                .find(|e| e.path == path)
                .map(|e| e.message.clone())
                .unwrap_or_else(|| panic!("no error for {path}: {errs:?}"))
        };
        assert!(msg("lubricant.cavity_drag.oil_fraction").contains("<= 1"));
        assert!(msg("lubricant.rolling_resistance.factor").contains("> 0"));
        assert!(msg("lubricant.pressure_viscosity").contains("1e-7"));
        // the limits themselves are accepted: air only, fully flooded
        let mut s = scene();
        s.lubricant.cavity_drag = CavityDrag::OilAir { oil_fraction: 0.0 };
        s.lubricant.rolling_resistance = RollingResistanceModel::Houpert { factor: 1.0 };
        assert!(s.validate().is_ok());
    }

    #[test]
    fn recorded_balls_must_exist() {
        let mut s = scene();
        s.outputs.contact_loads_ball = Some(16);
        s.outputs.ball_pocket = Some(16);
        let errs = s.validate().unwrap_err().0;
        for path in ["outputs.contact_loads_ball", "outputs.ball_pocket"] {
            let e = errs
                .iter()
                .find(|e| e.path == path)
                .unwrap_or_else(|| panic!("{errs:?}"));
            assert_eq!(e.message, "must be < bearing.ball_count (16)");
        }
        s.outputs.contact_loads_ball = Some(15);
        s.outputs.ball_pocket = Some(15);
        assert!(s.validate().is_ok());
    }

    #[test]
    fn too_many_defects_is_one_error_however_bad_they_are() {
        let mut s = scene();
        let bad = Fault {
            ring: Ring::Outer,
            angle: f64::NAN,
            width: -1.0,
            depth: f64::INFINITY,
        };
        s.faults = vec![bad; 100_000];
        let errs = s.validate().unwrap_err().0;
        assert_eq!(errs.len(), 1, "{:?}", &errs[..errs.len().min(3)]);
        assert_eq!(errs[0].path, "faults");
        assert!(
            errs[0].message.contains("got 100000"),
            "{}",
            errs[0].message
        );
        // within the cap every defect is still checked
        s.faults.truncate(MAX_FAULTS);
        let errs = s.validate().unwrap_err().0;
        assert!(
            errs.iter().any(|e| e.path == "faults[15].width"),
            "{errs:?}"
        );
    }

    #[test]
    fn implicit_integrators_are_accepted_at_every_fidelity() {
        let mut s = scene();
        for fidelity in [Fidelity::QuasiStaticBalls, Fidelity::ConcentricCage] {
            s.solver.fidelity = fidelity;
            for integrator in [
                Integrator::RosenbrockW,
                Integrator::Auto,
                Integrator::SlipImplicit,
                Integrator::AutoSlip,
                Integrator::AutoEtd,
            ] {
                s.solver.integrator = integrator;
                assert!(s.validate().is_ok(), "{fidelity:?} {integrator:?}");
            }
        }
    }

    #[test]
    fn film_traction_inputs_are_checked() {
        let mut s = scene();
        s.lubricant.traction = Traction::Film {
            shear_modulus: 0.0,
            eyring_stress: f64::NAN,
            limiting_coefficient: 0.8,
        };
        let errs = s.validate().unwrap_err().0;
        let paths: Vec<&str> = errs.iter().map(|e| e.path.as_str()).collect();
        assert_eq!(
            paths,
            [
                "lubricant.traction.shear_modulus",
                "lubricant.traction.eyring_stress",
                "lubricant.traction.limiting_coefficient"
            ],
            "{errs:?}"
        );
        // the defaults parse from the JSON tag alone and validate
        let mut s = scene();
        s.lubricant.traction = serde_json::from_str(r#"{"model": "film"}"#).unwrap();
        assert!(s.validate().is_ok());
        assert_eq!(
            s.lubricant.traction,
            Traction::Film {
                shear_modulus: 1e9,
                eyring_stress: 5e6,
                limiting_coefficient: 0.07
            }
        );
    }

    #[test]
    fn meaningless_inputs_are_refused_naming_their_field() {
        let paths = |s: &Scene| -> Vec<String> {
            s.validate()
                .err()
                .map(|e| e.0.into_iter().map(|e| e.path).collect())
                .unwrap_or_default()
        };
        // the issue's inputs: a 1 MiB name, 1e12 N, a 1 m defect, a 5e-324 s run
        let mut s = scene();
        s.name = "x".repeat(1 << 20);
        s.operating.axial_load = 1e12;
        s.operating.applied_moment = [0.0, 0.0];
        s.operating.speed.initial_rpm = 1e12;
        s.faults.push(Fault {
            ring: Ring::Inner,
            angle: 0.0,
            width: 0.2e-3,
            depth: 1.0,
        });
        s.solver.duration = 5e-324;
        assert_eq!(
            paths(&s),
            [
                "name",
                "operating.speed.initial_rpm",
                "operating.axial_load",
                "faults[0].depth",
                "solver.duration"
            ]
        );
        // at the bounds: 200 characters (multi-byte ones count once), one output sample,
        // a defect as deep as the ring wall or the ball radius, 100x the reference capacity
        let mut s = scene();
        let wall = 0.5 * (s.bearing.outer_diameter - s.bearing.outer_groove_diameter);
        s.name = "\u{e9}".repeat(MAX_NAME_CHARS);
        s.solver.duration = 1.0 / s.solver.sample_rate;
        let capacity = 15e6 * s.bearing.ball_count as f64 * s.bearing.ball_diameter.powi(2);
        s.operating.radial_load = 100.0 * capacity;
        s.faults.push(Fault {
            ring: Ring::Outer,
            angle: 0.0,
            width: 0.2e-3,
            depth: wall.min(0.5 * s.bearing.ball_diameter),
        });
        assert_eq!(paths(&s), Vec::<String>::new());
        s.name.push('x');
        s.operating.radial_load *= 1.01;
        s.faults[0].depth *= 1.01;
        s.solver.duration *= 0.99;
        assert_eq!(
            paths(&s),
            [
                "name",
                "operating.radial_load",
                "faults[0].depth",
                "solver.duration"
            ]
        );
    }

    #[test]
    fn rejects_impossible_geometry() {
        let mut s = scene();
        s.bearing.inner_groove_curvature = 0.5;
        assert!(s
            .validate()
            .unwrap_err()
            .0
            .iter()
            .any(|e| e.path == "bearing.inner_groove_curvature"));

        let mut s = scene();
        s.bearing.ball_count = 30; // 30 balls of 5.556 mm on a 36 mm pitch circle overlap
        assert!(s
            .validate()
            .unwrap_err()
            .0
            .iter()
            .any(|e| e.path == "bearing.ball_count"));

        let mut s = scene();
        s.bearing.contact_angle = 25f64.to_radians();
        assert!(s
            .validate()
            .unwrap_err()
            .0
            .iter()
            .any(|e| e.path == "bearing.contact_angle"));

        let mut s = scene();
        s.bearing.cage.pocket_diameter = 5.0e-3;
        assert!(s
            .validate()
            .unwrap_err()
            .0
            .iter()
            .any(|e| e.path == "bearing.cage.pocket_diameter"));

        let mut s = scene();
        s.faults.push(Fault {
            ring: Ring::Outer,
            angle: 0.0,
            width: 6e-3,
            depth: 1e-4,
        });
        assert!(s
            .validate()
            .unwrap_err()
            .0
            .iter()
            .any(|e| e.path == "faults[0].width"));
    }
}
