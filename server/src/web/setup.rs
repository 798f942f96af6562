//! The course set up on the web, by its instructors (`/courses/{course}`): the staff and
//! their one-time links, the roster previewed then imported, new sign-in codes (the
//! codes file is in the answer, the one time it can be read), the exercises opened with
//! their dates and policies, and API tokens. The same rules and messages as `estlab
//! course` (`courses::setup`), and the same audit log. Reading the set-up is for the
//! course's staff; changing it for its instructors (signed in, or an instructor's token).

use super::codes::{self, CodesStarted};
use super::extract::Body;
use super::pages::{Nav, html};
use super::viewer::Viewer;
use super::{AppState, Error, blocking, lab_field};
use crate::courses::deadline::{Counts, Policy, parse_moment, parse_penalty};
use crate::courses::setup::{self, RosterPlan, Setup};
use crate::store::{Assignment, Course, Member, Role, TokenInfo};
use askama::Template;
use axum::Json;
use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Redirect, Response};
use jiff::Timestamp;
use labs::Exercise;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use ts_rs::TS;

impl From<setup::Error> for Error {
    fn from(error: setup::Error) -> Error {
        match error {
            setup::Error::Invalid(message) => Error::BadRequest(message),
            setup::Error::Store(error) => Error::Store(error),
        }
    }
}

/// Runs one instructor's change to `course` on the database, off the async executor.
pub(super) async fn change<T: Send + 'static>(
    state: &AppState,
    viewer: &Viewer,
    course: String,
    work: impl FnOnce(&Setup) -> Result<T, setup::Error> + Send + 'static,
) -> Result<T, Error> {
    viewer.instructor_of(&course)?;
    let actor = viewer.actor();
    let now = state.clock.now();
    let grader = Arc::clone(&state.grader);
    tokio::task::spawn_blocking(move || {
        work(&Setup {
            store: grader.store(),
            course: &course,
            actor: &actor,
            now,
        })
    })
    .await
    .map_err(|e| crate::store::Error::Task(e.to_string()))?
    .map_err(Error::from)
}

/// An exercise as the set-up offers it.
#[derive(Serialize, TS)]
pub struct Offered {
    pub name: &'static str,
    pub title: &'static str,
}

/// `GET /api/courses/{course}`: for its staff, the course as set up: its people,
/// assignments and API tokens (never a token itself), the exercises it may open, and
/// whether the asker may change it.
#[derive(Serialize, TS)]
pub struct CourseView {
    pub course: Course,
    pub assignments: Vec<Assignment>,
    pub members: Vec<Member>,
    pub tokens: Vec<TokenInfo>,
    pub exercises: Vec<Offered>,
    pub may_set_up: bool,
}

pub async fn course(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(name): Path<String>,
) -> Result<Response, Error> {
    viewer.staff_of(&name)?;
    let may_set_up = viewer.instructor_of(&name).is_ok();
    let view = blocking(&state, move |store| {
        Ok(CourseView {
            course: store.course(&name)?,
            assignments: store.assignments(&name)?,
            members: store.members(&name)?,
            tokens: store.tokens(&name)?,
            exercises: Exercise::ALL
                .iter()
                .map(|e| Offered {
                    name: e.name(),
                    title: e.title(),
                })
                .collect(),
            may_set_up,
        })
    })
    .await?;
    Ok(Json(view).into_response())
}

/// The body of `POST /api/courses/{course}/staff`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StaffRequest {
    email: String,
    #[serde(default)]
    name: String,
    role: Role,
}

#[derive(Serialize, TS)]
pub(super) struct StaffAdded {
    email: String,
    role: Role,
    /// Their one-time sign-in link, valid for a week: shown this once.
    link: String,
}

/// `POST /api/courses/{course}/staff`: adds an instructor or assistant (or changes their
/// role) and answers with their one-time sign-in link. An instructor signed in may not
/// make themselves an assistant: another instructor does that.
pub async fn add_staff(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(course): Path<String>,
    body: Body,
) -> Result<Response, Error> {
    viewer.instructor_of(&course)?;
    let request: StaffRequest = body.json(&viewer, "the staff request").await?;
    let own = viewer
        .member()
        .is_some_and(|me| me.login == request.email.trim());
    if own && request.role != Role::Instructor {
        return Err(Error::BadRequest(
            "field `role`: you would no longer set up this course; another instructor can change your role".into(),
        ));
    }
    let added = change(&state, &viewer, course, move |setup| {
        let url = setup::public_url(setup.store)?;
        let link = setup.staff(&request.email, &request.name, request.role, &url)?;
        Ok(StaffAdded {
            email: request.email.trim().to_string(),
            role: request.role,
            link,
        })
    })
    .await?;
    Ok(Json(added).into_response())
}

/// The body of `POST /api/courses/{course}/roster[/preview]`: the roster file's name and
/// text (CSV with a header: id, name, email).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RosterRequest {
    file_name: String,
    csv: String,
}

/// A student of a roster's answer.
#[derive(Serialize, TS)]
pub(super) struct Listed {
    id: String,
    name: String,
    email: String,
}

/// What a roster adds, updates and drops; once it is imported, where to follow the
/// making of its new students' codes (none when it adds nobody).
#[derive(Serialize, TS)]
pub(super) struct RosterAnswer {
    students: usize,
    added: Vec<Listed>,
    updated: Vec<String>,
    unchanged: usize,
    dropped: Vec<String>,
    summary: String,
    codes: Option<CodesStarted>,
}

impl RosterAnswer {
    fn of(plan: RosterPlan, codes: Option<CodesStarted>) -> RosterAnswer {
        let summary = plan.summary();
        let change = plan.change;
        RosterAnswer {
            students: plan.students,
            added: change
                .added
                .into_iter()
                .map(|m| Listed {
                    id: m.login,
                    name: m.name,
                    email: m.email,
                })
                .collect(),
            updated: change.updated,
            unchanged: change.unchanged,
            dropped: change.dropped,
            summary,
            codes,
        }
    }
}

/// The longest roster file name kept in the audit log.
const MAX_FILE_NAME: usize = 255;

fn file_name(request: &RosterRequest) -> Result<String, Error> {
    let name = request.file_name.trim();
    if name.is_empty() || name.chars().count() > MAX_FILE_NAME || name.chars().any(char::is_control)
    {
        return Err(Error::BadRequest(format!(
            "field `file_name`: the roster file's name, of 1 to {MAX_FILE_NAME} characters"
        )));
    }
    Ok(crate::courses::ids::shown(name))
}

/// `POST /api/courses/{course}/roster/preview`: what importing the roster would add,
/// update and drop, changing nothing; a problem names the file's line.
pub async fn preview_roster(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(course): Path<String>,
    body: Body,
) -> Result<Response, Error> {
    viewer.instructor_of(&course)?;
    let request: RosterRequest = body.json(&viewer, "the roster").await?;
    let file = file_name(&request)?;
    let plan = change(&state, &viewer, course, move |setup| {
        setup.preview_roster(&file, &request.csv)
    })
    .await?;
    Ok(Json(RosterAnswer::of(plan, None)).into_response())
}

/// `POST /api/courses/{course}/roster`: imports the roster and answers with what changed
/// and where to follow the making of the new students' sign-in codes.
pub async fn import_roster(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(course): Path<String>,
    body: Body,
) -> Result<Response, Error> {
    viewer.instructor_of(&course)?;
    let request: RosterRequest = body.json(&viewer, "the roster").await?;
    let file = file_name(&request)?;
    let plan = change(&state, &viewer, course.clone(), move |setup| {
        setup.import_roster(&file, &request.csv)
    })
    .await?;
    let added = plan.change.added.clone();
    let codes = match added.is_empty() {
        true => None,
        false => Some(codes::start(&state, &viewer, course, (added, Vec::new())).await?),
    };
    Ok(Json(RosterAnswer::of(plan, codes)).into_response())
}

/// The body of `POST /api/courses/{course}/codes`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CodesRequest {
    students: Vec<String>,
}

/// The most students given new codes at once (a large class's roster).
const MAX_REISSUE: usize = 2000;

/// `POST /api/courses/{course}/codes`: new sign-in codes for these students (their old
/// ones stop working), made in the background: 202, with where to follow the making.
pub async fn reissue(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(course): Path<String>,
    body: Body,
) -> Result<Response, Error> {
    viewer.instructor_of(&course)?;
    let mut request: CodesRequest = body.json(&viewer, "the codes request").await?;
    request.students.sort();
    request.students.dedup();
    if request.students.is_empty() || request.students.len() > MAX_REISSUE {
        return Err(Error::BadRequest(format!(
            "field `students`: the ids of 1 to {MAX_REISSUE} students who need a new code"
        )));
    }
    let reissued = request.students.clone();
    let students = change(&state, &viewer, course.clone(), move |setup| {
        setup.students(&request.students)
    })
    .await?;
    let started = codes::start(&state, &viewer, course, (students, reissued)).await?;
    Ok((StatusCode::ACCEPTED, Json(started)).into_response())
}

/// The body of `POST /api/courses/{course}/assignments`: moments with their time zone
/// (`2026-12-15T23:59+01:00`), the penalty as `10%/day`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AssignRequest {
    lab: String,
    due: String,
    cutoff: Option<String>,
    #[serde(default = "no_penalty")]
    late_penalty: String,
    #[serde(default = "best")]
    counts: Counts,
}

fn no_penalty() -> String {
    "0%/day".into()
}

fn best() -> Counts {
    Counts::Best
}

fn moment(field: &str, text: &str) -> Result<Timestamp, Error> {
    parse_moment(text).map_err(|e| Error::BadRequest(format!("field `{field}`: {e}")))
}

/// `POST /api/courses/{course}/assignments`: opens an exercise for the course (or
/// changes its dates and policy); answers with the assignment as stored.
pub async fn assign(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(course): Path<String>,
    body: Body,
) -> Result<Response, Error> {
    viewer.instructor_of(&course)?;
    let request: AssignRequest = body.json(&viewer, "the assignment").await?;
    let exercise = lab_field(&request.lab)?;
    let due = moment("due", &request.due)?;
    let policy = Policy {
        due,
        cutoff: match &request.cutoff {
            Some(text) if !text.trim().is_empty() => moment("cutoff", text)?,
            _ => due,
        },
        penalty_per_day: parse_penalty(&request.late_penalty)
            .map_err(|e| Error::BadRequest(format!("field `late_penalty`: {e}")))?,
        counts: request.counts,
    };
    let assignment = change(&state, &viewer, course.clone(), move |setup| {
        setup.assign(exercise, &policy)?;
        Ok(setup
            .store
            .assignment(&course, exercise)?
            .expect("the assignment just stored"))
    })
    .await
    .map_err(|error| match error {
        // The one rule assign checks: the cutoff comes after the due date.
        Error::BadRequest(problem) => Error::BadRequest(format!("field `cutoff`: {problem}")),
        other => other,
    })?;
    Ok(Json(assignment).into_response())
}

/// The body of `POST /api/courses/{course}/tokens`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TokenRequest {
    role: Role,
}

#[derive(Serialize, TS)]
pub(super) struct TokenMade {
    id: i64,
    role: Role,
    /// Sent as `Authorization: Bearer TOKEN`; shown this once, stored hashed.
    token: String,
}

/// `POST /api/courses/{course}/tokens`: a new API token, shown in this answer only.
pub async fn make_token(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(course): Path<String>,
    body: Body,
) -> Result<Response, Error> {
    viewer.instructor_of(&course)?;
    let request: TokenRequest = body.json(&viewer, "the token request").await?;
    let (id, token) = change(&state, &viewer, course, move |setup| {
        setup.token(request.role)
    })
    .await?;
    Ok((
        StatusCode::CREATED,
        Json(TokenMade {
            id,
            role: request.role,
            token,
        }),
    )
        .into_response())
}

#[derive(Serialize, TS)]
pub(super) struct Revoked {
    id: i64,
    revoked: bool,
}

/// `POST /api/courses/{course}/tokens/{id}/revoke`: the token stops working at once; a
/// token of another course (or none) is the same 404.
pub async fn revoke_token(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, id)): Path<(String, String)>,
) -> Result<Response, Error> {
    viewer.instructor_of(&course)?;
    let missing = Error::NotFound(format!("{course} has no API token {id:?}"));
    let Ok(number) = id.parse::<i64>() else {
        return Err(missing);
    };
    let revoked = change(&state, &viewer, course, move |setup| setup.revoke(number)).await?;
    if !revoked {
        return Err(missing);
    }
    Ok(Json(Revoked {
        id: number,
        revoked,
    })
    .into_response())
}

#[derive(Template)]
#[template(path = "course.html")]
struct CoursePage<'a> {
    page: &'a str,
    assets: super::assets::PageAssets<'a>,
    nav: Nav,
    course: String,
}

/// `GET /courses/{course}`: the course's page for its staff: its exercises, people and
/// tokens, and for its instructors the forms that set it up.
pub async fn page(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(course): Path<String>,
) -> Result<Response, Error> {
    if matches!(viewer, Viewer::Anonymous) {
        return Ok(Redirect::to("/signin").into_response());
    }
    viewer.staff_of(&course)?;
    html(&CoursePage {
        page: "course",
        assets: state.assets.page("course"),
        nav: Nav::of(&state, &viewer).await?,
        course,
    })
}
