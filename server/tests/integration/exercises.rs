//! The graded exercises in one server run, in-process: a student submits the EKF
//! localization file, the odometry file and the sensor-fusion file to one course; each is
//! graded with its own exercise's tests and hidden cases, kept apart in the student's
//! history, and shown in its own class view and gradebook.

use crate::common;
use crate::student;

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
    for lab in [Exercise::SensorFusion, Exercise::UkfParticle] {
        app.store()
            .assign("el2320", lab, &open_policy(app.now()))
            .unwrap();
    }
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
        (Exercise::UkfParticle, student::ukf_particle::CORRECT),
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
            Exercise::UkfParticle => "motion",
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

/// What these tests read of a submission's language.
#[derive(Deserialize)]
struct Written {
    language: String,
    result: Result,
}

#[tokio::test(flavor = "multi_thread")]
async fn a_python_file_is_graded_in_its_language_and_kept_with_it() {
    let app = App::new();
    app.open_course("el2320");
    let ada = app.enrol("el2320", "ada");
    let who = app.signed_in(&ada).await;

    // A language the server does not know is refused, naming the field.
    let answer = app
        .send(
            Req::post("/api/submissions").who(&who).json(
                json!({ "source": "x = 1", "lab": "ekf-localization", "language": "fortran" }),
            ),
        )
        .await;
    assert_eq!(answer.status.as_u16(), 400, "{}", answer.body);
    assert!(
        answer
            .body
            .contains("field `language`: unknown language \\\"fortran\\\""),
        "{}",
        answer.body
    );

    // Submitted, graded, and read back.
    let graded = async |body: serde_json::Value| {
        let answer = app
            .send(Req::post("/api/submissions").who(&who).json(body))
            .await;
        assert_eq!(answer.status.as_u16(), 202, "{}", answer.body);
        let id = answer.json()["id"].as_i64().unwrap();
        app.graded(id).await;
        let answer = app
            .send(Req::get(&format!("/api/submissions/{id}")).who(&who))
            .await;
        let written: Written = serde_json::from_str(&answer.body).unwrap();
        (id, written)
    };
    let (id, written) = graded(json!({
        "source": student::python::EKF_LOCALIZATION.correct,
        "lab": "ekf-localization",
        "language": "python",
    }))
    .await;
    assert_eq!(written.language, "python");
    assert_eq!(written.result.score, 1.0);
    assert!(written.result.hidden_cases);
    // Its regrade grades it in its language again.
    let again = app.store().to_grade(id).unwrap();
    assert_eq!(again.language, labs::Language::Python);

    // The same file taken for JavaScript does not compile: the language is the student's
    // to say, and the result says what went wrong.
    let (_, written) = graded(json!({
        "source": student::python::EKF_LOCALIZATION.correct,
        "lab": "ekf-localization",
    }))
    .await;
    assert_eq!(written.language, "javascript");
    assert_eq!(written.result.score, 0.0);
}

/// What these tests read of a phase run on the server.
#[derive(Deserialize)]
struct PhaseOutputs {
    functions: Vec<FunctionOutput>,
    runs: Vec<RunOutput>,
}

#[derive(Deserialize)]
struct FunctionOutput {
    function: String,
    results: Vec<serde_json::Value>,
}

#[derive(Deserialize)]
struct RunOutput {
    name: String,
    error: Option<String>,
}

#[tokio::test(flavor = "multi_thread")]
async fn a_phase_of_the_shown_cases_runs_on_the_server_for_the_workbench() {
    let app = App::new();
    let ask = |phase: &str, source: &str| {
        Req::post("/api/phases").json(json!({
            "lab": "odometry", "language": "python", "seed": 2320,
            "phase": phase, "source": source,
        }))
    };
    let correct = student::python::ODOMETRY.correct;
    // A function's tests: the outputs of its shown cases and of their repeats.
    let answer = app.send(ask("wheel_noise", correct)).await;
    assert_eq!(answer.status.as_u16(), 200, "{}", answer.body);
    let outputs: PhaseOutputs = serde_json::from_str(&answer.body).unwrap();
    assert_eq!(outputs.runs.len(), 0);
    assert_eq!(outputs.functions.len(), 1);
    assert_eq!(outputs.functions[0].function, "wheel_noise");
    assert_eq!(outputs.functions[0].results.len(), 12);
    // A run of the loop.
    let answer = app.send(ask("square", correct)).await;
    assert_eq!(answer.status.as_u16(), 200, "{}", answer.body);
    let outputs: PhaseOutputs = serde_json::from_str(&answer.body).unwrap();
    assert_eq!(outputs.runs.len(), 1);
    assert_eq!(
        (outputs.runs[0].name.as_str(), &outputs.runs[0].error),
        ("square", &None)
    );
    // No such phase, named.
    let answer = app.send(ask("o3/sequential", correct)).await;
    assert_eq!(answer.status.as_u16(), 400, "{}", answer.body);
    assert!(answer.body.contains("field `phase`"), "{}", answer.body);

    // An asker's share of a minute, then a refusal that says when to try again.
    let mut refused = None;
    let quick = |phase: &str| {
        Req::post("/api/phases").json(json!({
            "lab": "odometry", "seed": 2320, "phase": phase, "source": "function f() {}",
        }))
    };
    for _ in 0..=estlab::web::phases::PER_MINUTE {
        let answer = app.send(quick("wheel_noise")).await;
        if answer.status.as_u16() == 429 {
            refused = Some(answer.body);
            break;
        }
        assert_eq!(answer.status.as_u16(), 200, "{}", answer.body);
    }
    let refused = refused.expect("a refusal within the minute");
    assert!(refused.contains("in the last minute"), "{refused}");
    // Once the minute has passed, the asker runs again.
    app.clock
        .set(app.now() + jiff::SignedDuration::from_secs(61));
    let answer = app.send(ask("wheel_noise", correct)).await;
    assert_eq!(answer.status.as_u16(), 200, "{}", answer.body);

    // With courses, only the signed-in run their files here.
    app.open_course("el2320");
    let answer = app.send(ask("wheel_noise", correct)).await;
    assert_eq!(answer.status.as_u16(), 401, "{}", answer.body);
}

#[derive(Deserialize)]
struct LanguagesSet {
    languages: Vec<String>,
}

#[tokio::test(flavor = "multi_thread")]
async fn staff_restrict_an_assignment_to_some_languages() {
    let app = App::new();
    app.open_course("el2320");
    let ada = app.enrol("el2320", "ada");
    let who = app.signed_in(&ada).await;
    let teacher = app.staff("el2320", "teacher@example.org", Role::Instructor);
    let teacher = app.signed_in(&teacher).await;
    let path = "/api/courses/el2320/labs/odometry/languages";
    app.store()
        .assign("el2320", Exercise::Odometry, &open_policy(app.now()))
        .unwrap();

    // Refused, naming the field: no language, or one not graded here.
    for body in [
        json!({ "languages": [] }),
        json!({ "languages": ["octave"] }),
    ] {
        let answer = app.send(Req::post(path).who(&teacher).json(body)).await;
        assert_eq!(answer.status.as_u16(), 400, "{}", answer.body);
        assert!(answer.body.contains("field `languages`"), "{}", answer.body);
    }
    let answer = app
        .send(
            Req::post(path)
                .who(&teacher)
                .json(json!({ "languages": ["python"] })),
        )
        .await;
    assert_eq!(answer.status.as_u16(), 200, "{}", answer.body);
    let set: LanguagesSet = serde_json::from_str(&answer.body).unwrap();
    assert_eq!(set.languages, ["python"]);

    // A JavaScript file is refused, saying which language the course takes; Python is
    // taken; the student's view and the class view say so.
    let submit = |language: &str| {
        Req::post("/api/submissions").who(&who).json(json!({
            "source": student::odometry::CORRECT, "lab": "odometry", "language": language,
        }))
    };
    let answer = app.send(submit("javascript")).await;
    assert_eq!(answer.status.as_u16(), 403, "{}", answer.body);
    assert!(
        answer
            .body
            .contains("your course takes files of odometry in Python only"),
        "{}",
        answer.body
    );
    let answer = app.send(submit("python")).await;
    assert_eq!(answer.status.as_u16(), 202, "{}", answer.body);
    let me = app.send(Req::get("/api/me").who(&who)).await;
    assert!(me.body.contains(r#""languages":["python"]"#), "{}", me.body);
    let class = app
        .send(Req::get("/api/courses/el2320/labs/odometry/class").who(&teacher))
        .await;
    assert!(
        class.body.contains(r#""languages":["python"]"#),
        "{}",
        class.body
    );

    // Every language again: no restriction.
    let answer = app
        .send(
            Req::post(path)
                .who(&teacher)
                .json(json!({ "languages": ["python", "javascript"] })),
        )
        .await;
    let set: LanguagesSet = serde_json::from_str(&answer.body).unwrap();
    assert_eq!(set.languages, ["javascript", "python"]);
    app.graded(
        app.store()
            .course_submissions("el2320", Exercise::Odometry)
            .unwrap()[0]
            .id,
    )
    .await;
    let answer = app.send(submit("javascript")).await;
    assert_eq!(answer.status.as_u16(), 202, "{}", answer.body);
}
