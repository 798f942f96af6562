//! The course set up on the web by its instructor, through the API the course's page
//! uses (the real application in-process, a clock the test sets): staff and their
//! one-time links, the roster previewed (nothing changes) then imported (codes that sign
//! in), a re-import's preview of who is added, updated and dropped, codes reissued (the
//! old one stops working), an exercise opened with its dates and policy, tokens made and
//! revoked; each change in the audit log under the instructor's name; bad input refused
//! naming the line or the field, with nothing saved changed; an assistant reads the
//! set-up and changes nothing; an instructor cannot demote themselves.

use crate::common;

use axum::http::StatusCode;
use common::*;
use estlab::store::Role;
use labs::Exercise;
use serde_json::{Value, json};

const COURSE: &str = "el2320";

async fn post(app: &App, who: &Who, path: &str, body: Value) -> Answer {
    app.send(
        Req::post(&format!("/api/courses/{COURSE}{path}"))
            .who(who)
            .json(body),
    )
    .await
}

/// The code of a sign-in link (`.../signin#CODE`).
fn code_of(link: &str) -> &str {
    link.split_once("/signin#")
        .unwrap_or_else(|| panic!("not a sign-in link: {link}"))
        .1
}

/// The codes file's rows by id: (name, code).
fn codes(answer: &Value) -> Vec<(String, String, String)> {
    let csv = answer["csv"].as_str().expect("a codes file");
    assert!(csv.starts_with("id,name,email,code,link\n"), "{csv}");
    csv_rows(csv)
        .iter()
        .map(|r| {
            assert_eq!(code_of(&r[4]), r[3], "the link carries the code");
            (r[0].clone(), r[1].clone(), r[3].clone())
        })
        .collect()
}

/// The codes file of a making of codes the server started (`{url, total}`), once made.
async fn made(app: &App, who: &Who, started: &Value) -> Value {
    let url = started["url"].as_str().expect("where to follow the making");
    let give_up = std::time::Instant::now() + GRADING_BOUND;
    loop {
        let progress = app.send(Req::get(url).who(who)).await;
        assert_eq!(progress.status, StatusCode::OK, "{}", progress.body);
        let progress = progress.json();
        assert!(progress["failed"].is_null(), "{progress}");
        if !progress["file"].is_null() {
            assert_eq!(progress["done"], progress["total"], "{progress}");
            // Handed over once: asked again, the codes are not shown.
            let again = app.send(Req::get(url).who(who)).await.json();
            assert!(
                again["file"].is_null() && again["fetched"] == true,
                "{again}"
            );
            return progress["file"].clone();
        }
        assert!(
            std::time::Instant::now() < give_up,
            "the codes were not made"
        );
        tokio::time::sleep(std::time::Duration::from_millis(20)).await;
    }
}

fn ids(list: &Value) -> Vec<&str> {
    list.as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().or_else(|| v["id"].as_str()).unwrap())
        .collect()
}

#[tokio::test(flavor = "multi_thread")]
async fn an_instructor_sets_the_course_up_on_the_web() {
    let app = App::new();
    app.store()
        .create_course(COURSE, "Applied Estimation", app.now())
        .unwrap();
    let teacher = app.staff(COURSE, "teacher@kth.example", Role::Instructor);
    let teacher = app.signed_in(&teacher).await;

    // Staff: a link that signs the new assistant in, once.
    let added = post(
        &app,
        &teacher,
        "/staff",
        json!({ "email": " ta@kth.example ", "name": "Tove Assistant", "role": "assistant" }),
    )
    .await;
    assert_eq!(added.status, StatusCode::OK, "{}", added.body);
    let added = added.json();
    assert_eq!(added["email"], "ta@kth.example");
    let assistant = app
        .sign_in(code_of(added["link"].as_str().unwrap()), peer(127, 0, 0, 1))
        .await;
    let again = app
        .send(Req::sign_in(code_of(added["link"].as_str().unwrap())))
        .await;
    assert_ne!(
        again.status,
        StatusCode::SEE_OTHER,
        "a staff link signs in once"
    );

    // The roster: a preview changes nothing; a bad line is named.
    let roster = "id,name,email\nu1,Åsa Öberg,asa@kth.example\nu2,Björn Berg,bjorn@kth.example\nu3,Cem Can,cem@kth.example\n";
    let bad = post(
        &app,
        &teacher,
        "/roster/preview",
        json!({ "file_name": "roster.csv", "csv": "id,name,email\nu1,A,a@x\nu1,B,b@x\n" }),
    )
    .await;
    assert_eq!(bad.status, StatusCode::BAD_REQUEST);
    assert!(
        bad.json()["error"]
            .as_str()
            .unwrap()
            .starts_with("roster.csv: line 3: the id \"u1\" appears a second time"),
        "{}",
        bad.body
    );
    let preview = post(
        &app,
        &teacher,
        "/roster/preview",
        json!({ "file_name": "roster.csv", "csv": roster }),
    )
    .await;
    assert_eq!(preview.status, StatusCode::OK, "{}", preview.body);
    let preview = preview.json();
    assert_eq!(ids(&preview["added"]), ["u1", "u2", "u3"]);
    assert!(preview["codes"].is_null(), "a preview makes no code");
    assert!(
        app.store()
            .members(COURSE)
            .unwrap()
            .iter()
            .all(|m| m.role.is_staff()),
        "a preview adds nobody"
    );

    // Imported: a code for each new student, each of which signs in.
    let imported = post(
        &app,
        &teacher,
        "/roster",
        json!({ "file_name": "roster.csv", "csv": roster }),
    )
    .await;
    assert_eq!(imported.status, StatusCode::OK, "{}", imported.body);
    let imported = imported.json();
    assert_eq!(imported["codes"]["total"], 3);
    let file = made(&app, &teacher, &imported["codes"]).await;
    assert_eq!(file["count"], 3);
    let first_codes = codes(&file);
    assert_eq!(first_codes[0].0, "u1");
    assert_eq!(first_codes[0].1, "Åsa Öberg");
    for (_, _, code) in &first_codes {
        app.sign_in(code, peer(127, 0, 0, 1)).await;
    }

    // A re-import: its preview says who is added, updated and dropped.
    let next = "id,name,email\nu1,Åsa Öberg,asa@kth.example\nu2,Björn Berg,bjorn.berg@kth.example\nu4,Dana Dahl,dana@kth.example\n";
    let preview = post(
        &app,
        &teacher,
        "/roster/preview",
        json!({ "file_name": "week2.csv", "csv": next }),
    )
    .await
    .json();
    assert_eq!(ids(&preview["added"]), ["u4"]);
    assert_eq!(ids(&preview["updated"]), ["u2"]);
    assert_eq!(ids(&preview["dropped"]), ["u3"]);
    assert_eq!(preview["unchanged"], 1);
    let u3 = app.store().member(COURSE, "u3").unwrap();
    assert!(!u3.dropped, "the preview dropped nobody");
    let imported = post(
        &app,
        &teacher,
        "/roster",
        json!({ "file_name": "week2.csv", "csv": next }),
    )
    .await
    .json();
    let file = made(&app, &teacher, &imported["codes"]).await;
    assert_eq!(codes(&file).len(), 1, "a code for u4 only");
    assert!(app.store().member(COURSE, "u3").unwrap().dropped);

    // Codes reissued: the new one signs in, the old one no longer.
    let reissued = post(&app, &teacher, "/codes", json!({ "students": ["u1"] })).await;
    assert_eq!(reissued.status, StatusCode::ACCEPTED, "{}", reissued.body);
    let new_code = codes(&made(&app, &teacher, &reissued.json()).await)[0]
        .2
        .clone();
    let old = app.send(Req::sign_in(&first_codes[0].2)).await;
    assert_ne!(old.status, StatusCode::SEE_OTHER, "the old code is over");
    app.sign_in(&new_code, peer(127, 0, 0, 1)).await;
    let staff_code = post(
        &app,
        &teacher,
        "/codes",
        json!({ "students": ["ta@kth.example"] }),
    )
    .await;
    assert_eq!(staff_code.status, StatusCode::BAD_REQUEST);
    assert!(
        staff_code.body.contains("staff get a new sign-in link"),
        "{}",
        staff_code.body
    );

    // An exercise opened with its dates and policy; bad dates named by field.
    let refused = [
        (
            json!({ "lab": "ekf-localization", "due": "2026-12-15T23:59" }),
            "field `due`",
        ),
        (
            json!({ "lab": "ekf-localization", "due": "2026-12-15T23:59Z", "cutoff": "2026-12-14T23:59Z" }),
            "the cutoff",
        ),
        (
            json!({ "lab": "ekf-localization", "due": "2026-12-15T23:59Z", "late_penalty": "150%/day" }),
            "field `late_penalty`",
        ),
        (
            json!({ "lab": "kalman", "due": "2026-12-15T23:59Z" }),
            "field `lab`",
        ),
    ];
    for (body, names) in refused {
        let answer = post(&app, &teacher, "/assignments", body.clone()).await;
        assert_eq!(answer.status, StatusCode::BAD_REQUEST, "{body}");
        assert!(answer.body.contains(names), "{body}: {}", answer.body);
    }
    assert!(app.store().assignments(COURSE).unwrap().is_empty());
    let opened = post(
        &app,
        &teacher,
        "/assignments",
        json!({ "lab": "odometry", "due": "2026-12-15T23:59+01:00", "cutoff": "2026-12-18T23:59+01:00",
                "late_penalty": "10%/day", "counts": "last" }),
    )
    .await;
    assert_eq!(opened.status, StatusCode::OK, "{}", opened.body);
    let stored = app
        .store()
        .assignment(COURSE, Exercise::Odometry)
        .unwrap()
        .unwrap();
    assert_eq!(stored.policy.due, at("2026-12-15T22:59Z"));
    assert_eq!(stored.policy.cutoff, at("2026-12-18T22:59Z"));
    assert_eq!(stored.policy.penalty_per_day, 0.1);
    assert_eq!(stored.policy.counts.as_str(), "last");

    // Tokens: one that works, until it is revoked.
    let made = post(&app, &teacher, "/tokens", json!({ "role": "assistant" })).await;
    assert_eq!(made.status, StatusCode::CREATED, "{}", made.body);
    let made = made.json();
    let token = Who::Token(made["token"].as_str().unwrap().to_string());
    assert_eq!(
        app.send(Req::get(&format!("/api/courses/{COURSE}")).who(&token))
            .await
            .status,
        StatusCode::OK
    );
    let id = made["id"].as_i64().unwrap();
    let revoked = post(&app, &teacher, &format!("/tokens/{id}/revoke"), json!(null)).await;
    assert_eq!(revoked.status, StatusCode::OK, "{}", revoked.body);
    assert_eq!(
        app.send(Req::get(&format!("/api/courses/{COURSE}")).who(&token))
            .await
            .status,
        StatusCode::UNAUTHORIZED
    );

    // The assistant reads the set-up, and changes nothing of it.
    let seen = app
        .get_json(&assistant, &format!("/api/courses/{COURSE}"))
        .await;
    assert_eq!(seen["may_set_up"], false);
    assert_eq!(seen["tokens"].as_array().unwrap().len(), 1);
    assert!(seen["tokens"][0]["revoked"].as_bool().unwrap());
    let before = app.store().audit_log(COURSE).unwrap().len();
    for (path, body) in [
        (
            "/staff",
            json!({ "email": "x@kth.example", "role": "instructor" }),
        ),
        (
            "/roster",
            json!({ "file_name": "r.csv", "csv": "id,name,email\n" }),
        ),
        ("/codes", json!({ "students": ["u1"] })),
        (
            "/assignments",
            json!({ "lab": "odometry", "due": "2030-01-01T00:00Z" }),
        ),
        ("/tokens", json!({ "role": "instructor" })),
    ] {
        let answer = post(&app, &assistant, path, body).await;
        assert_eq!(
            answer.status,
            StatusCode::FORBIDDEN,
            "{path}: {}",
            answer.body
        );
        assert!(answer.body.contains("only the instructors of el2320"));
    }
    assert_eq!(app.store().audit_log(COURSE).unwrap().len(), before);
    let seen = app
        .get_json(&teacher, &format!("/api/courses/{COURSE}"))
        .await;
    assert_eq!(seen["may_set_up"], true);

    // An instructor may not make themselves an assistant.
    let demoted = post(
        &app,
        &teacher,
        "/staff",
        json!({ "email": "teacher@kth.example", "role": "assistant" }),
    )
    .await;
    assert_eq!(demoted.status, StatusCode::BAD_REQUEST);
    assert!(demoted.body.contains("field `role`"));

    // Every change in the audit log, under the instructor's name, newest first.
    let log = app.store().audit_log(COURSE).unwrap();
    let actions: Vec<(&str, &str)> = log
        .iter()
        .rev()
        .map(|e| (e.action.as_str(), e.detail.as_str()))
        .collect();
    let expected = [
        ("staff", "ta@kth.example is assistant"),
        ("roster", "roster.csv: 3 new, 0 updated, 0 dropped"),
        ("roster", "week2.csv: 1 new, 1 updated, 1 dropped (u3)"),
        ("roster", "new code for u1"),
        ("assign", "odometry: due 2026-12-15T22:59:00Z"),
        ("token", "token 1 made (assistant)"),
        ("token", "token 1 revoked"),
    ];
    assert_eq!(actions.len(), expected.len(), "{actions:?}");
    for ((action, detail), (want_action, want_detail)) in actions.iter().zip(expected) {
        assert_eq!(*action, want_action);
        assert!(
            detail.starts_with(want_detail),
            "{detail:?} vs {want_detail:?}"
        );
    }
    assert!(log.iter().all(|e| e.actor == "teacher@kth.example"));
}
