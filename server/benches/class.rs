//! The instructor's side on a course of 500 students with 5,000 submissions (10 each) of
//! the EKF exercise: the dashboard's server time (`class::load` and its JSON, as
//! `GET /api/courses/{course}/labs/{lab}/class` makes them; budget 200 ms), the gradebook
//! CSV (budget 1 s), and the zips of Gradescope results and of sources. Run with
//! `cargo bench -p estlab --bench class`; the figures are in BENCHMARKS.md.
//!
//! The stored results are real: a few files (the starter file, the correct one and three
//! catalogued mistakes) are graded once with the server's sandbox, hidden cases included,
//! and every submission stores a copy of one of them (its own seed written in), so that
//! the class shows a spread of scores, failing tests and classic mistakes.
//!
//! `cargo test --all-targets` runs each benchmark once as a test, which checks only that
//! the calls complete and give a view of the whole class; no time is asserted.

use criterion::{Criterion, criterion_group, criterion_main};
use estlab::courses::class;
use estlab::courses::deadline::{Counts, Policy};
use estlab::courses::export::{self, Format};
use estlab::courses::roster;
use estlab::sandbox::{Code, Sandbox};
use estlab::store::{Holder, Lease, NewExtension, NewMember, NewSubmission, Role, Store};
use jiff::{SignedDuration, Timestamp};
use labs::Exercise;
use labs::grading::{GradeResult, Hidden, student_seed};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

const COURSE: &str = "el2320";
/// The grader the class's results name.
const GRADER: &str = "estlab 0.1.0 plan bench";
const STUDENTS: usize = 500;
const PER_STUDENT: usize = 10;
/// The catalogued mistakes graded (`tests/student/mistakes.json`), each in another function.
const MISTAKES: [&str; 3] = [
    "odometry-wheels-swapped",
    "bearing-not-wrapped",
    "associate-nearest-mahalanobis",
];

fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn read(path: &str) -> String {
    std::fs::read_to_string(repository().join(path))
        .unwrap_or_else(|e| panic!("reading {path}: {e}"))
}

/// `correct.js` with a catalogued mistake's lines changed.
fn mistake(correct: &str, catalogue: &serde_json::Value, name: &str) -> String {
    let entry = catalogue
        .as_array()
        .expect("the catalogue is a list")
        .iter()
        .find(|m| m["name"] == name)
        .unwrap_or_else(|| panic!("no mistake {name:?} in the catalogue"));
    let mut source = correct.to_string();
    for change in entry["replace"].as_array().expect("replacements") {
        let (from, to) = (
            change["from"].as_str().expect("from"),
            change["to"].as_str().expect("to"),
        );
        assert!(
            source.contains(from),
            "{name}: {from:?} is not in correct.js"
        );
        source = source.replacen(from, to, 1);
    }
    source
}

/// A file graded once, and its stored result.
struct Graded {
    source: String,
    result: GradeResult,
}

/// The files, graded side by side with the server's sandbox (hidden cases included):
/// the starter file, the mistakes, the correct file, in that order.
fn grade_files() -> Vec<Graded> {
    let correct = read("tests/student/correct.js");
    let catalogue: serde_json::Value =
        serde_json::from_str(&read("tests/student/mistakes.json")).expect("the catalogue");
    let mut sources = vec![read("labs/src/exercises/ekf_localization/web/starter.js")];
    sources.extend(MISTAKES.iter().map(|m| mistake(&correct, &catalogue, m)));
    sources.push(correct);
    let sandbox = Sandbox::new(PathBuf::from(env!("CARGO_BIN_EXE_estlab")), 1);
    std::thread::scope(|scope| {
        let handles: Vec<_> = sources
            .into_iter()
            .enumerate()
            .map(|(i, source)| {
                let sandbox = sandbox.clone();
                scope.spawn(move || {
                    let result = sandbox
                        .grade(
                            Exercise::EkfLocalization,
                            Code::javascript(&source),
                            1 + i as u64,
                            Some(Hidden {
                                cases: 1000 + i as u64,
                                class: 1,
                            }),
                        )
                        .stored();
                    assert!(result.gradable, "not gradable: {:?}", result.reason);
                    Graded { source, result }
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("a grading thread"))
            .collect()
    })
}

/// Which graded file a student's `n`-th submission is: the starter file first, then
/// mistakes, and for three students in four the correct file at the end.
fn pick(student: usize, n: usize, files: usize) -> usize {
    let mistakes = files - 2;
    match n {
        0..=1 => 0,
        _ if n + 1 == PER_STUDENT && !student.is_multiple_of(4) => files - 1,
        _ if n >= 7 && student % 4 == 1 => files - 1,
        _ => 1 + (student + n) % mistakes,
    }
}

/// A database of a course with the exercise open, an instructor, 500 students of the
/// roster, 10 graded submissions each (the last of one student in ten a day late), and a
/// few extensions.
fn build(dir: &Path) -> Store {
    let started = Instant::now();
    let files = grade_files();
    let graded_in = started.elapsed();
    let store = Store::open(dir).expect("the database");
    let opened: Timestamp = "2026-11-01T08:00:00Z".parse().unwrap();
    store
        .create_course(COURSE, "Applied Estimation", opened)
        .unwrap();
    let due = opened + SignedDuration::from_hours(24 * 28);
    store
        .assign(
            COURSE,
            Exercise::EkfLocalization,
            &Policy {
                due,
                cutoff: due + SignedDuration::from_hours(24 * 7),
                penalty_per_day: 0.1,
                counts: Counts::Best,
            },
        )
        .unwrap();
    store
        .add_member(
            COURSE,
            &NewMember {
                login: "teacher@example.org",
                name: "The Teacher",
                email: "teacher@example.org",
                role: Role::Instructor,
            },
        )
        .unwrap();
    let roster: Vec<roster::Student> = (1..=STUDENTS)
        .map(|i| roster::Student {
            id: format!("s{i:04}"),
            name: format!("Student Number {i}"),
            email: format!("s{i:04}@example.org"),
        })
        .collect();
    let members = store.import_roster(COURSE, &roster).unwrap().added;
    assert_eq!(members.len(), STUDENTS);
    let holder = Holder::this_process();
    for (i, member) in members.iter().enumerate() {
        let seed = student_seed(COURSE, &member.login);
        for n in 0..PER_STUDENT {
            let file = &files[pick(i, n, files.len())];
            let late = n + 1 == PER_STUDENT && i % 10 == 3;
            let submitted_at = if late {
                due + SignedDuration::from_hours(20)
            } else {
                opened + SignedDuration::from_mins((i * 37 + n * 1440) as i64 % (27 * 1440))
            };
            let source = format!("// {} submission {}\n{}", member.login, n + 1, file.source);
            let id = store
                .insert(
                    &NewSubmission {
                        course: COURSE,
                        student: &member.login,
                        member: Some(member.id),
                        lab: Exercise::EkfLocalization,
                        seed,
                        language: labs::Language::JavaScript,
                        source: &source,
                        submitted_at,
                        late_seconds: if late { 20 * 3600 } else { 0 },
                        penalty: if late { 0.1 } else { 0.0 },
                        grader: GRADER,
                    },
                    Timestamp::MAX,
                )
                .unwrap();
            let result = GradeResult {
                seed,
                ..file.result.clone()
            };
            let lease = Lease {
                holder: &holder,
                from: Timestamp::now(),
                length: Duration::from_secs(60),
            };
            store.claim_submission(id, &lease).unwrap();
            store
                .finish_grading(id, &result, Some(GRADER), &holder)
                .unwrap();
        }
    }
    for member in members.iter().step_by(50) {
        store
            .grant_extension(
                COURSE,
                &NewExtension {
                    lab: Exercise::EkfLocalization,
                    student: &member.login,
                    due: due + SignedDuration::from_hours(72),
                    cutoff: due + SignedDuration::from_hours(72),
                },
                "teacher@example.org",
                due,
            )
            .unwrap();
    }
    let bytes = match store.place() {
        estlab::store::Place::File(path) => std::fs::metadata(path).map_or(0, |m| m.len()),
        estlab::store::Place::Server(_) => 0,
    };
    eprintln!(
        "class bench: {} files graded in {:.1} s; {STUDENTS} students, {} submissions stored in {:.1} s; database {:.0} MB; stored results {}",
        files.len(),
        graded_in.as_secs_f64(),
        STUDENTS * PER_STUDENT,
        (started.elapsed() - graded_in).as_secs_f64(),
        bytes as f64 / 1e6,
        files
            .iter()
            .map(|f| format!(
                "{:.2} ({:.1} KB)",
                f.result.score,
                serde_json::to_string(&f.result).unwrap().len() as f64 / 1e3
            ))
            .collect::<Vec<_>>()
            .join(", ")
    );
    store
}

/// What `GET /api/courses/{course}/labs/{lab}/class` answers (`web::staff::ClassAnswer`).
#[derive(Serialize)]
struct ClassAnswer {
    course: String,
    lab: Exercise,
    policy: Policy,
    grader: String,
    #[serde(flatten)]
    view: class::ClassView,
    regrades: Vec<estlab::store::Regrade>,
}

/// The dashboard's answer as the handler makes it: the assignment, the class, the
/// course's regrades of the exercise, the JSON.
fn dashboard(store: &Store) -> Vec<u8> {
    let assignment = store
        .assignment(COURSE, Exercise::EkfLocalization)
        .unwrap()
        .expect("assigned");
    let view = class::load(store, COURSE, Exercise::EkfLocalization)
        .unwrap()
        .expect("assigned");
    let regrades = store
        .regrades(COURSE)
        .unwrap()
        .into_iter()
        .filter(|r| r.lab == Exercise::EkfLocalization)
        .collect();
    serde_json::to_vec(&ClassAnswer {
        course: COURSE.into(),
        lab: Exercise::EkfLocalization,
        policy: assignment.policy,
        grader: "estlab 0.1.0 plan bench".into(),
        view,
        regrades,
    })
    .expect("the answer serialises")
}

fn class(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let store = build(dir.path());

    // Once, outside the timing: the view covers the whole class.
    let view = class::load(&store, COURSE, Exercise::EkfLocalization)
        .unwrap()
        .unwrap();
    assert_eq!(view.students.len(), STUDENTS);
    assert!(view.students.iter().all(|s| s.submissions == PER_STUDENT));
    assert_eq!(view.distribution.iter().sum::<usize>(), STUDENTS);
    assert!(!view.mistakes.is_empty(), "no classic mistake in the class");
    let answer = dashboard(&store);
    let csv = export::make(&store, COURSE, Exercise::EkfLocalization, Format::Csv)
        .unwrap()
        .unwrap();
    assert_eq!(csv.iter().filter(|&&b| b == b'\n').count(), STUDENTS + 1);
    let sources = export::make(&store, COURSE, Exercise::EkfLocalization, Format::Sources)
        .unwrap()
        .unwrap();
    let gradescope = export::make(
        &store,
        COURSE,
        Exercise::EkfLocalization,
        Format::Gradescope,
    )
    .unwrap()
    .unwrap();
    eprintln!(
        "class bench: the dashboard's JSON {:.0} KB, the CSV {:.0} KB, the sources zip {:.0} KB, the Gradescope zip {:.0} KB",
        answer.len() as f64 / 1e3,
        csv.len() as f64 / 1e3,
        sources.len() as f64 / 1e3,
        gradescope.len() as f64 / 1e3
    );

    let mut group = c.benchmark_group("class of 500, 5,000 submissions");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(12));
    group.bench_function("dashboard: class::load and its JSON", |b| {
        b.iter(|| dashboard(&store))
    });
    group.bench_function("class::load alone", |b| {
        b.iter(|| class::load(&store, COURSE, Exercise::EkfLocalization).unwrap())
    });
    // Its parts: the submissions' rows, and the stored results of the counting ones.
    group.bench_function("part: Store::course_submissions", |b| {
        b.iter(|| {
            store
                .course_submissions(COURSE, Exercise::EkfLocalization)
                .unwrap()
        })
    });
    let counting: Vec<i64> = view
        .students
        .iter()
        .filter_map(|s| s.counting.as_ref().map(|c| c.id))
        .collect();
    group.bench_function("part: Store::results of the counting submissions", |b| {
        b.iter(|| store.results(&counting).unwrap())
    });
    for (name, format) in [
        ("export: gradebook CSV", Format::Csv),
        ("export: sources zip", Format::Sources),
        ("export: Gradescope results zip", Format::Gradescope),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| export::make(&store, COURSE, Exercise::EkfLocalization, format).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, class);
criterion_main!(benches);
