//! The class challenge of an exercise that has one (`labs::grading::Challenge`): every
//! submission's filter also runs over trials its class never sees, and the class is
//! ranked by that figure (a mean over the trials, its spread beside), lowest first. A student's figure is that of the latest of their
//! submissions with the score that counts for their grade (a better tuning submitted
//! after full marks counts); staff see the whole ranking, a student their own place
//! (unless staff switched the ranks off), never another student's.

use super::deadline::Counts;
use crate::store::{Member, SubmissionSummary};
use labs::grading::{Challenge, GradeResult};
use serde::Serialize;
use std::collections::{BTreeMap, HashSet};
use ts_rs::TS;

/// A student's figure in the ranking.
#[derive(Clone, Debug, PartialEq, Serialize, TS)]
#[ts(rename = "ChallengeEntry")]
pub struct Entry {
    pub student: String,
    /// The submission the figure is of: the one that counts for the student's grade.
    pub submission: i64,
    pub figure: f64,
    /// How much the figure varies between the runs it is a mean of.
    pub spread: Option<f64>,
    /// 1 for the lowest figure; equal figures share a rank.
    pub rank: usize,
}

/// What the challenge measures, its ranking and the reference's figure.
#[derive(Debug, Serialize, TS)]
pub struct ClassChallenge {
    pub measure: String,
    pub unit: String,
    /// The reference filter's figure over the same run.
    pub reference: f64,
    /// The students on the roster whose counting submission has a figure, lowest first.
    pub ranking: Vec<Entry>,
    /// Students on the roster with a graded submission but no figure: their filter did
    /// not finish the held-out trial, or it was graded before the challenge (a regrade
    /// runs it).
    pub without_figure: usize,
}

/// A student's own standing in the challenge.
#[derive(Debug, Serialize, TS)]
pub struct StudentChallenge {
    pub measure: String,
    pub unit: String,
    /// The figure of the submission that counts, and how much it varies between the runs
    /// it is a mean of.
    pub figure: f64,
    pub spread: Option<f64>,
    pub reference: f64,
    /// Whether the course shows its students their rank.
    pub ranks_shown: bool,
    /// Their rank among `of` students with a figure, while ranks are shown (none for a
    /// student no longer on the roster).
    pub rank: Option<usize>,
    pub of: Option<usize>,
}

/// The submission whose figure is a student's, of `own` (oldest first): the latest of
/// those with the score that counts by `counts`, so that a tuning submitted after full
/// marks counts under "best" too.
pub fn counting<'a>(
    own: &[&'a SubmissionSummary],
    counts: Counts,
) -> Option<&'a SubmissionSummary> {
    let score = counts
        .choose(own.iter().copied(), |s| s.final_score)?
        .final_score;
    own.iter().copied().rfind(|s| s.final_score == score)
}

/// The figures of the students on the roster (`members`, dropped ones and staff left
/// out), each that of their [`counting`] submission by `counts` among their
/// `submissions`, lowest first, and how many students have a graded submission without a
/// figure.
pub fn ranking(
    members: &[Member],
    submissions: &[SubmissionSummary],
    counts: Counts,
) -> (Vec<Entry>, usize) {
    let roster: HashSet<&str> = members
        .iter()
        .filter(|m| !m.role.is_staff() && !m.dropped)
        .map(|m| m.login.as_str())
        .collect();
    let mut by_student: BTreeMap<&str, Vec<&SubmissionSummary>> = BTreeMap::new();
    for s in submissions
        .iter()
        .filter(|s| roster.contains(s.student.as_str()))
    {
        by_student.entry(&s.student).or_default().push(s);
    }
    let mut without_figure = 0;
    let mut entries: Vec<Entry> = Vec::new();
    for (student, mut own) in by_student {
        own.sort_by_key(|s| s.id);
        let Some(counting) = counting(&own, counts) else {
            continue;
        };
        match counting.challenge {
            Some(figure) => entries.push(Entry {
                student: student.to_owned(),
                submission: counting.id,
                figure,
                spread: counting.challenge_spread,
                rank: 0,
            }),
            None => without_figure += 1,
        }
    }
    entries.sort_by(|a, b| {
        a.figure
            .total_cmp(&b.figure)
            .then_with(|| a.student.cmp(&b.student))
    });
    for i in 0..entries.len() {
        entries[i].rank = match i {
            0 => 1,
            _ if entries[i].figure == entries[i - 1].figure => entries[i - 1].rank,
            _ => i + 1,
        };
    }
    (entries, without_figure)
}

/// The class's challenge as staff see it: what it measures and the reference's figure
/// from `about` (a result that ran it), and the ranking.
pub fn class_challenge(
    about: &Challenge,
    (ranking, without_figure): (Vec<Entry>, usize),
) -> ClassChallenge {
    ClassChallenge {
        measure: about.measure.clone(),
        unit: about.unit.clone(),
        reference: about.reference,
        ranking,
        without_figure,
    }
}

/// `student`'s standing: the figure of their [`counting`] submission, whose result is
/// `counting`, with their rank in `ranking` when the course shows ranks (`ranked`); none
/// when that result has no figure.
pub fn standing(
    counting: &GradeResult,
    ranking: &[Entry],
    student: &str,
    ranked: bool,
) -> Option<StudentChallenge> {
    let challenge = counting.challenge.as_ref()?;
    let figure = challenge.figure?;
    Some(StudentChallenge {
        measure: challenge.measure.clone(),
        unit: challenge.unit.clone(),
        figure,
        spread: challenge.spread,
        reference: challenge.reference,
        ranks_shown: ranked,
        rank: ranked
            .then(|| {
                ranking
                    .iter()
                    .find(|e| e.student == student)
                    .map(|e| e.rank)
            })
            .flatten(),
        of: ranked.then_some(ranking.len()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store::{Role, Status};
    use labs::Exercise;

    fn member(login: &str, role: Role, dropped: bool) -> Member {
        Member {
            id: 0,
            course: "el2320".into(),
            login: login.into(),
            name: login.into(),
            email: format!("{login}@example.org"),
            role,
            dropped,
        }
    }

    fn submission(id: i64, student: &str, score: f64, figure: Option<f64>) -> SubmissionSummary {
        SubmissionSummary {
            id,
            course: "el2320".into(),
            student: student.into(),
            lab: Exercise::SensorFusion,
            language: labs::Language::JavaScript,
            status: Status::Graded,
            submitted_at: "2026-12-15T23:00:00.000Z".into(),
            late_seconds: 0,
            penalty: 0.0,
            score: Some(score),
            final_score: Some(score),
            waiver: None,
            challenge: figure,
            challenge_spread: figure.map(|f| f / 10.0),
        }
    }

    /// The counting submission's figure ranks each student, lowest first, ties sharing a
    /// rank; staff, dropped students and figures of submissions that do not count are
    /// left out.
    #[test]
    fn ranks_the_counting_submissions_of_the_roster() {
        let members = [
            member("ana", Role::Student, false),
            member("bo", Role::Student, false),
            member("cy", Role::Student, false),
            member("di", Role::Student, false),
            member("ed", Role::Student, true),
            member("ta", Role::Assistant, false),
        ];
        let submissions = [
            submission(1, "ana", 1.0, Some(0.09)),
            // A lower figure, but a lower score: the best score counts.
            submission(2, "ana", 0.5, Some(0.01)),
            submission(3, "bo", 1.0, Some(0.15)),
            submission(4, "cy", 1.0, Some(0.09)),
            submission(5, "di", 1.0, None),
            submission(6, "ed", 1.0, Some(0.02)),
            submission(7, "ta", 1.0, Some(0.03)),
            // Full marks again, tuned better: the latest of the best counts.
            submission(8, "bo", 1.0, Some(0.12)),
        ];
        let (ranking, without) = ranking(&members, &submissions, Counts::Best);
        let places: Vec<(&str, i64, usize)> = ranking
            .iter()
            .map(|e| (e.student.as_str(), e.submission, e.rank))
            .collect();
        assert_eq!(places, [("ana", 1, 1), ("cy", 4, 1), ("bo", 8, 3)]);
        assert_eq!(without, 1, "di's filter gave no figure");
        let (last, _) = super::ranking(&members, &submissions, Counts::Last);
        assert_eq!((last[0].student.as_str(), last[0].figure), ("ana", 0.01));
    }

    /// A student sees their figure and, while staff let them, their rank among all.
    #[test]
    fn a_student_sees_their_own_place_only_while_ranked() {
        let members = [
            member("ana", Role::Student, false),
            member("bo", Role::Student, false),
        ];
        let submissions = [
            submission(1, "ana", 1.0, Some(0.2)),
            submission(2, "bo", 1.0, Some(0.1)),
        ];
        let (ranking, _) = ranking(&members, &submissions, Counts::Best);
        let mut result = GradeResult::not_gradable(Exercise::SensorFusion, 1, "");
        assert!(standing(&result, &ranking, "ana", true).is_none());
        result.challenge = Some(Challenge {
            measure: "the RMS position error".into(),
            unit: "m".into(),
            figure: Some(0.2),
            spread: Some(0.03),
            reference: 0.15,
            message: String::new(),
        });
        let ranked = standing(&result, &ranking, "ana", true).unwrap();
        assert_eq!(
            (ranked.rank, ranked.of, ranked.figure, ranked.spread),
            (Some(2), Some(2), 0.2, Some(0.03))
        );
        let hidden = standing(&result, &ranking, "ana", false).unwrap();
        assert_eq!(
            (hidden.rank, hidden.of, hidden.ranks_shown),
            (None, None, false)
        );
        // A student no longer on the roster keeps their figure, without a rank.
        let gone = standing(&result, &ranking, "cy", true).unwrap();
        assert_eq!((gone.rank, gone.ranks_shown), (None, true));
    }
}
