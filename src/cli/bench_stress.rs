//! `bearing-sim bench stress`: the stability stress suite (`bearing_core::stress`) at bench
//! durations, as a markdown table: outcome, invariants, solver cost against the reference
//! scene, wall time. Exits with an error when any scene does not do what it is expected to.

use super::result::CliResult;
use bearing_core::stress::{catalogue, rhs_per_second, run_case, verdict, Outcome, REFERENCE};

/// Run the catalogue (`only`: these scene names; empty for all) for `duration` s each, the
/// scenes with a duration of their own (the 5 s long run) for theirs unless `short` is set.
pub fn stress(duration: f64, only: &[String], short: bool) -> CliResult {
    let all = catalogue();
    if let Some(bad) = only
        .iter()
        .find(|n| !all.iter().any(|c| c.name == n.as_str()))
    {
        let names: Vec<&str> = all.iter().map(|c| c.name).collect();
        return Err(format!("--only: no stress scene {bad} (have {})", names.join(", ")).into());
    }
    let reference_case = all
        .iter()
        .find(|c| c.name == REFERENCE)
        .expect("the catalogue has its reference");
    eprintln!("reference: {REFERENCE}, {duration} s");
    let reference = match run_case(reference_case, duration, None) {
        Outcome::Ran { result, .. } => rhs_per_second(&result),
        other => return Err(format!("the reference scene did not run: {other:?}").into()),
    };
    println!("| scene | stresses | duration (s) | outcome | invariants | RHS per simulated s | vs reference | wall time (s) |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    let mut failed = Vec::new();
    for case in all
        .iter()
        .filter(|c| only.is_empty() || only.iter().any(|n| n == c.name))
    {
        let t = match case.bench_duration {
            Some(own) if !short => own,
            _ => duration,
        };
        eprintln!("{} ({t} s)", case.name);
        let outcome = run_case(case, t, Some(reference));
        let ok = verdict(case, &outcome);
        let (what, invariants, cost, ratio, wall) = match &outcome {
            Outcome::Ran { result, violations } => {
                let r = rhs_per_second(result);
                (
                    "ran".to_string(),
                    if violations.is_empty() {
                        "ok".to_string()
                    } else {
                        violations
                            .iter()
                            .map(|v| v.to_string())
                            .collect::<Vec<_>>()
                            .join("; ")
                    },
                    format!("{r:.3e}"),
                    format!("{:.2}", r / reference),
                    format!("{:.2}", result.summary.stats.wall_time),
                )
            }
            Outcome::Refused(e) => {
                let fields: Vec<&str> = e.0.iter().map(|f| f.path.as_str()).collect();
                (
                    format!("refused: {}", fields.join(", ")),
                    "-".into(),
                    "-".into(),
                    "-".into(),
                    "-".into(),
                )
            }
            Outcome::Failed(e) => (
                format!("failed: {e}"),
                "-".into(),
                "-".into(),
                "-".into(),
                "-".into(),
            ),
        };
        let invariants = match &ok {
            Ok(()) => invariants,
            Err(why) => format!("**unexpected**: {why}"),
        };
        // the scene's own duration (a refused run-length scene sets one of its own)
        let shown = case.scene(t).solver.duration;
        println!(
            "| {} | {} | {shown} | {what} | {invariants} | {cost} | {ratio} | {wall} |",
            case.name, case.stresses
        );
        if ok.is_err() {
            failed.push(case.name);
        }
    }
    if failed.is_empty() {
        Ok(())
    } else {
        Err(format!("stress scenes not as expected: {}", failed.join(", ")).into())
    }
}
