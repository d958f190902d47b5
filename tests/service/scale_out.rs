//! Several machines on one PostgreSQL database, as processes: an API node that runs no
//! jobs (`serve --workers 0`) and `bearing-sim worker` processes. The server is the
//! suite's throw-away PostgreSQL (tests/service/common/postgres.rs).

use crate::common::*;
use serde_json::Value;
use sqlx::Connection;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicI64, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// A fresh database on the suite's server and a directory for the process logs.
async fn database() -> Option<(tempfile::TempDir, String)> {
    let url = pg_cluster()?.new_database().await;
    Some((tempfile::tempdir().unwrap(), url))
}

/// How many times each job id was started, from the workers' JSON logs.
fn starts_by_job(logs: &[String]) -> HashMap<String, usize> {
    let mut n = HashMap::new();
    for line in logs.iter().flat_map(|l| l.lines()) {
        let Ok(v) = serde_json::from_str::<Value>(line) else {
            continue;
        };
        if v["fields"]["message"] == "job started" {
            let id = v["span"]["id"].as_str().expect("the job span names its id");
            *n.entry(id.to_string()).or_insert(0) += 1;
        }
    }
    n
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn three_worker_processes_run_a_hundred_jobs_exactly_once() {
    let Some((dir, url)) = database().await else {
        return;
    };
    let api = Server::start_on(&url, &dir.path().join("api.log"), &["--workers", "0"]);
    let mut workers: Vec<WorkerProcess> = (0..3)
        .map(|i| {
            WorkerProcess::start(
                &url,
                &dir.path().join(format!("worker{i}.log")),
                &["--workers", "1", "--log-format", "json"],
            )
        })
        .collect();

    // The running count, sampled from the database while the jobs run.
    let stop = Arc::new(AtomicBool::new(false));
    let max_running = Arc::new(AtomicI64::new(0));
    let sampler = {
        let (stop, max_running, url) = (stop.clone(), max_running.clone(), url.clone());
        tokio::spawn(async move {
            let mut db = sqlx::PgConnection::connect(&url).await.unwrap();
            while !stop.load(Ordering::SeqCst) {
                let n: i64 =
                    sqlx::query_scalar("SELECT COUNT(*) FROM jobs WHERE state = 'running'")
                        .fetch_one(&mut db)
                        .await
                        .unwrap();
                max_running.fetch_max(n, Ordering::SeqCst);
                tokio::time::sleep(Duration::from_millis(5)).await;
            }
        })
    };

    let c = client();
    let mut ids = vec![];
    for _ in 0..100 {
        // ~0.1 s of solver time each: long enough to overlap, short enough for the suite
        ids.push(submit(&c, &api, &short_scene(0.02)).await);
    }
    for id in &ids {
        let job = wait_finished(&c, &api, id, Duration::from_secs(300)).await;
        assert_eq!(job["state"], "succeeded", "{job}");
        assert_eq!(job["attempt"], 1, "claimed once: {job}");
    }
    stop.store(true, Ordering::SeqCst);
    sampler.await.unwrap();

    let logs: Vec<String> = workers.iter().map(|w| w.log()).collect();
    let starts = starts_by_job(&logs);
    assert_eq!(starts.len(), 100, "every job started somewhere");
    for id in &ids {
        assert_eq!(starts.get(id), Some(&1), "job {id} started exactly once");
    }
    for (i, log) in logs.iter().enumerate() {
        assert!(
            !starts_by_job(std::slice::from_ref(log)).is_empty(),
            "worker {i} ran nothing (all three poll and LISTEN): {log}"
        );
    }
    let most = max_running.load(Ordering::SeqCst);
    assert!(most <= 3, "{most} jobs ran at once on 3 workers");
    assert!(
        most >= 2,
        "the workers never overlapped (max {most} running)"
    );

    // The API node, which runs nothing, serves what the workers computed.
    let (status, _, result) =
        get_json(&c, &api.url(&format!("/v1/simulations/{}/result", ids[0]))).await;
    assert_eq!(status, 200, "{result}");
    let (status, _, page) = get_json(&c, &api.url("/v1/simulations?limit=200")).await;
    assert_eq!(status, 200);
    assert_eq!(page["items"].as_array().map(Vec::len), Some(100), "{page}");
    assert!(!api.log().contains("job started"), "the API node ran a job");

    for w in &mut workers {
        assert!(w.terminate().success(), "worker exit: {}", w.log());
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_worker_killed_mid_job_loses_it_to_another_after_the_lease() {
    let Some((dir, url)) = database().await else {
        return;
    };
    let api = Server::start_on(&url, &dir.path().join("api.log"), &["--workers", "0"]);
    let lease = [
        "--workers",
        "1",
        "--lease-secs",
        "1",
        "--log-format",
        "json",
    ];
    let mut first = WorkerProcess::start(&url, &dir.path().join("first.log"), &lease);
    let c = client();
    // ~1.5 s of solver time: seen running with progress before the kill
    let id = submit(&c, &api, &short_scene(0.2)).await;
    wait_until(&c, &api, &id, Duration::from_secs(60), |j: &Value| {
        j["state"] == "running" && j["progress"].as_f64().unwrap_or(0.0) > 0.0
    })
    .await;
    let second = WorkerProcess::start(&url, &dir.path().join("second.log"), &lease);
    first.kill();

    let job = wait_finished(&c, &api, &id, Duration::from_secs(300)).await;
    assert_eq!(job["state"], "succeeded", "{job}\n{}", second.log());
    assert_eq!(
        job["attempt"], 2,
        "claimed before the kill and after: {job}"
    );
    assert_eq!(starts_by_job(&[second.log()]).get(&id), Some(&1));
    assert_eq!(starts_by_job(&[first.log()]).get(&id), Some(&1));
    let (status, _, _) = get_json(&c, &api.url(&format!("/v1/simulations/{id}/result"))).await;
    assert_eq!(status, 200);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_api_nodes_answer_for_each_other_and_long_polls_see_the_other_nodes_changes() {
    let Some((dir, url)) = database().await else {
        return;
    };
    let a = Server::start_on(&url, &dir.path().join("a.log"), &["--workers", "0"]);
    let b = Server::start_on(&url, &dir.path().join("b.log"), &["--workers", "0"]);
    let c = client();
    // no workers anywhere: the job stays queued until it is cancelled
    let id = submit(&c, &a, &short_scene(0.02)).await;
    let job_on = |s: &Server| s.url(&format!("/v1/simulations/{id}"));
    let (status, headers, job) = get_json(&c, &job_on(&b)).await;
    assert_eq!(
        (status, job["state"].as_str()),
        (200, Some("queued")),
        "{job}"
    );
    let etag = headers["etag"].to_str().unwrap().to_string();

    // a long poll on node A answers when node B cancels the job
    let poll = spawn_long_poll(&c, &job_on(&a), &etag);
    tokio::time::sleep(Duration::from_millis(300)).await;
    let r = c
        .post(b.url(&format!("/v1/simulations/{id}/cancel")))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), 202);
    let r = poll.await.unwrap();
    assert_eq!(r.status(), 200);
    assert_eq!(r.json::<Value>().await.unwrap()["state"], "cancelled");
    // and each node lists it
    for node in [&a, &b] {
        let (_, _, page) = get_json(&c, &node.url("/v1/simulations")).await;
        assert_eq!(page["items"][0]["id"], id.as_str(), "{page}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_worker_refuses_zero_workers_and_a_bad_database_url() {
    let bin = env!("CARGO_BIN_EXE_bearing-sim");
    for (args, expect) in [
        (
            vec!["--workers", "0", "--database-url", "sqlite::memory:"],
            "--workers must be at least 1",
        ),
        (
            vec!["--workers", "1", "--database-url", "mysql://u:secret@h/db"],
            "must start with sqlite:// or postgres://",
        ),
    ] {
        let out = std::process::Command::new(bin)
            .arg("worker")
            .args(&args)
            .env_remove("BEARING_SIM_DATABASE_URL")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} was accepted");
        assert!(err.contains(expect), "{args:?}: {err}");
        assert!(!err.contains("secret"), "the password was printed: {err}");
    }
}
