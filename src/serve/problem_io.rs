//! A connection's socket, wrapped for two things the HTTP server does not do itself:
//! the errors hyper answers on its own (400 for a malformed request, 431 for headers over
//! the limit) leave as problem+json like every other error instead of an empty body, and
//! a response the client stops reading is abandoned after the write timeout instead of
//! holding the connection forever.

use std::future::Future;
use std::io;
use std::pin::Pin;
use std::task::{Context, Poll};
use std::time::Duration;
use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio::time::Sleep;

pub struct ProblemIo<T> {
    inner: T,
    write_timeout: Duration,
    /// Running while writes are blocked by a client that does not read.
    stalled: Option<Pin<Box<Sleep>>>,
    /// A replacement response being written, and how much of it is out.
    replacement: Option<(Vec<u8>, usize)>,
}

impl<T> ProblemIo<T> {
    pub fn new(inner: T, write_timeout: Duration) -> Self {
        ProblemIo {
            inner,
            write_timeout,
            stalled: None,
            replacement: None,
        }
    }
}

/// The problem+json response for a head hyper wrote on its own, if `buf` is one: a whole
/// error head (`HTTP/1.1 4xx` or `5xx`) with an empty body. The service's own errors
/// always carry a problem body, so they never match.
fn replacement_for(buf: &[u8]) -> Option<Vec<u8>> {
    let head = std::str::from_utf8(buf).ok()?;
    let rest = head.strip_prefix("HTTP/1.1 ")?;
    if !(rest.starts_with('4') || rest.starts_with('5')) || !head.ends_with("\r\n\r\n") {
        return None;
    }
    let lower = head.to_ascii_lowercase();
    if !lower.contains("\r\ncontent-length: 0\r\n") || lower.contains("\r\ncontent-type:") {
        return None;
    }
    let status: u16 = rest.get(..3)?.parse().ok()?;
    let (title, detail) = match status {
        431 => (
            "Request Header Fields Too Large",
            "the request's headers are over the limit (--max-header-bytes)",
        ),
        400 => (
            "Bad Request",
            "the request is not valid HTTP/1.1 (malformed request line or header)",
        ),
        _ => ("Error", "the HTTP layer refused the request"),
    };
    let body = serde_json::json!({
        "type": "about:blank",
        "title": title,
        "status": status,
        "detail": detail,
    })
    .to_string();
    Some(
        format!(
            "HTTP/1.1 {status} {title}\r\ncontent-type: application/problem+json\r\ncontent-length: {}\r\nconnection: close\r\n\r\n{body}",
            body.len()
        )
        .into_bytes(),
    )
}

impl<T: AsyncRead + Unpin> AsyncRead for ProblemIo<T> {
    fn poll_read(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        Pin::new(&mut self.inner).poll_read(cx, buf)
    }
}

impl<T: AsyncWrite + Unpin> ProblemIo<T> {
    /// Map a blocked write to an error once it has been blocked for the write timeout.
    fn stall(&mut self, cx: &mut Context<'_>) -> Poll<io::Result<usize>> {
        let timeout = self.write_timeout;
        let sleep = self
            .stalled
            .get_or_insert_with(|| Box::pin(tokio::time::sleep(timeout)));
        match sleep.as_mut().poll(cx) {
            Poll::Ready(()) => Poll::Ready(Err(io::Error::new(
                io::ErrorKind::TimedOut,
                "the client read nothing of the response within the write timeout",
            ))),
            Poll::Pending => Poll::Pending,
        }
    }
}

impl<T: AsyncWrite + Unpin> AsyncWrite for ProblemIo<T> {
    fn poll_write(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<io::Result<usize>> {
        let this = &mut *self;
        if this.replacement.is_none() {
            if let Some(r) = replacement_for(buf) {
                this.replacement = Some((r, 0));
            }
        }
        // Write the replacement out whole, then tell hyper its own head was written.
        if let Some((bytes, done)) = this.replacement.as_mut() {
            while *done < bytes.len() {
                match Pin::new(&mut this.inner).poll_write(cx, &bytes[*done..]) {
                    Poll::Ready(Ok(n)) => {
                        *done += n;
                        this.stalled = None;
                    }
                    Poll::Ready(Err(e)) => return Poll::Ready(Err(e)),
                    Poll::Pending => return this.stall(cx),
                }
            }
            this.replacement = None;
            return Poll::Ready(Ok(buf.len()));
        }
        match Pin::new(&mut this.inner).poll_write(cx, buf) {
            Poll::Pending => this.stall(cx),
            ready => {
                this.stalled = None;
                ready
            }
        }
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.inner).poll_flush(cx)
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.inner).poll_shutdown(cx)
    }
}

#[cfg(test)]
mod tests {
    use super::replacement_for;

    #[test]
    fn hypers_own_error_heads_are_replaced() {
        let r = replacement_for(
            b"HTTP/1.1 431 Request Header Fields Too Large\r\ncontent-length: 0\r\ndate: x\r\n\r\n",
        )
        .unwrap();
        let r = String::from_utf8(r).unwrap();
        assert!(r.starts_with("HTTP/1.1 431 "), "{r}");
        assert!(
            r.contains("application/problem+json") && r.contains("\"status\":431"),
            "{r}"
        );
    }

    #[test]
    fn the_services_responses_are_left_alone() {
        // a problem from a handler has a type and a body
        assert!(replacement_for(b"HTTP/1.1 404 Not Found\r\ncontent-type: application/problem+json\r\ncontent-length: 90\r\n\r\n").is_none());
        // successes, and body bytes that happen to be text
        assert!(replacement_for(b"HTTP/1.1 200 OK\r\ncontent-length: 0\r\n\r\n").is_none());
        assert!(replacement_for(b"{\"status\": 400}").is_none());
    }
}
