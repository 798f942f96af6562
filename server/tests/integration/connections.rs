//! The server's connections under a client that takes its time or takes them all: slow
//! headers, silence, an idle kept-alive connection, a body dripped past its deadline, an
//! anonymous body on a course server, more connections than there is room for, and a
//! flood of connections while a submission is graded on a server with few descriptors.
//!
//! Each waits for the server to act (close, answer) with a generous bound that only keeps
//! a broken server from hanging the run; nothing asserts how quickly it acts.

use crate::common;

use common::{App, quick_source};
use estlab::web::connections::{self, Limits};
use serde_json::Value;
use std::io::{BufRead, BufReader};
use std::net::SocketAddr;
use std::os::unix::process::CommandExt;
use std::process::{Child, Command, Stdio};
use std::time::Duration;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio::time::timeout;

/// The longest any test waits for the server to do what it must.
const BOUND: Duration = Duration::from_secs(90);

/// Limits short enough for a test to see them act, long enough for a loaded machine.
fn short(headers: Duration, body: Duration, connections: usize) -> Limits {
    Limits {
        headers,
        body,
        connections,
        ..Limits::for_server(1 << 20, false)
    }
}

const LONG: Duration = Duration::from_secs(3600);

/// The application served in this process on a port of its own, within `limits`.
async fn serve(app: &App, limits: Limits) -> SocketAddr {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    let router = app.router.clone();
    tokio::spawn(connections::serve(
        listener,
        router,
        limits,
        std::future::pending(),
    ));
    addr
}

/// Reads until the server closes the connection; what it sent before.
async fn read_until_closed(stream: &mut TcpStream) -> String {
    let mut got = Vec::new();
    let mut buffer = [0u8; 4096];
    loop {
        match timeout(BOUND, stream.read(&mut buffer)).await {
            Err(_) => panic!(
                "the server kept the connection open past {BOUND:?}; it sent {:?}",
                String::from_utf8_lossy(&got)
            ),
            Ok(Ok(0) | Err(_)) => return String::from_utf8_lossy(&got).into_owned(),
            Ok(Ok(n)) => got.extend_from_slice(&buffer[..n]),
        }
    }
}

/// One answer on a kept-alive connection: its status line and its body.
async fn answer(stream: &mut TcpStream) -> (String, String) {
    let mut got = Vec::new();
    let mut byte = [0u8; 1];
    while !got.ends_with(b"\r\n\r\n") {
        let n = timeout(BOUND, stream.read(&mut byte))
            .await
            .expect("an answer")
            .unwrap();
        assert!(
            n == 1,
            "closed before answering: {:?}",
            String::from_utf8_lossy(&got)
        );
        got.push(byte[0]);
    }
    let head = String::from_utf8(got).unwrap();
    let length: usize = head
        .lines()
        .find_map(|line| {
            let (name, value) = line.split_once(':')?;
            name.eq_ignore_ascii_case("content-length")
                .then(|| value.trim().parse().unwrap())
        })
        .unwrap_or(0);
    let mut body = vec![0u8; length];
    timeout(BOUND, stream.read_exact(&mut body))
        .await
        .expect("the body")
        .unwrap();
    let status = head.lines().next().unwrap().to_owned();
    (status, String::from_utf8(body).unwrap())
}

#[tokio::test]
async fn a_connection_that_sends_nothing_is_closed() {
    let app = App::new();
    let addr = serve(&app, short(Duration::from_secs(1), LONG, 100)).await;
    let mut silent = TcpStream::connect(addr).await.unwrap();
    assert_eq!(read_until_closed(&mut silent).await, "");
}

#[tokio::test]
async fn headers_sent_a_byte_at_a_time_are_cut_off_at_their_deadline() {
    let app = App::new();
    let addr = serve(&app, short(Duration::from_secs(1), LONG, 100)).await;
    let (mut reader, mut writer) = TcpStream::connect(addr).await.unwrap().into_split();
    // Far more bytes than the deadline lets through, each well within any idle timeout.
    let drip = tokio::spawn(async move {
        let header = format!(
            "GET /healthz HTTP/1.1\r\nHost: x\r\nX-Slow: {}",
            "a".repeat(900)
        );
        for byte in header.bytes() {
            if writer.write_all(&[byte]).await.is_err() {
                return;
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    });
    let mut got = Vec::new();
    let closed = timeout(BOUND, reader.read_to_end(&mut got)).await;
    drip.abort();
    assert!(closed.is_ok(), "the connection stayed open");
    assert!(
        !String::from_utf8_lossy(&got).contains("200 OK"),
        "the request was answered"
    );
}

#[tokio::test]
async fn a_kept_alive_connection_is_closed_once_idle() {
    let app = App::new();
    let addr = serve(&app, short(Duration::from_secs(1), LONG, 100)).await;
    let mut stream = TcpStream::connect(addr).await.unwrap();
    stream
        .write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n")
        .await
        .unwrap();
    let (status, body) = answer(&mut stream).await;
    assert_eq!((status.as_str(), body.as_str()), ("HTTP/1.1 200 OK", "ok"));
    assert_eq!(read_until_closed(&mut stream).await, "");
}

#[tokio::test]
async fn a_body_must_arrive_whole_within_its_deadline_however_steadily_it_comes() {
    let app = App::new();
    let addr = serve(&app, short(LONG, Duration::from_secs(2), 100)).await;
    let (mut reader, mut writer) = TcpStream::connect(addr).await.unwrap().into_split();
    let length = 1000;
    let drip = tokio::spawn(async move {
        let head = format!(
            "POST /api/submissions HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: {length}\r\n\r\n"
        );
        writer.write_all(head.as_bytes()).await.unwrap();
        for _ in 0..length {
            if writer.write_all(b" ").await.is_err() {
                return;
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    });
    let mut got = Vec::new();
    let closed = timeout(BOUND, reader.read_to_end(&mut got)).await;
    drip.abort();
    assert!(closed.is_ok(), "the body was waited for past its deadline");
    let got = String::from_utf8_lossy(&got);
    assert!(got.starts_with("HTTP/1.1 408"), "{got}");
    let body: Value = serde_json::from_str(got.split("\r\n\r\n").nth(1).unwrap()).unwrap();
    assert_eq!(
        body["error"],
        "the submission body: the request body did not arrive in time"
    );
}

#[tokio::test]
async fn on_a_course_server_nobody_signed_in_is_refused_before_their_body_is_read() {
    let app = App::new();
    app.open_course("EL2320");
    let addr = serve(&app, short(LONG, LONG, 100)).await;
    let mut stream = TcpStream::connect(addr).await.unwrap();
    // The headers promise 4 MB; not a byte of it is sent.
    stream
        .write_all(
            b"POST /api/submissions HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: 4000000\r\n\r\n",
        )
        .await
        .unwrap();
    let (status, body) = answer(&mut stream).await;
    assert_eq!(status, "HTTP/1.1 401 Unauthorized", "{body}");
}

#[tokio::test]
async fn connections_beyond_the_limit_are_told_to_come_back_and_room_is_given_back() {
    let app = App::new();
    let addr = serve(&app, short(LONG, LONG, 3)).await;
    let mut held = Vec::new();
    for _ in 0..3 {
        let mut stream = TcpStream::connect(addr).await.unwrap();
        stream
            .write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n")
            .await
            .unwrap();
        assert_eq!(answer(&mut stream).await.0, "HTTP/1.1 200 OK");
        held.push(stream);
    }
    let mut refused = TcpStream::connect(addr).await.unwrap();
    let told = read_until_closed(&mut refused).await;
    assert!(told.starts_with("HTTP/1.1 503"), "{told}");
    assert!(told.contains("Retry-After: 5"), "{told}");
    drop(held.pop());
    // The server sees the close when it next reads; until then it may still refuse.
    let answered = timeout(BOUND, async {
        loop {
            let mut stream = TcpStream::connect(addr).await.unwrap();
            stream
                .write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n")
                .await
                .unwrap();
            let got = read_until_closed(&mut stream).await;
            if got.starts_with("HTTP/1.1 200") {
                return;
            }
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    })
    .await;
    assert!(
        answered.is_ok(),
        "the closed connection's room was not given back"
    );
}

/// `estlab serve` (or another command that serves) with at most `descriptors` open files,
/// on a port of its own.
struct Server {
    child: Child,
    addr: SocketAddr,
    data: tempfile::TempDir,
}

impl Server {
    fn start(descriptors: u64) -> Server {
        Server::of(
            &["serve", "--addr", "127.0.0.1:0"],
            descriptors,
            "estlab is serving on http://",
        )
    }

    /// `estlab ARGS`, whose address is what it prints after `said`.
    fn of(args: &[&str], descriptors: u64, said: &str) -> Server {
        let data = tempfile::tempdir().unwrap();
        common::fixed_secret(data.path());
        let mut command = Command::new(env!("CARGO_BIN_EXE_estlab"));
        command
            .args(args)
            .args(["--parallel", "1", "--data"])
            .arg(data.path())
            .stdout(Stdio::piped())
            .stderr(Stdio::null());
        let limit = libc::rlimit {
            rlim_cur: descriptors,
            rlim_max: descriptors,
        };
        // SAFETY: setrlimit is async-signal-safe and touches only the child.
        unsafe {
            command.pre_exec(move || {
                if libc::setrlimit(libc::RLIMIT_NOFILE, &limit) == 0 {
                    Ok(())
                } else {
                    Err(std::io::Error::last_os_error())
                }
            });
        }
        let mut child = command.spawn().unwrap();
        let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
        let addr = lines
            .by_ref()
            .map_while(Result::ok)
            .find_map(|line| {
                let rest = line.strip_prefix(said)?;
                rest.split('/').next()?.parse().ok()
            })
            .expect("the server printed its address");
        // What it prints later is read too, so that no write of its fails.
        std::thread::spawn(move || lines.for_each(drop));
        Server { child, addr, data }
    }
}

/// A request's status line and body, the connection closed after it.
async fn get(addr: SocketAddr, path: &str, authorization: &str) -> (String, String) {
    let mut stream = TcpStream::connect(addr).await.unwrap();
    let request = format!(
        "GET {path} HTTP/1.1\r\nHost: x\r\nAuthorization: {authorization}\r\nConnection: close\r\n\r\n"
    );
    stream.write_all(request.as_bytes()).await.unwrap();
    let answer = read_until_closed(&mut stream).await;
    let (head, body) = answer.split_once("\r\n\r\n").unwrap_or((&answer, ""));
    (
        head.lines().next().unwrap_or("").to_owned(),
        body.to_owned(),
    )
}

/// A grader process serves its sandbox's metrics (`--metrics`) to the token it wrote in
/// its data directory, and to nobody else.
#[tokio::test]
async fn a_grader_serves_its_metrics_to_the_data_directorys_token() {
    let grader = Server::of(
        &["grader", "--metrics", "127.0.0.1:0"],
        1024,
        "estlab grader: metrics on http://",
    );
    let token = std::fs::read_to_string(grader.data.path().join("metrics-token")).unwrap();
    let secret = estlab::grading::Secret::read(&grader.data.path().join("secret")).unwrap();
    assert_eq!(token, secret.metrics_token());
    let (status, body) = get(grader.addr, "/metrics", &format!("Bearer {token}")).await;
    assert_eq!(status, "HTTP/1.1 200 OK", "{body}");
    assert!(body.contains("estlab_sandbox_cap 3\n"), "{body}");
    assert!(
        body.contains("estlab_sandbox_waiting{kind=\"grading\"} 0\n"),
        "{body}"
    );
    let (status, _) = get(grader.addr, "/metrics", "Bearer not-the-token").await;
    assert_eq!(status, "HTTP/1.1 401 Unauthorized");
    let (status, _) = get(grader.addr, "/healthz", "").await;
    assert_eq!(
        status, "HTTP/1.1 404 Not Found",
        "a grader serves its metrics only"
    );
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The test process's own limit raised, for the connections it opens.
fn raise_own_descriptor_limit() {
    connections::raise_descriptor_limit();
}

#[tokio::test]
async fn a_flood_of_connections_is_refused_and_never_fails_a_grading() {
    raise_own_descriptor_limit();
    // 300 descriptors: room for (300 - 128) / 2 = 86 connections.
    let server = Server::start(300);
    let mut honest = TcpStream::connect(server.addr).await.unwrap();
    honest
        .write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n")
        .await
        .unwrap();
    assert_eq!(answer(&mut honest).await.0, "HTTP/1.1 200 OK");

    // More connections than the server has descriptors, each left idle.
    let mut flood = Vec::new();
    for _ in 0..400 {
        match TcpStream::connect(server.addr).await {
            Ok(stream) => flood.push(stream),
            Err(_) => break,
        }
    }
    // Beyond its room the server says so rather than leaving clients hanging.
    let mut last = flood.pop().unwrap();
    let told = read_until_closed(&mut last).await;
    assert!(told.starts_with("HTTP/1.1 503"), "{told}");

    // A submission on a connection opened before the flood is graded as ever.
    let body =
        serde_json::json!({ "student": "alice", "source": quick_source("flood") }).to_string();
    let request = format!(
        "POST /api/submissions HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    );
    honest.write_all(request.as_bytes()).await.unwrap();
    let (status, accepted) = answer(&mut honest).await;
    assert_eq!(status, "HTTP/1.1 202 Accepted", "{accepted}");
    let id = serde_json::from_str::<Value>(&accepted).unwrap()["id"]
        .as_i64()
        .unwrap();
    let graded = timeout(BOUND, async {
        loop {
            let ask = format!("GET /api/submissions/{id} HTTP/1.1\r\nHost: x\r\n\r\n");
            honest.write_all(ask.as_bytes()).await.unwrap();
            let (_, body) = answer(&mut honest).await;
            let submission: Value = serde_json::from_str(&body).unwrap();
            if submission["status"] != "queued" && submission["status"] != "grading" {
                return submission;
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    })
    .await
    .expect("the submission was graded");
    assert_eq!(graded["status"], "graded", "{graded}");
    assert_eq!(graded["result"]["gradable"], true, "{graded}");
    drop(flood);
}

/// One student sending many bodies slowly (here: bodies that never arrive) holds a few
/// turns of their own, never the shared pool: a few of their bodies are being read, the
/// rest wait on their own turns, and a classmate's submission is read and taken
/// meanwhile. (With one pool for everyone signed in, 64 of them were read at once and
/// held it all.)
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn one_persons_slow_bodies_cost_only_them() {
    use axum::body::Body;
    use tower::ServiceExt;
    let app = App::new();
    app.open_course("el2320");
    app.assign(
        "el2320",
        labs::Exercise::EkfLocalization,
        &common::open_policy(app.now()),
    );
    let (mallory, ada) = (app.enrol("el2320", "mallory"), app.enrol("el2320", "ada"));
    let (mallory, ada) = (app.signed_in(&mallory).await, app.signed_in(&ada).await);
    // How many of Mallory's bodies the server has begun to read.
    let reading = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(0));
    let stalled: Vec<_> = (0..80)
        .map(|_| {
            let (parts, _) = common::Req::post("/api/submissions")
                .who(&mallory)
                .json(serde_json::json!({}))
                .build()
                .into_parts();
            let (reading, mut counted) = (std::sync::Arc::clone(&reading), false);
            let never = futures::stream::poll_fn(move |_| {
                if !std::mem::replace(&mut counted, true) {
                    reading.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                }
                std::task::Poll::<Option<Result<Vec<u8>, std::io::Error>>>::Pending
            });
            let request = axum::http::Request::from_parts(parts, Body::from_stream(never));
            tokio::spawn(app.router.clone().oneshot(request))
        })
        .collect();
    let read = || reading.load(std::sync::atomic::Ordering::SeqCst);
    timeout(BOUND, async {
        while read() == 0 {
            tokio::task::yield_now().await;
        }
    })
    .await
    .expect("the server began to read Mallory's bodies");
    let answer = timeout(
        BOUND,
        app.submit_to(&ada, labs::Exercise::EkfLocalization, &quick_source("ada")),
    )
    .await
    .expect("Ada's submission was read beside Mallory's stalled bodies");
    assert_eq!(
        answer.status,
        axum::http::StatusCode::ACCEPTED,
        "{}",
        answer.body
    );
    for request in &stalled {
        assert!(
            !request.is_finished(),
            "a body that never arrives is still awaited"
        );
    }
    assert!(
        (1..=2).contains(&read()),
        "{} of Mallory's bodies read at once",
        read()
    );
    for request in stalled {
        request.abort();
    }
}
