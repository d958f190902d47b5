//! What the API shows of studies: state and progress derived from the points' jobs, the
//! ETag over the study and its points, and the table's rows read from the stored records.

use super::problem::{ApiResult, Problem};
use super::results::record;
use super::submission::Fnv1a;
use super::views::{bounded_text, MAX_ERROR_CHARS};
use crate::jobs::record::SimulationRecord;
use crate::store::{JobError, JobState, Study, StudyPointRow};
use crate::studies::charts::plot_names;
use bearing_core::scene::MAX_NAME_CHARS;
use bearing_core::study::{DesignSummary, PointSpec, PointState, RunDigest, StudyTableRow};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use utoipa::ToSchema;

/// A study's state, from its points': queued until a point runs, running until every
/// point has finished, then succeeded (some points may have failed: see `progress`),
/// failed (every point failed) or cancelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum StudyState {
    Queued,
    Running,
    Succeeded,
    Failed,
    Cancelled,
}

impl StudyState {
    pub fn is_finished(self) -> bool {
        matches!(
            self,
            StudyState::Succeeded | StudyState::Failed | StudyState::Cancelled
        )
    }
}

/// How far a study is.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct StudyProgress {
    pub points_total: usize,
    /// Points finished, whatever their outcome.
    pub points_done: usize,
    pub points_succeeded: usize,
    pub points_failed: usize,
    pub points_cancelled: usize,
    /// Simulated time of every point, s.
    pub simulated_time_total: f64,
    /// Simulated time done (finished points count whole, running ones by progress), s.
    pub simulated_time_done: f64,
    /// `simulated_time_done / simulated_time_total`, 0..=1.
    #[schema(minimum = 0.0, maximum = 1.0)]
    pub fraction: f64,
}

/// One point of a study and its simulation job.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct StudyPointView {
    pub index: usize,
    /// The simulation job that runs it (`/v1/simulations/{job_id}`).
    pub job_id: String,
    pub state: JobState,
    /// Fraction of the point's simulated time done, 0..=1.
    pub progress: f64,
    /// Another point, of this study or another, runs on the same job (identical scenes).
    pub shared: bool,
    #[serde(flatten)]
    pub spec: PointSpec,
    pub error: Option<JobError>,
}

/// A study as the API shows it.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct StudyView {
    pub id: String,
    pub name: String,
    pub state: StudyState,
    pub cancel_requested: bool,
    pub design: DesignSummary,
    pub progress: StudyProgress,
    /// RFC 3339, UTC.
    #[schema(format = DateTime)]
    pub created_at: String,
    #[schema(format = DateTime)]
    pub updated_at: String,
    pub points: Vec<StudyPointView>,
    /// `self`, `cancel`, `table`, and one `plot:<name>` per plot.
    pub links: BTreeMap<String, String>,
}

/// One page of studies, newest first.
#[derive(Debug, Clone, Serialize, ToSchema)]
pub struct StudyPage {
    pub items: Vec<StudyView>,
    /// Cursor of the next (older) page; null on the last page.
    pub next_cursor: Option<String>,
}

pub fn study_location(id: &str) -> String {
    format!("/v1/studies/{id}")
}

/// The stored design of a study.
pub fn design_of(study: &Study) -> ApiResult<DesignSummary> {
    serde_json::from_value(study.design.clone()).map_err(|e| {
        Problem::internal(format!(
            "stored design of study {} does not parse: {e}",
            study.id
        ))
    })
}

pub fn spec_of(study: &Study, p: &StudyPointRow) -> ApiResult<PointSpec> {
    serde_json::from_value(p.spec.clone()).map_err(|e| {
        Problem::internal(format!(
            "stored point {} of study {} does not parse: {e}",
            p.index, study.id
        ))
    })
}

/// Strong ETag over the study's own version and every point's job version.
pub fn study_etag(study: &Study) -> String {
    // any point's change changes the tag
    let mut h = Fnv1a::default();
    h.write(&study.version.to_le_bytes());
    for p in &study.points {
        h.write(&p.job.seq.to_le_bytes());
        h.write(&p.job.version.to_le_bytes());
    }
    format!("\"{}-{:016x}\"", &study.id[..study.id.len().min(8)], h.0)
}

pub fn study_state(study: &Study) -> StudyState {
    let states: Vec<JobState> = study.points.iter().map(|p| p.job.state).collect();
    if states.iter().any(|s| !s.is_finished()) {
        if states.iter().any(|s| *s != JobState::Queued) {
            StudyState::Running
        } else {
            StudyState::Queued
        }
    } else if study.cancel_requested {
        StudyState::Cancelled
    } else if states.contains(&JobState::Succeeded) {
        StudyState::Succeeded
    } else if states.iter().all(|s| *s == JobState::Cancelled) {
        StudyState::Cancelled
    } else {
        StudyState::Failed
    }
}

pub fn view(study: &Study) -> ApiResult<StudyView> {
    let design = design_of(study)?;
    let mut points = Vec::with_capacity(study.points.len());
    let (mut total, mut done_time) = (0.0, 0.0);
    let count = |s: JobState| study.points.iter().filter(|p| p.job.state == s).count();
    let (succeeded, failed, cancelled) = (
        count(JobState::Succeeded),
        count(JobState::Failed),
        count(JobState::Cancelled),
    );
    let mut per_job: BTreeMap<&str, usize> = BTreeMap::new();
    for p in &study.points {
        *per_job.entry(p.job.id.as_str()).or_default() += 1;
    }
    for p in &study.points {
        let spec = spec_of(study, p)?;
        total += spec.duration;
        done_time += if p.job.state.is_finished() {
            spec.duration
        } else {
            spec.duration * p.job.progress
        };
        points.push(StudyPointView {
            index: p.index,
            job_id: p.job.id.clone(),
            state: p.job.state,
            progress: p.job.progress,
            shared: p.shared_with_other_studies || per_job[p.job.id.as_str()] > 1,
            spec,
            error: p.job.error.as_ref().map(|e| JobError {
                kind: e.kind,
                message: bounded_text(&e.message, MAX_ERROR_CHARS),
            }),
        });
    }
    let base = study_location(&study.id);
    let mut links = BTreeMap::new();
    links.insert("self".to_string(), base.clone());
    links.insert("cancel".to_string(), format!("{base}/cancel"));
    links.insert("table".to_string(), format!("{base}/table"));
    // plot names come from the points' specs: no stored record is read to list them
    let names = plot_names(
        &design,
        points
            .iter()
            .map(|p| (p.spec.line.as_deref(), p.spec.fault_case)),
    );
    for n in &names {
        links.insert(format!("plot:{n}"), format!("{base}/plots/{n}"));
    }
    Ok(StudyView {
        id: study.id.clone(),
        name: bounded_text(&study.label, MAX_NAME_CHARS),
        state: study_state(study),
        cancel_requested: study.cancel_requested,
        design,
        progress: StudyProgress {
            points_total: study.points.len(),
            points_done: succeeded + failed + cancelled,
            points_succeeded: succeeded,
            points_failed: failed,
            points_cancelled: cancelled,
            simulated_time_total: total,
            simulated_time_done: done_time,
            fraction: if total > 0.0 {
                (done_time / total).clamp(0.0, 1.0)
            } else {
                0.0
            },
        },
        created_at: super::views::rfc3339(study.created_at),
        updated_at: super::views::rfc3339(
            study
                .points
                .iter()
                .map(|p| p.job.updated_at)
                .fold(study.updated_at, i64::max),
        ),
        points,
        links,
    })
}

/// What a table row needs of a succeeded point's stored record (`Err`: why it has none).
pub fn digest(p: &StudyPointRow) -> Result<RunDigest, String> {
    let rec: SimulationRecord = record(&p.job).map_err(|e| e.detail.clone())?;
    let analysis = rec.analysis.ok_or_else(|| {
        rec.analysis_error
            .unwrap_or_else(|| "no analysis was stored".into())
    })?;
    let frequencies = rec
        .frequencies
        .ok_or("the record predates frequency comparisons")?;
    Ok(RunDigest {
        frequencies,
        report: analysis.report,
        cage_speed: rec.cage.mean_speed,
        epicyclic_speed: rec.cage.epicyclic_speed,
        slip: rec.cage.slip,
        cage_motion: rec.cage.motion,
        wall_time: rec.solver.wall_time,
    })
}

/// A point's state is its job's.
fn point_state(s: JobState) -> PointState {
    match s {
        JobState::Queued => PointState::Queued,
        JobState::Running => PointState::Running,
        JobState::Succeeded => PointState::Succeeded,
        JobState::Failed => PointState::Failed,
        JobState::Cancelled => PointState::Cancelled,
    }
}

/// The table rows of a study, in point order.
pub fn rows(study: &Study) -> ApiResult<Vec<StudyTableRow>> {
    study
        .points
        .iter()
        .map(|p| {
            let spec = spec_of(study, p)?;
            let (d, err) = match p.job.state {
                JobState::Succeeded => match digest(p) {
                    Ok(d) => (Some(d), None),
                    Err(e) => (None, Some(e)),
                },
                _ => (
                    None,
                    p.job
                        .error
                        .as_ref()
                        .map(|e| format!("{}: {}", e.kind, e.message)),
                ),
            };
            Ok(StudyTableRow::new(
                p.index,
                &spec,
                Some(p.job.id.clone()),
                point_state(p.job.state),
                err,
                d.as_ref(),
            ))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store::{Job, JobKind};

    fn study(states: &[JobState], cancel_requested: bool) -> Study {
        let job = |i: usize, state: JobState| Job {
            seq: i as i64,
            id: format!("job-{i}"),
            tenant: String::new(),
            kind: JobKind::Simulation,
            state,
            label: String::new(),
            progress: 0.0,
            attempt: 1,
            cancel_requested: false,
            version: 1,
            created_at: 0,
            started_at: None,
            finished_at: None,
            updated_at: 0,
            error: None,
            stats: None,
            result: None,
        };
        Study {
            seq: 1,
            id: "study-1".into(),
            tenant: String::new(),
            label: String::new(),
            request: serde_json::Value::Null,
            design: serde_json::Value::Null,
            cancel_requested,
            version: 1,
            created_at: 0,
            updated_at: 0,
            points: states
                .iter()
                .enumerate()
                .map(|(i, s)| StudyPointRow {
                    index: i,
                    spec: serde_json::Value::Null,
                    job: job(i, *s),
                    shared_with_other_studies: false,
                })
                .collect(),
        }
    }

    #[test]
    fn a_failed_point_does_not_fail_the_study() {
        use JobState::*;
        let state = |s: &[JobState], c| study_state(&study(s, c));
        assert_eq!(state(&[Queued, Queued], false), StudyState::Queued);
        assert_eq!(state(&[Succeeded, Queued], false), StudyState::Running);
        assert_eq!(state(&[Succeeded, Failed], false), StudyState::Succeeded);
        assert_eq!(state(&[Failed, Failed], false), StudyState::Failed);
        assert_eq!(state(&[Succeeded, Cancelled], true), StudyState::Cancelled);
        assert_eq!(state(&[Cancelled, Cancelled], false), StudyState::Cancelled);
        // the tag moves with any point's version
        let a = study(&[Running, Queued], false);
        let mut b = a.clone();
        b.points[1].job.version += 1;
        assert_ne!(study_etag(&a), study_etag(&b));
    }
}
