//! The service in-process, zero-to-production style: the real router, store and workers on
//! a loopback port 0 with a temporary database, on a runtime of its own (so a test's own
//! runtime, single-threaded or not, only drives the client).

use bearing_sim::config::Config;
use clap::Parser;
use std::path::Path;
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, Instant};

/// `bearing-sim serve` flags, parsed as the binary parses them.
#[derive(Parser)]
struct ServeFlags {
    #[command(flatten)]
    config: Config,
}

pub struct TestApp {
    pub base: String,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    stopped: mpsc::Receiver<String>,
    runtime: Option<tokio::runtime::Runtime>,
    log: Arc<Mutex<Vec<u8>>>,
}

/// Appends to an app's own log buffer.
struct LogWriter(Arc<Mutex<Vec<u8>>>);

impl std::io::Write for LogWriter {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.0.lock().unwrap().extend_from_slice(b);
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl TestApp {
    /// Serve on `db` (a file path) with extra `serve` flags; returns once `/healthz` answers.
    pub fn spawn(db: &Path, args: &[&str]) -> TestApp {
        TestApp::spawn_on(&format!("sqlite://{}", db.display()), args)
    }

    /// Serve on the database `url` names (SQLite or PostgreSQL), as [`TestApp::spawn`].
    pub fn spawn_on(url: &str, args: &[&str]) -> TestApp {
        // Each app logs into its own buffer (shown by `log()` in failure messages): every
        // thread of its runtime, blocking ones included, gets the app's subscriber.
        let log = Arc::new(Mutex::new(Vec::new()));
        let filter =
            std::env::var("BEARING_SIM_TEST_LOG").unwrap_or_else(|_| "info,sqlx=warn".into());
        let sink = log.clone();
        let dispatch = tracing::Dispatch::new(
            tracing_subscriber::fmt()
                .with_env_filter(tracing_subscriber::EnvFilter::new(filter))
                .with_ansi(false)
                .with_writer(move || LogWriter(sink.clone()))
                .finish(),
        );
        let mut argv = vec!["serve", "--bind", "127.0.0.1:0", "--database-url", url];
        argv.extend_from_slice(args);
        let config = ServeFlags::try_parse_from(argv)
            .unwrap_or_else(|e| panic!("bad test flags {args:?}: {e}"))
            .config;
        let workers = config.worker.worker_count();
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .on_thread_start(move || {
                // the thread's default for its whole life
                std::mem::forget(tracing::dispatcher::set_default(&dispatch));
            })
            .worker_threads(2)
            .max_blocking_threads(2 * workers.max(1) + 4)
            .enable_all()
            .build()
            .expect("test runtime");
        let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("bind loopback");
        listener.set_nonblocking(true).unwrap();
        let base = format!("http://{}", listener.local_addr().unwrap());
        let (stop_tx, stop_rx) = tokio::sync::oneshot::channel::<()>();
        let (done_tx, done_rx) = mpsc::channel();
        runtime.spawn(async move {
            let listener = tokio::net::TcpListener::from_std(listener).unwrap();
            let shutdown = async {
                let _ = stop_rx.await;
            };
            let outcome = bearing_sim::run_until(config, listener, shutdown).await;
            let _ = done_tx.send(match outcome {
                Ok(()) => String::new(),
                Err(e) => e.to_string(),
            });
        });
        let app = TestApp {
            base,
            stop: Some(stop_tx),
            stopped: done_rx,
            runtime: Some(runtime),
            log,
        };
        app.wait_healthy();
        app
    }

    fn wait_healthy(&self) {
        let deadline = Instant::now() + Duration::from_secs(30);
        let addr = self.base.trim_start_matches("http://").to_string();
        loop {
            if let Ok(err) = self.stopped.try_recv() {
                panic!("the app stopped before serving: {err}");
            }
            if healthz(&addr) {
                return;
            }
            assert!(
                Instant::now() < deadline,
                "the app did not answer /healthz within 30 s"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    pub fn url(&self, path: &str) -> String {
        format!("{}{}", self.base, path)
    }

    /// What the app logged so far (level from `BEARING_SIM_TEST_LOG`, default info).
    pub fn log(&self) -> String {
        String::from_utf8_lossy(&self.log.lock().unwrap()).into_owned()
    }
}

/// A plain HTTP/1.0 GET of /healthz (no client runtime needed).
fn healthz(addr: &str) -> bool {
    use std::io::{Read, Write};
    let Ok(mut s) = std::net::TcpStream::connect(addr) else {
        return false;
    };
    let _ = s.set_read_timeout(Some(Duration::from_secs(2)));
    if s.write_all(b"GET /healthz HTTP/1.0\r\n\r\n").is_err() {
        return false;
    }
    let mut reply = String::new();
    let _ = s.read_to_string(&mut reply);
    reply.starts_with("HTTP/1.1 200") || reply.starts_with("HTTP/1.0 200")
}

impl Drop for TestApp {
    /// Shut down as SIGTERM would (running jobs are cancelled and requeued), wait for it,
    /// then drop the runtime without blocking the caller's runtime.
    fn drop(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
            let _ = self.stopped.recv_timeout(Duration::from_secs(20));
        }
        if let Some(rt) = self.runtime.take() {
            rt.shutdown_background();
        }
    }
}
