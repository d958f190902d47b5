//! Issue 12's attacks, each reproduced against the service and shown to fail: orphaned
//! direct work, scenes over the cost budget, jobs over the wall-clock budget.

use crate::common::*;
use serde_json::{json, Value};
use std::io::Write;
use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Seconds from submission to a finished job, and the job.
async fn timed_run(c: &reqwest::Client, app: &TestApp, body: &Value) -> (f64, Value) {
    let t = Instant::now();
    let id = submit(c, app, body).await;
    let job = wait_finished(c, app, &id, Duration::from_secs(300)).await;
    (t.elapsed().as_secs_f64(), job)
}

fn metric(text: &str, name: &str) -> f64 {
    text.lines()
        .find_map(|l| l.strip_prefix(name)?.strip_prefix(' ')?.trim().parse().ok())
        .unwrap_or_else(|| panic!("no {name} in\n{text}"))
}

/// One attacker: post a direct analysis (1 MiB of f32 samples, 16 levels, answered in the
/// request) and go away 120 ms later, over and over until `stop`.
fn disconnect_flood(addr: String, stop: Arc<AtomicBool>, sent: Arc<AtomicUsize>) {
    let body: Vec<u8> = (0..262_144)
        .flat_map(|i| ((i as f32 * 0.37).sin()).to_le_bytes())
        .collect();
    let head = format!(
        "POST /v1/analyses?sample_rate=48000&preset=cwru6205&shaft_rpm=1797&levels=16 HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/octet-stream\r\nContent-Length: {}\r\n\r\n",
        body.len()
    );
    while !stop.load(Ordering::SeqCst) {
        let Ok(mut s) = TcpStream::connect(&addr) else {
            continue;
        };
        if s.write_all(head.as_bytes()).is_err() || s.write_all(&body).is_err() {
            continue;
        }
        sent.fetch_add(1, Ordering::SeqCst);
        std::thread::sleep(Duration::from_millis(120));
        drop(s);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn direct_work_of_clients_that_went_away_stops_and_does_not_starve_the_jobs() {
    let (_dir, db) = temp_db();
    // one worker and one direct thread: on a 2-core machine each has a core, as in a
    // deployment with the defaults
    let app = TestApp::spawn(&db, &["--workers", "1", "--direct-concurrency", "1"]);
    let c = client();
    let scene = short_scene(0.02);

    let (alone, job) = timed_run(&c, &app, &scene).await;
    assert_eq!(job["state"], "succeeded", "{job}");

    let stop = Arc::new(AtomicBool::new(false));
    let sent = Arc::new(AtomicUsize::new(0));
    let addr = app.base.trim_start_matches("http://").to_string();
    let attackers: Vec<_> = (0..40)
        .map(|_| {
            let (a, s, n) = (addr.clone(), stop.clone(), sent.clone());
            std::thread::spawn(move || disconnect_flood(a, s, n))
        })
        .collect();
    tokio::time::sleep(Duration::from_secs(2)).await;
    let (flooded, job) = timed_run(&c, &app, &scene).await;
    stop.store(true, Ordering::SeqCst);
    for a in attackers {
        a.join().unwrap();
    }
    assert_eq!(job["state"], "succeeded", "{job}");
    let attacks = sent.load(Ordering::SeqCst);
    assert!(attacks >= 40, "the flood sent only {attacks} requests");
    // Before the fix this run took 100x its time alone (64 s against 0.6 s): the orphaned
    // analyses piled up on the blocking threads the worker also needs. Now at most one
    // direct computation runs, and each stops within a level of its client leaving; 4x
    // leaves room for the attackers' own threads and a noisy shared machine.
    assert!(
        flooded < 4.0 * alone.max(0.25),
        "the 20 ms simulation took {flooded:.2} s during the flood against {alone:.2} s alone"
    );

    // Nothing keeps running for nobody once the attack stops.
    let deadline = Instant::now() + Duration::from_secs(10);
    let text = loop {
        let text = get_text(&c, &app.url("/metrics")).await;
        if metric(&text, "bearing_sim_direct_running") == 0.0 || Instant::now() > deadline {
            break text;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    };
    assert_eq!(metric(&text, "bearing_sim_direct_running"), 0.0, "{text}");
    assert!(
        metric(&text, "bearing_sim_direct_cancelled_total") >= 1.0,
        "no direct computation was cancelled: {text}"
    );
    eprintln!("alone {alone:.2} s, during the flood {flooded:.2} s, {attacks} attacks");
}

#[tokio::test]
async fn a_scene_over_the_cost_budget_is_refused_naming_its_fields() {
    let (_dir, db) = temp_db();
    let app = TestApp::spawn(&db, &["--workers", "0"]);
    let c = client();
    // the scene: 10 s at a fixed step of 1e-12 s would run for decades
    let body = json!({"preset": "h7005c", "overrides": {"solver": {"duration": 10, "integrator": "rk4_fixed", "initial_step": 1e-12}}});
    let (st, h, p) = post_json(&c, &app.url("/v1/simulations"), &body).await;
    assert_problem(st, &h, &p, 422);
    assert_errors_name(
        &p,
        &["scene.solver.duration", "scene.solver.initial_step"],
        0,
        "--max-scene-evaluations",
    );
    // an adaptive scene with a tiny max_step names that field instead
    let body =
        json!({"preset": "h7005c", "overrides": {"solver": {"duration": 10, "max_step": 1e-10}}});
    let (st, _, p) = post_json(&c, &app.url("/v1/simulations"), &body).await;
    assert_eq!(st, 422, "{p}");
    assert_eq!(p["errors"][1]["path"], "scene.solver.max_step", "{p}");
    // the same scene as a study point is refused with the point's path
    let mut study = axial_load_study(10.0, &[300.0, 400.0]);
    study["base"]["overrides"]["solver"]["max_step"] = json!(1e-10);
    let (st, _, p) = post_json(&c, &app.url("/v1/studies"), &study).await;
    assert_eq!(st, 422, "{p}");
    assert!(
        p["errors"][0]["path"]
            .as_str()
            .unwrap()
            .starts_with("points[0].scene.solver."),
        "{p}"
    );
    // a run whose output would be over the per-job storage limit names the output fields
    let body = json!({"preset": "h7005c", "overrides": {
        "solver": {"duration": 10, "sample_rate": 500000},
        "outputs": {"cage_speed": true, "inner_ring_displacement": true, "contact_loads_ball": 0}}});
    let (st, _, p) = post_json(&c, &app.url("/v1/simulations"), &body).await;
    assert_eq!(st, 422, "{p}");
    assert_errors_name(
        &p,
        &["scene.solver.duration", "scene.solver.sample_rate"],
        1,
        "--max-job-bytes",
    );
    // a normal scene is within the default budget
    let (st, _, p) = post_json(&c, &app.url("/v1/simulations"), &short_scene(0.5)).await;
    assert_eq!(st, 202, "{p}");
}

#[tokio::test]
async fn a_job_over_the_wall_clock_limit_fails_saying_so() {
    let (_dir, db) = temp_db();
    let app = TestApp::spawn(&db, &["--workers", "1", "--job-time-limit", "0.5"]);
    let c = client();
    // 0.5 s simulated takes several seconds of solver time
    let id = submit(&c, &app, &short_scene(0.5)).await;
    let job = wait_finished(&c, &app, &id, Duration::from_secs(60)).await;
    assert_eq!(job["state"], "failed", "{job}");
    assert_eq!(job["error"]["kind"], "time_limit", "{job}");
    let msg = job["error"]["message"].as_str().unwrap();
    assert!(
        msg.contains("0.5 s") && msg.contains("--job-time-limit"),
        "{msg}"
    );
    // stopped on the way, not run to the end
    assert!(job["progress"].as_f64().unwrap() < 1.0, "{job}");
}

/// Read until the server closes the connection (EOF or reset), or `timeout`; true if it
/// closed. Whatever the server answered is appended to `got`.
fn closed_within(s: &mut TcpStream, timeout: Duration, got: &mut Vec<u8>) -> bool {
    use std::io::Read;
    let deadline = Instant::now() + timeout;
    let mut buf = [0u8; 4096];
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return false;
        }
        s.set_read_timeout(Some(left)).unwrap();
        match s.read(&mut buf) {
            Ok(0) => return true,
            Ok(n) => got.extend_from_slice(&buf[..n]),
            Err(e)
                if e.kind() == std::io::ErrorKind::WouldBlock
                    || e.kind() == std::io::ErrorKind::TimedOut =>
            {
                return false
            }
            Err(_) => return true, // reset
        }
    }
}

/// `GET /healthz` over a fresh connection: the status line's code, or None.
fn healthz_status(addr: &str) -> Option<u16> {
    use std::io::Read;
    let mut s = TcpStream::connect(addr).ok()?;
    s.set_read_timeout(Some(Duration::from_secs(5))).ok()?;
    s.write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n")
        .ok()?;
    let mut reply = String::new();
    let _ = s.read_to_string(&mut reply);
    reply.split_whitespace().nth(1)?.parse().ok()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn idle_and_half_sent_connections_are_closed_and_long_polls_are_not() {
    let (_dir, db) = temp_db();
    let app = TestApp::spawn(
        &db,
        &[
            "--workers",
            "0",
            "--header-timeout",
            "1",
            "--request-timeout",
            "1",
        ],
    );
    let addr = app.base.trim_start_matches("http://").to_string();
    let c = client();

    // silent sockets, half a header, and a keep-alive connection idle after one request
    let mut silent: Vec<TcpStream> = (0..100)
        .map(|_| TcpStream::connect(&addr).unwrap())
        .collect();
    let mut half: Vec<TcpStream> = (0..20)
        .map(|_| {
            let mut s = TcpStream::connect(&addr).unwrap();
            s.write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\nX-Slow: ")
                .unwrap();
            s
        })
        .collect();
    let mut kept = TcpStream::connect(&addr).unwrap();
    kept.write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n")
        .unwrap();
    // a body promised and never sent: the request timeout answers it
    let mut slow_body = TcpStream::connect(&addr).unwrap();
    slow_body
        .write_all(b"POST /v1/simulations HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: 1000\r\n\r\n{\"preset\"")
        .unwrap();
    // the service still answers while they are open
    assert_eq!(healthz_status(&addr), Some(200));

    // a long poll longer than the header timeout is not cut
    let id = submit(&c, &app, &short_scene(0.02)).await; // no worker: stays queued
    let (_, h, _) = get_json(&c, &app.url(&format!("/v1/simulations/{id}"))).await;
    let etag = h.get("etag").unwrap().to_str().unwrap().to_string();
    let t = Instant::now();
    let r = c
        .get(app.url(&format!("/v1/simulations/{id}?wait=2.5")))
        .header("if-none-match", &etag)
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 304);
    assert!(t.elapsed() >= Duration::from_secs(2), "{:?}", t.elapsed());

    // by now (2.5 s, header timeout 1 s) every idle connection must have been closed;
    // 3 s more of grace covers a loaded machine
    let grace = Duration::from_secs(3);
    for (i, s) in silent.iter_mut().enumerate() {
        assert!(
            closed_within(s, grace, &mut Vec::new()),
            "silent socket {i} still open"
        );
    }
    for (i, s) in half.iter_mut().enumerate() {
        assert!(
            closed_within(s, grace, &mut Vec::new()),
            "half-header socket {i} still open"
        );
    }
    let mut got = Vec::new();
    assert!(
        closed_within(&mut kept, grace, &mut got),
        "idle keep-alive connection still open"
    );
    assert!(String::from_utf8_lossy(&got).starts_with("HTTP/1.1 200"));
    let mut got = Vec::new();
    assert!(
        closed_within(&mut slow_body, grace, &mut got),
        "slow body still open"
    );
    let got = String::from_utf8_lossy(&got);
    assert!(got.starts_with("HTTP/1.1 408"), "{got}");
    assert!(got.contains("application/problem+json"), "{got}");

    let text = get_text(&c, &app.url("/metrics")).await;
    assert!(
        metric(&text, "bearing_sim_connections_open") <= 2.0,
        "{text}"
    );
}

#[tokio::test]
async fn connections_over_the_bound_get_a_503_and_the_rest_keep_working() {
    let (_dir, db) = temp_db();
    let app = TestApp::spawn(
        &db,
        &[
            "--workers",
            "0",
            "--max-connections",
            "20",
            // The held sockets must outlive the accept of the one over the bound: at 1 s a
            // loaded CI machine once accepted it after they had timed out (no 503, an idle
            // close instead).
            "--header-timeout",
            "4",
        ],
    );
    let addr = app.base.trim_start_matches("http://").to_string();
    // One address holds at most 18 of the 20 (an eighth kept for others), so 2 of the held
    // sockets are refused. A connection that has just closed (the start-up probe's) still
    // holds its slot until its task ends; on a loaded machine a third held socket was then
    // refused in its place, and the one over the bound took the freed slot (no 503; seen
    // 5 runs in 6 beside a busy core). So the held set is opened again until exactly the
    // two over the address's share were refused.
    let answered = |s: &TcpStream| {
        s.set_nonblocking(true).unwrap();
        let r = s.peek(&mut [0u8; 1]);
        s.set_nonblocking(false).unwrap();
        r.is_ok()
    };
    let mut attempts = 0;
    let hold = loop {
        let hold: Vec<TcpStream> = (0..20)
            .map(|_| TcpStream::connect(&addr).unwrap())
            .collect();
        std::thread::sleep(Duration::from_millis(200));
        let refused = hold.iter().filter(|s| answered(s)).count();
        if refused <= 2 {
            break hold;
        }
        attempts += 1;
        assert!(
            attempts < 10,
            "{refused} of the held sockets refused, every time"
        );
        drop(hold);
        std::thread::sleep(Duration::from_millis(300));
    };
    let mut over = TcpStream::connect(&addr).unwrap();
    let mut got = Vec::new();
    assert!(closed_within(&mut over, Duration::from_secs(5), &mut got));
    let got = String::from_utf8_lossy(&got);
    assert!(got.starts_with("HTTP/1.1 503"), "{got}");
    assert!(
        got.contains("application/problem+json") && got.contains("--max-connections"),
        "{got}"
    );
    // once the header timeout has closed the idle ones, the service answers again
    let deadline = Instant::now() + Duration::from_secs(10);
    while healthz_status(&addr) != Some(200) {
        assert!(Instant::now() < deadline, "healthz never recovered");
        std::thread::sleep(Duration::from_millis(100));
    }
    drop(hold);
    let text = get_text(&client(), &app.url("/metrics")).await;
    assert!(
        metric(&text, "bearing_sim_connections_refused_total") >= 1.0,
        "{text}"
    );
}

#[test]
fn idle_sockets_cannot_exhaust_a_small_descriptor_limit() {
    // The case: under a 256-descriptor limit, 300 idle sockets made /healthz time
    // out. The real binary, started under that limit, bounds its connections below it.
    use std::io::{BufRead, BufReader};
    let (dir, db) = temp_db();
    let log = dir.path().join("serve.log");
    let mut child = std::process::Command::new("sh")
        .arg("-c")
        .arg("ulimit -n 256 && exec \"$0\" serve --bind 127.0.0.1:0 --workers 1 --header-timeout 2 --log-format json --database-url \"$1\"")
        .arg(env!("CARGO_BIN_EXE_bearing-sim"))
        .arg(format!("sqlite://{}", db.display()))
        .env_remove("BEARING_SIM_MAX_CONNECTIONS")
        .stdout(std::process::Stdio::piped())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let base = loop {
        let line = lines.next().expect("server exited").unwrap();
        if let Some(url) = line.strip_prefix("listening on ") {
            break url.trim().trim_start_matches("http://").to_string();
        }
    };
    let mut idle = Vec::new();
    for _ in 0..300 {
        if let Ok(s) = TcpStream::connect(&base) {
            idle.push(s);
        }
    }
    // the connections past the bound were answered 503 at once, not left hanging
    std::thread::sleep(Duration::from_millis(300));
    let status = healthz_status(&base);
    assert!(
        matches!(status, Some(503) | Some(200)),
        "healthz during the flood: {status:?}"
    );
    // after the header timeout every idle socket is closed and the service answers
    let grace = Duration::from_secs(6);
    let still_open = idle
        .iter()
        .filter(|s| !closed_within(&mut s.try_clone().unwrap(), grace, &mut Vec::new()))
        .count();
    assert_eq!(still_open, 0);
    assert_eq!(healthz_status(&base), Some(200));
    let _ = child.kill();
    let _ = child.wait();
    let text = std::fs::read_to_string(&log).unwrap();
    assert!(text.contains("\"max_connections\":128"), "{text}");
    assert!(!text.contains("Too many open files"), "{text}");
}

#[tokio::test]
async fn errors_from_the_http_layer_are_problem_json() {
    let (_dir, db) = temp_db();
    let app = TestApp::spawn(&db, &["--workers", "0"]);
    let addr = app.base.trim_start_matches("http://").to_string();
    // the 1 MB header
    let mut s = TcpStream::connect(&addr).unwrap();
    let big = "a".repeat(1 << 20);
    let _ =
        s.write_all(format!("GET /healthz HTTP/1.1\r\nHost: x\r\nX-Big: {big}\r\n\r\n").as_bytes());
    let mut got = Vec::new();
    closed_within(&mut s, Duration::from_secs(10), &mut got);
    let got = String::from_utf8_lossy(&got);
    assert!(got.starts_with("HTTP/1.1 431"), "{got}");
    assert!(
        got.contains("application/problem+json") && got.contains("\"status\":431"),
        "{got}"
    );
    // a malformed request line
    let mut s = TcpStream::connect(&addr).unwrap();
    s.write_all(b"GET /healthz HTTP/1.1\r\nHost x\r\n\r\n")
        .unwrap();
    let mut got = Vec::new();
    closed_within(&mut s, Duration::from_secs(10), &mut got);
    let got = String::from_utf8_lossy(&got);
    assert!(got.starts_with("HTTP/1.1 400"), "{got}");
    assert!(got.contains("application/problem+json"), "{got}");
}

#[tokio::test]
async fn with_tokens_each_client_sees_and_changes_only_its_own_jobs() {
    let (list, a, b) = two_tokens();
    let (_dir, db) = temp_db();
    let app = TestApp::spawn(&db, &["--workers", "0", "--tokens", &list]);
    let c = client();
    let sims = app.url("/v1/simulations");

    // anonymous and unknown tokens are refused, with a problem and a challenge
    for req in [
        c.post(&sims).json(&short_scene(0.02)),
        c.get(&sims),
        c.get(&sims).bearer_auth("bs_not-a-token"),
        c.get(&sims).header("authorization", "Basic YTpi"),
    ] {
        let r = req.send().await.unwrap();
        let challenge = r.headers().get("www-authenticate").cloned();
        let (st, h, p) = decode(r).await;
        assert_problem(st, &h, &p, 401);
        assert!(challenge.is_some(), "{p}");
    }
    // health, metrics and the API document stay open
    for path in ["/healthz", "/metrics", "/openapi.yaml"] {
        assert_eq!(
            c.get(app.url(path)).send().await.unwrap().status(),
            200,
            "{path}"
        );
    }

    let r = c
        .post(&sims)
        .bearer_auth(a)
        .json(&short_scene(0.02))
        .send()
        .await
        .unwrap();
    let (st, _, job) = decode(r).await;
    assert_eq!(st, 202, "{job}");
    let id = job["id"].as_str().unwrap().to_string();
    let one = app.url(&format!("/v1/simulations/{id}"));

    // lab-b can neither see, list, cancel nor delete it: to b it does not exist
    let r = c.get(&one).bearer_auth(b).send().await.unwrap();
    assert_eq!(r.status(), 404);
    let (_, _, page) = decode(c.get(&sims).bearer_auth(b).send().await.unwrap()).await;
    assert_eq!(page["items"].as_array().unwrap().len(), 0, "{page}");
    let r = c
        .post(format!("{one}/cancel"))
        .bearer_auth(b)
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 404);
    let r = c.delete(&one).bearer_auth(b).send().await.unwrap();
    assert_eq!(r.status(), 404);
    // lab-a can
    let (_, _, page) = decode(c.get(&sims).bearer_auth(a).send().await.unwrap()).await;
    assert_eq!(page["items"][0]["id"], id.as_str(), "{page}");
    let r = c
        .post(format!("{one}/cancel"))
        .bearer_auth(a)
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 202);

    // the same Idempotency-Key from two tenants names two different requests
    let post = |tok: &'static str, d: f64| {
        c.post(&sims)
            .bearer_auth(tok)
            .header("idempotency-key", "run-1")
            .json(&short_scene(d))
            .send()
    };
    let (sa, _, ja) = decode(post(a, 0.02).await.unwrap()).await;
    let (sb, _, jb) = decode(post(b, 0.03).await.unwrap()).await;
    assert_eq!((sa, sb), (202, 202), "{ja} {jb}");
    assert_ne!(ja["id"], jb["id"]);
    // and a replay by its own tenant finds its own job
    let (sa2, _, ja2) = decode(post(a, 0.02).await.unwrap()).await;
    assert_eq!(sa2, 200);
    assert_eq!(ja2["id"], ja["id"]);

    // studies too
    let study = axial_load_study(0.02, &[300.0]);
    let r = c
        .post(app.url("/v1/studies"))
        .bearer_auth(a)
        .json(&study)
        .send()
        .await
        .unwrap();
    let (st, _, s) = decode(r).await;
    assert_eq!(st, 202, "{s}");
    let sid = s["id"].as_str().unwrap();
    let r = c
        .get(app.url(&format!("/v1/studies/{sid}")))
        .bearer_auth(b)
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 404);
    let (_, _, page) = decode(
        c.get(app.url("/v1/studies"))
            .bearer_auth(b)
            .send()
            .await
            .unwrap(),
    )
    .await;
    assert_eq!(page["items"].as_array().unwrap().len(), 0, "{page}");
    // b's identical study does not share a's job
    let r = c
        .post(app.url("/v1/studies"))
        .bearer_auth(b)
        .json(&study)
        .send()
        .await
        .unwrap();
    let (_, _, sb) = decode(r).await;
    assert_ne!(sb["points"][0]["job_id"], s["points"][0]["job_id"], "{sb}");
}

#[tokio::test]
async fn open_reads_let_a_dashboard_read_without_a_token_but_not_write() {
    let (list, a, _) = two_tokens();
    let (_dir, db) = temp_db();
    let app = TestApp::spawn(&db, &["--workers", "0", "--tokens", &list, "--open-reads"]);
    let c = client();
    let sims = app.url("/v1/simulations");
    let r = c
        .post(&sims)
        .bearer_auth(a)
        .json(&short_scene(0.02))
        .send()
        .await
        .unwrap();
    let (_, _, job) = decode(r).await;
    let (st, _, page) = get_json(&c, &sims).await;
    assert_eq!(st, 200);
    assert_eq!(page["items"][0]["id"], job["id"], "{page}");
    let (st, h, p) = post_json(&c, &sims, &short_scene(0.02)).await;
    assert_problem(st, &h, &p, 401);
    let id = job["id"].as_str().unwrap();
    let r = c
        .delete(app.url(&format!("/v1/simulations/{id}")))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 401);
}

#[test]
fn binding_beyond_loopback_without_tokens_warns_loudly() {
    let (_dir, db) = temp_db();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_bearing-sim"))
        .args([
            "serve",
            "--bind",
            "0.0.0.0:0",
            "--workers",
            "0",
            "--database-url",
        ])
        .arg(format!("sqlite://{}", db.display()))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    use std::io::{BufRead, BufReader};
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let first = lines.next().unwrap().unwrap();
    let _ = child.kill();
    let _ = child.wait();
    assert!(
        first.starts_with("WARNING") && first.contains("WITHOUT API TOKENS"),
        "{first}"
    );
}

#[test]
fn a_bad_tokens_file_stops_the_service_before_it_serves() {
    let (dir, db) = temp_db();
    let file = dir.path().join("tokens");
    std::fs::write(&file, "lab-a:not-a-hash\n").unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_bearing-sim"))
        .args([
            "serve",
            "--bind",
            "127.0.0.1:0",
            "--workers",
            "0",
            "--database-url",
        ])
        .arg(format!("sqlite://{}", db.display()))
        .arg("--tokens-file")
        .arg(&file)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("line 1") && err.contains("64 hex digits"),
        "{err}"
    );
}

#[tokio::test]
async fn finished_work_expires_after_the_retention_time() {
    let (_dir, db) = temp_db();
    let app = TestApp::spawn(&db, &["--workers", "1", "--retention", "1"]);
    let c = client();
    let id = submit(&c, &app, &short_scene(0.02)).await;
    let job = wait_finished(&c, &app, &id, Duration::from_secs(60)).await;
    assert_eq!(job["state"], "succeeded", "{job}");
    let study = axial_load_study(0.02, &[300.0]);
    let (st, _, s) = post_json(&c, &app.url("/v1/studies"), &study).await;
    assert_eq!(st, 202, "{s}");
    let study_path = format!("/v1/studies/{}", s["id"].as_str().unwrap());
    // 1 s after finishing, swept every 0.25 s: gone within a few seconds
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        let (sj, _, _) = get_json(&c, &app.url(&format!("/v1/simulations/{id}"))).await;
        let (ss, _, _) = get_json(&c, &app.url(&study_path)).await;
        if sj == 404 && ss == 404 {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "still there: job {sj}, study {ss}\n{}",
            app.log()
        );
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    let text = get_text(&c, &app.url("/metrics")).await;
    assert!(
        metric(&text, "bearing_sim_jobs_expired_total") >= 2.0,
        "{text}"
    );
    assert_eq!(metric(&text, "bearing_sim_store_bytes"), 0.0, "{text}");
}

#[tokio::test]
async fn a_full_store_refuses_new_work_with_507() {
    let (_dir, db) = temp_db();
    let app = TestApp::spawn(&db, &["--workers", "1", "--max-store-bytes", "20000"]);
    let c = client();
    let id = submit(&c, &app, &short_scene(0.02)).await;
    wait_finished(&c, &app, &id, Duration::from_secs(60)).await;
    let text = get_text(&c, &app.url("/metrics")).await;
    assert!(
        metric(&text, "bearing_sim_store_bytes") > 20_000.0,
        "{text}"
    );
    let (st, h, p) = post_json(&c, &app.url("/v1/simulations"), &short_scene(0.02)).await;
    assert_problem(st, &h, &p, 507);
    assert!(
        p["detail"].as_str().unwrap().contains("--max-store-bytes"),
        "{p}"
    );
    // deleting frees the room
    let r = c
        .delete(app.url(&format!("/v1/simulations/{id}")))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 204);
    let (st, _, p) = post_json(&c, &app.url("/v1/simulations"), &short_scene(0.02)).await;
    assert_eq!(st, 202, "{p}");
}

/// Peak resident memory of a process, bytes (Linux).
fn peak_rss(pid: u32) -> u64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap();
    let kb: u64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap();
    kb * 1024
}

#[tokio::test]
async fn the_largest_accepted_analysis_stays_under_its_memory_bound() {
    let (_dir, db) = temp_db();
    let server = Server::start(&db, &["--workers", "1"]);
    let c = client();
    let url = |n_levels: usize| {
        server.url(&format!(
            "/v1/analyses?sample_rate=48000&preset=cwru6205&shaft_rpm=1797&levels={n_levels}"
        ))
    };
    // just under the default per-job limit (128 MiB): 3.1e6 samples at 16 levels store
    // 130 MB (the 33 MB JSON analysis stored 334 MB and peaked at 3.7 GB)
    let n = 3_100_000;
    let body: Vec<u8> = (0..n)
        .flat_map(|i| ((i as f32 * 0.37).sin() + ((i * 7919) % 13) as f32 * 0.01).to_le_bytes())
        .collect();
    let r = c
        .post(url(16))
        .header("content-type", "application/octet-stream")
        .body(body.clone())
        .send()
        .await
        .unwrap();
    let (st, _, job) = decode(r).await;
    assert_eq!(st, 202, "{job}");
    let id = job["id"].as_str().unwrap();
    let job = wait_for(
        &c,
        &server,
        &format!("/v1/analyses/{id}"),
        Duration::from_secs(300),
        |j| matches!(j["state"].as_str(), Some("succeeded" | "failed")),
    )
    .await;
    assert_eq!(job["state"], "succeeded", "{job}");
    let peak = peak_rss(server.pid());
    // docs/reference/operations.md states 1.25 GiB for an analysis at the per-job limit (measured
    // 0.96 GB for 3e6 samples at 16 levels on the development machine)
    assert!(peak < 1_342_177_280, "peak RSS {peak} bytes");
    eprintln!("peak RSS {:.0} MB", peak as f64 / 1e6);

    // a little more is refused up front, naming what to change
    let more: Vec<u8> = body.iter().chain(&body[..800_000]).copied().collect();
    let r = c
        .post(url(16))
        .header("content-type", "application/octet-stream")
        .body(more)
        .send()
        .await
        .unwrap();
    let (st, h, p) = decode(r).await;
    assert_problem(st, &h, &p, 422);
    assert_eq!(p["errors"][0]["path"], "samples", "{p}");
    assert_eq!(p["errors"][1]["path"], "options.levels", "{p}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn large_transfers_wait_their_turn_and_max_points_is_bounded() {
    let (_dir, db) = temp_db();
    let app = TestApp::spawn(
        &db,
        &[
            "--workers",
            "1",
            "--max-large-transfers",
            "1",
            "--request-timeout",
            "2",
        ],
    );
    let c = client();
    let id = submit(&c, &app, &short_scene(0.02)).await;
    wait_finished(&c, &app, &id, Duration::from_secs(60)).await;
    let signals = app.url(&format!(
        "/v1/simulations/{id}/signals?channel=outer_ring_accel_z"
    ));
    // the 1 000 000 points are over the bound now
    let (st, h, p) = get_json(&c, &format!("{signals}&max_points=1000000")).await;
    assert_problem(st, &h, &p, 400);
    assert!(p["detail"].as_str().unwrap().contains("200000"), "{p}");

    // a 2 MB upload that stalls holds the only large-transfer permit until its request
    // timeout (2 s) answers it; a signal read meanwhile waits for the permit, then succeeds
    let addr = app.base.trim_start_matches("http://").to_string();
    let mut upload = TcpStream::connect(&addr).unwrap();
    upload
        .write_all(b"POST /v1/analyses?sample_rate=48000&preset=cwru6205&shaft_rpm=1797 HTTP/1.1\r\nHost: x\r\nContent-Type: application/octet-stream\r\nContent-Length: 2000000\r\n\r\n0123")
        .unwrap();
    tokio::time::sleep(Duration::from_millis(300)).await;
    let t = Instant::now();
    let (st, _, body) = get_json(&c, &signals).await;
    assert_eq!(st, 200, "{body}");
    // it could not start before the upload's permit was released, ~1.7 s from now
    assert!(
        t.elapsed() >= Duration::from_millis(1200),
        "{:?}",
        t.elapsed()
    );
    let mut got = Vec::new();
    closed_within(&mut upload, Duration::from_secs(5), &mut got);
    assert!(
        String::from_utf8_lossy(&got).starts_with("HTTP/1.1 408"),
        "{}",
        String::from_utf8_lossy(&got)
    );
}
