//! Recordings the way labs keep them (issue 36): the CWRU IR007 excerpt as a CWRU-style
//! MAT-file (plain and compressed), a 16-bit PCM WAV, a float WAV and a two-column CSV with
//! a header, made by scripts/fixtures/make_recordings.py. `bearing-sim analyze` names the
//! inner race from each, the same files uploaded over HTTP give the same verdict,
//! `inspect` lists their channels, malformed files get errors naming the problem, and a
//! simulated compound run-up exported with its tachometer reads back as a measured one.

use crate::common::*;
use serde_json::Value;
use std::process::Command;

const DIR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/crates/bearing-core/tests/fixtures/recordings/"
);

fn fixture(name: &str) -> String {
    format!("{DIR}{name}")
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_bearing-sim"))
}

/// Run the binary; `Ok(stdout)` on success, `Err(stderr)` on a clean failure (exit 1: an
/// error message, never a panic's 101).
fn run(args: &[&str]) -> Result<String, String> {
    let out = bin().args(args).output().unwrap();
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    match out.status.code() {
        Some(0) => Ok(text(&out.stdout)),
        Some(1) => Err(text(&out.stderr)),
        c => panic!("exit {c:?}: {}", text(&out.stderr)),
    }
}

/// Each fixture with what the command line must add: the channel and sample rate of the
/// MAT-files (CWRU's carry neither a single channel nor a rate; the shaft speed is in
/// X105RPM), the shaft speed of the others (their rate is in the header or time column).
const CASES: &[(&str, &[&str], &str)] = &[
    (
        "cwru_ir007.mat",
        &["--channel", "X105_DE_time", "--fs", "12000"],
        "channel=X105_DE_time&sample_rate=12000",
    ),
    (
        "cwru_ir007_compressed.mat",
        &["--channel", "0", "--fs", "12000"],
        "channel=0&sample_rate=12000",
    ),
    ("ir007_pcm16.wav", &["--rpm", "1797"], "shaft_rpm=1797"),
    ("ir007_float.wav", &["--rpm", "1797"], "shaft_rpm=1797"),
    (
        "ir007.csv",
        &["--channel", "accel", "--rpm", "1797"],
        "channel=accel&shaft_rpm=1797",
    ),
];

fn cli_verdict(file: &str, extra: &[&str]) -> Value {
    let path = fixture(file);
    let mut args = vec!["analyze", path.as_str(), "--bearing", "cwru6205"];
    args.extend_from_slice(extra);
    let out = run(&args).unwrap_or_else(|e| panic!("{file}: {e}"));
    let r: Value = serde_json::from_str(&out).unwrap();
    r["verdict"].clone()
}

/// The channel names of an `inspect --json` listing.
fn channel_names(listing: &Value) -> Vec<&str> {
    listing["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect()
}

fn faults(verdict: &Value) -> Vec<&str> {
    verdict["faults"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect()
}

#[test]
fn analyze_names_the_inner_race_from_every_format() {
    for (file, extra, _) in CASES {
        let v = cli_verdict(file, extra);
        assert_eq!(faults(&v), ["inner_race"], "{file}: {v}");
    }
}

#[test]
fn inspect_lists_the_channels_of_every_format() {
    for (file, names, rate) in [
        ("cwru_ir007.mat", vec!["X105_DE_time", "X105_FE_time"], None),
        (
            "cwru_ir007_compressed.mat",
            vec!["X105_DE_time", "X105_FE_time"],
            None,
        ),
        ("ir007_pcm16.wav", vec!["ch0"], Some(12000.0)),
        ("ir007_float.wav", vec!["ch0"], Some(12000.0)),
        ("ir007.csv", vec!["accel"], Some(12000.0)),
    ] {
        let out = run(&["inspect", &fixture(file), "--json"]).unwrap();
        let l: Value = serde_json::from_str(&out).unwrap();
        assert_eq!(channel_names(&l), names, "{file}");
        assert!(l["channels"]
            .as_array()
            .unwrap()
            .iter()
            .all(|c| c["samples"] == 12000));
        match rate {
            // the CSV's rate is the least-squares fit of times printed to 1e-8 s
            Some(r) => assert!(
                (l["sample_rate"]["value"].as_f64().unwrap() - r).abs() < 1e-6 * r,
                "{file}: {l}"
            ),
            None => assert!(l["sample_rate"].is_null(), "{file}: {l}"),
        }
        if file.ends_with(".mat") {
            assert_eq!(l["shaft_rpm"]["value"], 1797.0, "{file}");
            assert_eq!(l["shaft_rpm"]["from"], "variable X105RPM", "{file}");
        }
    }
    // the text listing, as a person reads it
    let text = run(&["inspect", &fixture("ir007.csv")]).unwrap();
    assert!(
        text.contains("0: accel  12000 samples") && text.contains("unit g"),
        "{text}"
    );
}

/// The malformed files of the issue, each as a path and the words its error must hold.
fn malformed(dir: &std::path::Path) -> Vec<(std::path::PathBuf, &'static str, &'static str)> {
    let mat = std::fs::read(fixture("cwru_ir007.mat")).unwrap();
    let cmat = std::fs::read(fixture("cwru_ir007_compressed.mat")).unwrap();
    let mut wav = std::fs::read(fixture("ir007_float.wav")).unwrap();
    // the data chunk's length doubled: the header claims 24000 samples, the file has 12000
    let at = wav.windows(4).position(|w| w == b"data").unwrap() + 4;
    let len = u32::from_le_bytes(wav[at..at + 4].try_into().unwrap());
    wav[at..at + 4].copy_from_slice(&(2 * len).to_le_bytes());
    let files: Vec<(&str, Vec<u8>, &str, &str)> = vec![
        (
            "cut.mat",
            mat[..mat.len() / 2].to_vec(),
            "file",
            "truncated",
        ),
        (
            "cut_compressed.mat",
            cmat[..cmat.len() / 2].to_vec(),
            "file",
            "truncated",
        ),
        ("lies.wav", wav, "file", "header declares 24000 samples"),
        (
            "ragged.csv",
            b"time,accel\n0,1\n0.001,2,3\n".to_vec(),
            "file",
            "line 3: 3 fields, the header has 2",
        ),
    ];
    files
        .into_iter()
        .map(|(name, bytes, field, words)| {
            let p = dir.join(name);
            std::fs::write(&p, bytes).unwrap();
            (p, field, words)
        })
        .collect()
}

#[test]
fn malformed_files_get_errors_naming_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    for (path, _, words) in malformed(dir.path()) {
        let p = path.to_str().unwrap();
        for args in [
            vec!["inspect", p],
            vec![
                "analyze",
                p,
                "--bearing",
                "cwru6205",
                "--fs",
                "12000",
                "--rpm",
                "1797",
            ],
        ] {
            let e = run(&args).expect_err(p);
            assert!(e.contains(words) && e.contains(p), "{args:?}: {e}");
        }
    }
    let mat = fixture("cwru_ir007.mat");
    let analyze = |extra: &[&str]| {
        let mut a = vec!["analyze", mat.as_str(), "--bearing", "cwru6205"];
        a.extend_from_slice(extra);
        run(&a).unwrap_err()
    };
    let e = analyze(&["--fs", "12000", "--channel", "X105_BA_time"]);
    assert!(
        e.contains("no channel 'X105_BA_time'")
            && e.contains("0: X105_DE_time, 1: X105_FE_time")
            && e.contains("--channel"),
        "{e}"
    );
    // two channels and none chosen: the choices, never a guess
    let e = analyze(&["--fs", "12000"]);
    assert!(
        e.contains("holds 2 channels") && e.contains("X105_FE_time"),
        "{e}"
    );
    // a MAT-file carries no sample rate: say how to give it
    let e = analyze(&["--channel", "0"]);
    assert!(e.contains("no sample rate") && e.contains("--fs"), "{e}");
    // a WAV's header rate and a different one on the command line
    let e = run(&[
        "analyze",
        &fixture("ir007_pcm16.wav"),
        "--bearing",
        "cwru6205",
        "--rpm",
        "1797",
        "--fs",
        "48000",
    ])
    .unwrap_err();
    assert!(e.contains("differs from the file's (12000 Hz"), "{e}");
}

async fn upload(
    c: &reqwest::Client,
    s: &TestApp,
    path: &str,
    file: &str,
    query: &str,
) -> (u16, reqwest::header::HeaderMap, Value) {
    let bytes = std::fs::read(fixture(file)).unwrap_or_else(|_| std::fs::read(file).unwrap());
    let name = std::path::Path::new(file)
        .file_name()
        .unwrap()
        .to_str()
        .unwrap();
    let r = c
        .post(s.url(&format!("{path}?filename={name}&{query}")))
        .header("content-type", "application/octet-stream")
        .body(bytes)
        .send()
        .await
        .unwrap();
    decode(r).await
}

#[tokio::test]
async fn uploads_over_http_give_the_command_lines_verdict() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "1"]);
    let c = client();
    for (file, cli_extra, query) in CASES {
        let cli = cli_verdict(file, cli_extra);
        let (st, _, r) = upload(
            &c,
            &s,
            "/v1/analyses",
            file,
            &format!("preset=cwru6205&{query}"),
        )
        .await;
        assert_eq!(st, 200, "{file}: {r}");
        let http = &r["analysis"]["verdict"];
        assert_eq!(faults(http), ["inner_race"], "{file}: {http}");
        // the same reader and analysis: the same numbers, not merely the same names
        assert_eq!(http["evidence"], cli["evidence"], "{file}");
        // the listing the page shows before it uploads
        let (st, _, l) = upload(&c, &s, "/v1/recordings/inspect", file, "").await;
        assert_eq!(st, 200, "{file}: {l}");
        assert!(!l["channels"].as_array().unwrap().is_empty());
    }
    // queued, the job keeps the file's name
    let (st, _, job) = upload(
        &c,
        &s,
        "/v1/analyses",
        "ir007_float.wav",
        "preset=cwru6205&shaft_rpm=1797&mode=async",
    )
    .await;
    assert_eq!(st, 202, "{job}");
    assert_eq!(job["label"], "ir007_float.wav", "{job}");
}

#[tokio::test]
async fn malformed_uploads_are_problems_naming_the_field() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "0", "--max-body-bytes", "150000"]);
    let c = client();
    let dir = tempfile::tempdir().unwrap();
    for (path, field, words) in malformed(dir.path()) {
        let p = path.to_str().unwrap();
        for route in ["/v1/recordings/inspect", "/v1/analyses"] {
            let (st, h, problem) = upload(
                &c,
                &s,
                route,
                p,
                "preset=cwru6205&shaft_rpm=1797&sample_rate=12000",
            )
            .await;
            assert_problem(st, &h, &problem, 422);
            assert_eq!(problem["errors"][0]["path"], field, "{p}: {problem}");
            let m = problem["errors"][0]["message"].as_str().unwrap();
            assert!(m.contains(words), "{p}: {m}");
        }
    }
    let q = "preset=cwru6205&sample_rate=12000";
    for (query, field, words) in [
        (
            "channel=X105_BA_time",
            "channel",
            "no channel 'X105_BA_time'",
        ),
        ("", "channel", "holds 2 channels"),
        ("channel=0&sample_rate=48000", "sample_rate", ""),
        ("channel=0&format=riff", "format", "unknown format 'riff'"),
        (
            "channel=0&tacho_channel=1",
            "tacho_channel",
            "not yet analysed over HTTP",
        ),
    ] {
        let query = if query.contains("sample_rate") {
            format!("preset=cwru6205&{query}")
        } else {
            format!("{q}&{query}")
        };
        let (st, h, problem) =
            upload(&c, &s, "/v1/analyses", "cwru_ir007_compressed.mat", &query).await;
        if field == "sample_rate" {
            // a MAT-file without fs takes the rate given: this one is fine (and queued
            // for want of workers, or answered); only its absence is a problem
            assert!(st == 200 || st == 202, "{problem}");
            continue;
        }
        assert_problem(st, &h, &problem, 422);
        assert_eq!(problem["errors"][0]["path"], field, "{query}: {problem}");
        assert!(
            problem["errors"][0]["message"]
                .as_str()
                .unwrap()
                .contains(words),
            "{problem}"
        );
    }
    // limits: a body over the limit is a 413; a file whose samples exceed what the body
    // limit allows (half its bytes: 8-bit PCM holds one sample a byte) is a 422 on samples
    let (st, h, problem) = upload(&c, &s, "/v1/recordings/inspect", "cwru_ir007.mat", "").await;
    assert_problem(st, &h, &problem, 413);
    let n = 100_000u32;
    let mut wav = Vec::new();
    wav.extend_from_slice(b"RIFF");
    wav.extend_from_slice(&(36 + n).to_le_bytes());
    wav.extend_from_slice(b"WAVEfmt ");
    wav.extend_from_slice(&16u32.to_le_bytes());
    for v in [1u16, 1] {
        wav.extend_from_slice(&v.to_le_bytes()); // PCM, mono
    }
    wav.extend_from_slice(&8000u32.to_le_bytes());
    wav.extend_from_slice(&8000u32.to_le_bytes());
    wav.extend_from_slice(&1u16.to_le_bytes());
    wav.extend_from_slice(&8u16.to_le_bytes());
    wav.extend_from_slice(b"data");
    wav.extend_from_slice(&n.to_le_bytes());
    wav.extend((0..n).map(|k| 128 + (k % 50) as u8));
    let p = dir.path().join("long8bit.wav");
    std::fs::write(&p, wav).unwrap();
    let (st, h, problem) = upload(&c, &s, "/v1/recordings/inspect", p.to_str().unwrap(), "").await;
    assert_problem(st, &h, &problem, 422);
    assert_eq!(problem["errors"][0]["path"], "samples", "{problem}");
}

/// The Table-1 compound scene is a run-up (1000 to 10000 rpm over its first 0.1 s, then
/// 0.4 s steady): simulated and exported with its tachometer as a MAT-file, then analysed
/// as a measured recording over the whole record, the shaft angle taken only from the
/// tachometer channel (order tracked), the verdict must name both races. (A record that is
/// all ramp, 1000 to 10000 rpm over 0.2 s, is order tracked too but the verdict does not
/// reach both races there yet: issue 35, docs/lab/cwru.md.)
#[test]
fn an_exported_compound_run_up_reads_back_as_a_measured_recording() {
    let dir = tempfile::tempdir().unwrap();
    let mat = dir.path().join("run_up.mat");
    let out = dir.path().join("run_up_result.json");
    let (mat_s, out_s) = (mat.to_str().unwrap(), out.to_str().unwrap());
    run(&[
        "run", "h7005c", "--fault", "compound", "--out", out_s, "--export", mat_s,
    ])
    .unwrap();
    let listing: Value =
        serde_json::from_str(&run(&["inspect", mat_s, "--json"]).unwrap()).unwrap();
    assert_eq!(
        channel_names(&listing),
        [
            "outer_ring_accel_y",
            "outer_ring_accel_z",
            "shaft_angle",
            "tachometer"
        ]
    );
    assert_eq!(listing["sample_rate"]["value"], 102400.0, "{listing}");
    let report = run(&[
        "analyze",
        mat_s,
        "--channel",
        "outer_ring_accel_z",
        "--tacho-channel",
        "tachometer",
        "--bearing",
        "h7005c",
    ])
    .unwrap();
    let r: Value = serde_json::from_str(&report).unwrap();
    assert!(r["order_tracking"].is_object(), "not order tracked: {r}");
    // the tachometer's speed range spans the ramp: from its first whole revolution's mean
    // (4100 rpm measured; the ramp passes 5500 rpm at 0.05 s) to the steady 10000 rpm
    // within 1 % (pulse edges are placed to a fraction of a sample at 102.4 kHz)
    let range = &r["order_tracking"]["shaft_hz_range"];
    assert!(range[0].as_f64().unwrap() * 60.0 < 5500.0, "{range}");
    assert!(
        (range[1].as_f64().unwrap() * 60.0 - 10000.0).abs() < 100.0,
        "{range}"
    );
    let mut f = faults(&r["verdict"]);
    f.sort();
    assert_eq!(f, ["inner_race", "outer_race"], "{}", r["verdict"]);
}

/// `GET /v1/simulations/{id}/recording`: a finished run as a recording file in each
/// format, which reads back through the same reader with the run's channels, its shaft
/// angle and tachometer, and its sample rate.
#[tokio::test]
async fn a_finished_run_downloads_as_a_recording() {
    use bearing_core::signal::recording::{read_recording, RecordingFormat, RecordingLimits};
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "1"]);
    let c = client();
    let id = submit(&c, &s, &steady_scene(0.02)).await;
    let job = wait_finished(&c, &s, &id, std::time::Duration::from_secs(120)).await;
    assert_eq!(job["state"], "succeeded", "{job}");
    let url = |q: &str| s.url(&format!("/v1/simulations/{id}/recording?{q}"));
    for (f, format, media) in [
        ("wav", RecordingFormat::Wav, "audio/wav"),
        ("csv", RecordingFormat::Csv, "text/csv"),
        ("mat", RecordingFormat::Mat, "application/x-matlab-data"),
    ] {
        let r = c.get(url(&format!("format={f}"))).send().await.unwrap();
        assert_eq!(r.status(), 200, "{f}");
        assert_eq!(r.headers()["content-type"], media);
        let bytes = r.bytes().await.unwrap();
        let rec = read_recording(&bytes, format, f, &RecordingLimits::LOCAL).unwrap();
        let names: Vec<&str> = rec.channels.iter().map(|c| c.name.as_str()).collect();
        let last = &names[names.len() - 2..];
        if f == "wav" {
            assert_eq!(names.len(), 4, "{names:?}"); // y, z, angle, tachometer; no names in WAV
        } else {
            assert_eq!(last, ["shaft_angle", "tachometer"], "{f}");
            assert!(names.contains(&"outer_ring_accel_z"), "{names:?}");
        }
        let fs = rec.sample_rate.unwrap().value;
        assert!((fs - 102_400.0).abs() < 1e-3, "{f}: {fs}");
        // the tachometer pulses once a revolution: its rising edges are a revolution apart
        let tach = &rec.channels[names.len() - 1].samples;
        let edges = tach
            .windows(2)
            .filter(|w| w[0] < 2.5 && w[1] >= 2.5)
            .count();
        let angle = &rec.channels[names.len() - 2].samples;
        let turns = (angle[angle.len() - 1] - angle[0]) / std::f64::consts::TAU;
        assert!(
            (edges as f64 - turns).abs() <= 1.0,
            "{f}: {edges} edges, {turns} turns"
        );
    }
    let r = c.get(url("format=tdms")).send().await.unwrap();
    let (st, h, problem) = decode(r).await;
    assert_problem(st, &h, &problem, 400);
}
