//! The stability stress suite (issue 10): extreme scenes of the H7005C across speed, load,
//! defects, lubricant, starts, run length and output rate, and the invariants a run of each
//! must keep. Each scene either runs with [`check`] and [`check_cost`] finding nothing, or
//! is refused before it runs ([`prepare`]) with an error naming a field and its limit.
//!
//! `crates/bearing-core/tests/engine_stress.rs` runs every scene for a few milliseconds; `bearing-sim bench
//! stress` runs them longer and prints a table.

use crate::model::Model;
use crate::scene::{
    fault_case_scene, preset_scene, CavityDrag, Fault, FaultCase, Fidelity, Integrator, Outputs,
    Ring, RollingResistanceModel, Scene, Traction, ValidScene, ValidationErrors,
};
use crate::simulation::{check_start, simulate, RunControl, SimError, SimResult};
use std::f64::consts::PI;
use std::fmt;

/// Name of the reference scene whose solver cost the others are compared with.
pub const REFERENCE: &str = "table1_steady";

/// What a stress scene is expected to do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Expectation {
    /// Runs with every invariant of [`check`] kept and a solver cost (RHS evaluations per
    /// simulated second) at most `cost_factor` times the reference scene's.
    Runs { cost_factor: f64 },
    /// Refused by [`prepare`] with an error on this field path.
    Refused { field: &'static str },
}

/// One scene of the catalogue.
#[derive(Debug, Clone, Copy)]
pub struct StressScene {
    /// Short identifier, e.g. `near_zero_speed`.
    pub name: &'static str,
    /// What it stresses.
    pub stresses: &'static str,
    /// The scene for a run of the given duration (s).
    pub build: fn(f64) -> Scene,
    pub expect: Expectation,
    /// Duration of the test run, s (short: the test suite runs every scene).
    pub test_duration: f64,
    /// Duration of the bench run when it is not the bench's default (the long run), s.
    pub bench_duration: Option<f64>,
}

impl StressScene {
    pub fn scene(&self, duration: f64) -> Scene {
        (self.build)(duration)
    }
}

/// Cost factors against the reference, the Table-1 bearing at its steady 10000 rpm under the
/// preset's physics. Scenes that only move the operating point keep the step limit of the
/// ball-race contact modes: measured 0.43-2.73x at 20 ms and 0.1 s (2026-11-29; 0.5-2.2x
/// under the paper's model; 0.58-3.37x at 0.1 s on 2026-11-30 under `auto_etd`, against a
/// reference 0.81 times as costly as `auto_slip`'s; 0.57-3.54x on the twenty-fourth
/// session's build, 0.55-3.39x on the twenty-fifth's, 0.58-2.74x on the twenty-sixth's;
/// 0.62-3.98x with `etd_rk4`'s stages a third of the step apart, 2026-12-01, against a
/// reference 0.82 times as costly: `ten_times_load` at 0.1 s is the 3.98, 18 % more
/// evaluations than under the stages before, its steps held by the error estimate below
/// the bound; docs/lab/benchmarks.md), so 4x leaves room for the start-up transient of
/// short runs and for defect edges.
const SAME_COST: f64 = 4.0;

/// With the cage whirling on its land film (eccentricity ~0.95 at 60000 rpm), `rk4_fsal`'s
/// step under the paper's model falls to ~1e-8 s: measured 10x at 20 ms and 180-215x at
/// 0.1 s as the whirl builds up (against the paper's model's own reference, 2026-11-24; 6.1x
/// and 174x against today's, 2026-11-29). The factor states the pathology;
/// `limit_speed_auto` is the remedy, and under the preset's physics the step does not
/// collapse there (`limit_speed`: `auto_slip` 0.89x; `auto_etd` 1.08x, 2026-11-30). The test suite's 20 ms run stays far below the
/// bound (6.1x): there the scene checks the invariants, the bench's 0.1 s run the cost
/// (215.41x on 2026-11-30 against `auto_etd`'s cheaper reference; 179.46x on the
/// twenty-fourth session's build, whose azimuths and contact logarithms moved at rounding
/// level; 182.84x on the twenty-fifth's, 182.70x on the twenty-sixth's).
const WHIRL_AT_LIMIT_SPEED: f64 = 250.0;

/// `auto` at the limit speed under the paper's model: measured 2.5-2.8x at 0.1 s (its
/// Jacobians count as evaluations; against that model's own reference, 2026-11-24).
const AUTO_AT_LIMIT_SPEED: f64 = 5.0;

/// The fast start's whirl under the paper's model (the eq. 15 curve with `rk4_fsal`, the
/// preset's until 2026-11-29; docs/lab/benchmarks.md, "Pathologies"): measured 9x at 20 ms,
/// 19x at 60 ms, 39x at 0.1 s against that model's reference, 7.8x at 20 ms and 34x at 0.1 s
/// against today's (2026-11-29). Under the preset's physics the implicit method takes the
/// land film into its Jacobian and the same start costs 1.2x at 20 ms (`fast_ramp`, under
/// `auto_slip`; 1.06x at 0.1 s under `auto_etd`, 2026-11-30).
const FAST_START_WHIRL: f64 = 60.0;

/// The fast start with `auto`: issue 10 asks for a fast start within 3x of the Table-1
/// case's time per simulated second; the reference here (constant speed, no fault) is
/// cheaper than that case (under the paper's model 5.3e5 against 8.5e5 evaluations per
/// simulated second, under the preset's 6.0e5 against 9.0e5), so 3x of it is the stricter
/// bound. Measured 3.3x at 20 ms (the switch waits for a streak of
/// small explicit steps), 2.0x at 60 ms, 1.85x at 0.1 s, under the paper's model and
/// against its reference (1.74x and 1.63x against today's, 2026-11-29); so the test runs it
/// for 60 ms. (Under the preset's physics `auto` measured 2.90x at 60 ms and 2.18x at 0.1 s,
/// where `auto_slip` needs 1.2x; on 2026-11-30 `fast_ramp_auto` 2.02x at 0.1 s against
/// `auto_etd`'s cheaper reference.)
const FAST_START_AUTO: f64 = 3.0;

/// At 1 Pa s the cage land and pocket films are stiff for an explicit method (their
/// damping grows with the viscosity): under the paper's model with `rk4_fsal` measured 47x
/// at 20 ms and 58x at 0.1 s; under the preset's law `auto_slip` takes them implicitly,
/// 3.42x at 10 ms and 3.24x at 0.1 s (2026-11-29; `auto_etd` 2.59x at 0.1 s against its
/// cheaper reference, 2026-11-30: 1.260e6 evaluations per simulated second, 1.919e6
/// before the cage's velocities and spin relaxed exactly). 8x would catch the explicit method's collapse coming back.
const VERY_VISCOUS: f64 = 8.0;

/// The catalogue, reference first.
pub fn catalogue() -> Vec<StressScene> {
    use Expectation::*;
    let runs = |cost_factor| Runs { cost_factor };
    let s = |name, stresses, build: fn(f64) -> Scene, expect, test_duration, bench_duration| {
        StressScene {
            name,
            stresses,
            build,
            expect,
            test_duration,
            bench_duration,
        }
    };
    vec![
        s(
            REFERENCE,
            "reference: Table 1 at a constant 10000 rpm",
            table1_steady,
            runs(1.0 + 1e-9),
            0.02,
            None,
        ),
        // Speed.
        s(
            "near_zero_speed",
            "speed: 1 rpm, almost no rolling, traction near zero slip",
            |t| constant_speed(t, 1.0),
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "limit_speed",
            "speed: 60000 rpm (dm n 2.2e6 mm/min), taken as the limit speed: the paper gives none",
            |t| constant_speed(t, 60_000.0),
            // measured 0.89x at 20 ms and 0.1 s (2026-11-29); under the paper's model the
            // cage whirls on its land (`limit_speed_paper_curve`)
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "limit_speed_paper_curve",
            "speed: 60000 rpm under the paper's model: the cage whirls on its land and holds \
             `rk4_fsal`'s step down",
            |t| paper_model(constant_speed(t, 60_000.0)),
            runs(WHIRL_AT_LIMIT_SPEED),
            0.02,
            None,
        ),
        s(
            "limit_speed_auto",
            "speed: 60000 rpm under the paper's model with the `auto` integrator, which steps \
             over the land whirl",
            |t| {
                let mut s = paper_model(constant_speed(t, 60_000.0));
                s.solver.integrator = Integrator::Auto;
                s
            },
            runs(AUTO_AT_LIMIT_SPEED),
            0.02,
            None,
        ),
        s(
            "above_speed_limit",
            "speed: 150000 rpm, beyond what the model is validated for",
            |t| constant_speed(t, 150_000.0),
            Refused {
                field: "operating.speed.steady_rpm",
            },
            0.02,
            None,
        ),
        // Load.
        s(
            "near_zero_load",
            "load: 1 N axial, no radial: balls held by centrifugal force more than by load",
            |t| loads(t, 0.0, 1.0),
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "zero_load",
            "load: none at all",
            |t| loads(t, 0.0, 0.0),
            Refused {
                field: "operating.axial_load",
            },
            0.02,
            None,
        ),
        s(
            "pure_axial",
            "load: 100 N axial, no radial: every ball equally loaded",
            |t| loads(t, 0.0, 100.0),
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "pure_radial",
            "load: 300 N radial, no axial: no equilibrium with the ring's tilt locked",
            |t| loads(t, 300.0, 0.0),
            Refused {
                field: "operating.axial_load",
            },
            0.02,
            None,
        ),
        s(
            "ten_times_load",
            "load: ten times Table 1 (3000 N radial, 1000 N axial)",
            |t| loads(t, 3000.0, 1000.0),
            runs(SAME_COST),
            0.02,
            None,
        ),
        // Defects.
        s(
            "micro_defect",
            "defect: inner pit 2 um wide and 1 um deep, far inside the contact ellipse",
            |t| {
                faults(
                    t,
                    vec![Fault {
                        ring: Ring::Inner,
                        angle: 0.0,
                        width: 2e-6,
                        depth: 1e-6,
                    }],
                )
            },
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "wide_defect",
            "defect: outer spall 1.5 mm long, several contact ellipses wide",
            |t| {
                faults(
                    t,
                    vec![Fault {
                        ring: Ring::Outer,
                        angle: 0.0,
                        width: 1.5e-3,
                        depth: 0.1e-3,
                    }],
                )
            },
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "defect_wider_than_ball_spacing",
            "defect: 4.5 mm long, more than half the 8.2 mm ball spacing on the outer race",
            |t| {
                faults(
                    t,
                    vec![Fault {
                        ring: Ring::Outer,
                        angle: 0.0,
                        width: 4.5e-3,
                        depth: 0.1e-3,
                    }],
                )
            },
            Refused {
                field: "faults[0].width",
            },
            0.02,
            None,
        ),
        s(
            "many_defects",
            "defects: 16 (the limit), 8 on each race, Table-1 size",
            |t| faults(t, many_faults(16)),
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "too_many_defects",
            "defects: 17",
            |t| faults(t, many_faults(17)),
            Refused { field: "faults" },
            0.02,
            None,
        ),
        // Lubricant.
        s(
            "near_dry",
            "lubricant: 0.01 mPa s with the film traction law, rolling resistance and drag",
            |t| lubricant(t, 1e-5),
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "paper_curve",
            "lubricant: the paper's model (eq. 15 curve, no rolling resistance, `rk4_fsal`), \
             Table 1's loads",
            |t| paper_model(loads(t, 300.0, 100.0)),
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "ten_times_load_paper_curve",
            "lubricant and load: the paper's model at ten times Table 1's load",
            |t| paper_model(loads(t, 3000.0, 1000.0)),
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "very_viscous",
            "lubricant: 1 Pa s (ISO VG 1000 at 40 C) with rolling resistance and cavity drag",
            |t| viscous(t, 1.0),
            runs(VERY_VISCOUS),
            0.01,
            None,
        ),
        // Starts.
        s(
            "from_rest",
            "start: 0 -> 10000 rpm in 0.1 s",
            |t| ramp(t, 0.0, 10_000.0, 0.1),
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "fast_ramp",
            "start: 1000 -> 10000 rpm in 10 ms (under the paper's model the cage then whirls on \
             its land: `fast_ramp_paper_curve`)",
            |t| ramp(t, 1_000.0, 10_000.0, 0.01),
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "fast_ramp_auto",
            "start: the fast ramp under the paper's model with the `auto` integrator, which \
             steps over the whirl",
            |t| {
                let mut s = paper_model(ramp(t, 1_000.0, 10_000.0, 0.01));
                s.solver.integrator = Integrator::Auto;
                s
            },
            runs(FAST_START_AUTO),
            0.06,
            None,
        ),
        s(
            "fast_ramp_paper_curve",
            "start: the fast ramp under the paper's model: the cage whirls on its land and \
             holds `rk4_fsal`'s step down",
            |t| paper_model(ramp(t, 1_000.0, 10_000.0, 0.01)),
            runs(FAST_START_WHIRL),
            0.02,
            None,
        ),
        // Run length and output rate.
        s(
            "long_run",
            "run length: the Table-1 scene (compound fault) for 5 s",
            |t| {
                let mut s = fault_case_scene("h7005c", FaultCase::Compound).expect("preset");
                s.solver.duration = t;
                all_outputs(s)
            },
            runs(SAME_COST),
            0.02,
            Some(5.0),
        ),
        s(
            "too_long_run",
            "run length: 20 s",
            |_| table1_steady(20.0),
            Refused {
                field: "solver.duration",
            },
            0.02,
            None,
        ),
        s(
            "fine_output",
            "output: 1 MHz sampling (the limit), every channel recorded",
            |t| {
                let mut s = table1_steady(t);
                s.solver.sample_rate = 1.0e6;
                s
            },
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "too_fine_output",
            "output: 2 MHz sampling",
            |t| {
                let mut s = table1_steady(t);
                s.solver.sample_rate = 2.0e6;
                s
            },
            Refused {
                field: "solver.sample_rate",
            },
            0.02,
            None,
        ),
        // Fidelity levels: the same invariants with the ball centres (and the cage) held
        // by algebraic balances instead of integrated.
        s(
            "quasi_static_balls",
            "fidelity: quasi_static_balls, Table-1 compound fault at 10000 rpm",
            |t| reduced(t, Fidelity::QuasiStaticBalls),
            runs(SAME_COST),
            0.02,
            None,
        ),
        s(
            "concentric_cage",
            "fidelity: concentric_cage, Table-1 compound fault at 10000 rpm",
            |t| reduced(t, Fidelity::ConcentricCage),
            runs(SAME_COST),
            0.02,
            None,
        ),
        // Until 2026-11-24 refused: with the whole block Jacobian its step underflowed
        // within 3 ms; with the land film's Jacobian alone it runs (dynamics::system).
        s(
            "reduced_fidelity_implicit",
            "fidelity: quasi_static_balls with rosenbrock_w (the land film's Jacobian)",
            |t| {
                let mut s = reduced(t, Fidelity::QuasiStaticBalls);
                s.solver.integrator = Integrator::RosenbrockW;
                s
            },
            runs(SAME_COST),
            0.02,
            None,
        ),
    ]
}

/// The Table-1 compound fault at a constant 10000 rpm at a reduced fidelity level.
fn reduced(duration: f64, level: Fidelity) -> Scene {
    let mut s = fault_case_scene("h7005c", FaultCase::Compound).expect("preset");
    s.operating.speed.initial_rpm = 10_000.0;
    s.operating.speed.ramp_time = 0.0;
    s.solver.duration = duration;
    s.solver.fidelity = level;
    all_outputs(s)
}

/// Record every optional channel, so the no-NaN check covers them all.
fn all_outputs(mut s: Scene) -> Scene {
    s.outputs = Outputs {
        cage_speed: true,
        inner_ring_displacement: true,
        contact_loads_ball: Some(0),
        ball_pocket: Some(0),
    };
    s
}

/// The Table-1 scene at a constant `rpm`.
fn constant_speed(duration: f64, rpm: f64) -> Scene {
    let mut s = preset_scene("h7005c").expect("preset");
    s.operating.speed.initial_rpm = rpm;
    s.operating.speed.steady_rpm = rpm;
    s.operating.speed.ramp_time = 0.0;
    s.solver.duration = duration;
    s.name = format!("stress: {rpm} rpm");
    all_outputs(s)
}

fn table1_steady(duration: f64) -> Scene {
    constant_speed(duration, 10_000.0)
}

fn loads(duration: f64, radial: f64, axial: f64) -> Scene {
    let mut s = table1_steady(duration);
    s.operating.radial_load = radial;
    s.operating.axial_load = axial;
    s
}

fn faults(duration: f64, faults: Vec<Fault>) -> Scene {
    let mut s = table1_steady(duration);
    s.faults = faults;
    s
}

/// `n` Table-1 defects (0.2 mm wide, 0.1 mm deep), alternately on the inner and outer race,
/// spread evenly round the bearing.
fn many_faults(n: usize) -> Vec<Fault> {
    (0..n)
        .map(|k| Fault {
            ring: if k % 2 == 0 { Ring::Inner } else { Ring::Outer },
            angle: 2.0 * PI * k as f64 / n as f64,
            width: 0.2e-3,
            depth: 0.1e-3,
        })
        .collect()
}

/// Every lubricant-dependent term on: the film traction law (its low-slip slope scales with
/// the viscosity), Houpert rolling resistance and oil-air cavity drag.
fn lubricant(duration: f64, viscosity: f64) -> Scene {
    let mut s = table1_steady(duration);
    s.lubricant.dynamic_viscosity = viscosity;
    s.lubricant.traction = Traction::Film {
        shear_modulus: 1e9,
        eyring_stress: 5e6,
        limiting_coefficient: 0.07,
    };
    s.lubricant.rolling_resistance = RollingResistanceModel::Houpert { factor: 1.0 };
    s.lubricant.cavity_drag = CavityDrag::OilAir { oil_fraction: 0.01 };
    s
}

/// `s` under the seed paper's model, the preset's until 2026-11-29: the eq. 15 curve, no
/// rolling resistance, the explicit `rk4_fsal`.
fn paper_model(mut s: Scene) -> Scene {
    s.lubricant.traction = Traction::PAPER_CURVE;
    s.lubricant.rolling_resistance = RollingResistanceModel::None;
    s.solver.integrator = Integrator::Rk4Fsal;
    s
}

/// Viscosity `viscosity` with the rolling resistance and cavity drag it drives, under the
/// preset's traction law.
fn viscous(duration: f64, viscosity: f64) -> Scene {
    let mut s = table1_steady(duration);
    s.lubricant.dynamic_viscosity = viscosity;
    s.lubricant.rolling_resistance = RollingResistanceModel::Houpert { factor: 1.0 };
    s.lubricant.cavity_drag = CavityDrag::OilAir { oil_fraction: 0.01 };
    s
}

fn ramp(duration: f64, from: f64, to: f64, ramp_time: f64) -> Scene {
    let mut s = table1_steady(duration);
    s.operating.speed.initial_rpm = from;
    s.operating.speed.steady_rpm = to;
    s.operating.speed.ramp_time = ramp_time;
    s
}

/// Validate a scene and check that its run can start (the quasi-static equilibrium at the
/// initial speed exists): the up-front refusal, with the fields to change.
pub fn prepare(scene: &Scene) -> Result<ValidScene, ValidationErrors> {
    let valid = scene.validated()?;
    check_start(&valid)?;
    Ok(valid)
}

/// Axis of the inner-ring reaction (the scene's frame: X axial, Y and Z radial).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    X,
    Y,
    Z,
}

/// Which race a contact angle belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Race {
    Inner,
    Outer,
}

/// A broken invariant.
#[derive(Debug, Clone, PartialEq)]
pub enum Violation {
    /// A summary field or channel sample is NaN or infinite (`field` names it, e.g.
    /// `mean_cage_speed`, `balls[3].inner_load` or `channels.cage_speed[120]`).
    NonFinite { field: String },
    /// The mean force of the balls on the inner ring does not balance the applied load.
    Reaction {
        axis: Axis,
        /// Mean reaction, N.
        reaction: f64,
        /// Minus the applied force, N.
        expected: f64,
        /// Allowed difference, N.
        tolerance: f64,
    },
    /// The mean cage speed is not between zero and the mean shaft speed (rad/s).
    CageSpeed { cage: f64, shaft: f64 },
    /// A mean contact angle outside `[min, max]` (rad); `field` names the summary entry.
    ContactAngle {
        field: String,
        race: Race,
        angle: f64,
        min: f64,
        max: f64,
    },
    /// More RHS evaluations per simulated second than `factor` times the reference's.
    SolverCost {
        rhs_per_second: f64,
        reference: f64,
        factor: f64,
    },
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Violation::NonFinite { field } => write!(f, "{field} is not finite"),
            Violation::Reaction {
                axis,
                reaction,
                expected,
                tolerance,
            } => write!(
                f,
                "mean inner-ring reaction {axis:?} {reaction:.3} N, expected {expected:.3} +- {tolerance:.3} N"
            ),
            Violation::CageSpeed { cage, shaft } => write!(
                f,
                "mean cage speed {cage:.4} rad/s not in [0, shaft speed {shaft:.4} rad/s]"
            ),
            Violation::ContactAngle {
                field,
                race,
                angle,
                min,
                max,
            } => write!(
                f,
                "{field} ({race:?}) {:.2} deg not in [{:.2}, {:.2}] deg",
                angle.to_degrees(),
                min.to_degrees(),
                max.to_degrees()
            ),
            Violation::SolverCost {
                rhs_per_second,
                reference,
                factor,
            } => write!(
                f,
                "{rhs_per_second:.3e} RHS per simulated second, {:.2}x the reference's {reference:.3e} (limit {factor}x)",
                rhs_per_second / reference
            ),
        }
    }
}

/// The reaction balance is held to 1 % of the applied load (the figure; the
/// steady-run fidelity test in `crates/bearing-core/tests/engine_dynamics.rs` uses the same), but never to less
/// than this, N: the window average of the reaction also carries the inner ring's momentum
/// change over the window, `m dv / T`, whatever the load. Measured at 1 N axial (15 ms
/// window): the reaction is 0.0108 N short, and `m dv / T` from the displacement channel
/// (0.55 kg ring and shaft, dv = 2.9e-4 m/s) is 0.0104 N of it. [`check`] now adds that term
/// where the run records the displacement, and the floor covers its estimate's error. Under
/// the rheology law the same scene's balls skid (the cage at 0.076 of the shaft speed, not
/// 0.42) and the ring moves 33 um axially: the reaction is 0.555 N beyond the load and
/// `m dv / T` is 0.562 N (2026-11-28).
pub const REACTION_FLOOR: f64 = 0.02;

/// The inner ring's (and shaft's) momentum change over the steady window divided by its
/// length, `m (v_end - v_start) / T` per axis (X, Y, Z), N; `None` where the run does not
/// record the inner ring's displacement over the window.
///
/// The velocities are second-order differences of the displacement samples at the window's
/// ends (central at the start, backward at the end, where the run stops): they must be the
/// ring's velocities at those instants, since the reaction is averaged over exactly that
/// window. Under 1 N the ring rings axially at a low frequency with micrometres of amplitude,
/// and velocities averaged over 0.5 ms at each end came 0.23 N from the balance. The
/// differences' own error is the contact modes' ripple (~40 kHz, nanometres, a few 1e-4
/// m/s): below 0.01 N of `m dv / T` over a 15 ms window, inside [`REACTION_FLOOR`]; measured
/// 0.007 N on the skidding 1 N scene.
fn inner_ring_momentum_rate(scene: &Scene, result: &SimResult) -> Option<[f64; 3]> {
    let mass = Model::new(&scene.validated().ok()?).inner_mass;
    let ch = &result.channels;
    let [w0, w1] = result.summary.steady_window;
    let index = |t: f64| ((t - ch.start_time) * ch.sample_rate).round();
    let (i0, i1) = (index(w0), index(w1));
    if i0 < 1.0 || i1 < i0 + 2.0 {
        return None;
    }
    let (i0, i1) = (i0 as usize, i1 as usize);
    let fs = ch.sample_rate;
    let mut rate = [0.0; 3];
    for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
        let name = format!("inner_ring_disp_{axis}");
        let x = &ch.channels.iter().find(|c| c.name == name)?.data;
        // the last sample, where the window's end falls after it within a sample interval
        // (the recorder keeps the samples up to the run's end)
        let i1 = i1.min(x.len().saturating_sub(1));
        if i1 < i0 + 2 || i0 + 1 >= x.len() {
            return None;
        }
        let v_start = 0.5 * (x[i0 + 1] - x[i0 - 1]) * fs;
        let v_end = 0.5 * (3.0 * x[i1] - 4.0 * x[i1 - 1] + x[i1 - 2]) * fs;
        rate[k] = mass * (v_end - v_start) / (w1 - w0);
    }
    Some(rate)
}

/// Physical range of the contact angle on one race, rad: up to the angle at which the
/// contact centre reaches the land's edge (beyond it the contact ellipse is truncated, which
/// the model does not represent), on either side of the groove bottom, as the model's groove
/// is symmetric. Slightly negative outer angles are real: where centrifugal force outweighs
/// a ball's share of the axial load (the unloaded side at 60000 rpm or under ten times the
/// Table-1 radial load) the outer contact moves a degree or so past the groove bottom.
pub fn contact_angle_range(scene: &Scene, race: Race) -> (f64, f64) {
    let b = &scene.bearing;
    let (groove, land, f) = match race {
        Race::Inner => (
            b.inner_groove_diameter,
            b.inner_land_diameter,
            b.inner_groove_curvature,
        ),
        Race::Outer => (
            b.outer_groove_diameter,
            b.outer_land_diameter,
            b.outer_groove_curvature,
        ),
    };
    let r_groove = f * b.ball_diameter;
    // shoulder height above the groove bottom
    let h = 0.5 * (groove - land).abs();
    let max = if h >= r_groove {
        0.5 * PI
    } else {
        (1.0 - h / r_groove).acos()
    };
    (-max, max)
}

/// Check the invariants of a run of `scene`: every summary value and channel sample finite;
/// the mean inner-ring reaction balancing the applied load; the mean cage speed between 0
/// and the shaft speed; the mean contact angles within [`contact_angle_range`].
pub fn check(scene: &Scene, result: &SimResult) -> Vec<Violation> {
    let mut v = Vec::new();
    let s = &result.summary;
    let mut finite = |field: String, x: f64| {
        if !x.is_finite() {
            v.push(Violation::NonFinite { field });
        }
    };
    let st = &s.stats;
    finite("stats.min_step".into(), st.min_step);
    finite("stats.max_step".into(), st.max_step);
    finite("stats.wall_time".into(), st.wall_time);
    for (k, x) in s.steady_window.iter().enumerate() {
        finite(format!("steady_window[{k}]"), *x);
    }
    finite("mean_shaft_speed".into(), s.mean_shaft_speed);
    finite("mean_cage_speed".into(), s.mean_cage_speed);
    finite("epicyclic_cage_speed".into(), s.epicyclic_cage_speed);
    finite("cage_slip".into(), s.cage_slip);
    for (k, x) in s.loaded_contact_angles.iter().enumerate() {
        finite(format!("loaded_contact_angles[{k}]"), *x);
    }
    for (k, x) in s.mean_inner_ring_reaction.iter().enumerate() {
        finite(format!("mean_inner_ring_reaction[{k}]"), *x);
    }
    for (list, bins) in [("balls", &s.balls), ("load_zone", &s.load_zone)] {
        for (k, b) in bins.iter().enumerate() {
            finite(format!("{list}[{k}].inner_load"), b.inner_load);
            finite(format!("{list}[{k}].outer_load"), b.outer_load);
            // An angle is NaN by design where its contact never carried load in the window.
            if b.inner_load != 0.0 {
                finite(
                    format!("{list}[{k}].inner_contact_angle"),
                    b.inner_contact_angle,
                );
            }
            if b.outer_load != 0.0 {
                finite(
                    format!("{list}[{k}].outer_contact_angle"),
                    b.outer_contact_angle,
                );
            }
        }
    }
    let c = &s.cage_motion;
    finite("cage_motion.mean_eccentricity".into(), c.mean_eccentricity);
    finite("cage_motion.max_eccentricity".into(), c.max_eccentricity);
    finite("cage_motion.whirl_speed".into(), c.whirl_speed);
    for ch in &result.channels.channels {
        if let Some(i) = ch.data.iter().position(|x| !x.is_finite()) {
            finite(format!("channels.{}[{i}]", ch.name), ch.data[i]);
        }
    }

    // Reaction: the balls' mean force on the inner ring is minus the applied force, plus
    // the ring's momentum change over the window where the run records its displacement
    // (Newton's second law, which holds whether the run is steady or not: a lightly loaded
    // bearing whose balls skid and slow moves its ring as their centrifugal force falls).
    let o = &scene.operating;
    let (sn, cs) = o.radial_load_angle.sin_cos();
    let applied = [o.axial_load, -o.radial_load * sn, o.radial_load * cs];
    let magnitude = applied.iter().map(|x| x * x).sum::<f64>().sqrt();
    let tolerance = (0.01 * magnitude).max(REACTION_FLOOR);
    let momentum = inner_ring_momentum_rate(scene, result);
    for (k, axis) in [Axis::X, Axis::Y, Axis::Z].into_iter().enumerate() {
        let reaction = s.mean_inner_ring_reaction[k];
        let expected = -applied[k] + momentum.map_or(0.0, |m| m[k]);
        // a NaN reaction is already reported above; `!(<)` would report it twice
        if (reaction - expected).abs() > tolerance {
            v.push(Violation::Reaction {
                axis,
                reaction,
                expected,
                tolerance,
            });
        }
    }

    // Cage between standstill and the shaft: the balls' orbit speed lies between the
    // stationary outer race and the inner race for any contact angles.
    if !(s.mean_cage_speed >= 0.0 && s.mean_cage_speed <= s.mean_shaft_speed) {
        v.push(Violation::CageSpeed {
            cage: s.mean_cage_speed,
            shaft: s.mean_shaft_speed,
        });
    }

    // Contact angles: per ball, per azimuth bin and the load-weighted pair.
    let mut angle = |field: String, race: Race, a: f64| {
        let (min, max) = contact_angle_range(scene, race);
        if a.is_finite() && !(a >= min && a <= max) {
            v.push(Violation::ContactAngle {
                field,
                race,
                angle: a,
                min,
                max,
            });
        }
    };
    angle(
        "loaded_contact_angles[0]".into(),
        Race::Inner,
        s.loaded_contact_angles[0],
    );
    angle(
        "loaded_contact_angles[1]".into(),
        Race::Outer,
        s.loaded_contact_angles[1],
    );
    for (list, bins) in [("balls", &s.balls), ("load_zone", &s.load_zone)] {
        for (k, b) in bins.iter().enumerate() {
            angle(
                format!("{list}[{k}].inner_contact_angle"),
                Race::Inner,
                b.inner_contact_angle,
            );
            angle(
                format!("{list}[{k}].outer_contact_angle"),
                Race::Outer,
                b.outer_contact_angle,
            );
        }
    }
    v
}

/// RHS evaluations per simulated second of a run (the run's end is its steady window's).
pub fn rhs_per_second(result: &SimResult) -> f64 {
    result.summary.stats.rhs_evaluations as f64 / result.summary.steady_window[1]
}

/// The solver-cost invariant: at most `factor` times the reference's RHS evaluations per
/// simulated second. Counts, not wall time, so the check is repeatable on a busy machine.
pub fn check_cost(result: &SimResult, reference: f64, factor: f64) -> Option<Violation> {
    let rhs_per_second = rhs_per_second(result);
    (rhs_per_second > factor * reference).then_some(Violation::SolverCost {
        rhs_per_second,
        reference,
        factor,
    })
}

/// What happened to a scene.
#[derive(Debug)]
pub enum Outcome {
    /// It ran; the invariants it broke, cost included, are listed.
    Ran {
        result: Box<SimResult>,
        violations: Vec<Violation>,
    },
    /// Refused up front.
    Refused(ValidationErrors),
    /// It passed [`prepare`] but the run failed (step underflow, non-finite state).
    Failed(SimError),
}

/// Run `case` for `duration` s and check it; `reference` is the reference scene's RHS
/// evaluations per simulated second (`None`: the cost is not checked, e.g. when running the
/// reference itself).
pub fn run_case(case: &StressScene, duration: f64, reference: Option<f64>) -> Outcome {
    let scene = case.scene(duration);
    let valid = match prepare(&scene) {
        Ok(v) => v,
        Err(e) => return Outcome::Refused(e),
    };
    match simulate(&valid, RunControl::default()) {
        Ok(result) => {
            let mut violations = check(&scene, &result);
            if let (Some(r), Expectation::Runs { cost_factor }) = (reference, case.expect) {
                violations.extend(check_cost(&result, r, cost_factor));
            }
            Outcome::Ran {
                result: Box::new(result),
                violations,
            }
        }
        Err(e) => Outcome::Failed(e),
    }
}

/// Whether an outcome is what `case` expects; the reason when it is not.
pub fn verdict(case: &StressScene, outcome: &Outcome) -> Result<(), String> {
    match (&case.expect, outcome) {
        (Expectation::Runs { .. }, Outcome::Ran { violations, .. }) => {
            if violations.is_empty() {
                Ok(())
            } else {
                Err(violations
                    .iter()
                    .map(|v| v.to_string())
                    .collect::<Vec<_>>()
                    .join("; "))
            }
        }
        (Expectation::Runs { .. }, Outcome::Refused(e)) => {
            Err(format!("expected to run, refused: {e}"))
        }
        (_, Outcome::Failed(e)) => Err(format!("run failed: {e}")),
        (Expectation::Refused { field }, Outcome::Refused(e)) => {
            if e.0.iter().any(|fe| fe.path == *field) {
                Ok(())
            } else {
                Err(format!("refused, but not on {field}: {e}"))
            }
        }
        (Expectation::Refused { field }, Outcome::Ran { .. }) => {
            Err(format!("expected a refusal on {field}, but it ran"))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalogue_names_are_unique_and_reference_first() {
        let c = catalogue();
        assert_eq!(c[0].name, REFERENCE);
        let mut names: Vec<_> = c.iter().map(|s| s.name).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), c.len());
        assert!(c.len() >= 15);
    }

    #[test]
    fn refusals_name_their_field_without_running() {
        for case in catalogue() {
            if let Expectation::Refused { field } = case.expect {
                let scene = case.scene(case.test_duration);
                let errs = match scene.validated() {
                    Err(e) => e,
                    Ok(v) => check_start(&v).unwrap_err(),
                };
                assert!(
                    errs.0.iter().any(|e| e.path == field),
                    "{}: {errs}",
                    case.name
                );
            }
        }
    }

    #[test]
    fn contact_angle_range_of_the_preset() {
        // shoulders 1.29 mm (inner) and 1.05 mm (outer) high on 2.94 / 2.98 mm grooves
        let s = preset_scene("h7005c").unwrap();
        let (lo, hi) = contact_angle_range(&s, Race::Inner);
        assert_eq!(lo, -hi);
        assert!((hi.to_degrees() - 55.7).abs() < 0.2, "{}", hi.to_degrees());
        let (_, hi) = contact_angle_range(&s, Race::Outer);
        assert!((hi.to_degrees() - 49.5).abs() < 0.3, "{}", hi.to_degrees());
    }

    #[test]
    fn check_reports_each_broken_invariant() {
        use crate::dynamics::{BallSummary, Channel, Channels, Summary};
        let scene = table1_steady(0.02);
        let ball = BallSummary {
            inner_load: 50.0,
            outer_load: 55.0,
            inner_contact_angle: 15f64.to_radians(),
            outer_contact_angle: 14f64.to_radians(),
        };
        let good = SimResult {
            summary: Summary {
                steady_window: [0.005, 0.02],
                mean_shaft_speed: 1047.2,
                mean_cage_speed: 446.7,
                epicyclic_cage_speed: 445.0,
                loaded_contact_angles: [0.26, 0.23],
                mean_inner_ring_reaction: [-100.0, 0.0, -300.0],
                balls: vec![ball.clone(); 16],
                load_zone: vec![
                    BallSummary {
                        inner_load: 0.0,
                        inner_contact_angle: f64::NAN,
                        ..ball.clone()
                    };
                    16
                ],
                ..Summary::default()
            },
            channels: Channels {
                sample_rate: 102_400.0,
                start_time: 0.0,
                channels: vec![Channel {
                    name: "outer_ring_accel_y".into(),
                    unit: "m/s^2".into(),
                    data: vec![0.0; 4],
                }],
            },
        };
        // a never-loaded contact's NaN angle is not a violation
        assert_eq!(check(&scene, &good), vec![]);
        let mut bad = good.clone();
        bad.summary.mean_inner_ring_reaction[2] = -296.0; // 4 N off, tolerance 3.16 N
        bad.summary.mean_cage_speed = -1.0;
        bad.summary.balls[3].outer_contact_angle = 60f64.to_radians();
        bad.channels.channels[0].data[2] = f64::NAN;
        let v = check(&scene, &bad);
        assert!(
            matches!(v[0], Violation::NonFinite { ref field } if field == "channels.outer_ring_accel_y[2]"),
            "{v:?}"
        );
        assert!(
            matches!(v[1], Violation::Reaction { axis: Axis::Z, .. }),
            "{v:?}"
        );
        assert!(matches!(v[2], Violation::CageSpeed { .. }), "{v:?}");
        assert!(
            matches!(
                v[3],
                Violation::ContactAngle {
                    race: Race::Outer,
                    ..
                }
            ),
            "{v:?}"
        );
        assert_eq!(v.len(), 4, "{v:?}");
        // A ring that accelerates (here 1 m/s^2 along X over the window, as a ring moves
        // when its balls skid and slow): under 1 N axial the reaction balances the load plus
        // `m a`, and that is no violation, while the same reaction with a ring at rest is one.
        let light = loads(0.02, 0.0, 1.0);
        let mass = Model::new(&light.validated().unwrap()).inner_mass;
        let fs = good.channels.sample_rate;
        // as recorded: the last sample at the run's end, 0.02 s (and one fewer: a window end
        // past the last sample is read at it)
        let samples = (0.02 * fs) as usize + 1;
        let disp = |name: &str, f: &dyn Fn(f64) -> f64| Channel {
            name: name.into(),
            unit: "m".into(),
            data: (0..samples).map(|i| f(i as f64 / fs)).collect(),
        };
        let moving = |accel: f64| {
            let mut r = good.clone();
            r.channels.channels.extend([
                disp("inner_ring_disp_x", &|t| 0.5 * accel * t * t),
                disp("inner_ring_disp_y", &|_| 0.0),
                disp("inner_ring_disp_z", &|_| 1e-6),
            ]);
            r.summary.mean_inner_ring_reaction = [-1.0 + mass * 1.0, 0.0, 0.0];
            r
        };
        assert_eq!(check(&light, &moving(1.0)), vec![]);
        let mut short = moving(1.0);
        for ch in &mut short.channels.channels[1..] {
            ch.data.pop();
        }
        assert_eq!(check(&light, &short), vec![]);
        let v = check(&light, &moving(0.0));
        assert!(
            matches!(v[..], [Violation::Reaction { axis: Axis::X, .. }]),
            "{v:?}"
        );
        // 10000 evaluations over 0.02 s: 5e5 per second
        let mut good = good;
        good.summary.stats.rhs_evaluations = 10_000;
        assert_eq!(check_cost(&good, 2e5, 3.0), None);
        let cost = check_cost(&good, 1e5, 3.0).unwrap();
        assert!(matches!(cost, Violation::SolverCost { .. }), "{cost}");
    }
}
