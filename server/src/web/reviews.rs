//! Peer review of the written answers in class. Staff open a round for a question set,
//! watch it, let late authors join, move a leaver's sheets and close it; each student
//! reviews the sheets handed to them (anonymous, numbered 1, 2, ... for them) against
//! the model answers and, once the round is closed, reads the marks of their own.
//!
//! - `GET|POST /api/courses/{course}/labs/{lab}/rounds`, `POST .../rounds/{id}` (staff)
//! - `GET /api/courses/{course}/labs/{lab}/reviews` (students)
//! - `GET|POST /api/courses/{course}/labs/{lab}/reviews/{round}/{sheet}` (its reviewer)
//!
//! Anyone else gets the 404 of a course that does not exist, as for a round or a sheet
//! that is not theirs.

use super::extract::Body;
use super::viewer::Viewer;
use super::{AppState, Error, blocking, known_lab};
use crate::courses::questions::QuestionSet;
use crate::courses::review::Pair;
use crate::courses::rounds::{self, Opening, Tally};
use crate::store::{Mark, Member, Role, Round, SheetAnswer, Store};
use axum::Json;
use axum::extract::{Path, State};
use axum::response::{IntoResponse, Response};
use labs::Exercise;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::sync::Arc;
use ts_rs::TS;

/// One student in a round, for staff.
#[derive(Serialize, TS)]
pub struct RoundStudent {
    pub student: String,
    pub name: String,
    /// Sheets handed to them, and how many they have submitted.
    #[ts(type = "number")]
    pub reviewing: usize,
    #[ts(type = "number")]
    pub submitted: usize,
    /// What the marks of their own sheet add up to so far.
    pub tally: Tally,
}

/// A round as staff see it.
#[derive(Serialize, TS)]
pub struct RoundView {
    #[serde(flatten)]
    pub round: Round,
    /// The title of the set it reviews.
    pub title: String,
    pub students: Vec<RoundStudent>,
    /// Students who have answered the set since and are not in the round: they may join.
    pub waiting: Vec<String>,
}

fn round_view(
    store: &Store,
    course: &str,
    lab: Exercise,
    round: Round,
) -> Result<RoundView, crate::store::Error> {
    let set = rounds::set_of(&round)?;
    let members: HashMap<i64, Member> = store
        .members(course)?
        .into_iter()
        .map(|m| (m.id, m))
        .collect();
    let pairs = store.pairs(round.id)?;
    let mut tallies = rounds::tallies(store, &round)?;
    let mut students: Vec<RoundStudent> = tallies
        .keys()
        .filter_map(|id| members.get(id))
        .map(|member| {
            let mine = pairs.iter().filter(|p| p.pair.reviewer == member.id);
            RoundStudent {
                student: member.login.clone(),
                name: member.name.clone(),
                reviewing: mine.clone().count(),
                submitted: mine.filter(|p| p.submitted_at.is_some()).count(),
                tally: Tally::default(),
            }
        })
        .collect();
    students.sort_by(|a, b| a.student.cmp(&b.student));
    for student in &mut students {
        let id = members
            .values()
            .find(|m| m.login == student.student)
            .map(|m| m.id);
        if let Some(tally) = id.and_then(|id| tallies.remove(&id)) {
            student.tally = tally;
        }
    }
    let mut waiting = Vec::new();
    if round.closed_at.is_none() {
        for member in members.values() {
            let in_round = students.iter().any(|s| s.student == member.login);
            if !in_round && rounds::may_take_part(store, member, lab, (round.part, &set))? {
                waiting.push(member.login.clone());
            }
        }
        waiting.sort();
    }
    Ok(RoundView {
        round,
        title: set.title,
        students,
        waiting,
    })
}

/// `GET .../rounds`: an assignment's rounds, the latest first.
pub async fn list(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let exercise = known_lab(&lab)?;
    let views = blocking(&state, move |store| {
        store
            .rounds(&course, exercise)?
            .into_iter()
            .map(|round| round_view(store, &course, exercise, round))
            .collect::<Result<Vec<_>, _>>()
    })
    .await?;
    Ok(Json(views).into_response())
}

/// The body of `POST .../rounds`.
#[derive(Deserialize, TS)]
#[serde(deny_unknown_fields)]
pub struct OpenRequest {
    /// The question set to review: its place in the assignment, from 0.
    #[ts(type = "number")]
    pub part: usize,
    /// How many classmates review each sheet.
    #[ts(type = "number")]
    pub per_sheet: usize,
    /// The share of correct marks above which the bonus is earned (default 0.3).
    pub bonus_above: Option<f64>,
}

/// Runs a change of staff on a round through a [`crate::courses::setup::Setup`] (logged
/// with who made it), then answers with the round as it stands.
async fn round_change(
    state: &Arc<AppState>,
    viewer: &Viewer,
    (course, exercise): (String, Exercise),
    work: impl FnOnce(&crate::courses::setup::Setup) -> Result<i64, crate::courses::setup::Error>
    + Send
    + 'static,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let actor = viewer.actor();
    let now = state.clock.now();
    let at = course.clone();
    let view = blocking(state, move |store| {
        let setup = crate::courses::setup::Setup {
            store,
            course: &at,
            actor: &actor,
            now,
        };
        let id = match work(&setup) {
            Ok(id) => id,
            Err(crate::courses::setup::Error::Store(e)) => return Err(e),
            Err(crate::courses::setup::Error::Invalid(problem)) => return Ok(Err(problem)),
        };
        let round = store
            .round(&at, exercise, id)?
            .expect("the round just changed");
        Ok(Ok(round_view(store, &at, exercise, round)?))
    })
    .await?
    .map_err(Error::BadRequest)?;
    Ok(Json(view).into_response())
}

/// `POST .../rounds`: opens a round; every student who has answered the set takes part.
pub async fn open(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
    body: Body,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let exercise = known_lab(&lab)?;
    let request: OpenRequest = body.json(&viewer, "the review round").await?;
    let opening = Opening {
        part: request.part,
        per_sheet: request.per_sheet,
        bonus_above: request.bonus_above.unwrap_or(rounds::BONUS_ABOVE),
    };
    round_change(&state, &viewer, (course, exercise), move |setup| {
        rounds::open(setup, exercise, &opening)
    })
    .await
}

/// The body of `POST .../rounds/{id}`: what staff do to a round.
#[derive(Deserialize, TS)]
#[serde(tag = "action", rename_all = "kebab-case", deny_unknown_fields)]
pub enum RoundAction {
    /// Close it: each author then reads their marks.
    Close,
    /// Let a student who answered after it opened join it.
    Join { student: String },
    /// Give the sheets a student has not reviewed to others (they left).
    Reassign { student: String },
}

/// `POST .../rounds/{id}`: closes a round, lets a late author join, or moves a leaver's
/// sheets; logged.
pub async fn act(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab, id)): Path<(String, String, i64)>,
    body: Body,
) -> Result<Response, Error> {
    viewer.staff_of(&course)?;
    let exercise = known_lab(&lab)?;
    let action: RoundAction = body.json(&viewer, "the action").await?;
    let at = course.clone();
    let found = blocking(&state, move |store| {
        Ok(store.round(&at, exercise, id)?.is_some())
    })
    .await?;
    if !found {
        return Err(Error::NotFound(format!(
            "{exercise} has no review round {id}"
        )));
    }
    round_change(&state, &viewer, (course, exercise), move |setup| {
        match action {
            RoundAction::Close => rounds::close(setup, exercise, id)?,
            RoundAction::Join { student } => rounds::join(setup, exercise, id, &student)?,
            RoundAction::Reassign { student } => {
                rounds::reassign(setup, exercise, id, &student)?;
            }
        }
        Ok(id)
    })
    .await
}

/// A sheet handed to the student, in the list of their rounds.
#[derive(Serialize, TS)]
pub struct HandedSheet {
    #[ts(type = "number")]
    pub number: usize,
    pub submitted: bool,
}

/// What the student's own sheet received, once the round is closed.
#[derive(Serialize, TS)]
pub struct Received {
    pub marks: Vec<Mark>,
    pub tally: Tally,
}

/// A round as a student sees it.
#[derive(Serialize, TS)]
pub struct StudentRound {
    pub id: i64,
    #[ts(type = "number")]
    pub part: usize,
    pub title: String,
    pub open: bool,
    pub sheets: Vec<HandedSheet>,
    /// Their own sheet's marks: only once the round is closed, and only if they took part.
    pub received: Option<Received>,
}

/// The signed-in student of `course`; for anyone else what a course that does not exist
/// answers (staff review no sheets: they are told so).
fn student_of(viewer: &Viewer, course: &str) -> Result<Member, Error> {
    match viewer.member() {
        Some(member) if member.course == course && member.role == Role::Student && member.dropped => {
            Err(Error::Forbidden(format!(
                "you are no longer on the roster of {course}: you take no part in its reviews"
            )))
        }
        Some(member) if member.course == course && member.role == Role::Student => Ok(member.clone()),
        _ if viewer.is_staff_of(course) => Err(Error::Forbidden(
            "only the course's students review sheets: staff follow the rounds on the questions page".into(),
        )),
        _ => Err(Error::NotFound(format!("there is no course {course:?}"))),
    }
}

/// `GET .../reviews`: the student's rounds, with the sheets handed to them and, once a
/// round is closed, the marks of their own.
pub async fn mine(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab)): Path<(String, String)>,
) -> Result<Response, Error> {
    let member = student_of(&viewer, &course)?;
    let exercise = known_lab(&lab)?;
    let rounds = blocking(&state, move |store| {
        let mut mine = Vec::new();
        for round in store.rounds(&course, exercise)? {
            let pairs = store.pairs(round.id)?;
            let sheets: Vec<HandedSheet> = pairs
                .iter()
                .filter(|p| p.pair.reviewer == member.id)
                .map(|p| HandedSheet {
                    number: p.number,
                    submitted: p.submitted_at.is_some(),
                })
                .collect();
            let author = store.sheets(round.id)?.iter().any(|(a, _)| *a == member.id);
            if sheets.is_empty() && !author {
                continue;
            }
            let received = if round.closed_at.is_some() && author {
                let submitted: Vec<Pair> = pairs
                    .iter()
                    .filter(|p| p.submitted_at.is_some())
                    .map(|p| p.pair)
                    .collect();
                let marks = store
                    .marks(round.id)?
                    .into_iter()
                    .filter(|(pair, _)| pair.author == member.id && submitted.contains(pair))
                    .map(|(_, mark)| mark)
                    .collect();
                let tally = rounds::tallies(store, &round)?
                    .remove(&member.id)
                    .unwrap_or_default();
                Some(Received { marks, tally })
            } else {
                None
            };
            mine.push(StudentRound {
                id: round.id,
                part: round.part,
                title: rounds::set_of(&round)?.title,
                open: round.closed_at.is_none(),
                sheets,
                received,
            });
        }
        Ok(mine)
    })
    .await?;
    Ok(Json(rounds).into_response())
}

/// A sheet as its reviewer reads and marks it.
#[derive(Serialize, TS)]
pub struct SheetView {
    pub round: i64,
    #[ts(type = "number")]
    pub number: usize,
    pub open: bool,
    pub submitted: bool,
    /// The set in full: the model answers and what answers are checked against.
    pub set: QuestionSet,
    /// The author's answers as the round froze them (the author unnamed).
    pub answers: Vec<SheetAnswer>,
    /// The reviewer's marks so far.
    pub marks: Vec<Mark>,
}

/// The sheet `number` of `round` handed to `member`, with what they need to mark it; a
/// 404 for any other.
fn sheet_view(
    store: &Store,
    (course, exercise): (&str, Exercise),
    member: &Member,
    (round, number): (i64, usize),
) -> Result<Result<(SheetView, Pair), Error>, crate::store::Error> {
    let missing = || {
        Ok(Err(Error::NotFound(format!(
            "you have no sheet {number} in round {round}"
        ))))
    };
    let Some(found) = store.round(course, exercise, round)? else {
        return missing();
    };
    let Some(stored) = store
        .pairs(round)?
        .into_iter()
        .find(|p| p.pair.reviewer == member.id && p.number == number)
    else {
        return missing();
    };
    let answers = store
        .sheets(round)?
        .into_iter()
        .find(|(author, _)| *author == stored.pair.author)
        .map(|(_, answers)| answers)
        .unwrap_or_default();
    let marks = store
        .marks(round)?
        .into_iter()
        .filter(|(pair, _)| *pair == stored.pair)
        .map(|(_, mark)| mark)
        .collect();
    Ok(Ok((
        SheetView {
            round,
            number,
            open: found.closed_at.is_none(),
            submitted: stored.submitted_at.is_some(),
            set: rounds::set_of(&found)?.for_reviewers(),
            answers,
            marks,
        },
        stored.pair,
    )))
}

/// `GET .../reviews/{round}/{sheet}`: a sheet handed to the student.
pub async fn sheet(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab, round, number)): Path<(String, String, i64, usize)>,
) -> Result<Response, Error> {
    let member = student_of(&viewer, &course)?;
    let exercise = known_lab(&lab)?;
    let (view, _) = blocking(&state, move |store| {
        sheet_view(store, (&course, exercise), &member, (round, number))
    })
    .await??;
    Ok(Json(view).into_response())
}

/// The body of `POST .../reviews/{round}/{sheet}`.
#[derive(Deserialize, TS)]
#[serde(deny_unknown_fields)]
pub struct MarkRequest {
    pub marks: Vec<Mark>,
    /// Hand the review in (every answer marked); it can no longer change.
    pub submit: bool,
}

/// `POST .../reviews/{round}/{sheet}`: the reviewer's marks of a sheet, kept, and handed
/// in when `submit`; while the round is open and the review not yet handed in.
pub async fn mark(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    Path((course, lab, round, number)): Path<(String, String, i64, usize)>,
    body: Body,
) -> Result<Response, Error> {
    let member = student_of(&viewer, &course)?;
    let exercise = known_lab(&lab)?;
    let request: MarkRequest = body.json(&viewer, "the marks").await?;
    let now = state.clock.now();
    let view = blocking(&state, move |store| {
        let (view, pair) = match sheet_view(store, (&course, exercise), &member, (round, number))? {
            Ok(found) => found,
            Err(error) => return Ok(Err(error)),
        };
        if !view.open {
            return Ok(Err(Error::Forbidden(format!("round {round} is closed"))));
        }
        if view.submitted {
            return Ok(Err(Error::Forbidden(format!(
                "your review of sheet {number} is handed in already"
            ))));
        }
        if let Err(problem) =
            rounds::check_marks(&view.set, &view.answers, &request.marks, request.submit)
        {
            return Ok(Err(Error::BadRequest(format!("field `marks`: {problem}"))));
        }
        if !store.save_marks(round, pair, &request.marks, request.submit, now)? {
            return Ok(Err(Error::Forbidden(format!(
                "round {round} closed, or your review of sheet {number} was handed in, meanwhile"
            ))));
        }
        Ok(sheet_view(store, (&course, exercise), &member, (round, number))?.map(|(view, _)| view))
    })
    .await??;
    Ok(Json(view).into_response())
}
