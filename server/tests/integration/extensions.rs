//! Extensions and waivers through the real web application, in-process with the test
//! clock: an extension re-judges the submissions already made (the class view, the
//! gradebook and the student's own page all count them by the new dates), leaves an
//! on-time submission alone, and lists the scores it changed; a waiver of one submission's penalty is for
//! the course's staff only, audited, and shown to the student; lateness under a minute is
//! written in seconds.

use crate::common;

use axum::http::StatusCode;
use common::*;
use estlab::courses::deadline::{Counts, Policy};
use estlab::store::Role;
use jiff::{SignedDuration, Timestamp};
use labs::Exercise;
use serde_json::{Value, json};

const COURSE: &str = "el2320";
const CLASS: &str = "/api/courses/el2320/labs/ekf-localization/class";
const EXPORT_CSV: &str = "/api/courses/el2320/labs/ekf-localization/export?format=csv";
const EXTENSIONS: &str = "/api/courses/el2320/extensions";
const AUDIT: &str = "/api/courses/el2320/audit";

/// A course whose exercise is due an hour after the clock's start, taken three days late
/// at 10 % a day begun; its instructor, and one student signed in.
struct Course {
    app: App,
    due: Timestamp,
    instructor: Who,
    student: Who,
}

async fn course() -> Course {
    let app = App::new();
    let due = app.now() + SignedDuration::from_hours(1);
    app.store()
        .create_course(COURSE, "Applied Estimation", app.now())
        .unwrap();
    app.assign(
        COURSE,
        Exercise::EkfLocalization,
        &Policy {
            due,
            cutoff: due + SignedDuration::from_hours(3 * 24),
            penalty_per_day: 0.1,
            counts: Counts::Best,
        },
    );
    let instructor = app.staff(COURSE, "teacher@kth.example", Role::Instructor);
    let instructor = app.signed_in(&instructor).await;
    let student = app.enrol(COURSE, "s1");
    let student = app.signed_in(&student).await;
    Course {
        app,
        due,
        instructor,
        student,
    }
}

/// Submits correct.js (a score of 1) at `at`, graded.
async fn correct_at(course: &Course, at: Timestamp) -> i64 {
    course.app.clock.set(at);
    course.app.submit_graded(&course.student, CORRECT).await.0
}

/// The course with s1's two correct submissions 18 s and 54 s after the due date.
async fn late_by_seconds() -> (Course, [i64; 2]) {
    let course = course().await;
    let first = correct_at(&course, course.due + SignedDuration::from_secs(18)).await;
    let second = correct_at(&course, course.due + SignedDuration::from_secs(54)).await;
    (course, [first, second])
}

fn moment(at: Timestamp) -> String {
    at.to_string()
}

async fn grant(course: &Course, body: Value) -> Value {
    let answer = course
        .app
        .send(Req::post(EXTENSIONS).who(&course.instructor).json(body))
        .await;
    assert_eq!(answer.status, StatusCode::OK, "{}", answer.body);
    answer.json()
}

/// The submissions an extension's or a waiver's answer lists: (id, final before, after).
fn changed(answer: &Value) -> Vec<(i64, f64, f64)> {
    answer["changed"]
        .as_array()
        .unwrap_or_else(|| panic!("no `changed` in {answer}"))
        .iter()
        .map(|c| {
            (
                c["submission"].as_i64().unwrap(),
                c["old_final"].as_f64().unwrap(),
                c["new_final"].as_f64().unwrap(),
            )
        })
        .collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

/// s1's submissions on /api/me: (id, late_seconds, penalty, final_score), and the score
/// that counts.
async fn own_view(course: &Course) -> (Vec<(i64, i64, f64, f64)>, f64) {
    let me = course.app.get_json(&course.student, "/api/me").await;
    let assignment = &me["assignments"][0];
    let history = assignment["history"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            (
                s["id"].as_i64().unwrap(),
                s["late_seconds"].as_i64().unwrap(),
                s["penalty"].as_f64().unwrap(),
                s["final_score"].as_f64().unwrap(),
            )
        })
        .collect();
    (history, assignment["counting_score"].as_f64().unwrap())
}

async fn me_page(course: &Course) -> String {
    let answer = course.app.send(Req::get("/me").who(&course.student)).await;
    assert_eq!(answer.status, StatusCode::OK, "{}", answer.body);
    answer.body
}

/// s1's row of the class view: the submission that counts.
async fn counting_in_class(course: &Course) -> Value {
    let view = course.app.get_json(&course.instructor, CLASS).await;
    view["students"][0]["counting"].clone()
}

/// s1's gradebook line: (late_penalty, final_score).
async fn gradebook_line(course: &Course) -> (String, String) {
    let answer = course
        .app
        .send(Req::get(EXPORT_CSV).who(&course.instructor))
        .await;
    assert_eq!(answer.status, StatusCode::OK, "{}", answer.body);
    let rows = csv_rows(&answer.body);
    (rows[0][6].clone(), rows[0][7].clone())
}

/// Proves that a submission under a minute late says so in seconds (`18 s late`), on the
/// student's page and in the API, and is charged a day begun.
#[tokio::test(flavor = "multi_thread")]
async fn lateness_under_a_minute_is_written_in_seconds() {
    let (course, [first, second]) = late_by_seconds().await;
    let (history, counting) = own_view(&course).await;
    assert_eq!(
        history,
        [(first, 18, 0.1, 0.9), (second, 54, 0.1, 0.9)],
        "each a day begun late"
    );
    assert!(close(counting, 0.9));
    let page = me_page(&course).await;
    assert!(page.contains("18 s late (−10 %)"), "{page}");
    assert!(page.contains("54 s late (−10 %)"), "{page}");
    assert!(!page.contains("0 min"), "{page}");
}

/// Proves that an extension re-judges the submissions already made by the student's new
/// due date: one that moves the due date past the first submission only makes that one on
/// time; one past both makes both count in full in the class view, the gradebook and the
/// student's own view, each listed with its score before and after in the answer and the
/// audit log.
#[tokio::test(flavor = "multi_thread")]
async fn an_extension_re_judges_the_submissions_already_made() {
    let (course, [first, second]) = late_by_seconds().await;
    let due = course.due;

    let partly = grant(
        &course,
        json!({ "student": "s1", "due": moment(due + SignedDuration::from_secs(30)) }),
    )
    .await;
    assert_eq!(changed(&partly), [(first, 0.9, 1.0)], "{partly}");
    let (history, _) = own_view(&course).await;
    assert_eq!(
        history,
        [(first, 0, 0.0, 1.0), (second, 24, 0.1, 0.9)],
        "late by the extension's due date, not the class's"
    );

    let later = due + SignedDuration::from_hours(4 * 24);
    let granted = grant(&course, json!({ "student": "s1", "due": moment(later) })).await;
    assert_eq!(changed(&granted), [(second, 0.9, 1.0)], "{granted}");
    assert_eq!(granted["due"], moment(later));

    let counting = counting_in_class(&course).await;
    assert_eq!(counting["final_score"], 1.0, "{counting}");
    assert_eq!(counting["penalty"], 0.0, "{counting}");
    assert_eq!(counting["late_seconds"], 0, "{counting}");
    assert_eq!(
        gradebook_line(&course).await,
        ("0.0000".to_string(), "1.0000".to_string())
    );
    let (history, counting) = own_view(&course).await;
    assert_eq!(history, [(first, 0, 0.0, 1.0), (second, 0, 0.0, 1.0)]);
    assert!(close(counting, 1.0));
    let page = me_page(&course).await;
    assert_eq!(
        page.matches(r#"<td class="late">on time</td>"#).count(),
        2,
        "{page}"
    );
    assert!(
        page.contains("They cover every submission of yours"),
        "/me says what the extension covers: {page}"
    );
    let read = course
        .app
        .get_json(&course.student, &format!("/api/submissions/{second}"))
        .await;
    assert_eq!(read["final_score"], 1.0, "{read}");

    let log = course.app.get_json(&course.instructor, AUDIT).await;
    assert_eq!(log[0]["action"], "extension");
    let detail = log[0]["detail"].as_str().unwrap();
    assert!(
        detail.contains(&format!("re-judged submission {second} 90 % → 100 %")),
        "{detail}"
    );
    let detail = log[1]["detail"].as_str().unwrap();
    assert!(
        detail.contains(&format!("re-judged submission {first} 90 % → 100 %")),
        "{detail}"
    );
}

/// Proves that an extension to a later date leaves an on-time submission on time and
/// unlisted, and that its dates hold for the student even when the class's change: the
/// class's due date moved before that submission makes it late for nobody with the
/// extension.
#[tokio::test(flavor = "multi_thread")]
async fn an_extension_shortens_nothing_for_an_on_time_submission() {
    let course = course().await;
    let submitted = course.due - SignedDuration::from_secs(5);
    let on_time = correct_at(&course, submitted).await;

    let later = course.due + SignedDuration::from_hours(1);
    let granted = grant(&course, json!({ "student": "s1", "due": moment(later) })).await;
    assert_eq!(changed(&granted), [], "{granted}");
    assert_eq!(granted["due"], moment(later));
    assert_eq!(
        granted["cutoff"],
        moment(later),
        "the cutoff defaults to the due date"
    );
    let (history, counting) = own_view(&course).await;
    assert_eq!(history, [(on_time, 0, 0.0, 1.0)]);
    assert!(close(counting, 1.0));

    // The class's dates move to before the submission: the extension's hold for s1.
    let moved = submitted - SignedDuration::from_hours(1);
    course.app.assign(
        COURSE,
        Exercise::EkfLocalization,
        &Policy {
            due: moved,
            cutoff: moved,
            penalty_per_day: 0.1,
            counts: Counts::Best,
        },
    );
    let student = course
        .app
        .get_json(
            &course.instructor,
            "/api/courses/el2320/labs/ekf-localization/students/s1",
        )
        .await;
    assert_eq!(student["policy"]["due"], moment(later), "{student}");
    assert_eq!(student["submissions"][0]["late_seconds"], 0, "{student}");
    assert_eq!(student["submissions"][0]["final_score"], 1.0, "{student}");
    assert_eq!(counting_in_class(&course).await["final_score"], 1.0);
}

/// Proves that a waiver of a submission's late penalty is for the course's staff (its
/// student, anyone anonymous and another course's staff get the 404 of a course they
/// cannot see; a submission of another course is the 404 of one that does not exist),
/// needs a reason, lists the score it changed, is audited, and is shown to the student
/// beside that submission.
#[tokio::test(flavor = "multi_thread")]
async fn a_waiver_is_for_the_courses_staff_audited_and_shown_to_the_student() {
    let course = course().await;
    let late = correct_at(&course, course.due + SignedDuration::from_secs(18)).await;
    let app = &course.app;
    app.open_course("other");
    let stranger = app.staff("other", "stranger@kth.example", Role::Instructor);
    let stranger = app.signed_in(&stranger).await;
    let outsider = app.enrol("other", "o1");
    let outsider = app.signed_in(&outsider).await;
    let elsewhere = app
        .submit_graded(&outsider, &quick_source("other course"))
        .await
        .0;
    let assistant = app.staff(COURSE, "ta@kth.example", Role::Assistant);
    let assistant = app.signed_in(&assistant).await;

    let waive = |who: &Who, id: i64, reason: &str| {
        Req::post(&format!("/api/courses/el2320/submissions/{id}/waiver"))
            .who(who)
            .json(json!({ "reason": reason }))
    };
    let reason = "ill on the due date";
    for (who, id, status) in [
        (&course.student, late, StatusCode::NOT_FOUND),
        (&Who::Anonymous, late, StatusCode::NOT_FOUND),
        (&stranger, late, StatusCode::NOT_FOUND),
        (&assistant, elsewhere, StatusCode::NOT_FOUND),
        (&assistant, 999_999, StatusCode::NOT_FOUND),
        (&assistant, late, StatusCode::BAD_REQUEST),
    ] {
        let text = if status == StatusCode::BAD_REQUEST {
            "  "
        } else {
            reason
        };
        let answer = app.send(waive(who, id, text)).await;
        assert_eq!(answer.status, status, "{id}: {}", answer.body);
    }
    let other_view = app
        .get_json(&outsider, &format!("/api/submissions/{elsewhere}"))
        .await;
    assert!(other_view["waiver"].is_null(), "{other_view}");
    assert!(counting_in_class(&course).await["waived"] == false);

    let answer = app.send(waive(&assistant, late, reason)).await;
    assert_eq!(answer.status, StatusCode::OK, "{}", answer.body);
    let waived = answer.json();
    assert_eq!(changed(&waived), [(late, 0.9, 1.0)], "{waived}");
    assert_eq!(waived["submission"]["waiver"]["reason"], reason);
    assert_eq!(
        waived["submission"]["waiver"]["waived_by"],
        "ta@kth.example"
    );

    let counting = counting_in_class(&course).await;
    assert_eq!(counting["final_score"], 1.0, "{counting}");
    assert_eq!(counting["waived"], true, "{counting}");
    assert_eq!(
        counting["late_seconds"], 18,
        "still late, the penalty waived"
    );
    assert_eq!(
        gradebook_line(&course).await,
        ("0.0000".to_string(), "1.0000".to_string())
    );
    let (history, counting) = own_view(&course).await;
    assert_eq!(history, [(late, 18, 0.0, 1.0)]);
    assert!(close(counting, 1.0));
    let page = me_page(&course).await;
    assert!(
        page.contains(&format!("18 s late, penalty waived: {reason}")),
        "{page}"
    );

    let log = app.get_json(&course.instructor, AUDIT).await;
    assert_eq!(log[0]["action"], "waiver");
    assert_eq!(log[0]["actor"], "ta@kth.example");
    let detail = log[0]["detail"].as_str().unwrap();
    assert!(
        detail.contains(&format!(
            "submission {late} waived (re-judged submission {late} 90 % → 100 %)"
        )) && detail.ends_with(reason),
        "{detail}"
    );
    let other_log = app.get_json(&stranger, "/api/courses/other/audit").await;
    assert!(
        other_log
            .as_array()
            .unwrap()
            .iter()
            .all(|e| e["action"] != "waiver"),
        "{other_log}"
    );
}
