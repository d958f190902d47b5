//! In-process metrics rendered as Prometheus text (exposition format 0.0.4).

use std::collections::BTreeMap;
use std::fmt::Write;
use std::sync::atomic::{AtomicI64, Ordering};
use std::sync::Mutex;

const HTTP_BUCKETS: &[f64] = &[
    0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0,
];
const JOB_BUCKETS: &[f64] = &[
    0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0, 30.0, 60.0, 120.0, 300.0, 600.0,
];

#[derive(Debug, Clone)]
struct Histogram {
    counts: Vec<u64>,
    sum: f64,
    count: u64,
}

impl Histogram {
    fn new(n: usize) -> Self {
        Histogram {
            counts: vec![0; n],
            sum: 0.0,
            count: 0,
        }
    }
    fn observe(&mut self, buckets: &[f64], v: f64) {
        for (i, b) in buckets.iter().enumerate() {
            if v <= *b {
                self.counts[i] += 1;
            }
        }
        self.sum += v;
        self.count += 1;
    }
}

#[derive(Default)]
pub struct Metrics {
    /// (method, route, status) -> latency histogram.
    http: Mutex<BTreeMap<(String, String, u16), Histogram>>,
    /// (kind, final state) -> run-time histogram.
    jobs: Mutex<BTreeMap<(String, String), Histogram>>,
    running: AtomicI64,
    running_max: AtomicI64,
    /// Studies accepted, their points, the jobs queued for them and the points that shared
    /// a job.
    studies: AtomicI64,
    study_points: AtomicI64,
    study_jobs_queued: AtomicI64,
    study_points_shared: AtomicI64,
    /// Direct computations running now, and those stopped because their request went away.
    direct_running: AtomicI64,
    direct_cancelled: AtomicI64,
    /// HTTP connections open now, and those refused at the connection bound.
    connections_open: AtomicI64,
    connections_refused: AtomicI64,
    /// Finished jobs deleted by retention.
    jobs_expired: AtomicI64,
}

/// Decrements the open-connections gauge when a connection closes.
pub struct ConnectionGuard(std::sync::Arc<Metrics>);

impl Drop for ConnectionGuard {
    fn drop(&mut self) {
        self.0.connections_open.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Decrements the direct-computation gauge when one ends.
pub struct DirectGuard(std::sync::Arc<Metrics>);

impl Drop for DirectGuard {
    fn drop(&mut self) {
        self.0.direct_running.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Decrements the running gauge when a job ends, whatever the path out.
pub struct RunningGuard<'a>(&'a Metrics);

impl Drop for RunningGuard<'_> {
    fn drop(&mut self) {
        self.0.running.fetch_sub(1, Ordering::SeqCst);
    }
}

impl Metrics {
    pub fn observe_http(&self, method: &str, route: &str, status: u16, seconds: f64) {
        let mut m = self.http.lock().unwrap_or_else(|e| e.into_inner());
        m.entry((method.to_string(), route.to_string(), status))
            .or_insert_with(|| Histogram::new(HTTP_BUCKETS.len()))
            .observe(HTTP_BUCKETS, seconds);
    }

    pub fn observe_job(&self, kind: &str, state: &str, seconds: f64) {
        let mut m = self.jobs.lock().unwrap_or_else(|e| e.into_inner());
        m.entry((kind.to_string(), state.to_string()))
            .or_insert_with(|| Histogram::new(JOB_BUCKETS.len()))
            .observe(JOB_BUCKETS, seconds);
    }

    /// Count a job as running in this process until the guard drops.
    pub fn job_started(&self) -> RunningGuard<'_> {
        let now = self.running.fetch_add(1, Ordering::SeqCst) + 1;
        self.running_max.fetch_max(now, Ordering::SeqCst);
        RunningGuard(self)
    }

    /// Count a direct computation as running until the guard drops.
    pub fn direct_started(self: &std::sync::Arc<Self>) -> DirectGuard {
        self.direct_running.fetch_add(1, Ordering::SeqCst);
        DirectGuard(self.clone())
    }

    /// Count a direct computation whose request went away before it ended.
    pub fn direct_cancelled(&self) {
        self.direct_cancelled.fetch_add(1, Ordering::SeqCst);
    }

    /// Count an HTTP connection as open until the guard drops.
    pub fn connection_opened(self: &std::sync::Arc<Self>) -> ConnectionGuard {
        self.connections_open.fetch_add(1, Ordering::SeqCst);
        ConnectionGuard(self.clone())
    }

    /// Count jobs deleted by retention.
    pub fn expired(&self, jobs: u64) {
        self.jobs_expired.fetch_add(jobs as i64, Ordering::SeqCst);
    }

    /// Count a connection refused at the connection bound.
    pub fn connection_refused(&self) {
        self.connections_refused.fetch_add(1, Ordering::SeqCst);
    }

    pub fn direct_running(&self) -> i64 {
        self.direct_running.load(Ordering::SeqCst)
    }

    /// Count an accepted study.
    pub fn study_created(&self, points: usize, queued: usize, shared: usize) {
        self.studies.fetch_add(1, Ordering::SeqCst);
        self.study_points.fetch_add(points as i64, Ordering::SeqCst);
        self.study_jobs_queued
            .fetch_add(queued as i64, Ordering::SeqCst);
        self.study_points_shared
            .fetch_add(shared as i64, Ordering::SeqCst);
    }

    pub fn running(&self) -> i64 {
        self.running.load(Ordering::SeqCst)
    }

    /// Render everything; `jobs_by_state` and `stored_bytes` come from the store at
    /// scrape time.
    pub fn render(
        &self,
        jobs_by_state: &[(&str, i64)],
        stored_bytes: i64,
        workers: usize,
    ) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "# HELP bearing_sim_store_bytes Bytes held by jobs and their outputs in the database (--max-store-bytes bounds it)."
        );
        let _ = writeln!(out, "# TYPE bearing_sim_store_bytes gauge");
        let _ = writeln!(out, "bearing_sim_store_bytes {stored_bytes}");
        let queued = jobs_by_state
            .iter()
            .find(|(s, _)| *s == "queued")
            .map(|x| x.1)
            .unwrap_or(0);
        let _ = writeln!(
            out,
            "# HELP bearing_sim_queue_depth Jobs waiting for a worker."
        );
        let _ = writeln!(out, "# TYPE bearing_sim_queue_depth gauge");
        let _ = writeln!(out, "bearing_sim_queue_depth {queued}");
        let _ = writeln!(
            out,
            "# HELP bearing_sim_jobs Jobs in the database by state."
        );
        let _ = writeln!(out, "# TYPE bearing_sim_jobs gauge");
        for (s, n) in jobs_by_state {
            let _ = writeln!(out, "bearing_sim_jobs{{state=\"{s}\"}} {n}");
        }
        let _ = writeln!(
            out,
            "# HELP bearing_sim_workers Worker threads of this process."
        );
        let _ = writeln!(out, "# TYPE bearing_sim_workers gauge");
        let _ = writeln!(out, "bearing_sim_workers {workers}");
        let _ = writeln!(
            out,
            "# HELP bearing_sim_jobs_running Jobs running in this process now."
        );
        let _ = writeln!(out, "# TYPE bearing_sim_jobs_running gauge");
        let _ = writeln!(out, "bearing_sim_jobs_running {}", self.running());
        let _ = writeln!(out, "# HELP bearing_sim_jobs_running_max Most jobs running at once in this process since start.");
        let _ = writeln!(out, "# TYPE bearing_sim_jobs_running_max gauge");
        let _ = writeln!(
            out,
            "bearing_sim_jobs_running_max {}",
            self.running_max.load(Ordering::SeqCst)
        );

        let _ = writeln!(
            out,
            "# HELP bearing_sim_direct_running Direct computations (quasi-static solves, small analyses) running now."
        );
        let _ = writeln!(out, "# TYPE bearing_sim_direct_running gauge");
        let _ = writeln!(out, "bearing_sim_direct_running {}", self.direct_running());

        let _ = writeln!(
            out,
            "# HELP bearing_sim_connections_open HTTP connections open now."
        );
        let _ = writeln!(out, "# TYPE bearing_sim_connections_open gauge");
        let _ = writeln!(
            out,
            "bearing_sim_connections_open {}",
            self.connections_open.load(Ordering::SeqCst)
        );

        for (name, help, v) in [
            (
                "bearing_sim_jobs_expired_total",
                "Finished jobs deleted by retention (--retention).",
                &self.jobs_expired,
            ),
            (
                "bearing_sim_connections_refused_total",
                "Connections answered 503 at the connection bound (--max-connections).",
                &self.connections_refused,
            ),
            (
                "bearing_sim_direct_cancelled_total",
                "Direct computations stopped because their request went away.",
                &self.direct_cancelled,
            ),
            (
                "bearing_sim_studies_created_total",
                "Studies accepted by this process.",
                &self.studies,
            ),
            (
                "bearing_sim_study_points_total",
                "Points of the studies accepted.",
                &self.study_points,
            ),
            (
                "bearing_sim_study_jobs_queued_total",
                "Simulation jobs queued for study points.",
                &self.study_jobs_queued,
            ),
            (
                "bearing_sim_study_points_shared_total",
                "Study points that shared the job of an identical scene.",
                &self.study_points_shared,
            ),
        ] {
            let _ = writeln!(out, "# HELP {name} {help}");
            let _ = writeln!(out, "# TYPE {name} counter");
            let _ = writeln!(out, "{name} {}", v.load(Ordering::SeqCst));
        }
        let _ = writeln!(
            out,
            "# HELP bearing_sim_job_duration_seconds Run time of jobs by kind and final state."
        );
        let _ = writeln!(out, "# TYPE bearing_sim_job_duration_seconds histogram");
        for ((kind, state), h) in self.jobs.lock().unwrap_or_else(|e| e.into_inner()).iter() {
            write_histogram(
                &mut out,
                "bearing_sim_job_duration_seconds",
                &format!("kind=\"{kind}\",state=\"{state}\""),
                JOB_BUCKETS,
                h,
            );
        }
        let _ = writeln!(out, "# HELP bearing_sim_http_request_duration_seconds HTTP request latency by route and status.");
        let _ = writeln!(
            out,
            "# TYPE bearing_sim_http_request_duration_seconds histogram"
        );
        for ((method, route, status), h) in
            self.http.lock().unwrap_or_else(|e| e.into_inner()).iter()
        {
            let labels = format!(
                "method=\"{method}\",route=\"{}\",status=\"{status}\"",
                escape(route)
            );
            write_histogram(
                &mut out,
                "bearing_sim_http_request_duration_seconds",
                &labels,
                HTTP_BUCKETS,
                h,
            );
        }
        out
    }
}

fn escape(s: &str) -> String {
    s.replace('\\', "\\\\")
        .replace('"', "\\\"")
        .replace('\n', "\\n")
}

fn write_histogram(out: &mut String, name: &str, labels: &str, buckets: &[f64], h: &Histogram) {
    for (b, c) in buckets.iter().zip(&h.counts) {
        let _ = writeln!(out, "{name}_bucket{{{labels},le=\"{b}\"}} {c}");
    }
    let _ = writeln!(out, "{name}_bucket{{{labels},le=\"+Inf\"}} {}", h.count);
    let _ = writeln!(out, "{name}_sum{{{labels}}} {}", h.sum);
    let _ = writeln!(out, "{name}_count{{{labels}}} {}", h.count);
}
