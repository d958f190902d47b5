//! Simulations end to end through the service (needs the real engine).

use crate::common::*;
use serde_json::json;
use std::time::{Duration, Instant};

#[tokio::test]
async fn short_scene_runs_to_success_with_result_signals_and_spectra() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "2"]);
    let c = client();
    let id = submit(&c, &s, &steady_scene(0.03)).await;
    let job = wait_finished(&c, &s, &id, Duration::from_secs(120)).await;
    assert_eq!(job["state"], "succeeded", "{job}\n{}", s.log());
    assert_eq!(job["progress"], 1.0);
    assert_eq!(job["attempt"], 1);
    assert!(job["started_at"].is_string() && job["finished_at"].is_string());
    assert!(
        job["stats"]["accepted_steps"].as_u64().unwrap() > 0,
        "{job}"
    );

    let (st, _, result) = get_json(&c, &s.url(&format!("/v1/simulations/{id}/result"))).await;
    assert_eq!(st, 200, "{result}");
    assert!(result["solver"]["accepted_steps"].as_u64().unwrap() > 0);
    assert!(
        result["cage"]["mean_speed"].is_number() && result["cage"]["slip"].is_number(),
        "{result}"
    );
    assert!(
        result["contact"]["inner_load"]["mean"].is_number(),
        "{result}"
    );
    assert!(
        result["contact"]["outer_contact_angle"]["max"].is_number(),
        "{result}"
    );
    // honest kinematics: the slip's definition beside it, and the frequencies three ways
    assert!(result["cage"]["slip_definition"]
        .as_str()
        .unwrap()
        .contains("loaded balls"));
    let f = &result["frequencies"];
    for way in ["nominal", "loaded", "simulated"] {
        let (o, i) = (
            f[way]["bpfo"].as_f64().unwrap(),
            f[way]["bpfi"].as_f64().unwrap(),
        );
        // BPFO + BPFI = Z f_shaft for any cage speed (16 balls)
        let z_fr = 16.0 * f["shaft_hz"].as_f64().unwrap();
        assert!((o + i - z_fr).abs() < 1e-9 * z_fr, "{way}: {f}");
    }
    assert!(f["bpfo_error_pct"].as_f64().unwrap().abs() < 5.0, "{f}");
    let analysis = &result["analysis"];
    assert!(
        analysis.is_object(),
        "analysis missing: {}",
        result["analysis_error"]
    );
    assert!(analysis["theory"]["bpfo"].as_f64().unwrap() > 0.0);
    assert!(!analysis["level_kurtosis"].as_array().unwrap().is_empty());
    assert!(analysis["raw"].is_array() && analysis["best_component"]["identifications"].is_array());

    // signals: every channel listed can be read, windowed and decimated
    let channels = result["channels"].as_array().unwrap();
    assert!(
        channels
            .iter()
            .any(|ch| ch["name"] == "outer_ring_accel_z" || ch["name"] == "outer_ring_accel_y"),
        "{result}"
    );
    let name = analysis["channel"].as_str().unwrap();
    let n = channels.iter().find(|ch| ch["name"] == name).unwrap()["samples"]
        .as_u64()
        .unwrap();
    let (st, _, full) = get_json(
        &c,
        &s.url(&format!(
            "/v1/simulations/{id}/signals?channel={name}&max_points=200000"
        )),
    )
    .await;
    assert_eq!(st, 200, "{full}");
    assert_eq!(full["count"].as_u64().unwrap(), n);
    let (_, _, dec) = get_json(
        &c,
        &s.url(&format!(
            "/v1/simulations/{id}/signals?channel={name}&max_points=100"
        )),
    )
    .await;
    assert!(
        dec["count"].as_u64().unwrap() <= 100
            && dec["data"].as_array().unwrap().len() == dec["count"].as_u64().unwrap() as usize
    );
    assert_eq!(
        dec["data"][1],
        full["data"][dec["decimation"].as_u64().unwrap() as usize],
        "every k-th sample"
    );
    let (_, _, win) = get_json(
        &c,
        &s.url(&format!(
            "/v1/simulations/{id}/signals?channel={name}&from=0.01&to=0.015"
        )),
    )
    .await;
    let t0 = win["start_time"].as_f64().unwrap();
    assert!((0.01..0.0101).contains(&t0), "{t0}");
    let (st, _, _) = get_json(
        &c,
        &s.url(&format!(
            "/v1/simulations/{id}/signals?channel=no_such_channel"
        )),
    )
    .await;
    assert_eq!(st, 404);

    // spectra: raw, best component, one level, with markers and a band limit
    for q in [
        "kind=raw",
        "kind=best_component",
        "kind=level&level=1",
        "kind=raw&fmax=5000",
    ] {
        let (st, _, sp) = get_json(&c, &s.url(&format!("/v1/simulations/{id}/spectra?{q}"))).await;
        assert_eq!(st, 200, "{q}: {sp}");
        assert!(!sp["amplitude"].as_array().unwrap().is_empty(), "{q}");
        assert!(sp["df"].as_f64().unwrap() > 0.0);
        assert!(sp["markers"].is_array() && sp["peaks"].is_array());
    }
    let (_, _, sp) = get_json(
        &c,
        &s.url(&format!("/v1/simulations/{id}/spectra?fmax=5000")),
    )
    .await;
    assert!(sp["fmax"].as_f64().unwrap() <= 5000.0);
    assert!(
        sp["markers"]
            .as_array()
            .unwrap()
            .iter()
            .any(|m| m["name"] == "bpfi"),
        "{sp}"
    );

    // the same spectrum as CSV: a header, then one `frequency_hz,amplitude` row per bin,
    // the JSON's values (both print the stored f32 values as f64)
    let r = c
        .get(s.url(&format!("/v1/simulations/{id}/spectra?fmax=5000")))
        .header("Accept", "text/csv")
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 200);
    assert_eq!(r.headers()["content-type"], "text/csv; charset=utf-8");
    let text = r.text().await.unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("frequency_hz,amplitude"));
    let rows: Vec<(f64, f64)> = lines
        .map(|l| {
            let (f, a) = l.split_once(',').unwrap();
            (f.parse().unwrap(), a.parse().unwrap())
        })
        .collect();
    let amp = sp["amplitude"].as_array().unwrap();
    let df = sp["df"].as_f64().unwrap();
    assert_eq!(rows.len(), amp.len());
    for (k, (f, a)) in rows.iter().enumerate() {
        assert!(
            (f - k as f64 * df).abs() <= 1e-9 * f.max(1.0),
            "row {k}: {f} Hz"
        );
        // serde_json's default float parser may land one ulp off the printed value
        let j = amp[k].as_f64().unwrap();
        assert!(
            (a - j).abs() <= 2.0 * f64::EPSILON * j.abs(),
            "row {k}: {a} vs {j}"
        );
    }

    // markers: as many harmonics of each line as asked for (default: the analysis' own 3),
    // every one below fmax = 20 kHz here (the largest line, BPFI, is ~1.5 kHz)
    let count_per_line = |sp: &serde_json::Value| {
        let mut n = std::collections::BTreeMap::<String, u64>::new();
        for m in sp["markers"].as_array().unwrap() {
            // a shaft sideband (BPFI's only) sits one shaft frequency off its harmonic
            let side = m["sideband"].as_i64().unwrap();
            let shaft = analysis["theory"]["shaft_hz"].as_f64().unwrap();
            if side == 0 {
                *n.entry(m["name"].as_str().unwrap().to_string())
                    .or_default() += 1;
            } else {
                assert!(m["name"] == "bpfi" && side.abs() == 1, "{m}");
            }
            // harmonic h of its line (to rounding: both sides went through JSON)
            let line = m["name"].as_str().unwrap();
            let f1 = analysis["theory"][line].as_f64().unwrap_or(shaft);
            let want = m["harmonic"].as_f64().unwrap() * f1 + side as f64 * shaft;
            let got = m["frequency"].as_f64().unwrap();
            assert!((got - want).abs() <= 1e-12 * want, "{m}: {got} vs {want}");
        }
        n
    };
    for (q, want) in [("", 3), ("&harmonics=5", 5), ("&harmonics=1", 1)] {
        let (st, _, sp) = get_json(
            &c,
            &s.url(&format!("/v1/simulations/{id}/spectra?fmax=20000{q}")),
        )
        .await;
        assert_eq!(st, 200, "{sp}");
        let n = count_per_line(&sp);
        for line in ["bpfo", "bpfi", "ftf", "bsf", "bsf2", "shaft"] {
            assert_eq!(n.get(line), Some(&want), "{line} with '{q}': {n:?}");
        }
    }
    let (st, h, p) = get_json(
        &c,
        &s.url(&format!("/v1/simulations/{id}/spectra?harmonics=0")),
    )
    .await;
    assert_problem(st, &h, &p, 400);

    // a finished job still answers 304 to its ETag, and can be deleted
    let url = s.url(&format!("/v1/simulations/{id}"));
    let etag = c.get(&url).send().await.unwrap().headers()["etag"]
        .to_str()
        .unwrap()
        .to_string();
    assert_eq!(
        c.get(&url)
            .header("if-none-match", etag)
            .send()
            .await
            .unwrap()
            .status(),
        304
    );
    assert_eq!(c.delete(&url).send().await.unwrap().status(), 204);
    assert_eq!(
        get_json(&c, &s.url(&format!("/v1/simulations/{id}/result")))
            .await
            .0,
        404
    );
}

#[tokio::test]
async fn running_job_stops_soon_after_cancel() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "1"]);
    let c = client();
    let id = submit(&c, &s, &short_scene(2.0)).await;
    wait_until(&c, &s, &id, Duration::from_secs(60), |j| {
        j["state"] == "running" && j["progress"].as_f64().unwrap_or(0.0) > 0.0
    })
    .await;
    let t = Instant::now();
    let (st, _, job) = post_json(
        &c,
        &s.url(&format!("/v1/simulations/{id}/cancel")),
        &json!({}),
    )
    .await;
    assert_eq!(st, 202, "{job}");
    assert_eq!(job["cancel_requested"], true);
    let job = wait_finished(&c, &s, &id, Duration::from_secs(5)).await;
    assert_eq!(job["state"], "cancelled", "{job}");
    assert_eq!(job["error"]["kind"], "cancelled");
    assert!(t.elapsed() < Duration::from_secs(5));
    // the cancelled run left no result
    assert_eq!(
        get_json(&c, &s.url(&format!("/v1/simulations/{id}/result")))
            .await
            .0,
        409
    );
}

#[tokio::test]
async fn graceful_shutdown_requeues_the_running_job() {
    let (_dir, db) = temp_db();
    // a real process: this is about SIGTERM
    let mut s = Server::start(&db, &["--workers", "1"]);
    let c = client();
    let id = submit(&c, &s, &short_scene(2.0)).await;
    wait_until(&c, &s, &id, Duration::from_secs(60), |j| {
        j["state"] == "running"
    })
    .await;
    let status = s.terminate();
    assert!(status.success(), "{status}\n{}", s.log());
    // API-only restart: the job is back in the queue, its attempt not counted
    let s = TestApp::spawn(&db, &["--workers", "0"]);
    let (_, _, job) = get_json(&c, &s.url(&format!("/v1/simulations/{id}"))).await;
    assert_eq!(job["state"], "queued", "{job}");
    assert_eq!(job["attempt"], 0, "{job}");
}
