//! The written part of an assignment through the real web application: students read
//! the questions without what they are checked against and save their answers until
//! their cutoff; staff read the sets in full; instructors give other sets, a problem
//! named by its set, line, question and field, and answers stay by question id.

mod common;

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
