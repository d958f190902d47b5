//! The scene types: the one serde-typed input of a simulation.
//!
//! Every quantity is SI (m, kg, s, N, Pa, rad) unless the field name says otherwise
//! (`*_rpm` is rev/min because that is how spindle speeds are specified).

use serde::{Deserialize, Serialize};

/// A complete simulation input.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Free-text label.
    #[serde(default)]
    pub name: String,
    pub bearing: Bearing,
    pub materials: Materials,
    pub lubricant: Lubricant,
    pub operating: Operating,
    /// Localized raceway defects; empty for a healthy bearing.
    #[serde(default)]
    pub faults: Vec<Fault>,
    #[serde(default)]
    pub solver: Solver,
    #[serde(default)]
    pub outputs: Outputs,
}

/// Bearing geometry (Table 1 plus what the dynamic model needs beyond it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Bearing {
    /// Bore (inner ring inner) diameter, m.
    pub bore_diameter: f64,
    /// Outer ring outside diameter, m.
    pub outer_diameter: f64,
    /// Bearing width, m.
    pub width: f64,
    /// Inner raceway groove-bottom diameter, m.
    pub inner_groove_diameter: f64,
    /// Outer raceway groove-bottom diameter, m.
    pub outer_groove_diameter: f64,
    /// Ball diameter D, m.
    pub ball_diameter: f64,
    /// Number of balls Z, -.
    pub ball_count: usize,
    /// Nominal (free) contact angle, rad.
    pub contact_angle: f64,
    /// Inner groove curvature factor f_i = r_groove / D, - (> 0.5).
    pub inner_groove_curvature: f64,
    /// Outer groove curvature factor f_o = r_groove / D, - (> 0.5).
    pub outer_groove_curvature: f64,
    /// Inner ring land (shoulder) diameter, m.
    pub inner_land_diameter: f64,
    /// Outer ring land (shoulder) diameter, m.
    pub outer_land_diameter: f64,
    pub cage: Cage,
}

/// Cage geometry and guidance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Cage {
    /// Cage bore diameter, m.
    pub inner_diameter: f64,
    /// Cage outside diameter, m.
    pub outer_diameter: f64,
    /// Cylindrical pocket diameter, m.
    pub pocket_diameter: f64,
    /// Cage axial width L_c, m.
    pub width: f64,
    /// Which surface pilots the cage.
    pub guidance: CageGuidance,
    /// Diametral clearance between the cage and its guiding land, m (ignored for ball guidance).
    pub land_clearance: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum CageGuidance {
    OuterLand,
    InnerLand,
    Ball,
}

/// Elastic and inertial properties of one part.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus, Pa.
    pub youngs_modulus: f64,
    /// Poisson's ratio, -.
    pub poisson_ratio: f64,
    /// Density, kg/m^3.
    pub density: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Materials {
    pub rings: Material,
    pub balls: Material,
    pub cage: Material,
}

/// Lubricant and friction data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Lubricant {
    /// Dynamic viscosity at operating temperature, Pa s.
    pub dynamic_viscosity: f64,
    /// EHL traction curve mu(s) with s the slip speed, m/s.
    pub traction: Traction,
    /// Critical film below which the ball-pocket contact becomes Hertzian, m.
    pub critical_film_ball_cage: f64,
    /// Critical film below which the cage-land contact becomes Hertzian, m.
    pub critical_film_cage_land: f64,
    /// Coulomb friction coefficient in Hertzian ball-pocket and cage-land contacts, -.
    pub cage_friction: f64,
    /// Damping ratio of the ball-race normal contact (EHL film damping), -. Default 0.05.
    #[serde(default = "default_contact_damping_ratio")]
    pub contact_damping_ratio: f64,
    /// Density of the lubricant (the grease's base oil), kg/m^3. Default 870, an assumption
    /// within base oils' 840 (PAO) to 900 (naphthenic) (Höglund 1999 as given by Arana et al.
    /// 2019, Table 2); with it Table 1's 5.1 mm^2/s is the preset's 4.44 mPa s.
    #[serde(default = "default_lubricant_density")]
    pub density: f64,
    /// Pressure-viscosity coefficient alpha (Barus), 1/Pa. Default 1.5e-8: mineral spindle
    /// oils give 1.3-2.0e-8 at 60-100 deg C (Stachowiak & Batchelor, Table 2.3).
    #[serde(default = "default_pressure_viscosity")]
    pub pressure_viscosity: f64,
    /// Drag of the cavity medium on the balls' orbital motion and spin and on the cage.
    /// Default none (the seed paper's model).
    #[serde(default)]
    pub cavity_drag: CavityDrag,
    /// EHL hydrodynamic rolling resistance at the ball-race contacts. Default none (the
    /// seed paper's model).
    #[serde(default)]
    pub rolling_resistance: RollingResistanceModel,
}

/// The medium the balls and cage move through (docs/reference/model.md, "Lubricant drag").
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)]
pub enum CavityDrag {
    /// No drag (the seed paper's model).
    None,
    /// A homogeneous oil-air mixture (docs/reference/model.md, "Lubricant drag").
    OilAir {
        /// Oil volume fraction of the mixture, - (0..1). Default 0.01: a channelled grease
        /// leaves the ball track mostly to air carrying bled oil; SKF fills high-speed
        /// spindle bearings to under 30 % of the free space, ADORE's jet-lubricated sample
        /// deck uses 0.05.
        #[serde(default = "default_oil_fraction")]
        oil_fraction: f64,
    },
}

/// Off by default: no read source measures its size in a grease-lubricated spindle bearing,
/// and the paper's model has none (docs/reference/model.md, "EHL rolling resistance").
impl Default for CavityDrag {
    fn default() -> Self {
        CavityDrag::None
    }
}

/// EHL rolling resistance (docs/reference/model.md, "EHL rolling resistance").
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)]
pub enum RollingResistanceModel {
    /// None (the seed paper's model).
    None,
    /// Biboulet & Houpert's fit (2010, Part 2, eq. 32) for fully flooded, isothermal
    /// elliptical contacts.
    Houpert {
        /// Multiplier for starvation and inlet shear heating, - (0..1]. Default 1: fully
        /// flooded and isothermal, as the seed paper assumes.
        #[serde(default = "default_film_factor")]
        factor: f64,
    },
}

/// Off by default, for the reason given at [`CavityDrag`]'s default.
impl Default for RollingResistanceModel {
    fn default() -> Self {
        RollingResistanceModel::None
    }
}

/// The EHL traction law of the ball-race contacts: a curve of the slip speed s (m/s), the
/// same at every contact (the paper's eq. 15), or a law from the lubricant's rheology.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(tag = "model", rename_all = "snake_case", deny_unknown_fields)]
pub enum Traction {
    /// The paper's eq. 15, `mu(s) = (a + b s) exp(-c s) + d`; a, d in -, b in s/m, c in
    /// s/m. The same at every load and speed. A coefficient left out (or set to null in an
    /// override) takes the ADORE sample deck's value (a -0.036, b 0.1018, c 1.547, d 0.036),
    /// so `{"model": "abcd"}` is the paper's curve.
    Abcd {
        #[serde(default = "paper_curve_a")]
        a: f64,
        #[serde(default = "paper_curve_b")]
        b: f64,
        #[serde(default = "paper_curve_c")]
        c: f64,
        #[serde(default = "paper_curve_d")]
        d: f64,
    },
    /// ADORE-style description: mu at zero slip, peak value, value at large slip (all -)
    /// and the slip speed of the peak u_m (m/s). Converted to `Abcd`.
    Adore {
        mu0: f64,
        mu_max: f64,
        mu_inf: f64,
        u_m: f64,
    },
    /// Traction from the lubricant's rheology, strip by strip (docs/reference/model.md,
    /// "Traction laws"): each strip of eq. 13 at its own mean Hertz pressure, its viscosity
    /// from Roelands (`dynamic_viscosity`, `pressure_viscosity`), shear thinning above the
    /// Eyring stress `2 Lambda / alpha(p)` and at most `limiting_coefficient` times its
    /// pressure (Arana, Larrañaga & Ulacia 2019, eq. 13), on the Hamrock-Dowson film.
    Rheology {
        /// Limiting shear stress over pressure Lambda, -. Default 0.047, a paraffinic
        /// mineral base oil (Höglund 1999 as given by Arana et al. 2019, Table 2); range
        /// 0.035 (PAO) to 0.053 (naphthenic).
        #[serde(default = "default_rheology_limiting")]
        limiting_coefficient: f64,
        /// Roelands' pressure-viscosity index Z, -. Default: from the lubricant's viscosity
        /// and pressure-viscosity coefficient, `alpha = Z (ln eta0 + 9.67) / 1.96e8 Pa`
        /// (0.69 for the preset's oil; spindle oils 0.68-0.81, Stachowiak & Batchelor
        /// Table 2.3).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        roelands_z: Option<f64>,
    },
    /// The project's earlier film law, kept to reproduce its studies: one slope per
    /// contact from the mean Hertz pressure with Barus viscosity, an elastic film term in
    /// series, an Eyring `asinh` and a `tanh` blend into the limiting coefficient. The
    /// elastic term and the `tanh` are the project's own closed form, and Barus at the mean
    /// pressure makes it far stiffer than `rheology` (docs/reference/model.md, "Traction
    /// laws").
    Film {
        /// Elastic shear modulus of the film in the contact, Pa. Default 1 GPa ("of the
        /// order 10^9 Pa", Arana et al. 2019).
        #[serde(default = "default_film_shear_modulus")]
        shear_modulus: f64,
        /// Eyring stress, Pa. Default 5 MPa (an assumption: no measured value for this oil
        /// was read).
        #[serde(default = "default_eyring_stress")]
        eyring_stress: f64,
        /// Limiting shear stress over pressure, -. Default 0.07.
        #[serde(default = "default_limiting_coefficient")]
        limiting_coefficient: f64,
    },
}

// The ADORE sample deck's eq. 15 coefficients: `abcd`'s defaults and Traction::PAPER_CURVE.
const fn paper_curve_a() -> f64 {
    -0.036
}

const fn paper_curve_b() -> f64 {
    0.1018
}

const fn paper_curve_c() -> f64 {
    1.547
}

const fn paper_curve_d() -> f64 {
    0.036
}

fn default_rheology_limiting() -> f64 {
    0.047
}

fn default_film_shear_modulus() -> f64 {
    1e9
}

fn default_eyring_stress() -> f64 {
    5e6
}

fn default_limiting_coefficient() -> f64 {
    0.07
}

/// Operating conditions.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Operating {
    pub speed: SpeedProfile,
    /// Radial load on the inner ring, N (>= 0).
    pub radial_load: f64,
    /// Azimuth of the radial load direction, rad (0 = +Z).
    #[serde(default)]
    pub radial_load_angle: f64,
    /// Axial load on the inner ring along +X, N (>= 0; an angular contact bearing needs some).
    pub axial_load: f64,
    /// Inner-ring tilt: held at zero by the shaft's bearing pair (default) or free.
    #[serde(default)]
    pub inner_ring_tilt: TiltMode,
    /// Mass moving with the inner ring besides the ring itself (its share of the shaft), kg.
    #[serde(default)]
    pub shaft_mass: f64,
    /// Moment applied to the inner ring about Y and Z, N m (only with free tilt).
    #[serde(default)]
    pub applied_moment: [f64; 2],
    pub pedestal: Pedestal,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum TiltMode {
    #[default]
    Locked,
    Free,
}

/// Inner-ring speed: linear ramp from `initial_rpm` to `steady_rpm` over `ramp_time`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct SpeedProfile {
    /// Speed at t = 0, rev/min.
    pub initial_rpm: f64,
    /// Speed after the ramp, rev/min.
    pub steady_rpm: f64,
    /// Ramp duration, s (0 = constant speed `steady_rpm`).
    #[serde(default)]
    pub ramp_time: f64,
}

/// 2-DOF spring-damper support of the outer ring (eq. 29).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Pedestal {
    /// Moving mass (outer ring plus participating housing), kg.
    pub mass: f64,
    /// Stiffness in Y, N/m.
    pub stiffness_y: f64,
    /// Stiffness in Z, N/m.
    pub stiffness_z: f64,
    /// Viscous damping in Y, N s/m.
    pub damping_y: f64,
    /// Viscous damping in Z, N s/m.
    pub damping_z: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum Ring {
    Inner,
    Outer,
}

/// A localized raceway defect (a pit or spall).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Fault {
    pub ring: Ring,
    /// Azimuth of the defect centre in the ring's own frame at t = 0, rad.
    pub angle: f64,
    /// Defect extent along the raceway (its diameter), m.
    pub width: f64,
    /// Defect depth, m.
    pub depth: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum Integrator {
    /// Embedded 4th-order Runge-Kutta with step-size control (Cash-Karp).
    Rk4Adaptive,
    /// Classical RK4 at `initial_step`.
    Rk4Fixed,
    /// Classical RK4 with step-size control from its first-same-as-last stage (an
    /// embedded 3rd-order estimate at no extra evaluation); the default of a scene that
    /// names none (the preset names `auto_etd`): the same accuracy as `rk4_adaptive` at
    /// 1e-6 for about 70 % of its evaluations (docs/lab/benchmarks.md).
    #[default]
    Rk4Fsal,
    /// `rk4_fsal`, switching to `rosenbrock_w` while a stiff mode (the cage whirling on its
    /// land film) holds the explicit step far below its usual stability limit, and back.
    Auto,
    /// Linearly implicit Rosenbrock-W method ROS34PW2 (order 3, L-stable) with step-size
    /// control and a block-diagonal finite-difference Jacobian: not held back by the
    /// stiff contact modes.
    RosenbrockW,
    /// The Rosenbrock-W method ROS34PRw with only each ball's velocity block in its
    /// Jacobian, and the cage's land film where it is too stiff for the method's explicit
    /// part (a whirling cage): implicit in the traction's slip relaxation (the stiffness of
    /// a rheology-based traction law, worst at low speed), explicit in the contact's elastic
    /// modes, with RK4's stability and about its damping on them (docs/reference/model.md,
    /// "Time integration").
    SlipImplicit,
    /// The preset's until 2026-11-30. `rk4_fsal` and `slip_implicit`, each in turn challenged by the other, priced in
    /// right-hand sides per simulated second as the run goes: `slip_implicit` takes the run
    /// where it costs at most 0.6 of `rk4_fsal` (where the balls' slip relaxation holds
    /// the explicit step, at low speed) and gives it back where it costs more than 0.9,
    /// the explicit method being the accurate one for the contact modes
    /// (docs/reference/model.md, "Time integration").
    AutoSlip,
    /// A fourth-order exponential Runge-Kutta method with stages a third of the step apart
    /// (with `L` zero, Kutta's 3/8 rule; the error estimate against its first-same-as-last
    /// companion), exact on each ball's contact oscillator (its axial and radial motion on
    /// its two Hertz contacts, with a mode's damping where it passes 1e5 1/s, linearised by
    /// differences every 80 steps), on the relaxation of its spin `w_t`, of its orbital
    /// speed and spin `w_x` together (one 2x2 block) and on the cage's radial velocities
    /// and spin: the contact modes rotated exactly, never damped numerically or unstable,
    /// the step held on them only to `omega h <= 1.35 pi` for accuracy
    /// (docs/reference/model.md, "Solver and integrators").
    EtdRk4,
    /// `etd_rk4` and `slip_implicit` under `auto_slip`'s measured-cost rule: `slip_implicit`
    /// where the balls' whole slip relaxation is stiff (low speed), `etd_rk4` elsewhere.
    AutoEtd,
}

/// How much of the model a run integrates (docs/reference/model.md, "Fidelity levels").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum Fidelity {
    /// Every body with its inertia (the paper's model).
    #[default]
    Full,
    /// Ball centres in quasi-static axial-radial equilibrium under their contact loads
    /// and centrifugal force at every evaluation (no ball-race contact vibration, the
    /// 30-58 kHz modes that hold the explicit step down); ball orbit and spin, the cage,
    /// the rings and the pedestal stay dynamic. For vibration signatures and fault
    /// frequencies below ~20 kHz.
    QuasiStaticBalls,
    /// `quasi_static_balls`, and the cage held concentric with its guiding ring and
    /// untilted: only its spin (and axial position) is integrated, so its whirl on the
    /// land film does not set the step. For fault frequencies and signatures when the
    /// cage's radial motion is not of interest.
    ConcentricCage,
}

impl Fidelity {
    /// True for the default, which a serialized scene leaves out.
    pub fn is_full(&self) -> bool {
        *self == Fidelity::Full
    }
}

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields, default)]
pub struct Solver {
    /// Simulated time, s.
    pub duration: f64,
    /// Which model is integrated: `full` (default) or a reduced level.
    #[serde(skip_serializing_if = "Fidelity::is_full")]
    pub fidelity: Fidelity,
    pub integrator: Integrator,
    /// First (adaptive) or only (fixed) step, s.
    pub initial_step: f64,
    /// Relative tolerance of the step controller, -.
    pub rtol: f64,
    /// Absolute tolerance scale, applied per state component in units of that component's
    /// natural scale (ball radius for lengths, ring surface speed for velocities), -.
    pub atol: f64,
    /// Largest step the controller may take, s.
    pub max_step: f64,
    /// Traction samples across the contact ellipse major axis (eq. 13, 2m strips), -.
    /// Absent (the default): the law's own ([`Traction::default_strips`]), 10 for the laws
    /// sampled at points and 4 Gauss nodes for the rheology law, whose samples are cell
    /// means ([`Scene::traction_strips`]; docs/reference/model.md, "Traction quadrature").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "openapi", schema(minimum = 1, maximum = 200))]
    pub traction_strips: Option<usize>,
    /// Where those samples sit and what load each carries (docs/reference/model.md, "Traction
    /// quadrature").
    pub traction_quadrature: TractionQuadrature,
    /// Uniform output sampling rate of the channels, Hz (default 102.4 kHz: above twice the
    /// ball-race contact modes, so interpolated samples do not alias them).
    pub sample_rate: f64,
    /// How the Hertz constants (load-deflection constant, contact ellipse) are computed.
    pub hertz: HertzModel,
}

/// How eq. 13's traction integral over the contact ellipse is sampled. Both rules weigh
/// the samples by the parabolic load `1 - x^2/a^2`; they differ in where the samples sit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum TractionQuadrature {
    /// Gauss nodes for the weight `1 - x^2` (default): on the Table-1 case 3 samples give
    /// the mean cage speed within 0.003 % of 20, 10 the band RMS below 20 kHz within
    /// 0.22 %.
    #[default]
    Gauss,
    /// Equal strips, as eq. 13 is printed: a Riemann sum, slow to converge (on the
    /// Table-1 case 10 strips are 0.016 % slow in mean cage speed and 11.5 % low in band
    /// RMS below 20 kHz against the converged integral).
    EqualStrips,
}

/// The Hertz point-contact solution used for the ball-race and ball-pocket contacts. Both
/// are computed once per run, so the choice costs nothing per step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "snake_case")]
pub enum HertzModel {
    /// Hamrock-Brewe curve fits (the paper's choice): K within 0.5-2.3 % of exact for this
    /// bearing's conformities.
    HamrockBrewe,
    /// Complete elliptic integrals (default; the ellipticity from Biboulet & Houpert 2010,
    /// Part 2, App. 2, eqs. 41-43), to ~1e-15: the ISO 16281 test bearing's static
    /// deflections within 0.03 % of the reference, where the fits miss by 0.5 %.
    #[default]
    Exact,
}

impl Default for Solver {
    fn default() -> Self {
        Solver {
            duration: 0.5,
            fidelity: Fidelity::Full,
            integrator: Integrator::Rk4Fsal,
            initial_step: 1e-4,
            rtol: 1e-5,
            atol: 1e-5,
            max_step: 1e-4,
            traction_strips: None,
            traction_quadrature: TractionQuadrature::Gauss,
            sample_rate: 102_400.0,
            hertz: HertzModel::Exact,
        }
    }
}

/// Which channels to record besides the outer-ring acceleration (always recorded).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields, default)]
pub struct Outputs {
    /// Cage angular speed, rad/s.
    pub cage_speed: bool,
    /// Inner-ring displacement y, z (and x), m.
    pub inner_ring_displacement: bool,
    /// Record the inner and outer contact loads (N) of this ball (0-based index).
    pub contact_loads_ball: Option<usize>,
    /// Record where this ball (0-based index) runs against its cage pocket: its azimuth
    /// (rad, 0 = +Z, the direction of a radial load at `radial_load_angle` 0), its orbital
    /// speed less the cage's (rad/s) and its centre's offset from the pocket's axis along
    /// the orbit (m, + toward increasing azimuth, ahead when the shaft turns positively;
    /// within the pocket's radial clearance, plus any contact penetration). Over many orbits
    /// they show where round the orbit the balls run ahead of the cage and where behind it,
    /// which sets the cage slip (docs/reference/model.md, "Cage motion in the summary").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ball_pocket: Option<usize>,
}

impl Traction {
    /// The paper's eq. 15 with the ADORE sample deck's coefficients (MIL-L-23699: mu0 0,
    /// mu_max 0.05 at 1 m/s, mu_inf 0.036; `mu(0) = 0` keeps traction continuous through
    /// zero slip): `{"model": "abcd"}`. The preset's traction until 2026-11-29, when the
    /// rheology law replaced it (issue 33; docs/reference/model.md, "Traction laws").
    pub const PAPER_CURVE: Traction = Traction::Abcd {
        a: paper_curve_a(),
        b: paper_curve_b(),
        c: paper_curve_c(),
        d: paper_curve_d(),
    };

    /// The rheology law with its defaults: the preset's traction since 2026-11-29.
    pub const RHEOLOGY: Traction = Traction::Rheology {
        limiting_coefficient: 0.047,
        roelands_z: None,
    };

    /// Traction samples a scene takes under this law and `quadrature` when it names none:
    /// 10 where the law is sampled at points (the paper's curve and the film law: Gauss 10
    /// within 0.22 % in band RMS of 20, 3 nodes 6.9 % off) and for equal strips, 4 Gauss
    /// nodes under the rheology law, whose samples are the law's means over their cells
    /// where it is steep (on the Table-1 compound case at 1e-7, 4 nodes within 0.1 % in
    /// band RMS and 6.2e-5 in cage speed of 20, 10 within 0.2 % and 6.2e-5, one run's own
    /// scatter under this law; docs/lab/benchmarks.md, "Four Gauss nodes under the
    /// rheology law"). Equal strips converge more slowly (the balls' traction moments 10 %
    /// off at 4 against 1.5 % for Gauss nodes) and were not measured at 4 under this law.
    pub fn default_strips(&self, quadrature: TractionQuadrature) -> usize {
        match (self, quadrature) {
            (Traction::Rheology { .. }, TractionQuadrature::Gauss) => 4,
            _ => 10,
        }
    }

    /// Coefficients `(a, b, c, d)` of eq. 15; `None` for a law that is not such a curve.
    pub fn abcd(&self) -> Option<(f64, f64, f64, f64)> {
        match *self {
            Traction::Abcd { a, b, c, d } => Some((a, b, c, d)),
            Traction::Adore {
                mu0,
                mu_max,
                mu_inf,
                u_m,
            } => Some(adore_to_abcd(mu0, mu_max, mu_inf, u_m)),
            Traction::Film { .. } | Traction::Rheology { .. } => None,
        }
    }
}

/// Convert ADORE-style traction parameters to eq. 15 coefficients.
///
/// `a = mu0 - mu_inf`, `d = mu_inf`; the peak at `u_m` fixes `c = b / (a + b u_m)` and
/// `(a + b u_m) exp(-b u_m / (a + b u_m)) = mu_max - mu_inf`, solved for `b` by bisection
/// (the left side grows monotonically with b on the admissible branch).
pub fn adore_to_abcd(mu0: f64, mu_max: f64, mu_inf: f64, u_m: f64) -> (f64, f64, f64, f64) {
    let a = mu0 - mu_inf;
    let d = mu_inf;
    let target = mu_max - mu_inf;
    let g = |b: f64| {
        let p = a + b * u_m;
        p * (-b * u_m / p).exp() - target
    };
    // b must make a + b u_m > 0 and the peak lie at u_m > 0, i.e. b > 0 and b > -a / u_m.
    let mut lo = (-a / u_m).max(0.0) + 1e-12;
    let mut hi = lo + 1.0;
    while g(hi) < 0.0 && hi < 1e9 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let b = 0.5 * (lo + hi);
    let c = b / (a + b * u_m);
    (a, b, c, d)
}

fn default_contact_damping_ratio() -> f64 {
    0.05
}

fn default_lubricant_density() -> f64 {
    870.0
}

fn default_pressure_viscosity() -> f64 {
    1.5e-8
}

fn default_oil_fraction() -> f64 {
    0.01
}

fn default_film_factor() -> f64 {
    1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adore_sample_deck_converts_to_published_abcd() {
        // MIL-L-23699 deck: mu0 0, mu_max 0.05, mu_inf 0.036, u_m 1 m/s -> published
        // A -0.036, B 0.1018, C 1.547, D 0.036 (4 significant figures, hence 1e-3 relative).
        let (a, b, c, d) = adore_to_abcd(0.0, 0.05, 0.036, 1.0);
        assert!((a + 0.036).abs() < 1e-12);
        assert!((b - 0.1018).abs() / 0.1018 < 1e-3, "b = {b}");
        assert!((c - 1.547).abs() / 1.547 < 1e-3, "c = {c}");
        assert!((d - 0.036).abs() < 1e-12);
        // the converted curve has its maximum mu_max at u_m
        let mu = |s: f64| (a + b * s) * (-c * s).exp() + d;
        assert!((mu(1.0) - 0.05).abs() < 1e-9);
        assert!(mu(0.9) < mu(1.0) && mu(1.1) < mu(1.0));
    }

    #[test]
    fn julia_default_converts() {
        // 0.08 / 0.10 / 0.04 / 0.5 -> A 0.04, B 0.1506, C 1.306, D 0.04 (published, 4 s.f.).
        let (a, b, c, d) = adore_to_abcd(0.08, 0.10, 0.04, 0.5);
        assert!((a - 0.04).abs() < 1e-12 && (d - 0.04).abs() < 1e-12);
        assert!((b - 0.1506).abs() / 0.1506 < 1e-3, "b = {b}");
        assert!((c - 1.306).abs() / 1.306 < 1e-3, "c = {c}");
    }
}
