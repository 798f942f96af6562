//! A course's exercise at a glance, for its staff: a row per student (the score that
//! counts, the latest, lateness, when last submitted), the distribution of scores, the
//! share of students passing each test, and the classic mistakes the class makes.

use super::challenge::{self, ClassChallenge};
use super::deadline::Policy;
use crate::store::{self, Extension, Member, Store, SubmissionSummary};
use labs::Exercise;
use labs::grading::{GradeResult, HintKind, Status as TestStatus};
use serde::Serialize;
use std::collections::{BTreeMap, HashMap};
use ts_rs::TS;

/// One submission as a row shows it.
#[derive(Clone, Debug, Serialize, TS)]
pub struct Shown {
    pub id: i64,
    pub submitted_at: String,
    pub score: Option<f64>,
    pub penalty: f64,
    pub final_score: Option<f64>,
    pub late_seconds: i64,
    /// Its late penalty waived by staff.
    pub waived: bool,
}

impl Shown {
    fn of(s: &SubmissionSummary) -> Shown {
        Shown {
            id: s.id,
            submitted_at: s.submitted_at.clone(),
            score: s.score,
            penalty: s.penalty,
            final_score: s.final_score,
            late_seconds: s.late_seconds,
            waived: s.waiver.is_some(),
        }
    }
}

/// A student of the roster and how they did.
#[derive(Debug, Serialize, TS)]
pub struct StudentRow {
    pub id: String,
    pub name: String,
    pub email: String,
    pub dropped: bool,
    pub submissions: usize,
    /// The submission whose score counts (best or last graded, after penalties).
    pub counting: Option<Shown>,
    pub latest: Option<Shown>,
    pub extension: Option<Extension>,
    /// The tests of the submission that counts, by what each tests, and whether it passed
    /// (empty until one is graded).
    pub tests: BTreeMap<String, bool>,
}

/// How many students pass a test (named by what it tests: the function, or the data-set
/// run), of those with a graded submission that counts.
#[derive(Debug, Serialize, TS)]
pub struct TestShare {
    pub name: String,
    pub passed: usize,
    pub of: usize,
}

/// A classic mistake and the students whose counting submission shows it.
#[derive(Debug, Serialize, TS)]
pub struct MistakeShare {
    pub kind: HintKind,
    pub text: String,
    /// What the tests that gave the hint test (a function, or a data-set run).
    pub functions: Vec<String>,
    pub students: Vec<String>,
}

#[derive(Debug, Serialize, TS)]
pub struct ClassView {
    pub students: Vec<StudentRow>,
    /// Counting scores in ten bins: [0, 0.1), ..., [0.9, 1].
    pub distribution: [usize; 10],
    pub tests: Vec<TestShare>,
    pub mistakes: Vec<MistakeShare>,
    /// The class challenge, where the exercise has one and a counting submission ran it.
    pub challenge: Option<ClassChallenge>,
}

/// The submission that counts under `policy` among a student's submissions (oldest
/// first): the best or the last of those graded, by the final score.
pub fn counting<'a>(
    policy: &Policy,
    history: impl IntoIterator<Item = &'a SubmissionSummary>,
) -> Option<&'a SubmissionSummary> {
    policy.counts.choose(history, |s| s.final_score)
}

/// The class from its people, their submissions to the exercise (any order), the
/// extensions, and the stored results of the counting submissions (`results(ids)`).
pub fn class_view<E>(
    members: &[Member],
    submissions: &[SubmissionSummary],
    extensions: Vec<Extension>,
    policy: &Policy,
    results: impl FnOnce(&[i64]) -> Result<HashMap<i64, GradeResult>, E>,
) -> Result<ClassView, E> {
    let mut by_student: HashMap<&str, Vec<&SubmissionSummary>> = HashMap::new();
    for s in submissions {
        by_student.entry(s.student.as_str()).or_default().push(s);
    }
    let mut extensions: HashMap<String, Extension> = extensions
        .into_iter()
        .map(|e| (e.student.clone(), e))
        .collect();
    let mut students: Vec<StudentRow> = members
        .iter()
        .filter(|m| !m.role.is_staff())
        .map(|m| {
            let mut own = by_student.remove(m.login.as_str()).unwrap_or_default();
            own.sort_by_key(|s| s.id);
            StudentRow {
                id: m.login.clone(),
                name: m.name.clone(),
                email: m.email.clone(),
                dropped: m.dropped,
                submissions: own.len(),
                counting: counting(policy, own.iter().copied()).map(Shown::of),
                latest: own.last().map(|s| Shown::of(s)),
                extension: extensions.remove(&m.login),
                tests: BTreeMap::new(),
            }
        })
        .collect();
    let counted: Vec<(String, i64)> = students
        .iter()
        .filter(|s| !s.dropped)
        .filter_map(|s| s.counting.as_ref().map(|c| (s.id.clone(), c.id)))
        .collect();
    let ids: Vec<i64> = counted.iter().map(|(_, id)| *id).collect();
    let results = results(&ids)?;
    let mut distribution = [0; 10];
    for s in students.iter().filter(|s| !s.dropped) {
        if let Some(score) = s.counting.as_ref().and_then(|c| c.final_score) {
            distribution[((score * 10.0).floor() as usize).min(9)] += 1;
        }
    }
    let mut tests: Vec<TestShare> = Vec::new();
    let mut mistakes: BTreeMap<String, (HintKind, Vec<String>, Vec<String>)> = BTreeMap::new();
    for (student, id) in &counted {
        let Some(result) = results.get(id) else {
            continue;
        };
        for test in &result.tests {
            // By what it tests: "predict: 12 cases" and "predict: 18 cases" (results of
            // graders with other plans) are one test.
            let name = test.subject.name();
            let share = match tests.iter_mut().find(|t| t.name == name) {
                Some(share) => share,
                None => {
                    tests.push(TestShare {
                        name: name.to_string(),
                        passed: 0,
                        of: 0,
                    });
                    tests.last_mut().expect("just pushed")
                }
            };
            share.of += 1;
            let passed = test.status == TestStatus::Passed;
            share.passed += usize::from(passed);
            if let Some(row) = students.iter_mut().find(|s| &s.id == student) {
                row.tests.insert(name.to_string(), passed);
            }
            for kind in &test.hints {
                let key = serde_json::to_string(kind).expect("hint kinds serialise");
                let (_, functions, showing) =
                    mistakes
                        .entry(key)
                        .or_insert((*kind, Vec::new(), Vec::new()));
                if !functions.iter().any(|f| f == name) {
                    functions.push(name.to_string());
                }
                if !showing.contains(student) {
                    showing.push(student.clone());
                }
            }
        }
    }
    let mut mistakes: Vec<MistakeShare> = mistakes
        .into_values()
        .map(|(kind, functions, students)| MistakeShare {
            text: kind.hint().text,
            kind,
            functions,
            students,
        })
        .collect();
    mistakes.sort_by_key(|m| std::cmp::Reverse(m.students.len()));
    // What the newest of the gradings that ran the challenge says of it.
    let challenge = results
        .iter()
        .filter_map(|(id, result)| Some((*id, result.challenge.as_ref()?)))
        .max_by_key(|(id, _)| *id)
        .map(|(_, about)| {
            let ranking = challenge::ranking(members, submissions, policy.counts);
            challenge::class_challenge(about, ranking)
        });
    Ok(ClassView {
        students,
        distribution,
        tests,
        mistakes,
        challenge,
    })
}

/// A course's exercise at a glance, from the database; `None` when the course has not
/// opened the exercise.
pub fn load(store: &Store, course: &str, lab: Exercise) -> Result<Option<ClassView>, store::Error> {
    let Some(assignment) = store.assignment(course, lab)? else {
        return Ok(None);
    };
    let members = store.members(course)?;
    let submissions = store.course_submissions(course, lab)?;
    let extensions = store.extensions(course, lab)?;
    class_view(
        &members,
        &submissions,
        extensions,
        &assignment.policy,
        |ids| store.results(ids),
    )
    .map(Some)
}
