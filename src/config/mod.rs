//! Service configuration: every setting is a flag with an environment variable.

mod tokens;
mod worker;

pub use tokens::{hash_token, Tokens};
pub use worker::WorkerConfig;

use std::net::SocketAddr;
use std::path::PathBuf;

#[derive(clap::Args, Debug, Clone)]
pub struct Config {
    #[command(flatten)]
    pub worker: WorkerConfig,

    /// Address to listen on (port 0 picks a free port; the bound address is printed).
    #[arg(long, env = "BEARING_SIM_BIND", default_value = "127.0.0.1:8080")]
    pub bind: SocketAddr,

    /// Direct computations (quasi-static solves, analyses answered in the request) run at
    /// the same time, on threads apart from the job workers; default: half the cores, at
    /// least 1. One whose client goes away is stopped.
    #[arg(long, env = "BEARING_SIM_DIRECT_CONCURRENCY")]
    pub direct_concurrency: Option<usize>,

    /// Queued jobs accepted before submissions get 429.
    #[arg(long, env = "BEARING_SIM_MAX_QUEUED", default_value_t = 1000)]
    pub max_queued: i64,

    /// Queued jobs one tenant (API token) may have, so that one tenant cannot fill the
    /// queue for everyone. Default: with tokens, half of `--max-queued`; without tokens
    /// (one tenant), no bound beyond `--max-queued`.
    #[arg(long, env = "BEARING_SIM_TENANT_MAX_QUEUED")]
    pub tenant_max_queued: Option<i64>,

    /// Comma-separated origins allowed by CORS (e.g. `http://localhost:3000`), or `*` for
    /// any origin; empty: none.
    #[arg(
        long,
        env = "BEARING_SIM_CORS_ORIGINS",
        value_delimiter = ',',
        default_value = "",
        value_parser = parse_cors_origin
    )]
    pub cors_origins: Vec<String>,

    /// File of API tokens, `name:sha256hex` per line (`bearing-sim token NAME` makes one).
    /// With tokens configured every `/v1` request needs `Authorization: Bearer <token>`,
    /// and each token sees and changes only what it created.
    #[arg(long, env = "BEARING_SIM_TOKENS_FILE")]
    pub tokens_file: Option<PathBuf>,

    /// API tokens as comma-separated `name:sha256hex` entries (added to --tokens-file).
    #[arg(
        long,
        env = "BEARING_SIM_TOKENS",
        default_value = "",
        hide_env_values = true
    )]
    pub tokens: String,

    /// With tokens: let GET requests without a token read every job and study (a read-only
    /// lab dashboard); writes still need a token.
    #[arg(long, env = "BEARING_SIM_OPEN_READS")]
    pub open_reads: bool,

    /// Largest request body, bytes (413 above it).
    #[arg(long, env = "BEARING_SIM_MAX_BODY_BYTES", default_value_t = 32 * 1024 * 1024)]
    pub max_body_bytes: usize,

    /// Time limit of an ordinary request, s (long polls with `wait` are exempt).
    #[arg(long, env = "BEARING_SIM_REQUEST_TIMEOUT", default_value_t = 30.0)]
    pub request_timeout: f64,

    /// HTTP connections open at once; one more is answered 503 and closed. Default: 512,
    /// or half the descriptor limit when that is less (the other half stays for the
    /// database and for answering the connections refused in a burst).
    #[arg(long, env = "BEARING_SIM_MAX_CONNECTIONS")]
    pub max_connections: Option<usize>,

    /// Time for a client to send a request's headers, and the longest a keep-alive
    /// connection may sit idle between requests, s.
    #[arg(long, env = "BEARING_SIM_HEADER_TIMEOUT", default_value_t = 10.0)]
    pub header_timeout: f64,

    /// Longest a response may wait for a client that does not read it, s.
    #[arg(long, env = "BEARING_SIM_WRITE_TIMEOUT", default_value_t = 30.0)]
    pub write_timeout: f64,

    /// Largest request head (request line and headers), bytes (431 above it).
    #[arg(long, env = "BEARING_SIM_MAX_HEADER_BYTES", default_value_t = 64 * 1024)]
    pub max_header_bytes: usize,

    /// Analyses of signals up to this many samples are answered directly; longer ones are queued.
    #[arg(
        long,
        env = "BEARING_SIM_SYNC_ANALYSIS_SAMPLES",
        default_value_t = 262_144
    )]
    pub sync_analysis_samples: usize,

    /// Largest estimated solver work of a scene, right-hand-side evaluations (four per
    /// step at the fixed step, or at the smaller of `max_step` and the typical 5 us step,
    /// plus one per output sample); a scene over it is refused with 422. The default is
    /// about 8 min of solver time (the Table-1 scene is 4.5e5).
    #[arg(
        long,
        env = "BEARING_SIM_MAX_SCENE_EVALUATIONS",
        default_value_t = 5.0e7
    )]
    pub max_scene_evaluations: f64,

    /// Bytes the database may hold in jobs and their outputs; past it submissions get
    /// 507 until retention or DELETE frees space. Default 20 GiB.
    #[arg(long, env = "BEARING_SIM_MAX_STORE_BYTES", default_value_t = 20 * 1024 * 1024 * 1024)]
    pub max_store_bytes: i64,

    /// Largest estimated storage of one analysis job, bytes: its samples (8 per sample)
    /// and its envelope spectra (4 per bin, levels + 1 spectra of n/2 bins). Default 128
    /// MiB: 3.2 million samples at 16 levels, 7 million at 5; about 1 GB of memory while
    /// it runs (docs/reference/operations.md).
    #[arg(long, env = "BEARING_SIM_MAX_JOB_BYTES", default_value_t = 128 * 1024 * 1024)]
    pub max_job_bytes: i64,

    /// Large transfers handled at once: request bodies over 1 MiB (or of unknown length)
    /// and channel or spectrum responses; more wait their turn (within the request
    /// timeout), so memory stays near this many times the body limit.
    #[arg(long, env = "BEARING_SIM_MAX_LARGE_TRANSFERS", default_value_t = 4)]
    pub max_large_transfers: usize,
}

impl Config {
    /// Queued jobs one tenant may have (`i64::MAX`: no bound); `tenants`: tokens are
    /// configured.
    pub fn tenant_queue_share(&self, tenants: bool) -> i64 {
        match (self.tenant_max_queued, tenants) {
            (Some(n), _) => n.max(1),
            (None, true) => (self.max_queued / 2).max(1),
            (None, false) => i64::MAX,
        }
    }

    /// `--request-timeout` as a duration (at least 0.1 s).
    pub fn request_deadline(&self) -> std::time::Duration {
        std::time::Duration::from_secs_f64(self.request_timeout.max(0.1))
    }

    /// The configured tokens (file and list), or why they cannot be read.
    pub fn load_tokens(&self) -> Result<Tokens, String> {
        let mut t = Tokens::parse(&self.tokens, "--tokens")?;
        // an empty path (BEARING_SIM_TOKENS_FILE= in a container) means no file
        if let Some(path) = self
            .tokens_file
            .as_ref()
            .filter(|p| !p.as_os_str().is_empty())
        {
            let text = std::fs::read_to_string(path)
                .map_err(|e| format!("--tokens-file {}: {e}", path.display()))?;
            t.merge(Tokens::parse(&text, &path.display().to_string())?)?;
        }
        Ok(t)
    }

    pub fn direct_count(&self) -> usize {
        self.direct_concurrency
            .unwrap_or_else(|| {
                std::thread::available_parallelism()
                    .map(|n| n.get() / 2)
                    .unwrap_or(1)
            })
            .max(1)
    }

    pub fn connection_count(&self) -> usize {
        self.max_connections
            .unwrap_or_else(|| match descriptor_limit() {
                Some(n) => (n / 2).clamp(16, 512),
                None => 512,
            })
            .max(1)
    }
}

/// One `--cors-origins` entry, checked before the service binds: empty (none), `*` (any
/// origin), or `scheme://host[:port]` as a browser sends it in `Origin` (no path, no
/// trailing slash), so a typo is refused at start instead of failing every request.
fn parse_cors_origin(s: &str) -> Result<String, String> {
    let o = s.trim();
    if o.is_empty() || o == "*" {
        return Ok(o.to_string());
    }
    let rest = o
        .strip_prefix("http://")
        .or_else(|| o.strip_prefix("https://"))
        .ok_or_else(|| format!("{o:?} must start with http:// or https:// (or be *)"))?;
    if rest.is_empty() || rest.contains('/') {
        return Err(format!(
            "{o:?} must be scheme://host[:port] with no path or trailing slash"
        ));
    }
    if axum::http::HeaderValue::from_str(o).is_err() || o.chars().any(char::is_whitespace) {
        return Err(format!("{o:?} is not a valid Origin header value"));
    }
    Ok(o.to_string())
}

/// The soft limit on open files of this process, if the platform tells.
fn descriptor_limit() -> Option<usize> {
    #[cfg(unix)]
    {
        let mut lim = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        // SAFETY: getrlimit writes the struct it is given and nothing else.
        if unsafe { libc::getrlimit(libc::RLIMIT_NOFILE, &mut lim) } == 0 {
            return Some(usize::try_from(lim.rlim_cur).unwrap_or(usize::MAX));
        }
        None
    }
    #[cfg(not(unix))]
    {
        None
    }
}
