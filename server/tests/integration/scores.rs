//! The rules that decide a grade, through the real web application (in-process, with the
//! test clock set around each rule's edges; no test waits on a wall clock):
//!
//! - `the_submission_limit_is_per_student_and_exercise`: a student at the limit holds up
//!   neither a classmate nor their own submissions to another exercise;
//! - `the_submission_limit_counts_the_last_hour`: a second inside the hour still counts,
//!   a second outside it no longer does, submission by submission;
//! - `the_best_final_score_counts_for_staff_and_in_the_exports` and
//!   `the_best_final_score_counts_on_the_students_own_page`: with `counts best`, a late
//!   submission with the best raw score loses to an on-time one with the better score
//!   after its penalty;
//! - `a_penalty_over_the_whole_score_takes_the_whole_score`: ⌈late / 1 day⌉ × penalty
//!   past 100 % leaves 0, never less;
//! - `the_edges_of_the_deadline`: exactly at the due date on time, a second after it late
//!   by one day begun, exactly at the cutoff still taken, a second after it refused.

use crate::common;

use axum::http::StatusCode;
use common::*;
use estlab::courses::deadline::{Counts, Policy};
use estlab::store::Role;
use jiff::{SignedDuration, Timestamp};
use labs::Exercise;
use serde_json::Value;

/// Submissions a student may make to an exercise in an hour (README: "at most 20 times
/// an hour to an exercise").
const PER_HOUR: usize = 20;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

/// A number of a JSON answer, by pointer.
fn number(value: &Value, pointer: &str) -> f64 {
    value
        .pointer(pointer)
        .and_then(Value::as_f64)
        .unwrap_or_else(|| panic!("no number at {pointer} in {value}"))
}

/// Submits `source` to `exercise` as `who`, expecting it taken; waits for its grading.
async fn taken(app: &App, who: &Who, exercise: Exercise, source: &str) -> i64 {
    let answer = app.submit_to(who, exercise, source).await;
    assert_eq!(
        answer.status,
        StatusCode::ACCEPTED,
        "at {}: {}",
        app.now(),
        answer.body
    );
    let id = answer.json()["id"].as_i64().unwrap();
    app.graded(id).await;
    id
}

/// Submits as `who`, expecting the hourly limit to refuse it; nothing is stored.
async fn refused_for_the_hour(app: &App, who: &Who, exercise: Exercise) {
    let before = app.count();
    let answer = app
        .submit_to(who, exercise, &quick_source("one too many"))
        .await;
    assert_eq!(
        answer.status,
        StatusCode::TOO_MANY_REQUESTS,
        "at {}: {}",
        app.now(),
        answer.body
    );
    assert!(
        answer.error().contains("in the last hour"),
        "{}",
        answer.body
    );
    assert_eq!(app.count(), before, "a refused submission was stored");
}

/// A course with both exercises open for a month, and its students signed in.
async fn course_with(app: &App, students: &[&str]) -> Vec<Who> {
    app.open_course("el2320");
    app.assign("el2320", Exercise::Odometry, &open_policy(app.now()));
    let mut signed_in = Vec::new();
    for id in students {
        let member = app.enrol("el2320", id);
        signed_in.push(app.signed_in(&member).await);
    }
    signed_in
}

// ---- the hourly limit ----

/// Proves that the limit counts one student's submissions to one exercise: after A's
/// twentieth EKF submission A is refused, while A's classmate B still submits to the
/// same exercise, and A still submits to the other exercise.
#[tokio::test(flavor = "multi_thread")]
async fn the_submission_limit_is_per_student_and_exercise() {
    let app = App::new();
    let [a, b] = course_with(&app, &["u-limit-a", "u-limit-b"])
        .await
        .try_into()
        .unwrap();
    for i in 0..PER_HOUR {
        let source = quick_source(&format!("A's try {i}"));
        taken(&app, &a, Exercise::EkfLocalization, &source).await;
    }
    refused_for_the_hour(&app, &a, Exercise::EkfLocalization).await;

    // A classmate, at the same moment, to the same exercise: not A's limit.
    taken(
        &app,
        &b,
        Exercise::EkfLocalization,
        &quick_source("B's first"),
    )
    .await;
    // A, to the other exercise: a limit of its own.
    taken(&app, &a, Exercise::Odometry, &quick_source("A's odometry")).await;
    // And A is still held for the EKF.
    refused_for_the_hour(&app, &a, Exercise::EkfLocalization).await;
}

/// Proves that the limit is the last hour, sliding: with twenty submissions two minutes
/// apart, a submission a second inside the hour after the first is refused, one a second
/// outside it is taken, and then the next is refused again until the second one, too,
/// is more than an hour old.
#[tokio::test(flavor = "multi_thread")]
async fn the_submission_limit_counts_the_last_hour() {
    let app = App::new();
    let [who] = course_with(&app, &["u-hour"]).await.try_into().unwrap();
    let first = app.now();
    let every = SignedDuration::from_mins(2);
    for i in 0..PER_HOUR {
        app.clock.set(first + every * i as i32);
        taken(
            &app,
            &who,
            Exercise::EkfLocalization,
            &quick_source(&format!("try {i}")),
        )
        .await;
    }
    let hour = SignedDuration::from_hours(1);
    let second = SignedDuration::from_secs(1);

    // Just inside the hour of the first: all twenty count.
    app.clock.set(first + hour - second);
    refused_for_the_hour(&app, &who, Exercise::EkfLocalization).await;
    // Just outside it: the first no longer counts, so one more is taken...
    app.clock.set(first + hour + second);
    taken(
        &app,
        &who,
        Exercise::EkfLocalization,
        &quick_source("the 21st"),
    )
    .await;
    // ...and only one: twenty again within the last hour.
    refused_for_the_hour(&app, &who, Exercise::EkfLocalization).await;
    // Just inside the hour of the second, still twenty; just outside it, one more.
    app.clock.set(first + every + hour - second);
    refused_for_the_hour(&app, &who, Exercise::EkfLocalization).await;
    app.clock.set(first + every + hour + second);
    taken(
        &app,
        &who,
        Exercise::EkfLocalization,
        &quick_source("the 22nd"),
    )
    .await;
}

// ---- the score that counts ----

/// One student whose best raw score and best final score are different submissions: an
/// on-time file with a classic mistake (raw = final = `mistake`), then the correct file a
/// day late at 90 % a day (raw 1, final 0.1). With `counts best` the on-time one counts.
struct BestOfTwo {
    app: App,
    instructor: Who,
    student: Who,
    on_time: i64,
    late: i64,
    /// The on-time submission's score (raw and final).
    mistake: f64,
    mistake_source: String,
}

const BEST_OF_TWO_STUDENT: &str = "u-best";

async fn best_of_two() -> BestOfTwo {
    let app = App::new();
    let due = app.now() + SignedDuration::from_hours(24);
    app.store()
        .create_course("el2320", "Applied Estimation", app.now())
        .unwrap();
    app.assign(
        "el2320",
        Exercise::EkfLocalization,
        &Policy {
            due,
            cutoff: due + SignedDuration::from_hours(3 * 24),
            penalty_per_day: 0.9,
            counts: Counts::Best,
        },
    );
    let instructor = app.staff("el2320", "teacher@kth.example", Role::Instructor);
    let instructor = app.signed_in(&instructor).await;
    let student = app.enrol("el2320", BEST_OF_TWO_STUDENT);
    let student = app.signed_in(&student).await;

    let mistake_source = with_mistake("odometry-wheels-swapped");
    let on_time = taken(&app, &student, Exercise::EkfLocalization, &mistake_source).await;
    app.clock.set(due + SignedDuration::from_hours(1));
    let late = taken(&app, &student, Exercise::EkfLocalization, CORRECT).await;

    let on_time_read = app
        .get_json(&student, &format!("/api/submissions/{on_time}"))
        .await;
    let late_read = app
        .get_json(&student, &format!("/api/submissions/{late}"))
        .await;
    let mistake = number(&on_time_read, "/score");
    assert!(
        close(number(&on_time_read, "/final_score"), mistake),
        "on time, nothing is taken off: {on_time_read}"
    );
    assert_eq!(number(&late_read, "/score"), 1.0, "{late_read}");
    let late_final = number(&late_read, "/final_score");
    assert!(close(late_final, 0.1), "a day late at 90 %: {late_read}");
    // What the test is about: the raw best is the late one, the final best the on-time.
    assert!(
        late_final < mistake && mistake < 1.0,
        "the mistake scores {mistake}: the set-up needs 0.1 < it < 1"
    );
    BestOfTwo {
        app,
        instructor,
        student,
        on_time,
        late,
        mistake,
        mistake_source,
    }
}

/// Proves that with `counts best` the class view, the gradebook and the exports take the
/// submission with the best score after its late penalty (on time, with a mistake), not
/// the one with the best raw score (the correct file, late).
#[tokio::test(flavor = "multi_thread")]
async fn the_best_final_score_counts_for_staff_and_in_the_exports() {
    let BestOfTwo {
        app,
        instructor,
        on_time,
        late,
        mistake,
        mistake_source,
        ..
    } = best_of_two().await;
    let lab = "/api/courses/el2320/labs/ekf-localization";

    let view = app.get_json(&instructor, &format!("{lab}/class")).await;
    let row = &view["students"][0];
    assert_eq!(row["id"], BEST_OF_TWO_STUDENT, "{view}");
    assert_eq!(
        row["counting"]["id"], on_time,
        "the class counts the best final score, not submission {late}'s raw one: {row}"
    );
    assert!(
        close(number(row, "/counting/final_score"), mistake),
        "{row}"
    );
    assert_eq!(row["latest"]["id"], late, "{row}");
    let bin = ((mistake * 10.0).floor() as usize).min(9);
    assert_eq!(view["distribution"][bin], 1, "{}", view["distribution"]);

    let export = |format: &str| {
        app.send(Req::get(&format!("{lab}/export?format={format}")).who(&instructor))
    };
    let gradebook = csv_rows(&export("csv").await.body);
    let row = &gradebook[0];
    assert_eq!(row[0], BEST_OF_TWO_STUDENT);
    assert_eq!(
        (row[5].as_str(), row[6].as_str(), row[7].as_str()),
        (
            format!("{mistake:.4}").as_str(),
            "0.0000",
            format!("{mistake:.4}").as_str()
        ),
        "the gradebook's score, late_penalty and final_score: {row:?}"
    );
    let sources = unzip(&export("sources").await.raw);
    assert_eq!(
        sources,
        [(format!("{BEST_OF_TWO_STUDENT}.js"), mistake_source)],
        "the sources export holds the file that counts"
    );
    for format in ["prairielearn", "gradescope"] {
        let files = unzip(&export(format).await.raw);
        assert_eq!(files.len(), 1, "{format}");
        let results: Value = serde_json::from_str(&files[0].1).unwrap();
        let score = match format {
            "prairielearn" => number(&results, "/score"),
            // Gradescope's is in points, out of its tests' together.
            _ => {
                let tests = results["tests"].as_array().unwrap();
                let max: f64 = tests.iter().map(|t| number(t, "/max_score")).sum();
                number(&results, "/score") / max
            }
        };
        assert!(
            close(score, mistake),
            "the {format} export holds the submission that counts: {results}"
        );
    }
}

/// Proves that with `counts best` the student's own `/api/me` and `/me` give the best
/// score after penalties (the on-time submission's), not the best raw one (the late
/// correct file's 100 %).
#[tokio::test(flavor = "multi_thread")]
async fn the_best_final_score_counts_on_the_students_own_page() {
    let BestOfTwo {
        app,
        student,
        late,
        mistake,
        ..
    } = best_of_two().await;
    let me = app.get_json(&student, "/api/me").await;
    let assignment = &me["assignments"][0];
    assert!(
        close(number(assignment, "/counting_score"), mistake),
        "the score that counts is the best final one, {mistake}: {assignment}"
    );
    assert_eq!(assignment["latest"]["id"], late, "{assignment}");

    let page = app.send(Req::get("/me").who(&student)).await;
    assert_eq!(page.status, StatusCode::OK, "{}", page.body);
    let shown = format!(
        r#"<dd class="counting"><span class="value">{:.0} %</span>"#,
        mistake * 100.0
    );
    assert!(
        page.body.contains(&shown),
        "/me shows the score that counts as {shown}: {}",
        page.body
            .split(r#"class="counting""#)
            .nth(1)
            .map_or("(no score that counts)", |s| &s[..s.len().min(200)])
    );
}

// ---- penalties and deadlines ----

/// Proves that a penalty of 60 % a day, two days begun, takes the whole score and no
/// more: the correct file's final score is 0 (not −0.2) in its answer, the student's
/// score that counts, the class view and the gradebook.
#[tokio::test(flavor = "multi_thread")]
async fn a_penalty_over_the_whole_score_takes_the_whole_score() {
    let app = App::new();
    let due = app.now();
    app.store()
        .create_course("el2320", "Applied Estimation", app.now())
        .unwrap();
    app.assign(
        "el2320",
        Exercise::EkfLocalization,
        &Policy {
            due,
            cutoff: due + SignedDuration::from_hours(5 * 24),
            penalty_per_day: 0.6,
            counts: Counts::Best,
        },
    );
    let instructor = app.staff("el2320", "teacher@kth.example", Role::Instructor);
    let instructor = app.signed_in(&instructor).await;
    let student = app.enrol("el2320", "u-very-late");
    let student = app.signed_in(&student).await;

    app.clock
        .set(due + SignedDuration::from_hours(24) + SignedDuration::from_mins(1));
    let answer = app
        .submit_to(&student, Exercise::EkfLocalization, CORRECT)
        .await;
    assert_eq!(answer.status, StatusCode::ACCEPTED, "{}", answer.body);
    let accepted = answer.json();
    assert_eq!(
        accepted["penalty"], 1.0,
        "2 × 60 % is all of it: {accepted}"
    );
    let id = accepted["id"].as_i64().unwrap();
    app.graded(id).await;

    let read = app
        .get_json(&student, &format!("/api/submissions/{id}"))
        .await;
    assert_eq!(
        (read["score"].as_f64(), read["final_score"].as_f64()),
        (Some(1.0), Some(0.0)),
        "{read}"
    );
    let me = app.get_json(&student, "/api/me").await;
    assert_eq!(me["assignments"][0]["counting_score"], 0.0, "{me}");
    let lab = "/api/courses/el2320/labs/ekf-localization";
    let view = app.get_json(&instructor, &format!("{lab}/class")).await;
    let counting = &view["students"][0]["counting"];
    assert_eq!(
        (
            counting["penalty"].as_f64(),
            counting["final_score"].as_f64()
        ),
        (Some(1.0), Some(0.0)),
        "{counting}"
    );
    assert_eq!(view["distribution"][0], 1, "{}", view["distribution"]);
    let csv = app
        .send(Req::get(&format!("{lab}/export?format=csv")).who(&instructor))
        .await;
    let row = &csv_rows(&csv.body)[0];
    assert_eq!(
        (row[5].as_str(), row[6].as_str(), row[7].as_str()),
        ("1.0000", "1.0000", "0.0000"),
        "{row:?}"
    );
}

/// What a submission at `moment` is told: its lateness and penalty, or the refusal.
async fn submitted_at(app: &App, who: &Who, moment: Timestamp) -> Result<(i64, f64), String> {
    app.clock.set(moment);
    let answer = app
        .submit_to(
            who,
            Exercise::EkfLocalization,
            &quick_source(&moment.to_string()),
        )
        .await;
    match answer.status {
        StatusCode::ACCEPTED => {
            let accepted = answer.json();
            app.graded(accepted["id"].as_i64().unwrap()).await;
            Ok((
                accepted["late_seconds"].as_i64().unwrap(),
                accepted["penalty"].as_f64().unwrap(),
            ))
        }
        StatusCode::FORBIDDEN => Err(answer.error()),
        other => panic!("at {moment}: {other} {}", answer.body),
    }
}

/// Proves the deadline's edges to the second: at the due date itself a submission is
/// on time; a second later it is late by one second and loses one day's penalty; at
/// the cutoff itself it is still taken (two days late, two days' penalty); a second
/// later it is refused and not stored; and the student's page says so each time.
#[tokio::test(flavor = "multi_thread")]
async fn the_edges_of_the_deadline() {
    let app = App::new();
    let due = at("2026-12-15T22:59:00Z");
    let cutoff = due + SignedDuration::from_hours(2 * 24);
    app.clock.set(due - SignedDuration::from_hours(1));
    app.store()
        .create_course("el2320", "Applied Estimation", app.now())
        .unwrap();
    app.assign(
        "el2320",
        Exercise::EkfLocalization,
        &Policy {
            due,
            cutoff,
            penalty_per_day: 0.1,
            counts: Counts::Best,
        },
    );
    let student = app.enrol("el2320", "u-edges");
    let who = app.signed_in(&student).await;
    let second = SignedDuration::from_secs(1);

    assert_eq!(
        submitted_at(&app, &who, due).await,
        Ok((0, 0.0)),
        "at the due date"
    );
    assert_eq!(
        submitted_at(&app, &who, due + second).await,
        Ok((1, 0.1)),
        "a second after the due date"
    );
    let standing = app.get_json(&who, "/api/me").await["assignments"][0]["standing"].clone();
    assert_eq!(standing["state"], "late", "{standing}");
    let (late_seconds, penalty) = submitted_at(&app, &who, cutoff)
        .await
        .expect("a submission at the cutoff itself is taken");
    assert_eq!(late_seconds, 2 * 24 * 3600, "at the cutoff");
    assert!(close(penalty, 0.2), "two days begun: {penalty}");
    let standing = app.get_json(&who, "/api/me").await["assignments"][0]["standing"].clone();
    assert_eq!(
        (
            standing["state"].as_str(),
            standing["seconds_to_cutoff"].as_i64()
        ),
        (Some("late"), Some(0)),
        "{standing}"
    );

    let before = app.count();
    let refused = submitted_at(&app, &who, cutoff + second)
        .await
        .expect_err("a second after the cutoff");
    assert!(refused.contains("cutoff"), "{refused}");
    assert_eq!(app.count(), before, "a refused submission was stored");
    let standing = app.get_json(&who, "/api/me").await["assignments"][0]["standing"].clone();
    assert_eq!(standing["state"], "closed", "{standing}");
}
