//! Helpers for the service tests: the service under test ([`TestApp`] in-process, or
//! [`Server`], the real `bearing-sim serve` binary, for tests of process signals), and
//! HTTP helpers that work with either.

use serde_json::{json, Value};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A `bearing-sim serve` process and the base URL it listens on.
pub struct Server {
    process: Process,
    pub base: String,
}

impl std::ops::Deref for Server {
    type Target = Process;
    fn deref(&self) -> &Process {
        &self.process
    }
}

impl std::ops::DerefMut for Server {
    fn deref_mut(&mut self) -> &mut Process {
        &mut self.process
    }
}

/// A log file next to `db` that no other process of this test writes.
pub fn unique_log(db: &Path) -> PathBuf {
    db.with_extension(format!(
        "log{}",
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap()
            .as_nanos()
    ))
}

/// Spawn `bearing-sim <command...> --database-url <url> <args>` with stderr to `log`, and
/// wait for the stdout line starting with `ready` (returns what follows it).
fn spawn_until(
    command: &[&str],
    url: &str,
    log: &Path,
    args: &[&str],
    ready: &str,
) -> (Child, String) {
    let log_file = std::fs::File::create(log).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_bearing-sim"))
        .args(command)
        .args(["--database-url", url])
        .args(args)
        .env_remove("BEARING_SIM_BIND")
        .env_remove("BEARING_SIM_DATABASE_URL")
        .env_remove("BEARING_SIM_WORKERS")
        .stdout(Stdio::piped())
        .stderr(Stdio::from(log_file))
        .spawn()
        .expect("spawn bearing-sim");
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let rest = loop {
        match lines.next() {
            Some(Ok(line)) => {
                if let Some(rest) = line.strip_prefix(ready) {
                    break rest.trim().to_string();
                }
            }
            _ => panic!(
                "bearing-sim {command:?} exited before {ready:?}; log:\n{}",
                std::fs::read_to_string(log).unwrap_or_default()
            ),
        }
    };
    // Keep draining stdout so the child never blocks on a full pipe.
    std::thread::spawn(move || for _ in lines {});
    (child, rest)
}

/// A child `bearing-sim` process and its log file; killed (SIGKILL) when dropped.
pub struct Process {
    child: Child,
    pub log: PathBuf,
}

impl Process {
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// SIGKILL: no shutdown code runs, as in a crash.
    pub fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }

    /// SIGTERM and wait for the process to exit.
    pub fn terminate(&mut self) -> std::process::ExitStatus {
        let _ = Command::new("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status();
        self.child.wait().unwrap()
    }

    pub fn log(&self) -> String {
        std::fs::read_to_string(&self.log).unwrap_or_default()
    }
}

impl Drop for Process {
    fn drop(&mut self) {
        self.kill();
    }
}

/// A `bearing-sim worker` process (job workers only, no HTTP).
pub struct WorkerProcess(Process);

impl WorkerProcess {
    /// Start workers on the database at `url`; returns once they run.
    pub fn start(url: &str, log: &Path, args: &[&str]) -> WorkerProcess {
        let (child, _) = spawn_until(&["worker"], url, log, args, "worker ready:");
        WorkerProcess(Process {
            child,
            log: log.to_path_buf(),
        })
    }
}

impl std::ops::Deref for WorkerProcess {
    type Target = Process;
    fn deref(&self) -> &Process {
        &self.0
    }
}

impl std::ops::DerefMut for WorkerProcess {
    fn deref_mut(&mut self) -> &mut Process {
        &mut self.0
    }
}

impl Server {
    /// Start on `db` (a file path) with extra flags; returns once it listens.
    pub fn start(db: &Path, args: &[&str]) -> Server {
        Server::start_on(&format!("sqlite://{}", db.display()), &unique_log(db), args)
    }

    /// Start on the database at `url`, logging to `log`; returns once it listens.
    pub fn start_on(url: &str, log: &Path, args: &[&str]) -> Server {
        let (child, base) = spawn_until(
            &["serve", "--bind", "127.0.0.1:0"],
            url,
            log,
            args,
            "listening on ",
        );
        Server {
            process: Process {
                child,
                log: log.to_path_buf(),
            },
            base,
        }
    }

    pub fn url(&self, path: &str) -> String {
        format!("{}{}", self.base, path)
    }
}

/// A running service under test: in-process or a child process.
pub trait Service {
    fn url(&self, path: &str) -> String;
    /// Its log, for failure messages.
    fn log(&self) -> String;
}

impl Service for Server {
    fn url(&self, path: &str) -> String {
        Server::url(self, path)
    }
    fn log(&self) -> String {
        Process::log(self)
    }
}

impl Service for super::TestApp {
    fn url(&self, path: &str) -> String {
        super::TestApp::url(self, path)
    }
    fn log(&self) -> String {
        super::TestApp::log(self)
    }
}

pub fn client() -> reqwest::Client {
    reqwest::Client::builder()
        .timeout(Duration::from_secs(60))
        .build()
        .unwrap()
}

/// A short simulation request: the H7005C compound-fault preset, `duration` s.
pub fn short_scene(duration: f64) -> Value {
    json!({"preset": "h7005c", "fault_case": "compound", "overrides": {"solver": {"duration": duration}}})
}

/// A short run that reaches steady speed (5 ms ramp), so the summary's averages exist.
pub fn steady_scene(duration: f64) -> Value {
    json!({"preset": "h7005c", "fault_case": "compound",
           "overrides": {"operating": {"speed": {"ramp_time": 0.005}}, "solver": {"duration": duration}}})
}

/// A study of the outer-fault preset at `loads` axial loads (N), `duration` s each.
pub fn axial_load_study(duration: f64, loads: &[f64]) -> Value {
    json!({
        "name": "axial loads",
        "base": {"preset": "h7005c", "fault_case": "outer", "overrides": {"solver": {"duration": duration}}},
        "design": {"type": "one_at_a_time", "factors": [
            {"name": "axial_load", "pointer": "/operating/axial_load", "values": loads}
        ]}
    })
}

pub async fn post_json(
    c: &reqwest::Client,
    url: &str,
    body: &Value,
) -> (u16, reqwest::header::HeaderMap, Value) {
    decode(c.post(url).json(body).send().await.unwrap()).await
}

/// A long poll started in the background: `GET url?wait=30` with `If-None-Match: etag`,
/// answered when the resource changes (or after 30 s with 304).
pub fn spawn_long_poll(
    c: &reqwest::Client,
    url: &str,
    etag: &str,
) -> tokio::task::JoinHandle<reqwest::Response> {
    let (c, url, etag) = (c.clone(), url.to_string(), etag.to_string());
    tokio::spawn(async move {
        c.get(format!("{url}?wait=30"))
            .header("if-none-match", etag)
            .send()
            .await
            .unwrap()
    })
}

pub async fn get_json(c: &reqwest::Client, url: &str) -> (u16, reqwest::header::HeaderMap, Value) {
    decode(c.get(url).send().await.unwrap()).await
}

/// Status, headers and body (JSON, or the text as a JSON string) of a response.
pub async fn decode(r: reqwest::Response) -> (u16, reqwest::header::HeaderMap, Value) {
    let status = r.status().as_u16();
    let headers = r.headers().clone();
    let text = r.text().await.unwrap();
    (
        status,
        headers,
        serde_json::from_str(&text).unwrap_or(Value::String(text)),
    )
}

/// Body of a GET as text (metrics, the OpenAPI document).
pub async fn get_text(c: &reqwest::Client, url: &str) -> String {
    c.get(url).send().await.unwrap().text().await.unwrap()
}

pub async fn submit(c: &reqwest::Client, s: &impl Service, body: &Value) -> String {
    let (status, _, job) = post_json(c, &s.url("/v1/simulations"), body).await;
    assert_eq!(status, 202, "submit: {job}");
    job["id"].as_str().unwrap().to_string()
}

/// Poll a job until `pred` holds, panicking with the last state after `timeout`.
pub async fn wait_until(
    c: &reqwest::Client,
    s: &impl Service,
    id: &str,
    timeout: Duration,
    pred: impl Fn(&Value) -> bool,
) -> Value {
    wait_for(c, s, &format!("/v1/simulations/{id}"), timeout, pred).await
}

/// Poll a resource (a job or a study) until `pred` holds, panicking with the last answer
/// after `timeout`.
pub async fn wait_for(
    c: &reqwest::Client,
    s: &impl Service,
    path: &str,
    timeout: Duration,
    pred: impl Fn(&Value) -> bool,
) -> Value {
    let start = Instant::now();
    loop {
        let (status, _, body) = get_json(c, &s.url(path)).await;
        assert_eq!(status, 200, "{body}");
        if pred(&body) {
            return body;
        }
        if start.elapsed() > timeout {
            panic!("{path} did not reach the expected state within {timeout:?}: {body}\nserver log:\n{}", s.log());
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

pub async fn wait_finished(
    c: &reqwest::Client,
    s: &impl Service,
    id: &str,
    timeout: Duration,
) -> Value {
    wait_until(c, s, id, timeout, |j| {
        matches!(
            j["state"].as_str(),
            Some("succeeded" | "failed" | "cancelled")
        )
    })
    .await
}

/// The `path` of every entry of a 422's `errors[]` (panics, showing the body, without one).
pub fn error_paths(body: &Value) -> Vec<&str> {
    body["errors"]
        .as_array()
        .unwrap_or_else(|| panic!("no errors[]: {body}"))
        .iter()
        .map(|e| e["path"].as_str().unwrap())
        .collect()
}

/// A 422's `errors[]` names exactly `paths`, and error `index`'s message mentions `hint`
/// (the flag that sets the limit, say).
pub fn assert_errors_name(body: &Value, paths: &[&str], index: usize, hint: &str) {
    assert_eq!(error_paths(body), paths, "{body}");
    assert!(
        body["errors"][index]["message"]
            .as_str()
            .unwrap()
            .contains(hint),
        "{body}"
    );
}

/// Every problem response has the RFC 9457 members and content type.
pub fn assert_problem(status: u16, headers: &reqwest::header::HeaderMap, body: &Value, want: u16) {
    assert_eq!(status, want, "{body}");
    assert_eq!(
        headers.get("content-type").unwrap(),
        "application/problem+json",
        "{body}"
    );
    assert_eq!(body["status"].as_u64(), Some(want as u64), "{body}");
    for k in ["type", "title", "detail"] {
        assert!(body[k].is_string(), "problem lacks {k}: {body}");
    }
}

pub fn temp_db() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("jobs.db");
    (dir, db)
}

/// Two tokens as `--tokens` takes them, and the tokens themselves.
pub fn two_tokens() -> (String, &'static str, &'static str) {
    let (a, b) = ("bs_token-of-lab-a", "bs_token-of-lab-b");
    let list = format!(
        "lab-a:{},lab-b:{}",
        bearing_sim::config::hash_token(a),
        bearing_sim::config::hash_token(b)
    );
    (list, a, b)
}
