//! Crash safety: a server killed mid-run (SIGKILL) loses nothing; after a restart on
//! the same database the job's expired lease requeues it and it completes.

use crate::common::*;
use std::time::Duration;

#[tokio::test]
async fn sigkill_mid_run_then_restart_completes_the_job() {
    let (_dir, db) = temp_db();
    let args = ["--workers", "1", "--lease-secs", "1"];
    let mut s = Server::start(&db, &args);
    let c = client();
    // long enough (~1.5 s) to be seen running with progress, which reaches the store
    // with the lease heartbeat every 0.5 s
    let id = submit(&c, &s, &short_scene(0.2)).await;
    let queued_too = submit(&c, &s, &short_scene(0.005)).await;
    wait_until(&c, &s, &id, Duration::from_secs(60), |j| {
        j["state"] == "running" && j["progress"].as_f64().unwrap_or(0.0) > 0.0
    })
    .await;
    s.kill();

    let s = Server::start(&db, &args);
    for job_id in [&id, &queued_too] {
        let job = wait_finished(&c, &s, job_id, Duration::from_secs(300)).await;
        assert_eq!(job["state"], "succeeded", "{job}\n{}", s.log());
    }
    let (_, _, job) = get_json(&c, &s.url(&format!("/v1/simulations/{id}"))).await;
    assert_eq!(
        job["attempt"], 2,
        "claimed once before the crash and once after: {job}"
    );
    assert_eq!(
        get_json(&c, &s.url(&format!("/v1/simulations/{id}/result")))
            .await
            .0,
        200
    );
    // nothing lost, nothing duplicated
    let (_, _, page) = get_json(&c, &s.url("/v1/simulations")).await;
    assert_eq!(page["items"].as_array().unwrap().len(), 2, "{page}");
}

#[tokio::test]
async fn a_study_survives_sigkill_and_completes_after_restart() {
    let (_dir, db) = temp_db();
    let args = ["--workers", "1", "--lease-secs", "1"];
    let mut s = Server::start(&db, &args);
    let c = client();
    // Points long enough to be seen running: progress reaches the store with the lease
    // heartbeat (every lease / 2 = 0.5 s here), and a 0.05 s point (~0.4 s of run time on
    // an idle machine) could finish before its first report.
    let study = serde_json::json!({
        "base": {"preset": "h7005c", "fault_case": "inner", "overrides": {"solver": {"duration": 0.2}}},
        "design": {"type": "grid", "factors": [{"pointer": "/operating/radial_load", "values": [200.0, 300.0]}]}
    });
    let (status, _, st) = post_json(&c, &s.url("/v1/studies"), &study).await;
    assert_eq!(status, 202, "{st}");
    let id = st["id"].as_str().unwrap().to_string();
    let first_job = st["points"][0]["job_id"].as_str().unwrap().to_string();
    wait_until(&c, &s, &first_job, Duration::from_secs(60), |j| {
        j["state"] == "running" && j["progress"].as_f64().unwrap_or(0.0) > 0.0
    })
    .await;
    s.kill();

    let s = Server::start(&db, &args);
    let done = wait_for(
        &c,
        &s,
        &format!("/v1/studies/{id}"),
        Duration::from_secs(300),
        |st| st["state"] != "running" && st["state"] != "queued",
    )
    .await;
    assert_eq!(done["state"], "succeeded", "{done}\n{}", s.log());
    assert_eq!(done["progress"]["points_succeeded"], 2);
    let (_, _, job) = get_json(&c, &s.url(&format!("/v1/simulations/{first_job}"))).await;
    assert_eq!(
        job["attempt"], 2,
        "claimed before the crash and after: {job}"
    );
    let (status, _, table) = get_json(&c, &s.url(&format!("/v1/studies/{id}/table"))).await;
    assert_eq!(status, 200);
    assert_eq!(table["rows"].as_array().unwrap().len(), 2);
}

/// Kill the server once the job runs its `attempt`-th time (and, with `headway`, has
/// reported progress in it beyond what any earlier attempt reached), then restart it.
async fn kill_during_attempt(
    c: &reqwest::Client,
    s: Server,
    db: &std::path::Path,
    args: &[&str],
    id: &str,
    attempt: i64,
    headway_over: Option<f64>,
) -> Server {
    let mut s = s;
    wait_until(c, &s, id, Duration::from_secs(60), |j| {
        j["state"] == "running"
            && j["attempt"] == attempt
            && headway_over.is_none_or(|p| j["progress"].as_f64().unwrap_or(0.0) > p + 0.02)
    })
    .await;
    s.kill();
    Server::start(db, args)
}

#[tokio::test]
async fn a_healthy_job_survives_three_sigkills_and_a_job_that_kills_its_worker_is_stopped() {
    let (_dir, db) = temp_db();
    let args = ["--workers", "1", "--lease-secs", "1", "--max-attempts", "3"];
    let c = client();

    // The case: SIGKILLed three times mid-run. The first death comes after the job
    // got somewhere; the next two right after it was claimed again (no headway): still
    // fewer than --max-attempts deaths in a row without headway, so it runs on.
    let s = Server::start(&db, &args);
    let id = submit(&c, &s, &short_scene(0.2)).await;
    let s = kill_during_attempt(&c, s, &db, &args, &id, 1, Some(0.0)).await;
    let s = kill_during_attempt(&c, s, &db, &args, &id, 2, None).await;
    let s = kill_during_attempt(&c, s, &db, &args, &id, 3, None).await;
    let job = wait_finished(&c, &s, &id, Duration::from_secs(300)).await;
    assert_eq!(job["state"], "succeeded", "{job}\n{}", s.log());
    assert_eq!(job["attempt"], 4, "{job}");

    // A job during which its worker dies each time at the same point (right after the
    // claim, before any progress) is stopped after --max-attempts such deaths, saying so.
    let id = submit(&c, &s, &short_scene(0.2)).await;
    let s = kill_during_attempt(&c, s, &db, &args, &id, 1, None).await;
    let s = kill_during_attempt(&c, s, &db, &args, &id, 2, None).await;
    let s = kill_during_attempt(&c, s, &db, &args, &id, 3, None).await;
    let job = wait_finished(&c, &s, &id, Duration::from_secs(60)).await;
    assert_eq!(job["state"], "failed", "{job}\n{}", s.log());
    assert_eq!(job["attempt"], 3, "{job}");
    assert_eq!(job["error"]["kind"], "lease_expired", "{job}");
    let message = job["error"]["message"].as_str().unwrap();
    assert!(
        message.contains("died 3 times in a row") && message.contains("kill its worker"),
        "{message}"
    );
}
