//! What the job workers need: the database and the lease rules. `bearing-sim serve`
//! flattens it into its [`Config`](super::Config); `bearing-sim worker` takes it alone.

#[derive(clap::Args, Debug, Clone)]
pub struct WorkerConfig {
    /// Database URL: `sqlite://PATH` (embedded; the file and its directory are created if
    /// missing) or `postgres://USER@HOST/DB` (shared by several API and worker machines).
    #[arg(
        long,
        env = "BEARING_SIM_DATABASE_URL",
        default_value = "sqlite://data/bearing-sim.db"
    )]
    pub database_url: String,

    /// Jobs run at the same time (blocking engine threads); default: available cores.
    /// With `serve`, 0 runs the API alone (jobs wait for `bearing-sim worker` processes
    /// or other servers on the same database).
    #[arg(long, env = "BEARING_SIM_WORKERS")]
    pub workers: Option<usize>,

    /// Log format on stderr: `text` or `json`.
    #[arg(long, env = "BEARING_SIM_LOG_FORMAT", default_value = "text", value_parser = ["text", "json"])]
    pub log_format: String,

    /// Lease of a running job, s: a job whose worker stops heartbeating is requeued after it.
    #[arg(long, env = "BEARING_SIM_LEASE_SECS", default_value_t = 10.0)]
    pub lease_secs: f64,

    /// Deaths in a row of a job's worker, without the job getting further (1% more of
    /// it than before), before the job is failed as one that kills its worker. A death
    /// after headway (a restart, a SIGKILL, a lost host) never counts against the job.
    #[arg(long, env = "BEARING_SIM_MAX_ATTEMPTS", default_value_t = 3)]
    pub max_attempts: i64,

    /// Wall-clock limit of one job's run, s: a job still running after it is stopped and
    /// failed (kind `time_limit`). 0 disables it.
    #[arg(long, env = "BEARING_SIM_JOB_TIME_LIMIT", default_value_t = 3600.0)]
    pub job_time_limit: f64,

    /// Finished jobs and studies are deleted this long after they finished, s (with their
    /// signals and spectra); 0 keeps them until deleted. Default 30 days.
    #[arg(long, env = "BEARING_SIM_RETENTION", default_value_t = 30.0 * 86400.0)]
    pub retention: f64,

    /// Jobs one tenant (API token) may run at once across the database, so that another
    /// tenant's job always finds a worker. Default: with tokens, one less than the workers
    /// (at least 1); without tokens (one tenant) or on `bearing-sim worker`, no bound.
    #[arg(long, env = "BEARING_SIM_TENANT_MAX_RUNNING")]
    pub tenant_max_running: Option<usize>,

    /// Grace period on shutdown for running jobs to stop and be requeued, s.
    #[arg(long, env = "BEARING_SIM_SHUTDOWN_GRACE", default_value_t = 10.0)]
    pub shutdown_grace: f64,
}

impl WorkerConfig {
    pub fn worker_count(&self) -> usize {
        self.workers.unwrap_or_else(|| {
            std::thread::available_parallelism()
                .map(|n| n.get())
                .unwrap_or(1)
        })
    }

    /// Most jobs one tenant may run at once (`i64::MAX`: no bound).
    pub fn tenant_share(&self) -> i64 {
        self.tenant_max_running
            .map_or(i64::MAX, |n| n.max(1) as i64)
    }

    pub fn lease_ms(&self) -> i64 {
        (self.lease_secs.max(0.5) * 1000.0) as i64
    }

    /// Heartbeats at a third of the lease (at most every 400 ms, so progress stays fresh).
    pub fn heartbeat_interval(&self) -> std::time::Duration {
        std::time::Duration::from_millis((self.lease_ms() / 3).clamp(50, 400) as u64)
    }
}
