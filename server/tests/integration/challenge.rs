//! The class challenge of the sensor-fusion exercise through the real web application:
//! every submission's filter also runs, with the settings of its `tuning()`, over a trial
//! the class never sees; staff see the class ranked, a student their own figure and rank
//! (never another's), and staff can switch the ranks off.

use crate::common;

use axum::http::StatusCode;
use common::*;
use estlab::store::Role;
use labs::Exercise;
use serde_json::{Value, json};

const CORRECT: &str = include_str!("../../../tests/student/sensor_fusion/correct.js");
const LAB: &str = "sensor-fusion";

/// The correct file with `tuning()` returning other settings.
fn tuned(settings: &str) -> String {
    let defaults = "return {\n    k_xy: 0.05, k_theta: 0.05, c_xy: 90, field_of_view: 2,\n    lambda: 16.266236196238,\n  };";
    assert_eq!(CORRECT.matches(defaults).count(), 1);
    CORRECT.replace(defaults, &format!("return {settings};"))
}

/// The fusion assignment as a student sees it in `/api/me`.
fn fusion(about: &Value) -> &Value {
    about["assignments"]
        .as_array()
        .unwrap()
        .iter()
        .find(|a| a["lab"] == LAB)
        .expect("the fusion assignment")
}

/// The standing in the challenge a student sees of themselves in `/api/me`.
fn own_challenge(about: &Value) -> &Value {
    &fusion(about)["challenge"]
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_class_is_ranked_on_a_trial_it_never_sees() {
    let app = App::new();
    app.open_course("el2320");
    app.assign("el2320", Exercise::SensorFusion, &open_policy(app.now()));
    let staff = app.staff("el2320", "teacher@kth.example", Role::Assistant);
    let staff = app.signed_in(&staff).await;
    let (ana, bo, cy) = (
        app.enrol("el2320", "ana"),
        app.enrol("el2320", "bo"),
        app.enrol("el2320", "cy"),
    );
    let (ana, bo, cy) = (
        app.signed_in(&ana).await,
        app.signed_in(&bo).await,
        app.signed_in(&cy).await,
    );
    // ana tunes near the reference's settings; bo trusts the odometry far too little and
    // has no gate; cy's filter does not run at all.
    let sources = [
        (
            &ana,
            tuned("{ k_xy: 0.1, k_theta: 0.02, c_xy: 120, field_of_view: 2.5, lambda: 20 }"),
        ),
        (
            &bo,
            tuned("{ k_xy: 2, k_theta: 2, c_xy: 400, field_of_view: 5, lambda: Infinity }"),
        ),
        (&cy, quick_source("nothing yet")),
    ];
    let mut ids = Vec::new();
    for (who, source) in &sources {
        let answer = app.submit_to(who, Exercise::SensorFusion, source).await;
        assert_eq!(answer.status, StatusCode::ACCEPTED, "{}", answer.body);
        let id = answer.json()["id"].as_i64().unwrap();
        app.graded(id).await;
        ids.push(id);
    }

    // Staff: the ranking of those with a figure, the reference's figure beside.
    let class = app
        .get_json(&staff, &format!("/api/courses/el2320/labs/{LAB}/class"))
        .await;
    assert_eq!(class["ranked"], true);
    let challenge = &class["challenge"];
    let ranking = challenge["ranking"].as_array().unwrap();
    let places: Vec<(&str, i64)> = ranking
        .iter()
        .map(|e| (e["student"].as_str().unwrap(), e["rank"].as_i64().unwrap()))
        .collect();
    assert_eq!(places, [("ana", 1), ("bo", 2)], "{challenge}");
    let (first, second) = (
        ranking[0]["figure"].as_f64().unwrap(),
        ranking[1]["figure"].as_f64().unwrap(),
    );
    let reference = challenge["reference"].as_f64().unwrap();
    assert!(second > first && first != reference, "{challenge}");
    assert_eq!(ranking[0]["submission"], ids[0]);

    // A student: their own figure and rank, nobody else's.
    let about = app.get_json(&bo, "/api/me").await;
    let own = own_challenge(&about);
    assert_eq!(
        (own["rank"].as_i64(), own["of"].as_i64()),
        (Some(2), Some(2))
    );
    assert_eq!(own["figure"].as_f64(), Some(second));
    let text = about.to_string();
    assert!(!text.contains("\"ana\"") && !text.contains(&first.to_string()));
    let message = &fusion(&about)["latest"]["result"]["challenge"]["message"];
    assert!(
        message
            .as_str()
            .unwrap()
            .contains("Your filter, with tuning() = {k_xy: 2,"),
        "{message}"
    );
    assert!(own_challenge(&app.get_json(&cy, "/api/me").await).is_null());

    // Nobody but staff switches the ranks, and only in their own course.
    for who in [&ana, &bo] {
        let refused = app
            .send(
                Req::post(&format!("/api/courses/el2320/labs/{LAB}/ranking"))
                    .who(who)
                    .json(json!({ "ranked": false })),
            )
            .await;
        assert_eq!(refused.status, StatusCode::NOT_FOUND, "{}", refused.body);
    }
    let switched = app
        .send(
            Req::post(&format!("/api/courses/el2320/labs/{LAB}/ranking"))
                .who(&staff)
                .json(json!({ "ranked": false })),
        )
        .await;
    assert_eq!(switched.status, StatusCode::OK, "{}", switched.body);
    let own = app.get_json(&ana, "/api/me").await;
    let own = own_challenge(&own);
    assert_eq!(own["rank"], Value::Null);
    assert_eq!(own["figure"].as_f64(), Some(first));
    let class = app
        .get_json(&staff, &format!("/api/courses/el2320/labs/{LAB}/class"))
        .await;
    assert_eq!(class["ranked"], false);
    assert_eq!(class["challenge"]["ranking"].as_array().unwrap().len(), 2);
    let audit = app
        .get_json(&staff, "/api/courses/el2320/audit")
        .await
        .to_string();
    assert!(
        audit.contains("the class challenge's ranks hidden to students"),
        "{audit}"
    );

    // An exercise the course has not opened has no switch.
    let missing = app
        .send(
            Req::post("/api/courses/el2320/labs/odometry/ranking")
                .who(&staff)
                .json(json!({ "ranked": true })),
        )
        .await;
    assert_eq!(missing.status, StatusCode::NOT_FOUND, "{}", missing.body);
}
