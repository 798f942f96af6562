//! The server's connections, and how long a client may hold one.
//!
//! axum's own `serve` accepts every connection and waits on each for as long as the
//! client likes: a client sending its headers a byte at a time, or nothing at all, holds
//! a socket and a file descriptor forever, and enough of them take every descriptor the
//! process has, so that the next grading's sandbox cannot start. Here:
//!
//! - a connection is taken only while there is room, in all (from the descriptors the
//!   process may open, keeping a reserve for the database, the sandboxes and the files
//!   served) and for its address; one refused for room is answered 503 with
//!   `Retry-After` and closed, so a client is told rather than left hanging;
//! - a request's headers must arrive within `headers` of the connection's start, and of
//!   the end of the answer before on a kept-alive connection, so an idle connection is
//!   closed too (hyper's header read timeout, which restarts when a connection goes idle);
//! - a request's whole body must arrive within `body` of its headers (`Deadline`), not
//!   within so long between chunks;
//! - no connection lives longer than `lifetime`, whatever it does;
//! - when accepting fails for want of descriptors or memory, the loop pauses and tries
//!   again instead of spinning.

use super::address::block;
use axum::Router;
use axum::body::{Body, Bytes};
use axum::extract::ConnectInfo;
use axum::http::Request;
use hyper::body::{Frame, Incoming, SizeHint};
use hyper::server::conn::http1;
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::server::graceful::GracefulShutdown;
use std::collections::HashMap;
use std::future::Future;
use std::io;
use std::net::{IpAddr, SocketAddr};
use std::pin::Pin;
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll};
use std::time::Duration;
use tokio::io::AsyncWriteExt;
use tokio::net::{TcpListener, TcpStream};
use tower::ServiceExt;

/// How long a client may take over each part of a connection, and how many it may hold.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// From a connection's start, or the end of its last answer, until the next request's
    /// headers have arrived.
    pub headers: Duration,
    /// From a request's headers until its whole body has arrived.
    pub body: Duration,
    /// The longest a connection stays open.
    pub lifetime: Duration,
    /// Connections open at once.
    pub connections: usize,
    /// Connections open at once from one address (an IPv6 client by its /64); `None`
    /// behind a proxy, whose own address every connection has.
    pub per_address: Option<usize>,
}

/// Descriptors kept for what is not a connection: the database and its journal, the
/// sandboxes' pipes, the logs, the listener.
const RESERVED_DESCRIPTORS: usize = 128;

/// Each connection may hold a second descriptor: the static file it is sending.
const DESCRIPTORS_PER_CONNECTION: usize = 2;

/// The most connections at once, however many descriptors there are: about 10 KB of
/// memory each while idle, and more than a class of 500 browsers opens.
const MOST_CONNECTIONS: usize = 8192;

/// From one address: a classroom behind one address (30 browsers, six connections each)
/// fits several times over.
const PER_ADDRESS: usize = 256;

impl Limits {
    /// The server's limits, with room for as many connections as `descriptors` allow.
    pub fn for_server(descriptors: usize, behind_proxy: bool) -> Limits {
        let connections = (descriptors.saturating_sub(RESERVED_DESCRIPTORS)
            / DESCRIPTORS_PER_CONNECTION)
            .clamp(1, MOST_CONNECTIONS);
        Limits {
            headers: Duration::from_secs(20),
            body: Duration::from_secs(30),
            lifetime: Duration::from_secs(10 * 60),
            connections,
            per_address: (!behind_proxy).then_some(PER_ADDRESS),
        }
    }
}

/// Raises the process's limit of open files to the most it is allowed (systemd and most
/// shells start it at 1024 with a far higher hard limit) and returns the limit in force.
pub fn raise_descriptor_limit() -> usize {
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit and setrlimit only read and write the struct given.
    unsafe {
        if libc::getrlimit(libc::RLIMIT_NOFILE, &mut limit) != 0 {
            return 1024;
        }
        if limit.rlim_cur < limit.rlim_max {
            let raised = libc::rlimit {
                rlim_cur: limit.rlim_max,
                rlim_max: limit.rlim_max,
            };
            if libc::setrlimit(libc::RLIMIT_NOFILE, &raised) == 0 {
                limit = raised;
            }
        }
    }
    usize::try_from(limit.rlim_cur).unwrap_or(usize::MAX)
}

/// Answers `router` on the connections `listener` accepts, within `limits`, until `stop`
/// completes; then waits for the answers in flight.
pub async fn serve(
    listener: TcpListener,
    router: Router,
    limits: Limits,
    stop: impl Future<Output = ()>,
) {
    let open = Arc::new(Open::default());
    let graceful = GracefulShutdown::new();
    let mut stop = std::pin::pin!(stop);
    loop {
        let (stream, peer) = tokio::select! {
            accepted = listener.accept() => match accepted {
                Ok(accepted) => accepted,
                Err(e) => {
                    pause_after(&e).await;
                    continue;
                }
            },
            () = &mut stop => break,
        };
        let Some(slot) = Open::take(&open, peer.ip(), &limits) else {
            tokio::spawn(refuse(stream));
            continue;
        };
        let connection = http1::Builder::new()
            .timer(TokioTimer::new())
            .header_read_timeout(limits.headers)
            .serve_connection(TokioIo::new(stream), answerer(router.clone(), peer, limits));
        let connection = graceful.watch(connection);
        tokio::spawn(async move {
            let _slot = slot;
            if tokio::time::timeout(limits.lifetime, connection)
                .await
                .is_err()
            {
                tracing::debug!("a connection closed at the end of its lifetime");
            }
        });
    }
    drop(listener);
    graceful.shutdown().await;
}

/// The service of one connection: each request with the peer's address (for
/// `ConnectInfo`) and its body held to the deadline.
fn answerer(
    router: Router,
    peer: SocketAddr,
    limits: Limits,
) -> impl hyper::service::Service<
    Request<Incoming>,
    Response = axum::response::Response,
    Error = std::convert::Infallible,
    Future: Send,
> + Clone {
    hyper::service::service_fn(move |request: Request<Incoming>| {
        let mut request = request.map(|body| Body::new(Deadline::new(body, limits.body)));
        request.extensions_mut().insert(ConnectInfo(peer));
        router.clone().oneshot(request)
    })
}

/// A connection refused for room: told so, and closed.
async fn refuse(mut stream: TcpStream) {
    const BUSY: &[u8] = b"HTTP/1.1 503 Service Unavailable\r\nRetry-After: 5\r\n\
        Content-Type: text/plain; charset=utf-8\r\nContent-Length: 60\r\nConnection: close\r\n\r\n\
        estlab has too many connections open: try again in a moment\n";
    // A client that does not read its answer is not waited for.
    let _ = tokio::time::timeout(Duration::from_secs(1), stream.write_all(BUSY)).await;
    let _ = stream.shutdown().await;
}

/// After a failed accept: out of descriptors or memory, the loop waits for connections
/// to close; a connection reset before it was accepted needs no pause.
async fn pause_after(error: &io::Error) {
    let short_of_resources = matches!(
        error.raw_os_error(),
        Some(libc::EMFILE | libc::ENFILE | libc::ENOBUFS | libc::ENOMEM)
    );
    if short_of_resources {
        tracing::warn!("accepting a connection: {error}; pausing 100 ms");
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

/// The connections open, in all and per address.
#[derive(Default)]
struct Open {
    counts: Mutex<Counts>,
}

#[derive(Default)]
struct Counts {
    total: usize,
    per_address: HashMap<IpAddr, usize>,
}

impl Open {
    /// A place for a connection from `address`, if there is room; loopback is held to the
    /// total only (a proxy on the same machine, the tests).
    fn take(open: &Arc<Open>, address: IpAddr, limits: &Limits) -> Option<Slot> {
        let key = block(address);
        let per_address = limits.per_address.filter(|_| !key.is_loopback());
        let mut counts = open.counts.lock().unwrap_or_else(|e| e.into_inner());
        if counts.total >= limits.connections {
            return None;
        }
        let from_here = counts.per_address.entry(key).or_default();
        if per_address.is_some_and(|most| *from_here >= most) {
            return None;
        }
        *from_here += 1;
        counts.total += 1;
        Some(Slot {
            open: Arc::clone(open),
            key,
        })
    }
}

/// A connection's place, given back when it closes.
struct Slot {
    open: Arc<Open>,
    key: IpAddr,
}

impl Drop for Slot {
    fn drop(&mut self) {
        let mut counts = self.open.counts.lock().unwrap_or_else(|e| e.into_inner());
        counts.total -= 1;
        if let Some(from_here) = counts.per_address.get_mut(&self.key) {
            *from_here -= 1;
            if *from_here == 0 {
                counts.per_address.remove(&self.key);
            }
        }
    }
}

/// A request body that ends in `BodyTooSlow` once its deadline has passed, however
/// steadily its bytes come.
struct Deadline {
    body: Incoming,
    expires: Pin<Box<tokio::time::Sleep>>,
}

impl Deadline {
    fn new(body: Incoming, within: Duration) -> Deadline {
        Deadline {
            body,
            expires: Box::pin(tokio::time::sleep(within)),
        }
    }
}

/// A request's body did not arrive within its deadline.
#[derive(Debug, thiserror::Error)]
#[error("the request body did not arrive in time")]
pub struct BodyTooSlow;

impl hyper::body::Body for Deadline {
    type Data = Bytes;
    type Error = axum::BoxError;

    fn poll_frame(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
    ) -> Poll<Option<Result<Frame<Bytes>, axum::BoxError>>> {
        if self.body.is_end_stream() {
            return Poll::Ready(None);
        }
        if self.expires.as_mut().poll(cx).is_ready() {
            return Poll::Ready(Some(Err(Box::new(BodyTooSlow))));
        }
        Pin::new(&mut self.body)
            .poll_frame(cx)
            .map_err(axum::BoxError::from)
    }

    fn is_end_stream(&self) -> bool {
        self.body.is_end_stream()
    }

    fn size_hint(&self) -> SizeHint {
        self.body.size_hint()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits(connections: usize, per_address: usize) -> Limits {
        Limits {
            connections,
            per_address: Some(per_address),
            ..Limits::for_server(1 << 20, false)
        }
    }

    #[test]
    fn connections_are_held_to_the_total_and_per_address_and_given_back() {
        let open = Arc::new(Open::default());
        let limits = limits(3, 2);
        let a: IpAddr = "192.0.2.1".parse().unwrap();
        let b: IpAddr = "192.0.2.2".parse().unwrap();
        let first = Open::take(&open, a, &limits).unwrap();
        let _second = Open::take(&open, a, &limits).unwrap();
        assert!(Open::take(&open, a, &limits).is_none(), "per address");
        let _third = Open::take(&open, b, &limits).unwrap();
        assert!(Open::take(&open, b, &limits).is_none(), "in all");
        drop(first);
        assert!(Open::take(&open, a, &limits).is_some(), "given back");
    }

    #[test]
    fn an_ipv6_client_is_counted_by_its_slash_64_and_loopback_by_the_total_only() {
        let open = Arc::new(Open::default());
        let limits = limits(10, 1);
        let one: IpAddr = "2001:db8:1:2::1".parse().unwrap();
        let same_block: IpAddr = "2001:db8:1:2:ffff::9".parse().unwrap();
        let other_block: IpAddr = "2001:db8:1:3::1".parse().unwrap();
        let _held = Open::take(&open, one, &limits).unwrap();
        assert!(Open::take(&open, same_block, &limits).is_none());
        assert!(Open::take(&open, other_block, &limits).is_some());
        let loopback: IpAddr = "127.0.0.1".parse().unwrap();
        let _a = Open::take(&open, loopback, &limits).unwrap();
        assert!(Open::take(&open, loopback, &limits).is_some());
    }

    #[test]
    fn the_descriptors_bound_the_connections_with_a_reserve_kept() {
        assert_eq!(Limits::for_server(1024, false).connections, 448);
        assert_eq!(Limits::for_server(1 << 20, false).connections, 8192);
        assert_eq!(Limits::for_server(100, false).connections, 1);
        assert_eq!(Limits::for_server(1024, true).per_address, None);
    }
}
