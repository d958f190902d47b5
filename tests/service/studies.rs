//! Parameter studies over HTTP: a small study runs to success with its table and plots,
//! identical points run once, a cancelled study cancels its points, bad points are named.

use crate::common::*;
use serde_json::{json, Value};
use std::time::Duration;

/// Outer fault at three axial loads, two of them equal (the preset's Table-1 speed ramp;
/// 30 ms simulated gives a 22.5 ms steady window, 15 ms of analysis).
fn small_study(duration: f64) -> Value {
    axial_load_study(duration, &[300.0, 400.0, 400.0])
}

async fn wait_study(
    c: &reqwest::Client,
    s: &impl Service,
    id: &str,
    timeout: Duration,
    pred: impl Fn(&Value) -> bool,
) -> Value {
    wait_for(c, s, &format!("/v1/studies/{id}"), timeout, pred).await
}

fn finished(st: &Value) -> bool {
    matches!(
        st["state"].as_str(),
        Some("succeeded" | "failed" | "cancelled")
    )
}

/// Parse an SVG document and return the text of every `<text>` element.
fn svg_texts(svg: &str) -> Vec<String> {
    let doc = roxmltree::Document::parse(svg).unwrap_or_else(|e| panic!("not XML: {e}\n{svg}"));
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    doc.descendants()
        .filter(|n| n.tag_name().name() == "text")
        .filter_map(|n| n.text().map(|t| t.trim().to_string()))
        .collect()
}

async fn get_svg(c: &reqwest::Client, url: &str) -> Vec<String> {
    let r = c.get(url).send().await.unwrap();
    assert_eq!(r.status(), 200, "{url}");
    assert_eq!(r.headers()["content-type"], "image/svg+xml");
    svg_texts(&r.text().await.unwrap())
}

#[tokio::test]
async fn a_small_study_runs_with_its_table_and_plots_and_shares_identical_points() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "2"]);
    let c = client();
    let (status, h, st) = post_json(&c, &s.url("/v1/studies"), &small_study(0.03)).await;
    assert_eq!(status, 202, "{st}");
    let id = st["id"].as_str().unwrap().to_string();
    assert_eq!(h["location"], format!("/v1/studies/{id}"));
    assert_eq!(st["progress"]["points_total"], 3);
    let points = st["points"].as_array().unwrap();
    // identical scenes share one job
    assert_eq!(points[1]["job_id"], points[2]["job_id"], "{st}");
    assert_ne!(points[0]["job_id"], points[1]["job_id"]);
    assert_eq!(points[2]["shared"], true);

    let done = wait_study(&c, &s, &id, Duration::from_secs(300), finished).await;
    assert_eq!(done["state"], "succeeded", "{done}");
    let p = &done["progress"];
    assert_eq!(
        (p["points_done"].as_u64(), p["points_succeeded"].as_u64()),
        (Some(3), Some(3))
    );
    // 3 points of 30 ms: the shared point counts for each point it serves
    assert!(
        (p["simulated_time_total"].as_f64().unwrap() - 0.09).abs() < 1e-12,
        "{p}"
    );
    assert_eq!(p["fraction"], 1.0);
    let etag = h_etag(&c, &s, &id).await;
    let r = c
        .get(s.url(&format!("/v1/studies/{id}")))
        .header("if-none-match", &etag)
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 304);

    // two simulation jobs only, however many points
    let (_, _, sims) = get_json(&c, &s.url("/v1/simulations")).await;
    assert_eq!(sims["items"].as_array().unwrap().len(), 2, "{sims}");

    // the table: one row per point with the fields a lab reads
    let (status, _, table) = get_json(&c, &s.url(&format!("/v1/studies/{id}/table"))).await;
    assert_eq!(status, 200, "{table}");
    let rows = table["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 3);
    assert_eq!(table["factors"], json!(["axial_load"]));
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r["index"], i);
        assert_eq!(r["state"], "succeeded");
        assert_eq!(r["fault_case"], "outer");
        let res = &r["result"];
        for line in ["bpfo", "bpfi"] {
            let l = &res[line];
            for k in ["theory_hz", "loaded_theory_hz", "cage_hz", "cage_error_pct"] {
                assert!(l[k].is_number(), "{line}.{k}: {r}");
            }
            for spectrum in ["raw", "best"] {
                assert!(l[spectrum]["hz"].is_number(), "{line}.{spectrum}: {r}");
                assert!(l[spectrum]["detected"].is_boolean());
                assert!(l[spectrum]["prominence_db"].is_number());
            }
        }
        // eq. 37 for the H7005C: BPFO = 6.8074 shaft revolutions (Z/2 (1 - D cos 15 deg /
        // dm)); 30 ms into the Table-1 ramp the shaft turns at ~50 Hz, so the absolute
        // value is not pinned, the ratio is (to 1e-4: rounding of the constant)
        let bpfo = res["bpfo"]["theory_hz"].as_f64().unwrap();
        let shaft = res["shaft_hz"].as_f64().unwrap();
        assert!((bpfo / shaft - 6.8074).abs() < 1e-4, "{bpfo} / {shaft}");
        assert!(res["cage"]["mean_speed"].as_f64().unwrap() > 0.0);
        assert!(res["cage"]["whirl"].is_boolean());
        assert!(res["wall_time"].as_f64().unwrap() > 0.0);
    }
    assert_eq!(rows[0]["factors"][0]["value"], 300.0);
    assert_eq!(rows[2]["factors"][0]["value"], 400.0);
    let csv = c
        .get(s.url(&format!("/v1/studies/{id}/table")))
        .header("accept", "text/csv")
        .send()
        .await
        .unwrap();
    assert!(csv.headers()["content-type"]
        .to_str()
        .unwrap()
        .starts_with("text/csv"));
    let csv = csv.text().await.unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 4, "{csv}");
    let header: Vec<&str> = lines[0].split(',').collect();
    for col in [
        "axial_load",
        "bpfo_theory_hz",
        "bpfo_best_detected",
        "bpfi_raw_error_pct",
        "cage_whirl",
        "wall_time_s",
    ] {
        assert!(header.contains(&col), "{col} missing: {}", lines[0]);
    }
    assert!(
        lines[1..]
            .iter()
            .all(|l| l.split(',').count() == header.len()),
        "{csv}"
    );

    // plots: valid SVG with the expected series and axes
    let links = &done["links"];
    assert!(links["plot:axial_load-outer.svg"].is_string(), "{links}");
    let trend = get_svg(
        &c,
        &s.url(&format!("/v1/studies/{id}/plots/axial_load-outer.svg")),
    )
    .await;
    for want in [
        "BPFO, eq. 37 (nominal angle)",
        "BPFO, raw envelope spectrum",
        "BPFO, best DTCWT component",
        "frequency (Hz)",
    ] {
        assert!(
            trend.iter().any(|t| t.contains(want)),
            "{want} not in {trend:?}"
        );
    }
    // an outer fault's trend shows BPFO only
    assert!(!trend.iter().any(|t| t.contains("BPFI")), "{trend:?}");
    let grid = get_svg(&c, &s.url(&format!("/v1/studies/{id}/plots/spectra.svg"))).await;
    assert_eq!(
        grid.iter().filter(|t| t.starts_with("axial_load=")).count(),
        3,
        "{grid:?}"
    );
    // labels that find no free spot are left to the legend under the grid
    assert!(grid.iter().any(|t| t == "BPFO"), "{grid:?}");
    assert!(
        grid.iter()
            .any(|t| t.starts_with("BPFI ") && t.ends_with("Hz and harmonics")),
        "{grid:?}"
    );
    let (status, _, body) = get_json(&c, &s.url(&format!("/v1/studies/{id}/plots/nope.svg"))).await;
    assert_eq!(status, 404, "{body}");

    // one simulation's plots
    let job = rows[0]["job_id"].as_str().unwrap();
    let sig = get_svg(
        &c,
        &s.url(&format!("/v1/simulations/{job}/plots/signal.svg")),
    )
    .await;
    assert!(
        sig.iter().any(|t| t == "time (s)") && sig.iter().any(|t| t.contains("m/s^2")),
        "{sig:?}"
    );
    let spec = get_svg(
        &c,
        &s.url(&format!("/v1/simulations/{job}/plots/spectrum.svg")),
    )
    .await;
    for want in ["BPFO", "BPFI", "BPFO×2", "FTF", "frequency (Hz)"] {
        assert!(spec.iter().any(|t| t == want), "{want} not in {spec:?}");
    }
    let k = get_svg(
        &c,
        &s.url(&format!("/v1/simulations/{job}/plots/kurtosis.svg")),
    )
    .await;
    assert!(k.iter().any(|t| t.contains("kurtosis")), "{k:?}");

    // the same study again shares every job; deleting the first keeps what the second holds
    let (status, _, again) = post_json(&c, &s.url("/v1/studies"), &small_study(0.03)).await;
    assert_eq!(status, 202, "{again}");
    assert_eq!(again["state"], "succeeded", "already done: {again}");
    let (_, _, sims) = get_json(&c, &s.url("/v1/simulations")).await;
    assert_eq!(sims["items"].as_array().unwrap().len(), 2);
    let metrics = get_text(&c, &s.url("/metrics")).await;
    assert!(
        metrics.contains("bearing_sim_study_points_shared_total 4"),
        "{metrics}"
    );
    assert!(
        metrics.contains("bearing_sim_study_jobs_queued_total 2"),
        "{metrics}"
    );
    // a point's job belongs to its studies
    let r = c
        .delete(s.url(&format!("/v1/simulations/{job}")))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 409);
    let r = c
        .delete(s.url(&format!("/v1/studies/{id}")))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 204);
    let (status, _, _) = get_json(&c, &s.url(&format!("/v1/studies/{id}"))).await;
    assert_eq!(status, 404);
    let (_, _, sims) = get_json(&c, &s.url("/v1/simulations")).await;
    assert_eq!(
        sims["items"].as_array().unwrap().len(),
        2,
        "the second study holds them"
    );
    let second = again["id"].as_str().unwrap();
    let r = c
        .delete(s.url(&format!("/v1/studies/{second}")))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 204);
    let (_, _, sims) = get_json(&c, &s.url("/v1/simulations")).await;
    assert_eq!(sims["items"].as_array().unwrap().len(), 0, "{sims}");
}

async fn h_etag(c: &reqwest::Client, s: &impl Service, id: &str) -> String {
    let (_, h, _) = get_json(c, &s.url(&format!("/v1/studies/{id}"))).await;
    h["etag"].to_str().unwrap().to_string()
}

#[tokio::test]
async fn cancelling_a_study_cancels_its_points() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "1"]);
    let c = client();
    let mut body = small_study(0.5);
    body["design"]["factors"][0]["values"] = json!([300.0, 350.0, 400.0]);
    let (status, _, st) = post_json(&c, &s.url("/v1/studies"), &body).await;
    assert_eq!(status, 202, "{st}");
    let id = st["id"].as_str().unwrap().to_string();
    wait_study(&c, &s, &id, Duration::from_secs(60), |st| {
        st["state"] == "running"
    })
    .await;
    let r = c
        .post(s.url(&format!("/v1/studies/{id}/cancel")))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 202);
    let done = wait_study(&c, &s, &id, Duration::from_secs(60), finished).await;
    assert_eq!(done["state"], "cancelled", "{done}");
    assert_eq!(done["progress"]["points_cancelled"], 3, "{done}");
    for p in done["points"].as_array().unwrap() {
        assert_eq!(p["state"], "cancelled", "{p}");
        assert_eq!(p["error"]["kind"], "cancelled");
    }
    // nothing left to cancel
    let r = c
        .post(s.url(&format!("/v1/studies/{id}/cancel")))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 409);
}

#[tokio::test]
async fn a_bad_point_is_named_and_nothing_is_queued() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "0"]);
    let c = client();
    let mut body = small_study(0.03);
    body["design"]["factors"][0]["values"] = json!([300.0, -5.0]);
    let (st, h, problem) = post_json(&c, &s.url("/v1/studies"), &body).await;
    assert_problem(st, &h, &problem, 422);
    let fields = error_paths(&problem);
    assert_eq!(
        fields,
        ["points[1].scene.operating.axial_load"],
        "{problem}"
    );
    // a pointer that names no field
    body["design"]["factors"][0]["pointer"] = json!("/operating/axial_lod");
    let (st, h, problem) = post_json(&c, &s.url("/v1/studies"), &body).await;
    assert_problem(st, &h, &problem, 422);
    assert_eq!(problem["errors"][0]["path"], "points[0].scene", "{problem}");
    assert!(
        problem["errors"][0]["message"]
            .as_str()
            .unwrap()
            .contains("axial_lod"),
        "{problem}"
    );
    // an unknown design member
    let (st, h, problem) = post_json(
        &c,
        &s.url("/v1/studies"),
        &json!({"base": {"preset": "h7005c"}, "design": {"type": "named", "name": "table3"}}),
    )
    .await;
    assert_problem(st, &h, &problem, 422);
    let (_, _, sims) = get_json(&c, &s.url("/v1/simulations")).await;
    assert_eq!(sims["items"].as_array().unwrap().len(), 0, "{sims}");
    let (status, _, _) = get_json(&c, &s.url("/v1/studies/nope")).await;
    assert_eq!(status, 404);
}

/// Run `bearing-sim study request` on `body` into a temporary directory; the directory
/// (kept alive by the returned guard) holds `table.json`, `table.csv` and the plots.
fn cli_study(body: &Value, args: &[&str]) -> (tempfile::TempDir, std::process::Output) {
    let dir = tempfile::tempdir().unwrap();
    let req = dir.path().join("request.json");
    std::fs::write(&req, serde_json::to_string(body).unwrap()).unwrap();
    let out = dir.path().join("out");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_bearing-sim"))
        .args(["study", "request", "--request"])
        .arg(&req)
        .arg("--out")
        .arg(&out)
        .args(args)
        .output()
        .unwrap();
    (dir, output)
}

/// Numbers equal to 1e-9 relative; everything else exactly. `skip` names members that
/// differ by nature (job ids, wall times). The 1e-9: the service stores the scene and the
/// record as JSON text and parses them back, which may move a float by an ulp.
fn same(a: &Value, b: &Value, skip: &[&str], at: &str) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys = |m: &serde_json::Map<String, Value>| -> Vec<String> {
                m.keys()
                    .filter(|k| !skip.contains(&k.as_str()))
                    .cloned()
                    .collect()
            };
            assert_eq!(keys(x), keys(y), "members at {at}");
            for k in keys(x) {
                same(&x[&k], &y[&k], skip, &format!("{at}.{k}"));
            }
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "length at {at}");
            for (i, (p, q)) in x.iter().zip(y).enumerate() {
                same(p, q, skip, &format!("{at}[{i}]"));
            }
        }
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!(
                (x - y).abs() <= 1e-9 * x.abs().max(y.abs()),
                "{at}: {x} against {y}"
            );
        }
        _ => assert_eq!(a, b, "at {at}"),
    }
}

#[tokio::test]
async fn the_cli_and_the_api_give_the_same_table_for_the_same_design() {
    // two short points of the outer-fault preset (30 ms: a 22.5 ms steady window)
    let body = axial_load_study(0.03, &[300.0, 400.0]);
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "2"]);
    let c = client();
    let (status, _, st) = post_json(&c, &s.url("/v1/studies"), &body).await;
    assert_eq!(status, 202, "{st}");
    let id = st["id"].as_str().unwrap().to_string();
    let done = wait_study(&c, &s, &id, Duration::from_secs(300), finished).await;
    assert_eq!(done["state"], "succeeded", "{done}");
    let (_, _, api) = get_json(&c, &s.url(&format!("/v1/studies/{id}/table"))).await;
    let api_csv = c
        .get(s.url(&format!("/v1/studies/{id}/table")))
        .header("accept", "text/csv")
        .send()
        .await
        .unwrap()
        .text()
        .await
        .unwrap();

    let (dir, output) = cli_study(&body, &["--workers", "2"]);
    assert!(output.status.success(), "{output:?}");
    let out = dir.path().join("out");
    let cli: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("table.json")).unwrap()).unwrap();
    let cli_csv = std::fs::read_to_string(out.join("table.csv")).unwrap();

    // the same table: name, factors, and per row every member and value but the job id
    // (a local run has none) and the solver's wall time
    assert_eq!(cli["name"], api["name"]);
    assert_eq!(cli["factors"], json!(["axial_load"]));
    same(&cli, &api, &["id", "job_id", "wall_time"], "table");
    assert_eq!(api["rows"].as_array().unwrap().len(), 2);
    assert!(api["rows"][1]["result"]["bpfo"]["theory_hz"].is_number());
    // the same CSV columns, and the same cells but those
    let (cl, al): (Vec<&str>, Vec<&str>) = (cli_csv.lines().collect(), api_csv.lines().collect());
    assert_eq!(cl.len(), 3, "{cli_csv}");
    assert_eq!(cl[0], al[0], "CSV headers");
    let header: Vec<&str> = cl[0].split(',').collect();
    for (c_line, a_line) in cl[1..].iter().zip(&al[1..]) {
        for ((h, x), y) in header.iter().zip(c_line.split(',')).zip(a_line.split(',')) {
            match *h {
                "job_id" | "wall_time_s" => {}
                _ => match (x.parse::<f64>(), y.parse::<f64>()) {
                    (Ok(x), Ok(y)) => {
                        assert!(
                            (x - y).abs() <= 1e-9 * x.abs().max(y.abs()),
                            "{h}: {x} against {y}"
                        )
                    }
                    _ => assert_eq!(x, y, "{h}"),
                },
            }
        }
    }
    // and the same plots
    for name in ["axial_load-outer.svg", "spectra.svg"] {
        assert!(done["links"][format!("plot:{name}")].is_string(), "{name}");
        assert!(out.join(name).is_file(), "{name}");
    }
}

#[tokio::test]
async fn the_cli_and_the_api_give_the_same_row_for_a_failed_point() {
    // Fixed-step RK4 at 1e-4 s is far above the contact modes' stability limit (~1e-6 s):
    // the run goes non-finite within a few steps, in the service and in-process alike.
    let body = json!({
        "name": "unstable step",
        "base": {"preset": "h7005c", "fault_case": "outer",
                 "overrides": {"solver": {"duration": 0.01, "integrator": "rk4_fixed"}}},
        "design": {"type": "one_at_a_time", "factors": [
            {"name": "initial_step", "pointer": "/solver/initial_step", "values": [1e-4]}
        ]}
    });
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(&db, &["--workers", "1"]);
    let c = client();
    let (status, _, st) = post_json(&c, &s.url("/v1/studies"), &body).await;
    assert_eq!(status, 202, "{st}");
    let id = st["id"].as_str().unwrap().to_string();
    wait_study(&c, &s, &id, Duration::from_secs(120), finished).await;
    let (_, _, api) = get_json(&c, &s.url(&format!("/v1/studies/{id}/table"))).await;
    assert_eq!(api["rows"][0]["state"], "failed", "{api}");
    let error = api["rows"][0]["error"].as_str().unwrap_or_default();
    assert!(error.starts_with("numerical: "), "{error}");

    let (dir, output) = cli_study(&body, &[]);
    assert!(output.status.success(), "{output:?}");
    let cli: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("out").join("table.json")).unwrap(),
    )
    .unwrap();
    // the same row: state, the job's failure kind and message, no result
    same(&cli, &api, &["id", "job_id", "wall_time"], "table");
}

#[test]
fn the_cli_stops_a_point_at_its_budget_and_lists_it_as_failed() {
    // 10 s simulated cannot finish in 0.3 s of wall time
    let (dir, output) = cli_study(
        &axial_load_study(10.0, &[300.0]),
        &["--point-budget", "0.3"],
    );
    assert!(output.status.success(), "{output:?}");
    let table: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("out/table.json")).unwrap())
            .unwrap();
    let row = &table["rows"][0];
    assert_eq!(row["state"], "failed", "{row}");
    assert!(row["result"].is_null(), "{row}");
    let e = row["error"].as_str().unwrap();
    assert!(
        e.contains("wall-time budget") && e.contains("of 10 s simulated"),
        "{e}"
    );
}
