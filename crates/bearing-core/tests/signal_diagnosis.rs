//! The verdict on short simulated runs, through the code the service uses
//! (`simulation_analysis::diagnose_run`): the H7005C preset at a constant 10000 rpm for
//! 0.1 s, the Table-1 scene (0.5 s with its ramp) and a compound run-up that is order
//! tracked. Each run is short (about a second of solver time in release).
//!
//! Asserted: what the verdict achieves (issue 35), under the preset's physics (the rheology
//! law with rolling resistance, the default since 2026-11-29, and the preset's integrator:
//! `auto_slip` until 2026-11-30, `auto_etd` since; the assertions hold under both). There the
//! cage's lag puts each race's harmonics on the other race's ball-return comb, whose higher
//! orders the race accepted first takes only where they rank as a family
//! (docs/lab/cwru.md, "The ball-return comb").
//!
//! The same scenes under the paper's model (its eq. 15 curve, no rolling resistance,
//! `rk4_fsal`: the default until then) are asserted too, but one: printed, not asserted,
//! because the verdict does not reach it there (docs/lab/cwru.md, "Short simulated runs"),
//! the healthy Table-1 scene, whose bearing strikes once per ball pass at a fixed place (a
//! ball that has left the load zone catching its pocket's leading face about 155 deg from
//! the load line: a burst in the 12.8-25.6 kHz band at every BPFO period, also at rtol
//! 1e-7) and reads outer race. The same strike is in the healthy 0.1 s scene, where it
//! passes the verdict's threshold in some runs and not others: asserted as a rate over 31
//! runs. (Under the preset's physics the healthy 0.1 s scene read no fault in 31 of 31
//! such runs, 2026-11-30, so it stays one run there.)

use bearing_core::scene::{
    fault_case_scene, FaultCase, Integrator, RollingResistanceModel, Scene, Traction,
};
use bearing_core::signal::verdict::{FaultType, Verdict};
use bearing_core::simulation::{simulate, RunControl};
use bearing_core::simulation_analysis::diagnose_run;

fn constant_speed(case: FaultCase, duration: f64) -> Scene {
    let mut s = fault_case_scene("h7005c", case).unwrap();
    s.operating.speed.initial_rpm = 10_000.0;
    s.operating.speed.steady_rpm = 10_000.0;
    s.operating.speed.ramp_time = 0.0;
    s.solver.duration = duration;
    s
}

/// `s` under the paper's model: its eq. 15 curve, no rolling resistance, `rk4_fsal` (the
/// preset's until 2026-11-29).
fn paper_model(mut s: Scene) -> Scene {
    s.lubricant.traction = Traction::PAPER_CURVE;
    s.lubricant.rolling_resistance = RollingResistanceModel::None;
    s.solver.integrator = Integrator::Rk4Fsal;
    s
}

/// The fault types a scene of `case` must read, in [`FaultType::ALL`] order.
fn truth(case: FaultCase) -> Vec<FaultType> {
    match case {
        FaultCase::None => vec![],
        FaultCase::Inner => vec![FaultType::InnerRace],
        FaultCase::Outer => vec![FaultType::OuterRace],
        FaultCase::Compound => vec![FaultType::OuterRace, FaultType::InnerRace],
    }
}

struct Diagnosis {
    faults: Vec<FaultType>,
    verdict: Verdict,
    order_tracked: bool,
}

fn diagnose(scene: &Scene) -> Diagnosis {
    let run = simulate(&scene.validated().unwrap(), RunControl::default()).unwrap();
    let (_, _, out) = diagnose_run(&run, scene).unwrap();
    let r = &out.report;
    // one notion of "found": a line shown as found either counts toward the verdict or
    // says why not
    for id in r
        .raw
        .iter()
        .chain(&r.best_component.identifications)
        .chain(&r.runner_up_component.identifications)
    {
        assert!(
            !id.detected || id.in_verdict || id.not_counted.is_some(),
            "{}: {id:?}",
            scene.name
        );
    }
    let verdict = out.report.verdict.unwrap();
    eprintln!("{}: {}", scene.name, verdict.summary);
    let mut faults = verdict.faults.clone();
    faults.sort_by_key(|f| FaultType::ALL.iter().position(|g| g == f));
    Diagnosis {
        faults,
        verdict,
        order_tracked: out.report.order_tracking.is_some(),
    }
}

/// Measured 2026-11-29 (inner / outer race p): inner 3.8e-7, outer 9.5e-5, compound
/// 1.2e-4 / 2.0e-4, healthy none. Before the ball-return comb was limited to its first two
/// orders, the compound run read the inner race only (outer p 2.1e-2).
#[test]
fn short_constant_speed_runs_read_their_fault() {
    for case in [FaultCase::Inner, FaultCase::Outer, FaultCase::None] {
        let want = truth(case);
        let d = diagnose(&constant_speed(case, 0.1));
        assert_eq!(d.faults, want, "{case:?}: {}", d.verdict.summary);
        assert!(!d.order_tracked, "constant speed needs no order tracking");
        // the sentence says what the verdict says
        assert_eq!(
            d.verdict.summary.starts_with("No fault indicated"),
            want.is_empty(),
            "{}",
            d.verdict.summary
        );
    }
    // the compound run names both races: neither race's lines take the other's harmonics
    let d = diagnose(&constant_speed(FaultCase::Compound, 0.1));
    assert_eq!(
        d.faults,
        truth(FaultCase::Compound),
        "{}",
        d.verdict.summary
    );
}

/// Measured 2026-11-29: compound 7.2e-8 / 1.3e-5; healthy none (closest outer race,
/// p = 0.28).
#[test]
fn table_1_scenes_read_their_faults() {
    let d = diagnose(&fault_case_scene("h7005c", FaultCase::Compound).unwrap());
    assert_eq!(d.faults, truth(FaultCase::Compound));
    let d = diagnose(&fault_case_scene("h7005c", FaultCase::None).unwrap());
    assert_eq!(d.faults, truth(FaultCase::None), "{}", d.verdict.summary);
}

/// The compound fault run up from 1000 to 10000 rpm over the whole 0.2 s of `s`.
fn run_up(mut s: Scene) -> Scene {
    s.operating.speed.initial_rpm = 1_000.0;
    s.operating.speed.steady_rpm = 10_000.0;
    s.operating.speed.ramp_time = 0.2;
    s.solver.duration = 0.2;
    s
}

#[test]
fn a_run_up_is_order_tracked_and_says_so() {
    let d = diagnose(&run_up(
        fault_case_scene("h7005c", FaultCase::Compound).unwrap(),
    ));
    // the steady window [0.1, 0.2] s lies in the ramp (5500 -> 10000 rpm): never analysed
    // as steady without saying so
    assert!(d.order_tracked);
    assert!(
        d.verdict.summary.contains("order tracked"),
        "{}",
        d.verdict.summary
    );
    // both races over the 12.9 revolutions of the window (measured 2026-11-29: inner
    // 3.4e-4, outer 6.5e-5; inner p = 1 before the ball-return comb was limited); 4xBPFO
    // (27.1 orders) and 4xBPFI (37.0) are not resolved from shaft orders there and give
    // way to the next harmonics
    assert_eq!(
        d.faults,
        truth(FaultCase::Compound),
        "{}",
        d.verdict.summary
    );
}

/// Every scene above under the paper's model, but the healthy Table-1 scene, printed for
/// the record (it reads outer race: the module's comment). Measured 2026-11-29 (the
/// fifteenth session's code, then the default): 0.1 s compound inner 4.4e-5 and outer
/// 1.2e-4, the run-up outer 1.4e-4.
///
/// The healthy 0.1 s scene is read as a small ensemble, not as one run: its bearing strikes
/// once per ball pass at a fixed place (the module's comment), and over 0.1 s that line at
/// BPFO sometimes passes the verdict's threshold. Measured 2026-11-30 over 31 runs with the
/// tolerance scaled by 1 + 0.0007 k (k = -15..15): 6 read outer race (p 9.5e-5 to 9.1e-4)
/// with libm's sine, 3 with the lanes' (the azimuths moved at rounding level, and the one
/// run this test took, k = 0, went from p = 0.66 to an outer-race read at p = 5.1e-4). So
/// the 31 runs must read no fault in at least two of three, and nothing but the outer race
/// where they read one. The bound is a guard against the verdict losing its specificity,
/// not a measure of the rate: binomially, at the pooled 15 % (9 of 62) more than 10 of 31
/// comes once in about 250 draws, at the libm runs' 19 % once in 43; a rate of 30 % passes
/// 69 % of the time, one of 40 % a quarter.
#[test]
fn under_the_papers_model_every_scene_but_one_reads_its_faults() {
    for case in [FaultCase::Inner, FaultCase::Outer, FaultCase::Compound] {
        let d = diagnose(&paper_model(constant_speed(case, 0.1)));
        assert_eq!(
            d.faults,
            truth(case),
            "0.1 s {case:?}: {}",
            d.verdict.summary
        );
    }
    let mut read_a_fault = 0;
    for k in -15..=15 {
        let mut s = paper_model(constant_speed(FaultCase::None, 0.1));
        s.solver.rtol *= 1.0 + 0.0007 * f64::from(k);
        let d = diagnose(&s);
        if !d.faults.is_empty() {
            read_a_fault += 1;
            assert_eq!(
                d.faults,
                [FaultType::OuterRace],
                "0.1 s healthy, k = {k}: {}",
                d.verdict.summary
            );
        }
    }
    eprintln!("{read_a_fault} of 31 healthy runs read a fault");
    assert!(
        read_a_fault <= 10,
        "{read_a_fault} of 31 healthy runs read a fault"
    );
    let d = diagnose(&paper_model(
        fault_case_scene("h7005c", FaultCase::Compound).unwrap(),
    ));
    assert_eq!(
        d.faults,
        truth(FaultCase::Compound),
        "Table-1 compound: {}",
        d.verdict.summary
    );
    diagnose(&paper_model(
        fault_case_scene("h7005c", FaultCase::None).unwrap(),
    ));
    let d = diagnose(&run_up(paper_model(
        fault_case_scene("h7005c", FaultCase::Compound).unwrap(),
    )));
    assert!(d.order_tracked);
    assert_eq!(
        d.faults,
        truth(FaultCase::Compound),
        "run-up: {}",
        d.verdict.summary
    );
}
