//! The web application: the pages, rendered with askama, the JSON API, signing in, and
//! the built browser assets. Every route checks on the server who may see or change what
//! it serves (see `viewer`); changes are taken from estlab's own pages only (`origin`).

mod address;
mod answers;
mod api;
mod assets;
mod codes;
pub mod connections;
mod error;
mod extract;
mod limiter;
mod me;
pub mod metrics;
mod origin;
mod pages;
pub mod phases;
mod registry;
pub mod report;
mod reviews;
mod setup;
mod signin;
mod staff;
mod submit;
#[cfg(test)]
mod types;
mod viewer;

pub use assets::Assets;
pub use error::Error;

pub use viewer::SESSION_COOKIE;

use crate::clock::Clock;
use crate::datasets::Datasets;
use crate::grading::Grader;
use crate::store::{self, Store};
use axum::Router;
use axum::extract::{DefaultBodyLimit, MatchedPath, Request, State};
use axum::handler::Handler;
use axum::http::{HeaderValue, header};
use axum::routing::{MethodRouter, get, post};
use labs::{Exercise, Language};
use registry::Page;
use std::sync::Arc;
use std::time::Duration;
use tower_http::compression::CompressionLayer;
use tower_http::set_header::SetResponseHeaderLayer;
use tower_http::trace::TraceLayer;
use tracing::Span;

/// The path of an exercise's workbench (`/ekf/code`).
pub fn workbench_path(exercise: Exercise) -> &'static str {
    &registry::workbench(exercise).path
}

/// What every request handler can reach.
pub struct AppState {
    pub assets: Assets,
    pub grader: Arc<Grader>,
    pub clock: Arc<dyn Clock>,
    /// Behind a TLS reverse proxy: cookies are `Secure`, and the client's address is the
    /// last one the proxy added to `X-Forwarded-For`.
    pub behind_https: bool,
    /// The real data sets of `--datasets DIR` (none without it).
    pub datasets: Arc<Datasets>,
}

/// The largest sign-in form: a code is 24 characters.
const MAX_SIGN_IN: usize = 1024;

/// Scripts from this origin only (and the wasm module they compile); styles may be
/// inline, as the plotting and formula libraries set them on elements.
const CONTENT_SECURITY_POLICY: &str = "default-src 'self'; script-src 'self' 'wasm-unsafe-eval'; \
    style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; font-src 'self'; \
    object-src 'none'; base-uri 'none'; frame-ancestors 'none'; form-action 'self'";

/// What serves a page of the registry: its handler, by the page's name; a workbench's,
/// for its exercise.
fn page_route(page: &Page) -> MethodRouter<Arc<AppState>> {
    if let Some(exercise) = page.exercise {
        return get(move |state, viewer| pages::workbench(state, viewer, exercise));
    }
    match page.name.as_str() {
        "home" => get(pages::home),
        "car" => get(pages::car),
        "ekf" => get(pages::ekf),
        "odometry" => get(pages::odometry),
        "fusion" => get(pages::fusion),
        "mrclam" => get(pages::mrclam),
        "signin" => {
            get(signin::page).post(signin::sign_in.layer(DefaultBodyLimit::max(MAX_SIGN_IN)))
        }
        "me" => get(me::page),
        "course" => get(setup::page),
        "dashboard" => get(staff::page),
        "dashboard-student" => get(staff::student_page),
        "questions" => get(answers::page),
        "report" => get(report::page),
        name => panic!("static/pages.json: no handler serves the page {name:?}"),
    }
}

pub fn router(state: Arc<AppState>) -> Router {
    let static_files = assets::service(state.assets.dir());
    let mut router = Router::new();
    for page in registry::pages() {
        router = router.route(&page.path, page_route(page));
        for &language in Language::ALL {
            if let (Some(exercise), Some(starter)) = (page.exercise, page.starter_path(language)) {
                router = router.route(&starter, get(move || pages::starter(exercise, language)));
            }
        }
    }
    router
        .route("/signout", post(signin::sign_out))
        .route("/api/me", get(me::about))
        .route("/api/me/submissions", get(me::history))
        .route("/api/submissions", post(api::submit))
        .route("/api/submissions/{id}", get(api::submission))
        .route("/api/phases", post(phases::run))
        .route("/api/courses/{course}", get(setup::course))
        .route("/api/courses/{course}/staff", post(setup::add_staff))
        .route(
            "/api/courses/{course}/roster/preview",
            post(setup::preview_roster),
        )
        .route("/api/courses/{course}/roster", post(setup::import_roster))
        .route("/api/courses/{course}/codes", post(setup::reissue))
        .route("/api/courses/{course}/codes/{id}", get(codes::progress))
        .route("/api/courses/{course}/assignments", post(setup::assign))
        .route("/api/courses/{course}/tokens", post(setup::make_token))
        .route(
            "/api/courses/{course}/tokens/{id}/revoke",
            post(setup::revoke_token),
        )
        .route(
            "/api/courses/{course}/submissions",
            get(api::course_submissions),
        )
        .route("/api/courses/{course}/labs/{lab}/class", get(staff::class))
        .route(
            "/api/courses/{course}/labs/{lab}/questions",
            get(answers::questions).post(answers::import),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/answers",
            post(answers::save),
        )
        .route("/api/courses/{course}/labs/{lab}/report", get(report::mine))
        .route(
            "/api/courses/{course}/labs/{lab}/report/runs",
            get(report::my_runs),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/report/analyses",
            post(report::save_analysis),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/report/hand-in",
            post(report::hand_in),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/reports",
            get(report::class),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/reports/{student}",
            get(report::of_student),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/reports/{student}/runs",
            get(report::student_runs),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/reports/{student}/rubric",
            post(report::rubric),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/rounds",
            get(reviews::list).post(reviews::open),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/rounds/{id}",
            post(reviews::act),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/reviews",
            get(reviews::mine),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/reviews/{round}/{sheet}",
            get(reviews::sheet).post(reviews::mark),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/ranking",
            post(staff::set_ranking),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/languages",
            post(staff::set_languages),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/students/{student}",
            get(staff::student),
        )
        .route(
            "/api/courses/{course}/labs/{lab}/export",
            get(staff::export),
        )
        .route("/api/courses/{course}/regrades", post(staff::start_regrade))
        .route("/api/courses/{course}/regrades/{id}", get(staff::regrade))
        .route("/api/courses/{course}/extensions", post(staff::extend))
        .route(
            "/api/courses/{course}/submissions/{id}/waiver",
            post(staff::waive),
        )
        .route("/api/courses/{course}/audit", get(staff::audit))
        .route("/api/datasets/northstar", get(pages::northstar_trials))
        .route("/api/datasets/mrclam", get(pages::mrclam_robots))
        .route("/api/datasets/mrclam/robot", get(pages::mrclam_robot))
        .route("/healthz", get(|| async { "ok" }))
        .route(
            "/metrics",
            get(|state: State<Arc<AppState>>, headers| {
                metrics::scrape(state.grader.clone(), headers)
            }),
        )
        .route("/favicon.svg", get(pages::icon))
        .route("/favicon.ico", get(pages::icon))
        .nest_service("/static", static_files)
        .fallback(pages::not_found)
        .layer(axum::middleware::from_fn(origin::same_origin_only))
        .layer(axum::middleware::from_fn(api_not_stored))
        .layer(DefaultBodyLimit::max(extract::MAX_BODY))
        .layer(CompressionLayer::new())
        .layer(SetResponseHeaderLayer::if_not_present(
            header::CONTENT_SECURITY_POLICY,
            HeaderValue::from_static(CONTENT_SECURITY_POLICY),
        ))
        .layer(SetResponseHeaderLayer::if_not_present(
            header::X_CONTENT_TYPE_OPTIONS,
            HeaderValue::from_static("nosniff"),
        ))
        .layer(SetResponseHeaderLayer::if_not_present(
            header::REFERRER_POLICY,
            HeaderValue::from_static("same-origin"),
        ))
        .layer(
            TraceLayer::new_for_http()
                .make_span_with(request_span)
                .on_request(())
                .on_response(
                    |response: &axum::response::Response, latency: Duration, _: &Span| {
                        tracing::info!(
                            status = response.status().as_u16(),
                            ms = latency.as_millis() as u64,
                            "answered"
                        );
                    },
                ),
        )
        .with_state(state)
}

/// The API's answers (sources and results) are kept by no cache, a shared lab
/// computer's browser included.
async fn api_not_stored(
    request: Request,
    next: axum::middleware::Next,
) -> axum::response::Response {
    let api = request.uri().path().starts_with("/api/");
    let mut response = next.run(request).await;
    if api {
        response
            .headers_mut()
            .insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
    }
    response
}

/// A request's span names its method and its route's pattern (`/api/submissions/{id}`),
/// never the path or query as sent: nothing a person typed reaches the log.
fn request_span(request: &Request) -> Span {
    let route = request
        .extensions()
        .get::<MatchedPath>()
        .map_or("(no route)", MatchedPath::as_str);
    tracing::info_span!("request", method = %request.method(), route)
}

/// Runs `work` on the database on a blocking thread, off the async executor.
pub async fn blocking<T: Send + 'static>(
    state: &AppState,
    work: impl FnOnce(&Store) -> Result<T, store::Error> + Send + 'static,
) -> Result<T, Error> {
    let grader = Arc::clone(&state.grader);
    tokio::task::spawn_blocking(move || work(grader.store()))
        .await
        .map_err(|e| store::Error::Task(e.to_string()))?
        .map_err(Error::from)
}

/// The exercise a request means when it names none (the default of every `lab` field).
fn default_lab() -> String {
    Exercise::default().name().to_owned()
}

/// The exercise a route's `{lab}` names; an unknown one is not found.
fn known_lab(lab: &str) -> Result<Exercise, Error> {
    lab.parse()
        .map_err(|unknown: labs::UnknownExercise| Error::NotFound(unknown.to_string()))
}

/// The exercise a request's `lab` field names; an unknown one is refused, naming the field
/// and the exercises graded here.
fn lab_field(lab: &str) -> Result<Exercise, Error> {
    lab.parse()
        .map_err(|unknown| Error::BadRequest(format!("field `lab`: {unknown}")))
}
