//! Exports that are safe in every locale and on every file system, for a course whose
//! database holds the ids and names an earlier release let in (written to the store
//! directly, past the roster's checks): the real web application, its export route, as
//! the course's instructor.
//!
//! - `the_csv_gradebook_is_inert_after_every_separator`: no piece of a cell that a
//!   spreadsheet splitting at `,`, `;` or a tab would see starts a formula;
//! - `the_xlsx_gradebook_holds_the_names_as_strings`: read back, every text is a string
//!   cell as it was written, and the sheet holds no formula;
//! - `zip_entries_are_safe_file_names_unique_ignoring_case`: the sources' and the
//!   platforms' zips name every student's file safely, two ids differing in case apart,
//!   with `names.csv` saying whose each escaped one is.

use crate::common;

use axum::http::{StatusCode, header};
use calamine::{Data, Reader, Xlsx};
use common::*;
use estlab::courses::ids;
use serde_json::json;
use std::collections::HashSet;

/// Ids, names and emails an earlier roster took: a formula after a `;` in a name and in
/// an id, ids differing only in case, a Windows device, characters Windows refuses, a
/// right-to-left override disguising an extension, a fullwidth slash, an option.
const STORED: [(&str, &str, &str); 11] = [
    ("nils", "nils;=2*21;x", "nils@x.example"),
    ("x;=2+3;", "Eve", "=cmd|' /C calc'!A0"),
    ("alice", "Alice Lower", "alice@x.example"),
    ("ALICE", "Alice Upper", "ALICE@x.example"),
    ("CON", "Con Sole", "con@x.example"),
    ("a\"<>b", "Quote Angle", "qa@x.example"),
    ("u1\u{202e}sj.exe", "Right To-Left", "rtl@x.example"),
    ("x\u{ff0f}y", "Full Width", "fw@x.example"),
    ("-rf", "Dash", "@SUM(1)"),
    ("josé", "José Plain", "jose@x.example"),
    ("u2", "+46 8 790 60 00\t-1", "u2@x.example"),
];

/// The course with those students, each of whom has submitted a file naming them.
async fn class() -> (App, Who) {
    let app = App::new();
    app.open_course("el2320");
    let roster: Vec<_> = STORED
        .iter()
        .map(|(id, name, email)| roster_line(id, name, email))
        .collect();
    app.store().import_roster("el2320", &roster).unwrap();
    for (id, _, _) in STORED {
        let member = app.store().member("el2320", id).unwrap();
        let who = app.signed_in(&member).await;
        if id == "u2" {
            // A file in Python, exported as one.
            let source =
                format!("def init(dataset):\n    raise NotImplementedError  # file of {id:?}\n");
            let answer = app
                .send(
                    Req::post("/api/submissions")
                        .who(&who)
                        .json(json!({ "source": source, "language": "python" })),
                )
                .await;
            assert_eq!(answer.status, StatusCode::ACCEPTED, "{}", answer.body);
            app.graded(answer.json()["id"].as_i64().unwrap()).await;
            continue;
        }
        app.submit_graded(&who, &quick_source(&format!("file of {id:?}")))
            .await;
    }
    let instructor = app.staff(
        "el2320",
        "teacher@kth.example",
        estlab::store::Role::Instructor,
    );
    let who = app.signed_in(&instructor).await;
    (app, who)
}

async fn export(app: &App, who: &Who, format: &str) -> Answer {
    let answer = app
        .send(
            Req::get(&format!(
                "/api/courses/el2320/labs/ekf-localization/export?format={format}"
            ))
            .who(who),
        )
        .await;
    assert_eq!(answer.status, StatusCode::OK, "{format}: {}", answer.body);
    answer
}

/// Proves that in the CSV gradebook, read as a spreadsheet of any locale reads it
/// (split at every `,`, `;`, tab and line break, quotes or not), no piece starts like a
/// formula after its spaces and quotes, and that a comma-reading one still gets each
/// name back whole, with its `'` marks.
#[tokio::test(flavor = "multi_thread")]
async fn the_csv_gradebook_is_inert_after_every_separator() {
    let (app, instructor) = class().await;
    let csv = export(&app, &instructor, "csv").await;
    assert!(
        csv.headers[header::CONTENT_TYPE]
            .to_str()
            .unwrap()
            .starts_with("text/csv")
    );
    for piece in csv.body.split([',', ';', '\t', '\r', '\n']) {
        let start = piece.trim_start_matches([' ', '"']);
        assert!(
            !start.starts_with(['=', '+', '-', '@']),
            "a formula in {piece:?} of:\n{}",
            csv.body
        );
    }
    let rows = csv_rows(&csv.body);
    let nils = rows.iter().find(|r| r[0] == "nils").expect("nils's row");
    assert_eq!(nils[1], "nils;'=2*21;x");
    let eve = rows.iter().find(|r| r[1] == "Eve").expect("Eve's row");
    assert_eq!(eve[0], "x;'=2+3;");
    assert_eq!(eve[2], "'=cmd|' /C calc'!A0");
    let u2 = rows.iter().find(|r| r[0] == "u2").expect("u2's row");
    assert_eq!(u2[1], "'+46 8 790 60 00\t'-1");
}

/// Proves that the XLSX gradebook, read back, has the CSV's header and a row per
/// student whose id, name and email are string cells exactly as stored (a leading `=`
/// and all), the counts numbers, and no formula anywhere.
#[tokio::test(flavor = "multi_thread")]
async fn the_xlsx_gradebook_holds_the_names_as_strings() {
    let (app, instructor) = class().await;
    let xlsx = export(&app, &instructor, "xlsx").await;
    assert_eq!(
        xlsx.headers[header::CONTENT_TYPE],
        "application/vnd.openxmlformats-officedocument.spreadsheetml.sheet"
    );
    assert!(
        xlsx.headers[header::CONTENT_DISPOSITION]
            .to_str()
            .unwrap()
            .contains("el2320-ekf-localization-grades.xlsx")
    );
    let mut book = Xlsx::new(std::io::Cursor::new(xlsx.raw.clone())).unwrap();
    assert_eq!(book.sheet_names(), ["grades"]);
    let formulas = book.worksheet_formula("grades").unwrap();
    assert!(
        formulas.cells().all(|(_, _, f)| f.is_empty()),
        "a formula in the gradebook"
    );
    let sheet = book.worksheet_range("grades").unwrap();
    let rows: Vec<&[Data]> = sheet.rows().collect();
    let header: Vec<String> = rows[0].iter().map(|c| c.to_string()).collect();
    assert_eq!(
        header,
        [
            "id",
            "name",
            "email",
            "status",
            "submissions",
            "score",
            "late_penalty",
            "final_score",
            "submitted_at",
            "report_status",
            "lab_passed"
        ]
    );
    assert_eq!(rows.len(), 1 + STORED.len());
    for (id, name, email) in STORED {
        let row = rows[1..]
            .iter()
            .find(|r| r[0] == Data::String(id.into()))
            .unwrap_or_else(|| panic!("no string cell {id:?}"));
        assert_eq!(row[1], Data::String(name.into()), "{id:?}");
        assert_eq!(row[2], Data::String(email.into()), "{id:?}");
        assert_eq!(row[3], Data::String("enrolled".into()));
        assert_eq!(row[4], Data::Float(1.0));
        assert_eq!(row[7], Data::Float(0.0), "the quick source scores 0");
        assert!(matches!(&row[8], Data::String(at) if at.ends_with('Z')));
    }
}

/// Whether a file name is one on Windows, macOS and Linux, as `ids` defines it (the
/// escaped names are safe ids too, but for their `~`).
fn safe_file_name(name: &str) -> bool {
    let (stem, _) = name.rsplit_once('.').expect("an extension");
    !stem.is_empty() && ids::is_safe(&stem.replace('~', "_"))
}

/// Proves that the sources' zip and the Gradescope and PrairieLearn zips name every
/// student's file safely on every system and differently ignoring case, keep a safe id's
/// own name, and list whose each file is in `names.csv`.
#[tokio::test(flavor = "multi_thread")]
async fn zip_entries_are_safe_file_names_unique_ignoring_case() {
    let (app, instructor) = class().await;
    let sources = unzip(&export(&app, &instructor, "sources").await.raw);
    let index = &sources.last().expect("files").1;
    assert_eq!(sources.last().unwrap().0, "names.csv");
    let whose: Vec<Vec<String>> = csv_rows(index);
    let files = &sources[..sources.len() - 1];
    assert_eq!(files.len(), STORED.len());
    let mut folded = HashSet::new();
    for (name, text) in files {
        assert!(safe_file_name(name), "{name:?}");
        assert!(
            folded.insert(ids::fold(name)),
            "{name:?} twice, ignoring case"
        );
        let row = whose
            .iter()
            .find(|r| r[0] == *name)
            .unwrap_or_else(|| panic!("{name} not in names.csv"));
        // Each file is its student's: names.csv shows the id escaped where it must be.
        let id = STORED
            .iter()
            .map(|(id, _, _)| *id)
            .find(|id| estlab::courses::export::inert(&ids::shown(id)) == row[1])
            .unwrap_or_else(|| panic!("names.csv names {:?}", row[1]));
        assert!(text.contains(&format!("file of {id:?}")), "{name}: {text}");
    }
    for kept in ["nils.js", "josé.js", "u2.py"] {
        assert!(files.iter().any(|(n, _)| n == kept), "no {kept}");
    }
    assert!(files.iter().any(|(n, _)| n.starts_with("alice~")));
    assert!(files.iter().any(|(n, _)| n.starts_with("ALICE~")));
    assert!(files.iter().any(|(n, _)| n.starts_with("CON~")));

    for format in ["gradescope", "prairielearn"] {
        let zip = unzip(&export(&app, &instructor, format).await.raw);
        let mut folded = HashSet::new();
        for (name, _) in zip.iter().filter(|(n, _)| n != "names.csv") {
            let (dir, file) = name.split_once('/').expect("ID/results.json");
            assert_eq!(file, "results.json");
            assert!(safe_file_name(&format!("{dir}.json")), "{name:?}");
            assert!(
                folded.insert(ids::fold(dir)),
                "{dir:?} twice, ignoring case"
            );
        }
        assert_eq!(folded.len(), STORED.len());
    }
}
