//! The engine benchmarks as a user runs them (`bearing-sim bench ...`), on scenes short
//! enough for the test suite: they print their table, write their plot and refuse what the
//! scene validation refuses. (Their figures are in docs/lab/benchmarks.md; nothing is timed.)

use std::process::Command;

fn bench(args: &[&str]) -> (String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_bearing-sim"))
        .arg("bench")
        .args(args)
        .output()
        .expect("the binary runs");
    let (stdout, stderr) = (
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    );
    assert!(out.status.success(), "{args:?} failed: {stderr}");
    (stdout, stderr)
}

/// `bench work-precision` on the test suite's short scene (0.02 s, one tolerance, a loose
/// reference) with `methods` at `levels`, and `extra` arguments.
fn work_precision(methods: &str, levels: &str, extra: &[&str]) -> (String, String) {
    let mut args = vec![
        "work-precision",
        "--duration",
        "0.02",
        "--tolerances",
        "1e-4",
        "--reference",
        "1e-6",
        "--methods",
        methods,
        "--levels",
        levels,
    ];
    args.extend_from_slice(extra);
    bench(&args)
}

/// `bench args` fails before it runs anything, and its error names `flag`; returns the error.
fn refused(args: &[&str], flag: &str) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_bearing-sim"))
        .arg("bench")
        .args(args)
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        !out.status.success() && stderr.contains(flag),
        "{args:?}: {stderr}"
    );
    // nothing ran: no reference's progress line
    assert!(!stderr.contains("reference"), "{stderr}");
    stderr
}

/// Table rows (not the header or its rule) whose first cell is `method`.
fn rows<'a>(table: &'a str, method: &str) -> Vec<Vec<&'a str>> {
    table
        .lines()
        .filter(|l| l.starts_with("| "))
        .map(|l| {
            l.trim_matches('|')
                .split('|')
                .map(str::trim)
                .collect::<Vec<_>>()
        })
        .filter(|cells| cells[0] == method)
        .collect()
}

#[test]
fn work_precision_prints_every_method_and_level_and_plots_them() {
    let dir = std::env::temp_dir().join(format!("bearing-sim-wp-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let svg = dir.join("wp.svg");
    let (table, log) = work_precision(
        "rk4_fsal,rosenbrock_w",
        "full,concentric_cage",
        &["--svg", svg.to_str().unwrap()],
    );
    // reference and check, then each method at both levels
    assert_eq!(rows(&table, "reference: rk4_adaptive").len(), 1, "{table}");
    assert_eq!(rows(&table, "check: rk4_fixed").len(), 1, "{table}");
    let fsal = rows(&table, "rk4_fsal");
    let levels: Vec<&str> = fsal.iter().map(|r| r[1]).collect();
    assert_eq!(levels, ["full", "concentric_cage"], "{table}");
    let ros = rows(&table, "rosenbrock_w");
    let levels: Vec<&str> = ros.iter().map(|r| r[1]).collect();
    assert_eq!(levels, ["full", "concentric_cage"], "{table}\n{log}");
    // the reduced level costs fewer evaluations than full at the same tolerance
    let rhs = |r: &Vec<&str>| r[5].parse::<u64>().unwrap();
    assert!(rhs(&fsal[1]) < rhs(&fsal[0]), "{table}");
    let chart = std::fs::read_to_string(&svg).unwrap();
    assert!(chart.starts_with("<svg"));
    for label in [
        "rk4_fsal",
        "rk4_fsal, concentric_cage",
        "rosenbrock_w",
        "rosenbrock_w, concentric_cage",
        "BPFI error",
    ] {
        assert!(chart.contains(label), "{label} missing from the chart");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `--runs` reads ensembles: each row is the mean of its runs (each from another initial
/// step, so another step sequence), with the standard errors of the cage speed and the band
/// RMS beside it; a count outside 1-9 is refused, naming the flag, before anything runs.
#[test]
fn work_precision_reads_ensembles_with_runs() {
    let (table, _) = work_precision("rk4_fsal", "full", &["--runs", "2"]);
    let header = table.lines().find(|l| l.starts_with("| method")).unwrap();
    assert!(
        header.contains("mean RHS evaluations") && header.contains("band RMS s.e."),
        "{table}"
    );
    for method in ["reference: rk4_adaptive", "check: rk4_fixed", "rk4_fsal"] {
        let r = rows(&table, method);
        assert_eq!(r.len(), 1, "{table}");
        assert_eq!(r[0].len(), 12, "{table}");
        // two step sequences give two band RMS readings: a standard error, neither 0 nor NaN
        let se: f64 = r[0][11].parse().unwrap();
        assert!(se > 0.0 && se.is_finite(), "{method}: {table}");
    }
    refused(&["work-precision", "--runs", "0"], "--runs");
}

#[test]
fn fidelity_compares_each_level_with_full() {
    let (table, _) = bench(&[
        "fidelity",
        "--duration",
        "0.02",
        "--levels",
        "quasi_static_balls",
        "--strips",
        "3",
        "--quadratures",
        "equal_strips,gauss",
    ]);
    let full = rows(&table, "full");
    assert_eq!(full.len(), 1, "{table}");
    // the reference is the scene's default: the rheology law's 4 Gauss nodes
    assert_eq!((full[0][2], full[0][3]), ("4", "gauss"), "{table}");
    let qs = rows(&table, "quasi_static_balls");
    assert_eq!(qs.len(), 2, "{table}");
    assert_eq!(
        (qs[0][1], qs[0][2], qs[0][3]),
        ("auto_etd", "3", "equal_strips"),
        "{table}"
    );
    assert_eq!(qs[1][3], "gauss", "{table}");
}

#[test]
fn fidelity_refuses_an_unknown_quadrature_before_running() {
    let stderr = refused(
        &["fidelity", "--quadratures", "gauss,simpson"],
        "--quadratures",
    );
    assert!(stderr.contains("simpson"), "{stderr}");
}

/// `bench stiffness` prints, per state, each part's largest eigenvalues with RK4's stable
/// step on each (2.8 / |lambda|); at the preset's start the whole Jacobian's largest is the
/// balls' slip relaxation, which taking their velocity blocks out removes (the row below
/// it is then smaller); a time outside 0-10 s or a count outside 1-50 is refused by name.
#[test]
fn stiffness_prints_each_part_at_each_state() {
    let (table, _) = bench(&["stiffness", "--fault", "none", "--at", "0", "--count", "2"]);
    let magnitude = |part: &str| -> Vec<f64> {
        rows(&table, part)
            .iter()
            .map(|cells| {
                let (m, step): (f64, f64) = (cells[3].parse().unwrap(), cells[4].parse().unwrap());
                // the printed step is 2.8 / |lambda| to the three figures printed
                assert!((step * m / 2.8 - 1.0).abs() < 0.01, "{cells:?}");
                m
            })
            .collect()
    };
    let whole = magnitude("nothing");
    let velocities_out = magnitude("each ball's velocity block");
    assert_eq!(whole.len(), 2, "{table}");
    assert_eq!(velocities_out.len(), 2, "{table}");
    assert_eq!(magnitude("every body's block").len(), 2, "{table}");
    assert!(
        whole[0] >= whole[1] && velocities_out[0] < whole[0],
        "{table}"
    );

    for (arg, says) in [
        ("--at=-1", "--at: times from 0 to 10 s (got -1)"),
        ("--at=11", "--at: times from 0 to 10 s (got 11)"),
        ("--count=0", "--count: 1 to 50 eigenvalues (got 0)"),
    ] {
        refused(&["stiffness", arg], says);
    }

    // the scene's --duration is not read (--at gives the times), so the help does not
    // offer it; the other benches that share the scene flags still do
    let help = |what: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_bearing-sim"))
            .args(["bench", what, "--help"])
            .output()
            .unwrap();
        assert!(out.status.success());
        String::from_utf8(out.stdout).unwrap()
    };
    let stiffness = help("stiffness");
    assert!(
        stiffness.contains("--at") && !stiffness.contains("--duration"),
        "{stiffness}"
    );
    assert!(help("work-precision").contains("--duration"));
    // and not checked either: a duration the others would refuse changes nothing here
    let (zero, _) = bench(&[
        "stiffness",
        "--fault",
        "none",
        "--at",
        "0",
        "--count",
        "2",
        "--duration",
        "0",
    ]);
    assert_eq!(zero, table);
}

/// `bench cases --runs 2` on a 5 ms run: each case's row once, its wall time the median of
/// its two rounds with their range (read back as three numbers in order; the median
/// itself is `median_and_range`'s, tested in `cli::bench`), the rounds' steps checked
/// equal by the bench itself; `--runs` out of range is refused before anything runs.
#[test]
fn cases_take_the_median_of_their_rounds() {
    let (table, log) = bench(&["cases", "--duration", "0.005", "--runs", "2"]);
    assert_eq!(log.matches("round ").count(), 2, "{log}");
    for case in ["None", "Inner", "Outer", "Compound"] {
        let r = rows(&table, case);
        assert_eq!(r.len(), 1, "{table}");
        let wall: Vec<f64> = r[0][1]
            .split([' ', '(', ')', '-'])
            .filter(|p| !p.is_empty())
            .map(|p| p.parse().unwrap())
            .collect();
        assert_eq!(wall.len(), 3, "{table}");
        assert!(wall[1] <= wall[0] && wall[0] <= wall[2], "{table}");
        // accepted steps and evaluations (columns 2 and 4; 1 is the wall time)
        assert!(r[0][2].parse::<u64>().unwrap() > 0, "{table}");
        assert!(r[0][4].parse::<u64>().unwrap() > r[0][2].parse::<u64>().unwrap());
    }
    for runs in ["0", "16"] {
        let out = Command::new(env!("CARGO_BIN_EXE_bearing-sim"))
            .args(["bench", "cases", "--runs", runs])
            .output()
            .unwrap();
        let stderr = String::from_utf8(out.stderr).unwrap();
        assert!(!out.status.success(), "{stderr}");
        assert!(stderr.contains("--runs: must be 1 to 15"), "{stderr}");
        assert!(!stderr.contains("round"), "{stderr}");
    }
}
