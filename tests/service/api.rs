//! HTTP API behaviour against the real server binary.

use crate::common::*;
use serde_json::{json, Value};
use std::time::Duration;

#[tokio::test]
async fn every_bad_input_gets_its_status_and_a_problem() {
    let (_dir, db) = temp_db();
    // No workers: jobs stay queued, so state conflicts are deterministic.
    let s = TestApp::spawn(&db, &["--workers", "0", "--max-body-bytes", "65536"]);
    let c = client();
    let sims = s.url("/v1/simulations");

    // 400: not JSON
    let r = c
        .post(&sims)
        .header("content-type", "application/json")
        .body("{nope")
        .send()
        .await
        .unwrap();
    let (st, h, problem) = decode(r).await;
    assert_problem(st, &h, &problem, 400);

    // 400 naming the field: NaN, Infinity and 1e400 are not JSON numbers
    for (body, path) in [
        (
            r#"{"preset":"h7005c","overrides":{"operating":{"axial_load":NaN}}}"#,
            "overrides.operating.axial_load",
        ),
        (
            r#"{"preset":"h7005c","overrides":{"operating":{"axial_load":1e400}}}"#,
            "overrides.operating.axial_load",
        ),
        (
            r#"{"preset":"h7005c","overrides":{"faults":[{"width":-Infinity}]}}"#,
            "overrides.faults[0].width",
        ),
    ] {
        let r = c
            .post(&sims)
            .header("content-type", "application/json")
            .body(body)
            .send()
            .await
            .unwrap();
        let (st, h, problem) = decode(r).await;
        assert_problem(st, &h, &problem, 400);
        assert_eq!(problem["errors"][0]["path"], path, "{problem}");
        let message = problem["errors"][0]["message"].as_str().unwrap();
        assert!(message.contains("not a finite JSON number"), "{problem}");
    }

    // 415: no JSON content type
    let r = c.post(&sims).body("{}").send().await.unwrap();
    let (st, h, problem) = decode(r).await;
    assert_problem(st, &h, &problem, 415);

    // 422: unknown scene member, with its path
    let mut scene = get_json(&c, &s.url("/v1/presets/h7005c")).await.2["scene"].clone();
    scene["bearing"]["colour"] = json!("red");
    let (st, h, body) = post_json(&c, &sims, &json!({ "scene": scene })).await;
    assert_problem(st, &h, &body, 422);
    assert_eq!(body["errors"][0]["path"], "scene.bearing.colour", "{body}");

    // 422: a wrong type names its path
    let (st, h, body) = post_json(&c, &sims, &json!({"preset": "h7005c", "overrides": {"faults": [{"ring": "inner", "angle": 0, "width": "wide", "depth": 1e-4}]}})).await;
    assert_problem(st, &h, &body, 422);
    assert_eq!(body["errors"][0]["path"], "scene.faults[0].width", "{body}");

    // 422: every field problem at once
    let (st, h, body) = post_json(&c, &sims, &json!({"preset": "h7005c", "overrides": {"bearing": {"ball_diameter": -1.0}, "solver": {"duration": 0}}})).await;
    assert_problem(st, &h, &body, 422);
    let paths = error_paths(&body);
    assert!(
        paths.contains(&"scene.bearing.ball_diameter") && paths.contains(&"scene.solver.duration"),
        "{body}"
    );

    // 422: request-level problems, all listed
    let (st, h, body) = post_json(
        &c,
        &sims,
        &json!({"preset": "h9999", "fault_case": "sideways", "extra": 1}),
    )
    .await;
    assert_problem(st, &h, &body, 422);
    let paths = error_paths(&body);
    for p in ["preset", "fault_case", "extra"] {
        assert!(paths.contains(&p), "{p} missing: {body}");
    }
    let (st, h, body) = post_json(&c, &sims, &json!([1, 2])).await;
    assert_problem(st, &h, &body, 422);

    // 422: no equilibrium to start from (10 N axial under 300 N radial, tilt locked) is
    // refused at submission, naming both loads and the limit Fr tan(alpha0) ~ 80 N
    let (st, h, body) = post_json(
        &c,
        &sims,
        &json!({"preset": "h7005c", "overrides": {"operating": {"axial_load": 10.0}}}),
    )
    .await;
    assert_problem(st, &h, &body, 422);
    let paths = error_paths(&body);
    assert_eq!(
        paths,
        ["scene.operating.axial_load", "scene.operating.radial_load"],
        "{body}"
    );
    let message = body["errors"][0]["message"].as_str().unwrap();
    assert!(
        message.contains("Fr tan(alpha0) = ") && message.contains("300 N"),
        "{body}"
    );
    // nothing was queued
    let list = get_json(&c, &sims).await.2;
    assert!(list["items"].as_array().unwrap().is_empty(), "{list}");

    // 413: body over the limit
    let big = json!({"preset": "h7005c", "overrides": {"name": "x".repeat(100_000)}});
    let (st, h, body) = post_json(&c, &sims, &big).await;
    assert_problem(st, &h, &body, 413);

    // 413 at once for a declared length over the limit, before the body is read: 400 MB
    // declared, 16 bytes sent, and the socket left open (it used to wait for the 30 s
    // request timeout and answer 408)
    {
        use std::io::{Read, Write};
        let addr = s.base.trim_start_matches("http://").to_string();
        let mut sock = std::net::TcpStream::connect(&addr).unwrap();
        sock.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        write!(
            sock,
            "POST /v1/simulations HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: 400000000\r\n\r\n{{\"preset\": \"h7\"}}"
        )
        .unwrap();
        let mut answer = Vec::new();
        let mut buf = [0u8; 4096];
        while let Ok(n) = sock.read(&mut buf) {
            if n == 0 {
                break;
            }
            answer.extend_from_slice(&buf[..n]);
            if answer.windows(4).any(|w| w == b"\r\n\r\n") && answer.ends_with(b"}") {
                break;
            }
        }
        let answer = String::from_utf8_lossy(&answer);
        assert!(answer.starts_with("HTTP/1.1 413"), "{answer}");
        assert!(answer.contains("application/problem+json"), "{answer}");
        assert!(answer.contains("400000000"), "{answer}");
    }

    // 404: unknown id and unknown route; 405: wrong method
    let (st, h, body) = get_json(&c, &s.url("/v1/simulations/does-not-exist")).await;
    assert_problem(st, &h, &body, 404);
    let (st, h, body) = get_json(&c, &s.url("/v1/nothing-here")).await;
    assert_problem(st, &h, &body, 404);
    let r = c.put(&sims).send().await.unwrap();
    let (st, h, problem) = decode(r).await;
    assert_problem(st, &h, &problem, 405);

    // 400: bad query parameters
    for q in ["?state=bogus", "?limit=0", "?limit=x", "?cursor=abc"] {
        let (st, h, body) = get_json(&c, &format!("{sims}{q}")).await;
        assert_problem(st, &h, &body, 400);
    }

    // 409: invalid transitions on a queued job
    let id = submit(&c, &s, &short_scene(0.01)).await;
    for path in ["result", "spectra"] {
        let (st, h, body) = get_json(&c, &s.url(&format!("/v1/simulations/{id}/{path}"))).await;
        assert_problem(st, &h, &body, 409);
        assert_eq!(body["job_state"], "queued");
    }
    let (st, h, body) = get_json(
        &c,
        &s.url(&format!(
            "/v1/simulations/{id}/signals?channel=outer_ring_accel_z"
        )),
    )
    .await;
    assert_problem(st, &h, &body, 409);
    let r = c
        .delete(s.url(&format!("/v1/simulations/{id}")))
        .send()
        .await
        .unwrap();
    let (st, h, problem) = decode(r).await;
    assert_problem(st, &h, &problem, 409);
    // 400: signals without a channel
    let (st, h, body) = get_json(&c, &s.url(&format!("/v1/simulations/{id}/signals"))).await;
    assert_problem(st, &h, &body, 400);
    // cancelling twice: the second is a 409
    let r = c
        .post(s.url(&format!("/v1/simulations/{id}/cancel")))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 202);
    let r = c
        .post(s.url(&format!("/v1/simulations/{id}/cancel")))
        .send()
        .await
        .unwrap();
    let (st, h, problem) = decode(r).await;
    assert_problem(st, &h, &problem, 409);

    // Idempotency-Key: replay -> 200 same job; other body -> 422
    let send = |body: Value| {
        let c = c.clone();
        let url = sims.clone();
        async move {
            let r = c
                .post(url)
                .header("Idempotency-Key", "key-1")
                .json(&body)
                .send()
                .await
                .unwrap();
            (r.status().as_u16(), r.json::<Value>().await.unwrap())
        }
    };
    let (st1, j1) = send(short_scene(0.01)).await;
    let (st2, j2) = send(short_scene(0.01)).await;
    assert_eq!((st1, st2), (202, 200));
    assert_eq!(j1["id"], j2["id"]);
    let (st3, j3) = send(short_scene(0.02)).await;
    assert_eq!(st3, 422, "{j3}");
    assert_eq!(j3["type"], "urn:bearing-sim:problem:idempotency-key-reused");

    // analyses: wrong media type, bad geometry, missing shaft speed
    let r = c
        .post(s.url("/v1/analyses"))
        .header("content-type", "text/csv")
        .body("1,2,3")
        .send()
        .await
        .unwrap();
    let (st, h, problem) = decode(r).await;
    assert_problem(st, &h, &problem, 415);
    let samples: Vec<f64> = (0..64).map(|i| (i as f64).sin()).collect();
    let (st, h, body) = post_json(&c, &s.url("/v1/analyses"), &json!({"samples": samples, "sample_rate": 1000.0, "geometry": {"ball_count": 9, "ball_diameter": -1.0, "pitch_diameter": 0.04, "contact_angle": 0.0}, "shaft_hz": 10.0})).await;
    assert_problem(st, &h, &body, 422);
    assert_eq!(
        body["errors"][0]["path"], "geometry.ball_diameter",
        "{body}"
    );
    let (st, h, body) = post_json(
        &c,
        &s.url("/v1/analyses"),
        &json!({"samples": samples, "sample_rate": 1000.0, "preset": "cwru6205"}),
    )
    .await;
    assert_problem(st, &h, &body, 422);
    let r = c
        .post(s.url("/v1/analyses?sample_rate=1000&preset=cwru6205&shaft_hz=20"))
        .header("content-type", "application/octet-stream")
        .body(vec![0u8; 7])
        .send()
        .await
        .unwrap();
    let (st, h, problem) = decode(r).await;
    assert_problem(st, &h, &problem, 422);

    // quasi-static: validation uses the same paths
    let (st, h, body) = post_json(
        &c,
        &s.url("/v1/quasi-static"),
        &json!({"preset": "h7005c", "shaft_rpm": -5}),
    )
    .await;
    assert_problem(st, &h, &body, 422);
    assert_eq!(body["errors"][0]["path"], "shaft_rpm");
}

/// The quasi-static answer carries the pocket-cycle cage speed only when asked, and then the
/// engine's own. Under the paper's model, whose cycle takes about 0.5 s at 10000 rpm and
/// whose torque falls steadily (under the preset's rheology law it takes about 5 s and its
/// torque is a staircase: docs/reference/model.md, "Cage speed by the pocket cycle").
#[tokio::test]
async fn quasi_static_gives_the_pocket_cycle_when_asked() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "0"]);
    let c = client();
    let url = s.url("/v1/quasi-static");
    let paper = json!({"lubricant": {"traction": {"model": "abcd"},
        "rolling_resistance": {"model": "none"}}});
    let (st, _, plain) = post_json(
        &c,
        &url,
        &json!({"preset": "h7005c", "shaft_rpm": 10000, "overrides": paper}),
    )
    .await;
    assert_eq!(st, 200, "{plain}");
    assert!(plain.get("pocket_cycle").is_none(), "{plain}");
    let (st, _, body) = post_json(
        &c,
        &url,
        &json!({"preset": "h7005c", "shaft_rpm": 10000, "pocket_cycle": true,
            "overrides": paper}),
    )
    .await;
    assert_eq!(st, 200, "{body}");
    let mut scene = bearing_core::scene::preset_scene("h7005c").unwrap();
    scene.lubricant.traction = bearing_core::scene::Traction::PAPER_CURVE;
    scene.lubricant.rolling_resistance = bearing_core::scene::RollingResistanceModel::None;
    let scene = scene.validated().unwrap();
    let engine = bearing_core::quasi_static::pocket_cycle(&scene, 10_000.0).unwrap();
    // serde_json's default parser may miss the last bit of a float: 1e-14 relative
    let served = body["pocket_cycle"]["cage_speed"].as_f64().unwrap();
    assert!(
        (served / engine.cage_speed - 1.0).abs() < 1e-14,
        "{served} against {}",
        engine.cage_speed
    );
    assert_eq!(body["pocket_cycle"]["monotone"], true);
    assert_eq!(body["cage_speed"], plain["cage_speed"]);
    // a flag that is not a boolean names its field
    let (st, h, problem) = post_json(
        &c,
        &url,
        &json!({"preset": "h7005c", "pocket_cycle": "yes"}),
    )
    .await;
    assert_problem(st, &h, &problem, 422);
    assert_eq!(problem["errors"][0]["path"], "pocket_cycle");
}

/// Overrides that name another lubricant model select it with its own defaults: the preset's
/// rheology law's fields do not carry over into the paper's curve as unknown fields.
#[tokio::test]
async fn overrides_naming_another_traction_law_select_it() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "0"]);
    let c = client();
    let url = s.url("/v1/quasi-static");
    let body = json!({"preset": "h7005c", "shaft_rpm": 10000,
        "overrides": {"lubricant": {"traction": {"model": "abcd"}}}});
    let (st, _, served) = post_json(&c, &url, &body).await;
    assert_eq!(st, 200, "{served}");
    let mut scene = bearing_core::scene::preset_scene("h7005c").unwrap();
    scene.lubricant.traction = bearing_core::scene::Traction::PAPER_CURVE;
    let engine = bearing_core::quasi_static::solve(&scene.validated().unwrap(), 10_000.0).unwrap();
    // the paper's curve's own balance, to the last bits, not the preset rheology law's
    let cage = served["cage_speed"].as_f64().unwrap();
    let (st, _, plain) =
        post_json(&c, &url, &json!({"preset": "h7005c", "shaft_rpm": 10000})).await;
    assert_eq!(st, 200, "{plain}");
    assert_ne!(plain["cage_speed"].as_f64().unwrap(), cage);
    assert!(
        (cage / engine.cage_speed - 1.0).abs() < 1e-14,
        "{cage} against {}",
        engine.cage_speed
    );
    // a field the named law does not have is still an error naming it
    let body = json!({"preset": "h7005c",
        "overrides": {"lubricant": {"traction": {"model": "abcd", "limiting_coefficient": 0.1}}}});
    let (st, h, problem) = post_json(&c, &url, &body).await;
    assert_problem(st, &h, &problem, 422);
    assert!(
        problem
            .to_string()
            .contains("unknown field `limiting_coefficient`"),
        "{problem}"
    );
}

#[tokio::test]
async fn full_queue_answers_429_with_retry_after() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "0", "--max-queued", "3"]);
    let c = client();
    for _ in 0..3 {
        submit(&c, &s, &short_scene(0.01)).await;
    }
    let (st, h, body) = post_json(&c, &s.url("/v1/simulations"), &short_scene(0.01)).await;
    assert_problem(st, &h, &body, 429);
    let retry: u64 = h
        .get("retry-after")
        .expect("Retry-After")
        .to_str()
        .unwrap()
        .parse()
        .unwrap();
    assert!(retry >= 1);
    // the queue depth is visible in the metrics
    let m = get_text(&c, &s.url("/metrics")).await;
    assert!(m.contains("bearing_sim_queue_depth 3"), "{m}");
}

#[tokio::test]
async fn queued_job_cancels_at_once_and_polling_is_cheap() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "0"]);
    let c = client();
    let id = submit(&c, &s, &short_scene(0.01)).await;
    let url = s.url(&format!("/v1/simulations/{id}"));

    // ETag + If-None-Match -> 304 without a body
    let r = c.get(&url).send().await.unwrap();
    let etag = r
        .headers()
        .get("etag")
        .unwrap()
        .to_str()
        .unwrap()
        .to_string();
    let r = c
        .get(&url)
        .header("if-none-match", &etag)
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 304);
    assert!(r.bytes().await.unwrap().is_empty());

    let (st, _, job) = post_json(
        &c,
        &s.url(&format!("/v1/simulations/{id}/cancel")),
        &json!({}),
    )
    .await;
    assert_eq!(st, 202);
    assert_eq!(job["state"], "cancelled", "{job}");
    // the change shows: the old ETag no longer matches
    let r = c
        .get(&url)
        .header("if-none-match", &etag)
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 200);
    // a finished job can be deleted, then it is gone
    let r = c.delete(&url).send().await.unwrap();
    assert_eq!(r.status(), 204);
    let (st, _, _) = get_json(&c, &url).await;
    assert_eq!(st, 404);
}

#[tokio::test]
async fn listing_filters_by_state_and_pages_with_a_cursor() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "0"]);
    let c = client();
    let mut ids = vec![];
    for _ in 0..5 {
        ids.push(submit(&c, &s, &short_scene(0.01)).await);
    }
    c.post(s.url(&format!("/v1/simulations/{}/cancel", ids[0])))
        .send()
        .await
        .unwrap();

    let mut seen = vec![];
    let mut url = s.url("/v1/simulations?limit=2");
    loop {
        let (st, _, page) = get_json(&c, &url).await;
        assert_eq!(st, 200, "{page}");
        for j in page["items"].as_array().unwrap() {
            seen.push(j["id"].as_str().unwrap().to_string());
        }
        match page["next_cursor"].as_str() {
            Some(cur) => url = s.url(&format!("/v1/simulations?limit=2&cursor={cur}")),
            None => break,
        }
    }
    let mut want = ids.clone();
    want.reverse(); // newest first
    assert_eq!(seen, want);

    let (_, _, page) = get_json(&c, &s.url("/v1/simulations?state=cancelled")).await;
    let items = page["items"].as_array().unwrap();
    assert_eq!(items.len(), 1);
    assert_eq!(items[0]["id"], ids[0].as_str());
    let (_, _, page) = get_json(&c, &s.url("/v1/simulations?state=queued")).await;
    assert_eq!(page["items"].as_array().unwrap().len(), 4);
}

#[tokio::test]
async fn presets_and_operational_endpoints() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(
        &db,
        &["--workers", "1", "--cors-origins", "http://lab.example"],
    );
    let c = client();
    let (st, _, list) = get_json(&c, &s.url("/v1/presets")).await;
    assert_eq!(st, 200);
    let names: Vec<&str> = list["items"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert!(
        names.contains(&"h7005c") && names.contains(&"cwru6205"),
        "{list}"
    );
    let (st, _, p) = get_json(&c, &s.url("/v1/presets/h7005c")).await;
    assert_eq!(st, 200);
    assert_eq!(p["scene"]["bearing"]["ball_count"], 16);
    assert_eq!(p["table2_groups"].as_array().unwrap().len(), 9);
    assert_eq!(
        p["fault_case_faults"]["compound"]["faults"]
            .as_array()
            .unwrap()
            .len(),
        2
    );
    let (st, _, p) = get_json(&c, &s.url("/v1/presets/cwru6205")).await;
    assert_eq!(st, 200);
    assert_eq!(p["kinematics"]["ball_count"], 9);
    assert_eq!(get_json(&c, &s.url("/v1/presets/nope")).await.0, 404);

    assert_eq!(get_json(&c, &s.url("/healthz")).await.0, 200);
    assert_eq!(get_json(&c, &s.url("/readyz")).await.0, 200);
    let m = get_text(&c, &s.url("/metrics")).await;
    for name in [
        "bearing_sim_queue_depth",
        "bearing_sim_jobs{state=\"queued\"}",
        "bearing_sim_http_request_duration_seconds_bucket",
    ] {
        assert!(m.contains(name), "{name} missing:\n{m}");
    }
    let spec = get_text(&c, &s.url("/openapi.yaml")).await;
    assert!(spec.starts_with("openapi: 3.1"));
    assert_eq!(spec, bearing_sim::api::openapi::yaml(), "served document");
    // the in-process app keeps its own log, for failure messages
    assert!(s.log().contains("serving"), "log: {}", s.log());

    // CORS: the configured origin may read Location, ETag and Retry-After
    let r = c
        .request(reqwest::Method::OPTIONS, s.url("/v1/simulations"))
        .header("origin", "http://lab.example")
        .header("access-control-request-method", "POST")
        .send()
        .await
        .unwrap();
    assert_eq!(
        r.headers().get("access-control-allow-origin").unwrap(),
        "http://lab.example"
    );
    let r = c
        .get(s.url("/v1/simulations"))
        .header("origin", "http://lab.example")
        .send()
        .await
        .unwrap();
    let exposed = r
        .headers()
        .get("access-control-expose-headers")
        .unwrap()
        .to_str()
        .unwrap()
        .to_ascii_lowercase();
    for h in ["location", "etag", "retry-after"] {
        assert!(exposed.contains(h), "{exposed}");
    }
    let r = c
        .get(s.url("/v1/simulations"))
        .header("origin", "http://evil.example")
        .send()
        .await
        .unwrap();
    assert!(r.headers().get("access-control-allow-origin").is_none());
}

/// A synthetic outer-race fault: impulses at BPFO exciting a decaying 3 kHz resonance.
fn synthetic_outer_fault(fs: f64, seconds: f64, bpfo: f64) -> Vec<f64> {
    let n = (fs * seconds) as usize;
    let mut x = vec![0.0; n];
    let mut t_hit = 0.0;
    while t_hit < seconds {
        let k0 = (t_hit * fs) as usize;
        let end = (k0 + (0.004 * fs) as usize).min(n);
        for (j, v) in x[k0.min(end)..end].iter_mut().enumerate() {
            let t = j as f64 / fs;
            *v += (-t * 800.0).exp() * (2.0 * std::f64::consts::PI * 3000.0 * t).sin();
        }
        t_hit += 1.0 / bpfo;
    }
    // a little deterministic noise
    let mut seed = 12345u64;
    for v in x.iter_mut() {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        *v += 0.05 * (((seed >> 33) as f64 / (1u64 << 31) as f64) - 0.5);
    }
    x
}

#[tokio::test]
async fn analyses_run_directly_or_as_queued_jobs() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "1"]);
    let c = client();
    let fs = 12_000.0;
    let shaft_hz = 1797.0 / 60.0;
    let bpfo = 3.5848 * shaft_hz; // CWRU 6205 BPFO per shaft revolution
    let x = synthetic_outer_fault(fs, 1.0, bpfo);

    // JSON, small: answered directly
    let req = json!({"samples": x, "sample_rate": fs, "preset": "cwru6205", "shaft_rpm": 1797.0});
    let (st, _, body) = post_json(&c, &s.url("/v1/analyses"), &req).await;
    assert_eq!(st, 200, "{body}");
    let theory_bpfo = body["analysis"]["theory"]["bpfo"].as_f64().unwrap();
    assert!(
        (theory_bpfo - bpfo).abs() / bpfo < 0.01,
        "{theory_bpfo} vs {bpfo}"
    );
    assert!(
        body["spectra"]["raw"]["amplitude"]
            .as_array()
            .unwrap()
            .len()
            > 100
    );
    // the verdict comes with the result: an outer-race fault and nothing else
    assert_eq!(
        body["analysis"]["verdict"]["faults"],
        json!(["outer_race"]),
        "{}",
        body["analysis"]["verdict"]
    );

    // raw f32 body, queued on request, searching 4 harmonics (the analysis default is 3)
    let raw: Vec<u8> = x.iter().flat_map(|v| (*v as f32).to_le_bytes()).collect();
    let r = c
        .post(s.url(
            "/v1/analyses?mode=async&sample_rate=12000&preset=cwru6205&shaft_rpm=1797&harmonics=4&false_alarm_rate=0.0001",
        ))
        .header("content-type", "application/octet-stream")
        .body(raw)
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 202);
    let loc = r
        .headers()
        .get("location")
        .unwrap()
        .to_str()
        .unwrap()
        .to_string();
    assert!(loc.starts_with("/v1/analyses/"));
    let mut job = Value::Null;
    for _ in 0..600 {
        job = get_json(&c, &s.url(&loc)).await.2;
        if job["state"] != "queued" && job["state"] != "running" {
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    assert_eq!(job["state"], "succeeded", "{job}\n{}", s.log());
    let (st, _, result) = get_json(&c, &s.url(&format!("{loc}/result"))).await;
    assert_eq!(st, 200);
    assert_eq!(result["analysis"]["verdict"]["false_alarm_rate"], 1e-4);
    assert!(
        result["analysis"]["level_kurtosis"]
            .as_array()
            .unwrap()
            .len()
            >= 3,
        "{result}"
    );
    let (st, _, spec) = get_json(
        &c,
        &s.url(&format!("{loc}/spectra?kind=best_component&fmax=500")),
    )
    .await;
    assert_eq!(st, 200, "{spec}");
    assert!(spec["fmax"].as_f64().unwrap() <= 500.0);
    assert!(
        spec["markers"]
            .as_array()
            .unwrap()
            .iter()
            .any(|m| m["name"] == "bpfo"),
        "{spec}"
    );
    // the stored analysis keeps its options, and the markers follow them: 4 harmonics of
    // BPFO (~107 Hz) lie below 500 Hz, and 4 of FTF (~12 Hz)
    assert_eq!(result["analysis"]["options"]["harmonics"], 4, "{result}");
    for line in ["bpfo", "ftf"] {
        let n = spec["markers"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|m| m["name"] == line)
            .count();
        assert_eq!(n, 4, "{line}: {spec}");
    }
    // the analysis id is not a simulation id
    assert_eq!(
        get_json(
            &c,
            &s.url(&format!("/v1/simulations/{}", job["id"].as_str().unwrap()))
        )
        .await
        .0,
        404
    );
}

#[tokio::test]
async fn long_poll_holds_an_unchanged_job_until_it_changes() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "0", "--request-timeout", "1"]);
    let c = client();
    let id = submit(&c, &s, &short_scene(0.01)).await;
    let url = s.url(&format!("/v1/simulations/{id}"));
    let etag = c.get(&url).send().await.unwrap().headers()["etag"]
        .to_str()
        .unwrap()
        .to_string();

    // Unchanged: held for `wait` (longer than the 1 s request timeout, which does not apply), then 304.
    let t = std::time::Instant::now();
    let r = c
        .get(format!("{url}?wait=1.5"))
        .header("if-none-match", &etag)
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 304);
    assert!(
        t.elapsed() >= Duration::from_millis(1400),
        "{:?}",
        t.elapsed()
    );

    // A change during the wait answers at once with the new state.
    let poll = spawn_long_poll(&c, &url, &etag);
    tokio::time::sleep(Duration::from_millis(300)).await;
    c.post(s.url(&format!("/v1/simulations/{id}/cancel")))
        .send()
        .await
        .unwrap();
    let r = poll.await.unwrap();
    assert_eq!(r.status(), 200);
    assert_eq!(r.json::<Value>().await.unwrap()["state"], "cancelled");

    // wait out of range is a 400
    let (st, h, body) = get_json(&c, &format!("{url}?wait=61")).await;
    assert_problem(st, &h, &body, 400);
}

/// `--cors-origins '*'` allows any origin (it used to panic after "listening on"), and a
/// malformed origin is refused when the flags are parsed, before the service binds.
#[tokio::test]
async fn cors_wildcard_allows_any_origin_and_bad_origins_are_refused_up_front() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "1", "--cors-origins", "*"]);
    let r = client()
        .request(reqwest::Method::OPTIONS, s.url("/v1/presets"))
        .header("origin", "http://any.example")
        .header("access-control-request-method", "GET")
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 200);
    assert_eq!(r.headers()["access-control-allow-origin"], "*");

    let bin = env!("CARGO_BIN_EXE_bearing-sim");
    for bad in ["http://lab.example/", "lab.example", "http://"] {
        let out = std::process::Command::new(bin)
            .args(["serve", "--bind", "127.0.0.1:0", "--cors-origins", bad])
            .output()
            .unwrap();
        let (stdout, stderr) = (
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr),
        );
        assert!(!out.status.success(), "{bad}: accepted");
        assert!(
            !stdout.contains("listening on"),
            "{bad}: bound first: {stdout}"
        );
        assert!(stderr.contains("--cors-origins"), "{bad}: {stderr}");
    }
}

/// Analysis options are checked the same way on the direct and the queued path, before
/// anything runs or is queued, with the path of the option in `errors[]`; unknown option
/// names are refused like unknown members anywhere else.
#[tokio::test]
async fn analysis_options_are_checked_up_front_on_every_path() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "0"]);
    let c = client();
    let x: Vec<f64> = (0..4096).map(|k| (k as f64 * 0.37).sin()).collect();
    let base =
        json!({"samples": x, "sample_rate": 12000.0, "preset": "cwru6205", "shaft_rpm": 1797.0});
    for mode in ["", "?mode=async"] {
        for (options, path) in [
            (json!({"levels": 99}), "options.levels"),
            (json!({"harmonics": 0}), "options.harmonics"),
            (json!({"biort": "nope"}), "options.biort"),
            (json!({"window": [0.5, 0.2]}), "options.window"),
            (json!({"harmonicz": 4}), "options.harmonicz"),
        ] {
            let mut req = base.clone();
            req["options"] = options.clone();
            let url = s.url(&format!("/v1/analyses{mode}"));
            let (st, h, body) = post_json(&c, &url, &req).await;
            assert_problem(st, &h, &body, 422);
            let paths = error_paths(&body);
            assert!(
                paths.iter().any(|p| p.starts_with(path)),
                "{mode} {options}: {paths:?} in {body}"
            );
        }
    }
    // nothing was queued
    let (_, _, list) = get_json(&c, &s.url("/v1/analyses")).await;
    assert!(list["items"].as_array().unwrap().is_empty(), "{list}");
    // query parameters name themselves
    let raw: Vec<u8> = x.iter().flat_map(|v| (*v as f32).to_le_bytes()).collect();
    let r = c
        .post(s.url(
            "/v1/analyses?mode=async&sample_rate=12000&preset=cwru6205&shaft_rpm=1797&levels=99",
        ))
        .header("content-type", "application/octet-stream")
        .body(raw)
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 422);
    let body: Value = r.json().await.unwrap();
    assert_eq!(body["errors"][0]["path"], "levels", "{body}");
}

#[tokio::test]
async fn the_web_page_and_its_assets_are_served_from_the_binary() {
    let (_dir, db) = temp_db();
    let app = TestApp::spawn(&db, &["--workers", "0"]);
    let c = client();
    let r = c.get(app.url("/")).send().await.unwrap();
    assert_eq!(r.status(), 200);
    assert!(r.headers()["content-type"]
        .to_str()
        .unwrap()
        .starts_with("text/html"));
    // the page may load only its own assets
    assert!(r.headers()["content-security-policy"]
        .to_str()
        .unwrap()
        .contains("default-src 'self'"));
    let html = r.text().await.unwrap();
    for asset in ["/assets/app.js", "/assets/style.css"] {
        assert!(html.contains(asset), "{asset} not linked");
    }
    for (asset, ct) in [
        ("/assets/app.js", "text/javascript"),
        ("/assets/plot.js", "text/javascript"),
        ("/assets/style.css", "text/css"),
    ] {
        let r = c.get(app.url(asset)).send().await.unwrap();
        assert_eq!(r.status(), 200, "{asset}");
        assert!(r.headers()["content-type"]
            .to_str()
            .unwrap()
            .starts_with(ct));
        assert!(!r.text().await.unwrap().is_empty());
    }
    let (st, h, p) = get_json(&c, &app.url("/assets/nope.js")).await;
    assert_problem(st, &h, &p, 404);
}
