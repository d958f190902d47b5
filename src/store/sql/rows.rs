//! Rows to model types, for both backends: a backend says how to read one column of each
//! kind ([`Columns`]); what a job, study or artifact is made of is written once here.

use crate::store::contract::StoreError;
use crate::store::model::*;
use sqlx::postgres::PgRow;
use sqlx::sqlite::SqliteRow;
use sqlx::Row;

/// One column of a row by name, as the few kinds the store uses.
pub trait Columns {
    fn text(&self, col: &str) -> Result<String, sqlx::Error>;
    fn opt_text(&self, col: &str) -> Result<Option<String>, sqlx::Error>;
    fn int(&self, col: &str) -> Result<i64, sqlx::Error>;
    fn opt_int(&self, col: &str) -> Result<Option<i64>, sqlx::Error>;
    fn real(&self, col: &str) -> Result<f64, sqlx::Error>;
    fn opt_bytes(&self, col: &str) -> Result<Option<Vec<u8>>, sqlx::Error>;
    /// A yes/no column: 0/1 in SQLite, `boolean` in PostgreSQL.
    fn flag(&self, col: &str) -> Result<bool, sqlx::Error>;
}

macro_rules! columns_for {
    ($row:ty, |$r:ident, $c:ident| $flag:expr) => {
        impl Columns for $row {
            fn text(&self, col: &str) -> Result<String, sqlx::Error> {
                self.try_get(col)
            }
            fn opt_text(&self, col: &str) -> Result<Option<String>, sqlx::Error> {
                self.try_get(col)
            }
            fn int(&self, col: &str) -> Result<i64, sqlx::Error> {
                self.try_get(col)
            }
            fn opt_int(&self, col: &str) -> Result<Option<i64>, sqlx::Error> {
                self.try_get(col)
            }
            fn real(&self, col: &str) -> Result<f64, sqlx::Error> {
                self.try_get(col)
            }
            fn opt_bytes(&self, col: &str) -> Result<Option<Vec<u8>>, sqlx::Error> {
                self.try_get(col)
            }
            fn flag(&self, col: &str) -> Result<bool, sqlx::Error> {
                let ($r, $c) = (self, col);
                $flag
            }
        }
    };
}

columns_for!(SqliteRow, |r, c| Ok(r.try_get::<i64, _>(c)? != 0));
columns_for!(PgRow, |r, c| r.try_get::<bool, _>(c));

/// The job columns every read selects (and the study point view prefixes with `jobs.`).
pub(super) const JOB_COLUMNS: &str =
    "seq, id, tenant, kind, state, label, progress, attempt, cancel_requested, version, \
     created_at, started_at, finished_at, updated_at, error, stats, result";

pub(super) const STUDY_COLUMNS: &str =
    "seq, id, tenant, label, request, design, cancel_requested, version, created_at, updated_at";

/// `JOB_COLUMNS` read from the `jobs` table of a join, under their own names.
pub(super) fn job_columns_of_join() -> String {
    JOB_COLUMNS
        .split(", ")
        .map(|c| format!("jobs.{} AS {}", c.trim(), c.trim()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The idempotency key as stored: a tenant's keys live apart from every other tenant's
/// (the unit separator cannot occur in a header value); without tokens it is the key.
pub(super) fn scoped_idempotency_key(tenant: &str, key: &str) -> String {
    if tenant.is_empty() {
        key.to_string()
    } else {
        format!("{tenant}\u{1f}{key}")
    }
}

pub(super) fn opt_json(v: &Option<serde_json::Value>) -> Option<String> {
    v.as_ref().map(|v| v.to_string())
}

fn parse_json(s: Option<String>) -> Option<serde_json::Value> {
    s.and_then(|s| serde_json::from_str(&s).ok())
}

fn decode_error(message: String) -> StoreError {
    StoreError::Db(sqlx::Error::Decode(message.into()))
}

pub(super) fn job_from_row(r: &impl Columns) -> Result<Job, StoreError> {
    let kind = r.text("kind")?;
    let state = r.text("state")?;
    let bad = |what: &str, v: &str| decode_error(format!("bad {what} '{v}' in jobs row"));
    Ok(Job {
        seq: r.int("seq")?,
        id: r.text("id")?,
        tenant: r.text("tenant")?,
        kind: JobKind::parse(&kind).ok_or_else(|| bad("kind", &kind))?,
        state: JobState::parse(&state).ok_or_else(|| bad("state", &state))?,
        label: r.text("label")?,
        progress: r.real("progress")?,
        attempt: r.int("attempt")?,
        cancel_requested: r.flag("cancel_requested")?,
        version: r.int("version")?,
        created_at: r.int("created_at")?,
        started_at: r.opt_int("started_at")?,
        finished_at: r.opt_int("finished_at")?,
        updated_at: r.int("updated_at")?,
        error: parse_json(r.opt_text("error")?).and_then(|v| serde_json::from_value(v).ok()),
        stats: parse_json(r.opt_text("stats")?),
        result: parse_json(r.opt_text("result")?),
    })
}

/// A study without its points (see [`study_point_from_row`]).
pub(super) fn study_from_row(r: &impl Columns) -> Result<Study, StoreError> {
    let json = |col: &str| -> Result<serde_json::Value, StoreError> {
        serde_json::from_str(&r.text(col)?)
            .map_err(|e| decode_error(format!("bad {col} in studies row: {e}")))
    };
    Ok(Study {
        seq: r.int("seq")?,
        id: r.text("id")?,
        tenant: r.text("tenant")?,
        label: r.text("label")?,
        request: json("request")?,
        design: json("design")?,
        cancel_requested: r.flag("cancel_requested")?,
        version: r.int("version")?,
        created_at: r.int("created_at")?,
        updated_at: r.int("updated_at")?,
        points: vec![],
    })
}

/// A row of the study point view: `idx`, `spec`, `others` and the job's columns.
pub(super) fn study_point_from_row(
    study: &str,
    r: &impl Columns,
) -> Result<StudyPointRow, StoreError> {
    Ok(StudyPointRow {
        index: r.int("idx")? as usize,
        spec: serde_json::from_str(&r.text("spec")?)
            .map_err(|e| decode_error(format!("bad spec of a point of study {study}: {e}")))?,
        job: job_from_row(r)?,
        shared_with_other_studies: r.flag("others")?,
    })
}

/// The `RETURNING id, kind, attempt, input, input_blob, cancel_requested` of a claim.
pub(super) fn claimed_from_row(owner: &str, r: &impl Columns) -> Result<Claimed, StoreError> {
    let kind = r.text("kind")?;
    Ok(Claimed {
        lease: Lease {
            id: r.text("id")?,
            owner: owner.to_string(),
            attempt: r.int("attempt")?,
        },
        kind: JobKind::parse(&kind).unwrap_or(JobKind::Simulation),
        input: serde_json::from_str(&r.text("input")?).unwrap_or(serde_json::Value::Null),
        input_blob: r.opt_bytes("input_blob")?,
        cancel_requested: r.flag("cancel_requested")?,
    })
}

/// `name, meta, data` of an artifacts row of job `job`.
pub(super) fn artifact_from_row(job: &str, r: &impl Columns) -> Result<Artifact, StoreError> {
    let name = r.text("name")?;
    let meta = serde_json::from_str(&r.text("meta")?)
        .map_err(|e| decode_error(format!("bad metadata of artifact {name} of job {job}: {e}")))?;
    Ok(Artifact {
        name,
        meta,
        data: r.opt_bytes("data")?.unwrap_or_default(),
    })
}

/// What a finished job's row gets: (state, progress, error, stats, result, artifacts,
/// scene key).
pub(super) type FinishedRow = (
    &'static str,
    Option<f64>,
    Option<String>,
    Option<String>,
    Option<String>,
    Vec<Artifact>,
    Option<String>,
);

pub(super) fn finished_row(outcome: Outcome) -> FinishedRow {
    let (state, progress, error, stats, result, artifacts, key) = match outcome {
        Outcome::Succeeded {
            result,
            stats,
            artifacts,
            scene_key,
        } => (
            "succeeded",
            Some(1.0),
            None,
            stats,
            Some(result),
            artifacts,
            scene_key,
        ),
        Outcome::Failed { error, stats } => {
            ("failed", None, Some(error), stats, None, vec![], None)
        }
        Outcome::Cancelled { error } => ("cancelled", None, Some(error), None, None, vec![], None),
    };
    (
        state,
        progress,
        error.map(|e| serde_json::to_string(&e).unwrap_or_default()),
        opt_json(&stats),
        opt_json(&result),
        artifacts,
        key,
    )
}

/// The error of a job whose worker died `max_attempts` times in a row without the job
/// getting further: it appears to kill its worker.
pub(super) fn poison_error(max_attempts: i64) -> String {
    serde_json::to_string(&JobError {
        kind: FailureKind::LeaseExpired,
        message: format!(
            "the worker running this job died {max_attempts} times in a row, each time before the job got further than before: the job appears to kill its worker (a poison job), so it is not run again"
        ),
    })
    .unwrap_or_default()
}

/// The error of a job cancelled while queued (`study`: by cancelling that study).
pub(super) fn cancelled_while_queued(study: Option<&str>) -> String {
    let message = match study {
        Some(id) => format!("cancelled while queued, with study {id}"),
        None => "cancelled while queued".into(),
    };
    serde_json::to_string(&JobError {
        kind: FailureKind::Cancelled,
        message,
    })
    .unwrap_or_default()
}

/// The error of a job asked to cancel whose worker stopped before confirming.
pub(super) const CANCELLED_UNCONFIRMED: &str =
    r#"{"kind":"cancelled","message":"cancelled (its worker stopped before confirming)"}"#;

/// The decisions both backends make alike, apart from their SQL.
///
/// A page of `limit` items from up to `limit + 1` rows (newest first); the cursor is the
/// last item's `seq` when there was one more.
pub(super) fn page_of<T>(
    mut items: Vec<T>,
    limit: i64,
    seq: impl Fn(&T) -> i64,
) -> (Vec<T>, Option<i64>) {
    if items.len() as i64 > limit {
        items.truncate(limit as usize);
        let next = items.last().map(&seq);
        (items, next)
    } else {
        (items, None)
    }
}

/// A submission whose idempotency key names the stored job `(id, request_hash, kind)`:
/// the same request (a replay of that job) or `IdempotencyMismatch`.
pub(super) fn replay_of(
    stored: (String, Option<String>, String),
    job: &NewJob,
) -> Result<String, StoreError> {
    let (id, hash, kind) = stored;
    if hash.as_deref() != Some(job.request_hash.as_str()) || kind != job.kind.as_str() {
        return Err(StoreError::IdempotencyMismatch(id));
    }
    Ok(id)
}

/// The answer to a cancel, from the job after it: `cancelled_now` when this cancel ended it.
pub(super) fn cancel_answer(job: Job, cancelled_now: bool) -> Result<Job, StoreError> {
    if job.state.is_finished() && !(job.state == JobState::Cancelled && cancelled_now) {
        return Err(StoreError::Conflict {
            id: job.id,
            state: job.state,
            message: "only queued or running jobs can be cancelled".into(),
        });
    }
    Ok(job)
}

/// Why a job could not be deleted: unfinished, or a point of `study`.
pub(super) fn delete_refusal(job: Job, study: Option<String>) -> StoreError {
    let message = if job.state.is_finished() {
        format!(
            "it is a point of study {}; delete the study instead",
            study.unwrap_or_default()
        )
    } else {
        "only finished jobs can be deleted; cancel it first".into()
    };
    StoreError::Conflict {
        id: job.id,
        state: job.state,
        message,
    }
}
