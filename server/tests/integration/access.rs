//! Who may see and change what: the real web application, built in-process over a
//! database in a temporary directory, with a clock the tests set, asked as each kind of
//! person (and program) there is.
//!
//! - `access_matrix`: every route as anonymous, two students, the course's assistant and
//!   instructor, another course's instructor, an API token, a revoked and a made-up one;
//!   a student never receives anything of another student;
//! - `open_mode_until_a_course_exists`: without courses anyone submits and reads results
//!   (never sources); the first course closes that;
//! - `changes_from_other_sites_are_refused`: submitting, signing in and out only from
//!   estlab's own pages;
//! - `sign_in_limits_and_codes`: failed sign-ins limited per address (and by nothing
//!   else), one-time and expired codes;
//! - `deadlines_penalties_and_the_roster`: due date, late penalty and cutoff by the
//!   injected clock, a dropped student, a course without the exercise;
//! - `secrets_are_not_stored_in_clear`: codes, session keys and API tokens are not in
//!   the database files;
//! - `a_database_of_estlab_0_1_0_migrates_forward`: nothing of an 0.1.0 database is lost;
//! - `refusals_of_the_api_are_json_naming_what_is_wrong`: a body too large, a query that
//!   does not parse and a body of the wrong JSON are answered with `{"error": ...}`;
//! - `every_route_of_the_router_is_in_the_matrix` and
//!   `every_page_of_the_registry_is_in_the_matrix`: a new route is in the matrix too.
//!
//! `objects.rs` asks who may reach which object (another course's ids) through each
//! route; `scores.rs` holds the rules that decide a grade (the hourly limit, the score
//! that counts, the deadline's edges).
//!
//! The server grades submissions on tasks of its own; a test waits for a result by
//! polling the database, for at most `GRADING_BOUND`.

use crate::common;

use axum::http::{StatusCode, header};
use common::*;
use estlab::courses::codes::new_code;
use estlab::courses::deadline::{Counts, Policy};
use estlab::store::{Role, Status, Store};
use jiff::SignedDuration;
use labs::Exercise;
use serde_json::{Value, json};
use std::path::Path;
// ---- 1. the access-control matrix ----

/// The principals, in the order of the matrix's columns.
const PRINCIPALS: [&str; 9] = [
    "anonymous",
    "student A",
    "student B",
    "el2320's assistant",
    "el2320's instructor",
    "other's instructor",
    "el2320 API token",
    "revoked token",
    "made-up token",
];

/// The status each principal gets: `{A}` and `{B}` stand for the students' submissions.
/// Routes that look at who asks answer a token that is revoked or unknown with 401,
/// pages included (a browser never sends one); the rest ignore it.
#[rustfmt::skip]
const MATRIX: &[(&str, &str, [u16; 9])] = &[
    //                                        anon  A    B    TA   inst other token rev  bad
    ("GET",  "/",                              [200, 200, 200, 200, 200, 200, 200, 401, 401]),
    ("GET",  "/car",                           [200, 200, 200, 200, 200, 200, 200, 401, 401]),
    ("GET",  "/odometry",                      [200, 200, 200, 200, 200, 200, 200, 401, 401]),
    ("GET",  "/fusion",                        [200, 200, 200, 200, 200, 200, 200, 401, 401]),
    // The real trials of --datasets are shown on a public page: anyone may read them.
    ("GET",  "/api/datasets/northstar",        [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/mrclam",                        [200, 200, 200, 200, 200, 200, 200, 401, 401]),
    ("GET",  "/api/datasets/mrclam",           [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    // This server has no data sets: no robot of them, for anyone.
    ("GET",  "/api/datasets/mrclam/robot?dataset=6&robot=1", [404, 404, 404, 404, 404, 404, 404, 404, 404]),
    ("GET",  "/ekf",                           [200, 200, 200, 200, 200, 200, 200, 401, 401]),
    ("GET",  "/ekf/code",                      [200, 200, 200, 200, 200, 200, 200, 401, 401]),
    ("GET",  "/ekf/starter.js",                [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/ekf/starter.py",                [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/ekf/starter.m",                 [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/odometry/code",                 [200, 200, 200, 200, 200, 200, 200, 401, 401]),
    ("GET",  "/odometry/starter.js",           [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/odometry/starter.py",           [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/odometry/starter.m",            [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/fusion/code",                   [200, 200, 200, 200, 200, 200, 200, 401, 401]),
    ("GET",  "/fusion/starter.js",             [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/fusion/starter.py",             [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/fusion/starter.m",              [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/mrclam/code",                   [200, 200, 200, 200, 200, 200, 200, 401, 401]),
    ("GET",  "/mrclam/starter.js",             [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/mrclam/starter.py",             [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/mrclam/starter.m",              [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/signin",                        [200, 200, 200, 200, 200, 200, 200, 401, 401]),
    // Only a signed-in person has a page of their own; the rest are sent to sign in.
    ("GET",  "/me",                            [303, 200, 200, 200, 200, 200, 303, 401, 401]),
    ("GET",  "/healthz",                       [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    // The sandbox's metrics: to the data directory's metrics token only (below).
    ("GET",  "/metrics",                       [401, 401, 401, 401, 401, 401, 401, 401, 401]),
    ("GET",  "/favicon.svg",                   [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    ("GET",  "/favicon.ico",                   [200, 200, 200, 200, 200, 200, 200, 200, 200]),
    // A token is nobody: courses true, member null (like anonymous).
    ("GET",  "/api/me",                        [200, 200, 200, 200, 200, 200, 200, 401, 401]),
    ("GET",  "/api/me/submissions",            [401, 200, 200, 200, 200, 200, 401, 401, 401]),
    // A submission: its student and their course's staff; anyone else 404, as if absent.
    ("GET",  "/api/submissions/{A}",           [404, 200, 404, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/submissions/{B}",           [404, 404, 200, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/submissions/999999",        [404, 404, 404, 404, 404, 404, 404, 401, 401]),
    // A course: its staff only; anyone else 404, as if there were no such course.
    ("GET",  "/api/courses/el2320",            [404, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/courses/el2320/submissions",[404, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/courses/other",             [404, 404, 404, 404, 404, 200, 404, 401, 401]),
    ("GET",  "/api/courses/other/submissions", [404, 404, 404, 404, 404, 200, 404, 401, 401]),
    // The instructor's side: the course's staff and its token only.
    ("GET",  "/courses/el2320/ekf-localization",                    [303, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/courses/el2320/ekf-localization/students/{A_ID}",    [303, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/courses/el2320/labs/ekf-localization/class",            [404, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/courses/el2320/labs/ekf-localization/students/{A_ID}",  [404, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/courses/el2320/labs/ekf-localization/export?format=csv",     [404, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/courses/el2320/labs/ekf-localization/export?format=sources", [404, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/courses/other/labs/ekf-localization/class",             [404, 404, 404, 404, 404, 200, 404, 401, 401]),
    // The class challenge's ranking switch, for the course's staff; sent without a body,
    // they get the 400 of a body checked after who asks.
    ("POST", "/api/courses/el2320/labs/ekf-localization/ranking",          [404, 404, 404, 400, 400, 404, 400, 401, 401]),
    ("POST", "/api/courses/other/labs/ekf-localization/ranking",           [404, 404, 404, 404, 404, 400, 404, 401, 401]),
    // The languages an assignment takes, for the course's staff, alike.
    ("POST", "/api/courses/el2320/labs/ekf-localization/languages",        [404, 404, 404, 400, 400, 404, 400, 401, 401]),
    ("POST", "/api/courses/other/labs/ekf-localization/languages",         [404, 404, 404, 404, 404, 400, 404, 401, 401]),
    // The written questions' page, for the course's people; their API alike.
    ("GET",  "/courses/el2320/ekf-localization/questions",                 [303, 200, 200, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/courses/other/ekf-localization/questions",                  [303, 404, 404, 404, 404, 200, 404, 401, 401]),
    // The written questions: the course's students (without what answers are checked
    // against) and staff (in full); other sets from its instructors, answers from its
    // students only; sent without a body, they get the 400 of a body checked after who asks.
    ("GET",  "/api/courses/el2320/labs/ekf-localization/questions",        [404, 200, 200, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/courses/other/labs/ekf-localization/questions",         [404, 404, 404, 404, 404, 200, 404, 401, 401]),
    ("POST", "/api/courses/el2320/labs/ekf-localization/questions",        [404, 404, 404, 403, 400, 404, 400, 401, 401]),
    ("POST", "/api/courses/other/labs/ekf-localization/questions",         [404, 404, 404, 404, 404, 400, 404, 401, 401]),
    ("POST", "/api/courses/el2320/labs/ekf-localization/answers",          [404, 400, 400, 403, 403, 404, 403, 401, 401]),
    ("POST", "/api/courses/other/labs/ekf-localization/answers",           [404, 404, 404, 404, 404, 403, 404, 401, 401]),
    // Review rounds: run by the course's staff; the sheets reviewed by its students only
    // (staff are told so); sent without a body, the 400 of a body checked after who asks.
    ("GET",  "/api/courses/el2320/labs/ekf-localization/rounds",           [404, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/courses/other/labs/ekf-localization/rounds",            [404, 404, 404, 404, 404, 200, 404, 401, 401]),
    ("POST", "/api/courses/el2320/labs/ekf-localization/rounds",           [404, 404, 404, 400, 400, 404, 400, 401, 401]),
    ("POST", "/api/courses/el2320/labs/ekf-localization/rounds/1",         [404, 404, 404, 400, 400, 404, 400, 401, 401]),
    ("GET",  "/api/courses/el2320/labs/ekf-localization/reviews",          [404, 200, 200, 403, 403, 404, 403, 401, 401]),
    ("GET",  "/api/courses/el2320/labs/ekf-localization/reviews/1/1",      [404, 404, 404, 403, 403, 404, 403, 401, 401]),
    ("POST", "/api/courses/el2320/labs/ekf-localization/reviews/1/1",      [404, 400, 400, 403, 403, 404, 403, 401, 401]),
    // The report: the page for the course's people (staff read the class's); each
    // student's own through `report` (staff are told theirs is `reports/{student}`), which
    // only its staff read and judge. Sent without a body: the 400 of a body checked after
    // who asks.
    ("GET",  "/courses/el2320/ekf-localization/report",                    [303, 200, 200, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/courses/other/ekf-localization/report",                     [303, 404, 404, 404, 404, 200, 404, 401, 401]),
    ("GET",  "/api/courses/el2320/labs/ekf-localization/report",           [404, 200, 200, 403, 403, 404, 403, 401, 401]),
    ("GET",  "/api/courses/el2320/labs/ekf-localization/report/runs",      [404, 200, 200, 403, 403, 404, 403, 401, 401]),
    ("POST", "/api/courses/el2320/labs/ekf-localization/report/analyses",  [404, 400, 400, 403, 403, 404, 403, 401, 401]),
    ("POST", "/api/courses/el2320/labs/ekf-localization/report/hand-in",   [404, 400, 400, 403, 403, 404, 403, 401, 401]),
    ("GET",  "/api/courses/el2320/labs/ekf-localization/reports",          [404, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/courses/other/labs/ekf-localization/reports",           [404, 404, 404, 404, 404, 200, 404, 401, 401]),
    ("GET",  "/api/courses/el2320/labs/ekf-localization/reports/{A_ID}",   [404, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("GET",  "/api/courses/el2320/labs/ekf-localization/reports/{A_ID}/runs", [404, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("POST", "/api/courses/el2320/labs/ekf-localization/reports/{A_ID}/rubric", [404, 404, 404, 400, 400, 404, 400, 401, 401]),
    ("POST", "/api/courses/el2320/regrades",   [404, 404, 404, 202, 202, 404, 202, 401, 401]),
    ("GET",  "/api/courses/el2320/regrades/1", [404, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("POST", "/api/courses/el2320/extensions", [404, 404, 404, 200, 200, 404, 200, 401, 401]),
    // Sent without a reason: staff get the 400 of a body checked after who asks.
    ("POST", "/api/courses/el2320/submissions/{A}/waiver", [404, 404, 404, 400, 400, 404, 400, 401, 401]),
    ("GET",  "/api/courses/el2320/audit",      [404, 404, 404, 200, 200, 404, 200, 401, 401]),
    // The course's set-up: its page for its staff, its changes for its instructors (and
    // an instructor's token); sent without a body, they get the 400 of a body checked
    // after who asks. `{T}` is a revoked token of el2320's.
    ("GET",  "/courses/el2320",                          [303, 404, 404, 200, 200, 404, 200, 401, 401]),
    ("POST", "/api/courses/el2320/staff",                [404, 404, 404, 403, 400, 404, 400, 401, 401]),
    ("POST", "/api/courses/el2320/roster/preview",       [404, 404, 404, 403, 400, 404, 400, 401, 401]),
    ("POST", "/api/courses/el2320/roster",               [404, 404, 404, 403, 400, 404, 400, 401, 401]),
    ("POST", "/api/courses/el2320/codes",                [404, 404, 404, 403, 400, 404, 400, 401, 401]),
    ("GET",  "/api/courses/el2320/codes/1",              [404, 404, 404, 403, 404, 404, 404, 401, 401]),
    ("POST", "/api/courses/el2320/assignments",          [404, 404, 404, 403, 400, 404, 400, 401, 401]),
    ("POST", "/api/courses/el2320/tokens",               [404, 404, 404, 403, 400, 404, 400, 401, 401]),
    ("POST", "/api/courses/el2320/tokens/{T}/revoke",    [404, 404, 404, 403, 200, 404, 200, 401, 401]),
    // Anyone signed in may run a phase of the shown cases on the server (staff try files
    // too); nobody anonymously once the server runs courses, and no token.
    ("POST", "/api/phases",                    [401, 200, 200, 200, 200, 200, 403, 401, 401]),
    // Students submit for themselves; staff and tokens do not; nobody anonymously.
    ("POST", "/api/submissions",               [401, 202, 202, 403, 403, 403, 403, 401, 401]),
    // Last: it ends the sessions.
    ("POST", "/signout",                       [303, 303, 303, 303, 303, 303, 303, 303, 303]),
];

const A_ID: &str = "u-alpha-7731";
const A_NAME: &str = "Ada Alphaworth";
const A_EMAIL: &str = "alpha7731@student.example";
const A_MARKER: &str = "marker-A-5e1f0c";
const B_ID: &str = "u-bravo-4412";
const B_NAME: &str = "Bob Bravington";
const B_EMAIL: &str = "bravo4412@student.example";
const B_MARKER: &str = "marker-B-9c3d27";

/// A 404 for a submission that exists, with its id written as N: identical to the 404
/// for one that does not.
fn not_found_shape(answer: &Answer, id: &str) -> Value {
    let mut body: Value =
        serde_json::from_str(&answer.body).unwrap_or_else(|_| Value::String(answer.body.clone()));
    if let Some(error) = body.get("error").and_then(Value::as_str) {
        body["error"] = Value::String(error.replace(id, "N"));
    }
    json!({
        "status": answer.status.as_u16(),
        "content-type": answer.headers.get(header::CONTENT_TYPE).and_then(|v| v.to_str().ok()),
        "body": body,
    })
}

/// Proves that every route answers each kind of asker as the matrix says; that a
/// student reads their own submission with its source, and another student's is a 404
/// indistinguishable from a submission that does not exist; that staff read their
/// course's submissions with sources and another course's staff cannot; and that
/// nothing a student receives anywhere names the other student or shows their code.
#[tokio::test(flavor = "multi_thread")]
async fn access_matrix() {
    let app = App::new();
    let store = app.store();
    let now = app.now();
    store
        .create_course("el2320", "Applied Estimation", now)
        .unwrap();
    store.create_course("other", "Another Course", now).unwrap();
    store
        .import_roster(
            "el2320",
            &[
                roster_line(A_ID, A_NAME, A_EMAIL),
                roster_line(B_ID, B_NAME, B_EMAIL),
            ],
        )
        .unwrap();
    store
        .assign("el2320", Exercise::EkfLocalization, &open_policy(now))
        .unwrap();
    store
        .assign("other", Exercise::EkfLocalization, &open_policy(now))
        .unwrap();
    let student_a = store.member("el2320", A_ID).unwrap();
    let student_b = store.member("el2320", B_ID).unwrap();
    let assistant = app.staff("el2320", "ta@kth.example", Role::Assistant);
    let instructor = app.staff("el2320", "teacher@kth.example", Role::Instructor);
    let other = app.staff("other", "prof@other.example", Role::Instructor);
    let (_, token) = store.create_token("el2320", Role::Instructor, now).unwrap();
    let (revoked_id, revoked) = store.create_token("el2320", Role::Instructor, now).unwrap();
    assert!(store.revoke_token("el2320", revoked_id, now).unwrap());
    let made_up = format!("estlab_{}", "0".repeat(64));

    let principals = [
        Who::Anonymous,
        app.signed_in(&student_a).await,
        app.signed_in(&student_b).await,
        app.signed_in(&assistant).await,
        app.signed_in(&instructor).await,
        app.signed_in(&other).await,
        Who::Token(token),
        Who::Token(revoked),
        Who::Token(made_up),
    ];
    let logins = [
        None,
        Some(A_ID),
        Some(B_ID),
        Some("ta@kth.example"),
        Some("teacher@kth.example"),
        Some("prof@other.example"),
        None,
        None,
        None,
    ];
    // What each would submit: the students their marked code, the rest a file of their
    // own (it must not be taken).
    let sources = [
        quick_source("anonymous-try"),
        quick_source(A_MARKER),
        quick_source(B_MARKER),
        quick_source("staff-try"),
        quick_source("staff-try"),
        quick_source("staff-try"),
        quick_source("token-try"),
        quick_source("token-try"),
        quick_source("token-try"),
    ];

    let (a_submission, _) = app.submit_graded(&principals[1], &sources[1]).await;
    let (b_submission, _) = app.submit_graded(&principals[2], &sources[2]).await;
    let (a_id, b_id) = (a_submission.to_string(), b_submission.to_string());
    let missing = app.send(Req::get("/api/submissions/999999")).await;
    assert_eq!(missing.status, StatusCode::NOT_FOUND, "{}", missing.body);
    let missing_shape = not_found_shape(&missing, "999999");

    let mut problems = Vec::new();
    // Every body each principal received, to look for what they must not see.
    let mut received: Vec<Vec<(String, String)>> = vec![Vec::new(); PRINCIPALS.len()];
    for (method, pattern, expected) in MATRIX {
        let path = pattern
            .replace("{A}", &a_id)
            .replace("{B}", &b_id)
            .replace("{A_ID}", A_ID)
            .replace("{T}", &revoked_id.to_string());
        for (i, who) in principals.iter().enumerate() {
            let mut request = if *method == "GET" {
                Req::get(&path)
            } else {
                Req::post(&path)
            };
            if path == "/api/submissions" {
                request = request.json(json!({ "source": sources[i] }));
            }
            if path == "/api/phases" {
                request = request.json(json!({
                    "lab": "odometry", "seed": 7, "phase": "wheel_noise", "source": sources[i],
                }));
            }
            if path == "/api/courses/el2320/regrades" {
                request =
                    request.json(json!({ "scope": { "kind": "submission", "of": a_submission } }));
            }
            if path == "/api/courses/el2320/extensions" {
                request = request.json(json!({ "student": A_ID, "due": "2030-01-01T00:00Z" }));
            }
            let answer = app.send(request.who(who)).await;
            let asked = format!("{method} {path} as {}", PRINCIPALS[i]);
            let mut problem = |what: String| problems.push(format!("{asked}: {what}"));
            if answer.status.as_u16() != expected[i] {
                problem(format!(
                    "expected {}, got {}: {}",
                    expected[i],
                    answer.status.as_u16(),
                    answer.body.chars().take(300).collect::<String>()
                ));
            }
            let ok = answer.status == StatusCode::OK;

            // A submission read: with its student's code; refused: as if absent.
            for (id, marker, student) in [(&a_id, A_MARKER, A_ID), (&b_id, B_MARKER, B_ID)] {
                if path != format!("/api/submissions/{id}") {
                    continue;
                }
                if ok {
                    let body = answer.json();
                    if !body["source"].as_str().is_some_and(|s| s.contains(marker)) {
                        problem("200 without the student's source".into());
                    }
                    if body["student"] != student {
                        problem(format!("the student is {}", body["student"]));
                    }
                } else if answer.status == StatusCode::NOT_FOUND {
                    let shape = not_found_shape(&answer, id);
                    if shape != missing_shape {
                        problem(format!(
                            "this 404 differs from a missing submission's: {shape} vs {missing_shape}"
                        ));
                    }
                }
            }
            if path == "/api/me" && ok {
                let body = answer.json();
                if body["courses"] != true {
                    problem(format!("courses is {}", body["courses"]));
                }
                let login = body["member"]["login"].as_str();
                if login != logins[i] {
                    problem(format!("the member is {}", body["member"]));
                }
            }
            if path == "/me"
                && answer.status == StatusCode::SEE_OTHER
                && answer.location() != Some("/signin")
            {
                problem(format!("sent to {:?}", answer.location()));
            }
            if path == "/signout" && answer.session().is_some() {
                problem("signing out set a session".into());
            }
            if path == "/api/courses/el2320/submissions" && ok {
                let list = answer.json();
                let students: Vec<&str> = list
                    .as_array()
                    .map(|list| list.iter().filter_map(|s| s["student"].as_str()).collect())
                    .unwrap_or_default();
                if !(students.contains(&A_ID) && students.contains(&B_ID)) {
                    problem(format!("the list names {students:?}"));
                }
            }
            if path == "/api/submissions" && answer.status == StatusCode::ACCEPTED {
                app.graded(answer.json()["id"].as_i64().unwrap()).await;
            }
            received[i].push((asked, answer.body));
        }
    }

    // Nothing of one student reaches the other, nor anyone outside el2320's staff.
    let a_things = [A_MARKER, A_ID, A_NAME, A_EMAIL];
    let b_things = [B_MARKER, B_ID, B_NAME, B_EMAIL];
    // Anonymous, the other course's instructor, the revoked and the made-up token.
    let outsiders = [0, 5, 7, 8];
    for (i, bodies) in received.iter().enumerate() {
        let forbidden: Vec<&str> = match i {
            1 => b_things.to_vec(),
            2 => a_things.to_vec(),
            i if outsiders.contains(&i) => a_things.iter().chain(&b_things).copied().collect(),
            _ => continue,
        };
        for (asked, body) in bodies {
            for thing in &forbidden {
                if body.contains(thing) {
                    problems.push(format!(
                        "{} received {thing:?} in {asked}: {}",
                        PRINCIPALS[i],
                        body.chars().take(300).collect::<String>()
                    ));
                }
            }
        }
    }

    // Signing out ended the sessions (of the principals signed in: columns 1 to 5).
    for (i, who) in principals.iter().enumerate().take(6).skip(1) {
        let answer = app.send(Req::get("/api/me").who(who)).await;
        if answer.status != StatusCode::OK || !answer.json()["member"].is_null() {
            problems.push(format!(
                "{} is still signed in after signing out: {} {}",
                PRINCIPALS[i], answer.status, answer.body
            ));
        }
    }

    assert!(
        problems.is_empty(),
        "{} problem(s):\n{}",
        problems.len(),
        problems.join("\n")
    );
}

// ---- 2. open mode ----

/// Proves that a server without courses takes a submission from anyone under any id and
/// shows its result, never its code; and that the first course ends this: anonymous
/// submissions are refused and the open-mode submission is no longer anyone's to read.
#[tokio::test(flavor = "multi_thread")]
async fn open_mode_until_a_course_exists() {
    let app = App::new();
    let body = json!({ "student": "x", "source": quick_source("open-mode") });
    let answer = app
        .send(Req::post("/api/submissions").json(body.clone()))
        .await;
    assert_eq!(answer.status, StatusCode::ACCEPTED, "{}", answer.body);
    let id = answer.json()["id"].as_i64().unwrap();
    assert_eq!(
        answer.location(),
        Some(format!("/api/submissions/{id}").as_str())
    );
    app.graded(id).await;

    let read = app.send(Req::get(&format!("/api/submissions/{id}"))).await;
    assert_eq!(read.status, StatusCode::OK, "{}", read.body);
    let read = read.json();
    assert_eq!(read["student"], "x");
    assert_eq!(read["status"], "graded");
    assert!(read["result"].is_object(), "{read}");
    assert!(read.get("source").is_none(), "open mode shows code: {read}");

    app.store()
        .create_course("el2320", "Applied Estimation", app.now())
        .unwrap();
    let refused = app.send(Req::post("/api/submissions").json(body)).await;
    assert_eq!(refused.status, StatusCode::UNAUTHORIZED, "{}", refused.body);
    assert!(refused.error().contains("sign in"), "{}", refused.body);
    let gone = app.send(Req::get(&format!("/api/submissions/{id}"))).await;
    assert_eq!(gone.status, StatusCode::NOT_FOUND, "{}", gone.body);
    // Nor does the new course's staff read it: it belongs to none of its people.
    let instructor = app.staff("el2320", "teacher@kth.example", Role::Instructor);
    let instructor = app.signed_in(&instructor).await;
    let staff = app
        .send(Req::get(&format!("/api/submissions/{id}")).who(&instructor))
        .await;
    assert_eq!(staff.status, StatusCode::NOT_FOUND, "{}", staff.body);
    assert_eq!(app.count(), 1);
}

// ---- 3. other sites ----

/// Proves that a page on another site cannot submit, sign out or sign in in a signed-in
/// student's name (by `Origin` or by `Sec-Fetch-Site`), that nothing is stored then,
/// and that a request from estlab's own origin passes.
#[tokio::test(flavor = "multi_thread")]
async fn changes_from_other_sites_are_refused() {
    let app = App::new();
    app.open_course("el2320");
    let student = app.enrol("el2320", "u-cross-1");
    let code = app.code(&student);
    // The session cookie itself is out of other sites' and scripts' reach.
    let answer = app.send(Req::sign_in(&code)).await;
    assert_eq!(answer.status, StatusCode::SEE_OTHER, "{}", answer.body);
    let cookie = answer.headers[header::SET_COOKIE].to_str().unwrap();
    for attribute in ["HttpOnly", "SameSite=Lax", "Path=/"] {
        assert!(cookie.contains(attribute), "{cookie}");
    }
    assert!(!cookie.contains("Secure"), "Secure without HTTPS: {cookie}");
    let who = Who::Session(answer.session().unwrap());
    let submit = || {
        Req::post("/api/submissions")
            .who(&who)
            .header("host", "estlab.test")
            .json(json!({ "source": quick_source("cross-site") }))
    };

    // A page of another origin on the same site (another port, a sibling subdomain) is
    // another site too: SameSite=Lax cookies go with its requests.
    for (name, value) in [
        ("origin", "http://evil.example"),
        ("sec-fetch-site", "cross-site"),
        ("sec-fetch-site", "same-site"),
        ("origin", "http://estlab.test:8081"),
    ] {
        let answer = app.send(submit().header(name, value)).await;
        assert_eq!(
            answer.status,
            StatusCode::FORBIDDEN,
            "{name}: {}",
            answer.body
        );
        assert!(answer.error().contains("another site"), "{}", answer.body);
        assert_eq!(
            app.count(),
            0,
            "stored a submission from another site ({name})"
        );
    }

    // From estlab's own page (Origin is the Host it was asked at): taken.
    let answer = app
        .send(submit().header("origin", "http://estlab.test"))
        .await;
    assert_eq!(answer.status, StatusCode::ACCEPTED, "{}", answer.body);
    assert_eq!(app.count(), 1);
    app.graded(answer.json()["id"].as_i64().unwrap()).await;

    // Signing out from another site: refused, and the session goes on.
    let answer = app
        .send(
            Req::post("/signout")
                .who(&who)
                .header("origin", "http://evil.example"),
        )
        .await;
    assert_eq!(answer.status, StatusCode::FORBIDDEN, "{}", answer.body);
    assert!(answer.error().contains("another site"), "{}", answer.body);
    let me = app.send(Req::get("/api/me").who(&who)).await.json();
    assert_eq!(me["member"]["login"], "u-cross-1", "{me}");

    // Signing in from another site, even with the right code: refused, no session.
    for (name, value) in [
        ("origin", "http://evil.example"),
        ("sec-fetch-site", "cross-site"),
        ("sec-fetch-site", "same-site"),
    ] {
        let answer = app.send(Req::sign_in(&code).header(name, value)).await;
        assert_eq!(
            answer.status,
            StatusCode::FORBIDDEN,
            "{name}: {}",
            answer.body
        );
        assert!(answer.error().contains("another site"), "{}", answer.body);
        assert_eq!(answer.session(), None);
    }
}

// ---- 4. sign-in limits and codes ----

/// A well-formed code no one was given.
fn unknown_code() -> String {
    new_code().text
}

/// A code with a real selector and a wrong secret: its last characters changed.
fn wrong_secret(code: &str) -> String {
    let (head, tail) = code.split_at(code.len() - 4);
    let wrong = if tail == "0000" { "1111" } else { "0000" };
    format!("{head}{wrong}")
}

/// Proves that an address is refused after 30 codes of nobody's while its right code
/// still gets in; that 10 wrong tries of a code refuse that code from that address (even
/// the right one) while another address signs in with it; that 50 wrong secrets for one
/// person's code from 50 addresses refuse none of them; that the refusal ends when the
/// window has passed; that a one-time code works once; and that an expired code does not
/// work.
#[tokio::test(flavor = "multi_thread")]
async fn sign_in_limits_and_codes() {
    let app = App::new();
    let now = app.now();
    app.store()
        .create_course("el2320", "Applied Estimation", now)
        .unwrap();
    let student = app.enrol("el2320", "u-limit-1");
    let code = app.code(&student);

    // Guesses per address: a burst of 40 codes of nobody's at once, of which 30 are
    // checked and the rest refused; a code that is someone's is not held up by them.
    let guesser = peer(192, 0, 2, 1);
    let burst: Vec<_> = (0..40)
        .map(|_| app.send(Req::sign_in(&unknown_code()).sent_from(guesser)))
        .collect();
    let answers = futures::future::join_all(burst).await;
    let count = |status| answers.iter().filter(|a| a.status == status).count();
    assert_eq!(count(StatusCode::UNAUTHORIZED), 30, "checked");
    assert_eq!(count(StatusCode::TOO_MANY_REQUESTS), 10, "refused");
    assert!(answers.iter().all(|a| a.session().is_none()));
    let refused = answers
        .iter()
        .find(|a| a.status == StatusCode::TOO_MANY_REQUESTS)
        .unwrap();
    assert!(
        refused.body.contains("codes that are nobody"),
        "{}",
        refused.body
    );
    app.sign_in(&code, guesser).await;

    // Tries of one code per address: 10 wrong secrets, then even the right one is refused.
    let wrong = wrong_secret(&code);
    assert_ne!(wrong, code);
    for i in 0..10 {
        let answer = app.send(Req::sign_in(&wrong).sent_from(guesser)).await;
        assert_eq!(answer.status, StatusCode::UNAUTHORIZED, "wrong secret {i}");
    }
    let answer = app.send(Req::sign_in(&code).sent_from(guesser)).await;
    assert_eq!(
        answer.status,
        StatusCode::TOO_MANY_REQUESTS,
        "{}",
        answer.body
    );
    assert!(answer.body.contains("Too many"), "{}", answer.body);
    assert!(answer.body.contains("from your address"), "{}", answer.body);
    assert_eq!(answer.session(), None);
    // Not behind a proxy, `X-Forwarded-For` is the client's word only: it changes nothing.
    let answer = app
        .send(
            Req::sign_in(&code)
                .sent_from(guesser)
                .header("x-forwarded-for", "203.0.113.99"),
        )
        .await;
    assert_eq!(
        answer.status,
        StatusCode::TOO_MANY_REQUESTS,
        "{}",
        answer.body
    );
    // Another address is not held up.
    app.sign_in(&code, peer(192, 0, 2, 2)).await;

    // Wrong secrets for a real person's code from 50 addresses refuse none of them: the
    // right code gets in from an address that failed (server/tests/signin_limits.rs has
    // the classroom's case).
    for i in 0..50u8 {
        let answer = app
            .send(Req::sign_in(&wrong).sent_from(peer(198, 51, 100, i)))
            .await;
        assert_eq!(answer.status, StatusCode::UNAUTHORIZED, "wrong secret {i}");
    }
    let tried = peer(198, 51, 100, 7);
    app.sign_in(&code, tried).await;

    // Once the window has passed, the right code works again, from either address.
    app.clock
        .set(now + SignedDuration::from_mins(15) + SignedDuration::from_secs(1));
    app.sign_in(&code, tried).await;
    app.sign_in(&code, guesser).await;

    // A one-time code of a member of staff: once.
    let assistant = app.staff("el2320", "ta@kth.example", Role::Assistant);
    let once = new_code();
    app.store()
        .add_code(assistant.id, &once, true, None, app.now())
        .unwrap();
    let from = peer(203, 0, 113, 2);
    app.sign_in(&once.text, from).await;
    let again = app.send(Req::sign_in(&once.text).sent_from(from)).await;
    assert_eq!(again.status, StatusCode::UNAUTHORIZED, "{}", again.body);
    assert_eq!(again.session(), None);

    // A code that expired before now.
    let late = app.enrol("el2320", "u-limit-2");
    let expired = new_code();
    app.store()
        .add_code(
            late.id,
            &expired,
            false,
            Some(app.now() - SignedDuration::from_hours(1)),
            now,
        )
        .unwrap();
    let answer = app.send(Req::sign_in(&expired.text).sent_from(from)).await;
    assert_eq!(answer.status, StatusCode::UNAUTHORIZED, "{}", answer.body);
    assert_eq!(answer.session(), None);

    // A session lasts 30 days, by the server's clock.
    let session = app.sign_in(&code, from).await;
    let signed_in_at = app.now();
    app.clock
        .set(signed_in_at + SignedDuration::from_hours(30 * 24));
    let me = app.send(Req::get("/api/me").who(&session)).await.json();
    assert_eq!(me["member"]["login"], "u-limit-1", "{me}");
    app.clock
        .set(signed_in_at + SignedDuration::from_hours(30 * 24) + SignedDuration::from_secs(1));
    let me = app.send(Req::get("/api/me").who(&session)).await.json();
    assert!(me["member"].is_null(), "the session outlived 30 days: {me}");
}

// ---- 5. deadlines ----

/// Proves, with the clock set around an assignment's dates, that a submission before
/// the due date is on time, one a day and a minute late is taken with two days'
/// penalty (and its score, and the score that counts, are cut by it), and one after the
/// cutoff is refused and not stored; that a student dropped from the roster may no
/// longer submit nor run a file on the server, but still reads what they submitted; and
/// that a course that has not opened the exercise takes nothing.
#[tokio::test(flavor = "multi_thread")]
async fn deadlines_penalties_and_the_roster() {
    let app = App::new();
    let store = app.store();
    let due = at("2026-12-15T22:59:00Z");
    let cutoff = due + SignedDuration::from_hours(3 * 24);
    app.clock.set(due - SignedDuration::from_hours(1));
    store
        .create_course("el2320", "Applied Estimation", app.now())
        .unwrap();
    store
        .assign(
            "el2320",
            Exercise::EkfLocalization,
            &Policy {
                due,
                cutoff,
                penalty_per_day: 0.1,
                counts: Counts::Best,
            },
        )
        .unwrap();
    let student = app.enrol("el2320", "u-late-1");
    app.enrol("el2320", "u-late-2");
    let who = app.signed_in(&student).await;

    // An hour before the due date: on time.
    let (on_time, accepted) = app.submit_graded(&who, &quick_source("on time")).await;
    assert_eq!(accepted["late_seconds"], 0, "{accepted}");
    assert_eq!(accepted["penalty"], 0.0, "{accepted}");

    // A day and a minute late: two days begun, 20 % off the score.
    app.clock
        .set(due + SignedDuration::from_hours(24) + SignedDuration::from_mins(1));
    let (late, accepted) = app.submit_graded(&who, CORRECT).await;
    assert_eq!(accepted["late_seconds"], 24 * 3600 + 60, "{accepted}");
    let penalty = accepted["penalty"].as_f64().unwrap();
    assert!((penalty - 0.2).abs() < 1e-9, "{accepted}");
    let read = app
        .send(Req::get(&format!("/api/submissions/{late}")).who(&who))
        .await;
    assert_eq!(read.status, StatusCode::OK, "{}", read.body);
    let read = read.json();
    assert_eq!(read["score"], 1.0, "the correct file scores 1: {read}");
    let final_score = read["final_score"].as_f64().unwrap();
    assert!((final_score - 0.8).abs() < 1e-9, "{read}");
    let me = app.send(Req::get("/api/me").who(&who)).await.json();
    let assignment = &me["assignments"][0];
    assert_eq!(
        assignment["history"].as_array().map(Vec::len),
        Some(2),
        "{me}"
    );
    let counting = assignment["counting_score"].as_f64().unwrap();
    assert!((counting - 0.8).abs() < 1e-9, "the best counts: {me}");

    // A second past the cutoff: refused, nothing stored.
    app.clock.set(cutoff + SignedDuration::from_secs(1));
    let before = app.count();
    let answer = app
        .send(
            Req::post("/api/submissions")
                .who(&who)
                .json(json!({ "source": quick_source("too late") })),
        )
        .await;
    assert_eq!(answer.status, StatusCode::FORBIDDEN, "{}", answer.body);
    assert!(answer.error().contains("cutoff"), "{}", answer.body);
    assert_eq!(app.count(), before);

    // Dropped from the roster (while the exercise is open again): no more submitting,
    // but what they submitted is still theirs to read.
    app.clock.set(due - SignedDuration::from_hours(1));
    store
        .import_roster("el2320", &[roster_line("u-late-2", "Student u-late-2", "")])
        .unwrap();
    let answer = app
        .send(
            Req::post("/api/submissions")
                .who(&who)
                .json(json!({ "source": quick_source("dropped") })),
        )
        .await;
    assert_eq!(answer.status, StatusCode::FORBIDDEN, "{}", answer.body);
    assert!(answer.error().contains("roster"), "{}", answer.body);
    assert_eq!(app.count(), before);
    let phase = app
        .send(Req::post("/api/phases").who(&who).json(json!({
            "lab": "ekf-localization", "language": "python", "seed": 7,
            "phase": "calculate_odometry", "source": "def calculate_odometry(e_R, e_L, E_T, B, R_R, R_L, delta_t, mu):\n    while True: pass\n",
        })))
        .await;
    assert_eq!(phase.status, StatusCode::FORBIDDEN, "{}", phase.body);
    assert!(phase.error().contains("roster"), "{}", phase.body);
    for id in [on_time, late] {
        let read = app
            .send(Req::get(&format!("/api/submissions/{id}")).who(&who))
            .await;
        assert_eq!(read.status, StatusCode::OK, "{}", read.body);
        assert!(read.json()["source"].is_string(), "{}", read.body);
    }

    // A course that has not opened the exercise.
    store
        .create_course("closed", "No Assignment", app.now())
        .unwrap();
    let other = app.enrol("closed", "u-closed-1");
    let other = app.signed_in(&other).await;
    let answer = app
        .send(
            Req::post("/api/submissions")
                .who(&other)
                .json(json!({ "source": quick_source("not opened") })),
        )
        .await;
    assert_eq!(answer.status, StatusCode::FORBIDDEN, "{}", answer.body);
    assert!(answer.error().contains("not opened"), "{}", answer.body);
    assert_eq!(app.count(), before);
}

// ---- 6. secrets at rest ----

fn contains(haystack: &[u8], needle: &str) -> bool {
    haystack
        .windows(needle.len())
        .any(|window| window == needle.as_bytes())
}

/// Proves that the database files hold no sign-in code (as handed out, without its
/// dashes, or its secret part), no session key and no API token: only their hashes.
#[tokio::test(flavor = "multi_thread")]
async fn secrets_are_not_stored_in_clear() {
    let app = App::new();
    let now = app.now();
    app.store()
        .create_course("el2320", "Applied Estimation", now)
        .unwrap();
    let student = app.enrol("el2320", "u-secret-1");
    let instructor = app.staff("el2320", "teacher@kth.example", Role::Instructor);
    let student_code = app.code(&student);
    let once = new_code();
    app.store()
        .add_code(instructor.id, &once, true, None, now)
        .unwrap();
    let Who::Session(session) = app.sign_in(&student_code, peer(127, 0, 0, 1)).await else {
        unreachable!()
    };
    let (_, token) = app
        .store()
        .create_token("el2320", Role::Instructor, now)
        .unwrap();

    let mut secrets = vec![session.clone(), token.clone()];
    secrets.push(token.trim_start_matches("estlab_").to_string());
    for code in [&student_code, &once.text] {
        let plain = code.replace('-', "");
        secrets.push(code.clone());
        secrets.push(plain[8..].to_string());
        secrets.push(plain);
    }

    let mut files = Vec::new();
    if app.url.is_some() {
        // PostgreSQL's files belong to its server: every row of every table, as text.
        let database = app.database();
        let tables: Vec<String> = database
            .query_map(
                "SELECT CAST(table_name AS TEXT) FROM information_schema.tables WHERE table_schema = 'public'",
                (),
                |row| row.get(0),
            )
            .unwrap();
        let mut rows = String::new();
        for table in tables {
            let texts: Vec<String> = database
                .query_map(
                    &format!("SELECT CAST(t AS TEXT) FROM {table} t"),
                    (),
                    |row| row.get(0),
                )
                .unwrap();
            rows.push_str(&texts.join("\n"));
        }
        files.push((estlab::store::FILE.to_string(), rows.into_bytes()));
    }
    for entry in std::fs::read_dir(app.dir.path()).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name.starts_with(estlab::store::FILE) {
            files.push((name, std::fs::read(&path).unwrap()));
        }
    }
    assert!(
        files.iter().any(|(name, _)| name == estlab::store::FILE),
        "no database file in {:?}",
        files.iter().map(|(name, _)| name).collect::<Vec<_>>()
    );
    for (name, bytes) in &files {
        for secret in &secrets {
            assert!(!contains(bytes, secret), "{name} holds {secret:?} in clear");
        }
    }
}

// ---- 7. migration ----

/// Every row of every table, as text: what a second opening must not change.
fn dump(path: &Path) -> (i64, String) {
    let connection = rusqlite::Connection::open(path).unwrap();
    let version: i64 = connection
        .query_row("PRAGMA user_version", [], |row| row.get(0))
        .unwrap();
    let mut text = String::new();
    let tables: Vec<(String, String)> = {
        let mut statement = connection
            .prepare("SELECT name, sql FROM sqlite_master WHERE sql IS NOT NULL ORDER BY name")
            .unwrap();
        statement
            .query_map([], |row| Ok((row.get(0)?, row.get(1)?)))
            .unwrap()
            .collect::<Result<_, _>>()
            .unwrap()
    };
    for (name, sql) in &tables {
        text.push_str(&format!("{sql}\n"));
        if !sql.starts_with("CREATE TABLE") {
            continue;
        }
        let mut statement = connection
            .prepare(&format!("SELECT * FROM \"{name}\" ORDER BY rowid"))
            .unwrap();
        let columns = statement.column_count();
        let rows = statement
            .query_map([], |row| {
                (0..columns)
                    .map(|i| row.get::<_, rusqlite::types::Value>(i))
                    .collect::<Result<Vec<_>, _>>()
            })
            .unwrap();
        for row in rows {
            text.push_str(&format!("  {:?}\n", row.unwrap()));
        }
    }
    (version, text)
}

/// The columns estlab 0.1.0 wrote, row by row.
fn original_columns(path: &Path) -> Vec<Vec<rusqlite::types::Value>> {
    let connection = rusqlite::Connection::open(path).unwrap();
    let mut statement = connection
        .prepare(
            "SELECT id, course, student, lab, seed, source, status, submitted_at, graded_at,
             score, result FROM submissions ORDER BY id",
        )
        .unwrap();
    statement
        .query_map([], |row| {
            (0..11)
                .map(|i| row.get::<_, rusqlite::types::Value>(i))
                .collect::<Result<Vec<_>, _>>()
        })
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap()
}

/// Proves that a database written by estlab 0.1.0 opens: its schema is brought to the
/// newest version, every submission is still there as it was (student, status, score,
/// a readable result and the source), and opening it again changes nothing.
#[test]
fn a_database_of_estlab_0_1_0_migrates_forward() {
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/estlab-0.1.0.sqlite3");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(estlab::store::FILE);
    std::fs::copy(&fixture, &path).unwrap();
    let before = original_columns(&path);
    assert_eq!(before.len(), 3, "the fixture holds three submissions");

    let newest = {
        let fresh = tempfile::tempdir().unwrap();
        drop(Store::open(fresh.path()).unwrap());
        dump(&fresh.path().join(estlab::store::FILE)).0
    };
    assert!(newest >= 2, "the newest schema is version {newest}");

    let store = Store::open(dir.path()).unwrap();
    let all = store.all_submissions().unwrap();
    let found: Vec<(i64, &str, &str, Status, Option<f64>)> = all
        .iter()
        .map(|s| {
            (
                s.id,
                s.course.as_str(),
                s.student.as_str(),
                s.status,
                s.score,
            )
        })
        .collect();
    assert_eq!(
        found,
        [
            (1, "el2320", "ada", Status::Graded, Some(1.0)),
            (2, "el2320", "grace", Status::Graded, Some(0.0)),
            (3, "el2320", "linus", Status::Graded, Some(0.0)),
        ]
    );
    for summary in &all {
        assert_eq!(summary.late_seconds, 0);
        assert_eq!(summary.penalty, 0.0);
        assert_eq!(summary.final_score, summary.score);
        let submission = store.get(summary.id, true).unwrap().unwrap();
        let source = submission.source.as_deref().unwrap_or("");
        assert!(
            !source.is_empty(),
            "submission {} lost its source",
            summary.id
        );
        assert_eq!(submission.member, None);
        let result = submission
            .result
            .unwrap_or_else(|| panic!("submission {} has no result", summary.id));
        assert!(result.gradable);
        assert_eq!(Some(result.score), summary.score);
        assert_eq!(result.seed, submission.seed);
        assert!(!result.tests.is_empty());
    }
    assert!(!store.any_course().unwrap());
    drop(store);

    let (version, first) = dump(&path);
    assert_eq!(version, newest, "the schema is not the newest");
    // Each result's tests gained their subject (migration 5), and nothing else changed.
    let mut after = original_columns(&path);
    let subjects: Vec<serde_json::Value> = after
        .iter_mut()
        .map(|row| {
            let rusqlite::types::Value::Text(text) = &row[10] else {
                panic!("a result is text");
            };
            let mut result: serde_json::Value = serde_json::from_str(text).unwrap();
            let subjects = result["tests"]
                .as_array_mut()
                .unwrap()
                .iter_mut()
                .map(|test| test.as_object_mut().unwrap().remove("subject").unwrap())
                .collect();
            row[10] = rusqlite::types::Value::Text(result.to_string());
            subjects
        })
        .collect();
    let as_read = |rows: Vec<Vec<rusqlite::types::Value>>| -> Vec<Vec<String>> {
        rows.into_iter()
            .map(|row| {
                row.into_iter()
                    .map(|value| match value {
                        rusqlite::types::Value::Text(text) => {
                            serde_json::from_str::<serde_json::Value>(&text)
                                .map_or(text, |json| json.to_string())
                        }
                        other => format!("{other:?}"),
                    })
                    .collect()
            })
            .collect()
    };
    assert_eq!(
        as_read(after),
        as_read(before),
        "the columns of 0.1.0 changed"
    );
    let function = |name: &str| json!({ "kind": "function", "name": name });
    let run = |name: &str| json!({ "kind": "run", "name": name });
    assert_eq!(
        subjects[0],
        json!([
            function("calculate_odometry"),
            function("predict"),
            function("observation_model"),
            function("jacobian_observation_model"),
            function("associate"),
            function("batch_associate"),
            function("update"),
            function("batch_update"),
            run("o3"),
            run("outliers"),
            run("no-odometry"),
        ])
    );

    // Opening it again changes nothing.
    drop(Store::open(dir.path()).unwrap());
    let (version, second) = dump(&path);
    assert_eq!(version, newest);
    assert_eq!(first, second, "a second opening changed the database");
}

/// Proves that a reissued code signs out whoever used the old one; that a student
/// submits at most twenty times an hour; that the API's answers are kept by no cache; and
/// that another scheme's `Authorization` (a proxy's Basic) is left alone.
#[tokio::test(flavor = "multi_thread")]
async fn reissued_codes_submission_caps_and_caching() {
    let app = App::new();
    let now = app.now();
    app.open_course("el2320");
    let student = app.enrol("el2320", "u-cap");
    let who = app.signed_in(&student).await;
    let me = |who: &Who| Req::get("/api/me").who(who);
    assert_eq!(app.send(me(&who)).await.json()["member"]["login"], "u-cap");

    for i in 0..20 {
        app.submit_graded(&who, &quick_source(&format!("try {i}")))
            .await;
    }
    let submit = |who: &Who| {
        Req::post("/api/submissions")
            .who(who)
            .json(json!({ "source": quick_source("one too many") }))
    };
    let refused = app.send(submit(&who)).await;
    assert_eq!(
        refused.status,
        StatusCode::TOO_MANY_REQUESTS,
        "{}",
        refused.body
    );
    assert!(refused.error().contains("20 times in the last hour"));
    app.clock.set(now + SignedDuration::from_mins(61));
    let taken = app.send(submit(&who)).await;
    assert_eq!(taken.status, StatusCode::ACCEPTED, "{}", taken.body);
    let id = taken.json()["id"].as_i64().unwrap();
    let read = app
        .send(Req::get(&format!("/api/submissions/{id}")).who(&who))
        .await;
    assert_eq!(read.headers[header::CACHE_CONTROL], "no-store");

    // A proxy's own authentication is not a token.
    let page = app
        .send(Req::get("/").header("authorization", "Basic dXNlcjpwYXNz"))
        .await;
    assert_eq!(page.status, StatusCode::OK);

    // The teacher reissues the code: the session made with the old one ends.
    app.store()
        .add_code(student.id, &new_code(), false, None, app.now())
        .unwrap();
    assert!(app.send(me(&who)).await.json()["member"].is_null());
}

/// Proves issue 21's minor refusals: a path under `/static` too long for any file name
/// (3,000 `a/` segments) is a 404, not a 500; a sign-in sent as JSON, or with a body over
/// its limit, gets the sign-in page again with its status and what was wrong, not plain
/// text; and a submission of another student's is the same 404 as one that does not
/// exist.
#[tokio::test(flavor = "multi_thread")]
async fn odd_requests_get_the_answer_a_person_can_read() {
    let app = App::new();
    app.open_course("el2320");
    let deep = format!("/static/{}x.js", "a/".repeat(3000));
    let answer = app.send(Req::get(&deep)).await;
    assert_eq!(answer.status, StatusCode::NOT_FOUND, "{}", answer.body);

    let as_json = app
        .send(Req::post("/signin").json(json!({ "code": "ABCD-EFGH" })))
        .await;
    assert_eq!(as_json.status, StatusCode::UNSUPPORTED_MEDIA_TYPE);
    assert!(
        as_json.headers[header::CONTENT_TYPE]
            .to_str()
            .unwrap()
            .starts_with("text/html"),
        "{:?}",
        as_json.headers
    );
    assert!(
        as_json.body.contains("Sign in with the form on this page"),
        "{}",
        as_json.body
    );
    let long = app
        .send(Req::post("/signin").form(&format!("code={}", "A".repeat(4096))))
        .await;
    assert_eq!(long.status, StatusCode::PAYLOAD_TOO_LARGE, "{}", long.body);
    assert!(
        long.body.contains("Sign in with the form on this page"),
        "{}",
        long.body
    );

    let owner = app.enrol("el2320", "u-owner");
    let other = app.enrol("el2320", "u-other");
    let owner_session = app.signed_in(&owner).await;
    let other_session = app.signed_in(&other).await;
    let submitted = app
        .send(
            Req::post("/api/submissions")
                .who(&owner_session)
                .json(json!({ "source": quick_source("u-owner") })),
        )
        .await;
    assert_eq!(submitted.status, StatusCode::ACCEPTED, "{}", submitted.body);
    let id = submitted.json()["id"].as_i64().unwrap();
    let theirs = app
        .send(Req::get(&format!("/api/submissions/{id}")).who(&other_session))
        .await;
    let none = app
        .send(Req::get("/api/submissions/999999").who(&other_session))
        .await;
    assert_eq!(theirs.status, StatusCode::NOT_FOUND);
    assert_eq!(
        theirs.body.replace(&id.to_string(), "N"),
        none.body.replace("999999", "N")
    );
}

#[tokio::test]
async fn refusals_of_the_api_are_json_naming_what_is_wrong() {
    let app = App::new();
    app.open_course("el2320");
    let student = app.enrol("el2320", "u-shapes");
    let who = app.signed_in(&student).await;

    // A body over the router's limit: 413, said in JSON.
    let huge = Req::post("/api/submissions")
        .who(&who)
        .json(json!({ "source": "x".repeat(5 << 20) }));
    let answer = app.send(huge).await;
    assert_eq!(answer.status, StatusCode::PAYLOAD_TOO_LARGE);
    assert!(
        answer.error().starts_with("the submission body: "),
        "{}",
        answer.body
    );

    // A query that does not parse: 400, naming the query and the field.
    for uri in [
        "/api/me/submissions?lab=ekf-localization&lab=odometry",
        "/api/me/submissions?exercise=ekf-localization",
    ] {
        let answer = app.send(Req::get(uri).who(&who)).await;
        assert_eq!(answer.status, StatusCode::BAD_REQUEST, "{uri}");
        let error = answer.error();
        assert!(
            error.starts_with("the query: ") && error.contains("field"),
            "{uri}: {error}"
        );
    }

    // An exercise that is not graded here: 400, naming the field and the known ones.
    let answer = app
        .send(Req::get("/api/me/submissions?lab=kidnapped-robot").who(&who))
        .await;
    assert_eq!(answer.status, StatusCode::BAD_REQUEST);
    assert_eq!(
        answer.error(),
        "field `lab`: unknown exercise \"kidnapped-robot\"; the exercises graded here: ekf-localization, odometry, sensor-fusion, ukf-particle"
    );

    // A file holding a NUL character: 400, naming its line; nothing stored.
    let before = app.count();
    let answer = app
        .send(
            Req::post("/api/submissions")
                .who(&who)
                .json(json!({ "source": "function init() {}\n// \u{0}\n" })),
        )
        .await;
    assert_eq!(answer.status, StatusCode::BAD_REQUEST, "{}", answer.body);
    assert!(
        answer
            .error()
            .starts_with("field `source`: line 2 holds a NUL character"),
        "{}",
        answer.body
    );
    assert_eq!(app.count(), before);

    // A body that is not the JSON asked for: 400, naming the line and column.
    let broken = Req::post("/api/submissions").who(&who).json(json!(null));
    let error = app.send(broken).await.error();
    assert!(
        error.starts_with("the submission body: ") && error.contains("line 1 column 4"),
        "{error}"
    );
}

/// `/metrics` answers the data directory's metrics token, with every lane and the work
/// done so far: a student's submission graded is one grading done, its CPU time counted.
#[tokio::test]
async fn the_metrics_token_opens_the_sandboxs_metrics() {
    let app = App::new();
    app.open_course("el2320");
    let student = app.enrol("el2320", "u-metrics");
    let who = app.signed_in(&student).await;
    let token = app.state.grader.metrics_token();
    let scrape = || Req::get("/metrics").header("authorization", &format!("Bearer {token}"));
    let before = app.send(scrape()).await;
    assert_eq!(before.status, StatusCode::OK, "{}", before.body);
    assert!(
        before.headers[header::CONTENT_TYPE]
            .to_str()
            .unwrap()
            .starts_with("application/openmetrics-text"),
    );
    for kind in ["phase", "grading", "report_runs", "regrade"] {
        for metric in ["waiting", "oldest_wait_seconds", "cpu_seconds_total"] {
            let line = format!("estlab_sandbox_{metric}{{kind=\"{kind}\"}} ");
            assert!(before.body.contains(&line), "{line} in {}", before.body);
        }
    }
    assert!(
        before.body.contains("estlab_sandbox_cap 3\n"),
        "{}",
        before.body
    );
    assert!(!before.body.contains("outcome=\"done\""), "{}", before.body);

    // A file that loops as it loads: every phase runs to its limit.
    app.submit_graded(&who, "for (;;) {}").await;
    // Its turn's end is counted before its sandbox's place is given back.
    let give_up = std::time::Instant::now() + GRADING_BOUND;
    while app.state.grader.running() > 0 {
        assert!(
            std::time::Instant::now() < give_up,
            "the grading never ended"
        );
        tokio::time::sleep(std::time::Duration::from_millis(20)).await;
    }
    let after = app.send(scrape()).await.body;
    assert!(
        after.contains("estlab_sandbox_ended_total{kind=\"grading\",outcome=\"done\"} 1\n"),
        "{after}"
    );
    let cpu: f64 = after
        .lines()
        .find_map(|line| line.strip_prefix("estlab_sandbox_cpu_seconds_total{kind=\"grading\"} "))
        .unwrap()
        .parse()
        .unwrap();
    assert!(cpu > 0.5, "an endless loop's grading used {cpu} s of CPU");

    // Another token, or another scheme, is refused.
    for header in [
        "Bearer nope".to_owned(),
        format!("Basic {token}"),
        format!("Bearer {}", app.state.grader.metrics_token().to_uppercase()),
    ] {
        let refused = app
            .send(Req::get("/metrics").header("authorization", &header))
            .await;
        assert_eq!(refused.status, StatusCode::UNAUTHORIZED, "{header}");
    }
}

/// Every route of the router (`web::router`'s own and the registry's pages) is in the
/// matrix, so a new route is checked too (`objects.rs` asks those with a parameter with
/// another course's ids).
#[test]
fn every_route_of_the_router_is_in_the_matrix() {
    for route in routes() {
        assert!(
            MATRIX.iter().any(|(_, path, _)| route_serves(&route, path)),
            "{route} is not in the access matrix"
        );
    }
}

/// Every page of the site's registry (`static/pages.json`, which the router serves) and
/// every exercise's workbench and starter file is in the matrix, so a new page is checked
/// too.
#[test]
fn every_page_of_the_registry_is_in_the_matrix() {
    #[derive(serde::Deserialize)]
    struct Registry {
        pages: Vec<Page>,
    }
    #[derive(serde::Deserialize)]
    struct Page {
        path: String,
    }
    let registry: Registry =
        serde_json::from_str(include_str!("../../../static/pages.json")).unwrap();
    let in_matrix = |path: &str| {
        MATRIX
            .iter()
            .any(|(method, p, _)| *method == "GET" && *p == path)
    };
    for page in &registry.pages {
        let path = page
            .path
            .replace("{course}", "el2320")
            .replace("{lab}", "ekf-localization")
            .replace("{student}", "{A_ID}");
        assert!(in_matrix(&path), "{path} is not in the access matrix");
    }
    for path in workbench_routes() {
        assert!(in_matrix(&path), "{path} is not in the access matrix");
    }
}
