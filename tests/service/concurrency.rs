//! 50 concurrent clients submit 200 short jobs: every job completes exactly once and
//! running jobs never exceed the worker count.

use crate::common::*;
use serde_json::Value;
use std::collections::HashSet;
use std::time::{Duration, Instant};

const WORKERS: usize = 2;

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn fifty_clients_two_hundred_jobs_each_completes_exactly_once() {
    let (_dir, db) = temp_db();
    let s = TestApp::spawn(
        &db,
        &["--workers", &WORKERS.to_string(), "--max-queued", "1000"],
    );
    let c = client();
    let base = s.base.clone();
    let mut tasks = vec![];
    for client_no in 0..50 {
        let c = client(); // each client its own connection pool
        let base = base.clone();
        tasks.push(tokio::spawn(async move {
            let mut ids = vec![];
            for k in 0..4 {
                // distinct durations only to vary the work; each request is its own job
                let body = short_scene(0.002 + 0.001 * ((client_no + k) % 4) as f64);
                let r = c
                    .post(format!("{base}/v1/simulations"))
                    .json(&body)
                    .send()
                    .await
                    .unwrap();
                assert_eq!(r.status(), 202);
                ids.push(
                    r.json::<Value>().await.unwrap()["id"]
                        .as_str()
                        .unwrap()
                        .to_string(),
                );
            }
            ids
        }));
    }
    let mut ids = HashSet::new();
    for t in tasks {
        ids.extend(t.await.unwrap());
    }
    assert_eq!(ids.len(), 200);

    let start = Instant::now();
    let jobs = loop {
        let (_, _, page) = get_json(&c, &s.url("/v1/simulations?limit=500")).await;
        let items = page["items"].as_array().unwrap().clone();
        let failed: Vec<&Value> = items
            .iter()
            .filter(|j| j["state"] == "failed" || j["state"] == "cancelled")
            .collect();
        assert!(failed.is_empty(), "{:?}\n{}", failed.first(), s.log());
        if items.iter().all(|j| j["state"] == "succeeded") {
            break items;
        }
        assert!(
            start.elapsed() < Duration::from_secs(600),
            "jobs still pending\n{}",
            s.log()
        );
        tokio::time::sleep(Duration::from_millis(250)).await;
    };
    assert_eq!(jobs.len(), 200);
    let listed: HashSet<String> = jobs
        .iter()
        .map(|j| j["id"].as_str().unwrap().to_string())
        .collect();
    assert_eq!(listed, ids);
    for j in &jobs {
        assert_eq!(j["attempt"], 1, "ran more than once: {j}");
    }

    // The process never ran more than WORKERS jobs at once ...
    let m = get_text(&c, &s.url("/metrics")).await;
    let max: usize = m
        .lines()
        .find_map(|l| l.strip_prefix("bearing_sim_jobs_running_max "))
        .unwrap()
        .trim()
        .parse()
        .unwrap();
    assert!((1..=WORKERS).contains(&max), "max running {max}");
    assert!(
        m.contains("bearing_sim_jobs{state=\"succeeded\"} 200"),
        "{m}"
    );
    // ... and neither did the store's record of run intervals.
    let mut events: Vec<(String, i32)> = vec![];
    for j in &jobs {
        events.push((j["started_at"].as_str().unwrap().to_string(), 1));
        events.push((j["finished_at"].as_str().unwrap().to_string(), -1));
    }
    events.sort(); // same-millisecond ends (-1) sort before starts (+1)
    let (mut now, mut peak) = (0, 0);
    for (_, d) in events {
        now += d;
        peak = peak.max(now);
    }
    assert!(
        peak as usize <= WORKERS,
        "store shows {peak} overlapping runs"
    );
}
