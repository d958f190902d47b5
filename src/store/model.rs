//! Rows and values exchanged with a [`super::Store`].

use serde::{Deserialize, Serialize};
use std::fmt;
use utoipa::ToSchema;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum JobState {
    Queued,
    Running,
    Succeeded,
    Failed,
    Cancelled,
}

impl JobState {
    pub const ALL: [JobState; 5] = [
        JobState::Queued,
        JobState::Running,
        JobState::Succeeded,
        JobState::Failed,
        JobState::Cancelled,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            JobState::Queued => "queued",
            JobState::Running => "running",
            JobState::Succeeded => "succeeded",
            JobState::Failed => "failed",
            JobState::Cancelled => "cancelled",
        }
    }

    pub fn parse(s: &str) -> Option<JobState> {
        JobState::ALL.into_iter().find(|st| st.as_str() == s)
    }

    pub fn is_finished(self) -> bool {
        matches!(
            self,
            JobState::Succeeded | JobState::Failed | JobState::Cancelled
        )
    }
}

impl fmt::Display for JobState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum JobKind {
    Simulation,
    Analysis,
}

impl JobKind {
    pub fn as_str(self) -> &'static str {
        match self {
            JobKind::Simulation => "simulation",
            JobKind::Analysis => "analysis",
        }
    }
    pub fn parse(s: &str) -> Option<JobKind> {
        match s {
            "simulation" => Some(JobKind::Simulation),
            "analysis" => Some(JobKind::Analysis),
            _ => None,
        }
    }
}

/// What kind of failure ended a job.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum FailureKind {
    /// The stored input did not parse or validate.
    Invalid,
    /// The solver failed: no quasi-static start, step-size underflow, a non-finite state.
    Numerical,
    /// The engine panicked (a bug); the process survived.
    Panic,
    /// Cancelled on request.
    Cancelled,
    /// Its worker died too many times in a row without the job getting further (a job
    /// that kills its worker); deaths with headway, restarts say, do not count.
    LeaseExpired,
    /// Still running at the wall-clock limit (`--job-time-limit`); stopped.
    TimeLimit,
    /// The signal analysis refused its input.
    Analysis,
    /// A fault of the service itself (e.g. a result that does not serialize).
    Internal,
}

impl FailureKind {
    pub fn as_str(self) -> &'static str {
        match self {
            FailureKind::Invalid => "invalid",
            FailureKind::Numerical => "numerical",
            FailureKind::Panic => "panic",
            FailureKind::Cancelled => "cancelled",
            FailureKind::LeaseExpired => "lease_expired",
            FailureKind::TimeLimit => "time_limit",
            FailureKind::Analysis => "analysis",
            FailureKind::Internal => "internal",
        }
    }
}

impl fmt::Display for FailureKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Why a job failed or stopped, as stored and shown.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct JobError {
    pub kind: FailureKind,
    pub message: String,
}

/// A job row as handlers see it (inputs and outputs stay in the store).
#[derive(Debug, Clone)]
pub struct Job {
    pub seq: i64,
    pub id: String,
    /// The name of the API token that created it ('' without tokens).
    pub tenant: String,
    pub kind: JobKind,
    pub state: JobState,
    pub label: String,
    pub progress: f64,
    pub attempt: i64,
    pub cancel_requested: bool,
    pub version: i64,
    /// Unix milliseconds.
    pub created_at: i64,
    pub started_at: Option<i64>,
    pub finished_at: Option<i64>,
    pub updated_at: i64,
    pub error: Option<JobError>,
    pub stats: Option<serde_json::Value>,
    pub result: Option<serde_json::Value>,
}

/// The newest format of stored job inputs (scenes and analysis requests) this binary
/// writes and can run. Workers claim only jobs whose format is at most theirs, so when
/// several worker machines share one database during an upgrade, an older worker leaves a
/// newer job queued for a newer worker instead of failing it as unparsable. Bump it when a
/// stored input gains a field or a value an older binary would refuse.
/// `tests/checks/input_format.rs` fails until you do for a change of the inputs' schemas;
/// it does not see a loosened validation bound, a change of the analysis request's sample
/// or shaft rate, or of the signal blob's encoding (bump for those by hand). Format 1 is every input stored before
/// the column existed.
pub const INPUT_FORMAT: i64 = 7;

/// What a submission stores.
#[derive(Debug, Clone)]
pub struct NewJob {
    pub id: String,
    /// The name of the API token submitting it ('' without tokens); scopes the
    /// idempotency key.
    pub tenant: String,
    pub kind: JobKind,
    pub label: String,
    pub input: serde_json::Value,
    pub input_blob: Option<Vec<u8>>,
    pub idempotency_key: Option<String>,
    /// Hash of the resolved request, compared on idempotent replays.
    pub request_hash: String,
    /// The format `input` is written in: [`INPUT_FORMAT`] for what this binary writes.
    pub input_format: i64,
}

#[derive(Debug, Clone)]
pub struct Created {
    pub job: Job,
    /// False when an idempotent replay returned an existing job.
    pub created: bool,
}

#[derive(Debug, Clone, Default)]
pub struct ListFilter {
    /// Only this tenant's jobs (None: everyone's).
    pub tenant: Option<String>,
    pub kind: Option<JobKind>,
    pub state: Option<JobState>,
    /// Only jobs with `seq` below this (the cursor).
    pub before: Option<i64>,
    pub limit: i64,
}

#[derive(Debug, Clone)]
pub struct Page {
    pub jobs: Vec<Job>,
    /// Cursor for the next (older) page, if there is one.
    pub next: Option<i64>,
}

/// Proof of a claim: every write by a worker is fenced on (id, owner, attempt).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Lease {
    pub id: String,
    pub owner: String,
    pub attempt: i64,
}

/// A job taken from the queue with what the worker needs to run it.
#[derive(Debug, Clone)]
pub struct Claimed {
    pub lease: Lease,
    pub kind: JobKind,
    pub input: serde_json::Value,
    pub input_blob: Option<Vec<u8>>,
    pub cancel_requested: bool,
}

#[derive(Debug, Clone, Copy)]
pub struct Heartbeat {
    pub cancel_requested: bool,
}

/// A stored output: typed metadata plus a binary body (little-endian f32 samples).
#[derive(Debug, Clone)]
pub struct Artifact {
    /// `channel:<name>`, `spectrum:raw` or `spectrum:level:<k>`.
    pub name: String,
    pub meta: ArtifactMeta,
    pub data: Vec<u8>,
}

/// What an artifact's samples are. Stored as JSON; the two shapes are told apart by their
/// fields (untagged), so rows written before the type existed still read.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ArtifactMeta {
    /// A sampled channel of a simulation; sample `k` is at `start_time + k / sample_rate`.
    Channel {
        name: String,
        /// SI unit of the samples.
        unit: String,
        /// Hz.
        sample_rate: f64,
        /// s.
        start_time: f64,
        samples: usize,
    },
    /// An envelope spectrum; bin `k` is at `k * df`.
    Spectrum {
        /// Bin spacing, Hz.
        df: f64,
        bins: usize,
    },
}

/// How a claimed job ended.
#[derive(Debug, Clone)]
pub enum Outcome {
    Succeeded {
        result: serde_json::Value,
        stats: Option<serde_json::Value>,
        artifacts: Vec<Artifact>,
        /// The run's study scene key under the build that computed it (simulations; see
        /// `studies::scene_key`): it replaces the key the submitting node wrote, so that
        /// during a rolling upgrade a run an older worker computed is not reused by studies
        /// of the newer build. None leaves the key as it is; a job that has none (a
        /// simulation submitted on its own, not a study point) keeps none.
        scene_key: Option<String>,
    },
    Failed {
        error: JobError,
        stats: Option<serde_json::Value>,
    },
    Cancelled {
        error: JobError,
    },
}

#[derive(Debug, Clone, Default)]
pub struct StateCounts {
    pub queued: i64,
    pub running: i64,
    pub succeeded: i64,
    pub failed: i64,
    pub cancelled: i64,
}

impl StateCounts {
    pub fn get(&self, s: JobState) -> i64 {
        match s {
            JobState::Queued => self.queued,
            JobState::Running => self.running,
            JobState::Succeeded => self.succeeded,
            JobState::Failed => self.failed,
            JobState::Cancelled => self.cancelled,
        }
    }
    pub fn set(&mut self, s: JobState, n: i64) {
        match s {
            JobState::Queued => self.queued = n,
            JobState::Running => self.running = n,
            JobState::Succeeded => self.succeeded = n,
            JobState::Failed => self.failed = n,
            JobState::Cancelled => self.cancelled = n,
        }
    }
}

/// A study to store: its request and design (JSON), and its points in order.
#[derive(Debug, Clone)]
pub struct NewStudy {
    pub id: String,
    /// Owner of the study and of the jobs queued for it; points share only its jobs.
    pub tenant: String,
    pub label: String,
    pub request: serde_json::Value,
    pub design: serde_json::Value,
    pub points: Vec<NewStudyPoint>,
}

/// One point: what it is (JSON), its scene key, and the job to queue if none is shared.
#[derive(Debug, Clone)]
pub struct NewStudyPoint {
    pub spec: serde_json::Value,
    pub scene_key: String,
    pub job: NewJob,
}

#[derive(Debug, Clone)]
pub struct StudyCreated {
    pub study: Study,
    /// Jobs queued for it.
    pub queued: usize,
    /// Points that share a job (another point's or an earlier run's).
    pub shared: usize,
}

/// A study row with its points.
#[derive(Debug, Clone)]
pub struct Study {
    pub seq: i64,
    pub id: String,
    pub tenant: String,
    pub label: String,
    pub request: serde_json::Value,
    pub design: serde_json::Value,
    pub cancel_requested: bool,
    pub version: i64,
    /// Unix milliseconds.
    pub created_at: i64,
    pub updated_at: i64,
    pub points: Vec<StudyPointRow>,
}

/// A point of a study and its job.
#[derive(Debug, Clone)]
pub struct StudyPointRow {
    pub index: usize,
    pub spec: serde_json::Value,
    pub job: Job,
    /// Other studies hold the same job.
    pub shared_with_other_studies: bool,
}

#[derive(Debug, Clone)]
pub struct StudyPage {
    pub studies: Vec<Study>,
    pub next: Option<i64>,
}

/// Milliseconds since the Unix epoch.
pub fn now_ms() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_millis() as i64)
        .unwrap_or(0)
}
