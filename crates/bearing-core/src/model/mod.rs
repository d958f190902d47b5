//! Constants of one bearing model, derived once from a valid scene: what the
//! quasi-static solver and the equations of motion share.

pub mod layout;

use crate::physics::cage_land::LandParams;
use crate::physics::cage_pocket::PocketParams;
use crate::physics::defect::RaceDefect;
use crate::physics::drag::{BallDrag, CavityMedium};
use crate::physics::frames::Azimuth;
use crate::physics::hertz::{effective_modulus, exact, hamrock_brewe, HertzContact};
use crate::physics::race_contact::{ContactParams, Race};
use crate::physics::rheology_traction::{roelands_z, Rheology, RheologyTraction};
use crate::physics::rolling_resistance::RollingResistance;
use crate::physics::strips::{StripRule, Strips};
use crate::physics::traction::{FilmRheology, FilmTraction, TractionCurve, TractionLaw};
use crate::scene::{
    CageGuidance, CavityDrag, Fidelity, HertzModel, Ring, RollingResistanceModel, TiltMode,
    Traction, TractionQuadrature, ValidScene,
};
use layout::{cage, inner, outer};
use std::f64::consts::PI;

use layout::Layout;

/// Everything the right-hand side needs, in SI units.
#[derive(Debug, Clone)]
pub struct Model {
    pub layout: Layout,
    pub z: usize,
    /// Ball diameter, m.
    pub ball_diameter: f64,
    /// Ball mass, kg.
    pub ball_mass: f64,
    /// Ball moment of inertia, kg m^2.
    pub ball_inertia: f64,
    /// Pitch diameter (mean of groove diameters), m.
    pub pitch_diameter: f64,
    /// Free contact angle from clearance and conformity, rad.
    pub free_contact_angle: f64,
    pub inner_race: Race,
    pub outer_race: Race,
    pub contact: ContactParams,
    pub pocket: PocketParams,
    /// None for a ball-guided cage.
    pub land: Option<LandParams>,
    pub land_on_outer: bool,
    /// Inner ring plus shaft share, kg.
    pub inner_mass: f64,
    /// Inner ring diametral moment of inertia (with shaft share as a point mass at the axis), kg m^2.
    pub inner_tilt_inertia: f64,
    pub tilt_free: bool,
    pub applied_force: [f64; 3],
    pub applied_moment: [f64; 2],
    pub pedestal_mass: f64,
    pub pedestal_k: [f64; 2],
    pub pedestal_c: [f64; 2],
    pub cage_mass: f64,
    /// Cage inertia about its axis and a diameter, kg m^2.
    pub cage_inertia: [f64; 2],
    /// Speed profile: initial and steady speed (rad/s), ramp time (s).
    pub speed: (f64, f64, f64),
    /// Positions of the pockets in the cage frame, rad.
    pub pocket_angles: Vec<f64>,
    /// The same as sines and cosines.
    pub pocket_azimuths: Vec<Azimuth>,
    /// Drag of the cavity medium on each ball; None without cavity drag.
    pub ball_drag: Option<BallDrag>,
    /// The cavity medium acting on the cage faces; None without cavity drag.
    pub cage_windage: Option<CavityMedium>,
    /// Cage outer and inner radius, m (for the face windage).
    pub cage_radii: [f64; 2],
    /// Ball centres held in quasi-static equilibrium (`solver.fidelity`), not integrated.
    pub quasi_static_balls: bool,
    /// Cage held concentric with its guiding ring and untilted; only its spin is integrated.
    pub concentric_cage: bool,
}

impl Model {
    pub fn new(scene: &ValidScene) -> Model {
        // decide the contact code's instruction set here, so that the right-hand side never
        // reads the environment (which allocates)
        crate::physics::cpu::wide_vectors();
        let b = &scene.bearing;
        let m = &scene.materials;
        let d = b.ball_diameter;
        let rb = 0.5 * d;
        let z = b.ball_count;
        let dm = 0.5 * (b.inner_groove_diameter + b.outer_groove_diameter);
        let pd = b.outer_groove_diameter - b.inner_groove_diameter - 2.0 * d;
        let bsum = (b.inner_groove_curvature + b.outer_groove_curvature - 1.0) * d;
        let cos_free = 1.0 - pd / (2.0 * bsum);
        let alpha0 = cos_free.clamp(-1.0, 1.0).acos();
        let gamma = d * alpha0.cos() / dm;
        let hertz: fn(f64, f64, f64) -> HertzContact = match scene.solver.hertz {
            HertzModel::HamrockBrewe => hamrock_brewe,
            HertzModel::Exact => exact,
        };
        let ep_race = effective_modulus(
            m.balls.youngs_modulus,
            m.balls.poisson_ratio,
            m.rings.youngs_modulus,
            m.rings.poisson_ratio,
        );
        // One race: `sign` is -1 for the inner race (convex, ball outside the curvature-
        // centre circle), +1 for the outer race (concave). Curvature centres: outer at
        // x = 0, inner offset axially so that an unloaded ball touches both at the free
        // contact angle (eqs. 4-7).
        let lub = &scene.lubricant;
        let race = |ring: Ring, groove_diameter: f64, f: f64, centre_axial: f64| {
            let sign = if ring == Ring::Inner { -1.0 } else { 1.0 };
            let rx = 0.5 * d * (1.0 + sign * gamma);
            let ry = f * d / (2.0 * f - 1.0);
            let path = 0.5 * dm + sign * rb * alpha0.cos();
            let hz = hertz(rx, ry, ep_race);
            Race {
                inner: ring == Ring::Inner,
                centre_radius: 0.5 * groove_diameter - sign * f * d,
                centre_axial,
                free_distance: (f - 0.5) * d,
                hertz: hz,
                traction: match lub.traction {
                    Traction::Film {
                        shear_modulus,
                        eyring_stress,
                        limiting_coefficient,
                    } => TractionLaw::Film(FilmTraction::new(
                        ep_race,
                        rx,
                        &hz,
                        &FilmRheology {
                            eta0: lub.dynamic_viscosity,
                            alpha: lub.pressure_viscosity,
                            shear_modulus,
                            eyring_stress,
                            limiting: limiting_coefficient,
                        },
                    )),
                    Traction::Rheology {
                        limiting_coefficient,
                        roelands_z: z,
                    } => TractionLaw::Rheology(RheologyTraction::new(
                        ep_race,
                        rx,
                        &hz,
                        &Rheology {
                            eta0: lub.dynamic_viscosity,
                            alpha0: lub.pressure_viscosity,
                            z: z.unwrap_or_else(|| {
                                roelands_z(lub.dynamic_viscosity, lub.pressure_viscosity)
                            }),
                            limiting: limiting_coefficient,
                        },
                    )),
                    Traction::Abcd { .. } | Traction::Adore { .. } => {
                        let (a, b, c, d) = lub.traction.abcd().expect("a curve");
                        TractionLaw::Curve(TractionCurve { a, b, c, d })
                    }
                },
                rolling: match lub.rolling_resistance {
                    RollingResistanceModel::None => None,
                    RollingResistanceModel::Houpert { factor } => Some(RollingResistance::new(
                        ep_race,
                        rx,
                        ry,
                        lub.dynamic_viscosity,
                        factor,
                    )),
                },
                r_prime: 2.0 * f * d / (2.0 * f + 1.0),
                ball_radius: rb,
                path_radius: path,
                rx,
                defects: scene
                    .faults
                    .iter()
                    .filter(|fault| fault.ring == ring)
                    .map(|fault| RaceDefect::new(fault.angle, fault.width, fault.depth, path))
                    .collect(),
            }
        };
        let inner_race = race(
            Ring::Inner,
            b.inner_groove_diameter,
            b.inner_groove_curvature,
            bsum * alpha0.sin(),
        );
        let outer_race = race(
            Ring::Outer,
            b.outer_groove_diameter,
            b.outer_groove_curvature,
            0.0,
        );
        let ball_mass = m.balls.density * PI * d * d * d / 6.0;
        let contact = ContactParams {
            strips: Strips::new(
                scene.traction_strips(),
                match scene.solver.traction_quadrature {
                    TractionQuadrature::Gauss => StripRule::Gauss,
                    TractionQuadrature::EqualStrips => StripRule::Equal,
                },
            ),
            damping_ratio: scene.lubricant.contact_damping_ratio,
            ball_mass,
        };
        let cg = &b.cage;
        let ep_cage = effective_modulus(
            m.balls.youngs_modulus,
            m.balls.poisson_ratio,
            m.cage.youngs_modulus,
            m.cage.poisson_ratio,
        );
        // Ball in a cylindrical pocket: conformal across the pocket axis, sphere along it.
        let r_across = 1.0 / (2.0 / d - 2.0 / cg.pocket_diameter);
        let pocket = PocketParams {
            clearance: 0.5 * (cg.pocket_diameter - d),
            pocket_radius: 0.5 * dm,
            hertz: hertz(rb, r_across, ep_cage),
            critical_film: scene.lubricant.critical_film_ball_cage,
            viscosity: scene.lubricant.dynamic_viscosity,
            ball_radius: rb,
            friction: scene.lubricant.cage_friction,
            damping_ratio: scene.lubricant.contact_damping_ratio,
            damping_mass: ball_mass,
        };
        let ep_land = effective_modulus(
            m.rings.youngs_modulus,
            m.rings.poisson_ratio,
            m.cage.youngs_modulus,
            m.cage.poisson_ratio,
        );
        let (ro, ri) = (0.5 * cg.outer_diameter, 0.5 * cg.inner_diameter);
        let cage_volume = PI * (ro * ro - ri * ri) * cg.width
            - z as f64 * 0.25 * PI * cg.pocket_diameter * cg.pocket_diameter * (ro - ri);
        let cage_mass = m.cage.density * cage_volume;
        let land_k = 0.25 * PI * ep_land * cg.width;
        let land_of = |radius: f64| LandParams {
            clearance: 0.5 * cg.land_clearance,
            radius,
            width: cg.width,
            viscosity: scene.lubricant.dynamic_viscosity,
            critical_film: scene
                .lubricant
                .critical_film_cage_land
                .min(0.5 * cg.land_clearance * 0.9),
            contact_stiffness: land_k,
            friction: scene.lubricant.cage_friction,
            contact_damping: 2.0
                * scene.lubricant.contact_damping_ratio
                * (land_k * cage_mass).sqrt(),
        };
        let (land, land_on_outer) = match cg.guidance {
            CageGuidance::OuterLand => (Some(land_of(0.5 * cg.outer_diameter)), true),
            CageGuidance::InnerLand => (Some(land_of(0.5 * cg.inner_diameter)), false),
            CageGuidance::Ball => (None, false),
        };
        let cage_inertia = [
            0.5 * cage_mass * (ro * ro + ri * ri),
            cage_mass * (3.0 * (ro * ro + ri * ri) + cg.width * cg.width) / 12.0,
        ];
        let (rio, rii) = (0.5 * b.inner_land_diameter, 0.5 * b.bore_diameter);
        let ring_mass = m.rings.density * PI * (rio * rio - rii * rii) * b.width;
        let inner_mass = ring_mass + scene.operating.shaft_mass;
        let inner_tilt_inertia =
            ring_mass * (3.0 * (rio * rio + rii * rii) + b.width * b.width) / 12.0;
        let op = &scene.operating;
        let (s, c) = op.radial_load_angle.sin_cos();
        let rpm = |n: f64| n * 2.0 * PI / 60.0;
        let speed = if op.speed.ramp_time > 0.0 {
            (
                rpm(op.speed.initial_rpm),
                rpm(op.speed.steady_rpm),
                op.speed.ramp_time,
            )
        } else {
            (rpm(op.speed.steady_rpm), rpm(op.speed.steady_rpm), 0.0)
        };
        let medium = match lub.cavity_drag {
            CavityDrag::None => None,
            CavityDrag::OilAir { oil_fraction } => Some(CavityMedium::mixture(
                oil_fraction,
                lub.density,
                lub.dynamic_viscosity,
            )),
        };
        Model {
            layout: Layout::new(z),
            z,
            ball_diameter: d,
            ball_mass,
            ball_inertia: 0.4 * ball_mass * rb * rb,
            pitch_diameter: dm,
            free_contact_angle: alpha0,
            inner_race,
            outer_race,
            contact,
            pocket,
            land,
            land_on_outer,
            inner_mass,
            inner_tilt_inertia,
            tilt_free: op.inner_ring_tilt == TiltMode::Free,
            applied_force: [op.axial_load, -op.radial_load * s, op.radial_load * c],
            applied_moment: op.applied_moment,
            pedestal_mass: op.pedestal.mass,
            pedestal_k: [op.pedestal.stiffness_y, op.pedestal.stiffness_z],
            pedestal_c: [op.pedestal.damping_y, op.pedestal.damping_z],
            cage_mass,
            cage_inertia,
            speed,
            pocket_angles: (0..z).map(|j| 2.0 * PI * j as f64 / z as f64).collect(),
            pocket_azimuths: (0..z)
                .map(|j| Azimuth::new(2.0 * PI * j as f64 / z as f64))
                .collect(),
            ball_drag: medium.map(|medium| BallDrag { medium, radius: rb }),
            cage_windage: medium,
            cage_radii: [ro, ri],
            quasi_static_balls: scene.solver.fidelity != Fidelity::Full,
            concentric_cage: scene.solver.fidelity == Fidelity::ConcentricCage,
        }
    }

    /// Inner-ring speed at time t, rad/s.
    #[inline]
    pub fn shaft_speed(&self, t: f64) -> f64 {
        let (w0, w1, tr) = self.speed;
        if t < tr {
            w0 + (w1 - w0) * t / tr
        } else {
            w1
        }
    }

    /// Inner-ring rotation angle at time t (integral of the speed), rad.
    #[inline]
    pub fn shaft_angle(&self, t: f64) -> f64 {
        let (w0, w1, tr) = self.speed;
        if t < tr {
            w0 * t + 0.5 * (w1 - w0) * t * t / tr
        } else {
            w0 * tr + 0.5 * (w1 - w0) * tr + w1 * (t - tr)
        }
    }

    /// True when the inner ring guides the cage (an inner-land cage); an outer-land or
    /// ball-guided cage is referred to the outer ring.
    #[inline]
    pub fn cage_guided_by_inner(&self) -> bool {
        self.land.is_some() && !self.land_on_outer
    }

    /// Cage centre relative to its guiding ring in Y and Z (m), and that offset over the
    /// land's radial clearance (-). The guiding ring is the outer ring unless the cage is
    /// inner-land guided; a ball-guided cage is measured from the outer ring, unscaled.
    #[inline]
    pub fn cage_offset(&self, y: &[f64]) -> ([f64; 2], f64) {
        let (c, o, i) = (self.layout.cage, self.layout.outer, self.layout.inner);
        let (gy, gz) = if self.cage_guided_by_inner() {
            (y[i + inner::Y], y[i + inner::Z])
        } else {
            (y[o + outer::Y], y[o + outer::Z])
        };
        let d = [y[c + cage::Y] - gy, y[c + cage::Z] - gz];
        let scale = self.land.as_ref().map_or(1.0, |l| l.clearance);
        (d, d[0].hypot(d[1]) / scale)
    }

    /// Pure-rolling (epicyclic) cage speed for shaft speed `w` and contact angle `alpha`, rad/s.
    pub fn epicyclic_cage_speed(&self, w: f64, alpha: f64) -> f64 {
        0.5 * w * (1.0 - self.ball_diameter * alpha.cos() / self.pitch_diameter)
    }
}
