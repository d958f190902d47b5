//! The stability stress suite (issue 10, `bearing_core::stress`): every extreme scene for a
//! few milliseconds, its invariants checked, or its refusal and the field it names.
//! `bearing-sim bench stress` runs the same catalogue longer.
//!
//! One test per scene, so the harness runs them side by side and a failure names its scene;
//! `every_scene_has_a_test` keeps this list and the catalogue in step.

use bearing_core::stress::{
    catalogue, rhs_per_second, run_case, verdict, Outcome, StressScene, REFERENCE,
};
use std::sync::OnceLock;

fn case(name: &str) -> StressScene {
    catalogue()
        .into_iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no stress scene {name}"))
}

/// RHS evaluations per simulated second of the reference scene at its test duration, run
/// once for all the tests of this binary.
fn reference() -> f64 {
    static REF: OnceLock<f64> = OnceLock::new();
    *REF.get_or_init(|| {
        let c = case(REFERENCE);
        match run_case(&c, c.test_duration, None) {
            Outcome::Ran { result, violations } => {
                assert!(violations.is_empty(), "reference: {violations:?}");
                rhs_per_second(&result)
            }
            other => panic!("the reference scene must run: {other:?}"),
        }
    })
}

fn stress(name: &str) {
    let c = case(name);
    let reference = reference();
    let outcome = run_case(&c, c.test_duration, Some(reference));
    match &outcome {
        Outcome::Ran { result, .. } => {
            let s = &result.summary;
            eprintln!(
                "{name}: {} RHS ({:.2}x the reference per simulated second), steps {:.1e}..{:.1e} s, cage {:.3} of shaft, reaction {:?} N",
                s.stats.rhs_evaluations,
                rhs_per_second(result) / reference,
                s.stats.min_step,
                s.stats.max_step,
                s.mean_cage_speed / s.mean_shaft_speed,
                s.mean_inner_ring_reaction
            );
        }
        Outcome::Refused(e) => eprintln!("{name}: refused: {e}"),
        Outcome::Failed(e) => eprintln!("{name}: failed: {e}"),
    }
    if let Err(why) = verdict(&c, &outcome) {
        panic!("stress scene {name} ({}): {why}", c.stresses);
    }
}

macro_rules! stress_tests {
    ($($name:ident),* $(,)?) => {
        $(
            #[test]
            fn $name() {
                stress(stringify!($name));
            }
        )*
        const TESTED: &[&str] = &[$(stringify!($name)),*];
    };
}

stress_tests!(
    table1_steady,
    near_zero_speed,
    limit_speed,
    limit_speed_paper_curve,
    limit_speed_auto,
    above_speed_limit,
    near_zero_load,
    zero_load,
    pure_axial,
    pure_radial,
    ten_times_load,
    micro_defect,
    wide_defect,
    defect_wider_than_ball_spacing,
    many_defects,
    too_many_defects,
    near_dry,
    paper_curve,
    ten_times_load_paper_curve,
    very_viscous,
    from_rest,
    fast_ramp,
    fast_ramp_auto,
    fast_ramp_paper_curve,
    long_run,
    too_long_run,
    fine_output,
    too_fine_output,
    quasi_static_balls,
    concentric_cage,
    reduced_fidelity_implicit,
);

#[test]
fn every_scene_has_a_test() {
    let names: Vec<&str> = catalogue().iter().map(|c| c.name).collect();
    assert_eq!(names, TESTED, "the catalogue and this file's tests differ");
}
