//! The written part of an assignment through the real web application: students read
//! the questions without what they are checked against and save their answers until
//! their cutoff; staff read the sets in full; instructors give other sets, a problem
//! named by its set, line, question and field, and answers stay by question id.

use crate::common;

use axum::http::StatusCode;
use common::*;
use estlab::store::Role;
use jiff::SignedDuration;
use labs::Exercise;
use serde_json::{Value, json};

const QUESTIONS: &str = "/api/courses/el2320/labs/ekf-localization/questions";
const ANSWERS: &str = "/api/courses/el2320/labs/ekf-localization/answers";

/// A set of two questions: the first keeps the id of the lab's Part I's first question.
const OTHER_SET: &str = r#"
title = "A shorter Part I"

[[question]]
id = "roles"
kind = "text"
prompt = "What is a state?"
model = "What the filter estimates."

[[question]]
id = "gate"
kind = "number"
prompt = "The gate at 0.999?"
answer = 13.8155
tolerance = 0.01
"#;

fn answer(part: usize, question: &str, answer: Value) -> Value {
    json!({ "part": part, "question": question, "answer": answer })
}

#[tokio::test]
async fn students_answer_staff_read_instructors_import() {
    let app = App::new();
    app.open_course("el2320");
    app.open_course("other");
    let a = app.enrol("el2320", "u-a-1001");
    let b = app.enrol("el2320", "u-b-1002");
    let outsider = app.enrol("other", "u-c-1003");
    let instructor = app.staff("el2320", "teacher@example.org", Role::Instructor);
    let assistant = app.staff("el2320", "ta@example.org", Role::Assistant);
    let (a, b, outsider) = (
        app.signed_in(&a).await,
        app.signed_in(&b).await,
        app.signed_in(&outsider).await,
    );
    let (instructor, assistant) = (
        app.signed_in(&instructor).await,
        app.signed_in(&assistant).await,
    );

    // The lab's own sets: a student sees no model answer and no answer key.
    let seen = app.get_json(&a, QUESTIONS).await;
    assert_eq!(seen["own"], true);
    let sets = seen["sets"].as_array().unwrap();
    assert_eq!(sets.len(), 2);
    assert_eq!(sets[0]["questions"].as_array().unwrap().len(), 15);
    let text = serde_json::to_string(&seen).unwrap();
    assert!(
        !text.contains("13.8155"),
        "the gate's answer leaked: {text}"
    );
    assert!(
        seen["sets"][1]["questions"]
            .as_array()
            .unwrap()
            .iter()
            .all(|q| q["model"] == "" && q.get("correct").is_none_or(Value::is_null))
    );
    assert!(seen["cutoff"].is_string());
    // Staff read them in full.
    let full = app.get_json(&assistant, QUESTIONS).await;
    let gate = full["sets"][1]["questions"]
        .as_array()
        .unwrap()
        .iter()
        .find(|q| q["id"] == "gate-value")
        .unwrap()
        .clone();
    assert_eq!(gate["answer"], 13.8155);
    assert!(gate["model"].as_str().unwrap().contains("ln"));

    // Answers are saved, replaced, and read back by their student only.
    let save = |who, body| app.send(Req::post(ANSWERS).who(who).json(body));
    for body in [
        answer(0, "roles", json!({"kind": "text", "value": "first draft"})),
        answer(
            0,
            "roles",
            json!({"kind": "text", "value": "The state is the pose $x_t$."}),
        ),
        answer(0, "map-mle", json!({"kind": "choice", "value": 0})),
        answer(1, "gate-value", json!({"kind": "number", "value": "13.82"})),
        answer(
            1,
            "batch-dimensions",
            json!({"kind": "table", "value": [["2n x 1", "2 x 1"], ["2n x 3", "2 x 3"]]}),
        ),
    ] {
        let saved = save(&a, body.clone()).await;
        assert_eq!(saved.status, StatusCode::OK, "{body}: {}", saved.body);
    }
    let mine = app.get_json(&a, QUESTIONS).await;
    let answers = mine["answers"].as_array().unwrap();
    assert_eq!(answers.len(), 4);
    let roles = answers.iter().find(|x| x["question"] == "roles").unwrap();
    assert_eq!(roles["answer"]["value"], "The state is the pose $x_t$.");
    assert!(
        app.get_json(&b, QUESTIONS).await["answers"]
            .as_array()
            .unwrap()
            .is_empty()
    );
    assert!(
        app.get_json(&instructor, QUESTIONS).await["answers"]
            .as_array()
            .unwrap()
            .is_empty()
    );

    // Wrong answers are refused, naming the field; nothing saved is lost.
    for (body, expected) in [
        (
            answer(0, "roles", json!({"kind": "number", "value": "1"})),
            "field `answer`: roles takes an answer of kind \"text\"",
        ),
        (
            answer(0, "map-mle", json!({"kind": "choice", "value": 7})),
            "field `answer`: map-mle has 3 options",
        ),
        (
            answer(
                1,
                "batch-dimensions",
                json!({"kind": "table", "value": [["1"]]}),
            ),
            "2 rows and 2 columns",
        ),
        (
            answer(2, "roles", json!({"kind": "text", "value": "x"})),
            "field `part`: the assignment has 2 question sets",
        ),
        (
            answer(0, "nothing", json!({"kind": "text", "value": "x"})),
            "field `question`",
        ),
        (
            answer(
                0,
                "roles",
                json!({"kind": "text", "value": "x".repeat(20_001)}),
            ),
            "longer than 20000",
        ),
    ] {
        let refused = save(&a, body).await;
        assert_eq!(refused.status, StatusCode::BAD_REQUEST, "{}", refused.body);
        assert!(refused.error().contains(expected), "{}", refused.error());
    }
    // Nobody else answers for the course.
    assert_eq!(
        save(
            &outsider,
            answer(0, "roles", json!({"kind": "text", "value": "x"}))
        )
        .await
        .status,
        StatusCode::NOT_FOUND
    );
    assert_eq!(
        save(
            &instructor,
            answer(0, "roles", json!({"kind": "text", "value": "x"}))
        )
        .await
        .status,
        StatusCode::FORBIDDEN
    );
    assert_eq!(
        app.send(Req::get(QUESTIONS).who(&outsider)).await.status,
        StatusCode::NOT_FOUND
    );

    // An instructor's set with a mistake is refused, naming where; an assistant may not
    // change the sets at all.
    let broken = OTHER_SET.replace("tolerance = 0.01", "tolerance = -1");
    let refused = app
        .send(
            Req::post(QUESTIONS)
                .who(&instructor)
                .json(json!({ "sets": [broken] })),
        )
        .await;
    assert_eq!(refused.status, StatusCode::BAD_REQUEST, "{}", refused.body);
    assert!(
        refused
            .error()
            .contains("field `sets`: set 1: line 10: question 2: tolerance -1"),
        "{}",
        refused.error()
    );
    let refused = app
        .send(
            Req::post(QUESTIONS)
                .who(&assistant)
                .json(json!({ "sets": [OTHER_SET] })),
        )
        .await;
    assert_eq!(refused.status, StatusCode::FORBIDDEN);

    // Other sets: answers to a question that keeps its id stay.
    let imported = app
        .send(
            Req::post(QUESTIONS)
                .who(&instructor)
                .json(json!({ "sets": [OTHER_SET] })),
        )
        .await;
    assert_eq!(imported.status, StatusCode::OK, "{}", imported.body);
    assert_eq!(imported.json()["own"], false);
    let mine = app.get_json(&a, QUESTIONS).await;
    assert_eq!(mine["sets"].as_array().unwrap().len(), 1);
    assert_eq!(mine["sets"][0]["title"], "A shorter Part I");
    let roles = mine["answers"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["question"] == "roles")
        .unwrap();
    assert_eq!(roles["answer"]["value"], "The state is the pose $x_t$.");
    let audit = app.get_json(&instructor, "/api/courses/el2320/audit").await;
    assert!(
        serde_json::to_string(&audit)
            .unwrap()
            .contains("A shorter Part I"),
        "{audit}"
    );
    // And back to the lab's own.
    let back = app
        .send(
            Req::post(QUESTIONS)
                .who(&instructor)
                .json(json!({ "sets": null })),
        )
        .await;
    assert_eq!(back.status, StatusCode::OK, "{}", back.body);
    assert_eq!(app.get_json(&b, QUESTIONS).await["own"], true);

    // After the cutoff no answer is taken.
    let cutoff = app
        .store()
        .assignment("el2320", Exercise::EkfLocalization)
        .unwrap()
        .unwrap()
        .policy
        .cutoff;
    app.clock.set(cutoff + SignedDuration::from_secs(1));
    let a = app
        .signed_in(&app.store().member("el2320", "u-a-1001").unwrap())
        .await;
    let late = save(
        &a,
        answer(0, "roles", json!({"kind": "text", "value": "too late"})),
    )
    .await;
    assert_eq!(late.status, StatusCode::FORBIDDEN, "{}", late.body);
    assert!(late.error().contains("cutoff"), "{}", late.error());
    let kept = app.get_json(&a, QUESTIONS).await;
    let roles = kept["answers"]
        .as_array()
        .unwrap()
        .iter()
        .find(|x| x["question"] == "roles")
        .unwrap();
    assert_eq!(roles["answer"]["value"], "The state is the pose $x_t$.");
}

const ROUNDS: &str = "/api/courses/el2320/labs/ekf-localization/rounds";
const REVIEWS: &str = "/api/courses/el2320/labs/ekf-localization/reviews";

/// Saves `text` as `who`'s answer to the first two questions of Part I.
async fn answer_part_one(app: &App, who: &Who, text: &str) {
    for question in ["roles", "weighing"] {
        let saved = app
            .send(Req::post(ANSWERS).who(who).json(answer(
                0,
                question,
                json!({"kind": "text", "value": format!("{text} ({question})")}),
            )))
            .await;
        assert_eq!(saved.status, StatusCode::OK, "{}", saved.body);
    }
}

/// Marks every answer of `who`'s sheet `number` of `round` (the first right, the rest
/// wrong), and hands the review in.
async fn review_sheet(app: &App, who: &Who, round: i64, number: u64) -> Value {
    let path = format!("{REVIEWS}/{round}/{number}");
    let sheet = app.get_json(who, &path).await;
    let marks: Vec<Value> = sheet["answers"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .map(|(i, a)| json!({ "question": a["question"], "correct": i == 0, "comment": format!("mark {i}") }))
        .collect();
    let done = app
        .send(
            Req::post(&path)
                .who(who)
                .json(json!({ "marks": marks, "submit": true })),
        )
        .await;
    assert_eq!(done.status, StatusCode::OK, "{}", done.body);
    sheet
}

#[tokio::test]
async fn a_review_round_in_class() {
    let app = App::new();
    app.open_course("el2320");
    app.open_course("other");
    let logins = ["u-a-2001", "u-b-2002", "u-c-2003", "u-d-2004"];
    let mut who = Vec::new();
    for login in logins {
        let member = app.enrol("el2320", login);
        who.push(app.signed_in(&member).await);
    }
    let outsider = app.signed_in(&app.enrol("other", "u-x-2009")).await;
    let assistant = app
        .signed_in(&app.staff("el2320", "ta@example.org", Role::Assistant))
        .await;
    let other_staff = app
        .signed_in(&app.staff("other", "t@other.example", Role::Instructor))
        .await;
    let instructor = app
        .signed_in(&app.staff("el2320", "teacher@example.org", Role::Instructor))
        .await;
    for (i, w) in who.iter().take(3).enumerate() {
        answer_part_one(&app, w, &format!("sheet of student {i}")).await;
    }

    // Opening: too many reviews for three sheets, then two each.
    let refused = app
        .send(
            Req::post(ROUNDS)
                .who(&assistant)
                .json(json!({"part": 0, "per_sheet": 3})),
        )
        .await;
    assert_eq!(refused.status, StatusCode::BAD_REQUEST);
    assert!(refused.error().contains("at most 2"), "{}", refused.error());
    let opened = app
        .send(
            Req::post(ROUNDS)
                .who(&assistant)
                .json(json!({"part": 0, "per_sheet": 2})),
        )
        .await;
    assert_eq!(opened.status, StatusCode::OK, "{}", opened.body);
    let round = opened.json();
    let id = round["id"].as_i64().unwrap();
    assert_eq!(round["students"].as_array().unwrap().len(), 3);
    assert_eq!(round["bonus_above"], 0.3);
    let again = app
        .send(
            Req::post(ROUNDS)
                .who(&assistant)
                .json(json!({"part": 0, "per_sheet": 2})),
        )
        .await;
    assert!(again.error().contains("still open"), "{}", again.error());

    // A late answer joins; every student then reviews two sheets, none their own.
    answer_part_one(&app, &who[3], "sheet of student 3").await;
    let rounds = app.get_json(&assistant, ROUNDS).await;
    assert_eq!(rounds[0]["waiting"], json!(["u-d-2004"]));
    let joined = app
        .send(
            Req::post(&format!("{ROUNDS}/{id}"))
                .who(&assistant)
                .json(json!({"action": "join", "student": "u-d-2004"})),
        )
        .await;
    assert_eq!(joined.status, StatusCode::OK, "{}", joined.body);
    for (i, w) in who.iter().enumerate() {
        let mine = app.get_json(w, REVIEWS).await;
        let sheets = mine[0]["sheets"].as_array().unwrap();
        assert_eq!(sheets.len(), 2, "{}: {mine}", logins[i]);
        assert!(mine[0]["received"].is_null());
        for number in sheets.iter().map(|s| s["number"].as_u64().unwrap()) {
            let sheet = app.get_json(w, &format!("{REVIEWS}/{id}/{number}")).await;
            // The model answers, but no key a reviewer could use for their own answers.
            for question in sheet["set"]["questions"].as_array().unwrap() {
                assert!(
                    question.get("correct").is_none_or(Value::is_null),
                    "{question}"
                );
                assert!(
                    question.get("answer").is_none_or(Value::is_null),
                    "{question}"
                );
            }
            let text = serde_json::to_string(&sheet).unwrap();
            assert!(
                !text.contains(&format!("student {i} ")),
                "{} has their own sheet",
                logins[i]
            );
            assert!(!text.contains("u-"), "a sheet names someone: {text}");
            assert!(
                sheet["set"]["questions"][0]["model"]
                    .as_str()
                    .unwrap()
                    .len()
                    > 10
            );
        }
        assert_eq!(
            app.send(Req::get(&format!("{REVIEWS}/{id}/99")).who(w))
                .await
                .status,
            StatusCode::NOT_FOUND
        );
    }

    // A review is handed in only when every answer is marked (and only those), and then
    // no more changed.
    let first = app.get_json(&who[0], REVIEWS).await[0]["sheets"][0]["number"]
        .as_u64()
        .unwrap();
    let path = format!("{REVIEWS}/{id}/{first}");
    let unanswered = json!({"marks": [{"question": "optimal", "correct": false, "comment": ""}], "submit": false});
    let refused = app
        .send(Req::post(&path).who(&who[0]).json(unanswered))
        .await;
    assert!(
        refused.error().contains("no question the sheet answers"),
        "{}",
        refused.error()
    );
    let partial =
        json!({"marks": [{"question": "roles", "correct": true, "comment": ""}], "submit": true});
    let refused = app.send(Req::post(&path).who(&who[0]).json(partial)).await;
    assert_eq!(refused.status, StatusCode::BAD_REQUEST);
    assert!(
        refused.error().contains("weighing is not marked yet"),
        "{}",
        refused.error()
    );
    review_sheet(&app, &who[0], id, first).await;
    let late = app
        .send(
            Req::post(&path)
                .who(&who[0])
                .json(json!({"marks": [], "submit": false})),
        )
        .await;
    assert_eq!(late.status, StatusCode::FORBIDDEN);

    // Other sets imported meanwhile leave the open round's set alone.
    let imported = app
        .send(
            Req::post(QUESTIONS)
                .who(&instructor)
                .json(json!({ "sets": [OTHER_SET] })),
        )
        .await;
    assert_eq!(imported.status, StatusCode::OK, "{}", imported.body);
    let mine = app.get_json(&who[0], REVIEWS).await;
    assert_eq!(mine[0]["title"], "Part I: before the lab");

    // Student b leaves: their sheets go to the others; the rest review everything.
    let moved = app
        .send(
            Req::post(&format!("{ROUNDS}/{id}"))
                .who(&assistant)
                .json(json!({"action": "reassign", "student": "u-b-2002"})),
        )
        .await;
    assert_eq!(moved.status, StatusCode::OK, "{}", moved.body);
    let b = moved.json()["students"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["student"] == "u-b-2002")
        .unwrap()
        .clone();
    assert_eq!(b["reviewing"], 0);
    for (i, w) in who.iter().enumerate() {
        for sheet in app.get_json(w, REVIEWS).await[0]["sheets"]
            .as_array()
            .unwrap()
        {
            if sheet["submitted"] == false {
                review_sheet(&app, w, id, sheet["number"].as_u64().unwrap()).await;
            }
        }
        assert!(
            i != 1
                || app.get_json(w, REVIEWS).await[0]["sheets"]
                    .as_array()
                    .unwrap()
                    .is_empty()
        );
    }

    // Closed: each author reads the marks of their sheet, a share of a half (one answer
    // of two marked right by each reviewer), above 30 %: the bonus.
    let closed = app
        .send(
            Req::post(&format!("{ROUNDS}/{id}"))
                .who(&assistant)
                .json(json!({"action": "close"})),
        )
        .await;
    assert_eq!(closed.status, StatusCode::OK, "{}", closed.body);
    for student in closed.json()["students"].as_array().unwrap() {
        assert_eq!(student["tally"]["marks"], 4, "{student}");
        assert_eq!(student["tally"]["share"], 0.5, "{student}");
        assert_eq!(student["tally"]["bonus"], true, "{student}");
    }
    let mine = app.get_json(&who[2], REVIEWS).await;
    let received = &mine[0]["received"];
    assert_eq!(received["marks"].as_array().unwrap().len(), 4);
    assert_eq!(received["tally"]["share"], 0.5);
    assert!(
        !serde_json::to_string(received).unwrap().contains("u-"),
        "a mark names its reviewer"
    );
    let theirs = mine[0]["sheets"][0]["number"].as_u64().unwrap();
    let shut = app
        .send(
            Req::post(&format!("{REVIEWS}/{id}/{theirs}"))
                .who(&who[2])
                .json(json!({"marks": [], "submit": false})),
        )
        .await;
    assert_eq!(shut.status, StatusCode::FORBIDDEN);

    // The gradebook has each student's share and bonus.
    let export = app
        .send(
            Req::get("/api/courses/el2320/labs/ekf-localization/export?format=csv").who(&assistant),
        )
        .await;
    assert_eq!(export.status, StatusCode::OK);
    let mut reader = csv::Reader::from_reader(export.body.as_bytes());
    let header = reader.headers().unwrap().clone();
    let column = |name: &str| header.iter().position(|c| c == name).unwrap();
    let (share, bonus) = (column("review_share_1"), column("review_bonus_1"));
    let rows = csv_rows(&export.body);
    assert_eq!(rows.len(), 4);
    for row in &rows {
        assert_eq!(
            (row[share].as_str(), row[bonus].as_str()),
            ("0.5000", "yes"),
            "{row:?}"
        );
    }

    // Nobody outside reaches the rounds.
    assert_eq!(
        app.send(Req::get(REVIEWS).who(&outsider)).await.status,
        StatusCode::NOT_FOUND
    );
    assert_eq!(
        app.send(Req::get(&format!("{REVIEWS}/{id}/1")).who(&outsider))
            .await
            .status,
        StatusCode::NOT_FOUND
    );
    assert_eq!(
        app.send(Req::get(ROUNDS).who(&who[0])).await.status,
        StatusCode::NOT_FOUND
    );
    assert_eq!(
        app.send(Req::get(REVIEWS).who(&assistant)).await.status,
        StatusCode::FORBIDDEN
    );
    let theirs = format!("/api/courses/other/labs/ekf-localization/rounds/{id}");
    let refused = app
        .send(
            Req::post(&theirs)
                .who(&other_staff)
                .json(json!({"action": "close"})),
        )
        .await;
    assert_eq!(refused.status, StatusCode::NOT_FOUND);
    let audit = serde_json::to_string(&app.get_json(&assistant, "/api/courses/el2320/audit").await)
        .unwrap();
    for logged in ["opened", "u-d-2004 joined", "went to others", "closed"] {
        assert!(audit.contains(logged), "{logged} not in the audit: {audit}");
    }
}

const REPORT: &str = "/api/courses/el2320/labs/ekf-localization/report";
const REPORTS: &str = "/api/courses/el2320/labs/ekf-localization/reports";

/// A rubric of the EKF report's six parts: `revise` the ones named, the rest pass.
fn rubric(handed_in: u32, revise: &[&str]) -> Value {
    let parts: Vec<Value> = [
        "o3/sequential",
        "outliers/sequential",
        "no-odometry/sequential",
        "no-odometry/batch",
        "questions-1",
        "questions-2",
    ]
    .iter()
    .map(|part| {
        let verdict = if revise.contains(part) {
            "revise"
        } else {
            "pass"
        };
        json!({ "part": part, "verdict": verdict, "comment": format!("on {part}") })
    })
    .collect();
    json!({ "handed_in": handed_in, "parts": parts })
}

/// A student's report from its draft to accepted through the API: analyses only of its
/// runs and within their length, no hand-in without a submission, the runs made once on
/// the server with the student's code and read alike by staff, a hand-in that shuts the
/// analyses until staff send it back, a rubric that judges every part of the hand-in staff
/// read (a later hand-in is not judged unread), drafts refused after the cutoff and a
/// report sent back taken after it; the gradebook's report columns.
#[tokio::test(flavor = "multi_thread")]
async fn a_report_from_draft_to_accepted() {
    let app = App::new();
    app.open_course("el2320");
    let a = app.enrol("el2320", "u-a-1001");
    app.enrol("el2320", "u-l-1003");
    let assistant = app.staff("el2320", "ta@example.org", Role::Assistant);
    app.staff("el2320", "teacher@example.org", Role::Instructor);
    let a = app.signed_in(&a).await;
    let assistant = app.signed_in(&assistant).await;
    let post =
        |who: &Who, path: String, body: Value| app.send(Req::post(&path).who(who).json(body));

    // A draft: the four runs and both sets as parts, nothing handed in, no submission.
    let draft = app.get_json(&a, REPORT).await;
    assert_eq!(draft["state"], "draft");
    assert_eq!(draft["parts"].as_array().unwrap().len(), 6);
    assert!(draft["submission"].is_null());
    let runs = app.get_json(&a, &format!("{REPORT}/runs")).await;
    assert_eq!(runs["state"], "no_submission");
    let wrong_run = post(
        &a,
        format!("{REPORT}/analyses"),
        json!({ "run": "o4/batch", "text": "x" }),
    )
    .await;
    assert_eq!(
        wrong_run.status,
        StatusCode::BAD_REQUEST,
        "{}",
        wrong_run.body
    );
    assert!(
        wrong_run.error().contains("field `run`"),
        "{}",
        wrong_run.error()
    );
    let long = "x".repeat(20_001);
    let too_long = post(
        &a,
        format!("{REPORT}/analyses"),
        json!({ "run": "o3/sequential", "text": long }),
    )
    .await;
    assert_eq!(
        too_long.status,
        StatusCode::BAD_REQUEST,
        "{}",
        too_long.body
    );
    let saved = post(
        &a,
        format!("{REPORT}/analyses"),
        json!({ "run": "o3/sequential", "text": "small $\\Sigma$" }),
    )
    .await;
    assert_eq!(saved.status, StatusCode::NO_CONTENT, "{}", saved.body);
    let early = post(&a, format!("{REPORT}/hand-in"), json!({ "submission": 1 })).await;
    assert_eq!(early.status, StatusCode::CONFLICT, "{}", early.body);
    assert!(
        early.error().contains("submit your code first"),
        "{}",
        early.error()
    );

    // The runs of the latest submission, made once on the server; staff read the same.
    let (submission, _) = app.submit_graded(&a, &quick_source("report")).await;
    let runs = wait_for_runs(&app, &a, &format!("{REPORT}/runs")).await;
    assert_eq!(runs["submission"], submission);
    let mut names: Vec<&str> = runs["outputs"]["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["name"].as_str().unwrap())
        .collect();
    names.sort_unstable();
    assert_eq!(
        names,
        [
            "no-odometry/batch",
            "no-odometry/sequential",
            "o3/sequential",
            "outliers/sequential"
        ]
    );
    // The file lacks the functions the loop calls: each run says so, for the report to show.
    assert!(
        runs["outputs"]["runs"][0]["error"]
            .as_str()
            .is_some_and(|e| e.contains("is not defined")),
        "{runs}"
    );
    let staff_runs = app
        .get_json(&assistant, &format!("{REPORTS}/u-a-1001/runs"))
        .await;
    assert_eq!(staff_runs, runs);

    // Handed in with the submission read (another is refused, naming the field): the
    // analyses are shut, a second hand-in refused, staff see it waiting, and read it as it
    // was handed in, whatever answer changes later.
    let unread = post(
        &a,
        format!("{REPORT}/hand-in"),
        json!({ "submission": submission + 1 }),
    )
    .await;
    assert_eq!(unread.status, StatusCode::CONFLICT, "{}", unread.body);
    assert!(
        unread.error().contains("field `submission`"),
        "{}",
        unread.error()
    );
    let handed = post(
        &a,
        format!("{REPORT}/hand-in"),
        json!({ "submission": submission }),
    )
    .await;
    assert_eq!(handed.status, StatusCode::OK, "{}", handed.body);
    assert_eq!(handed.json()["state"], "handed_in");
    assert_eq!(handed.json()["handed_in"], 1);
    let shut = post(
        &a,
        format!("{REPORT}/analyses"),
        json!({ "run": "o3/sequential", "text": "more" }),
    )
    .await;
    assert_eq!(shut.status, StatusCode::CONFLICT, "{}", shut.body);
    assert_eq!(
        post(
            &a,
            format!("{REPORT}/hand-in"),
            json!({ "submission": submission })
        )
        .await
        .status,
        StatusCode::CONFLICT
    );
    let later = answer(
        0,
        "roles",
        json!({"kind": "text", "value": "written after the hand-in"}),
    );
    assert_eq!(
        post(&a, ANSWERS.to_string(), later).await.status,
        StatusCode::OK
    );
    let class = app.get_json(&assistant, REPORTS).await;
    let line = class
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["student"] == "u-a-1001")
        .unwrap();
    assert_eq!(line["state"], "handed_in");
    assert_eq!(line["lab_passed"], false);
    let read = app
        .get_json(&assistant, &format!("{REPORTS}/u-a-1001"))
        .await;
    assert_eq!(read["analyses"]["o3/sequential"], "small $\\Sigma$");
    assert_eq!(read["staff"], true);
    assert!(
        !read["answers"].to_string().contains("after the hand-in"),
        "{}",
        read["answers"]
    );

    // The rubric: every part, once; the hand-in read; one part sent back.
    let mut partial = rubric(1, &[]);
    partial["parts"].as_array_mut().unwrap().pop();
    let missing = post(&assistant, format!("{REPORTS}/u-a-1001/rubric"), partial).await;
    assert_eq!(missing.status, StatusCode::BAD_REQUEST, "{}", missing.body);
    assert!(
        missing.error().contains("questions-2"),
        "{}",
        missing.error()
    );
    let unknown = post(
        &assistant,
        format!("{REPORTS}/u-a-1001/rubric"),
        rubric(5, &[]),
    )
    .await;
    assert_eq!(unknown.status, StatusCode::BAD_REQUEST, "{}", unknown.body);
    assert!(
        unknown.error().contains("field `handed_in`"),
        "{}",
        unknown.error()
    );
    let nothing = post(
        &assistant,
        format!("{REPORTS}/u-l-1003/rubric"),
        rubric(1, &[]),
    )
    .await;
    assert_eq!(nothing.status, StatusCode::CONFLICT, "{}", nothing.body);
    let sent_back = post(
        &assistant,
        format!("{REPORTS}/u-a-1001/rubric"),
        rubric(1, &["no-odometry/sequential"]),
    )
    .await;
    assert_eq!(sent_back.status, StatusCode::OK, "{}", sent_back.body);
    assert_eq!(sent_back.json()["state"], "revise");

    // After the cutoff: a draft is refused, a report sent back is taken.
    let cutoff = app
        .store()
        .assignment("el2320", Exercise::EkfLocalization)
        .unwrap()
        .unwrap()
        .policy
        .cutoff;
    app.clock.set(cutoff + SignedDuration::from_secs(1));
    let a = app
        .signed_in(&app.store().member("el2320", "u-a-1001").unwrap())
        .await;
    // (Sessions have expired by then: everyone signs in again.)
    let late = app
        .signed_in(&app.store().member("el2320", "u-l-1003").unwrap())
        .await;
    let instructor = app
        .signed_in(&app.store().member("el2320", "teacher@example.org").unwrap())
        .await;
    let too_late = post(
        &late,
        format!("{REPORT}/analyses"),
        json!({ "run": "o3/sequential", "text": "late" }),
    )
    .await;
    assert_eq!(too_late.status, StatusCode::FORBIDDEN, "{}", too_late.body);
    assert!(too_late.error().contains("cutoff"), "{}", too_late.error());
    let mine = app.get_json(&a, REPORT).await;
    assert_eq!(mine["rubric"][2]["verdict"], "revise");
    assert_eq!(mine["rubric"][2]["comment"], "on no-odometry/sequential");
    let revised = post(
        &a,
        format!("{REPORT}/analyses"),
        json!({ "run": "no-odometry/sequential", "text": "revised" }),
    )
    .await;
    assert_eq!(revised.status, StatusCode::NO_CONTENT, "{}", revised.body);
    // Its answers too, after the cutoff; not the draft's.
    let corrected = answer(0, "roles", json!({"kind": "text", "value": "corrected"}));
    let taken = post(&a, ANSWERS.to_string(), corrected.clone()).await;
    assert_eq!(taken.status, StatusCode::OK, "{}", taken.body);
    assert_eq!(app.get_json(&a, QUESTIONS).await["open"], true);
    assert_eq!(
        post(&late, ANSWERS.to_string(), corrected).await.status,
        StatusCode::FORBIDDEN
    );
    assert_eq!(app.get_json(&late, QUESTIONS).await["open"], false);
    assert_eq!(app.get_json(&late, REPORT).await["may_change"], false);
    // Staff read the first hand-in until the next.
    let first = app
        .get_json(&instructor, &format!("{REPORTS}/u-a-1001"))
        .await;
    assert!(
        first["analyses"].get("no-odometry/sequential").is_none(),
        "{first}"
    );
    let again = post(
        &a,
        format!("{REPORT}/hand-in"),
        json!({ "submission": submission }),
    )
    .await;
    assert_eq!(again.status, StatusCode::OK, "{}", again.body);
    assert_eq!(again.json()["handed_in"], 2);
    let second = app
        .get_json(&instructor, &format!("{REPORTS}/u-a-1001"))
        .await;
    assert_eq!(second["analyses"]["no-odometry/sequential"], "revised");
    assert!(
        second["answers"].to_string().contains("corrected"),
        "{}",
        second["answers"]
    );

    // A rubric of the hand-in read before is not taken for the new one.
    let stale = post(
        &instructor,
        format!("{REPORTS}/u-a-1001/rubric"),
        rubric(1, &[]),
    )
    .await;
    assert_eq!(stale.status, StatusCode::CONFLICT, "{}", stale.body);
    assert!(stale.error().contains("again"), "{}", stale.error());
    let accepted = post(
        &instructor,
        format!("{REPORTS}/u-a-1001/rubric"),
        rubric(2, &[]),
    )
    .await;
    assert_eq!(accepted.status, StatusCode::OK, "{}", accepted.body);
    assert_eq!(accepted.json()["state"], "accepted");
    // The code does not pass: the lab is not passed, whatever the report.
    assert_eq!(accepted.json()["lab_passed"], false);
    assert_eq!(
        post(
            &a,
            format!("{REPORT}/analyses"),
            json!({ "run": "o3/sequential", "text": "x" })
        )
        .await
        .status,
        StatusCode::CONFLICT
    );
    let audit = app.get_json(&instructor, "/api/courses/el2320/audit").await;
    assert!(
        audit
            .to_string()
            .contains("u-a-1001's report (hand-in 2) accepted"),
        "{audit}"
    );

    // The gradebook: the report's state and whether the lab is passed, per student.
    let csv = app
        .send(
            Req::get("/api/courses/el2320/labs/ekf-localization/export?format=csv")
                .who(&instructor),
        )
        .await;
    assert_eq!(csv.status, StatusCode::OK, "{}", csv.body);
    let rows = csv_rows(&csv.body);
    let header: Vec<&str> = csv.body.lines().next().unwrap().split(',').collect();
    let column = |name: &str| {
        header
            .iter()
            .position(|c| *c == name)
            .unwrap_or_else(|| panic!("no {name}: {header:?}"))
    };
    let (status, passed) = (column("report_status"), column("lab_passed"));
    let row = |id: &str| rows.iter().find(|r| r[0] == id).unwrap();
    assert_eq!(
        (
            row("u-a-1001")[status].as_str(),
            row("u-a-1001")[passed].as_str()
        ),
        ("accepted", "no")
    );
    assert_eq!(
        (
            row("u-l-1003")[status].as_str(),
            row("u-l-1003")[passed].as_str()
        ),
        ("draft", "no")
    );
}

/// The runs at `path` once the server has made them.
async fn wait_for_runs(app: &App, who: &Who, path: &str) -> Value {
    let started = std::time::Instant::now();
    loop {
        let runs = app.get_json(who, path).await;
        if runs["state"] != "making" {
            assert_eq!(runs["state"], "made", "{runs}");
            return runs;
        }
        assert!(
            started.elapsed() < GRADING_BOUND,
            "the runs were not made within {GRADING_BOUND:?}"
        );
        tokio::time::sleep(std::time::Duration::from_millis(100)).await;
    }
}
