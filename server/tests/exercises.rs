//! The graded exercises in one server run, in-process: a student submits the EKF
//! localization file, the odometry file and the sensor-fusion file to one course; each is
//! graded with its own exercise's tests and hidden cases, kept apart in the student's
//! history, and shown in its own class view and gradebook.

mod common;
mod student;

use common::*;
use estlab::store::Role;
use labs::Exercise;
use serde::Deserialize;
use serde_json::json;

/// What these tests read of a submission.
#[derive(Deserialize)]
struct Graded {
    lab: String,
    result: Result,
}

#[derive(Deserialize)]
struct Result {
    lab: String,
    score: f64,
    hidden_cases: bool,
    tests: Vec<Test>,
}

#[derive(Deserialize)]
struct Test {
    name: String,
}

#[derive(Deserialize)]
struct Summary {
    id: i64,
    lab: String,
}

#[derive(Deserialize)]
struct Class {
    students: Vec<Row>,
}

#[derive(Deserialize)]
struct Row {
    id: String,
    counting: Option<Shown>,
}

#[derive(Deserialize)]
struct Shown {
    id: i64,
    score: Option<f64>,
}

#[tokio::test(flavor = "multi_thread")]
async fn the_exercises_are_graded_side_by_side_each_with_its_own_tests() {
    let app = App::new();
    app.open_course("el2320");
    app.store()
        .assign("el2320", Exercise::Odometry, &open_policy(app.now()))
        .unwrap();
    app.store()
        .assign("el2320", Exercise::SensorFusion, &open_policy(app.now()))
        .unwrap();
    let ada = app.enrol("el2320", "ada");
    let who = app.signed_in(&ada).await;
    let teacher = app.staff("el2320", "teacher@example.org", Role::Instructor);
    let teacher = app.signed_in(&teacher).await;

    // All at once: a student may have one submission waiting per exercise.
    let mut ids = Vec::new();
    for (lab, source) in [
        (Exercise::EkfLocalization, student::CORRECT),
        (Exercise::Odometry, student::odometry::CORRECT),
        (Exercise::SensorFusion, student::sensor_fusion::CORRECT),
    ] {
        let answer = app
            .send(
                Req::post("/api/submissions")
                    .who(&who)
                    .json(json!({ "source": source, "lab": lab.name() })),
            )
            .await;
        assert_eq!(answer.status.as_u16(), 202, "{lab}: {}", answer.body);
        ids.push((lab, answer.json()["id"].as_i64().unwrap()));
    }
    for (lab, id) in &ids {
        app.graded(*id).await;
        let answer = app
            .send(Req::get(&format!("/api/submissions/{id}")).who(&who))
            .await;
        let graded: Graded = serde_json::from_str(&answer.body).unwrap();
        assert_eq!(
            (graded.lab.as_str(), graded.result.lab.as_str()),
            (lab.name(), lab.name())
        );
        assert_eq!(graded.result.score, 1.0, "{lab}: {}", answer.body);
        assert!(graded.result.hidden_cases, "{lab}");
        let first = &graded.result.tests[0].name;
        let expected = match lab {
            Exercise::EkfLocalization => "calculate_odometry",
            Exercise::Odometry => "odometry_step",
            Exercise::SensorFusion => "combine_platforms",
        };
        assert!(first.starts_with(expected), "{lab}: {first}");

        // The history and the class of each exercise hold its own submission only.
        let history = app
            .send(Req::get(&format!("/api/me/submissions?lab={lab}")).who(&who))
            .await;
        let history: Vec<Summary> = serde_json::from_str(&history.body).unwrap();
        assert_eq!(history.len(), 1, "{lab}");
        assert_eq!((history[0].id, history[0].lab.as_str()), (*id, lab.name()));
        let class = app
            .send(Req::get(&format!("/api/courses/el2320/labs/{lab}/class")).who(&teacher))
            .await;
        let class: Class = serde_json::from_str(&class.body).unwrap();
        let row = class.students.iter().find(|r| r.id == "ada").unwrap();
        let counting = row.counting.as_ref().expect("a counting submission");
        assert_eq!((counting.id, counting.score), (*id, Some(1.0)), "{lab}");
    }
}
