//! The instructor's side: a course's exercise at a glance (`/courses/{course}/{lab}`),
//! one student's submissions, regrades, extensions, the audit log and the exports. Every
//! route is for the course's staff (signed in, or with the course's API token); anyone
//! else gets the same 404 as for a course that does not exist.

use super::extract::{Body, Query};
use super::pages::{Nav, html};
use super::viewer::Viewer;
use super::{AppState, Error, blocking, known_lab, lab_field};
use crate::courses::class::{self, ClassView};
use crate::courses::deadline::{Policy, parse_moment};
use crate::courses::export::{self, Format};
use crate::store::{
    AuditEntry, Extension, Member, NewExtension, NewWaiver, Regrade, Scope, SubmissionSummary,
};
use askama::Template;
use axum::Json;
use axum::extract::{Path, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Redirect, Response};
use labs::{Exercise, Language};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use ts_rs::TS;

/// `GET /api/courses/{course}/labs/{lab}/class`.
#[derive(Serialize, TS)]
pub struct ClassAnswer {
    pub course: String,
    pub lab: Exercise,
    pub policy: Policy,
    /// Whether students see their rank in the class challenge.
    pub ranked: bool,
    /// The languages the assignment takes.
    pub languages: Vec<Language>,
    /// The grader that grades now (a regrade uses it).
    pub grader: String,
    #[serde(flatten)]
    pub view: ClassView,
    pub regrades: Vec<Regrade>,
}

async fn class_answer(
    state: &AppState,
    course: String,
    exercise: Exercise,
) -> Result<ClassAnswer, Error> {
    let grader = state.grader.version(exercise).to_string();
    blocking(state, move |store| {
        let Some(assignment) = store.assignment(&course, exercise)? else {
            return Ok(None);
        };
        let Some(view) = class::load(store, &course, exercise)? else {
            return Ok(None);
        };
        let regrades = store
            .regrades(&course)?
            .into_iter()
            .filter(|r| r.lab == exercise)
            .collect();
        Ok(Some(ClassAnswer {
            course,
            policy: assignment.policy,
            ranked: assignment.ranked,
            languages: assignment.languages,
            lab: exercise,
            grader,
            view,
            regrades,
        }))
    })
    .await?
    .ok_or_else(|| Error::NotFound("the course has not opened this exercise".into()))
}

pub async fn class(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let exercise = known_lab(&lab)?;
    Ok(Json(class_answer(&state, course, exercise).await?).into_response())
}

/// The body of `POST /api/courses/{course}/labs/{lab}/ranking`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RankingRequest {
    ranked: bool,
}

/// What the ranking switch answers: the switch as stored.
#[derive(Serialize, TS)]
pub(super) struct RankingSet {
    ranked: bool,
}

/// `POST /api/courses/{course}/labs/{lab}/ranking`: shows the students of an assignment
/// their rank in the class challenge, or stops (each still sees their own figure); logged.
pub async fn set_ranking(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
    body: Body,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let exercise = known_lab(&lab)?;
    let request: RankingRequest = body.json(&viewer, "the ranking switch").await?;
    let who = viewer.actor();
    let now = state.clock.now();
    let ranked = request.ranked;
    let shown = if ranked { "shown" } else { "hidden" };
    let detail = format!("{exercise}: the class challenge's ranks {shown} to students");
    let at = course.clone();
    let change = move |store: &crate::store::Store| store.set_ranked(&at, exercise, ranked);
    audited(&state, course, change, (who, "ranking", detail, now)).await?;
    Ok(Json(RankingSet { ranked }).into_response())
}

/// Changes a setting of an assignment of `course` with `change` (false: the course has
/// not opened the exercise, a 404) and logs it in the course's audit as `(who, action,
/// detail, now)`.
async fn audited(
    state: &Arc<AppState>,
    course: String,
    change: impl FnOnce(&crate::store::Store) -> Result<bool, crate::store::Error> + Send + 'static,
    (who, action, detail, now): (String, &'static str, String, jiff::Timestamp),
) -> Result<(), Error> {
    let found = blocking(state, move |store| {
        if !change(store)? {
            return Ok(false);
        }
        store.audit(&course, &who, action, &detail, now)?;
        Ok(true)
    })
    .await?;
    if !found {
        return Err(Error::NotFound(
            "the course has not opened this exercise".into(),
        ));
    }
    Ok(())
}

/// The body of `POST /api/courses/{course}/labs/{lab}/languages`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LanguagesRequest {
    languages: Vec<String>,
}

/// What the languages' choice answers: the languages as stored.
#[derive(Serialize, TS)]
pub(super) struct LanguagesSet {
    languages: Vec<Language>,
}

/// `POST /api/courses/{course}/labs/{lab}/languages`: the languages an assignment's
/// files may be written in (a course that teaches in one language takes files in it
/// only); submissions already made stay as they are; logged.
pub async fn set_languages(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
    body: Body,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let exercise = known_lab(&lab)?;
    let request: LanguagesRequest = body.json(&viewer, "the languages").await?;
    let mut languages = Vec::new();
    for name in &request.languages {
        let language: Language = name
            .parse()
            .map_err(|unknown| Error::BadRequest(format!("field `languages`: {unknown}")))?;
        if !languages.contains(&language) {
            languages.push(language);
        }
    }
    if languages.is_empty() {
        return Err(Error::BadRequest(
            "field `languages`: name one language at least".into(),
        ));
    }
    languages.sort();
    let who = viewer.actor();
    let now = state.clock.now();
    let names: Vec<&str> = languages.iter().map(|l| l.title()).collect();
    let detail = format!("{exercise}: files taken in {}", names.join(" and "));
    let stored = languages.clone();
    let at = course.clone();
    let change = move |store: &crate::store::Store| store.set_languages(&at, exercise, &stored);
    audited(&state, course, change, (who, "languages", detail, now)).await?;
    Ok(Json(LanguagesSet { languages }).into_response())
}

/// `GET /api/courses/{course}/labs/{lab}/students/{student}`: one student's submissions.
#[derive(Serialize, TS)]
pub struct StudentAnswer {
    pub member: Member,
    pub policy: Policy,
    pub extension: Option<Extension>,
    pub submissions: Vec<SubmissionSummary>,
}

pub async fn student(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab, student)): Path<(String, String, String)>,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let lab = known_lab(&lab)?;
    let missing = Error::NotFound(format!("{course} has no student {student:?}"));
    let answer = blocking(&state, move |store| {
        let Some(member) = store.student(&course, &student)? else {
            return Ok(None);
        };
        let Some(policy) = store.policy_for(&course, lab, member.id)? else {
            return Ok(None);
        };
        let extension = store.extension_for(&course, lab, member.id)?;
        Ok(Some(StudentAnswer {
            submissions: store.history(member.id, lab)?,
            member,
            policy,
            extension,
        }))
    })
    .await?
    .ok_or(missing)?;
    Ok(Json(answer).into_response())
}

/// The body of `POST /api/courses/{course}/regrades`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RegradeRequest {
    #[serde(default = "super::default_lab")]
    lab: String,
    scope: Scope,
}

#[derive(Serialize, TS)]
pub(super) struct RegradeStarted {
    id: i64,
    total: usize,
    url: String,
}

/// `POST /api/courses/{course}/regrades`: grades again, in the background, with the
/// grader as it is now; answers at once with where to follow it.
pub async fn start_regrade(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(course): Path<String>,
    body: Body,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let request: RegradeRequest = body.json(&viewer, "the regrade request").await?;
    let exercise = lab_field(&request.lab)?;
    let who = viewer.actor();
    let now = state.clock.now();
    let grader = state.grader.version(exercise).to_string();
    let url_course = course.clone();
    let (id, total) = blocking(&state, move |store| {
        let started = store.start_regrade(&course, exercise, &request.scope, &who, &grader, now)?;
        store.audit(
            &course,
            &who,
            "regrade",
            &format!(
                "{} of {}: {} submission(s) with {grader}",
                describe(&request.scope),
                request.lab,
                started.1
            ),
            now,
        )?;
        Ok(started)
    })
    .await?;
    state.grader.regrade_started();
    let url = format!("/api/courses/{url_course}/regrades/{id}");
    Ok((
        StatusCode::ACCEPTED,
        [(header::LOCATION, url.clone())],
        Json(RegradeStarted { id, total, url }),
    )
        .into_response())
}

fn describe(scope: &Scope) -> String {
    match scope {
        Scope::Submission(id) => format!("submission {id}"),
        Scope::Student(login) => format!("every submission of {login}"),
        Scope::Students(logins) => format!("every submission of {}", logins.join(", ")),
        Scope::Assignment => "every submission".into(),
    }
}

/// `GET /api/courses/{course}/regrades/{id}`: its progress and the scores it changed.
pub async fn regrade(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, id)): Path<(String, String)>,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let missing = Error::NotFound(format!("there is no regrade {id:?}"));
    let Ok(number) = id.parse::<i64>() else {
        return Err(missing);
    };
    let found = blocking(&state, move |store| store.regrade(&course, number))
        .await?
        .ok_or(missing)?;
    Ok(Json(found).into_response())
}

/// The body of `POST /api/courses/{course}/extensions`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ExtensionRequest {
    #[serde(default = "super::default_lab")]
    lab: String,
    student: String,
    due: String,
    cutoff: Option<String>,
}

/// `POST /api/courses/{course}/extensions`: new dates for one student, recorded with who
/// granted them; answers with the extension and the scores of the submissions already
/// made that it changed (they are judged against the new dates).
pub async fn extend(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(course): Path<String>,
    body: Body,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let request: ExtensionRequest = body.json(&viewer, "the extension request").await?;
    let exercise = lab_field(&request.lab)?;
    let due =
        parse_moment(&request.due).map_err(|e| Error::BadRequest(format!("field `due`: {e}")))?;
    let cutoff = match &request.cutoff {
        Some(text) => {
            parse_moment(text).map_err(|e| Error::BadRequest(format!("field `cutoff`: {e}")))?
        }
        None => due,
    };
    if cutoff < due {
        return Err(Error::BadRequest(
            "field `cutoff`: before `due`; the cutoff is the last moment a late submission is taken".into(),
        ));
    }
    let who = viewer.actor();
    let now = state.clock.now();
    let granted = blocking(&state, move |store| {
        let grant = NewExtension {
            lab: exercise,
            student: &request.student,
            due,
            cutoff,
        };
        store.grant_extension(&course, &grant, &who, now)
    })
    .await?;
    Ok(Json(granted).into_response())
}

/// The body of `POST /api/courses/{course}/submissions/{id}/waiver`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct WaiverRequest {
    reason: String,
}

/// The longest reason a waiver keeps: a sentence or two for the audit log and the student.
const MAX_REASON: usize = 500;

/// `POST /api/courses/{course}/submissions/{id}/waiver`: waives one submission's late
/// penalty, with the reason (shown to the student and logged); answers with the
/// submission as it counts now and the score that changed. A submission of another course
/// (or none) is the same 404.
pub async fn waive(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, id)): Path<(String, String)>,
    body: Body,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let missing = Error::NotFound(format!("{course} has no submission {id:?}"));
    let Ok(submission) = id.parse::<i64>() else {
        return Err(missing);
    };
    let request: WaiverRequest = body.json(&viewer, "the waiver request").await?;
    let reason = request.reason.trim().to_string();
    if reason.is_empty() || reason.chars().count() > MAX_REASON {
        return Err(Error::BadRequest(format!(
            "field `reason`: say why the penalty is waived, in at most {MAX_REASON} characters"
        )));
    }
    let who = viewer.actor();
    let now = state.clock.now();
    let waived = blocking(&state, move |store| {
        let waiver = NewWaiver {
            submission,
            reason: &reason,
        };
        store.waive(&course, &waiver, &who, now)
    })
    .await?
    .ok_or(missing)?;
    Ok(Json(waived).into_response())
}

/// `GET /api/courses/{course}/audit`: every staff action, newest first.
pub async fn audit(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(course): Path<String>,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let log: Vec<AuditEntry> = blocking(&state, move |store| store.audit_log(&course)).await?;
    Ok(Json(log).into_response())
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExportQuery {
    format: Format,
}

/// `GET /api/courses/{course}/labs/{lab}/export?format=csv|xlsx|gradescope|prairielearn|sources`.
pub async fn export(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
    Query(query): Query<ExportQuery>,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let exercise = known_lab(&lab)?;
    let name = query.format.file_name(&course, &lab);
    let bytes = blocking(&state, move |store| {
        export::make(store, &course, exercise, query.format)
    })
    .await?
    .ok_or_else(|| Error::NotFound("the course has not opened this exercise".into()))?;
    Ok((
        [
            (
                header::CONTENT_TYPE,
                query.format.content_type().to_string(),
            ),
            (
                header::CONTENT_DISPOSITION,
                format!("attachment; filename=\"{name}\""),
            ),
        ],
        bytes,
    )
        .into_response())
}

#[derive(Template)]
#[template(path = "dashboard.html")]
struct Dashboard<'a> {
    page: &'a str,
    assets: super::assets::PageAssets<'a>,
    nav: Nav,
    course: String,
    lab: String,
    /// A student's page when set.
    student: Option<String>,
    /// Whether the exercise asks for a report (the class's and each student's linked).
    report: bool,
}

impl Dashboard<'_> {
    /// Every language a file may be written in, for the assignment's choice.
    fn languages(&self) -> &'static [Language] {
        Language::ALL
    }
}

async fn dashboard_page(
    state: &Arc<AppState>,
    viewer: &Viewer,
    course: String,
    lab: String,
    student: Option<String>,
) -> Result<Response, Error> {
    if matches!(viewer, Viewer::Anonymous) {
        return Ok(Redirect::to("/signin").into_response());
    }
    viewer.staff_of(&course)?;
    let exercise = known_lab(&lab)?;
    html(&Dashboard {
        page: "dashboard",
        assets: state.assets.page("dashboard"),
        nav: Nav::of(state, viewer).await?,
        course,
        lab,
        student,
        report: !exercise.declaration().report.is_empty(),
    })
}

/// `GET /courses/{course}/{lab}`: the class at a glance.
pub async fn page(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
) -> Result<Response, Error> {
    dashboard_page(&state, &viewer, course, lab, None).await
}

/// `GET /courses/{course}/{lab}/students/{student}`: one student's submissions.
pub async fn student_page(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab, student)): Path<(String, String, String)>,
) -> Result<Response, Error> {
    dashboard_page(&state, &viewer, course, lab, Some(student)).await
}
