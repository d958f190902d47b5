//! `bearing-sim serve`: the HTTP service with its durable job queue and worker pool.

use crate::api::{self, AppState};
use crate::config::Config;
use crate::jobs::{WorkerEnv, WorkerPool};
use crate::metrics::Metrics;
use crate::store::sqlite::SqliteStore;
use crate::store::Store;
use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::{Notify, Semaphore};

#[derive(clap::Args, Debug)]
pub struct ServeArgs {
    #[command(flatten)]
    pub config: Config,

    /// Do not serve: check that the server at --bind answers GET /healthz, exit 0 if so.
    /// Used as the container HEALTHCHECK, which has no shell or curl.
    #[arg(long)]
    pub probe: bool,
}

pub fn main(args: ServeArgs) -> crate::cli::CliResult {
    let config = args.config;
    if args.probe {
        return probe(config.bind);
    }
    init_logging(&config.log_format);
    let workers = config.worker_count();
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        // Engine runs are bounded by the worker pool; the margin serves direct requests
        // (also bounded, by a semaphore) and tokio's own blocking work.
        .max_blocking_threads(2 * workers.max(1) + 4)
        .build()?;
    runtime.block_on(run(config))
}

fn init_logging(format: &str) {
    let filter = tracing_subscriber::EnvFilter::try_from_env("BEARING_SIM_LOG")
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info,sqlx=warn,tower_http=warn"));
    let builder = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr);
    if format == "json" {
        builder.json().init();
    } else {
        builder.init();
    }
}

async fn run(config: Config) -> crate::cli::CliResult {
    let config = Arc::new(config);
    let store: Arc<dyn Store> = Arc::new(SqliteStore::connect(&config.database_url).await?);
    let metrics = Arc::new(Metrics::default());
    let wake = Arc::new(Notify::new());
    let ready = Arc::new(AtomicBool::new(true));
    let workers = config.worker_count();

    let pool = WorkerPool::start(WorkerEnv {
        store: store.clone(),
        config: config.clone(),
        metrics: metrics.clone(),
        wake: wake.clone(),
    });
    let state = AppState {
        store,
        config: config.clone(),
        metrics,
        wake,
        ready: ready.clone(),
        direct: Arc::new(Semaphore::new(workers.max(1))),
    };

    let listener = tokio::net::TcpListener::bind(config.bind).await?;
    let addr = listener.local_addr()?;
    // Machine-readable: tests and scripts read the port from this line.
    println!("listening on http://{addr}");
    std::io::stdout().flush()?;
    tracing::info!(%addr, workers, database = %config.database_url, "serving");

    let (stop_tx, mut stop_rx) = tokio::sync::watch::channel(false);
    tokio::spawn(async move {
        shutdown_signal().await;
        let _ = stop_tx.send(true);
    });
    let mut server_stop = stop_rx.clone();
    let server = axum::serve(listener, api::router(state)).with_graceful_shutdown(async move {
        let _ = server_stop.wait_for(|s| *s).await;
    });
    let server = tokio::spawn(async move { server.await });

    let _ = stop_rx.wait_for(|s| *s).await;
    tracing::info!("shutting down: no new jobs; running jobs are stopped and requeued");
    ready.store(false, Ordering::SeqCst);
    pool.shutdown(Duration::from_secs_f64(config.shutdown_grace.max(0.0)))
        .await;
    match tokio::time::timeout(Duration::from_secs(5), server).await {
        Ok(Ok(Ok(()))) => {}
        Ok(Ok(Err(e))) => return Err(e.into()),
        Ok(Err(e)) => return Err(e.into()),
        Err(_) => tracing::warn!("open connections did not close within 5 s"),
    }
    tracing::info!("stopped");
    Ok(())
}

fn probe(bind: std::net::SocketAddr) -> crate::cli::CliResult {
    use std::io::Read;
    let mut addr = bind;
    if addr.ip().is_unspecified() {
        addr.set_ip(if addr.is_ipv4() {
            std::net::Ipv4Addr::LOCALHOST.into()
        } else {
            std::net::Ipv6Addr::LOCALHOST.into()
        });
    }
    let timeout = Duration::from_secs(3);
    let mut stream = std::net::TcpStream::connect_timeout(&addr, timeout)?;
    stream.set_read_timeout(Some(timeout))?;
    stream.write_all(format!("GET /healthz HTTP/1.0\r\nHost: {addr}\r\n\r\n").as_bytes())?;
    let mut reply = String::new();
    stream.read_to_string(&mut reply)?;
    let status_line = reply.lines().next().unwrap_or("");
    if status_line.split_whitespace().nth(1) == Some("200") {
        Ok(())
    } else {
        Err(format!("health check failed: {status_line}").into())
    }
}

async fn shutdown_signal() {
    let ctrl_c = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    let term = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let term = std::future::pending::<()>();
    tokio::select! {
        _ = ctrl_c => {}
        _ = term => {}
    }
}
