//! Dynamic model against the quasi-static reference and its own convergence.

use bearing_core::dynamics::CageState;
use bearing_core::quasi_static::{pocket_cycle, pocket_cycle_with, solve, PocketCycleSettings};
use bearing_core::scene::{
    fault_case_scene, preset_scene, CavityDrag, FaultCase, Fidelity, Integrator,
    RollingResistanceModel, Scene, Traction,
};
use bearing_core::simulation::{simulate, RunControl, SimResult};
use bearing_core::simulation_analysis::steady_band_rms;

/// H7005C at a constant 10000 rpm (no ramp), `duration` s.
fn constant_speed(duration: f64, tol: f64) -> Scene {
    let mut s = preset_scene("h7005c").unwrap();
    s.operating.speed.initial_rpm = 10_000.0;
    s.operating.speed.steady_rpm = 10_000.0;
    s.operating.speed.ramp_time = 0.0;
    s.solver.duration = duration;
    s.solver.rtol = tol;
    s.solver.atol = tol;
    s
}

/// `s` under the seed paper's model as the measurements below the tests that call this were
/// made: the paper's eq. 15 curve, no rolling resistance, the explicit `rk4_fsal`.
fn paper_model(mut s: Scene) -> Scene {
    s.lubricant.traction = Traction::PAPER_CURVE;
    s.lubricant.rolling_resistance = RollingResistanceModel::None;
    s.solver.integrator = Integrator::Rk4Fsal;
    s
}

fn run(s: &Scene) -> SimResult {
    simulate(&s.validated().unwrap(), RunControl::default()).unwrap()
}

#[test]
fn steady_run_agrees_with_quasi_static() {
    let scene = constant_speed(0.1, 1e-5);
    let r = run(&scene);
    agrees_with_quasi_static(&scene, &r);
    // At this point the cage centre keeps far from the land: within ~20 % of the land
    // clearance under the paper's model (measured 0.18-0.24), 0.31 under the preset's physics
    // (2026-11-29).
    let c = r.summary.cage_motion;
    eprintln!("{c:?}");
    assert!(c.mean_eccentricity < 0.5, "{c:?}");
}

/// Under the paper's curve the cage speed by the pocket cycle (one ball carried round its
/// orbit in a pocket turning with the cage) is closer to what a running cage settles to than
/// the steady traction balance that holds every ball at the cage's speed: at the paper's
/// point and at 12000 rpm, where the steady balance finds no root and falls back on the
/// epicyclic speed. As this test printed it 2026-11-28 (0.2 s runs): dynamic 446.946 and
/// 538.287 rad/s, pocket cycle +0.095 % and +0.034 %, steady balance -0.283 % and -0.629 %
/// (docs/reference/model.md, "Cage speed by the pocket cycle"). Asserted: within issue 33's
/// 0.3 % and closer than the steady balance (which 0.3 % alone does not tell apart at 10000
/// rpm), against the mean over the run's steady window; and the torque the search met falls
/// with the cage speed (one root; `monotone` leaves out rises within what a trial's torque is
/// known to, about 1e-3 of the drag: the last trials lie 1e-3 rad/s apart with torques
/// 1e-6 N m apart).
#[test]
fn pocket_cycle_gives_the_running_cage_speed() {
    for rpm in [10_000.0, 12_000.0] {
        // the paper's model, where the figures above were measured; under the preset's
        // rheology law the cycle's torque is a staircase and a 0.2 s run's cage has not
        // settled (docs/reference/model.md, "Cage speed by the pocket cycle")
        let mut scene = paper_model(constant_speed(0.2, 1e-5));
        scene.operating.speed.initial_rpm = rpm;
        scene.operating.speed.steady_rpm = rpm;
        let dynamic = run(&scene).summary.mean_cage_speed;
        let cycle = pocket_cycle(&scene.validated().unwrap(), rpm).unwrap();
        let steady = solve(&scene.validated().unwrap(), rpm).unwrap().cage_speed;
        let (e_cycle, e_steady) = (cycle.cage_speed / dynamic - 1.0, steady / dynamic - 1.0);
        eprintln!(
            "{rpm} rpm: dynamic {dynamic:.3} rad/s, pocket cycle {:+.3} %, steady balance {:+.3} % ({} orbits)",
            100.0 * e_cycle,
            100.0 * e_steady,
            cycle.orbits
        );
        assert!(
            e_cycle.abs() < 3e-3,
            "{rpm} rpm: {cycle:?} against {dynamic}"
        );
        assert!(
            e_cycle.abs() < e_steady.abs(),
            "{rpm} rpm: pocket cycle {e_cycle:+.2e}, steady balance {e_steady:+.2e}"
        );
        assert!(cycle.monotone, "{rpm} rpm: {:?}", cycle.torque_curve);
    }
}

/// Under the default physics (the rheology law with rolling resistance; the figures below
/// measured under `auto_slip`, the test runs the preset's integrator, `auto_etd` since
/// 2026-11-30) at the
/// paper's point the pocket cycle's cage speed is within issue 33's 0.3 % of a settled running
/// cage, and the steady balance is not. The running cage first holds a lower regime for about
/// 0.5 s (441.6-441.8 rad/s, against which the cycle is +0.32-0.35 %), so it is averaged over
/// 0.75-1.5 s of a 1.5 s run, after it has left that regime. Measured 2026-11-29
/// (docs/reference/model.md, "Cage speed by the pocket cycle"): a 3 s run's quarter-second
/// means 442.21-442.29 rad/s from 0.75 s on (442.15 over 0.5-0.75 s); the cycle 443.170
/// (+0.21 %); the steady balance 445.15 (+0.65 %). One of the cycle's trials, next to the
/// step in its torque, does not settle within its 64 orbits (`unsettled` 1; its torque is
/// the last block's mean): not asserted, the convergence test below covering that choice.
/// Under `auto_etd` (2026-11-30): 442.339 rad/s over 0.75-1.5 s, the cycle +0.19 %, the
/// steady balance +0.64 %.
#[test]
fn pocket_cycle_gives_the_running_cage_speed_under_the_default_physics() {
    let mut scene = constant_speed(1.5, 1e-5);
    scene.outputs.cage_speed = true;
    // only the cage channel is read
    scene.solver.sample_rate = 20_480.0;
    let r = run(&scene);
    let fs = r.channels.sample_rate;
    let cage = &r.channels.get("cage_speed").unwrap().data;
    let from = ((0.75 - r.channels.start_time) * fs) as usize;
    let dynamic = cage[from..].iter().sum::<f64>() / (cage.len() - from) as f64;
    let valid = scene.validated().unwrap();
    let cycle = pocket_cycle(&valid, 10_000.0).unwrap();
    let steady = solve(&valid, 10_000.0).unwrap().cage_speed;
    let (e_cycle, e_steady) = (cycle.cage_speed / dynamic - 1.0, steady / dynamic - 1.0);
    eprintln!(
        "default physics: dynamic {dynamic:.3} rad/s (0.75-1.5 s), pocket cycle {:.3} ({:+.3} %, {} orbits, {} unsettled), steady balance {steady:.3} ({:+.3} %)",
        cycle.cage_speed,
        100.0 * e_cycle,
        cycle.orbits,
        cycle.unsettled,
        100.0 * e_steady
    );
    assert!(e_cycle.abs() < 3e-3, "{cycle:?} against {dynamic}");
    assert!(
        e_cycle.abs() < e_steady.abs(),
        "pocket cycle {e_cycle:+.2e}, steady balance {e_steady:+.2e}"
    );
    // why the cycle is needed here: the steady balance misses the 0.3 %
    assert!(e_steady.abs() > 3e-3, "steady balance {e_steady:+.2e}");
}

/// The pocket cycle's cage speed under the default physics at the paper's point does not
/// depend on its numerical choices: a tenth of the tolerance, blocks of 16 orbits instead of
/// 8, and a search started at the settled running cage's 442.26 rad/s instead of the steady
/// balance's 445.15 each move it by under 1e-5 (measured 2026-11-29: 443.1697 as committed;
/// 443.1685, 443.1696 and 443.1695, so 2.7e-6 at most). The bound, 1e-5, is the search's own
/// 1e-6 with room for the torque's 1e-3-of-the-drag accuracy, and 300 times below issue 33's
/// 0.3 %. The block size only acts on trials whose orbits do not repeat within 8; the base run
/// is checked to have some (224 orbits over its 8 trials). What it does not cover: choices of the model itself (where the cage sits; a single
/// orbit's torque instead of the mean), which model.md lists with their roots.
#[test]
fn pocket_cycle_is_converged_in_its_numerical_choices() {
    let valid = constant_speed(1.0, 1e-5).validated().unwrap();
    let base = PocketCycleSettings::default();
    let base_cycle = pocket_cycle_with(&valid, 10_000.0, &base, &|| false).unwrap();
    assert!(
        base_cycle.orbits > 8 * base_cycle.torque_curve.len() as u32,
        "no trial reached the averaging blocks: {base_cycle:?}"
    );
    let kept = base_cycle.cage_speed;
    for (what, settings) in [
        (
            "tolerance 1e-7",
            PocketCycleSettings {
                tolerance: 1e-7,
                ..base
            },
        ),
        (
            "blocks of 16 orbits",
            PocketCycleSettings {
                block_orbits: 16,
                ..base
            },
        ),
        (
            "started at 442.26 rad/s",
            PocketCycleSettings {
                start: Some(442.26),
                ..base
            },
        ),
    ] {
        let c = pocket_cycle_with(&valid, 10_000.0, &settings, &|| false)
            .unwrap()
            .cage_speed;
        let e = c / kept - 1.0;
        eprintln!("{what}: {c:.4} rad/s against {kept:.4} ({e:+.1e})");
        assert!(e.abs() < 1e-5, "{what}: {c} against {kept}");
    }
}

/// Cash-Karp RK4 (the former default), the Rosenbrock-W method and `etd_rk4` (the preset's
/// `auto_etd`'s method at running speed) reach the same steady state as the quasi-static
/// solver, like `rk4_fsal`, and the same mean cage speed as it
/// within the brief's 0.01 %, under the paper's model. Under the preset's rheology law a
/// 0.1 s run's mean cage speed is not known to 0.01 %: a 1e-8 change of the axial load
/// moves it by 5e-5 and the integrators' answers spread over 3e-4, at 1e-7 as at 1e-5
/// (docs/lab/benchmarks.md, "The default law's runs scatter"); the methods are compared
/// under that law at 2000 rpm below, where its runs do not scatter.
#[test]
fn other_integrators_agree_with_quasi_static_and_rk4_fsal() {
    let reference = run(&paper_model(constant_speed(0.1, 1e-5)));
    for (integrator, tol) in [
        (Integrator::Rk4Adaptive, 1e-6),
        (Integrator::RosenbrockW, 1e-5),
        (Integrator::EtdRk4, 1e-5),
    ] {
        let mut scene = paper_model(constant_speed(0.1, tol));
        scene.solver.integrator = integrator;
        let r = run(&scene);
        agrees_with_quasi_static(&scene, &r);
        let (c, c_ref) = (r.summary.mean_cage_speed, reference.summary.mean_cage_speed);
        assert!(
            ((c - c_ref) / c_ref).abs() < 1e-4,
            "{integrator:?}: cage speed {c} vs {c_ref} rad/s"
        );
    }
}

/// `slip_implicit` under the rheology law at 2000 rpm, where the thin film makes the slip
/// relax faster than the contact modes ring (no fault, 0.05 s), both methods at 1e-7: the
/// same mean cage speed as `rk4_fsal` within 1e-5 (issue 34's cage-speed accuracy; measured
/// 2026-11-28 with ROS34PRw 3.7e-6 apart, `auto_slip` 8.4e-6; with ROS34PW2 6.4e-6 and
/// 6.3e-6; with the law's cell means 8.1e-6 and 7.9e-6, the three methods within 3.6e-6 of
/// each other at 1e-8; with the cell's across part split at saturation 5.4e-6 and 9.4e-6,
/// close to the bound; a land film always implicit in `slip_implicit` made it 1.1e-5, so
/// the film goes implicit only where the explicit part cannot take it) and far fewer
/// evaluations, the slip no longer setting the step (measured 39k
/// against 210k, 51k with ROS34PW2; half leaves room; 2026-11-29 at the law's own 4 nodes
/// 37 446 and `auto_slip` 41 135 against 204 409, the cages within the bound; with the
/// preset's rolling resistance since the default changed, 40 255 and 42 188 against 206 521). (0.05 s is 1.7 shaft turns: too short for the load-zone bins of the
/// quasi-static comparison, which the 10000 rpm tests above make.)
///
/// Each method's cage speed is the mean of three runs started at 1, 0.9 and 0.8 of the
/// initial step, which changes the whole step sequence: one run's moves with it, by a
/// standard deviation of about 2.5e-6 around `auto_slip`'s -5e-6 (five runs each of
/// `4d6b9c7` and of the build with the contacts side by side, 2026-11-30, whose single run
/// came to -1.02e-5 with the first start and -2.5e-6 to -6.9e-6 with the others). So the
/// bound tests the methods' bias, not one step sequence's luck.
#[test]
fn slip_implicit_steps_over_the_slip_relaxation_at_low_speed() {
    let mut explicit = constant_speed(0.05, 1e-7);
    explicit.operating.speed.initial_rpm = 2_000.0;
    explicit.operating.speed.steady_rpm = 2_000.0;
    explicit.lubricant.traction = Traction::RHEOLOGY;
    // the explicit reference named, not the preset's default integrator
    explicit.solver.integrator = Integrator::Rk4Fsal;
    let mut implicit = explicit.clone();
    implicit.solver.integrator = Integrator::SlipImplicit;
    let re = run(&explicit);
    let ce = re.summary.mean_cage_speed;
    // the mean cage speed of three starts and the first start's evaluations
    let three_starts = |s: &Scene| {
        let mut cage = 0.0;
        let mut first = 0;
        for (k, factor) in [1.0, 0.9, 0.8].into_iter().enumerate() {
            let mut s = s.clone();
            s.solver.initial_step *= factor;
            let r = run(&s);
            cage += r.summary.mean_cage_speed / 3.0;
            if k == 0 {
                first = r.summary.stats.rhs_evaluations;
            }
        }
        (cage, first)
    };
    let (ci, ni) = three_starts(&implicit);
    assert!(((ci - ce) / ce).abs() < 1e-5, "cage {ci} vs {ce} rad/s");
    let ne = re.summary.stats.rhs_evaluations;
    eprintln!("rk4_fsal {ne}, slip_implicit {ni} evaluations");
    assert!(
        2 * ni < ne,
        "slip_implicit {ni} against rk4_fsal {ne} evaluations"
    );
    // `auto_slip` finds the implicit method the cheaper by measuring, and stays with it
    let mut auto = explicit.clone();
    auto.solver.integrator = Integrator::AutoSlip;
    let (ca, na) = three_starts(&auto);
    eprintln!("auto_slip {na} evaluations");
    assert!(((ca - ce) / ce).abs() < 1e-5, "cage {ca} vs {ce} rad/s");
    assert!(
        2 * na < ne,
        "auto_slip {na} against rk4_fsal {ne} evaluations"
    );
}

/// `auto_slip` under the rheology law at the default tolerance, no fault, 0.05 s: at 10000
/// rpm it costs at most a quarter more than `rk4_fsal` alone (the lost trials of the other
/// method; measured 2026-11-28 29 672 against 34 669, 0.86x, `slip_implicit` with ROS34PRw
/// being the cheaper here too; with ROS34PW2 37 980, 1.10x); and a simulated second at 2000
/// rpm costs at most 1.5 times one at 10000 rpm in evaluations (issue 34's bound; measured
/// 32 195 against 29 672, 1.09x; with ROS34PW2 1.41x), where `rk4_fsal` alone takes 6x
/// (210k against 34.7k). 2026-11-29, at the law's own 4 nodes and with the implicit method
/// taking the run only where it saves 40 % and giving it back where it saves less than a
/// tenth (`ode::auto_switch`): 28 682 against 31 569 (0.91x), and 32 698 at 2000 rpm
/// (1.14x); with the preset's rolling resistance (the default since that day) 30 232 against
/// 33 941 (0.89x), and 32 313 at 2000 rpm (1.07x).
#[test]
fn auto_slip_costs_little_more_at_low_speed_than_at_high() {
    let mut fast = constant_speed(0.05, 1e-5);
    fast.lubricant.traction = Traction::RHEOLOGY;
    fast.solver.integrator = Integrator::AutoSlip;
    let mut slow = fast.clone();
    slow.operating.speed.initial_rpm = 2_000.0;
    slow.operating.speed.steady_rpm = 2_000.0;
    let mut explicit = fast.clone();
    explicit.solver.integrator = Integrator::Rk4Fsal;
    let count = |s: &Scene| run(s).summary.stats.rhs_evaluations as f64;
    let (n_fast, n_slow, n_explicit) = (count(&fast), count(&slow), count(&explicit));
    eprintln!("auto_slip 10000 rpm {n_fast}, 2000 rpm {n_slow}; rk4_fsal 10000 rpm {n_explicit}");
    assert!(n_fast <= 1.25 * n_explicit, "{n_fast} against {n_explicit}");
    assert!(n_slow <= 1.5 * n_fast, "{n_slow} against {n_fast}");
}

/// The reduced fidelity levels (docs/reference/model.md, "Fidelity levels") reach the quasi-static
/// steady state like the full model: the ball centres the Newton solve puts in balance
/// carry the same load zone and contact angles as the independent quasi-static solver.
#[test]
fn reduced_fidelity_levels_agree_with_quasi_static() {
    for level in [Fidelity::QuasiStaticBalls, Fidelity::ConcentricCage] {
        let mut scene = constant_speed(0.1, 1e-5);
        scene.solver.fidelity = level;
        let r = run(&scene);
        eprintln!("{level:?}: {} RHS", r.summary.stats.rhs_evaluations);
        agrees_with_quasi_static(&scene, &r);
    }
}

/// The compound fault at a constant 10000 rpm, 0.15 s (steady window 0.1-0.15 s, ~3.5 cage
/// revolutions, ~30 ball passes over each defect): a reduced level keeps the mean cage speed
/// of the full model within 0.05 % (the limit on BPFO and BPFI, which for a fixed
/// outer ring are Z f_cage and Z (f_shaft - f_cage), so their errors are the cage speed's
/// and 0.74 of it), and its pedestal band RMS (< 20 kHz) within the 10 %, while
/// costing fewer right-hand sides. Measured 2026-11-23 (after the cube-root change):
/// quasi_static_balls -0.016 % and +5.5 % for 0.37 of the evaluations, concentric_cage
/// +0.041 % and +6.3 % for 0.32. (On
/// the 0.5 s Table-1 ramp concentric_cage exceeds 10 % of band RMS: docs/lab/benchmarks.md.)
#[test]
fn reduced_fidelity_levels_keep_the_full_models_cage_speed_and_signal() {
    // the paper's model, where the figures above were measured; the preset's rheology law's
    // are in docs/lab/benchmarks.md ("The default law's runs scatter")
    let mut full = paper_model(fault_case_scene("h7005c", FaultCase::Compound).unwrap());
    full.operating.speed.initial_rpm = 10_000.0;
    full.operating.speed.ramp_time = 0.0;
    full.solver.duration = 0.15;
    let reference = run(&full);
    let rms = |r: &SimResult| steady_band_rms(r, "outer_ring_accel_z", 20e3).unwrap();
    let (c_ref, rms_ref) = (reference.summary.mean_cage_speed, rms(&reference));
    for level in [Fidelity::QuasiStaticBalls, Fidelity::ConcentricCage] {
        let mut scene = full.clone();
        scene.solver.fidelity = level;
        let r = run(&scene);
        let dc = (r.summary.mean_cage_speed - c_ref) / c_ref;
        let dr = (rms(&r) - rms_ref) / rms_ref;
        let cost =
            r.summary.stats.rhs_evaluations as f64 / reference.summary.stats.rhs_evaluations as f64;
        eprintln!(
            "{level:?}: cage speed {:+.4} %, band RMS {:+.2} %, RHS {:.2} of full",
            100.0 * dc,
            100.0 * dr,
            cost
        );
        assert!(dc.abs() < 5e-4, "{level:?}: cage speed changed by {dc:.2e}");
        assert!(dr.abs() < 0.10, "{level:?}: band RMS changed by {dr:.2e}");
        assert!(cost < 0.7, "{level:?}: {cost:.2} of full's RHS evaluations");
    }
}

/// At 400 N axial every ball is loaded and the balls pull the cage round evenly: it runs
/// centred without orbiting (measured e = 0.04 under the paper's model, 0.004 under the
/// preset's physics, 2026-11-29), which the summary reports as quiet.
#[test]
fn evenly_loaded_cage_runs_quiet() {
    let mut scene = constant_speed(0.06, 1e-5);
    scene.operating.axial_load = 400.0;
    let c = run(&scene).summary.cage_motion;
    eprintln!("{c:?}");
    assert_eq!(c.state, CageState::Quiet, "{c:?}");
    assert!(c.mean_eccentricity < 0.1, "{c:?}");
}

/// With lubricant drag and EHL rolling resistance the balls are braked: the cage runs
/// slower than in the paper's model, and the loads still balance and agree with the
/// quasi-static solution (drag and rolling resistance act along the rolling direction, so
/// the quasi-static normal equilibrium does not change). Started from the traction balance
/// the cage runs quiet on its land: the half-speed whirl once seen here came from the start
/// (every ball at its own rolling speed and the cage at their mean, 2.3 % fast); measured
/// 2026-11-27 from the balanced start, e = 0.11 over 0.3 s, no orbit (docs/lab/history.md).
#[test]
fn drag_and_rolling_resistance_brake_the_cage() {
    // the paper's model named, not taken from the preset: the measurements below are its
    let paper = paper_model(constant_speed(0.06, 1e-5));
    let mut full = paper.clone();
    full.lubricant.cavity_drag = CavityDrag::OilAir { oil_fraction: 0.01 };
    full.lubricant.rolling_resistance = RollingResistanceModel::Houpert { factor: 1.0 };
    let (rp, rf) = (run(&paper), run(&full));
    agrees_with_quasi_static(&full, &rf);
    let (cp, cf) = (rp.summary.mean_cage_speed, rf.summary.mean_cage_speed);
    // Measured: -0.27 % (446.73 -> 445.52 rad/s); the braking must at least exceed the
    // window-to-window scatter of the mean cage speed (~0.05 %) and stay below the 1 %
    // a cage could lose before the loaded balls themselves skid.
    let change = cf / cp - 1.0;
    eprintln!(
        "cage {cp:.3} -> {cf:.3} rad/s ({:.3} %), {:?}",
        100.0 * change,
        rf.summary.cage_motion
    );
    assert!(change < -5e-4 && change > -1e-2, "cage {cp} -> {cf} rad/s");
    // No whirl: measured mean eccentricity 0.13 over this window (0.11 over 0.3 s), where
    // the whirl grew to 0.97; 0.3 leaves room and stays far below it.
    let c = rf.summary.cage_motion;
    assert!(c.mean_eccentricity < 0.3, "{c:?}");
}

/// The earlier film traction law (an Eyring film with a limiting shear stress): the normal equilibrium is unchanged, so the fidelity
/// checks hold; its low-slip slope on the loaded balls is ~240 times the paper's curve's, so
/// the solver needs more steps; and the cage runs slower than with the paper's curve.
#[test]
fn film_traction_keeps_the_equilibrium_and_slows_the_cage() {
    // the comparison is with the paper's model under the explicit `rk4_fsal`, named rather
    // than taken from the preset (the step count below is the explicit method's)
    let curve = paper_model(constant_speed(0.06, 1e-5));
    let mut film = curve.clone();
    film.lubricant.traction = Traction::Film {
        shear_modulus: 1e9,
        eyring_stress: 5e6,
        limiting_coefficient: 0.07,
    };
    let (rc, rf) = (run(&curve), run(&film));
    agrees_with_quasi_static(&film, &rf);
    let (cc, cf) = (rc.summary.mean_cage_speed, rf.summary.mean_cage_speed);
    let steps = rf.summary.stats.rhs_evaluations as f64 / rc.summary.stats.rhs_evaluations as f64;
    eprintln!(
        "cage {cc:.3} -> {cf:.3} rad/s ({:.3} %), {steps:.1}x RHS, {:?}",
        100.0 * (cf / cc - 1.0),
        rf.summary.cage_motion
    );
    // Measured: -0.88 % (446.73 -> 442.79 rad/s; -0.85 %, 446.95 -> 443.15, with exact Hertz
    // and the balanced start, 2026-11-29), slip against the loaded balls' rolling +0.64 %
    // (the curve gives -0.27 %): the nearly unloaded balls, whose thin low-pressure
    // film barely drives them, hold the cage back. The change must exceed four times the
    // window-to-window scatter of the mean cage speed (~0.05 %) and stay below 2 %, where
    // the loaded balls themselves would have to skid.
    let change = cf / cc - 1.0;
    assert!(change < -2e-3 && change > -2e-2, "cage {cc} -> {cf} rad/s");
    assert!(rf.summary.cage_slip > 0.0, "slip {}", rf.summary.cage_slip);
    // the stiffer law costs steps (measured 2.4x), not orders of magnitude
    assert!(steps > 1.5 && steps < 20.0, "{steps}x RHS evaluations");
}

/// The fidelity checks of a steady constant-speed 10000 rpm run against the quasi-static
/// solution of the same scene.
fn agrees_with_quasi_static(scene: &Scene, r: &SimResult) {
    let s = &r.summary;
    let qs = solve(&scene.validated().unwrap(), 10_000.0).unwrap();

    // Ring reaction balances the applied load (300 N radial along +Z, 100 N axial) within
    // 1 % of the load: the brief's figure; the window spans ~5 cage revolutions, so the
    // average covers whole ball passages.
    let f = s.mean_inner_ring_reaction;
    let applied = (300f64.powi(2) + 100f64.powi(2)).sqrt();
    assert!(
        (f[0] + 100.0).abs() < 0.01 * applied,
        "axial reaction {}",
        f[0]
    );
    assert!(f[1].abs() < 0.01 * applied, "y reaction {}", f[1]);
    assert!(
        (f[2] + 300.0).abs() < 0.01 * applied,
        "radial reaction {}",
        f[2]
    );

    // Load zone, binned by azimuth, against the quasi-static ball at that azimuth.
    let qmax = qs.balls.iter().map(|b| b.inner_load).fold(0.0, f64::max);
    for (k, (d, q)) in s.load_zone.iter().zip(&qs.balls).enumerate() {
        // 5 % (the brief's figure) of the load on balls carrying a quarter of the peak or
        // more; lightly loaded balls are held to 5 % of the peak load in absolute terms,
        // because there the ball-cage and traction forces the quasi-static model ignores
        // are a large part of a small load.
        for (name, dl, ql) in [
            ("inner", d.inner_load, q.inner_load),
            ("outer", d.outer_load, q.outer_load),
        ] {
            let tol = if ql > 0.25 * qmax {
                0.05 * ql
            } else {
                0.05 * qmax
            };
            assert!(
                (dl - ql).abs() < tol,
                "bin {k} {name}: dynamic {dl:.2} N, quasi-static {ql:.2} N"
            );
        }
        // Contact angles within 0.5 deg (the brief's figure) where the ball is loaded.
        if q.inner_load > 0.25 * qmax {
            for (name, da, qa) in [
                ("inner", d.inner_contact_angle, q.inner_contact_angle),
                ("outer", d.outer_contact_angle, q.outer_contact_angle),
            ] {
                assert!(
                    (da - qa).abs().to_degrees() < 0.5,
                    "bin {k} {name} angle: {:.3} vs {:.3} deg",
                    da.to_degrees(),
                    qa.to_degrees()
                );
            }
        }
    }

    // Cage against the loaded balls' pure rolling (the epicyclic speed at the load zone's
    // load-weighted contact angles). Under the paper's curve the cage runs ~0.3 % faster than
    // that at this point (issue 9: the nearly unloaded balls, under outer-race control and
    // unbraked, drive it); under the preset's rheology law it lags by 0.8-0.95 % (the paper's
    // cage lag; 0.93 % measured on these 0.1 s runs, 2026-11-29), so the sign is left open;
    // 1 % bounds it either way, close to the law's lag. (Against the old reference, which
    // averaged every ball's angles alike, the curve's run read +1.1 %.)
    assert!(s.cage_slip.abs() < 0.01, "slip {}", s.cage_slip);
    // The loaded angles agree with the quasi-static load-weighted ones within the 0.5 deg
    // the per-ball comparison above allows.
    let weighted = |load: fn(&bearing_core::quasi_static::QsBall) -> f64,
                    angle: fn(&bearing_core::quasi_static::QsBall) -> f64| {
        let w: f64 = qs.balls.iter().map(load).sum();
        qs.balls.iter().map(|b| load(b) * angle(b)).sum::<f64>() / w
    };
    let qs_angles = [
        weighted(|b| b.inner_load, |b| b.inner_contact_angle),
        weighted(|b| b.outer_load, |b| b.outer_contact_angle),
    ];
    for (name, d, q) in [
        ("inner", s.loaded_contact_angles[0], qs_angles[0]),
        ("outer", s.loaded_contact_angles[1], qs_angles[1]),
    ] {
        assert!(
            (d - q).abs().to_degrees() < 0.5,
            "loaded {name} angle {:.3} vs quasi-static {:.3} deg",
            d.to_degrees(),
            q.to_degrees()
        );
    }
    eprintln!(
        "cage {:.3} rad/s, epicyclic (loaded balls) {:.3} rad/s, slip {:.3} %, loaded angles {:.2} / {:.2} deg (quasi-static {:.2} / {:.2})",
        s.mean_cage_speed,
        s.epicyclic_cage_speed,
        100.0 * s.cage_slip,
        s.loaded_contact_angles[0].to_degrees(),
        s.loaded_contact_angles[1].to_degrees(),
        qs_angles[0].to_degrees(),
        qs_angles[1].to_degrees()
    );
}

/// Relative changes of the mean cage speed and of the pedestal Z band RMS (< 20 kHz, over the
/// steady window) when the Table-1 scene of `case` is run under the paper's model at the
/// default solver settings (rk4_fsal, rtol = atol = 1e-5) and 10 times tighter: each the
/// mean of `runs` runs whose tolerances are 1 + 1e-3 j times those. One pair of runs
/// measured the chaos as much as the tolerance: on the compound case, runs 1e-3 apart in
/// tolerance scatter by 0.3-0.5 % in that band RMS (six runs each of two builds,
/// 2026-11-30), and on 2026-11-30 a rounding-level change of the engine made the single
/// pair read 1.01 %, failing the 1 % limit (a second redesign for scatter: these tests
/// moved to the paper's model for it first). Five runs a side bring the difference's
/// standard error to about 0.3 %, a third of the limit. Under the preset's rheology law
/// the runs scatter further (a 1e-8 change of the axial load moves the inner fault's band
/// RMS by 2 %), so it is not measured there (docs/lab/benchmarks.md, "The default law's
/// runs scatter").
fn tolerance_changes(case: FaultCase, runs: usize) -> (f64, f64) {
    let default = paper_model(fault_case_scene("h7005c", case).unwrap());
    let mean_of = |base: &Scene, scale: f64| {
        let (mut cage, mut rms, mut steps) = (0.0, 0.0, 0);
        for j in 0..runs {
            let mut s = base.clone();
            let k = scale * (1.0 + 1e-3 * j as f64);
            s.solver.rtol *= k;
            s.solver.atol *= k;
            let r = run(&s);
            cage += r.summary.mean_cage_speed;
            rms += steady_band_rms(&r, "outer_ring_accel_z", 20e3).unwrap();
            steps += r.summary.stats.accepted_steps;
        }
        let n = runs as f64;
        (cage / n, rms / n, steps / runs as u64)
    };
    let (ca, ra, sa) = mean_of(&default, 1.0);
    let (cb, rb, sb) = mean_of(&default, 0.1);
    let dc = (ca - cb).abs() / cb;
    let dr = (ra - rb).abs() / rb;
    eprintln!(
        "{case:?}: mean cage speed {ca:.4} vs {cb:.4} rad/s ({dc:.1e}), \
         mean RMS(<20 kHz) {ra:.4} vs {rb:.4} m/s^2 ({dr:.1e}), mean steps {sa} vs {sb}"
    );
    (dc, dr)
}

/// Runs a side in [`tolerance_changes`] where the band RMS is asserted.
const TOLERANCE_RUNS: usize = 5;

// Tightening the default tolerance 10x (issues 2 and 10): the Table-1 scene (1000 -> 10000
// rpm in 0.1 s, 0.5 s, averages over 0.2-0.5 s: ~21 cage revolutions, ~340 outer-defect
// passes). The brief's limits are 0.01 % on the mean cage speed and 1 % on the band RMS.
// Measured 2026-11-21 with the former default (rk4_adaptive, 1e-6 against 1e-7): cage speed
// changes of 3e-7 to 6e-7, RMS changes of 0.07 % (inner), 0.41 % (outer) and 0.28 %
// (compound); `rk4_fsal`'s (the paper's model's default since) are in docs/lab/benchmarks.md.
// Means of five runs a side, 2026-11-30 (`rk4_fsal`): cage speed changes of 1.2e-7 to
// 2.0e-6, RMS changes of 0.32 % (inner), 0.03 % (outer) and 0.09 % (compound).

#[test]
fn tighter_tolerance_changes_little_inner_fault() {
    let (dc, dr) = tolerance_changes(FaultCase::Inner, TOLERANCE_RUNS);
    assert!(dc < 1e-4, "mean cage speed changed by {dc:.2e}");
    assert!(dr < 1e-2, "band RMS changed by {dr:.2e}");
}

#[test]
fn tighter_tolerance_changes_little_outer_fault() {
    let (dc, dr) = tolerance_changes(FaultCase::Outer, TOLERANCE_RUNS);
    assert!(dc < 1e-4, "mean cage speed changed by {dc:.2e}");
    assert!(dr < 1e-2, "band RMS changed by {dr:.2e}");
}

#[test]
fn tighter_tolerance_changes_little_compound_fault() {
    let (dc, dr) = tolerance_changes(FaultCase::Compound, TOLERANCE_RUNS);
    assert!(dc < 1e-4, "mean cage speed changed by {dc:.2e}");
    assert!(dr < 1e-2, "band RMS changed by {dr:.2e}");
}

#[test]
fn tighter_tolerance_keeps_healthy_cage_speed() {
    // Healthy bearing: the mean cage speed converges like the faulted ones. Its band RMS
    // (~2.3 m/s^2, mostly the 4th ball-pass harmonic on the pedestal resonance plus lightly
    // loaded balls knocking in their pockets) is chaotic: 25 ms blocks scatter by ~4 %, and a
    // 1e-8 relative change of the axial load moves the 0.3 s RMS by ~1.6 %, as much as a
    // tolerance change does. It is printed here, not asserted (docs/lab/benchmarks.md).
    // The cage speed's limit is far above its change (1e-6), so one run a side does.
    let (dc, _) = tolerance_changes(FaultCase::None, 1);
    assert!(dc < 1e-4, "mean cage speed changed by {dc:.2e}");
}

#[test]
fn every_fault_case_runs_clean() {
    for case in [
        FaultCase::None,
        FaultCase::Inner,
        FaultCase::Outer,
        FaultCase::Compound,
    ] {
        let mut s = fault_case_scene("h7005c", case).unwrap();
        s.solver.duration = 0.02;
        let r = run(&s);
        for c in &r.channels.channels {
            assert!(
                c.data.iter().all(|v| v.is_finite()),
                "{case:?}: {} has non-finite samples",
                c.name
            );
        }
        let n = r.channels.get("outer_ring_accel_y").unwrap().data.len();
        // uniform sampling: floor(T fs) + 1 samples
        assert_eq!(n, (0.02 * s.solver.sample_rate).floor() as usize + 1);
        // every controlled method spends at least 4 evaluations per accepted step
        assert!(
            r.summary.stats.accepted_steps > 0
                && r.summary.stats.rhs_evaluations >= 4 * r.summary.stats.accepted_steps
        );
    }
}

#[test]
fn cancellation_stops_the_run() {
    use std::sync::atomic::AtomicBool;
    let flag = AtomicBool::new(true);
    let s = constant_speed(0.05, 1e-5);
    let err = simulate(
        &s.validated().unwrap(),
        RunControl {
            cancel: Some(&flag),
            progress: None,
        },
    )
    .unwrap_err();
    assert!(err.is_cancelled(), "{err}");
}

#[test]
fn progress_is_reported_up_to_one() {
    let mut last = 0.0;
    let mut calls = 0;
    let mut cb = |f: f64| {
        assert!(f >= last, "progress went back");
        last = f;
        calls += 1;
    };
    let mut s = constant_speed(0.01, 1e-5);
    s.solver.duration = 0.01;
    simulate(
        &s.validated().unwrap(),
        RunControl {
            cancel: None,
            progress: Some(&mut cb),
        },
    )
    .unwrap();
    assert_eq!(last, 1.0);
    assert!(calls >= 1);
}

/// Asking for a contact-load channel must not change the acceleration channels by a bit
/// (the recorder evaluates the same forces either way; `dynamics::rhs::tests` compares that
/// evaluation with the whole right-hand side at every fidelity level and cage guidance).
#[test]
fn acceleration_channels_do_not_depend_on_the_load_channel() {
    let mut s = fault_case_scene("h7005c", FaultCase::Compound).unwrap();
    s.solver.duration = 3e-3;
    s.solver.fidelity = Fidelity::QuasiStaticBalls;
    let accel_only = run(&s);
    s.outputs.contact_loads_ball = Some(0);
    let with_loads = run(&s);
    for name in ["outer_ring_accel_y", "outer_ring_accel_z"] {
        let a = &accel_only.channels.get(name).unwrap().data;
        let b = &with_loads.channels.get(name).unwrap().data;
        assert!(a.len() > 100, "{} samples", a.len());
        assert!(
            a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits()),
            "{name} differs"
        );
    }
}

/// `outputs.ball_pocket`: one ball's azimuth, its orbital speed less the cage's and its
/// place in its pocket. Asserted: the ball stays in its pocket (the offset within the
/// radial clearance, plus a contact penetration), its lead on the cage integrates to no
/// more than the pocket and the cage's own play allow, and it visits the whole orbit.
/// And the pattern the paper's model gives (named here, so a change of the preset's physics
/// does not move this test): the balls lag the cage through the load zone and run ahead of it
/// opposite, where they lie on the pocket's leading face, and the cage runs ahead of the
/// loaded balls' rolling (the summary's `cage_slip = 1 - cage / epicyclic` is -0.3 %;
/// docs/reference/model.md, "Cage motion in the summary"; the geometry of the offset is
/// checked exactly in `dynamics::rhs`'s unit tests).
#[test]
fn a_ball_runs_through_its_pocket_clearance_and_stays_in_it() {
    let mut s = paper_model(constant_speed(0.1, 1e-5));
    s.outputs.ball_pocket = Some(3);
    let r = run(&s);
    let ch = |name: &str| &r.channels.get(name).unwrap().data;
    let (az, lead, offset) = (
        ch("ball3_azimuth"),
        ch("ball3_cage_lead"),
        ch("ball3_pocket_offset"),
    );
    let fs = r.channels.sample_rate;
    // from 30 ms: past the start's transient (the steady window of a 0.1 s run starts at
    // 25 ms)
    let i0 = (0.03 * fs) as usize;
    let (az, lead, offset) = (&az[i0..], &lead[i0..], &offset[i0..]);
    let cage = &s.bearing.cage;
    let clearance = 0.5 * (cage.pocket_diameter - s.bearing.ball_diameter);
    // The pocket's Hertz contact is entered at the 0.8 um critical film; a few newtons on
    // the phenolic wall penetrate about a micrometre (measured: at most 1.2 um past the
    // clearance under the rheology law, 0.2 um under the curve). 5 um is 3 % of the
    // clearance.
    let worst = offset.iter().fold(0.0f64, |a, &o| a.max(o.abs()));
    assert!(
        worst <= clearance + 5e-6,
        "offset {worst:.3e} m against clearance {clearance:.3e} m"
    );
    // The lead integrates to the ball's turn relative to the cage: over the window, at the
    // pitch radius, at most the pocket's play (2 clearances) plus the cage centre's (the
    // land's diametral clearance) apart.
    let t = az.len() as f64 / fs;
    let pitch_radius =
        0.5 * 0.5 * (s.bearing.inner_groove_diameter + s.bearing.outer_groove_diameter);
    let mean_lead = lead.iter().sum::<f64>() / lead.len() as f64;
    let play = 2.0 * (clearance + 5e-6) + cage.land_clearance;
    assert!(
        mean_lead.abs() * pitch_radius * t <= play,
        "mean lead {mean_lead:.3e} rad/s over {t:.3} s"
    );
    // every 30 deg of the orbit visited
    let sector =
        |a: f64| (((a + std::f64::consts::PI) / std::f64::consts::TAU * 12.0) as usize).min(11);
    let mut seen = [false; 12];
    az.iter().for_each(|&a| seen[sector(a)] = true);
    assert!(seen.iter().all(|&x| x), "{seen:?}");
    let mean_in = |keep: &dyn Fn(f64) -> bool| {
        let v: Vec<f64> = az
            .iter()
            .zip(lead)
            .filter(|(a, _)| keep(a.abs()))
            .map(|(_, l)| *l)
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let load_zone = mean_in(&|a| a < 45f64.to_radians());
    let opposite = mean_in(&|a| a > 135f64.to_radians());
    eprintln!(
        "ball 3: lead {load_zone:.3} rad/s in the load zone, {opposite:.3} opposite, mean {mean_lead:.4}; offset up to {worst:.4e} m (clearance {clearance:.4e})"
    );
    assert!(
        load_zone < 0.0 && opposite > 0.0,
        "{load_zone} / {opposite}"
    );
    // from the far side of the orbit to the load zone (-180 to -100 deg, before the ball
    // enters it at about -90) the ball lies on its pocket's leading face: within 5 um of
    // the clearance (measured: 164-167 um of 167 um over the Table-1 scene's 0.2-0.5 s)
    let trailing_side = az
        .iter()
        .zip(offset)
        .filter(|(a, _)| **a < -100f64.to_radians())
        .fold(f64::INFINITY, |m, (_, &o)| m.min(o));
    eprintln!("ball 3: least offset from -180 to -100 deg {trailing_side:.4e} m");
    assert!(
        trailing_side > clearance - 5e-6,
        "{trailing_side:.3e} m: off the pocket's leading face before the load zone"
    );
}
