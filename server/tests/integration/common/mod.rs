//! What the in-process tests of the web application share: the real application over a
//! database in a temporary directory, with a clock the tests set, and requests sent as
//! one kind of asker or another.

#![allow(dead_code)]

use axum::Router;
use axum::body::Body;
use axum::extract::ConnectInfo;
use axum::http::{HeaderMap, Method, Request, StatusCode, header};
use estlab::clock::{Clock, FixedClock};
use estlab::courses::codes::new_code;
use estlab::courses::deadline::{Counts, Policy};
use estlab::courses::roster;
use estlab::grading::{Grader, Secret};
use estlab::sandbox::Sandbox;
use estlab::store::{Member, NewMember, Role, Status, Store, Submission};
use estlab::web::{AppState, Assets, SESSION_COOKIE};
use jiff::{SignedDuration, Timestamp};
use labs::Exercise;
use serde_json::{Value, json};
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};
use tower::ServiceExt;

/// The correct solution: scores 1.
pub const CORRECT: &str = include_str!("../../../../tests/student/correct.js");

/// The catalogue of classic mistakes, each a change to correct.js.
pub const MISTAKES: &str = include_str!("../../../../tests/student/mistakes.json");

/// The secret every test's server, grader and package grades with (a submission's hidden
/// cases and a class's held-out trials are drawn from it): fixed, so that what a test
/// asserts of them holds at every run. `scripts/test` checks that no test draws its own.
pub const TEST_SECRET: [u8; 32] = [7; 32];

/// The secret file of the data directory `dir`: [`TEST_SECRET`], unless the test put
/// another there first.
pub fn fixed_secret(dir: &Path) -> PathBuf {
    let path = dir.join("secret");
    if !path.exists() {
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(&path, TEST_SECRET).unwrap();
    }
    path
}

/// How long a test waits for one grading before it gives up.
pub const GRADING_BOUND: Duration = Duration::from_secs(120);

/// A source that grades at once (every function throws), marked so that it can be
/// looked for in answers.
pub fn quick_source(marker: &str) -> String {
    format!("function init(){{ throw new Error(\"not implemented\") }} // {marker}\n")
}

pub fn at(text: &str) -> Timestamp {
    text.parse()
        .unwrap_or_else(|e| panic!("{text:?} is not a moment: {e}"))
}

pub fn peer(a: u8, b: u8, c: u8, d: u8) -> SocketAddr {
    SocketAddr::from(([a, b, c, d], 9))
}

// ---- the application ----

/// The built browser assets: the pages link to them, so the router needs them.
pub fn assets() -> Assets {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/web/dist");
    if !dir.join("manifest.json").is_file() {
        panic!(
            "the browser assets are not built at {}: run scripts/build-web first (scripts/test does)",
            dir.display()
        );
    }
    Assets::load(&dir).unwrap_or_else(|e| panic!("{e} (run scripts/build-web)"))
}

/// When the tests run on PostgreSQL (`ESTLAB_TEST_DATABASE=postgres`), the database of
/// the test whose data directory is `dir`: made at the first ask, and named in a file of
/// that directory from then on (as `estlab --database` would be given it).
pub fn database_url(dir: &Path) -> Option<String> {
    if !pgtest::wanted() {
        return None;
    }
    let file = dir.join("test-database");
    if let Ok(url) = std::fs::read_to_string(&file) {
        return Some(url);
    }
    let url = pgtest::database();
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(&file, &url).unwrap();
    Some(url)
}

/// The store of the test whose data directory is `dir`, on the engine the tests run on.
pub fn store_in(dir: &Path) -> Store {
    match database_url(dir) {
        Some(url) => Store::connect(&url).unwrap(),
        None => Store::open(dir).unwrap(),
    }
}

/// The web application over a fresh data directory, with a clock of its own.
pub struct App {
    pub dir: tempfile::TempDir,
    /// The PostgreSQL database, when the tests run on PostgreSQL.
    pub url: Option<String>,
    pub clock: Arc<FixedClock>,
    pub state: Arc<AppState>,
    pub router: Router,
}

impl App {
    pub fn new() -> App {
        let clock = Arc::new(FixedClock::new(at("2026-12-01T10:00:00Z")));
        App::over(tempfile::tempdir().unwrap(), clock)
    }

    /// The application over a data directory, grading (and regrading) what waits there.
    fn over(dir: tempfile::TempDir, clock: Arc<FixedClock>) -> App {
        let store = store_in(dir.path());
        let url = database_url(dir.path());
        let secret = Secret::read(&fixed_secret(dir.path())).unwrap();
        let sandbox = Sandbox::new(PathBuf::from(env!("CARGO_BIN_EXE_estlab")), 1);
        let grader = Grader::new(
            store,
            sandbox,
            secret,
            1,
            Arc::clone(&clock) as Arc<dyn Clock>,
        );
        grader.resume().unwrap();
        let state = Arc::new(AppState {
            assets: assets(),
            grader,
            clock: Arc::clone(&clock) as Arc<dyn Clock>,
            behind_https: false,
            datasets: Default::default(),
        });
        let router = estlab::web::router(Arc::clone(&state));
        App {
            dir,
            url,
            clock,
            state,
            router,
        }
    }

    /// The application again over the same data directory, as after a restart.
    pub fn restart(self) -> App {
        App::over(self.dir, self.clock)
    }

    /// A connection of its own to the application's database, for tests that change it
    /// behind the server.
    pub fn database(&self) -> estlab::store::db::Connection {
        use estlab::store::db::Connection;
        match &self.url {
            Some(url) => Connection::Postgres(
                estlab::store::db::Postgres::connect(url.parse().unwrap()).unwrap(),
            ),
            None => Connection::Sqlite(
                rusqlite::Connection::open(self.dir.path().join(estlab::store::FILE)).unwrap(),
            ),
        }
    }

    pub fn store(&self) -> &Store {
        self.state.grader.store()
    }

    pub fn now(&self) -> Timestamp {
        self.clock.now()
    }

    pub async fn send(&self, request: Req) -> Answer {
        let response = self
            .router
            .clone()
            .oneshot(request.build())
            .await
            .expect("the router answers every request");
        let (parts, body) = response.into_parts();
        let bytes = axum::body::to_bytes(body, usize::MAX).await.unwrap();
        Answer {
            status: parts.status,
            headers: parts.headers,
            body: String::from_utf8_lossy(&bytes).into_owned(),
            raw: bytes.to_vec(),
        }
    }

    /// Waits until a submission is graded; panics after `GRADING_BOUND`.
    pub async fn graded(&self, id: i64) -> Submission {
        let give_up = Instant::now() + GRADING_BOUND;
        loop {
            let submission = self
                .store()
                .get(id, false)
                .unwrap()
                .unwrap_or_else(|| panic!("submission {id} is not stored"));
            if submission.summary.status == Status::Graded {
                return submission;
            }
            assert!(
                Instant::now() < give_up,
                "submission {id} was not graded within {GRADING_BOUND:?} (status {:?})",
                submission.summary.status
            );
            tokio::time::sleep(Duration::from_millis(25)).await;
        }
    }

    /// Submits `source` as `who`, expecting 202; waits for the grading; returns the id
    /// and the 202's body.
    pub async fn submit_graded(&self, who: &Who, source: &str) -> (i64, Value) {
        let answer = self
            .send(
                Req::post("/api/submissions")
                    .who(who)
                    .json(json!({ "source": source })),
            )
            .await;
        assert_eq!(answer.status, StatusCode::ACCEPTED, "{}", answer.body);
        let accepted = answer.json();
        let id = accepted["id"].as_i64().expect("an id");
        self.graded(id).await;
        (id, accepted)
    }

    /// Creates `course` ("Applied Estimation") with the EKF exercise open, due in a week.
    pub fn open_course(&self, course: &str) {
        let now = self.now();
        self.store()
            .create_course(course, "Applied Estimation", now)
            .unwrap();
        self.store()
            .assign(course, Exercise::EkfLocalization, &open_policy(now))
            .unwrap();
    }

    /// Adds a student to a course's roster (keeping those already on it).
    pub fn enrol(&self, course: &str, id: &str) -> Member {
        let mut students: Vec<roster::Student> = self
            .store()
            .members(course)
            .unwrap()
            .into_iter()
            .filter(|m| !m.role.is_staff() && !m.dropped)
            .map(|m| roster_line(&m.login, &m.name, &m.email))
            .collect();
        students.push(roster_line(id, &format!("Student {id}"), ""));
        self.store().import_roster(course, &students).unwrap();
        self.store().member(course, id).unwrap()
    }

    pub fn staff(&self, course: &str, email: &str, role: Role) -> Member {
        self.store()
            .add_member(
                course,
                &NewMember {
                    login: email,
                    name: "Staff Person",
                    email,
                    role,
                },
            )
            .unwrap()
    }

    /// A new sign-in code for a member (not one-time, no expiry); its text.
    pub fn code(&self, member: &Member) -> String {
        let code = new_code();
        self.store()
            .add_code(member.id, &code, false, None, self.now())
            .unwrap();
        code.text
    }

    /// Signs in with `code` from `from`, expecting success; the session.
    pub async fn sign_in(&self, code: &str, from: SocketAddr) -> Who {
        let answer = self.send(Req::sign_in(code).sent_from(from)).await;
        assert_eq!(
            answer.status,
            StatusCode::SEE_OTHER,
            "signing in: {}",
            answer.body
        );
        assert_eq!(answer.location(), Some("/me"));
        Who::Session(answer.session().expect("a session cookie"))
    }

    /// A member signed in with a code of their own.
    pub async fn signed_in(&self, member: &Member) -> Who {
        let code = self.code(member);
        self.sign_in(&code, peer(127, 0, 0, 1)).await
    }

    pub fn count(&self) -> usize {
        self.store().all_submissions().unwrap().len()
    }

    /// Opens `exercise` for `course` with `policy` (again: new dates).
    pub fn assign(&self, course: &str, exercise: Exercise, policy: &Policy) {
        self.store().assign(course, exercise, policy).unwrap();
    }

    /// Submits `source` to `exercise` as `who`; the answer, whatever it is (nothing waits
    /// for a grading).
    pub async fn submit_to(&self, who: &Who, exercise: Exercise, source: &str) -> Answer {
        self.send(
            Req::post("/api/submissions")
                .who(who)
                .json(json!({ "source": source, "lab": exercise.name() })),
        )
        .await
    }

    /// Waits until every regrade begun is done; panics after `GRADING_BOUND`.
    pub async fn regrades_done(&self) {
        let give_up = Instant::now() + GRADING_BOUND;
        let grader = &self.state.grader;
        while let Some((regrade, submission)) = self
            .store()
            .next_regrade_item(Timestamp::MAX, &grader.versions(), &Default::default())
            .unwrap()
        {
            assert!(
                Instant::now() < give_up,
                "regrade {regrade} did not regrade submission {submission} within {GRADING_BOUND:?}"
            );
            tokio::time::sleep(Duration::from_millis(25)).await;
        }
    }

    /// `GET path` as `who`, expecting 200 and JSON.
    pub async fn get_json(&self, who: &Who, path: &str) -> Value {
        let answer = self.send(Req::get(path).who(who)).await;
        assert_eq!(answer.status, StatusCode::OK, "GET {path}: {}", answer.body);
        answer.json()
    }
}

/// correct.js with one of the catalogued classic mistakes (`tests/student/mistakes.json`)
/// made.
pub fn with_mistake(name: &str) -> String {
    #[derive(serde::Deserialize)]
    struct Mistake {
        name: String,
        replace: Vec<Replacement>,
    }
    #[derive(serde::Deserialize)]
    struct Replacement {
        from: String,
        to: String,
    }
    let mistakes: Vec<Mistake> = serde_json::from_str(MISTAKES).unwrap();
    let mistake = mistakes
        .iter()
        .find(|m| m.name == name)
        .unwrap_or_else(|| panic!("the mistake {name:?} is not catalogued"));
    let source = mistake
        .replace
        .iter()
        .fold(CORRECT.to_string(), |s, r| s.replace(&r.from, &r.to));
    assert_ne!(source, CORRECT, "the mistake {name:?} changed nothing");
    source
}

/// The files of a zip, by name, as text.
pub fn unzip(bytes: &[u8]) -> Vec<(String, String)> {
    use std::io::Read;
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
    (0..archive.len())
        .map(|i| {
            let mut file = archive.by_index(i).unwrap();
            let mut text = String::new();
            file.read_to_string(&mut text).unwrap();
            (file.name().unwrap().into_owned(), text)
        })
        .collect()
}

/// The rows of a CSV file (without its header), each as its cells.
pub fn csv_rows(text: &str) -> Vec<Vec<String>> {
    csv::Reader::from_reader(text.as_bytes())
        .records()
        .map(|r| r.unwrap().iter().map(str::to_string).collect())
        .collect()
}

// ---- the routes ----

/// The router's own source: its routes are read from it, so that a test that must cover
/// every route learns of a new one.
const ROUTER_SOURCE: &str = include_str!("../../../src/web/mod.rs");

/// The site's registry of pages, which the router serves too.
pub const PAGES: &str = include_str!("../../../../static/pages.json");

/// Every exercise's workbench and its starter file (`/ekf/code`, `/ekf/starter.js`), which
/// the router serves from the exercises' declarations.
pub fn workbench_routes() -> Vec<String> {
    labs::Exercise::ALL
        .iter()
        .flat_map(|exercise| {
            let path = exercise.declaration().workbench.path;
            let folder = path
                .strip_suffix("/code")
                .expect("a workbench's path ends in /code");
            std::iter::once(path.to_owned()).chain(
                labs::Language::ALL
                    .iter()
                    .map(move |language| format!("{folder}/starter.{}", language.extension())),
            )
        })
        .collect()
}

/// Every route the router serves, as it names them (`/api/submissions/{id}`): the
/// literal ones of `web::router`, the pages of the registry and the workbenches.
pub fn routes() -> Vec<String> {
    let mut routes: Vec<String> = ROUTER_SOURCE
        .split(".route(")
        .skip(1)
        .filter_map(|after| {
            let rest = after.trim_start().strip_prefix('"')?;
            Some(rest[..rest.find('"')?].to_string())
        })
        .collect();
    #[derive(serde::Deserialize)]
    struct Registry {
        pages: Vec<Page>,
    }
    #[derive(serde::Deserialize)]
    struct Page {
        path: String,
    }
    let registry: Registry = serde_json::from_str(PAGES).unwrap();
    routes.extend(registry.pages.into_iter().map(|p| p.path));
    routes.extend(workbench_routes());
    assert!(
        routes.iter().any(|r| r == "/api/submissions/{id}"),
        "no routes read from web/mod.rs: {routes:?}"
    );
    routes
}

/// Whether `path` (without its query) is one the route `pattern` serves: segment by
/// segment, a `{name}` standing for any one segment.
pub fn route_serves(pattern: &str, path: &str) -> bool {
    let path = path.split('?').next().unwrap_or(path);
    let (a, b): (Vec<&str>, Vec<&str>) = (pattern.split('/').collect(), path.split('/').collect());
    a.len() == b.len()
        && a.iter()
            .zip(&b)
            .all(|(p, s)| (p.starts_with('{') && p.ends_with('}')) || p == s)
}

pub fn roster_line(id: &str, name: &str, email: &str) -> roster::Student {
    roster::Student {
        id: id.into(),
        name: name.into(),
        email: email.into(),
    }
}

/// An assignment of the exercise due well after the clock's start.
pub fn open_policy(now: Timestamp) -> Policy {
    Policy {
        due: now + SignedDuration::from_hours(30 * 24),
        cutoff: now + SignedDuration::from_hours(31 * 24),
        penalty_per_day: 0.1,
        counts: Counts::Best,
    }
}

/// Who asks.
#[derive(Clone, Debug)]
pub enum Who {
    Anonymous,
    /// The value of the session cookie.
    Session(String),
    /// An API token, sent as `Authorization: Bearer`.
    Token(String),
}

/// A request about to be sent.
pub struct Req {
    method: Method,
    uri: String,
    headers: Vec<(String, String)>,
    body: Option<(&'static str, String)>,
    peer: SocketAddr,
}

impl Req {
    pub fn new(method: Method, uri: &str) -> Req {
        Req {
            method,
            uri: uri.into(),
            headers: Vec::new(),
            body: None,
            peer: peer(127, 0, 0, 9),
        }
    }

    pub fn get(uri: &str) -> Req {
        Req::new(Method::GET, uri)
    }

    pub fn post(uri: &str) -> Req {
        Req::new(Method::POST, uri)
    }

    /// `POST /signin` with a code, as the sign-in form sends it.
    pub fn sign_in(code: &str) -> Req {
        Req::post("/signin").form(&format!("code={code}"))
    }

    pub fn header(mut self, name: &str, value: &str) -> Req {
        self.headers.push((name.into(), value.into()));
        self
    }

    pub fn who(self, who: &Who) -> Req {
        match who {
            Who::Anonymous => self,
            Who::Session(key) => self.header("cookie", &format!("{SESSION_COOKIE}={key}")),
            Who::Token(token) => self.header("authorization", &format!("Bearer {token}")),
        }
    }

    pub fn json(mut self, value: Value) -> Req {
        self.body = Some(("application/json", value.to_string()));
        self
    }

    pub fn form(mut self, text: &str) -> Req {
        self.body = Some(("application/x-www-form-urlencoded", text.into()));
        self
    }

    /// The client's address (what the sign-in limiter counts by).
    pub fn sent_from(mut self, peer: SocketAddr) -> Req {
        self.peer = peer;
        self
    }

    pub fn build(self) -> Request<Body> {
        let mut builder = Request::builder().method(self.method).uri(self.uri);
        for (name, value) in &self.headers {
            builder = builder.header(name, value);
        }
        let body = match self.body {
            Some((content_type, text)) => {
                builder = builder.header(header::CONTENT_TYPE, content_type);
                Body::from(text)
            }
            None => Body::empty(),
        };
        let mut request = builder.body(body).unwrap();
        request.extensions_mut().insert(ConnectInfo(self.peer));
        request
    }
}

/// A response, read whole.
pub struct Answer {
    pub status: StatusCode,
    pub headers: HeaderMap,
    pub body: String,
    /// The body's bytes, for an answer that is not text (a zip).
    pub raw: Vec<u8>,
}

impl Answer {
    pub fn json(&self) -> Value {
        serde_json::from_str(&self.body).unwrap_or_else(|e| panic!("not JSON ({e}): {}", self.body))
    }

    pub fn location(&self) -> Option<&str> {
        self.headers
            .get(header::LOCATION)
            .and_then(|v| v.to_str().ok())
    }

    /// The session key a `Set-Cookie` header sets (not the empty one of signing out).
    pub fn session(&self) -> Option<String> {
        self.headers
            .get_all(header::SET_COOKIE)
            .iter()
            .filter_map(|v| v.to_str().ok())
            .filter_map(|v| v.split(';').next())
            .filter_map(|pair| pair.trim().split_once('='))
            .find(|(name, value)| *name == SESSION_COOKIE && !value.is_empty())
            .map(|(_, value)| value.to_string())
    }

    /// The `error` of a JSON error body.
    pub fn error(&self) -> String {
        self.json()["error"]
            .as_str()
            .unwrap_or_else(|| panic!("no `error` in {}", self.body))
            .to_string()
    }
}
