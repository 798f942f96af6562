//! The signed-in person's side: `/me` (a student's assignments with their deadlines,
//! scores and history; a member of staff's course at a glance) and the API behind it.

use super::extract::Query;
use super::pages::{Nav, html};
use super::viewer::Viewer;
use super::{AppState, Error, blocking, lab_field};
use crate::courses::challenge::{self, StudentChallenge};
use crate::courses::deadline::{Policy, Timing, span};
use crate::store::{
    Assignment, Course, Extension, Member, Status, Store, Submission, SubmissionSummary,
};
use askama::Template;
use axum::Json;
use axum::extract::State;
use axum::response::{IntoResponse, Redirect, Response};
use jiff::Timestamp;
use labs::Exercise;
use labs::grading::student_seed;
use serde::{Deserialize, Serialize};
use std::collections::HashSet;
use std::sync::Arc;
use ts_rs::TS;

/// Where an assignment stands at the moment of asking.
#[derive(Serialize, TS)]
#[serde(rename_all = "snake_case", tag = "state")]
pub enum Standing {
    /// Before the due date.
    Open {
        seconds_left: i64,
    },
    /// After the due date, before the cutoff: a submission now is late by
    /// `late_seconds` and loses `penalty` of its score.
    Late {
        late_seconds: i64,
        penalty: f64,
        seconds_to_cutoff: i64,
    },
    Closed,
}

impl Standing {
    pub fn of(policy: &Policy, now: Timestamp) -> Standing {
        match policy.timing(now) {
            Timing::OnTime => Standing::Open {
                seconds_left: policy.due.duration_since(now).as_secs(),
            },
            Timing::Late { seconds, penalty } => Standing::Late {
                late_seconds: seconds,
                penalty,
                seconds_to_cutoff: policy.cutoff.duration_since(now).as_secs(),
            },
            Timing::Closed => Standing::Closed,
        }
    }

    /// The standing in words, for the page.
    pub fn describe(&self) -> String {
        match self {
            Standing::Open { seconds_left } => format!("due in {}", span(*seconds_left)),
            Standing::Late {
                late_seconds,
                penalty,
                seconds_to_cutoff,
            } => format!(
                "{} late: a submission now loses {:.0} % of its score; closes in {}",
                span(*late_seconds),
                penalty * 100.0,
                span(*seconds_to_cutoff)
            ),
            Standing::Closed => "closed: no more submissions are taken".into(),
        }
    }
}

/// A student's view of one assignment.
#[derive(Serialize, TS)]
pub struct StudentAssignment {
    #[serde(flatten)]
    pub assignment: Assignment,
    /// Its exercise (`assignment.lab`, by name).
    #[serde(skip)]
    pub exercise: Exercise,
    /// The path of its exercise's workbench, where the student writes, tests and submits
    /// their file, and opens a submission (`?submission=ID`).
    pub workbench: &'static str,
    pub standing: Standing,
    /// Their own dates, when staff extended the assignment's (`assignment.policy` has
    /// them): their submissions, those already made included, are judged by them.
    pub extension: Option<Extension>,
    /// Their submissions, oldest first, each judged by the dates in force.
    pub history: Vec<SubmissionSummary>,
    /// The score that counts (best or last, after late penalties).
    pub counting_score: Option<f64>,
    /// Their standing in the class challenge, where the exercise has one and the
    /// submission that counts ran it.
    pub challenge: Option<StudentChallenge>,
    /// Their latest submission with its full result.
    pub latest: Option<Submission>,
}

/// A member of staff's view of one assignment.
#[derive(Serialize, TS)]
pub struct StaffAssignment {
    #[serde(flatten)]
    pub assignment: Assignment,
    pub standing: Standing,
    /// Students on the roster (not dropped).
    pub students: usize,
    /// Of them, those who have submitted at least once.
    pub submitted: usize,
    pub submissions: usize,
}

/// `GET /api/me`: who is signed in and what they have to do.
#[derive(Serialize, TS)]
pub struct About {
    /// Whether the server has courses (without, submitting is open to anyone).
    pub courses: bool,
    pub member: Option<Member>,
    pub course: Option<Course>,
    /// A student's variant.
    pub seed: Option<u64>,
    pub assignments: Vec<StudentAssignment>,
    pub staff_assignments: Vec<StaffAssignment>,
}

fn gather(
    store: &Store,
    viewer_member: Option<Member>,
    now: Timestamp,
) -> Result<About, crate::store::Error> {
    let courses = store.any_course()?;
    let Some(member) = viewer_member else {
        return Ok(About {
            courses,
            member: None,
            course: None,
            seed: None,
            assignments: Vec::new(),
            staff_assignments: Vec::new(),
        });
    };
    let course = store.course(&member.course)?;
    let mut assignments = Vec::new();
    let mut staff_assignments = Vec::new();
    for assignment in store.assignments(&member.course)? {
        let standing = Standing::of(&assignment.policy, now);
        if member.role.is_staff() {
            let members = store.members(&member.course)?;
            let roster: HashSet<&str> = members
                .iter()
                .filter(|m| !m.role.is_staff() && !m.dropped)
                .map(|m| m.login.as_str())
                .collect();
            let submissions = store.course_submissions(&member.course, assignment.lab)?;
            let submitted: HashSet<&str> = submissions
                .iter()
                .map(|s| s.student.as_str())
                .filter(|s| roster.contains(s))
                .collect();
            staff_assignments.push(StaffAssignment {
                standing,
                students: roster.len(),
                submitted: submitted.len(),
                submissions: submissions.len(),
                assignment,
            });
        } else {
            let exercise = assignment.lab;
            let mut assignment = assignment;
            if let Some(policy) = store.policy_for(&member.course, exercise, member.id)? {
                assignment.policy = policy;
            }
            let standing = Standing::of(&assignment.policy, now);
            let extension = store.extension_for(&member.course, exercise, member.id)?;
            let history = store.history(member.id, exercise)?;
            let counting_score = assignment
                .policy
                .counts
                .choose(history.iter(), |s| s.final_score)
                .and_then(|s| s.final_score);
            let own: Vec<&SubmissionSummary> = history.iter().collect();
            let figured = challenge::counting(&own, assignment.policy.counts)
                .filter(|s| s.challenge.is_some());
            let challenge = match figured {
                Some(counting) => challenge_standing(store, &member, &assignment, counting.id)?,
                None => None,
            };
            let latest = match history.last() {
                Some(last) => store
                    .get(last.id, false)?
                    .map(|latest| {
                        Ok::<_, crate::store::Error>(Submission {
                            earlier: store.earlier_results(last.id)?,
                            ..latest
                        })
                    })
                    .transpose()?,
                None => None,
            };
            assignments.push(StudentAssignment {
                assignment,
                exercise,
                workbench: super::workbench_path(exercise),
                standing,
                extension,
                history,
                counting_score,
                challenge,
                latest,
            });
        }
    }
    Ok(About {
        courses,
        seed: (!member.role.is_staff()).then(|| student_seed(&member.course, &member.login)),
        member: Some(member),
        course: Some(course),
        assignments,
        staff_assignments,
    })
}

/// A student's standing in the class challenge of `assignment`, where `counting` (the id
/// of their submission whose figure counts) has a figure: their rank among the class's.
fn challenge_standing(
    store: &Store,
    member: &Member,
    assignment: &Assignment,
    counting: i64,
) -> Result<Option<StudentChallenge>, crate::store::Error> {
    let Some(result) = store.results(&[counting])?.remove(&counting) else {
        return Ok(None);
    };
    let members = store.members(&member.course)?;
    let submissions = store.course_submissions(&member.course, assignment.lab)?;
    let (ranking, _) = challenge::ranking(&members, &submissions, assignment.policy.counts);
    Ok(challenge::standing(
        &result,
        &ranking,
        &member.login,
        assignment.ranked,
    ))
}

async fn load(state: &AppState, viewer: &Viewer) -> Result<About, Error> {
    let member = viewer.member().cloned();
    let now = state.clock.now();
    blocking(state, move |store| gather(store, member, now)).await
}

/// `GET /api/me`.
pub async fn about(State(state): State<Arc<AppState>>, viewer: Viewer) -> Result<Response, Error> {
    Ok(Json(load(&state, &viewer).await?).into_response())
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HistoryQuery {
    #[serde(default = "super::default_lab")]
    lab: String,
}

/// `GET /api/me/submissions?lab=...`: the signed-in student's own submissions.
pub async fn history(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Query(query): Query<HistoryQuery>,
) -> Result<Response, Error> {
    let Some(member) = viewer.member().cloned() else {
        return Err(Error::Unauthorized(
            "sign in to see your submissions".into(),
        ));
    };
    let lab = lab_field(&query.lab)?;
    let list = blocking(&state, move |store| store.history(member.id, lab)).await?;
    Ok(Json(list).into_response())
}

#[derive(Template)]
#[template(path = "me.html")]
struct MePage<'a> {
    page: &'a str,
    assets: super::assets::PageAssets<'a>,
    nav: Nav,
    about: About,
    member: Member,
}

impl MePage<'_> {
    fn standing(&self, standing: &Standing) -> String {
        standing.describe()
    }

    fn score(&self, score: &Option<f64>) -> String {
        score.map_or_else(|| "–".into(), |s| format!("{:.0} %", s * 100.0))
    }

    /// A figure of the class challenge, with four decimals.
    fn figure(&self, value: &f64) -> String {
        format!("{value:.4}")
    }

    fn percent(&self, share: &f64) -> String {
        format!("{:.0} %", share * 100.0)
    }

    fn moment(&self, at: &Timestamp) -> String {
        at.strftime("%Y-%m-%d %H:%M UTC").to_string()
    }

    /// A submission's lateness by the dates in force, with its penalty or its waiver.
    fn lateness(&self, submission: &SubmissionSummary) -> String {
        if submission.late_seconds == 0 {
            return "on time".into();
        }
        let late = format!("{} late", span(submission.late_seconds));
        match &submission.waiver {
            Some(waiver) => format!("{late}, penalty waived: {}", waiver.reason),
            None => format!("{late} (−{})", self.percent(&submission.penalty)),
        }
    }

    fn status(&self, status: &Status) -> &'static str {
        match status {
            Status::Queued => "waiting",
            Status::Grading => "being graded",
            Status::Graded => "graded",
        }
    }
}

/// `GET /me`: the signed-in person's page; anyone else is sent to sign in.
pub async fn page(State(state): State<Arc<AppState>>, viewer: Viewer) -> Result<Response, Error> {
    let Some(member) = viewer.member().cloned() else {
        return Ok(Redirect::to("/signin").into_response());
    };
    let about = load(&state, &viewer).await?;
    html(&MePage {
        page: "me",
        assets: state.assets.page("me"),
        nav: Nav::of(&state, &viewer).await?,
        about,
        member,
    })
}
