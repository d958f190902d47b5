//! The store's contract: one suite, run against both backends (SQLite in a temporary
//! file, PostgreSQL in a throw-away server started by the suite, tests/service/common/postgres.rs).
//! Every test takes a fresh, empty store.

use crate::common;
use bearing_sim::store::{self, *};
use serde_json::json;
use std::sync::Arc;
use std::time::Duration;

/// Both backends of every contract test: `sqlite::name` and `postgres::name`.
macro_rules! contract {
    ($($name:ident),* $(,)?) => {
        mod sqlite {
            $(
                #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
                async fn $name() {
                    let (_dir, s) = super::sqlite_store().await;
                    super::$name(s).await;
                }
            )*
        }
        mod postgres {
            $(
                #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
                async fn $name() {
                    let Some(s) = super::postgres_store().await else { return };
                    super::$name(s).await;
                }
            )*
        }
    };
}

contract!(
    a_stale_lease_can_never_write,
    lost_leases_give_up_after_max_attempts_and_release_does_not_count,
    worker_deaths_with_headway_never_stop_a_job,
    claims_go_round_the_tenants_within_their_share,
    admission_idempotency_and_cancel,
    tenants_keep_their_idempotency_keys_and_listings_apart,
    listings_filter_and_page,
    artifacts_are_stored_counted_and_deleted_with_their_job,
    heartbeats_keep_progress_monotone_and_bump_the_version,
    a_cancel_requested_job_whose_worker_died_ends_cancelled,
    concurrent_claims_take_every_job_exactly_once,
    workers_claim_only_the_input_formats_they_run,
    study_points_keep_their_input_format,
    concurrent_submissions_fill_the_queue_to_its_bound_exactly,
    studies_share_identical_points_and_earlier_runs,
    a_run_is_reused_under_the_key_of_the_build_that_computed_it,
    a_study_over_the_queue_bound_stores_nothing,
    cancelling_a_study_spares_points_another_study_wants,
    deleting_studies_and_their_points,
    retention_deletes_only_what_finished_before_the_cutoff,
);

async fn sqlite_store() -> (tempfile::TempDir, Arc<dyn Store>) {
    let dir = tempfile::tempdir().unwrap();
    let url = format!("sqlite://{}", dir.path().join("t.db").display());
    let s = store::connect(&url).await.unwrap();
    (dir, s)
}

async fn postgres_store() -> Option<Arc<dyn Store>> {
    let url = common::pg_cluster()?.new_database().await;
    Some(store::connect(&url).await.unwrap())
}

fn new_job(key: Option<&str>, hash: &str) -> NewJob {
    new_job_of("", key, hash)
}

fn new_job_of(tenant: &str, key: Option<&str>, hash: &str) -> NewJob {
    NewJob {
        id: uuid::Uuid::now_v7().to_string(),
        tenant: tenant.into(),
        kind: JobKind::Simulation,
        label: "t".into(),
        input: json!({}),
        input_blob: None,
        idempotency_key: key.map(String::from),
        request_hash: hash.into(),
        input_format: INPUT_FORMAT,
    }
}

fn succeeded(artifacts: Vec<Artifact>) -> Outcome {
    Outcome::Succeeded {
        result: json!({"ok": true}),
        stats: None,
        artifacts,
        scene_key: None,
    }
}

/// Claim the next job and finish it as succeeded; returns its id.
async fn run_next(s: &Arc<dyn Store>) -> String {
    run_next_keyed(s, None).await
}

/// [`run_next`] by a worker whose build writes the scene key `key`.
async fn run_next_keyed(s: &Arc<dyn Store>, key: Option<&str>) -> String {
    let l = s
        .claim("W", 60_000)
        .await
        .unwrap()
        .expect("a queued job")
        .lease;
    let mut outcome = succeeded(vec![]);
    if let Outcome::Succeeded { scene_key, .. } = &mut outcome {
        *scene_key = key.map(String::from);
    }
    s.finish(&l, outcome).await.unwrap();
    l.id
}

async fn a_stale_lease_can_never_write(s: Arc<dyn Store>) {
    let id = s.create_job(new_job(None, "h"), 10).await.unwrap().job.id;
    // Worker A claims with a lease that is already over (as if it hung).
    let a = s.claim("A", -1).await.unwrap().unwrap().lease;
    assert_eq!((a.id.as_str(), a.attempt), (id.as_str(), 1));
    assert_eq!(s.recover_expired(3).await.unwrap(), 1);
    let b = s.claim("B", 60_000).await.unwrap().unwrap().lease;
    assert_eq!(b.attempt, 2);
    // A wakes up: every write of its lease is refused.
    assert!(matches!(
        s.heartbeat(&a, 0.5, 1000).await,
        Err(StoreError::LeaseLost)
    ));
    let late = Outcome::Failed {
        error: JobError {
            kind: FailureKind::Numerical,
            message: "stale".into(),
        },
        stats: None,
    };
    assert!(matches!(
        s.finish(&a, late).await,
        Err(StoreError::LeaseLost)
    ));
    assert!(matches!(s.release(&a).await, Err(StoreError::LeaseLost)));
    // B's outcome stands.
    s.heartbeat(&b, 0.5, 60_000).await.unwrap();
    s.finish(
        &b,
        Outcome::Succeeded {
            result: json!({"ok": true}),
            stats: None,
            artifacts: vec![],
            scene_key: None,
        },
    )
    .await
    .unwrap();
    let job = s.get_job(&id).await.unwrap();
    assert_eq!(job.state, JobState::Succeeded);
    assert_eq!(job.result, Some(json!({"ok": true})));
    assert!(s.claim("C", 1000).await.unwrap().is_none());
}

async fn lost_leases_give_up_after_max_attempts_and_release_does_not_count(s: Arc<dyn Store>) {
    let id = s.create_job(new_job(None, "h"), 10).await.unwrap().job.id;
    let l = s.claim("A", 60_000).await.unwrap().unwrap().lease;
    s.release(&l).await.unwrap();
    assert_eq!(s.get_job(&id).await.unwrap().attempt, 0);
    for _ in 0..2 {
        s.claim("A", -1).await.unwrap().unwrap();
        s.recover_expired(2).await.unwrap();
    }
    let job = s.get_job(&id).await.unwrap();
    assert_eq!(job.state, JobState::Failed);
    assert_eq!(job.error.unwrap().kind, FailureKind::LeaseExpired);
}

/// A job whose worker dies again and again (restarts, SIGKILLs) is requeued every time as
/// long as it gets further than before; deaths at one point in a row stop it, saying why.
async fn worker_deaths_with_headway_never_stop_a_job(s: Arc<dyn Store>) {
    let id = s.create_job(new_job(None, "h"), 10).await.unwrap().job.id;
    // A dies twice without headway: 2 strikes of 3
    for _ in 0..2 {
        let l = s.claim("A", -1).await.unwrap().unwrap().lease;
        s.heartbeat(&l, 0.0, -1).await.unwrap();
        s.recover_expired(3).await.unwrap();
    }
    // ten deaths, each further than before: never stopped, and the strikes start again
    for k in 1..=10 {
        let l = s.claim("A", -1).await.unwrap().unwrap().lease;
        s.heartbeat(&l, 0.05 * k as f64, -1).await.unwrap();
        s.recover_expired(3).await.unwrap();
        let job = s.get_job(&id).await.unwrap();
        assert_eq!(job.state, JobState::Queued, "death {k}: {:?}", job.error);
    }
    // within 1% of the best is no headway: the third such death in a row stops it
    for k in 1..=3 {
        let l = s.claim("A", -1).await.unwrap().unwrap().lease;
        s.heartbeat(&l, 0.505, -1).await.unwrap();
        s.recover_expired(3).await.unwrap();
        let job = s.get_job(&id).await.unwrap();
        let want = if k < 3 {
            JobState::Queued
        } else {
            JobState::Failed
        };
        assert_eq!(job.state, want, "death {k} without headway");
    }
    let err = s.get_job(&id).await.unwrap().error.unwrap();
    assert_eq!(err.kind, FailureKind::LeaseExpired);
    assert!(err.message.contains("poison"), "{}", err.message);
}

/// Claims take the tenant running fewest first (then the oldest job), and never a job of
/// a tenant already running its share.
async fn claims_go_round_the_tenants_within_their_share(s: Arc<dyn Store>) {
    let mut a = Vec::new();
    for i in 0..3 {
        a.push(
            s.create_job(new_job_of("a", None, &format!("a{i}")), 10)
                .await
                .unwrap()
                .job
                .id,
        );
    }
    let b = s
        .create_job(new_job_of("b", None, "b0"), 10)
        .await
        .unwrap()
        .job
        .id;
    let claim = |share: i64| {
        let s = s.clone();
        async move {
            s.claim_shared("W", 60_000, INPUT_FORMAT, share)
                .await
                .unwrap()
                .map(|c| c.lease.id)
        }
    };
    // no bound: round robin, so b's job, queued last, runs second
    assert_eq!(claim(i64::MAX).await.as_deref(), Some(a[0].as_str()));
    assert_eq!(claim(i64::MAX).await.as_deref(), Some(b.as_str()));
    assert_eq!(claim(i64::MAX).await.as_deref(), Some(a[1].as_str()));
    // a share of 2: a runs 2 already, b has nothing queued
    assert_eq!(claim(2).await, None);
    assert_eq!(claim(3).await.as_deref(), Some(a[2].as_str()));
}

async fn admission_idempotency_and_cancel(s: Arc<dyn Store>) {
    let first = s.create_job(new_job(Some("k"), "h1"), 2).await.unwrap();
    assert!(first.created);
    let replay = s.create_job(new_job(Some("k"), "h1"), 2).await.unwrap();
    assert!(!replay.created);
    assert_eq!(replay.job.id, first.job.id);
    assert!(matches!(
        s.create_job(new_job(Some("k"), "h2"), 2).await,
        Err(StoreError::IdempotencyMismatch(_))
    ));
    s.create_job(new_job(None, "h"), 2).await.unwrap();
    assert!(matches!(
        s.create_job(new_job(None, "h"), 2).await,
        Err(StoreError::QueueFull(2))
    ));

    // queued -> cancelled at once; running -> flagged, seen by the heartbeat
    let c = s.request_cancel(&first.job.id).await.unwrap();
    assert_eq!(c.state, JobState::Cancelled);
    assert!(matches!(
        s.request_cancel(&first.job.id).await,
        Err(StoreError::Conflict { .. })
    ));
    let l = s.claim("A", 60_000).await.unwrap().unwrap().lease;
    assert!(!s.heartbeat(&l, 0.1, 60_000).await.unwrap().cancel_requested);
    assert_eq!(
        s.request_cancel(&l.id).await.unwrap().state,
        JobState::Running
    );
    assert!(s.heartbeat(&l, 0.2, 60_000).await.unwrap().cancel_requested);
    assert!(matches!(
        s.delete_job(&l.id).await,
        Err(StoreError::Conflict { .. })
    ));
    assert!(matches!(
        s.get_job("nope").await,
        Err(StoreError::NotFound(_))
    ));
}

async fn tenants_keep_their_idempotency_keys_and_listings_apart(s: Arc<dyn Store>) {
    let a = s
        .create_job(new_job_of("a", Some("k"), "h1"), 10)
        .await
        .unwrap();
    // the same key from another tenant is another request, not a replay or a mismatch
    let b = s
        .create_job(new_job_of("b", Some("k"), "h2"), 10)
        .await
        .unwrap();
    assert!(a.created && b.created);
    assert_ne!(a.job.id, b.job.id);
    let replay = s
        .create_job(new_job_of("a", Some("k"), "h1"), 10)
        .await
        .unwrap();
    assert_eq!((replay.created, replay.job.id), (false, a.job.id.clone()));
    assert_eq!(replay.job.tenant, "a");
    let only_a = ListFilter {
        tenant: Some("a".into()),
        limit: 10,
        ..Default::default()
    };
    let page = s.list_jobs(&only_a).await.unwrap();
    assert_eq!(page.jobs.len(), 1);
    assert_eq!(page.jobs[0].id, a.job.id);
    let all = ListFilter {
        limit: 10,
        ..Default::default()
    };
    assert_eq!(s.list_jobs(&all).await.unwrap().jobs.len(), 2);
}

async fn listings_filter_and_page(s: Arc<dyn Store>) {
    let mut ids = vec![];
    for _ in 0..5 {
        ids.push(s.create_job(new_job(None, "h"), 100).await.unwrap().job.id);
    }
    let mut analysis = new_job(None, "h");
    analysis.kind = JobKind::Analysis;
    analysis.input_blob = Some(vec![1u8; 16]);
    ids.push(s.create_job(analysis, 100).await.unwrap().job.id);
    let running = s.claim("W", 60_000).await.unwrap().unwrap().lease.id;
    assert_eq!(running, ids[0], "the oldest queued job is claimed first");

    // newest first, three pages of two
    let mut seen = vec![];
    let mut before = None;
    for page_no in 0..3 {
        let page = s
            .list_jobs(&ListFilter {
                before,
                limit: 2,
                ..Default::default()
            })
            .await
            .unwrap();
        assert_eq!(page.jobs.len(), 2);
        seen.extend(page.jobs.iter().map(|j| j.id.clone()));
        before = page.next;
        assert_eq!(before.is_some(), page_no < 2, "page {page_no}");
    }
    let newest_first: Vec<String> = ids.iter().rev().cloned().collect();
    assert_eq!(seen, newest_first);

    let count = |kind, state| {
        let s = s.clone();
        async move {
            s.list_jobs(&ListFilter {
                kind,
                state,
                limit: 100,
                ..Default::default()
            })
            .await
            .unwrap()
            .jobs
            .len()
        }
    };
    assert_eq!(count(Some(JobKind::Analysis), None).await, 1);
    assert_eq!(count(None, Some(JobState::Running)).await, 1);
    assert_eq!(
        count(Some(JobKind::Simulation), Some(JobState::Queued)).await,
        4
    );
    let c = s.counts().await.unwrap();
    assert_eq!((c.queued, c.running, c.succeeded), (5, 1, 0));
}

async fn artifacts_are_stored_counted_and_deleted_with_their_job(s: Arc<dyn Store>) {
    let empty = s.stored_bytes().await.unwrap();
    assert_eq!(empty, 0);
    let mut job = new_job(None, "h");
    job.kind = JobKind::Analysis;
    job.input_blob = Some(vec![7u8; 800]);
    let id = s.create_job(job, 10).await.unwrap().job.id;
    let queued_bytes = s.stored_bytes().await.unwrap();
    // the JSON input "{}" (2 bytes) and the 800-byte blob
    assert_eq!(queued_bytes, 802);

    let claimed = s.claim("W", 60_000).await.unwrap().unwrap();
    assert_eq!(claimed.input_blob.as_deref(), Some(&[7u8; 800][..]));
    let data: Vec<u8> = (0..4000u32).map(|i| (i % 251) as u8).collect();
    let meta = ArtifactMeta::Spectrum {
        df: 0.5,
        bins: 1000,
    };
    let art = Artifact {
        name: "spectrum:raw".into(),
        meta: meta.clone(),
        data: data.clone(),
    };
    s.finish(&claimed.lease, succeeded(vec![art]))
        .await
        .unwrap();
    let got = s.get_artifact(&id, "spectrum:raw").await.unwrap().unwrap();
    assert_eq!((got.meta, got.data), (meta.clone(), data));
    assert!(s
        .get_artifact(&id, "spectrum:level:1")
        .await
        .unwrap()
        .is_none());
    let meta_len = serde_json::to_string(&meta).unwrap().len() as i64;
    let result_len = json!({"ok": true}).to_string().len() as i64;
    assert_eq!(
        s.stored_bytes().await.unwrap(),
        queued_bytes + result_len + 4000 + meta_len
    );

    s.delete_job(&id).await.unwrap();
    assert!(s.get_artifact(&id, "spectrum:raw").await.unwrap().is_none());
    assert!(matches!(s.get_job(&id).await, Err(StoreError::NotFound(_))));
    assert_eq!(s.stored_bytes().await.unwrap(), 0);
}

async fn heartbeats_keep_progress_monotone_and_bump_the_version(s: Arc<dyn Store>) {
    let id = s.create_job(new_job(None, "h"), 10).await.unwrap().job.id;
    let l = s.claim("W", 60_000).await.unwrap().unwrap().lease;
    let read = || async { s.get_job(&id).await.unwrap() };
    let v0 = read().await.version;
    s.heartbeat(&l, 0.5, 60_000).await.unwrap();
    let j = read().await;
    assert_eq!((j.progress, j.version), (0.5, v0 + 1));
    // going back, NaN or nothing new: no visible change (the ETag holds)
    for p in [0.3, f64::NAN, 0.5] {
        s.heartbeat(&l, p, 60_000).await.unwrap();
        let j = read().await;
        assert_eq!((j.progress, j.version), (0.5, v0 + 1), "after {p}");
    }
    s.heartbeat(&l, 2.0, 60_000).await.unwrap();
    assert_eq!(read().await.progress, 1.0, "clamped to 1");
    assert_eq!(read().await.state, JobState::Running);
}

async fn a_cancel_requested_job_whose_worker_died_ends_cancelled(s: Arc<dyn Store>) {
    let id = s.create_job(new_job(None, "h"), 10).await.unwrap().job.id;
    s.claim("A", -1).await.unwrap().unwrap();
    let j = s.request_cancel(&id).await.unwrap();
    assert_eq!((j.state, j.cancel_requested), (JobState::Running, true));
    assert_eq!(s.recover_expired(3).await.unwrap(), 1);
    let j = s.get_job(&id).await.unwrap();
    assert_eq!(j.state, JobState::Cancelled);
    assert_eq!(j.error.unwrap().kind, FailureKind::Cancelled);
    assert!(s.claim("B", 1000).await.unwrap().is_none(), "not run again");
}

/// A mixed-version deployment: a job written in a newer input format waits for a worker
/// that runs it, and does not hold up the older-format jobs queued behind it.
async fn workers_claim_only_the_input_formats_they_run(s: Arc<dyn Store>) {
    let newer = NewJob {
        input_format: INPUT_FORMAT + 1,
        ..new_job(None, "n")
    };
    let newer = s.create_job(newer, 10).await.unwrap().job.id;
    let older = s.create_job(new_job(None, "o"), 10).await.unwrap().job.id;
    let c = s.claim("old worker", 60_000).await.unwrap().unwrap();
    assert_eq!(
        c.lease.id, older,
        "the older format is taken past the newer one"
    );
    s.finish(&c.lease, succeeded(vec![])).await.unwrap();
    assert!(
        s.claim("old worker", 60_000).await.unwrap().is_none(),
        "a worker never claims a format newer than its own"
    );
    assert_eq!(s.get_job(&newer).await.unwrap().state, JobState::Queued);
    let c = s
        .claim_up_to("new worker", 60_000, INPUT_FORMAT + 1)
        .await
        .unwrap()
        .unwrap();
    assert_eq!((c.lease.id.as_str(), c.lease.attempt), (newer.as_str(), 1));
    // and a newer worker still runs every older format: "at most", not "equal"
    let older = s.create_job(new_job(None, "o2"), 10).await.unwrap().job.id;
    let c = s
        .claim_up_to("new worker", 60_000, INPUT_FORMAT + 1)
        .await
        .unwrap()
        .expect("an older-format job for a newer worker");
    assert_eq!(c.lease.id, older);
}

/// A study's points are stored in the format their jobs carry, like single jobs: a study
/// submitted through a newer node is not run by an older worker either.
async fn study_points_keep_their_input_format(s: Arc<dyn Store>) {
    let mut study = new_study("", &["k1"]);
    study.points[0].job.input_format = INPUT_FORMAT + 1;
    let point = s.create_study(study, 10).await.unwrap().study.points[0]
        .job
        .id
        .clone();
    assert!(
        s.claim("old worker", 60_000).await.unwrap().is_none(),
        "a study point in a newer format waits for a newer worker"
    );
    let c = s
        .claim_up_to("new worker", 60_000, INPUT_FORMAT + 1)
        .await
        .unwrap()
        .unwrap();
    assert_eq!(c.lease.id, point);
}

async fn concurrent_claims_take_every_job_exactly_once(s: Arc<dyn Store>) {
    const JOBS: usize = 60;
    for _ in 0..JOBS {
        s.create_job(new_job(None, "h"), 1000).await.unwrap();
    }
    let claimers: Vec<_> = (0..6)
        .map(|w| {
            let s = s.clone();
            tokio::spawn(async move {
                let mut mine = vec![];
                while let Some(c) = s.claim(&format!("w{w}"), 60_000).await.unwrap() {
                    s.finish(&c.lease, succeeded(vec![])).await.unwrap();
                    mine.push(c.lease.id);
                }
                mine
            })
        })
        .collect();
    let mut all = vec![];
    for c in claimers {
        all.extend(c.await.unwrap());
    }
    let distinct: std::collections::HashSet<_> = all.iter().collect();
    assert_eq!((all.len(), distinct.len()), (JOBS, JOBS), "each job once");
    let page = s
        .list_jobs(&ListFilter {
            limit: 1000,
            ..Default::default()
        })
        .await
        .unwrap();
    for j in page.jobs {
        assert_eq!((j.state, j.attempt), (JobState::Succeeded, 1), "{}", j.id);
    }
}

async fn concurrent_submissions_fill_the_queue_to_its_bound_exactly(s: Arc<dyn Store>) {
    // 8 clients x 10 submissions against a bound of 25: the admission check and the
    // insert must act as one, or two clients both take the 25th place.
    let clients: Vec<_> = (0..8)
        .map(|_| {
            let s = s.clone();
            tokio::spawn(async move {
                let (mut accepted, mut full) = (0, 0);
                for _ in 0..10 {
                    match s.create_job(new_job(None, "h"), 25).await {
                        Ok(_) => accepted += 1,
                        Err(StoreError::QueueFull(_)) => full += 1,
                        Err(e) => panic!("{e}"),
                    }
                }
                (accepted, full)
            })
        })
        .collect();
    let (mut accepted, mut full) = (0, 0);
    for c in clients {
        let (a, f) = c.await.unwrap();
        accepted += a;
        full += f;
    }
    assert_eq!((accepted, full), (25, 55));
    assert_eq!(s.counts().await.unwrap().queued, 25);
}

/// A study of `tenant` whose points have these scene keys.
fn new_study(tenant: &str, keys: &[&str]) -> NewStudy {
    NewStudy {
        id: uuid::Uuid::now_v7().to_string(),
        tenant: tenant.into(),
        label: "s".into(),
        request: json!({"keys": keys}),
        design: json!({"type": "list"}),
        points: keys
            .iter()
            .map(|k| NewStudyPoint {
                spec: json!({"key": k}),
                scene_key: k.to_string(),
                job: new_job_of(tenant, None, k),
            })
            .collect(),
    }
}

async fn studies_share_identical_points_and_earlier_runs(s: Arc<dyn Store>) {
    let a = s
        .create_study(new_study("", &["k1", "k2", "k1"]), 100)
        .await
        .unwrap();
    assert_eq!((a.queued, a.shared), (2, 1));
    let pa = &a.study.points;
    assert_eq!(pa.len(), 3);
    assert_eq!(pa[0].job.id, pa[2].job.id);
    assert_ne!(pa[0].job.id, pa[1].job.id);
    assert_eq!(pa[1].spec, json!({"key": "k2"}));
    assert_eq!(run_next(&s).await, pa[0].job.id);

    // a later study reuses the succeeded run of k1 and queues only k3
    let b = s
        .create_study(new_study("", &["k1", "k3"]), 100)
        .await
        .unwrap();
    assert_eq!((b.queued, b.shared), (1, 1));
    assert_eq!(b.study.points[0].job.id, pa[0].job.id);
    assert_eq!(b.study.points[0].job.state, JobState::Succeeded);
    let a_now = s.get_study(&a.study.id).await.unwrap();
    assert!(a_now.points[0].shared_with_other_studies);
    assert!(!a_now.points[1].shared_with_other_studies);

    // another tenant shares nothing
    let c = s.create_study(new_study("x", &["k1"]), 100).await.unwrap();
    assert_eq!((c.queued, c.shared), (1, 0));

    let page = s.list_studies(None, None, 2).await.unwrap();
    assert_eq!(page.studies.len(), 2);
    assert_eq!(page.studies[0].id, c.study.id, "newest first");
    let rest = s.list_studies(None, page.next, 2).await.unwrap();
    assert_eq!(rest.studies.len(), 1);
    assert_eq!(rest.studies[0].id, a.study.id);
    assert_eq!(rest.next, None);
    let x = s.list_studies(Some("x"), None, 10).await.unwrap();
    assert_eq!(x.studies.len(), 1);
    assert_eq!(x.studies[0].points.len(), 1);
    assert!(matches!(
        s.get_study("nope").await,
        Err(StoreError::StudyNotFound(_))
    ));
}

/// During a rolling upgrade a newer node's study point may be run by an older worker: the
/// worker's outcome writes the key of its own build, so the newer build's later studies
/// queue the point again and the older build's reuse it.
async fn a_run_is_reused_under_the_key_of_the_build_that_computed_it(s: Arc<dyn Store>) {
    let study = |key: &'static str| {
        let s = s.clone();
        async move { s.create_study(new_study("", &[key]), 100).await.unwrap() }
    };
    let a = study("new-build").await;
    let run = run_next_keyed(&s, Some("old-build")).await;
    assert_eq!(run, a.study.points[0].job.id);
    let newer = study("new-build").await;
    assert_eq!((newer.queued, newer.shared), (1, 0));
    assert_ne!(newer.study.points[0].job.id, run);
    let older = study("old-build").await;
    assert_eq!((older.queued, older.shared), (0, 1));
    assert_eq!(older.study.points[0].job.id, run);
    // the first study keeps its point's run
    let a_now = s.get_study(&a.study.id).await.unwrap();
    assert_eq!(a_now.points[0].job.id, run);

    // a simulation submitted on its own has no key and gets none: no study takes it over
    // (it stays the submitter's to delete)
    assert_eq!(run_next(&s).await, newer.study.points[0].job.id);
    let own = s
        .create_job(new_job(None, "own"), 100)
        .await
        .unwrap()
        .job
        .id;
    assert_eq!(run_next_keyed(&s, Some("own-build")).await, own);
    let later = study("own-build").await;
    assert_eq!((later.queued, later.shared), (1, 0));
    assert_ne!(later.study.points[0].job.id, own);
}

async fn a_study_over_the_queue_bound_stores_nothing(s: Arc<dyn Store>) {
    s.create_job(new_job(None, "h"), 10).await.unwrap();
    assert!(matches!(
        s.create_study(new_study("", &["k1", "k2", "k3"]), 3).await,
        Err(StoreError::QueueFull(1))
    ));
    assert!(s
        .list_studies(None, None, 10)
        .await
        .unwrap()
        .studies
        .is_empty());
    assert_eq!(s.counts().await.unwrap().queued, 1);
    // it fits once the bound allows it
    s.create_study(new_study("", &["k1", "k2", "k3"]), 4)
        .await
        .unwrap();
}

async fn cancelling_a_study_spares_points_another_study_wants(s: Arc<dyn Store>) {
    let a = s
        .create_study(new_study("", &["k1", "k2", "k3"]), 100)
        .await
        .unwrap();
    let b = s.create_study(new_study("", &["k3"]), 100).await.unwrap();
    let ids: Vec<String> = a.study.points.iter().map(|p| p.job.id.clone()).collect();
    assert_eq!(b.study.points[0].job.id, ids[2]);
    let running = s.claim("W", 60_000).await.unwrap().unwrap().lease;
    assert_eq!(running.id, ids[0]);

    let a_now = s.cancel_study(&a.study.id).await.unwrap();
    assert!(a_now.cancel_requested);
    let state = |i: usize| a_now.points[i].job.clone();
    assert_eq!(
        (state(0).state, state(0).cancel_requested),
        (JobState::Running, true)
    );
    assert_eq!(state(1).state, JobState::Cancelled);
    assert_eq!(state(2).state, JobState::Queued, "study B still wants it");
    assert!(!state(2).cancel_requested);
    assert!(
        s.heartbeat(&running, 0.1, 60_000)
            .await
            .unwrap()
            .cancel_requested
    );

    // B's cancel takes k3 now that A no longer wants it
    let b_now = s.cancel_study(&b.study.id).await.unwrap();
    assert_eq!(b_now.points[0].job.state, JobState::Cancelled);
    s.finish(
        &running,
        Outcome::Cancelled {
            error: JobError {
                kind: FailureKind::Cancelled,
                message: "cancelled".into(),
            },
        },
    )
    .await
    .unwrap();
    assert!(matches!(
        s.cancel_study(&b.study.id).await,
        Err(StoreError::StudyConflict { .. })
    ));
    assert!(matches!(
        s.cancel_study("nope").await,
        Err(StoreError::StudyNotFound(_))
    ));
}

async fn deleting_studies_and_their_points(s: Arc<dyn Store>) {
    let a = s.create_study(new_study("", &["k1"]), 100).await.unwrap();
    let b = s
        .create_study(new_study("", &["k1", "k2"]), 100)
        .await
        .unwrap();
    let k1 = a.study.points[0].job.id.clone();
    let l = s.claim("W", 60_000).await.unwrap().unwrap().lease;
    assert_eq!(l.id, k1);
    // A's only point is running but B holds it too: A can go, the job stays
    s.delete_study(&a.study.id).await.unwrap();
    assert!(matches!(
        s.get_study(&a.study.id).await,
        Err(StoreError::StudyNotFound(_))
    ));
    assert_eq!(s.get_job(&k1).await.unwrap().state, JobState::Running);
    // B alone holds the running point now
    assert!(matches!(
        s.delete_study(&b.study.id).await,
        Err(StoreError::StudyConflict { .. })
    ));
    s.finish(&l, succeeded(vec![])).await.unwrap();
    run_next(&s).await;
    assert!(matches!(
        s.delete_job(&k1).await,
        Err(StoreError::Conflict { .. })
    ));
    s.delete_study(&b.study.id).await.unwrap();
    for p in &b.study.points {
        assert!(matches!(
            s.get_job(&p.job.id).await,
            Err(StoreError::NotFound(_))
        ));
    }
    assert!(matches!(
        s.delete_study("nope").await,
        Err(StoreError::StudyNotFound(_))
    ));
    assert_eq!(s.stored_bytes().await.unwrap(), 0);
}

async fn retention_deletes_only_what_finished_before_the_cutoff(s: Arc<dyn Store>) {
    let done = s.create_job(new_job(None, "h"), 10).await.unwrap().job.id;
    run_next(&s).await;
    let st = s.create_study(new_study("", &["k1"]), 10).await.unwrap();
    run_next(&s).await;
    // one job left running, one queued: neither has finished, neither goes
    let running = s.create_job(new_job(None, "h"), 10).await.unwrap().job.id;
    s.create_job(new_job(None, "h"), 10).await.unwrap();
    assert_eq!(
        s.claim("W", 60_000).await.unwrap().unwrap().lease.id,
        running
    );

    assert_eq!(s.expire(now_ms() - 60_000).await.unwrap(), (0, 0));
    assert_eq!(s.expire(now_ms() + 1000).await.unwrap(), (2, 1));
    assert!(matches!(
        s.get_job(&done).await,
        Err(StoreError::NotFound(_))
    ));
    assert!(matches!(
        s.get_study(&st.study.id).await,
        Err(StoreError::StudyNotFound(_))
    ));
    let c = s.counts().await.unwrap();
    assert_eq!((c.queued, c.running, c.succeeded), (1, 1, 0));
}

/// PostgreSQL only (SQLite has no other process to hear from): a job queued through one
/// connection pool wakes the workers listening through another.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn postgres_notifies_listeners_of_new_and_requeued_work() {
    let Some(url) = (match common::pg_cluster() {
        Some(c) => Some(c.new_database().await),
        None => None,
    }) else {
        return;
    };
    let api = store::connect(&url).await.unwrap();
    let worker = store::connect(&url).await.unwrap();
    let wake = Arc::new(tokio::sync::Notify::new());
    worker.wake_on_new_work(wake.clone()).await.unwrap();
    let wait = Duration::from_secs(10);

    let woken = wake.notified();
    api.create_job(new_job(None, "h"), 10).await.unwrap();
    tokio::time::timeout(wait, woken)
        .await
        .expect("woken by a new job");

    let lease = worker.claim("W", -1).await.unwrap().unwrap().lease;
    let woken = wake.notified();
    api.recover_expired(3).await.unwrap();
    tokio::time::timeout(wait, woken)
        .await
        .expect("woken by a requeued job");
    let _ = lease;

    // a claim, a heartbeat or a finish makes no work for anyone
    let l = worker.claim("W", 60_000).await.unwrap().unwrap().lease;
    let woken = wake.notified();
    worker.heartbeat(&l, 0.5, 60_000).await.unwrap();
    worker.finish(&l, succeeded(vec![])).await.unwrap();
    assert!(
        tokio::time::timeout(Duration::from_millis(300), woken)
            .await
            .is_err(),
        "woken with nothing to claim"
    );
}

/// Upgrading the embedded database keeps what was queued: a job stored before jobs had an
/// input format (schema of migrations 0001-0003) is format 1 after the migration and runs.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_job_queued_before_the_input_format_column_is_claimed_after_the_upgrade() {
    let dir = tempfile::tempdir().unwrap();
    let old = dir.path().join("old-migrations");
    std::fs::create_dir(&old).unwrap();
    let here = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("migrations/sqlite");
    for name in ["0001_jobs.sql", "0002_studies.sql", "0003_tenants.sql"] {
        std::fs::copy(here.join(name), old.join(name)).unwrap();
    }
    let url = format!("sqlite://{}?mode=rwc", dir.path().join("t.db").display());
    {
        let pool = sqlx::SqlitePool::connect(&url).await.unwrap();
        sqlx::migrate::Migrator::new(old.as_path())
            .await
            .unwrap()
            .run(&pool)
            .await
            .unwrap();
        sqlx::query(
            "INSERT INTO jobs (id, kind, state, input, created_at, updated_at) \
             VALUES ('before', 'simulation', 'queued', '{}', 1, 1)",
        )
        .execute(&pool)
        .await
        .unwrap();
        pool.close().await;
    }
    let s = store::connect(&url).await.unwrap();
    let c = s.claim("W", 60_000).await.unwrap().expect("the old job");
    assert_eq!(c.lease.id, "before");
}

/// A rolling upgrade: once a newer release has migrated the database, this one still opens
/// it (and runs), on both backends. Without that, an older node that restarts mid-upgrade
/// could not come back, and an upgrade could not be rolled back.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_database_migrated_by_a_newer_release_still_opens() {
    // what sqlx records for a migration this release does not have
    const NEWER: &str = "INSERT INTO _sqlx_migrations \
         (version, description, success, checksum, execution_time) \
         VALUES (99999999, 'from a newer release', TRUE, $1, 1)";
    let dir = tempfile::tempdir().unwrap();
    let mut urls = vec![format!("sqlite://{}", dir.path().join("t.db").display())];
    if let Some(c) = common::pg_cluster() {
        urls.push(c.new_database().await);
    }
    for url in urls {
        drop(store::connect(&url).await.unwrap());
        // the same statement through either backend's own pool type
        macro_rules! record_newer {
            ($pool:ty) => {{
                let pool = <$pool>::connect(&url).await.unwrap();
                sqlx::query(NEWER)
                    .bind(vec![0u8; 48])
                    .execute(&pool)
                    .await
                    .unwrap();
                pool.close().await;
            }};
        }
        if url.starts_with("sqlite") {
            record_newer!(sqlx::SqlitePool)
        } else {
            record_newer!(sqlx::PgPool)
        }
        let s = store::connect(&url)
            .await
            .unwrap_or_else(|e| panic!("{url}: a newer migration stops the store: {e}"));
        s.create_job(new_job(None, "h"), 10).await.unwrap();
        assert!(s.claim("W", 60_000).await.unwrap().is_some(), "{url}");
    }
}
