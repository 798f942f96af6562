//! Who may reach which object through which route, between courses. `access.rs` asks who
//! may open each route; this asks who may reach an object through it: the staff (an
//! instructor, an assistant) and the API token of one course name the other course's
//! objects (a submission, a student, a regrade, an extension's student) through their
//! own course's URLs, both ways round. The rules (DESIGN.md, "Courses: who may see and
//! change what"):
//!
//! - an id of another course is answered exactly as an id that exists nowhere;
//! - no answer to one course's staff holds anything of another course (its people's
//!   names, emails and code, its staff, its title, its extension's dates; any `course`
//!   field of a JSON answer is the asker's course), exports and pages included;
//! - nothing of the other course changes (no regrade of its submissions, no extension
//!   for its students, nothing in its audit log).
//!
//! - `staff_of_one_course_reach_nothing_of_another`: the object matrix;
//! - `every_route_with_a_parameter_is_in_the_object_matrix`: a new route that takes an
//!   id must be added to it.

use crate::common;

use axum::http::{StatusCode, header};
use common::*;
use estlab::store::{Role, Store};
use serde_json::{Value, json};

const LAB: &str = "ekf-localization";

/// A login on both courses' rosters: the same person in two courses is two members.
const BOTH: &str = "u-both-3090";

/// One request of the matrix. In `path` and `body`, `{course}` is the asker's own course
/// (always: the matrix is about reaching through one's own course's URLs), `{lab}` the
/// exercise, and `{submission}`, `{student}` and `{regrade}` the ids of the course whose
/// object is asked for: the asker's own, the other course's, or ids that exist nowhere.
struct Row {
    method: &'static str,
    /// The route as the router names it (for the completeness check).
    route: &'static str,
    path: &'static str,
    body: Option<&'static str>,
    /// The answer with the asker's own course's ids.
    own: u16,
    /// The answer with the other course's ids, which must be the answer with ids that
    /// exist nowhere; `None` for a request that names no object, asked once.
    other: Option<u16>,
    /// A number the answer with the asker's own ids holds: (JSON pointer, value).
    holds: Option<(&'static str, i64)>,
    /// A change of the course's set-up: its assistant is refused (403) whatever it names.
    instructors: bool,
}

const fn row(method: &'static str, route: &'static str, path: &'static str) -> Row {
    Row {
        method,
        route,
        path,
        body: None,
        own: 200,
        other: None,
        holds: None,
        instructors: false,
    }
}

impl Row {
    const fn body(self, body: &'static str) -> Row {
        Row {
            body: Some(body),
            ..self
        }
    }

    const fn own(self, own: u16) -> Row {
        Row { own, ..self }
    }

    const fn other(self, other: u16) -> Row {
        Row {
            other: Some(other),
            ..self
        }
    }

    const fn holds(self, pointer: &'static str, value: i64) -> Row {
        Row {
            holds: Some((pointer, value)),
            ..self
        }
    }

    const fn instructors(self) -> Row {
        Row {
            instructors: true,
            ..self
        }
    }

    /// What `asker` gets with the asker's own ids, and with another course's.
    fn expected(&self, asker: &str) -> (u16, Option<u16>) {
        if self.instructors && asker.ends_with("assistant") {
            (403, self.other.map(|_| 403))
        } else {
            (self.own, self.other)
        }
    }

    /// The object placeholder the row names, if any.
    fn names(&self) -> Option<&'static str> {
        [
            "{submission}",
            "{student}",
            "{regrade}",
            "{token}",
            "{round}",
            "{codes}",
        ]
        .into_iter()
        .find(|p| self.path.contains(p) || self.body.is_some_and(|b| b.contains(p)))
    }
}

const STUDENT: &str = "/api/courses/{course}/labs/{lab}/students/{student}";
const EXPORT: &str = "/api/courses/{course}/labs/{lab}/export";
const REGRADES: &str = "/api/courses/{course}/regrades";
const EXTENSIONS: &str = "/api/courses/{course}/extensions";

/// Every route that takes a parameter, with the objects it can name. Each course holds
/// a student of its own (`{student}`, with a graded submission `{submission}`), `BOTH`
/// (with a graded submission), a finished regrade (`{regrade}`) and an extension.
#[rustfmt::skip]
const OBJECTS: &[Row] = &[
    // A submission, by id: the other course's is a 404 like one that does not exist.
    row("GET", "/api/submissions/{id}", "/api/submissions/{submission}").other(404),
    // The course's own lists: nothing of the other course in them.
    row("GET", "/api/courses/{course}", "/api/courses/{course}"),
    row("GET", "/api/courses/{course}/submissions", "/api/courses/{course}/submissions"),
    row("GET", "/api/courses/{course}/labs/{lab}/class", "/api/courses/{course}/labs/{lab}/class"),
    // The class challenge's ranks switch names no object but the course's exercise.
    row("POST", "/api/courses/{course}/labs/{lab}/ranking", "/api/courses/{course}/labs/{lab}/ranking")
        .body(r#"{"ranked": true}"#),
    // So does the choice of its languages.
    row("POST", "/api/courses/{course}/labs/{lab}/languages", "/api/courses/{course}/labs/{lab}/languages")
        .body(r#"{"languages": ["javascript", "python"]}"#),
    // The written questions name no object but the course's exercise; staff answer none.
    row("GET", "/api/courses/{course}/labs/{lab}/questions", "/api/courses/{course}/labs/{lab}/questions"),
    row("POST", "/api/courses/{course}/labs/{lab}/questions", "/api/courses/{course}/labs/{lab}/questions")
        .body(r#"{"sets": null}"#).instructors(),
    row("POST", "/api/courses/{course}/labs/{lab}/answers", "/api/courses/{course}/labs/{lab}/answers")
        .body(r#"{"part": 0, "question": "roles", "answer": {"kind": "text", "value": "a state"}}"#).own(403),
    // Review rounds: the course's own list; a new one while one is open is refused; a
    // round by id, the other course's a 404 like one that does not exist; staff review
    // no sheets, of any round.
    row("GET", "/api/courses/{course}/labs/{lab}/rounds", "/api/courses/{course}/labs/{lab}/rounds"),
    row("POST", "/api/courses/{course}/labs/{lab}/rounds", "/api/courses/{course}/labs/{lab}/rounds")
        .body(r#"{"part": 0, "per_sheet": 1}"#).own(400),
    row("POST", "/api/courses/{course}/labs/{lab}/rounds/{id}", "/api/courses/{course}/labs/{lab}/rounds/{round}")
        .body(r#"{"action": "join", "student": "u-both-3090"}"#).own(400).other(404),
    row("GET", "/api/courses/{course}/labs/{lab}/reviews", "/api/courses/{course}/labs/{lab}/reviews").own(403),
    row("GET", "/api/courses/{course}/labs/{lab}/reviews/{round}/{sheet}", "/api/courses/{course}/labs/{lab}/reviews/{round}/1")
        .own(403).other(403),
    row("POST", "/api/courses/{course}/labs/{lab}/reviews/{round}/{sheet}", "/api/courses/{course}/labs/{lab}/reviews/{round}/1")
        .body(r#"{"marks": [], "submit": false}"#).own(403).other(403),
    // The report: staff write none of their own; the class's list holds this course's
    // students only; a student's report, its runs and its rubric, by id: the other
    // course's is no student of this one (a rubric judging no part is refused, 400).
    row("GET", "/api/courses/{course}/labs/{lab}/report", "/api/courses/{course}/labs/{lab}/report").own(403),
    row("GET", "/api/courses/{course}/labs/{lab}/report/runs", "/api/courses/{course}/labs/{lab}/report/runs").own(403),
    row("POST", "/api/courses/{course}/labs/{lab}/report/analyses", "/api/courses/{course}/labs/{lab}/report/analyses")
        .body(r#"{"run": "o3/sequential", "text": "why"}"#).own(403),
    row("POST", "/api/courses/{course}/labs/{lab}/report/hand-in", "/api/courses/{course}/labs/{lab}/report/hand-in").own(403),
    row("GET", "/api/courses/{course}/labs/{lab}/reports", "/api/courses/{course}/labs/{lab}/reports"),
    row("GET", "/api/courses/{course}/labs/{lab}/reports/{student}", "/api/courses/{course}/labs/{lab}/reports/{student}")
        .other(404),
    row("GET", "/api/courses/{course}/labs/{lab}/reports/{student}/runs", "/api/courses/{course}/labs/{lab}/reports/{student}/runs")
        .other(404),
    row("POST", "/api/courses/{course}/labs/{lab}/reports/{student}/rubric", "/api/courses/{course}/labs/{lab}/reports/{student}/rubric")
        .body(r#"{"handed_in": 1, "parts": []}"#).own(400).other(404),
    // A student, by id: the other course's is no student of this one; one on both
    // rosters is this course's member, with this course's submissions only.
    row("GET", STUDENT, STUDENT).other(404),
    row("GET", STUDENT, "/api/courses/{course}/labs/{lab}/students/u-both-3090"),
    // The exports: this course's people and files only.
    row("GET", EXPORT, "/api/courses/{course}/labs/{lab}/export?format=csv"),
    row("GET", EXPORT, "/api/courses/{course}/labs/{lab}/export?format=gradescope"),
    row("GET", EXPORT, "/api/courses/{course}/labs/{lab}/export?format=prairielearn"),
    row("GET", EXPORT, "/api/courses/{course}/labs/{lab}/export?format=sources"),
    // A regrade's scope names a submission or a student: the other course's are nothing
    // to regrade; a student on both rosters is regraded in this course only.
    row("POST", REGRADES, REGRADES).body(r#"{"scope": {"kind": "submission", "of": {submission}}}"#)
        .own(202).other(409).holds("/total", 1),
    row("POST", REGRADES, REGRADES).body(r#"{"scope": {"kind": "student", "of": "{student}"}}"#)
        .own(202).other(409).holds("/total", 1),
    row("POST", REGRADES, REGRADES).body(r#"{"scope": {"kind": "student", "of": "u-both-3090"}}"#)
        .own(202).holds("/total", 1),
    row("POST", REGRADES, REGRADES).body(r#"{"scope": {"kind": "assignment"}}"#)
        .own(202).holds("/total", 2),
    // A regrade, by id: the other course's is a 404 like one that does not exist.
    row("GET", "/api/courses/{course}/regrades/{id}", "/api/courses/{course}/regrades/{regrade}").other(404),
    // An extension names a student: the other course's is no student of this one.
    row("POST", EXTENSIONS, EXTENSIONS).body(r#"{"student": "{student}", "due": "2032-01-01T00:00Z"}"#)
        .other(404),
    row("POST", EXTENSIONS, EXTENSIONS).body(r#"{"student": "u-both-3090", "due": "2032-01-01T00:00Z"}"#),
    // A waiver names a submission: the other course's is a 404 like one that does not
    // exist, and keeps its penalty.
    row("POST", "/api/courses/{course}/submissions/{id}/waiver", "/api/courses/{course}/submissions/{submission}/waiver")
        .body(r#"{"reason": "a doctor's note"}"#).other(404),
    // The audit log: this course's actions only.
    row("GET", "/api/courses/{course}/audit", "/api/courses/{course}/audit"),
    // The course's set-up, for its instructors: a token to revoke, by id, the other
    // course's is a 404 like one that does not exist; a student to give a new code, by
    // id, the other course's is nobody of this one (404, as for any student missing);
    // the rest name no object. `{roster}` is the course's own roster as it is, so
    // importing it changes nobody.
    row("POST", "/api/courses/{course}/staff", "/api/courses/{course}/staff")
        .body(r#"{"email": "new.ta@staff.example", "role": "assistant"}"#).instructors(),
    row("POST", "/api/courses/{course}/roster/preview", "/api/courses/{course}/roster/preview")
        .body(r#"{"file_name": "roster.csv", "csv": {roster}}"#).instructors().holds("/unchanged", 2),
    row("POST", "/api/courses/{course}/roster", "/api/courses/{course}/roster")
        .body(r#"{"file_name": "roster.csv", "csv": {roster}}"#).instructors().holds("/unchanged", 2),
    row("POST", "/api/courses/{course}/codes", "/api/courses/{course}/codes")
        .body(r#"{"students": ["{student}"]}"#).instructors().other(404).own(202).holds("/total", 1),
    // The making of codes: the course's own job, for its instructors.
    row("GET", "/api/courses/{course}/codes/{id}", "/api/courses/{course}/codes/{codes}")
        .instructors().other(404).holds("/total", 0),
    row("POST", "/api/courses/{course}/assignments", "/api/courses/{course}/assignments")
        .body(r#"{"lab": "{lab}", "due": "2031-01-01T00:00Z", "cutoff": "2032-06-01T00:00Z", "late_penalty": "10%/day"}"#)
        .instructors(),
    row("POST", "/api/courses/{course}/tokens", "/api/courses/{course}/tokens")
        .body(r#"{"role": "assistant"}"#).instructors().own(201),
    row("POST", "/api/courses/{course}/tokens/{id}/revoke", "/api/courses/{course}/tokens/{token}/revoke")
        .instructors().other(404),
    // The pages (their data comes from the API above); a student's page names whoever
    // was typed in its URL, and nothing else.
    row("GET", "/courses/{course}", "/courses/{course}"),
    row("GET", "/courses/{course}/{lab}", "/courses/{course}/{lab}"),
    row("GET", "/courses/{course}/{lab}/questions", "/courses/{course}/{lab}/questions"),
    row("GET", "/courses/{course}/{lab}/report", "/courses/{course}/{lab}/report"),
    row("GET", "/courses/{course}/{lab}/students/{student}", "/courses/{course}/{lab}/students/{student}")
        .other(200),
];

/// The ids of a course's objects (or ids of nothing) that fill a row.
struct Ids {
    submission: i64,
    student: String,
    regrade: i64,
    /// An open review round of Part I, between the course's two students.
    round: i64,
    /// A spare API token's id (revoking it again changes nothing).
    token: i64,
    /// A job of sign-in codes, made (its file fetched already).
    codes: i64,
    /// The course's roster as a CSV, as a JSON string.
    roster: String,
}

impl Ids {
    fn nowhere() -> Ids {
        Ids {
            submission: 999_999,
            student: "u-nobody-0000".into(),
            regrade: 999_999,
            round: 999_999,
            token: 999_999,
            codes: 999_999,
            roster: json!("id,name,email\n").to_string(),
        }
    }

    fn fill(&self, text: &str, course: &str) -> String {
        text.replace("{course}", course)
            .replace("{lab}", LAB)
            .replace("{submission}", &self.submission.to_string())
            .replace("{student}", &self.student)
            .replace("{regrade}", &self.regrade.to_string())
            .replace("{round}", &self.round.to_string())
            .replace("{token}", &self.token.to_string())
            .replace("{codes}", &self.codes.to_string())
            .replace("{roster}", &self.roster)
    }

    /// What is typed for a placeholder.
    fn typed(&self, placeholder: &str) -> String {
        match placeholder {
            "{submission}" => self.submission.to_string(),
            "{student}" => self.student.clone(),
            "{token}" => self.token.to_string(),
            "{round}" => self.round.to_string(),
            "{codes}" => self.codes.to_string(),
            _ => self.regrade.to_string(),
        }
    }
}

/// A course with one of everything, and who acts for it.
struct Course {
    name: &'static str,
    ids: Ids,
    /// `BOTH`'s submission in this course, and `BOTH` signed in to this course.
    both_submission: i64,
    both: Who,
    /// Its instructor and assistant, signed in, and its API token.
    askers: Vec<(String, Who)>,
    /// Texts found in this course's data only.
    markers: Vec<String>,
}

/// A course `name` whose every text carries `tag`: a student of its own and `BOTH`, each
/// with a graded submission; an instructor, an assistant and an API token; a finished
/// regrade of the assignment; an extension (due on `extended`) for its own student; and
/// so an audit log.
async fn course(app: &App, name: &'static str, tag: &str, student: &str, extended: &str) -> Course {
    let store = app.store();
    let now = app.now();
    let title = format!("Course {tag}");
    store.create_course(name, &title, now).unwrap();
    app.assign(name, labs::Exercise::EkfLocalization, &open_policy(now));
    let (student_name, student_email) =
        (format!("Student {tag}"), format!("{tag}@students.example"));
    let (both_name, both_email) = (
        format!("Both {tag}"),
        format!("both.{tag}@students.example"),
    );
    store
        .import_roster(
            name,
            &[
                roster_line(student, &student_name, &student_email),
                roster_line(BOTH, &both_name, &both_email),
            ],
        )
        .unwrap();
    let instructor_email = format!("teacher.{tag}@staff.example");
    let assistant_email = format!("ta.{tag}@staff.example");
    let instructor = app.staff(name, &instructor_email, Role::Instructor);
    let assistant = app.staff(name, &assistant_email, Role::Assistant);
    let (_, token) = store.create_token(name, Role::Instructor, now).unwrap();
    let (spare_token, _) = store.create_token(name, Role::Assistant, now).unwrap();
    let roster = json!(format!(
        "id,name,email\n{student},{student_name},{student_email}\n{BOTH},{both_name},{both_email}\n"
    ))
    .to_string();
    let instructor = app.signed_in(&instructor).await;
    let assistant = app.signed_in(&assistant).await;

    let (student_source, both_source) =
        (format!("source-of-{tag}"), format!("both-source-of-{tag}"));
    let own = app.signed_in(&store.member(name, student).unwrap()).await;
    let (submission, _) = app
        .submit_graded(&own, &quick_source(&student_source))
        .await;
    let both = app.signed_in(&store.member(name, BOTH).unwrap()).await;
    let (both_submission, _) = app.submit_graded(&both, &quick_source(&both_source)).await;

    let started = app
        .send(
            Req::post(&format!("/api/courses/{name}/regrades"))
                .who(&instructor)
                .json(json!({ "scope": { "kind": "assignment" } })),
        )
        .await;
    assert_eq!(started.status, StatusCode::ACCEPTED, "{}", started.body);
    let regrade = started.json()["id"].as_i64().unwrap();
    app.regrades_done().await;
    let extension = app
        .send(
            Req::post(&format!("/api/courses/{name}/extensions"))
                .who(&instructor)
                .json(json!({ "student": student, "due": format!("{extended}T00:00Z") })),
        )
        .await;
    assert_eq!(extension.status, StatusCode::OK, "{}", extension.body);
    // Both students answer Part I, and a round hands each the other's sheet.
    for (who, text) in [(&own, &student_source), (&both, &both_source)] {
        let answer =
            json!({"part": 0, "question": "roles", "answer": {"kind": "text", "value": text}});
        let saved = app
            .send(
                Req::post(&format!("/api/courses/{name}/labs/{LAB}/answers"))
                    .who(who)
                    .json(answer),
            )
            .await;
        assert_eq!(saved.status, StatusCode::OK, "{}", saved.body);
    }
    let opened = app
        .send(
            Req::post(&format!("/api/courses/{name}/labs/{LAB}/rounds"))
                .who(&instructor)
                .json(json!({ "part": 0, "per_sheet": 1 })),
        )
        .await;
    assert_eq!(opened.status, StatusCode::OK, "{}", opened.body);
    let round = opened.json()["id"].as_i64().unwrap();
    let store = app.store();
    let codes = store
        .start_codes_job(name, 0, &app.state.grader.lease())
        .unwrap();
    let file = r#"{"file_name": "codes.csv", "count": 0, "csv": "id,name,email,code,link\n"}"#;
    store
        .end_codes_job(codes, Ok(file), app.state.grader.lease().holder)
        .unwrap();

    Course {
        name,
        ids: Ids {
            submission,
            student: student.into(),
            regrade,
            round,
            token: spare_token,
            codes,
            roster,
        },
        both_submission,
        both,
        askers: vec![
            (format!("{name}'s instructor"), instructor),
            (format!("{name}'s assistant"), assistant),
            (format!("{name}'s API token"), Who::Token(token)),
        ],
        markers: vec![
            title,
            student_name,
            student_email,
            both_name,
            both_email,
            student_source,
            both_source,
            instructor_email,
            assistant_email,
            extended.into(),
        ],
    }
}

/// What a course holds that the other course's staff must leave alone: its extensions,
/// regrades, audit log, submissions and the results regrades replaced.
fn state_of(store: &Store, course: &str) -> String {
    let submissions = store
        .course_submissions(course, labs::Exercise::EkfLocalization)
        .unwrap();
    let earlier: Vec<usize> = submissions
        .iter()
        .map(|s| store.earlier_results(s.id).unwrap().len())
        .collect();
    format!(
        "{:?}\n{:?}\n{:?}\n{:?}\n{earlier:?}",
        store
            .extensions(course, labs::Exercise::EkfLocalization)
            .unwrap(),
        store.regrades(course).unwrap(),
        store.audit_log(course).unwrap(),
        submissions,
    )
}

/// Every string `course` field of a JSON value, at any depth.
fn courses_named(value: &Value, found: &mut Vec<String>) {
    match value {
        Value::Object(map) => {
            for (key, value) in map {
                if let (true, Value::String(course)) = (key == "course", value) {
                    found.push(course.clone());
                }
                courses_named(value, found);
            }
        }
        Value::Array(items) => items.iter().for_each(|v| courses_named(v, found)),
        _ => {}
    }
}

/// The texts of an answer to search: its body, or each file of a zip with its name.
fn texts(answer: &Answer) -> Vec<String> {
    let zip = answer
        .headers
        .get(header::CONTENT_TYPE)
        .is_some_and(|t| t == "application/zip");
    if zip {
        unzip(&answer.raw)
            .into_iter()
            .flat_map(|(name, text)| [name, text])
            .collect()
    } else {
        vec![answer.body.clone()]
    }
}

/// `text` with `word` written as N wherever it stands alone (not inside a longer word or
/// number).
fn word_as_n(text: &str, word: &str) -> String {
    let alone = |c: Option<char>| !c.is_some_and(|c| c.is_alphanumeric() || c == '-');
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find(word) {
        let after = &rest[at + word.len()..];
        out.push_str(&rest[..at]);
        let standing_alone = alone(out.chars().last()) && alone(after.chars().next());
        out.push_str(if standing_alone { "N" } else { word });
        rest = after;
    }
    out.push_str(rest);
    out
}

/// An answer with what was typed written as N: the status, the content type, and the
/// body (in a JSON error, its message), to compare with the answer for another id.
fn shape(answer: &Answer, typed: &str) -> Value {
    let body = match serde_json::from_str::<Value>(&answer.body) {
        Ok(mut json) => {
            if let Some(error) = json.get("error").and_then(Value::as_str) {
                json["error"] = Value::String(word_as_n(error, typed));
            }
            json
        }
        Err(_) => Value::String(word_as_n(&answer.body, typed)),
    };
    json!({
        "status": answer.status.as_u16(),
        "content-type": answer.headers.get(header::CONTENT_TYPE).and_then(|v| v.to_str().ok()),
        "body": body,
    })
}

async fn ask(app: &App, row: &Row, who: &Who, course: &str, ids: &Ids) -> (String, Answer) {
    let path = ids.fill(row.path, course);
    let mut request = match row.method {
        "GET" => Req::get(&path),
        "POST" => Req::post(&path),
        other => panic!("no method {other}"),
    };
    let mut asked = format!("{} {path}", row.method);
    if let Some(body) = row.body {
        let body = ids.fill(body, course);
        asked.push_str(&format!(" {body}"));
        request = request.json(serde_json::from_str(&body).expect("a row's body is JSON"));
    }
    (asked, app.send(request.who(who)).await)
}

/// Proves, for every route that takes a parameter and both ways round, that the staff
/// and the token of one course reach the objects of their own course through it, and
/// that the other course's ids get exactly the answer of ids that exist nowhere; that
/// no answer they receive holds anything of the other course; that nothing of the other
/// course changed; and that a person on both rosters, signed in to one course, does not
/// read their submission of the other.
#[tokio::test(flavor = "multi_thread")]
async fn staff_of_one_course_reach_nothing_of_another() {
    let app = App::new();
    let el2320 = course(&app, "el2320", "alfa7731", "u-alfa-7731", "2031-03-03").await;
    let other = course(&app, "other", "omega4412", "u-omega-4412", "2031-07-07").await;

    let mut problems = Vec::new();
    for (asker, owner) in [(&el2320, &other), (&other, &el2320)] {
        app.regrades_done().await;
        let before = state_of(app.store(), owner.name);
        for (name, who) in &asker.askers {
            for row in OBJECTS {
                let (own, other) = row.expected(name);
                let (asked, answer) = ask(&app, row, who, asker.name, &asker.ids).await;
                let mut problem =
                    |what: String| problems.push(format!("{asked} as {name}: {what}"));
                if answer.status.as_u16() != own {
                    problem(format!(
                        "expected {own}, got {}: {}",
                        answer.status, answer.body
                    ));
                } else if own == row.own
                    && let Some((pointer, value)) = row.holds
                    && answer.json().pointer(pointer).and_then(Value::as_i64) != Some(value)
                {
                    problem(format!("expected {pointer} = {value}: {}", answer.body));
                }
                let mut answers = vec![(asked.clone(), answer)];

                if let (Some(expected), Some(placeholder)) = (other, row.names()) {
                    let (asked, answer) = ask(&app, row, who, asker.name, &owner.ids).await;
                    let (_, nowhere) = ask(&app, row, who, asker.name, &Ids::nowhere()).await;
                    let mut problem =
                        |what: String| problems.push(format!("{asked} as {name}: {what}"));
                    if answer.status.as_u16() != expected {
                        problem(format!(
                            "expected {expected}, got {}: {}",
                            answer.status, answer.body
                        ));
                    }
                    let (theirs, none) = (
                        shape(&answer, &owner.ids.typed(placeholder)),
                        shape(&nowhere, &Ids::nowhere().typed(placeholder)),
                    );
                    if theirs != none {
                        problem(format!(
                            "differs from the answer for an id of nothing:\n  {theirs}\n  {none}"
                        ));
                    }
                    answers.push((asked, answer));
                }

                // Nothing of the other course in any of these answers.
                for (asked, answer) in &answers {
                    for text in texts(answer) {
                        for marker in &owner.markers {
                            if text.contains(marker.as_str()) {
                                problems.push(format!(
                                    "{asked} as {name}: the answer holds {}'s {marker:?}",
                                    owner.name
                                ));
                            }
                        }
                        if let Ok(json) = serde_json::from_str::<Value>(&text) {
                            let mut found = Vec::new();
                            courses_named(&json, &mut found);
                            found.retain(|c| c != asker.name);
                            if !found.is_empty() {
                                problems.push(format!(
                                    "{asked} as {name}: the answer names the course(s) {found:?}"
                                ));
                            }
                        }
                    }
                }
            }
        }
        let after = state_of(app.store(), owner.name);
        if after != before {
            problems.push(format!(
                "{}'s staff changed {}:\nbefore {before}\nafter  {after}",
                asker.name, owner.name
            ));
        }

        // The same person, signed in to the asker's course, reads nothing of their
        // submission to the other.
        let (asked, answer) = ask(
            &app,
            &OBJECTS[0],
            &asker.both,
            asker.name,
            &Ids {
                submission: owner.both_submission,
                ..Ids::nowhere()
            },
        )
        .await;
        let (_, nowhere) = ask(&app, &OBJECTS[0], &asker.both, asker.name, &Ids::nowhere()).await;
        if shape(&answer, &owner.both_submission.to_string()) != shape(&nowhere, "999999") {
            problems.push(format!(
                "{asked} as {BOTH} of {}: {} {}",
                asker.name, answer.status, answer.body
            ));
        }
    }
    app.regrades_done().await;
    assert!(
        problems.is_empty(),
        "{} problem(s):\n{}",
        problems.len(),
        problems.join("\n")
    );
}

/// Every route of the router and the registry that takes a parameter is in the object
/// matrix, and one whose parameter names an object (anything but the course and the
/// exercise) is asked with the other course's ids: a new route is checked too.
#[test]
fn every_route_with_a_parameter_is_in_the_object_matrix() {
    let routes = routes();
    for row in OBJECTS {
        assert!(
            routes.iter().any(|r| r == row.route),
            "the matrix's {} is no route of the router",
            row.route
        );
        assert!(
            route_serves(row.route, row.path),
            "{} is not a path of {}",
            row.path,
            row.route
        );
        assert_eq!(
            row.other.is_some(),
            row.names().is_some(),
            "{} {}: asked with the other course's ids exactly when it names an object",
            row.method,
            row.path
        );
    }
    for route in routes.iter().filter(|r| r.contains('{')) {
        let rows: Vec<&Row> = OBJECTS.iter().filter(|r| r.route == route).collect();
        assert!(!rows.is_empty(), "{route} is not in the object matrix");
        let names_an_object = route
            .split('/')
            .any(|s| s.starts_with('{') && !["{course}", "{lab}"].contains(&s));
        assert!(
            !names_an_object || rows.iter().any(|r| r.other.is_some()),
            "{route} takes an object's id, but the matrix never asks it with the other course's"
        );
    }
}
