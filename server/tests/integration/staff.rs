//! The instructor's side through the real web application, in-process: the class at a
//! glance, regrades (every changed score listed, the replaced results kept, a regrade cut
//! off by a stop resumed), extensions, the audit log and the exports.

use crate::common;

use axum::http::StatusCode;
use common::*;
use estlab::store::{Role, Scope};
use jiff::SignedDuration;
use labs::Exercise;
use serde_json::json;
use std::time::{Duration, Instant};

/// The first catalogued mistake: correct.js with the wheels swapped.
fn wheels_swapped() -> String {
    with_mistake("odometry-wheels-swapped")
}

/// A course with three students who have each submitted once (a correct file, a file
/// with a classic mistake, a file that implements nothing), and its instructor.
struct Class {
    app: App,
    instructor: Who,
    students: [(String, Who, i64); 3],
}

async fn class() -> Class {
    let app = App::new();
    app.open_course("el2320");
    let instructor = app.staff("el2320", "teacher@kth.example", Role::Instructor);
    let instructor = app.signed_in(&instructor).await;
    let sources = [
        CORRECT.to_string(),
        wheels_swapped(),
        quick_source("nothing yet"),
    ];
    let mut students = Vec::new();
    for (id, source) in ["s1", "s2", "s3"].into_iter().zip(&sources) {
        let member = app.enrol("el2320", id);
        let who = app.signed_in(&member).await;
        let (submission, _) = app.submit_graded(&who, source).await;
        students.push((id.to_string(), who, submission));
    }
    Class {
        app,
        instructor,
        students: students.try_into().unwrap(),
    }
}

/// Waits until a regrade is finished; its last state.
async fn finished(app: &App, who: &Who, url: &str) -> serde_json::Value {
    let give_up = Instant::now() + GRADING_BOUND;
    loop {
        let answer = app.send(Req::get(url).who(who)).await;
        assert_eq!(answer.status, StatusCode::OK, "{}", answer.body);
        let regrade = answer.json();
        if !regrade["finished_at"].is_null() {
            return regrade;
        }
        assert!(Instant::now() < give_up, "regrade not done: {regrade}");
        tokio::time::sleep(Duration::from_millis(25)).await;
    }
}

/// Proves that the class view shows each student's score that counts, each test's pass
/// share and the classic mistake with the student who makes it.
#[tokio::test(flavor = "multi_thread")]
async fn the_class_at_a_glance() {
    let Class {
        app,
        instructor,
        students,
    } = class().await;
    let answer = app
        .send(Req::get("/api/courses/el2320/labs/ekf-localization/class").who(&instructor))
        .await;
    assert_eq!(answer.status, StatusCode::OK, "{}", answer.body);
    let view = answer.json();
    let counting: Vec<(String, f64)> = view["students"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            (
                s["id"].as_str().unwrap().to_string(),
                s["counting"]["final_score"].as_f64().unwrap(),
            )
        })
        .collect();
    assert_eq!(counting[0], ("s1".to_string(), 1.0));
    assert!(counting[1].1 < 1.0 && counting[1].1 > 0.0, "{counting:?}");
    assert_eq!(counting[2], ("s3".to_string(), 0.0));
    let bins: Vec<u64> = view["distribution"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b.as_u64().unwrap())
        .collect();
    assert_eq!(bins.iter().sum::<u64>(), 3);
    assert_eq!((bins[0], bins[9]), (1, 1));
    let odometry = view["tests"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| {
            t["name"]
                .as_str()
                .unwrap()
                .starts_with("calculate_odometry")
        })
        .expect("a test of calculate_odometry");
    assert_eq!(
        (odometry["passed"].as_u64(), odometry["of"].as_u64()),
        (Some(1), Some(3))
    );
    let wheels = view["mistakes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["kind"] == "wheels_swapped")
        .unwrap_or_else(|| panic!("the wheels mistake among {}", view["mistakes"]));
    assert_eq!(wheels["students"], json!(["s2"]));
    assert_eq!(wheels["functions"], json!(["calculate_odometry"]));
    assert!(wheels["text"].as_str().unwrap().contains("wheel"));
    // Each student's tests of the submission that counts, by what each tests.
    let marks = |id: &str| {
        view["students"]
            .as_array()
            .unwrap()
            .iter()
            .find(|s| s["id"] == id)
            .unwrap()["tests"]
            .clone()
    };
    assert_eq!(marks("s1")["calculate_odometry"], true);
    assert_eq!(marks("s2")["calculate_odometry"], false);
    assert_eq!(marks("s3")["calculate_odometry"], false);
    assert_eq!(
        marks("s1").as_object().unwrap().len(),
        view["tests"].as_array().unwrap().len()
    );
    drop(students);
}

/// Proves that a regrade lists every score it changed, keeps the result it replaced
/// (the student sees both), records the grader, and is in the audit log.
#[tokio::test(flavor = "multi_thread")]
async fn a_regrade_lists_every_changed_score_and_keeps_the_replaced_results() {
    let Class {
        app,
        instructor,
        students,
    } = class().await;
    let (_, s2, s2_submission) = &students[1];
    // As if an older grader had graded s2's submission 0.5.
    app.database()
        .execute(
            "UPDATE submissions SET score = 0.5, grader = 'estlab 0.0.1 plan old' WHERE id = ?1",
            [s2_submission],
        )
        .unwrap();
    let answer = app
        .send(
            Req::post("/api/courses/el2320/regrades")
                .who(&instructor)
                .json(json!({ "scope": { "kind": "assignment" } })),
        )
        .await;
    assert_eq!(answer.status, StatusCode::ACCEPTED, "{}", answer.body);
    let started = answer.json();
    assert_eq!(started["total"], 3);
    let regrade = finished(&app, &instructor, started["url"].as_str().unwrap()).await;
    assert_eq!(
        (regrade["done"].as_u64(), regrade["total"].as_u64()),
        (Some(3), Some(3))
    );
    let changed = regrade["changed"].as_array().unwrap();
    assert_eq!(changed.len(), 1, "only s2's score changed: {changed:?}");
    assert_eq!(changed[0]["student"], "s2");
    assert_eq!(changed[0]["old_score"], 0.5);
    assert_eq!(changed[0]["old_final"], 0.5, "on time: nothing taken off");
    let new_score = changed[0]["new_score"].as_f64().unwrap();
    assert!(new_score < 0.99, "{new_score}");

    // The student sees that it was regraded, and the result it had.
    let answer = app
        .send(Req::get(&format!("/api/submissions/{s2_submission}")).who(s2))
        .await;
    let submission = answer.json();
    assert_eq!(submission["score"].as_f64(), Some(new_score));
    assert_eq!(submission["grader"], regrade["grader"]);
    let earlier = submission["earlier"].as_array().unwrap();
    assert_eq!(earlier.len(), 1);
    assert_eq!(earlier[0]["score"], 0.5);
    assert_eq!(earlier[0]["grader"], "estlab 0.0.1 plan old");
    assert_eq!(earlier[0]["replaced_by"], started["id"]);
    assert_eq!(earlier[0]["replaced_on_request_of"], "teacher@kth.example");
    assert!(earlier[0]["result"]["tests"].is_array());

    // Nothing to regrade is a clear refusal; the action is logged with its actor.
    let nothing = app
        .send(
            Req::post("/api/courses/el2320/regrades")
                .who(&instructor)
                .json(json!({ "scope": { "kind": "student", "of": "nobody" } })),
        )
        .await;
    assert_eq!(nothing.status, StatusCode::CONFLICT, "{}", nothing.body);
    assert!(nothing.error().contains("nothing to regrade"));
    let log = app
        .send(Req::get("/api/courses/el2320/audit").who(&instructor))
        .await
        .json();
    assert_eq!(log[0]["action"], "regrade");
    assert_eq!(log[0]["actor"], "teacher@kth.example");
    assert!(
        log[0]["detail"]
            .as_str()
            .unwrap()
            .contains("3 submission(s)")
    );
}

/// Proves that a regrade cut off by a stop is carried out after the restart, each
/// submission regraded once.
#[tokio::test(flavor = "multi_thread")]
async fn a_regrade_cut_off_by_a_stop_resumes_at_the_next_start() {
    let Class { app, students, .. } = class().await;
    let grader = app
        .state
        .grader
        .version(Exercise::EkfLocalization)
        .to_string();
    // Started, but its grading never begun before the stop.
    let (regrade, total) = app
        .store()
        .start_regrade(
            "el2320",
            Exercise::EkfLocalization,
            &Scope::Assignment,
            "teacher",
            &grader,
            app.now(),
        )
        .unwrap();
    assert_eq!(total, 3);
    let app = app.restart();
    let give_up = Instant::now() + GRADING_BOUND;
    let done = loop {
        let found = app.store().regrade("el2320", regrade).unwrap().unwrap();
        if found.finished_at.is_some() {
            break found;
        }
        assert!(Instant::now() < give_up, "not resumed: {found:?}");
        tokio::time::sleep(Duration::from_millis(25)).await;
    };
    assert_eq!((done.done, done.total), (3, 3));
    for (_, _, submission) in &students {
        assert_eq!(app.store().earlier_results(*submission).unwrap().len(), 1);
    }
}

/// Proves that an extension lets one student submit after the class's cutoff, on time
/// by their own dates, and is recorded with who granted it.
#[tokio::test(flavor = "multi_thread")]
async fn an_extension_moves_one_students_dates() {
    let app = App::new();
    let now = app.now();
    app.open_course("el2320");
    // After the class's cutoff (and signed in then: a session lasts 30 days).
    app.clock.set(now + SignedDuration::from_hours(40 * 24));
    let teacher = app.staff("el2320", "teacher@kth.example", Role::Assistant);
    let teacher = app.signed_in(&teacher).await;
    let late = app.enrol("el2320", "late");
    let other = app.enrol("el2320", "other");
    let (late, other) = (app.signed_in(&late).await, app.signed_in(&other).await);
    let submit = |who: &Who| {
        Req::post("/api/submissions")
            .who(who)
            .json(json!({ "source": quick_source("after the cutoff") }))
    };
    assert_eq!(app.send(submit(&late)).await.status, StatusCode::FORBIDDEN);
    for (body, status, says) in [
        (
            json!({ "student": "nobody", "due": "2030-01-01T00:00Z" }),
            StatusCode::NOT_FOUND,
            "has nobody with the id or email \"nobody\"",
        ),
        (
            json!({ "student": "late", "due": "2030-01-01T00:00" }),
            StatusCode::BAD_REQUEST,
            "time zone",
        ),
        (
            json!({ "student": "late", "due": "2030-01-02T00:00Z", "cutoff": "2030-01-01T00:00Z" }),
            StatusCode::BAD_REQUEST,
            "before `due`",
        ),
    ] {
        let answer = app
            .send(
                Req::post("/api/courses/el2320/extensions")
                    .who(&teacher)
                    .json(body),
            )
            .await;
        assert_eq!(answer.status, status, "{}", answer.body);
        assert!(answer.error().contains(says), "{}", answer.body);
    }
    let granted = app
        .send(
            Req::post("/api/courses/el2320/extensions")
                .who(&teacher)
                .json(json!({ "student": "late", "due": "2030-01-01T00:00Z" })),
        )
        .await;
    assert_eq!(granted.status, StatusCode::OK, "{}", granted.body);
    assert_eq!(granted.json()["granted_by"], "teacher@kth.example");
    let answer = app.send(submit(&late)).await;
    assert_eq!(answer.status, StatusCode::ACCEPTED, "{}", answer.body);
    assert_eq!(answer.json()["late_seconds"], 0);
    assert_eq!(app.send(submit(&other)).await.status, StatusCode::FORBIDDEN);
    let student = app
        .send(Req::get("/api/courses/el2320/labs/ekf-localization/students/late").who(&teacher))
        .await
        .json();
    assert_eq!(student["extension"]["due"], "2030-01-01T00:00:00Z");
    assert_eq!(student["policy"]["due"], "2030-01-01T00:00:00Z");
    let log = app
        .send(Req::get("/api/courses/el2320/audit").who(&teacher))
        .await
        .json();
    assert_eq!(log[0]["action"], "extension");
    assert!(
        log[0]["detail"]
            .as_str()
            .unwrap()
            .starts_with("late, ekf-localization")
    );
}

/// Proves that the exports hold each student's submission that counts: the gradebook's
/// rows, a results.json per student in each platform's format, a source per student.
#[tokio::test(flavor = "multi_thread")]
async fn the_exports_hold_each_students_submission_that_counts() {
    let Class {
        app, instructor, ..
    } = class().await;
    let export = |format: &str| {
        Req::get(&format!(
            "/api/courses/el2320/labs/ekf-localization/export?format={format}"
        ))
        .who(&instructor)
    };
    let csv = app.send(export("csv")).await;
    assert_eq!(csv.status, StatusCode::OK);
    assert!(
        csv.headers["content-disposition"]
            .to_str()
            .unwrap()
            .contains("el2320-ekf-localization-grades.csv")
    );
    let mut reader = csv::Reader::from_reader(csv.body.as_bytes());
    let rows: Vec<(String, String)> = reader
        .records()
        .map(|r| {
            let r = r.unwrap();
            (r[0].to_string(), r[7].to_string())
        })
        .collect();
    assert_eq!(rows[0], ("s1".to_string(), "1.0000".to_string()));
    assert_eq!(rows[2], ("s3".to_string(), "0.0000".to_string()));

    let gradescope = unzip(&app.send(export("gradescope")).await.raw);
    assert_eq!(
        gradescope
            .iter()
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>(),
        ["s1/results.json", "s2/results.json", "s3/results.json"]
    );
    let s1: serde_json::Value = serde_json::from_str(&gradescope[0].1).unwrap();
    assert!(s1["tests"].as_array().unwrap().len() > 8);
    let prairielearn = unzip(&app.send(export("prairielearn")).await.raw);
    let s3: serde_json::Value = serde_json::from_str(&prairielearn[2].1).unwrap();
    assert_eq!(s3["score"], 0.0);
    let sources = unzip(&app.send(export("sources")).await.raw);
    assert_eq!(sources[0].0, "s1.js");
    assert_eq!(sources[0].1, CORRECT);
    assert!(sources[2].1.contains("nothing yet"));
    let unknown = app.send(export("ods")).await;
    assert_eq!(unknown.status, StatusCode::BAD_REQUEST);
}

/// Proves that a regrade of a selection of the class covers exactly the selected
/// students' graded submissions (an id of nobody adds none), and that a selection with
/// none to regrade is refused.
#[tokio::test(flavor = "multi_thread")]
async fn a_regrade_of_a_selection_covers_its_students_only() {
    let Class {
        app,
        instructor,
        students,
    } = class().await;
    let start = |of: serde_json::Value| {
        Req::post("/api/courses/el2320/regrades")
            .who(&instructor)
            .json(json!({ "scope": { "kind": "students", "of": of } }))
    };
    let answer = app.send(start(json!(["s1", "s3", "u-nobody"]))).await;
    assert_eq!(answer.status, StatusCode::ACCEPTED, "{}", answer.body);
    let started = answer.json();
    assert_eq!(started["total"], 2);
    let regrade = finished(&app, &instructor, started["url"].as_str().unwrap()).await;
    assert_eq!(regrade["scope"], "students s1, s3, u-nobody");
    let s2 = students[1].2;
    let s2_earlier = app.store().earlier_results(s2).unwrap();
    assert!(s2_earlier.is_empty(), "s2 was not selected");
    for (_, _, submission) in [&students[0], &students[2]] {
        assert_eq!(app.store().earlier_results(*submission).unwrap().len(), 1);
    }
    let none = app.send(start(json!(["u-nobody"]))).await;
    assert_eq!(none.status, StatusCode::CONFLICT, "{}", none.body);
    assert!(none.body.contains("nothing to regrade"), "{}", none.body);
}
