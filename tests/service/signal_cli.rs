//! `bearing-sim analyze` end to end: formats, bearing presets and files, JSON shape, errors.

use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_bearing-sim"))
}

const OR007: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/crates/bearing-core/tests/fixtures/cwru/cwru_or007c_0hp_12k_de.f32le"
);

/// `analyze FILE --fs FS --rpm 1796 --bearing BEARING` (the CWRU 12 kHz drive-end records
/// run at 1796 rpm) followed by `extra`.
fn analyze<'a>(file: &'a str, fs: &'a str, bearing: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "analyze",
        file,
        "--fs",
        fs,
        "--rpm",
        "1796",
        "--bearing",
        bearing,
    ];
    args.extend_from_slice(extra);
    args
}

fn run_ok(args: &[&str]) -> serde_json::Value {
    let out = bin().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

fn run_err(args: &[&str]) -> String {
    let out = bin().args(args).output().unwrap();
    assert!(!out.status.success());
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn analyze_f32le_with_preset_prints_the_report() {
    let r = run_ok(&analyze(OR007, "12000", "cwru6205", &["--levels", "4"]));
    assert_eq!(r["level_kurtosis"].as_array().unwrap().len(), 4);
    assert_eq!(r["n_samples"], 18000);
    let raw = r["raw"].as_array().unwrap();
    let names: Vec<&str> = raw.iter().map(|i| i["name"].as_str().unwrap()).collect();
    for n in ["BPFO", "BPFI", "FTF", "BSF", "2xBSF"] {
        assert!(names.contains(&n), "{n} missing");
    }
    let bpfo = raw
        .iter()
        .find(|i| i["name"] == "BPFO" && i["harmonic"] == 1)
        .unwrap();
    for key in [
        "theory_hz",
        "identified_hz",
        "error_pct",
        "prominence_db",
        "detected",
    ] {
        assert!(bpfo.get(key).is_some(), "{key} missing");
    }
    assert_eq!(bpfo["detected"], true);
    assert!(
        r["best_component"]["identifications"]
            .as_array()
            .unwrap()
            .len()
            >= 10
    );
    assert!(r["runner_up_component"]["level"].as_u64().unwrap() >= 1);
}

#[test]
fn csv_json_and_bearing_file_give_the_same_answer() {
    let dir = tempfile::tempdir().unwrap();
    let raw = std::fs::read(OR007).unwrap();
    let x: Vec<f32> = raw
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let x = &x[..6000];
    let csv = dir.path().join("s.csv");
    let text: String = std::iter::once("accel_g".to_string())
        .chain(x.iter().map(|v| format!("{v}")))
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(&csv, text).unwrap();
    let json = dir.path().join("s.json");
    std::fs::write(&json, serde_json::to_string(&x).unwrap()).unwrap();
    let bearing = dir.path().join("b.json");
    std::fs::write(
        &bearing,
        r#"{"ball_count": 9, "ball_diameter": 0.00794004, "pitch_diameter": 0.0390398, "contact_angle": 0.0}"#,
    )
    .unwrap();
    let a = run_ok(&analyze(csv.to_str().unwrap(), "12000", "cwru6205", &[]));
    let b = run_ok(&analyze(
        json.to_str().unwrap(),
        "12000",
        bearing.to_str().unwrap(),
        &[],
    ));
    // f32 printed with Rust's shortest round-trip formatting parses back exactly, and the
    // bearing file holds the preset's numbers (inch -> m, 6 significant figures) -> identical
    // identifications up to the geometry rounding (1e-6 relative).
    let fa = a["raw"][0]["identified_hz"].as_f64().unwrap();
    let fb = b["raw"][0]["identified_hz"].as_f64().unwrap();
    assert!(((fa - fb) / fa).abs() < 1e-6, "{fa} vs {fb}");
    assert_eq!(a["level_kurtosis"], b["level_kurtosis"]);
    // window and band options
    let w = run_ok(&analyze(
        json.to_str().unwrap(),
        "12000",
        "cwru6205",
        &[
            "--window",
            "0.1,0.4",
            "--band",
            "2000,5000",
            "--search-band-pct",
            "3",
        ],
    ));
    assert_eq!(w["n_samples"], 3600);
    assert_eq!(w["band"], serde_json::json!([2000.0, 5000.0]));
}

#[test]
fn errors_say_what_is_wrong_with_which_input() {
    let e = run_err(&analyze(OR007, "0", "cwru6205", &[]));
    assert!(e.contains("--fs"), "{e}");
    let e = run_err(&analyze(OR007, "12000", "nosuch", &[]));
    assert!(e.contains("--bearing") && e.contains("cwru6205"), "{e}");
    let e = run_err(&analyze("/nonexistent/x.f32le", "12000", "cwru6205", &[]));
    assert!(e.contains("/nonexistent/x.f32le"), "{e}");
    let e = run_err(&analyze(OR007, "12000", "cwru6205", &["--window", "0.5"]));
    assert!(e.contains("--window"), "{e}");
    let e = run_err(&analyze(OR007, "12000", "cwru6205", &["--window", "5,6"]));
    assert!(e.contains("window: starts at 5 s"), "{e}");
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "1\n2\nabc\n").unwrap();
    let e = run_err(&analyze(bad.to_str().unwrap(), "12000", "cwru6205", &[]));
    assert!(e.contains("line 3: 'abc' is not a number"), "{e}");
    let e = run_err(&analyze(
        bad.to_str().unwrap(),
        "12000",
        "cwru6205",
        &["--format", "xyz"],
    ));
    assert!(
        e.contains("--format") || e.contains("unknown format"),
        "{e}"
    );
    let short = dir.path().join("short.json");
    std::fs::write(&short, "[1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]").unwrap();
    let e = run_err(&analyze(short.to_str().unwrap(), "12000", "cwru6205", &[]));
    assert!(
        e.contains("12 samples is too short for 5 levels (need >= 64)"),
        "{e}"
    );
}
