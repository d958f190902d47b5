//! The accept loop: HTTP/1.1 connections under a bound, with header-read, idle and write
//! timeouts (axum::serve has none of these: 2000 idle sockets stayed open past 100 s, and
//! 300 of them under a 256-descriptor limit made `/healthz` time out).

use super::problem_io::ProblemIo;
use crate::api::ClientAddr;
use crate::metrics::Metrics;
use axum::body::Body;
use axum::extract::Request;
use axum::Router;
use hyper::body::Incoming;
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use std::collections::HashMap;
use std::future::Future;
use std::net::IpAddr;
use std::sync::{Arc, Mutex};
use std::time::Duration;
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{watch, Semaphore};
use tower::ServiceExt;

/// The limits of the connection layer (`Config` flags; docs/reference/operations.md says why).
#[derive(Debug, Clone, Copy)]
pub struct ConnectionLimits {
    /// Connections open at once; one more is answered 503 and closed.
    pub max_connections: usize,
    /// Time for a client to send a request's headers, and the longest a keep-alive
    /// connection may sit idle between requests.
    pub header_timeout: Duration,
    /// Longest a response may wait for a client that does not read it.
    pub write_timeout: Duration,
    /// Largest request head (request line and headers), bytes; 431 above it.
    pub max_header_bytes: usize,
}

/// Serve `router` on `listener` until `shutdown` completes, then stop accepting and wait
/// for the open connections to finish their requests.
pub async fn serve(
    listener: TcpListener,
    router: Router,
    limits: ConnectionLimits,
    metrics: Arc<Metrics>,
    shutdown: impl Future<Output = ()> + Send + 'static,
) {
    let permits = Arc::new(Semaphore::new(limits.max_connections));
    let addresses = Arc::new(PerAddress::new(limits.max_connections));
    // Dropping `signal_rx` tells the loop and every connection to wind down; each
    // connection holds a `close_rx` until it is done.
    let (signal_tx, signal_rx) = watch::channel(());
    tokio::spawn(async move {
        shutdown.await;
        drop(signal_rx);
    });
    let (close_tx, close_rx) = watch::channel(());
    loop {
        let (stream, peer) = tokio::select! {
            accepted = listener.accept() => match accepted {
                Ok(a) => a,
                Err(e) => {
                    // out of descriptors (EMFILE) or a connection reset before accept:
                    // wait a little instead of spinning
                    tracing::warn!(error = %e, "accept failed");
                    tokio::time::sleep(Duration::from_millis(50)).await;
                    continue;
                }
            },
            _ = signal_tx.closed() => break,
        };
        let Some(mine) = addresses.open(peer.ip()) else {
            metrics.connection_refused();
            refuse(
                stream,
                &format!(
                    "this address holds {} of the {} connections (--max-connections), the most one address may: the rest are kept for others; retry later",
                    addresses.max,
                    limits.max_connections
                ),
            );
            continue;
        };
        let Ok(permit) = permits.clone().try_acquire_owned() else {
            metrics.connection_refused();
            refuse(
                stream,
                &format!(
                    "the server holds its limit of {} open connections (--max-connections); retry later",
                    limits.max_connections
                ),
            );
            continue;
        };
        let _ = stream.set_nodelay(true);
        let client = ClientAddr(peer.ip());
        let service =
            TowerToHyperService::new(router.clone().map_request(move |r: Request<Incoming>| {
                let mut r = r.map(Body::new);
                r.extensions_mut().insert(client);
                r
            }));
        let signal_tx = signal_tx.clone();
        let close_rx = close_rx.clone();
        let metrics = metrics.clone();
        tokio::spawn(async move {
            let _open = metrics.connection_opened();
            let io = TokioIo::new(ProblemIo::new(stream, limits.write_timeout));
            let conn = hyper::server::conn::http1::Builder::new()
                .timer(TokioTimer::new())
                .header_read_timeout(limits.header_timeout)
                .max_header_size(limits.max_header_bytes)
                .serve_connection(io, service);
            tokio::pin!(conn);
            let mut signal = std::pin::pin!(signal_tx.closed());
            let mut draining = false;
            loop {
                tokio::select! {
                    result = conn.as_mut() => {
                        if let Err(e) = result {
                            tracing::debug!(error = %e, "connection ended with an error");
                        }
                        break;
                    }
                    _ = &mut signal, if !draining => {
                        draining = true;
                        conn.as_mut().graceful_shutdown();
                    }
                }
            }
            drop(permit);
            drop(mine);
            drop(close_rx);
        });
    }
    drop(close_rx);
    drop(listener);
    close_tx.closed().await;
}

/// Connections open per client address: one address may hold all but an eighth of
/// `--max-connections` (at least one), so the rest stay for others. Before, 513 idle
/// sockets from one host, refilled as they closed, made every other client's `/healthz`
/// answer 503.
struct PerAddress {
    max: usize,
    open: Mutex<HashMap<IpAddr, usize>>,
}

/// One connection of an address, counted until it is dropped.
struct AddressSlot {
    of: Arc<PerAddress>,
    ip: IpAddr,
}

impl PerAddress {
    fn new(max_connections: usize) -> PerAddress {
        let reserve = (max_connections / 8).max(1);
        PerAddress {
            max: max_connections.saturating_sub(reserve).max(1),
            open: Mutex::new(HashMap::new()),
        }
    }

    /// A slot for one more connection of `ip`, if it holds fewer than its most.
    fn open(self: &Arc<Self>, ip: IpAddr) -> Option<AddressSlot> {
        let mut open = self.open.lock().unwrap_or_else(|e| e.into_inner());
        let n = open.entry(ip).or_insert(0);
        if *n >= self.max {
            return None;
        }
        *n += 1;
        Some(AddressSlot {
            of: self.clone(),
            ip,
        })
    }
}

impl Drop for AddressSlot {
    fn drop(&mut self) {
        let mut open = self.of.open.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(n) = open.get_mut(&self.ip) {
            *n -= 1;
            if *n == 0 {
                open.remove(&self.ip);
            }
        }
    }
}

/// Answer a connection over a bound with 503 (problem+json) and close it at once,
/// without reading its request: one non-blocking write into the fresh socket's buffer, so
/// a burst of refusals holds no descriptor longer than the accept loop's turn.
fn refuse(stream: TcpStream, detail: &str) {
    let body = serde_json::json!({
        "type": "about:blank",
        "title": "Service Unavailable",
        "status": 503,
        "detail": detail,
    })
    .to_string();
    let reply = format!(
        "HTTP/1.1 503 Service Unavailable\r\ncontent-type: application/problem+json\r\ncontent-length: {}\r\nretry-after: 1\r\nconnection: close\r\n\r\n{body}",
        body.len()
    );
    let _ = stream.try_write(reply.as_bytes());
}
