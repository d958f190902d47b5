//! Queueing a job, with `Idempotency-Key` replays.

use super::caller::Caller;
use super::job_resource::job_response;
use super::problem::{ApiResult, Problem};
use super::state::AppState;
use crate::store::{JobKind, NewJob, INPUT_FORMAT};
use axum::http::{HeaderMap, StatusCode};
use axum::response::Response;
use serde_json::Value;

/// Queue a job owned by the caller, honouring `Idempotency-Key` (scoped to the caller):
/// 202 for a new job, 200 with the original
/// job for a replay of the same request, 422 for the same key with a different request.
pub async fn enqueue(
    state: &AppState,
    caller: &Caller,
    headers: &HeaderMap,
    kind: JobKind,
    label: String,
    input: Value,
    blob: Option<Vec<u8>>,
) -> ApiResult<Response> {
    let key = match headers.get("idempotency-key") {
        None => None,
        Some(v) => {
            // 1-255 printable ASCII characters, not starting or ending with a space.
            let b = v.as_bytes();
            let ok = (1..=255).contains(&b.len())
                && b.iter().all(|c| (0x20..=0x7e).contains(c))
                && b[0] != b' '
                && b[b.len() - 1] != b' ';
            if !ok {
                return Err(Problem::bad_request("Idempotency-Key must be 1-255 printable ASCII characters, without leading or trailing spaces"));
            }
            Some(String::from_utf8_lossy(b).into_owned())
        }
    };
    check_storage(state).await?;
    let mut hasher = Fnv1a::default();
    hasher.write(input.to_string().as_bytes());
    if let Some(b) = &blob {
        hasher.write(b);
    }
    let new = NewJob {
        id: uuid::Uuid::now_v7().to_string(),
        tenant: caller.tenant().to_string(),
        kind,
        label,
        input,
        input_blob: blob,
        // Keys are scoped by kind so the two collections do not collide.
        idempotency_key: key.map(|k| format!("{}:{k}", kind.as_str())),
        request_hash: format!("{:016x}", hasher.0),
        input_format: INPUT_FORMAT,
    };
    let tenant_share = state.config.tenant_queue_share(!state.tokens.is_empty());
    let created = state
        .store
        .create_job_within(new, state.config.max_queued, tenant_share)
        .await?;
    if created.created {
        state.wake.notify_waiters();
        Ok(job_response(StatusCode::ACCEPTED, &created.job))
    } else {
        Ok(job_response(StatusCode::OK, &created.job))
    }
}

/// 507 while the database holds more than `--max-store-bytes`: nothing new is accepted
/// until retention or DELETE frees space (what was accepted is never dropped for room).
pub async fn check_storage(state: &AppState) -> ApiResult<()> {
    let held = state.store.stored_bytes().await?;
    let limit = state.config.max_store_bytes;
    if held > limit {
        return Err(Problem::new(
            StatusCode::INSUFFICIENT_STORAGE,
            Some("storage-full"),
            "Insufficient storage",
            format!(
                "the service holds {held} bytes of jobs and results, over its limit of {limit} (--max-store-bytes); delete finished jobs or wait for retention"
            ),
        ));
    }
    Ok(())
}

/// FNV-1a, 64 bit: a stable fingerprint of a request or a study's versions (not a
/// security boundary).
pub struct Fnv1a(pub u64);

impl Default for Fnv1a {
    fn default() -> Self {
        Fnv1a(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv1a {
    pub fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 ^= *b as u64;
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
}
