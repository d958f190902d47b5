//! The large-transfer slots (`--max-large-transfers`: big request bodies, channel and
//! spectrum answers in memory at once), shared fairly: one client (a tenant, or an address
//! without tokens) holds at most half of them, so its stalled uploads cannot make everyone
//! else wait. Before, 12 sockets of one tenant that sent the headers of a 2 MB upload and
//! stalled made another tenant's small spectrum read answer 408 after 30 s.

use super::problem::Problem;
use axum::http::StatusCode;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::Duration;
use tokio::sync::{OwnedSemaphorePermit, Semaphore};

pub struct LargeTransfers {
    all: Arc<Semaphore>,
    total: usize,
    /// Slots one client may hold: half of them, at least one.
    per_client: usize,
    clients: Mutex<HashMap<String, Arc<Semaphore>>>,
}

/// A slot held: the client's share and one of all the slots, released together.
pub struct LargePermit {
    _client: OwnedSemaphorePermit,
    _all: OwnedSemaphorePermit,
}

/// `Retry-After` of a refusal, s.
const RETRY_AFTER: u64 = 5;

impl LargeTransfers {
    pub fn new(total: usize) -> LargeTransfers {
        let total = total.max(1);
        LargeTransfers {
            all: Arc::new(Semaphore::new(total)),
            total,
            per_client: (total / 2).max(1),
            clients: Mutex::new(HashMap::new()),
        }
    }

    /// A slot for `client`, waited for at most `wait`: first one of the client's share,
    /// then one of all. 503 with `Retry-After` naming the limit when none came in time.
    pub async fn acquire(&self, client: &str, wait: Duration) -> Result<LargePermit, Problem> {
        let share = self.share_of(client);
        let taken = tokio::time::timeout(wait, async {
            let client = share.acquire_owned().await.ok()?;
            let all = self.all.clone().acquire_owned().await.ok()?;
            Some(LargePermit {
                _client: client,
                _all: all,
            })
        })
        .await;
        match taken {
            Ok(Some(p)) => Ok(p),
            Ok(None) => Err(Problem::unavailable("shutting down")),
            Err(_) => {
                let mut p = Problem::new(
                    StatusCode::SERVICE_UNAVAILABLE,
                    Some("large-transfers-busy"),
                    "Large transfers busy",
                    format!(
                        "no large-transfer slot came free within {:.0} s: {} in all (--max-large-transfers), at most {} for one client; retry later",
                        wait.as_secs_f64(),
                        self.total,
                        self.per_client
                    ),
                );
                p.retry_after = Some(RETRY_AFTER);
                Err(p)
            }
        }
    }

    /// The client's share, created on first use. Shares nobody holds are forgotten once
    /// there are many, so the map stays as small as the clients in flight.
    fn share_of(&self, client: &str) -> Arc<Semaphore> {
        let mut clients = self.clients.lock().unwrap_or_else(|e| e.into_inner());
        if clients.len() > 1024 {
            let full = self.per_client;
            clients.retain(|_, s| s.available_permits() < full || Arc::strong_count(s) > 1);
        }
        clients
            .entry(client.to_string())
            .or_insert_with(|| Arc::new(Semaphore::new(self.per_client)))
            .clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test]
    async fn one_client_holds_at_most_half_and_the_others_get_the_rest() {
        let slots = LargeTransfers::new(4);
        let wait = Duration::from_millis(50);
        let a1 = slots.acquire("a", wait).await.unwrap();
        let _a2 = slots.acquire("a", wait).await.unwrap();
        let refused = slots.acquire("a", wait).await.err().unwrap();
        assert_eq!(refused.status(), StatusCode::SERVICE_UNAVAILABLE);
        assert_eq!(refused.retry_after, Some(RETRY_AFTER));
        let _b1 = slots.acquire("b", wait).await.unwrap();
        let _c1 = slots.acquire("c", wait).await.unwrap();
        // all four taken: b waits for one to come free
        assert!(slots.acquire("b", wait).await.is_err());
        drop(a1);
        assert!(slots.acquire("b", wait).await.is_ok());
    }
}
