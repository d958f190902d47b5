//! `bearing-sim bench stiffness`: where the bearing's stiffness is at states of a run
//! (`bearing_core::stiffness`), as a markdown table per state: the largest eigenvalues of
//! the Jacobian, whole and with chosen diagonal blocks taken out, and the step RK4 is
//! stable at on each.

use super::bench_comparison::{comparison_scene, ComparisonArgs};
use super::result::CliResult;
use bearing_core::stiffness::{stiffness_at, Removed, RK4_STABILITY};

/// Print the `count` largest eigenvalues of each part at each time of `at` (s).
pub fn stiffness(on: &ComparisonArgs, at: &[f64], count: usize) -> CliResult {
    // a scene runs at most 10 s (`solver.duration`); the state at a time is reached by
    // running to it, whatever the scene's own duration
    if let Some(bad) = at
        .iter()
        .find(|t| !(t.is_finite() && (0.0..=10.0).contains(*t)))
    {
        return Err(format!("--at: times from 0 to 10 s (got {bad})").into());
    }
    if !(1..=50).contains(&count) {
        return Err(format!("--count: 1 to 50 eigenvalues (got {count})").into());
    }
    let mut scene = comparison_scene(on)?;
    // each state is reached by running to it, so the scene's own duration (the hidden
    // `--duration`) is not read and not checked: any valid one will do
    scene.solver.duration = at.iter().copied().fold(0.05, f64::max);
    let scene = scene.validated()?;
    for &t in at {
        let report = stiffness_at(&scene, t, count)?;
        println!(
            "State at t = {t} s ({} components):\n",
            report.jacobian.nrows()
        );
        println!("| taken out | rank | eigenvalue (1/s) | magnitude (1/s) | RK4 stable step (s) |");
        println!("| --- | --- | --- | --- | --- |");
        for part in &report.parts {
            let what = match part.removed {
                Removed::Nothing => "nothing",
                Removed::BallVelocities => "each ball's velocity block",
                Removed::Balls => "each ball's block",
                Removed::Bodies => "every body's block",
            };
            for (k, l) in part.largest.iter().enumerate() {
                println!(
                    "| {what} | {} | {:.3e} {:+.3e} i | {:.3e} | {:.2e} |",
                    k + 1,
                    l.re,
                    l.im,
                    l.norm(),
                    RK4_STABILITY / l.norm()
                );
            }
        }
        println!();
    }
    Ok(())
}
