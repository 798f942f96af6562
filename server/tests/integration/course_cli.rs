//! `estlab course` and `estlab backup`, run as an instructor runs them on the server's
//! machine: set-up from scratch, re-runs that change only what they should, and bad
//! input refused with a message naming the file's line, the flag or the course.

use calamine::Reader;
use estlab::courses::codes::read_code;
use estlab::store::{NewSubmission, Store};
use jiff::Timestamp;
use std::os::unix::fs::PermissionsExt;
use std::path::Path;
use std::process::{Command, Output};

use crate::common;
use common::{database_url, store_in};

fn estlab(data: &Path, args: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_estlab"));
    command.args(args).args(["--data", data.to_str().unwrap()]);
    match database_url(data) {
        Some(url) => command.env("ESTLAB_DATABASE", url),
        None => command.env_remove("ESTLAB_DATABASE"),
    };
    if args[0] == "course" {
        command.args(["--url", "https://estlab.example"]);
    }
    command.output().unwrap()
}

/// Standard output of a command that must succeed.
fn ok(data: &Path, args: &[&str]) -> String {
    let out = estlab(data, args);
    assert!(
        out.status.success(),
        "estlab {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// Standard error of a command that must fail.
fn refused(data: &Path, args: &[&str]) -> String {
    let out = estlab(data, args);
    assert!(!out.status.success(), "estlab {args:?} succeeded");
    String::from_utf8(out.stderr).unwrap()
}

/// The sign-in link a command printed.
fn link(text: &str) -> &str {
    text.lines()
        .find(|l| l.starts_with("https://estlab.example/signin#"))
        .unwrap_or_else(|| panic!("no sign-in link in:\n{text}"))
}

/// The rows of a codes file: id, name, email, code, link.
fn codes(path: &Path) -> Vec<Vec<String>> {
    let mut reader = csv::Reader::from_path(path).unwrap();
    assert_eq!(
        reader.headers().unwrap().iter().collect::<Vec<_>>(),
        ["id", "name", "email", "code", "link"]
    );
    reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect()
}

#[test]
fn a_course_is_set_up_from_scratch_and_re_imports_change_only_what_changed() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    assert!(ok(&data, &["course", "list"]).contains("No course yet"));

    let created = ok(
        &data,
        &[
            "course",
            "create",
            "el2320",
            "--title",
            "Applied Estimation",
        ],
    );
    assert!(created.starts_with("Created course el2320 (Applied Estimation)."));
    let first_link = link(&created).to_string();
    // Again: the same course with a new title, and a new link (the first one ends).
    let again = ok(
        &data,
        &[
            "course",
            "create",
            "el2320",
            "--title",
            "Applied Estimation HT26",
        ],
    );
    assert!(again.starts_with("Updated course el2320"));
    assert_ne!(link(&again), first_link);
    let staff = ok(
        &data,
        &[
            "course",
            "staff",
            "el2320",
            "ta@kth.se",
            "--role",
            "assistant",
        ],
    );
    assert!(staff.contains("ta@kth.se is assistant of el2320"));
    link(&staff);

    let roster = dir.path().join("roster.csv");
    std::fs::write(
        &roster,
        "id,name,email\nu1,Ada Lovelace,ada@kth.se\nu2,Grace Hopper,grace@kth.se\nu3,=1+1,alan@kth.se\n",
    )
    .unwrap();
    let imported = ok(
        &data,
        &["course", "roster", "el2320", roster.to_str().unwrap()],
    );
    assert!(imported.contains("3 students; 3 new, 0 updated, 0 unchanged, 0 marked dropped"));
    let first_codes = dir.path().join("roster-codes.csv");
    let rows = codes(&first_codes);
    assert_eq!(
        rows.iter().map(|r| r[0].as_str()).collect::<Vec<_>>(),
        ["u1", "u2", "u3"]
    );
    for row in &rows {
        assert_eq!(row[4], format!("https://estlab.example/signin#{}", row[3]));
    }
    let mode = std::fs::metadata(&first_codes)
        .unwrap()
        .permissions()
        .mode();
    assert_eq!(
        mode & 0o777,
        0o600,
        "the codes file is the instructor's only"
    );
    // Codes are shown once: the file is never overwritten.
    assert!(
        refused(
            &data,
            &["course", "roster", "el2320", roster.to_str().unwrap()]
        )
        .contains("exists already")
    );

    // u3 has a submission; the next roster drops u3, renames u2 and adds u4.
    let store = store_in(&data);
    let u3 = store.member("el2320", "u3").unwrap();
    let kept = store
        .insert(
            &NewSubmission {
                course: "el2320",
                student: "u3",
                member: Some(u3.id),
                lab: labs::Exercise::EkfLocalization,
                seed: 1,
                language: labs::Language::JavaScript,
                source: "// u3's work",
                submitted_at: Timestamp::now(),
                late_seconds: 0,
                penalty: 0.0,
                grader: "estlab test plan 0",
            },
            Timestamp::MAX,
        )
        .unwrap();
    std::fs::write(
        &roster,
        "email,name,id\nada@kth.se,Ada Lovelace,u1\ngrace@kth.se,Grace B. Hopper,u2\nkatherine@kth.se,Katherine Johnson,u4\n",
    )
    .unwrap();
    let second_codes = dir.path().join("second.csv");
    let reimported = ok(
        &data,
        &[
            "course",
            "roster",
            "el2320",
            roster.to_str().unwrap(),
            "--out",
            second_codes.to_str().unwrap(),
        ],
    );
    assert!(
        reimported.contains("3 students; 1 new, 1 updated, 1 unchanged, 1 marked dropped (u3)"),
        "{reimported}"
    );
    assert_eq!(
        codes(&second_codes).len(),
        1,
        "a code for the new student only"
    );
    assert_eq!(codes(&second_codes)[0][0], "u4");
    assert!(store.member("el2320", "u3").unwrap().dropped);
    assert_eq!(
        store.member("el2320", "u2").unwrap().name,
        "Grace B. Hopper"
    );
    assert_eq!(
        store.get(kept, true).unwrap().unwrap().source.as_deref(),
        Some("// u3's work"),
        "a dropped student's submission stays"
    );

    // A lost code: --reissue gives a new one; the old one stops working.
    let reissued = dir.path().join("reissued.csv");
    ok(
        &data,
        &[
            "course",
            "roster",
            "el2320",
            "--reissue",
            "u1",
            "--out",
            reissued.to_str().unwrap(),
        ],
    );
    let new_code = &codes(&reissued)[0];
    assert_eq!(new_code[0], "u1");
    let old_code = &rows[0][3];
    assert!(
        store
            .find_code(read_code(old_code).unwrap())
            .unwrap()
            .is_none()
    );
    assert!(
        store
            .find_code(read_code(&new_code[3]).unwrap())
            .unwrap()
            .is_some()
    );

    let assigned = ok(
        &data,
        &[
            "course",
            "assign",
            "el2320",
            "ekf-localization",
            "--due",
            "2026-12-15T23:59+01:00",
            "--late-penalty",
            "10%/day",
            "--cutoff",
            "2026-12-18T23:59+01:00",
            "--counts",
            "last",
        ],
    );
    assert!(assigned.contains("due 2026-12-15T22:59:00Z"), "{assigned}");
    let token = ok(
        &data,
        &["course", "token", "el2320", "--role", "instructor"],
    );
    assert!(
        token
            .lines()
            .any(|l| l.starts_with("estlab_") && l.len() == 71)
    );
    let shown = ok(&data, &["course", "show", "el2320"]);
    for expected in [
        "el2320 (Applied Estimation HT26)",
        "  instructor (instructor)",
        "  ta@kth.se (assistant)",
        "Students: 3 on the roster, 1 dropped",
        "ekf-localization: due 2026-12-15T22:59:00Z, cutoff 2026-12-18T22:59:00Z, 10 %/day late, counts last; 1 submission(s)",
        "  1 (instructor, made ",
    ] {
        assert!(shown.contains(expected), "no {expected:?} in:\n{shown}");
    }
    assert!(ok(&data, &["course", "token", "el2320", "--revoke", "1"]).contains("revoked"));
    assert!(ok(&data, &["course", "show", "el2320"]).contains(", revoked"));
    assert_eq!(
        ok(&data, &["course", "list"]),
        "el2320\tApplied Estimation HT26\n"
    );

    // The gradebook: a row per student of the roster, dropped ones marked.
    let grades = dir.path().join("grades.csv");
    let export = [
        "course",
        "export",
        "el2320",
        "ekf-localization",
        "--format",
        "csv",
        "--out",
        grades.to_str().unwrap(),
    ];
    ok(&data, &export);
    let mut reader = csv::Reader::from_path(&grades).unwrap();
    assert_eq!(
        reader.headers().unwrap().iter().collect::<Vec<_>>(),
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
    let rows: Vec<Vec<String>> = reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    let brief: Vec<(&str, &str, &str)> = rows
        .iter()
        .map(|r| (r[0].as_str(), r[3].as_str(), r[4].as_str()))
        .collect();
    assert_eq!(
        brief,
        [
            ("u1", "enrolled", "0"),
            ("u2", "enrolled", "0"),
            ("u3", "dropped", "1"),
            ("u4", "enrolled", "0")
        ]
    );
    assert!(refused(&data, &export).contains("exists already"));
    // The same gradebook as a workbook: the ids as string cells.
    let workbook = dir.path().join("grades.xlsx");
    ok(
        &data,
        &[
            "course",
            "export",
            "el2320",
            "ekf-localization",
            "--format",
            "xlsx",
            "--out",
            workbook.to_str().unwrap(),
        ],
    );
    let mut book: calamine::Xlsx<_> = calamine::open_workbook(&workbook).unwrap();
    let sheet = book.worksheet_range("grades").unwrap();
    let ids: Vec<&calamine::Data> = sheet.rows().skip(1).map(|r| &r[0]).collect();
    assert_eq!(
        ids,
        ["u1", "u2", "u3", "u4"]
            .map(|id| calamine::Data::String(id.into()))
            .iter()
            .collect::<Vec<_>>()
    );
    let u3 = sheet.rows().nth(3).unwrap();
    assert_eq!(
        u3[1],
        calamine::Data::String("=1+1".into()),
        "a string, not a formula"
    );

    // Every change is in the audit log, newest first, by the command line.
    let log = store.audit_log("el2320").unwrap();
    let actions: Vec<(&str, &str)> = log
        .iter()
        .rev()
        .map(|e| (e.action.as_str(), e.detail.as_str()))
        .collect();
    let expected = [
        ("course", "title \"Applied Estimation\""),
        ("staff", "instructor is instructor; sign-in link"),
        ("course", "title \"Applied Estimation HT26\""),
        ("staff", "instructor is instructor; sign-in link"),
        ("staff", "ta@kth.se is assistant"),
        ("roster", "roster.csv: 3 new, 0 updated, 0 dropped"),
        ("roster", "roster.csv: 1 new, 1 updated, 1 dropped (u3)"),
        ("roster", "new code for u1"),
        ("assign", "ekf-localization: due 2026-12-15T22:59:00Z"),
        ("token", "token 1 made (instructor)"),
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
    assert!(log.iter().all(|e| e.actor.starts_with("command line (")));
}

#[test]
fn bad_input_is_refused_naming_the_line_the_flag_or_the_course() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let roster = dir.path().join("roster.csv");
    let roster = roster.to_str().unwrap();
    let assign = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut args = vec!["course", "assign", "el2320", "ekf-localization"];
        args.extend_from_slice(extra);
        args
    };
    // Each command, the roster file's text (if it reads one), and what the error says.
    let cases: Vec<(Vec<&str>, Option<&str>, &str)> = vec![
        (
            vec!["course", "show", "el2320"],
            None,
            "there is no course \"el2320\"; no course is set up yet",
        ),
        (
            vec!["course", "create", "EL 2320", "--title", "x"],
            None,
            "not a course name",
        ),
        (
            vec![
                "course",
                "create",
                "el2320",
                "--title",
                "Applied Estimation",
            ],
            None,
            "",
        ),
        (
            vec![
                "course",
                "assign",
                "el2321",
                "ekf-localization",
                "--due",
                "2026-12-15T23:59Z",
            ],
            None,
            "there is no course \"el2321\"; the courses are: el2320",
        ),
        (
            assign(&["--due", "2026-12-15T23:59"]),
            None,
            "is not a moment with a time zone",
        ),
        (assign(&["--due", "2026-12-15"]), None, "has no time"),
        (
            assign(&[
                "--due",
                "2026-12-15T23:59Z",
                "--cutoff",
                "2026-12-14T23:59Z",
            ]),
            None,
            "--cutoff: the cutoff 2026-12-14T23:59:00Z is before the due date",
        ),
        (
            assign(&["--due", "2026-12-15T23:59Z", "--late-penalty", "lots"]),
            None,
            "10%/day",
        ),
        (
            vec![
                "course",
                "assign",
                "el2320",
                "particle-filter",
                "--due",
                "2026-12-15T23:59Z",
            ],
            None,
            "ekf-localization",
        ),
        (
            vec!["course", "roster", "el2320", roster],
            Some("id,name,email\nu1,Ada,ada@kth.se\nu2,Grace\n"),
            "roster.csv: line 3",
        ),
        (
            vec!["course", "roster", "el2320", roster],
            Some("id,name,mail\nu1,Ada,ada@kth.se\n"),
            "line 1 (the header): no column \"email\"",
        ),
        (
            vec!["course", "roster", "el2320", roster],
            Some("id,name,email\nu1,Ada,ada@kth.se\nu\u{200b}2,Grace,g@kth.se\n"),
            "roster.csv: line 3: the id \"u\\u{200b}2\" holds U+200B, a space, an invisible character",
        ),
        (
            vec!["course", "roster", "el2320", roster],
            Some("id,name,email\nalice,Ada,ada@kth.se\nbob,Bob,b@kth.se\nALICE,Grace,g@kth.se\n"),
            "roster.csv: line 4: the id \"ALICE\" is too like \"alice\" of line 2: ids must differ in more than case",
        ),
        (
            vec!["course", "roster", "el2320", roster],
            Some("id,name,email\nace,Ada,ada@kth.se\n\u{430}\u{441}\u{435},Grace,g@kth.se\n"),
            "roster.csv: line 3: the id \"асе\" is too like \"ace\" of line 2",
        ),
        (
            vec!["course", "roster", "el2320", roster],
            Some("id,name,email\n\u{430}da,Ada,ada@kth.se\n"),
            "roster.csv: line 2: the id \"аda\" mixes scripts",
        ),
        (
            vec!["course", "roster", "el2320", roster],
            Some("id,name,email\nu1,Ada,ada@kth.se\nCON,Grace,g@kth.se\n"),
            "roster.csv: line 3: the id \"CON\" is CON, which Windows keeps for a device",
        ),
        (
            vec!["course", "roster", "el2320", roster],
            Some("id,name,email\na\u{ff0f}b,Ada,ada@kth.se\n"),
            "roster.csv: line 2: the id \"a／b\" holds '/'",
        ),
        (
            vec!["course", "roster", "el2320", roster],
            Some("id,name,email\nu1.,Ada,ada@kth.se\n"),
            "roster.csv: line 2: the id \"u1.\" ends with '.'",
        ),
        (
            vec!["course", "roster", "el2320", roster],
            Some("id,name,email\nu1,Ada,ada@kth.se\nu2,Grace\u{202e}exe.js,g@kth.se\n"),
            "roster.csv: line 3: the name \"Grace\\u{202e}exe.js\" holds U+202E",
        ),
        (
            vec![
                "course",
                "roster",
                "el2320",
                "--reissue",
                "nobody",
                "--out",
                "x.csv",
            ],
            None,
            "course \"el2320\" has nobody with the id or email \"nobody\"",
        ),
        (
            vec!["course", "token", "el2320", "--revoke", "7"],
            None,
            "has no token 7",
        ),
    ];
    for (args, file, expected) in cases {
        if let Some(text) = file {
            std::fs::write(roster, text).unwrap();
        }
        if expected.is_empty() {
            ok(&data, &args);
            continue;
        }
        let message = refused(&data, &args);
        assert!(message.contains(expected), "estlab {args:?}: {message}");
    }
    assert!(
        !dir.path().join("roster-codes.csv").exists(),
        "nothing written for a refused roster"
    );
}

/// Proves that an id an earlier release let into the database (a right-to-left override
/// disguising `.exe` as `.js`) is printed escaped when the roster drops it, in the
/// command's output and in the audit log, and that a new id too like one already on the
/// course's roster is refused, naming both.
#[test]
fn ids_from_before_the_rules_are_printed_escaped_and_new_ones_may_not_look_like_them() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    ok(&data, &["course", "create", "el2320", "--title", "x"]);
    let disguised = "u9\u{202e}sj.exe";
    let store = store_in(&data);
    store
        .import_roster(
            "el2320",
            &[estlab::courses::roster::Student {
                id: disguised.into(),
                name: "Old".into(),
                email: String::new(),
            }],
        )
        .unwrap();
    let roster = dir.path().join("roster.csv");
    let roster = roster.to_str().unwrap();
    std::fs::write(roster, "id,name,email\nu1,Ada,ada@kth.se\n").unwrap();
    let printed = ok(&data, &["course", "roster", "el2320", roster]);
    assert!(!printed.contains('\u{202e}'), "{printed:?}");
    assert!(
        printed.contains("1 marked dropped (\"u9\\u{202e}sj.exe\")"),
        "{printed}"
    );
    let log = store.audit_log("el2320").unwrap();
    assert!(
        log[0].detail.ends_with("(\"u9\\u{202e}sj.exe\")"),
        "{}",
        log[0].detail
    );

    std::fs::write(
        roster,
        "id,name,email\nu1,Ada,ada@kth.se\nU1,Grace,g@kth.se\n",
    )
    .unwrap();
    let out = dir.path().join("more-codes.csv");
    let message = refused(
        &data,
        &[
            "course",
            "roster",
            "el2320",
            roster,
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(
        message.contains("line 3: the id \"U1\" is too like \"u1\" of line 2"),
        "{message}"
    );
    std::fs::write(roster, "id,name,email\nU1,Grace,g@kth.se\n").unwrap();
    let message = refused(
        &data,
        &[
            "course",
            "roster",
            "el2320",
            roster,
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(
        message
            .contains("line 2: the id \"U1\" is too like \"u1\", already on the course's roster"),
        "{message}"
    );
    assert!(!out.exists());
}

#[test]
fn a_backup_taken_while_the_database_is_in_use_restores_every_submission() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    // The server's connection stays open (as a running server's does) throughout.
    let store = store_in(&data);
    if database_url(&data).is_some() {
        let refusal = refused(&data, &["backup", dir.path().join("b").to_str().unwrap()]);
        assert!(refusal.contains("pg_dump --format=custom"), "{refusal}");
        return;
    }
    for i in 0..25 {
        store
            .insert(
                &NewSubmission {
                    course: "el2320",
                    student: &format!("s{i}"),
                    member: None,
                    lab: labs::Exercise::EkfLocalization,
                    seed: i,
                    language: labs::Language::JavaScript,
                    source: &format!("// file {i}"),
                    submitted_at: Timestamp::now(),
                    late_seconds: 0,
                    penalty: 0.0,
                    grader: "estlab test plan 0",
                },
                Timestamp::MAX,
            )
            .unwrap();
    }
    let copy = dir.path().join("backup.sqlite3");
    let printed = ok(&data, &["backup", copy.to_str().unwrap()]);
    assert!(printed.contains("(25 submissions)"), "{printed}");
    assert!(refused(&data, &["backup", copy.to_str().unwrap()]).contains("exists already"));
    assert!(
        refused(
            &dir.path().join("nowhere"),
            &["backup", dir.path().join("b2").to_str().unwrap()]
        )
        .contains("there is no database")
    );

    // Restoring: the copy as the database of a new data directory.
    let restored = dir.path().join("restored");
    std::fs::create_dir(&restored).unwrap();
    std::fs::copy(&copy, restored.join(estlab::store::FILE)).unwrap();
    let reopened = Store::open(&restored).unwrap();
    let all = reopened.all_submissions().unwrap();
    assert_eq!(all.len(), 25);
    for (i, s) in all.iter().enumerate() {
        assert_eq!(s.student, format!("s{i}"));
        assert_eq!(
            reopened.get(s.id, true).unwrap().unwrap().source.unwrap(),
            format!("// file {i}")
        );
    }
}

#[test]
fn questions_are_imported_from_files_each_problem_naming_its_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    ok(
        &data,
        &[
            "course",
            "create",
            "el2320",
            "--title",
            "Applied Estimation",
        ],
    );
    ok(
        &data,
        &[
            "course",
            "assign",
            "el2320",
            "ekf-localization",
            "--due",
            "2026-12-15T23:59+01:00",
        ],
    );
    let good = dir.path().join("part-1.toml");
    std::fs::write(
        &good,
        "title = \"Part I\"\n\n[[question]]\nkind = \"text\"\nprompt = \"Why?\"\n",
    )
    .unwrap();
    let bad = dir.path().join("part-2.toml");
    std::fs::write(
        &bad,
        "title = \"Part II\"\n\n[[question]]\nkind = \"choice\"\nprompt = \"Which?\"\noptions = [\"a\"]\n",
    )
    .unwrap();
    let [good_path, bad_path] = [&good, &bad].map(|p| p.to_str().unwrap());
    let error = refused(
        &data,
        &[
            "course",
            "questions",
            "el2320",
            "ekf-localization",
            good_path,
            bad_path,
        ],
    );
    assert!(
        error.contains(&format!(
            "{bad_path}: line 3: question 1: options: 1 given; give 2 to 30"
        )),
        "{error}"
    );
    let store = || store_in(&data);
    assert_eq!(
        store()
            .questions("el2320", labs::Exercise::EkfLocalization)
            .unwrap(),
        None
    );
    let done = ok(
        &data,
        &[
            "course",
            "questions",
            "el2320",
            "ekf-localization",
            good_path,
        ],
    );
    assert_eq!(
        done.trim(),
        "ekf-localization in el2320 has 1 written questions."
    );
    assert_eq!(
        store()
            .questions("el2320", labs::Exercise::EkfLocalization)
            .unwrap(),
        Some(vec![std::fs::read_to_string(&good).unwrap()])
    );
    let own = ok(
        &data,
        &["course", "questions", "el2320", "ekf-localization", "--own"],
    );
    assert_eq!(
        own.trim(),
        "ekf-localization in el2320 has 26 written questions, the exercise's own."
    );
    let error = refused(
        &data,
        &["course", "questions", "el2320", "odometry", "--own"],
    );
    assert!(error.contains("el2320 has not opened odometry"), "{error}");
}

/// A database URL that PostgreSQL cannot read, or whose server is not there, is refused
/// without repeating its password.
#[test]
fn a_database_that_cannot_be_opened_is_refused_without_its_password() {
    let dir = tempfile::tempdir().unwrap();
    for (url, said) in [
        (
            "postgres://ada:hunter2@localhost:notaport/estlab",
            "is not one PostgreSQL reads",
        ),
        (
            "postgres://ada:hunter2@127.0.0.1:1/estlab",
            "postgres://ada@127.0.0.1:1/estlab",
        ),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_estlab"))
            .args(["course", "list", "--data", dir.path().to_str().unwrap()])
            .env("ESTLAB_DATABASE", url)
            .output()
            .unwrap();
        assert!(!out.status.success(), "{url}");
        let error = String::from_utf8_lossy(&out.stderr);
        assert!(
            error.contains(said) && !error.contains("hunter2"),
            "{url}: {error}"
        );
    }
}
