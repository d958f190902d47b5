//! One worker: claim, run on a blocking thread, heartbeat, record the outcome.

use super::control::Control;
use super::env::WorkerEnv;
use super::outcome::{JobFailure, JobOutput};
use super::{analysis_job, simulation_job};
use crate::store::{Claimed, FailureKind, JobError, JobKind, Outcome, StoreError, INPUT_FORMAT};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};
use tokio::sync::watch;
use tracing::Instrument;

/// Idle workers poll this often (other processes may queue jobs into a shared database).
const IDLE_POLL: Duration = Duration::from_millis(250);

pub async fn worker_loop(env: WorkerEnv, owner: String, mut shutdown: watch::Receiver<bool>) {
    loop {
        if *shutdown.borrow() {
            return;
        }
        // Register interest before claiming so a submission between the two is not missed.
        let woken = env.wake.notified();
        let claim = env.store.claim_shared(
            &owner,
            env.config.lease_ms(),
            INPUT_FORMAT,
            env.config.tenant_share(),
        );
        match claim.await {
            Ok(Some(job)) => {
                let span = tracing::info_span!("job", id = %job.lease.id, kind = job.kind.as_str(), attempt = job.lease.attempt);
                run_claimed(&env, job, &mut shutdown).instrument(span).await;
                continue;
            }
            Ok(None) => {}
            Err(e) => tracing::warn!(error = %e, "claim failed"),
        }
        tokio::select! {
            _ = woken => {}
            _ = tokio::time::sleep(IDLE_POLL) => {}
            _ = shutdown.changed() => {}
        }
    }
}

enum Ending {
    Finished(Result<JobOutput, JobFailure>),
    /// Lease lost: another worker owns the job now; write nothing.
    Abandoned,
}

async fn run_claimed(env: &WorkerEnv, job: Claimed, shutdown: &mut watch::Receiver<bool>) {
    let lease = job.lease.clone();
    let kind = job.kind.as_str();
    tracing::info!("job started");
    let started = Instant::now();
    let _running = env.metrics.job_started();

    let ctl = Control::default();
    ctl.cancel.store(job.cancel_requested, Ordering::SeqCst);
    let mut user_cancel = job.cancel_requested;
    let mut stopping = *shutdown.borrow();
    if stopping {
        ctl.cancel.store(true, Ordering::SeqCst);
    }

    let run_ctl = ctl.clone();
    let mut task = tokio::task::spawn_blocking(move || guarded(|| execute(&job, &run_ctl)));

    // The wall-clock budget: past it the run is stopped and the job failed.
    let limit = env.config.job_time_limit;
    let deadline = tokio::time::sleep(if limit > 0.0 {
        Duration::from_secs_f64(limit)
    } else {
        Duration::from_secs(u64::MAX / 4)
    });
    tokio::pin!(deadline);
    let mut timed_out = false;

    let mut ticker = tokio::time::interval(env.config.heartbeat_interval());
    ticker.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let ending = loop {
        tokio::select! {
            joined = &mut task => {
                break Ending::Finished(joined.unwrap_or_else(|e| Err(JobFailure::new(FailureKind::Panic, format!("worker task failed: {e}")))));
            }
            _ = ticker.tick() => {
                match env.store.heartbeat(&lease, ctl.progress(), env.config.lease_ms()).await {
                    Ok(hb) => if hb.cancel_requested && !user_cancel {
                        user_cancel = true;
                        ctl.cancel.store(true, Ordering::SeqCst);
                    },
                    Err(StoreError::LeaseLost) => {
                        tracing::warn!("lease lost; stopping the run and leaving the job to its new owner");
                        ctl.cancel.store(true, Ordering::SeqCst);
                        let _ = task.await;
                        break Ending::Abandoned;
                    }
                    Err(e) => tracing::warn!(error = %e, "heartbeat failed"),
                }
            }
            _ = &mut deadline, if !timed_out && limit > 0.0 => {
                tracing::warn!(limit, "wall-clock limit reached; stopping the run");
                timed_out = true;
                ctl.cancel.store(true, Ordering::SeqCst);
            }
            _ = shutdown.changed(), if !stopping => {
                stopping = true;
                ctl.cancel.store(true, Ordering::SeqCst);
            }
        }
    };

    let Ending::Finished(result) = ending else {
        return;
    };
    let (state, write) = match result {
        Ok(out) => (
            "succeeded",
            Some(Outcome::Succeeded {
                result: out.result,
                stats: out.stats,
                artifacts: out.artifacts,
                scene_key: out.scene_key,
            }),
        ),
        // the limit wins over a shutdown or cancel that came later: the run did end on it
        Err(f) if f.is_cancel() && timed_out => (
            "failed",
            Some(Outcome::Failed {
                error: JobError {
                    kind: FailureKind::TimeLimit,
                    message: format!(
                        "stopped after the wall-clock limit of {limit} s per job (--job-time-limit); {}",
                        f.message
                    ),
                },
                stats: f.stats,
            }),
        ),
        Err(f) if f.is_cancel() && stopping && !user_cancel => ("requeued", None),
        Err(f) if f.is_cancel() => (
            "cancelled",
            Some(Outcome::Cancelled {
                error: JobError {
                    kind: f.kind,
                    message: f.message,
                },
            }),
        ),
        Err(f) => (
            "failed",
            Some(Outcome::Failed {
                error: JobError {
                    kind: f.kind,
                    message: f.message,
                },
                stats: f.stats,
            }),
        ),
    };
    let written = match write {
        Some(outcome) => env.store.finish(&lease, outcome).await,
        None => env.store.release(&lease).await,
    };
    match written {
        Ok(()) => {
            let secs = started.elapsed().as_secs_f64();
            env.metrics.observe_job(kind, state, secs);
            tracing::info!(state, seconds = secs, "job ended");
        }
        Err(StoreError::LeaseLost) => tracing::warn!(
            state,
            "lease lost before the outcome was written; discarded"
        ),
        Err(e) => {
            tracing::error!(error = %e, state, "could not record the outcome; the lease will expire and requeue the job")
        }
    }
}

/// Run a claimed job's blocking part.
fn execute(job: &Claimed, ctl: &Control) -> Result<JobOutput, JobFailure> {
    match job.kind {
        JobKind::Simulation => simulation_job::execute(&job.input, ctl),
        JobKind::Analysis => {
            analysis_job::execute(&job.input, job.input_blob.as_deref().unwrap_or(&[]), ctl)
        }
    }
}

/// A panic in the engine fails this job with its message, not the process.
fn guarded(run: impl FnOnce() -> Result<JobOutput, JobFailure>) -> Result<JobOutput, JobFailure> {
    catch_unwind(AssertUnwindSafe(run))
        .unwrap_or_else(|p| Err(JobFailure::new(FailureKind::Panic, panic_message(&p))))
}

fn panic_message(p: &Box<dyn std::any::Any + Send>) -> String {
    let msg = p
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "non-string panic payload".into());
    format!("engine panicked: {msg}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_the_jobs_failure() {
        let r = guarded(|| panic!("index 7 out of range"));
        let f = r.err().unwrap();
        assert_eq!(f.kind, FailureKind::Panic);
        assert!(f.message.contains("index 7 out of range"), "{}", f.message);
        let r = guarded(|| std::panic::panic_any(42_u8));
        assert_eq!(r.err().unwrap().kind, FailureKind::Panic);
    }
}
