//! A student's report (the lab's hand-in beside the code): the runs its exercise asks
//! for (`Declaration::report`), each run with the student's own code on the whole of its
//! data set and their analysis beside it, and their answers to the assignment's question
//! sets; staff judge it part by part (pass or revise, with a comment the student reads).
//! Its parts, its states and the checks of what students and staff send are here; the
//! store keeps it (`store::reports`), the web serves it (`web::report`).

use super::questions::QuestionSet;
use crate::store::{self, SavedAnswer, Store};
use jiff::Timestamp;
use labs::Exercise;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};
use ts_rs::TS;

/// The longest analysis of one run, and the longest comment on one part, in characters.
pub const MAX_TEXT: usize = 20_000;

/// What a part of a report is: one of its runs, or one of the assignment's question sets.
#[derive(Clone, Debug, PartialEq, Serialize, TS)]
#[ts(rename = "ReportPart")]
pub struct Part {
    /// The run's name (`o3/sequential`), or `questions-N` for the Nth set (from 1).
    pub id: String,
    pub title: String,
    /// For a run, what the student is asked to analyse beside it (Markdown).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ask: Option<String>,
}

/// The parts of a report of `lab` whose assignment has the question sets `sets`: its
/// runs, then its sets; empty when the exercise asks for no report.
pub fn parts(lab: Exercise, sets: &[QuestionSet]) -> Vec<Part> {
    let runs = lab.declaration().report;
    if runs.is_empty() {
        return Vec::new();
    }
    let runs = runs.iter().map(|run| Part {
        id: run.run.to_owned(),
        title: run.title.to_owned(),
        ask: Some(run.ask.to_owned()),
    });
    let sets = sets.iter().enumerate().map(|(i, set)| Part {
        id: format!("questions-{}", i + 1),
        title: set.title.clone(),
        ask: None,
    });
    runs.chain(sets).collect()
}

/// Whether a part passes, or is to be revised.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, TS)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    Pass,
    Revise,
}

/// Staff's judgement of one part of a report.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[serde(deny_unknown_fields)]
pub struct PartMark {
    /// The part's id (`Part::id`).
    pub part: String,
    pub verdict: Verdict,
    /// What the student reads beside the part (Markdown); may be empty.
    pub comment: String,
}

/// Where a report stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, TS)]
#[serde(rename_all = "snake_case")]
#[ts(rename = "ReportState")]
pub enum State {
    /// Not handed in yet: the student writes.
    Draft,
    /// Handed in, waiting for staff.
    HandedIn,
    /// Every part passed: with the code passing, the lab is passed.
    Accepted,
    /// Some part is to be revised: the student writes again and hands in anew.
    Revise,
}

impl State {
    /// What the gradebook and the class's table call it.
    pub fn name(self) -> &'static str {
        match self {
            State::Draft => "draft",
            State::HandedIn => "handed_in",
            State::Accepted => "accepted",
            State::Revise => "revise",
        }
    }

    /// Whether the student may change their analyses and hand in.
    pub fn open_to_student(self) -> bool {
        matches!(self, State::Draft | State::Revise)
    }
}

/// A report as stored.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stored {
    /// The student's analysis of each run, by run name.
    pub analyses: BTreeMap<String, String>,
    /// How many times it was handed in.
    pub handed_in: u32,
    /// The submission whose runs the last hand-in shows.
    pub submission: Option<i64>,
    pub handed_in_at: Option<Timestamp>,
    /// The analyses and the answers as the last hand-in had them: what staff judge.
    pub handed_analyses: BTreeMap<String, String>,
    pub handed_answers: Vec<SavedAnswer>,
    /// The last judgement, of the hand-in counted `reviewed`.
    pub rubric: Vec<PartMark>,
    pub reviewed: Option<u32>,
    pub reviewed_by: Option<String>,
    pub reviewed_at: Option<Timestamp>,
}

impl Stored {
    /// Where it stands: a draft until handed in; handed in until staff judge that very
    /// hand-in; then accepted when every part passed, or to be revised.
    pub fn state(&self) -> State {
        if self.handed_in == 0 {
            State::Draft
        } else if self.reviewed != Some(self.handed_in) {
            State::HandedIn
        } else if self.rubric.iter().all(|m| m.verdict == Verdict::Pass) {
            State::Accepted
        } else {
            State::Revise
        }
    }
}

/// The report state of every student of a course's exercise, by id (login); none when the
/// exercise asks for no report. A student who never wrote one has a draft.
pub fn states(
    store: &Store,
    course: &str,
    lab: Exercise,
) -> Result<Option<HashMap<String, State>>, store::Error> {
    if lab.declaration().report.is_empty() {
        return Ok(None);
    }
    let states: HashMap<i64, State> = store.report_states(course, lab)?.into_iter().collect();
    Ok(Some(
        store
            .members(course)?
            .into_iter()
            .filter(|m| !m.role.is_staff())
            .map(|m| {
                let state = states.get(&m.id).copied().unwrap_or(State::Draft);
                (m.login, state)
            })
            .collect(),
    ))
}

/// Whether a student's code passes: the submission that counts (its `score`) passes
/// every test.
pub fn code_passes(score: Option<f64>) -> bool {
    score == Some(1.0)
}

/// Whether a student passed the lab: their code passes and their report is accepted.
pub fn lab_passed(score: Option<f64>, state: State) -> bool {
    code_passes(score) && state == State::Accepted
}

/// Checks a student's analysis of `run` of a report with `parts`: a run of the report, and
/// not too long.
pub fn check_analysis(parts: &[Part], run: &str, text: &str) -> Result<(), String> {
    if !parts.iter().any(|p| p.id == run && p.ask.is_some()) {
        let runs: Vec<&str> = parts
            .iter()
            .filter(|p| p.ask.is_some())
            .map(|p| p.id.as_str())
            .collect();
        return Err(format!(
            "field `run`: the report has no run {run:?} (its runs: {})",
            runs.join(", ")
        ));
    }
    check_length("text", text)
}

/// Checks staff's rubric of a report with `parts`: every part judged once, no other, each
/// comment not too long; the marks come back in the parts' order.
pub fn check_rubric(parts: &[Part], marks: Vec<PartMark>) -> Result<Vec<PartMark>, String> {
    let mut by_part: BTreeMap<String, PartMark> = BTreeMap::new();
    for (i, mark) in marks.into_iter().enumerate() {
        if !parts.iter().any(|p| p.id == mark.part) {
            return Err(format!(
                "field `parts`: mark {}: the report has no part {:?}",
                i + 1,
                mark.part
            ));
        }
        check_length(&format!("parts: mark {}: comment", i + 1), &mark.comment)?;
        if by_part.insert(mark.part.clone(), mark).is_some() {
            return Err(format!(
                "field `parts`: mark {}: that part is judged twice",
                i + 1
            ));
        }
    }
    parts
        .iter()
        .map(|part| {
            by_part.remove(&part.id).ok_or_else(|| {
                format!(
                    "field `parts`: part {:?} ({}) has no verdict: every part is judged",
                    part.id, part.title
                )
            })
        })
        .collect()
}

fn check_length(field: &str, text: &str) -> Result<(), String> {
    let length = text.chars().count();
    if length > MAX_TEXT {
        return Err(format!(
            "field `{field}`: {length} characters, more than the {MAX_TEXT} it may have"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::courses::questions;

    fn ekf_parts() -> Vec<Part> {
        let sets = questions::read_all(&questions::own(Exercise::EkfLocalization)).unwrap();
        parts(Exercise::EkfLocalization, &sets)
    }

    fn mark(part: &str, verdict: Verdict) -> PartMark {
        PartMark {
            part: part.into(),
            verdict,
            comment: String::new(),
        }
    }

    #[test]
    fn the_lab_report_has_its_four_runs_and_both_sets() {
        let ids: Vec<String> = ekf_parts().into_iter().map(|p| p.id).collect();
        assert_eq!(
            ids,
            [
                "o3/sequential",
                "outliers/sequential",
                "no-odometry/sequential",
                "no-odometry/batch",
                "questions-1",
                "questions-2"
            ]
        );
        let odometry = questions::read_all(&questions::own(Exercise::Odometry)).unwrap();
        assert!(parts(Exercise::Odometry, &odometry).is_empty());
    }

    #[test]
    fn every_report_run_is_a_run_of_its_exercise() {
        for &exercise in Exercise::ALL {
            let job = labs::grading::Plan::new(exercise, 1, None).job();
            for run in exercise.declaration().report {
                assert!(
                    job.runs.iter().any(|r| r.name == run.run),
                    "{}: {}",
                    exercise.name(),
                    run.run
                );
            }
        }
    }

    #[test]
    fn a_rubric_judges_every_part_once() {
        let parts = ekf_parts();
        let all: Vec<PartMark> = parts.iter().map(|p| mark(&p.id, Verdict::Pass)).collect();
        let mut reversed = all.clone();
        reversed.reverse();
        assert_eq!(check_rubric(&parts, reversed), Ok(all.clone()));
        let missing = check_rubric(&parts, all[1..].to_vec()).unwrap_err();
        assert!(missing.contains("\"o3/sequential\""), "{missing}");
        let mut twice = all.clone();
        twice.push(mark("questions-1", Verdict::Revise));
        assert!(check_rubric(&parts, twice).unwrap_err().contains("twice"));
        let mut other = all;
        other.push(mark("o4", Verdict::Pass));
        assert!(
            check_rubric(&parts, other)
                .unwrap_err()
                .contains("no part \"o4\"")
        );
    }

    #[test]
    fn analyses_name_a_run_and_keep_within_their_length() {
        let parts = ekf_parts();
        assert_eq!(check_analysis(&parts, "o3/sequential", "ok"), Ok(()));
        assert!(check_analysis(&parts, "questions-1", "").is_err());
        let long = "x".repeat(MAX_TEXT + 1);
        let problem = check_analysis(&parts, "o3/sequential", &long).unwrap_err();
        assert!(problem.contains("field `text`"), "{problem}");
    }

    #[test]
    fn a_report_is_judged_hand_in_by_hand_in() {
        let mut report = Stored::default();
        assert_eq!(report.state(), State::Draft);
        report.handed_in = 1;
        assert_eq!(report.state(), State::HandedIn);
        report.reviewed = Some(1);
        report.rubric = vec![mark("a", Verdict::Pass), mark("b", Verdict::Revise)];
        assert_eq!(report.state(), State::Revise);
        assert!(report.state().open_to_student());
        report.handed_in = 2;
        assert_eq!(report.state(), State::HandedIn);
        assert!(!report.state().open_to_student());
        report.reviewed = Some(2);
        report.rubric[1].verdict = Verdict::Pass;
        assert_eq!(report.state(), State::Accepted);
        assert!(lab_passed(Some(1.0), State::Accepted));
        assert!(!lab_passed(Some(0.9), State::Accepted));
        assert!(!lab_passed(Some(1.0), State::Revise));
    }
}
