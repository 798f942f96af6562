//! The report: a student's runs of their own code on the whole data sets, their analyses
//! beside them and their answers, handed in and judged by staff part by part
//! (`courses::report`).
//!
//! - `GET /courses/{course}/{lab}/report`: the page (a student's own; staff's list of the
//!   class, and any student's report with `?student=ID`)
//! - `GET /api/courses/{course}/labs/{lab}/report`, `GET .../report/runs` (students)
//! - `POST .../report/analyses`, `POST .../report/hand-in` (students)
//! - `GET /api/courses/{course}/labs/{lab}/reports` (staff: the class)
//! - `GET .../reports/{student}`, `GET .../reports/{student}/runs`,
//!   `POST .../reports/{student}/rubric` (staff)
//!
//! Anyone outside the course gets the 404 of a course that does not exist.

use super::extract::Body;
use super::pages::{Nav, html};
use super::viewer::Viewer;
use super::{AppState, Error, blocking, known_lab};
use crate::courses::class::counting;
use crate::courses::export::HandIn;
use crate::courses::questions::{self, QuestionSet};
use crate::courses::report::{self, Part, PartMark, State as ReportState, Stored};
use crate::courses::rounds::Tally;
use crate::grading::Tenant;
use crate::sandbox::Tried;
use crate::store::{Closed, Member, ReportMaking, Role, SavedAnswer, Store, SubmissionSummary};
use askama::Template;
use axum::Json;
use axum::extract::{Path, State};
use axum::response::{IntoResponse, Redirect, Response};
use jiff::Timestamp;
use labs::grading::Outputs;
use labs::{Exercise, Language};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::value::RawValue;
use std::collections::BTreeMap;
use std::sync::Arc;
use ts_rs::TS;

/// The submission whose runs a report shows.
#[derive(Clone, Serialize, TS)]
pub struct ShownSubmission {
    pub id: i64,
    pub language: Language,
    /// The variant whose data sets it runs on.
    #[ts(type = "number")]
    pub seed: u64,
    pub submitted_at: String,
    pub score: Option<f64>,
}

/// What `GET .../report` and `GET .../reports/{student}` answer.
#[derive(Serialize, TS)]
pub struct ReportView {
    pub lab: Exercise,
    pub student: String,
    pub name: String,
    /// Whether staff read it (the sets in full; the rubric theirs to give).
    pub staff: bool,
    pub parts: Vec<Part>,
    /// The assignment's question sets, without what they are checked against for the
    /// student; in full for staff.
    pub sets: Vec<QuestionSet>,
    /// The student's answers: as they stand (corrected after the review) while the
    /// student writes; as handed in once it is, and for staff.
    pub answers: Vec<SavedAnswer>,
    /// The student's analysis of each run, by run name: the same.
    pub analyses: BTreeMap<String, String>,
    /// Whether the student may change it now (write, hand in).
    pub may_change: bool,
    pub state: ReportState,
    /// How many times it was handed in (the rubric names the hand-in it judges).
    pub handed_in: u32,
    #[ts(as = "Option<String>")]
    pub handed_in_at: Option<Timestamp>,
    /// Handed in: the submission it was handed in with; else the student's latest.
    pub submission: Option<ShownSubmission>,
    /// Staff's last judgement, with the hand-in it judged.
    pub rubric: Vec<PartMark>,
    pub reviewed: Option<u32>,
    pub reviewed_by: Option<String>,
    #[ts(as = "Option<String>")]
    pub reviewed_at: Option<Timestamp>,
    /// The score of the submission that counts (best or last, by the assignment).
    pub counting_score: Option<f64>,
    /// Whether the submission that counts passes every test.
    pub code_passes: bool,
    /// The code passes and the report is accepted.
    pub lab_passed: bool,
    /// The last moment a draft is taken (the student's cutoff, extensions counted); a
    /// report sent back for revision is taken after it too.
    #[ts(as = "String")]
    pub cutoff: Timestamp,
}

fn shown(summary: &SubmissionSummary, seed: u64) -> ShownSubmission {
    ShownSubmission {
        id: summary.id,
        language: summary.language,
        seed,
        submitted_at: summary.submitted_at.clone(),
        score: summary.score,
    }
}

/// The submission whose runs a report shows: the one handed in while staff read it or
/// have accepted it; else the student's latest (`history`, oldest first).
fn shown_submission(stored: &Stored, history: &[SubmissionSummary]) -> Option<i64> {
    match stored.state() {
        ReportState::HandedIn | ReportState::Accepted => stored.submission,
        ReportState::Draft | ReportState::Revise => history.last().map(|s| s.id),
    }
}

/// The report of `member` (a student of their course) at `now`, as `staff` or the
/// student reads it; none when the course has not opened the exercise.
fn report_view(
    store: &Store,
    member: &Member,
    lab: Exercise,
    staff: bool,
    now: Timestamp,
) -> Result<Option<ReportView>, crate::store::Error> {
    let Some(policy) = store.policy_for(&member.course, lab, member.id)? else {
        return Ok(None);
    };
    let sets = questions::of_assignment(store, &member.course, lab)?;
    let stored = store.report(member.id, lab)?.unwrap_or_default();
    let history = store.history(member.id, lab)?;
    let state = stored.state();
    let submission = match shown_submission(&stored, &history) {
        Some(id) => store.get(id, false)?.map(|s| shown(&s.summary, s.seed)),
        None => None,
    };
    let counting_score = counting(&policy, &history).and_then(|s| s.score);
    // What was handed in, for staff and for a report not open to its student; else the
    // student's own as they write.
    let handed = stored.handed_in > 0 && (staff || !state.open_to_student());
    let Stored {
        analyses,
        handed_in,
        handed_in_at,
        handed_analyses,
        handed_answers,
        rubric,
        reviewed,
        reviewed_by,
        reviewed_at,
        ..
    } = stored;
    let mut view = ReportView {
        lab,
        student: member.login.clone(),
        name: member.name.clone(),
        staff,
        parts: report::parts(lab, &sets),
        sets: if staff {
            sets
        } else {
            sets.iter().map(QuestionSet::for_students).collect()
        },
        answers: if handed {
            handed_answers
        } else {
            store.answers(member.id, lab)?
        },
        analyses: if handed { handed_analyses } else { analyses },
        may_change: false,
        state,
        handed_in,
        handed_in_at,
        submission,
        rubric,
        reviewed,
        reviewed_by,
        reviewed_at,
        counting_score,
        code_passes: report::code_passes(counting_score),
        lab_passed: report::lab_passed(counting_score, state),
        cutoff: policy.cutoff,
    };
    view.may_change = !staff && closed_to_student(member, &view, now).is_none();
    Ok(Some(view))
}

/// The exercise, when it asks for a report.
fn reported_lab(lab: &str) -> Result<Exercise, Error> {
    let exercise = known_lab(lab)?;
    if exercise.declaration().report.is_empty() {
        return Err(Error::NotFound(format!(
            "{} asks for no report",
            exercise.declaration().title
        )));
    }
    Ok(exercise)
}

/// The signed-in student of `course`; staff are told that reports are their students';
/// anyone else gets the 404 of a course that does not exist.
fn student_of(viewer: &Viewer, course: &str) -> Result<Member, Error> {
    match viewer.member() {
        Some(member) if member.course == course && member.role == Role::Student => {
            Ok(member.clone())
        }
        _ if viewer.is_staff_of(course) => Err(Error::Forbidden(
            "staff write no report: read your students' at .../reports/{student}".into(),
        )),
        _ => Err(Error::NotFound(format!("there is no course {course:?}"))),
    }
}

/// The student `login` of `course`, for its staff; the 404 of a course that does not
/// exist for anyone else, and of a student that does not exist for staff.
fn student_for_staff(
    store: &Store,
    course: &str,
    login: &str,
) -> Result<Result<Member, Error>, crate::store::Error> {
    let student = store.student(course, login)?;
    Ok(student.ok_or_else(|| Error::NotFound(format!("{course} has no student {login:?}"))))
}

fn not_opened() -> Error {
    Error::NotFound("the course has not opened this exercise".into())
}

/// `GET .../report`: the student's own report.
pub async fn mine(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
) -> Result<Response, Error> {
    let exercise = reported_lab(&lab)?;
    let member = student_of(&viewer, &course)?;
    let now = state.clock.now();
    let view = blocking(&state, move |store| {
        report_view(store, &member, exercise, false, now)
    })
    .await?
    .ok_or_else(not_opened)?;
    Ok(Json(view).into_response())
}

/// `GET .../reports/{student}`: a student's report, for staff.
pub async fn of_student(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab, student)): Path<(String, String, String)>,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let exercise = reported_lab(&lab)?;
    let now = state.clock.now();
    let view = blocking(&state, move |store| {
        let member = match student_for_staff(store, &course, &student)? {
            Ok(member) => member,
            Err(error) => return Ok(Err(error)),
        };
        Ok(report_view(store, &member, exercise, true, now)?.ok_or_else(not_opened))
    })
    .await??;
    Ok(Json(view).into_response())
}

/// One student's line of the class's reports.
#[derive(Serialize, TS)]
pub struct ReportLine {
    pub student: String,
    pub name: String,
    pub dropped: bool,
    /// The score of the submission that counts.
    pub score: Option<f64>,
    /// Their sheet's tally in the latest closed review round of each set that has one.
    pub reviews: Vec<SetReview>,
    pub state: ReportState,
    pub lab_passed: bool,
}

/// A student's tally in the review of a question set.
#[derive(Serialize, TS)]
pub struct SetReview {
    /// The set's place in the assignment, from 0.
    #[ts(type = "number")]
    pub part: usize,
    /// None when their sheet was not in the round.
    pub tally: Option<Tally>,
}

/// `GET .../reports`: every student's report state, for staff.
pub async fn class(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let exercise = reported_lab(&lab)?;
    let lines = blocking(&state, move |store| {
        let Some(class) = crate::courses::class::load(store, &course, exercise)? else {
            return Ok(None);
        };
        let hand_in = HandIn::load(store, &course, exercise)?;
        let lines = class.students.into_iter().map(|s| {
            let score = s.counting.and_then(|c| c.score);
            let (state, lab_passed) = hand_in
                .report(&s.id, score)
                .unwrap_or((ReportState::Draft, false));
            let reviews = hand_in
                .reviewed
                .parts
                .iter()
                .map(|(part, tallies)| SetReview {
                    part: *part,
                    tally: tallies.get(&s.id).cloned(),
                })
                .collect();
            ReportLine {
                lab_passed,
                student: s.id,
                name: s.name,
                dropped: s.dropped,
                score,
                reviews,
                state,
            }
        });
        Ok(Some(lines.collect::<Vec<_>>()))
    })
    .await?
    .ok_or_else(not_opened)?;
    Ok(Json(lines).into_response())
}

/// The body of `POST .../report/analyses`: the analysis of one run.
#[derive(Deserialize, TS)]
#[serde(deny_unknown_fields)]
pub struct AnalysisRequest {
    /// The run's name (`o3/sequential`).
    pub run: String,
    pub text: String,
}

/// Why a student may not change a report in `state` at all: handed in and not sent back.
fn locked(state: ReportState) -> Option<Error> {
    match state {
        ReportState::HandedIn => Some(Error::Conflict(
            "your report is handed in: it changes again only if staff send it back for revision"
                .into(),
        )),
        ReportState::Accepted => Some(Error::Conflict(
            "your report is accepted: it changes no more".into(),
        )),
        ReportState::Draft | ReportState::Revise => None,
    }
}

/// Why `member` may not change their report now, if they may not: off the roster, handed
/// in and not sent back, or a draft past the cutoff (a report sent back is taken after it).
fn closed_to_student(member: &Member, view: &ReportView, now: Timestamp) -> Option<Error> {
    if member.dropped {
        return Some(Error::Forbidden(format!(
            "you are no longer on the roster of {}: your report is kept as it is",
            member.course
        )));
    }
    locked(view.state).or_else(|| {
        (view.state == ReportState::Draft && now > view.cutoff).then(|| {
            Error::Forbidden(format!(
                "the cutoff of this exercise was {}: reports are no longer taken",
                view.cutoff.strftime("%Y-%m-%d %H:%M UTC")
            ))
        })
    })
}

/// A change the store refused: the report was handed in (or judged) meanwhile.
fn closed(Closed(state): Closed) -> Error {
    locked(state)
        .unwrap_or_else(|| Error::Conflict("the report changed meanwhile: reload it".into()))
}

/// A change of a student's own report: who asks and what they send (`what`, read as `T`)
/// checked, and whether they may change it now; `change` then runs on the store with the
/// report as it stands.
async fn student_change<T, R>(
    state: &Arc<AppState>,
    viewer: &Viewer,
    (course, lab): (String, String),
    (body, what): (Body, &str),
    change: impl FnOnce(&Store, &Member, ReportView, T, Timestamp) -> Changed<R> + Send + 'static,
) -> Result<R, Error>
where
    T: DeserializeOwned + Send + 'static,
    R: Send + 'static,
{
    let exercise = reported_lab(&lab)?;
    let member = student_of(viewer, &course)?;
    let request: T = body.json(viewer, what).await?;
    let now = state.clock.now();
    blocking(state, move |store| {
        let Some(view) = report_view(store, &member, exercise, false, now)? else {
            return Ok(Err(not_opened()));
        };
        if let Some(error) = closed_to_student(&member, &view, now) {
            return Ok(Err(error));
        }
        change(store, &member, view, request, now)
    })
    .await?
}

/// What a change of a report comes to: done, refused, or a fault of the store's.
type Changed<R> = Result<Result<R, Error>, crate::store::Error>;

/// `POST .../report/analyses`: a student's analysis of one run, kept as typed.
pub async fn save_analysis(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(place): Path<(String, String)>,
    body: Body,
) -> Result<Response, Error> {
    let what = (body, "the analysis");
    student_change(
        &state,
        &viewer,
        place,
        what,
        |store, member, view, request: AnalysisRequest, now| {
            if let Err(problem) = report::check_analysis(&view.parts, &request.run, &request.text) {
                return Ok(Err(Error::BadRequest(problem)));
            }
            let saved =
                store.save_analysis(member.id, view.lab, &request.run, &request.text, now)?;
            Ok(saved.map_err(closed))
        },
    )
    .await?;
    Ok(axum::http::StatusCode::NO_CONTENT.into_response())
}

/// The body of `POST .../report/hand-in`.
#[derive(Deserialize, TS)]
#[serde(deny_unknown_fields)]
pub struct HandInRequest {
    /// The submission whose runs the student read (`ReportView::submission`): a later one
    /// is not handed in unread.
    pub submission: i64,
}

/// `POST .../report/hand-in`: hands the report in with the runs of the student's latest
/// submission (the one they read), its analyses and their answers as they are now.
pub async fn hand_in(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path(place): Path<(String, String)>,
    body: Body,
) -> Result<Response, Error> {
    let what = (body, "the hand-in");
    let view = student_change(&state, &viewer, place, what, |store, member, view, request: HandInRequest, now| {
        let Some(submission) = view.submission else {
            return Ok(Err(Error::Conflict(
                "submit your code first: the report shows the runs of your latest submission"
                    .into(),
            )));
        };
        if submission.id != request.submission {
            return Ok(Err(Error::Conflict(format!(
                "field `submission`: your latest submission is {}, not {}: read its runs, then hand in",
                submission.id, request.submission
            ))));
        }
        let answers = store.answers(member.id, view.lab)?;
        let handed = (submission.id, answers.as_slice());
        if let Err(closed_now) = store.hand_in_report(member.id, view.lab, handed, now)? {
            return Ok(Err(closed(closed_now)));
        }
        Ok(report_view(store, member, view.lab, false, now)?.ok_or_else(not_opened))
    })
    .await?;
    Ok(Json(view).into_response())
}

/// The body of `POST .../reports/{student}/rubric`.
#[derive(Deserialize, TS)]
#[serde(deny_unknown_fields)]
pub struct RubricRequest {
    /// The hand-in judged (`ReportView::handed_in` as read): a later one is not judged
    /// unread.
    pub handed_in: u32,
    pub parts: Vec<PartMark>,
}

/// `POST .../reports/{student}/rubric`: staff judge the hand-in they read, every part
/// pass or revise with a comment; logged.
pub async fn rubric(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab, student)): Path<(String, String, String)>,
    body: Body,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let exercise = reported_lab(&lab)?;
    let request: RubricRequest = body.json(&viewer, "the rubric").await?;
    let actor = viewer.actor();
    let now = state.clock.now();
    let view = blocking(&state, move |store| {
        let member = match student_for_staff(store, &course, &student)? {
            Ok(member) => member,
            Err(error) => return Ok(Err(error)),
        };
        let Some(view) = report_view(store, &member, exercise, true, now)? else {
            return Ok(Err(not_opened()));
        };
        let marks = match report::check_rubric(&view.parts, request.parts) {
            Ok(marks) => marks,
            Err(problem) => return Ok(Err(Error::BadRequest(problem))),
        };
        let judged = (actor.as_str(), now);
        let judging = (request.handed_in, marks.as_slice());
        let reviewed = match store.review_report(member.id, exercise, judging, judged)? {
            Ok(reviewed) => reviewed,
            Err(Closed(ReportState::Draft)) => {
                return Ok(Err(Error::Conflict(format!(
                    "{student} has not handed in the report: there is nothing to judge"
                ))));
            }
            Err(_) if request.handed_in < view.handed_in => {
                return Ok(Err(Error::Conflict(format!(
                    "field `handed_in`: {student} has handed in the report again since (hand-in {}, not {}): read it anew",
                    view.handed_in, request.handed_in
                ))));
            }
            Err(_) => {
                return Ok(Err(Error::BadRequest(format!(
                    "field `handed_in`: {} is not a hand-in of {student}'s, whose latest is {}",
                    request.handed_in, view.handed_in
                ))));
            }
        };
        store.audit(
            &course,
            &actor,
            "report",
            &format!(
                "{exercise}: {student}'s report (hand-in {}) {}",
                request.handed_in,
                reviewed.state().name()
            ),
            now,
        )?;
        Ok(report_view(store, &member, exercise, true, now)?.ok_or_else(not_opened))
    })
    .await??;
    Ok(Json(view).into_response())
}

/// The runs of a report, as `GET .../report/runs` answers while they are made and once
/// they are.
#[derive(Serialize, TS)]
#[serde(tag = "state", rename_all = "snake_case")]
pub enum ReportRuns {
    /// No submission yet: nothing to run.
    NoSubmission,
    /// The server is running the student's code on the whole data sets: ask again.
    Making { submission: i64 },
    /// The harness's outputs of every run of the report (sent as they were kept).
    Made {
        submission: i64,
        #[ts(as = "Outputs")]
        outputs: Box<RawValue>,
    },
    /// The server could not run the code (its own fault, or a language it cannot run):
    /// asking again tries again.
    Failed { submission: i64, reason: String },
}

/// The runs of the report of `member`: made once a submission (in the background, the
/// first time they are asked for) and kept.
async fn runs_of(
    state: &Arc<AppState>,
    member: Member,
    lab: Exercise,
) -> Result<ReportRuns, Error> {
    let grader = state.grader.version(lab).to_owned();
    let student = member.id;
    let tenant = Tenant::Student {
        course: member.course.clone(),
        student: member.login.clone(),
    };
    let found = blocking(state, move |store| {
        if store.policy_for(&member.course, lab, member.id)?.is_none() {
            return Ok(Err(not_opened()));
        }
        let stored = store.report(member.id, lab)?.unwrap_or_default();
        let history = store.history(member.id, lab)?;
        let Some(submission) = shown_submission(&stored, &history) else {
            return Ok(Ok((None, None)));
        };
        let made = store.report_runs(submission, &grader)?;
        Ok(Ok((Some(submission), made)))
    })
    .await??;
    let (Some(submission), made) = found else {
        return Ok(ReportRuns::NoSubmission);
    };
    if let Some(outputs) = made {
        return Ok(ReportRuns::Made {
            submission,
            outputs,
        });
    }
    let grader = Arc::clone(&state.grader);
    let making = blocking(state, move |store| {
        store.begin_report_making(student, submission, &grader.lease())
    })
    .await?;
    match making {
        ReportMaking::Failed(reason) => Ok(ReportRuns::Failed { submission, reason }),
        // A student's next submission waits until their last is made (asked again then).
        ReportMaking::Running { .. } => Ok(ReportRuns::Making { submission }),
        ReportMaking::Yours => {
            tokio::spawn(make_runs(
                Arc::clone(state),
                (student, tenant, submission),
                lab,
            ));
            Ok(ReportRuns::Making { submission })
        }
    }
}

/// Why a report's runs are not made on a server where the submission's language does not run.
const UNAVAILABLE: &str =
    "files in this language cannot be run on this server: its sandbox for them does not start here";

/// Runs a submission's code on the whole data sets of its report's runs, in the student's
/// turn with the rest of the sandbox's work (`Grader::report_runs`), renewing its lease
/// meanwhile, and keeps the outputs (unless another ask made them meanwhile); a failure of
/// the server's is kept to be told once, in words for the student (the log has the
/// detail). Whose runs are being made (one student's at a time, under the lease of the
/// process making them) and why a try failed are the database's (`store::ReportMaking`),
/// so that every web process answers a student alike and a process that died leaves the
/// making to another.
async fn make_runs(
    state: Arc<AppState>,
    (student, tenant, submission): (i64, Tenant, i64),
    lab: Exercise,
) {
    let grader = state.grader.version(lab).to_owned();
    let made = async {
        let made_by = grader.clone();
        let stored = blocking(&state, move |store| {
            if store.report_runs(submission, &made_by)?.is_some() {
                return Ok(None);
            }
            store.get(submission, true)
        })
        .await
        .map_err(|e| e.to_string())?;
        let Some(stored) = stored else {
            return Ok(());
        };
        let runs: Vec<&str> = lab.declaration().report.iter().map(|r| r.run).collect();
        let code = (stored.summary.language, stored.source.unwrap_or_default());
        let outputs = state
            .grader
            .report_runs(tenant, lab, code, stored.seed, runs)
            .await
            .map_err(|tried| match tried {
                Tried::Unavailable(_) => format!("{UNAVAILABLE}: {tried}"),
                other => other.to_string(),
            })?;
        blocking(&state, move |store| {
            store.keep_report_runs(submission, &grader, &outputs)
        })
        .await
        .map_err(|e| e.to_string())
    };
    tokio::pin!(made);
    let every = state.grader.lease().length / 3;
    let made = loop {
        tokio::select! {
            made = &mut made => break made,
            () = tokio::time::sleep(every) => {
                let grader = Arc::clone(&state.grader);
                let renewed = blocking(&state, move |store| {
                    store.renew_report_making(student, &grader.lease())
                })
                .await;
                if !matches!(renewed, Ok(true)) {
                    tracing::warn!(submission, "the making of a report's runs lost its lease");
                }
            }
        }
    };
    let failed = made.err().map(|detail| {
        tracing::warn!(submission, %detail, "a report's runs were not made");
        if detail.starts_with(UNAVAILABLE) {
            UNAVAILABLE
        } else {
            "the server could not run the code this time (its sandbox failed: not the code's doing)"
        }
    });
    let grader = Arc::clone(&state.grader);
    let ended = blocking(&state, move |store| {
        store.end_report_making(student, grader.lease().holder, failed)
    })
    .await;
    if let Err(err) = ended {
        tracing::warn!(
            submission,
            "the making of a report's runs could not be ended: {err}"
        );
    }
}

/// `GET .../report/runs`: the runs of the student's own report.
pub async fn my_runs(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
) -> Result<Response, Error> {
    let exercise = reported_lab(&lab)?;
    let member = student_of(&viewer, &course)?;
    Ok(Json(runs_of(&state, member, exercise).await?).into_response())
}

/// `GET .../reports/{student}/runs`: the runs of a student's report, for staff.
pub async fn student_runs(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab, student)): Path<(String, String, String)>,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let exercise = reported_lab(&lab)?;
    let member = blocking(&state, move |store| {
        student_for_staff(store, &course, &student)
    })
    .await??;
    Ok(Json(runs_of(&state, member, exercise).await?).into_response())
}

#[derive(Template)]
#[template(path = "report.html")]
struct ReportPage<'a> {
    page: &'a str,
    assets: super::assets::PageAssets<'a>,
    nav: Nav,
    course: String,
    lab: Exercise,
    folder: &'static str,
    title: &'static str,
    /// Whether staff read it: the class's reports, and any student's.
    staff: bool,
}

/// `GET /courses/{course}/{lab}/report`: the report page, for the course's people; anyone
/// signed out is sent to sign in, anyone else gets the 404 of a course that does not
/// exist.
pub async fn page(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
) -> Result<Response, Error> {
    if matches!(viewer, Viewer::Anonymous) {
        return Ok(Redirect::to("/signin").into_response());
    }
    if !viewer.of_course(&course) {
        return Err(Error::NotFound(format!("there is no course {course:?}")));
    }
    let exercise = reported_lab(&lab)?;
    let staff = viewer.is_staff_of(&course);
    html(&ReportPage {
        page: "report",
        assets: state.assets.page("report"),
        nav: Nav::of(&state, &viewer).await?,
        course,
        lab: exercise,
        folder: exercise.folder(),
        title: exercise.declaration().title,
        staff,
    })
}
