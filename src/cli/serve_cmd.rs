//! `bearing-sim serve`: bind, print the address, and run the service.

use super::result::CliResult;
use crate::config::Config;
use std::io::Write;
use std::time::Duration;

#[derive(clap::Args, Debug)]
pub struct ServeArgs {
    #[command(flatten)]
    pub config: Config,

    /// Do not serve: check that the server at --bind answers GET /healthz, exit 0 if so.
    /// Used as the container HEALTHCHECK, which has no shell or curl.
    #[arg(long)]
    pub probe: bool,
}

pub fn main(args: ServeArgs) -> CliResult {
    let config = args.config;
    if args.probe {
        return probe(config.bind);
    }
    init_logging(&config.worker.log_format);
    let workers = config.worker.worker_count();
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        // Engine runs are bounded by the worker pool and direct computations by their own
        // semaphore; the margin serves start checks, the store and tokio's blocking work.
        .max_blocking_threads(workers + config.direct_count() + 8)
        .build()?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::bind(config.bind).await?;
        // Machine-readable: tests and scripts read the port from this line.
        println!("listening on http://{}", listener.local_addr()?);
        std::io::stdout().flush()?;
        crate::serve::run(config, listener).await?;
        Ok(())
    })
}

pub(super) fn init_logging(format: &str) {
    let filter = tracing_subscriber::EnvFilter::try_from_env("BEARING_SIM_LOG")
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info,sqlx=warn,tower_http=warn"));
    // colour codes only for a terminal, not for log files and collectors
    let builder = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .with_writer(std::io::stderr);
    if format == "json" {
        builder.json().init();
    } else {
        builder.init();
    }
}

fn probe(bind: std::net::SocketAddr) -> super::result::CliResult {
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
