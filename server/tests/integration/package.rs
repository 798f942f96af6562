//! The packages of `estlab package`, unpacked and run as each platform runs them, under a
//! temporary root instead of `/`:
//!
//! - Gradescope: the zip unpacked into `ROOT/source`, `setup.sh` run, `run_autograder`
//!   copied to `ROOT/run_autograder` and run for each submission in `ROOT/submission` with
//!   `ROOT/submission_metadata.json`; `ROOT/results/results.json` read back into the
//!   documented fields (unknown fields refused) and compared with `estlab grade --format
//!   gradescope` for the same file, student and secret.
//! - PrairieLearn: the question's `tests/` as `ROOT/tests`, the student's file in
//!   `ROOT/student`, `ROOT/data/data.json`, the image's entrypoint (from info.json) run
//!   with the packaged binary; results compared with `estlab grade --format prairielearn`.
//! - The packaged binary is statically linked (`file`, `ldd`), and packaging refuses a
//!   dynamically linked one.
//!
//! The packages carry the static build of estlab (scripts/build-static, which
//! scripts/test runs first); `estlab package` finds it beside the debug build.

use estlab::platforms::{GradescopeResults, HIDDEN_LATER, PrairieLearnResults};
use labs::grading::{Status, Visibility, student_seed};
use serde::Deserialize;
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::command;
use crate::common;
use crate::student;

use command::estlab;
use student::{CORRECT, Mistake, STARTER};

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn succeeded(output: &Output, what: &str) -> String {
    assert!(
        output.status.success(),
        "{what} failed with {}: {}{}",
        output.status,
        text(&output.stderr),
        text(&output.stdout)
    );
    text(&output.stdout)
}

fn read<T: DeserializeOwned>(path: &Path) -> T {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}\n{text}", path.display()))
}

/// correct.js with the named classic mistake put in, and the function it breaks.
fn mistaken(name: &str) -> (String, String) {
    let mistake = Mistake::named(name);
    (mistake.source().unwrap(), mistake.breaks)
}

/// Hostile or broken files, each with what its results must say.
fn hostile() -> Vec<(&'static str, String, &'static str)> {
    vec![
        (
            "throws",
            "throw new Error('no thanks');".to_owned(),
            "no thanks",
        ),
        (
            "replaces the harness",
            format!("{STARTER}\nestlabHarness = {{ run() {{ return {{ score: 1 }}; }} }};"),
            "not implemented",
        ),
        (
            "ends the process",
            format!("process.exit(0);\n{CORRECT}"),
            "process",
        ),
    ]
}

/// The package's binary as `file` and `ldd` see it: statically linked.
fn assert_static(binary: &Path) {
    let file = text(&Command::new("file").arg(binary).output().unwrap().stdout);
    assert!(
        file.contains("statically linked") || file.contains("static-pie linked"),
        "{file}"
    );
    let ldd = Command::new("ldd").arg(binary).output().unwrap();
    let said = text(&ldd.stdout) + &text(&ldd.stderr);
    assert!(
        said.contains("statically linked") || said.contains("not a dynamic executable"),
        "{said}"
    );
    let version = succeeded(
        &Command::new(binary).arg("--version").output().unwrap(),
        "the packaged estlab",
    );
    assert!(version.starts_with("estlab "), "{version}");
}

// ---- Gradescope ----

/// A Gradescope autograder's root: the package of an exercise unpacked into `source/`
/// and set up.
struct Gradescope {
    root: tempfile::TempDir,
    lab: &'static str,
}

impl Gradescope {
    fn new(lab: &'static str) -> Gradescope {
        let root = tempfile::tempdir().unwrap();
        let zip = root.path().join("autograder.zip");
        let secret = common::fixed_secret(&root.path().join("server"));
        let said = succeeded(
            &estlab(&[
                "package",
                "gradescope",
                "--lab",
                lab,
                "--out",
                zip.to_str().unwrap(),
                "--secret",
                secret.to_str().unwrap(),
            ]),
            "estlab package gradescope",
        );
        assert!(said.contains("Configure Autograder"), "{said}");
        let source = root.path().join("source");
        let mut archive = zip::ZipArchive::new(std::fs::File::open(&zip).unwrap()).unwrap();
        let mut names: Vec<String> = archive
            .file_names()
            .map(|name| name.unwrap().into_owned())
            .collect();
        names.sort();
        assert_eq!(
            names,
            [
                "estlab",
                "estlab-package.json",
                "run_autograder",
                "secret",
                "setup.sh"
            ]
        );
        archive.extract(&source).unwrap();
        for (name, mode) in [
            ("estlab", 0o755),
            ("run_autograder", 0o755),
            ("secret", 0o600),
        ] {
            use std::os::unix::fs::PermissionsExt;
            let found = std::fs::metadata(source.join(name)).unwrap().permissions();
            assert_eq!(found.mode() & 0o777, mode, "{name}");
        }
        assert_eq!(std::fs::metadata(source.join("secret")).unwrap().len(), 32);
        assert_static(&source.join("estlab"));
        let setup = Command::new("bash")
            .arg(source.join("setup.sh"))
            .output()
            .unwrap();
        assert!(succeeded(&setup, "setup.sh").contains("estlab"));
        // Gradescope runs run_autograder from the root.
        std::fs::copy(
            source.join("run_autograder"),
            root.path().join("run_autograder"),
        )
        .unwrap();
        Gradescope { root, lab }
    }

    fn path(&self, part: &str) -> PathBuf {
        self.root.path().join(part)
    }

    /// Lays out a submission of `files` by the Gradescope users `users` with the
    /// submission id `id`, runs the autograder and reads its results.
    fn grade(&self, files: &[(&str, &str)], users: &[i64], id: i64) -> GradescopeResults {
        let submission = self.path("submission");
        let _ = std::fs::remove_dir_all(&submission);
        let _ = std::fs::remove_dir_all(self.path("results"));
        std::fs::create_dir_all(&submission).unwrap();
        for (name, source) in files {
            let path = submission.join(name);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, source).unwrap();
        }
        let metadata = serde_json::json!({
            "id": id,
            "created_at": "2026-11-30T14:22:32.365935-07:00",
            "assignment": { "id": 25828, "title": "Lab 1", "total_points": "110.0" },
            "submission_method": "upload",
            "users": users
                .iter()
                .map(|user| serde_json::json!({
                    "email": format!("user{user}@example.org"),
                    "id": user,
                    "name": format!("Student {user}")
                }))
                .collect::<Vec<_>>(),
            "previous_submissions": []
        });
        std::fs::write(self.path("submission_metadata.json"), metadata.to_string()).unwrap();
        let run = Command::new(self.path("run_autograder")).output().unwrap();
        succeeded(&run, "run_autograder");
        read(&self.path("results/results.json"))
    }

    /// `estlab grade --format gradescope` (the packaged estlab, whose C library computes
    /// the student's Math functions) for the same file, student and hidden cases (the
    /// key the results name).
    fn graded_alone(&self, source: &str, graded: &GradescopeResults) -> GradescopeResults {
        let seed = graded.extra_data.seed;
        let key = graded
            .extra_data
            .hidden_key
            .expect("hidden cases were graded");
        let file = self.path("alone.js");
        std::fs::write(&file, source).unwrap();
        let output = Command::new(self.path("source/estlab"))
            .arg("grade")
            .arg(&file)
            .args(["--lab", self.lab, "--seed", &seed.to_string()])
            .args(["--format", "gradescope", "--javascript", "quickjs"])
            .arg("--secret")
            .arg(self.path("source/secret"))
            .args(["--submission", &key.to_string()])
            .output()
            .unwrap();
        serde_json::from_str(&succeeded(&output, "estlab grade")).unwrap()
    }
}

#[test]
fn gradescope_grades_as_estlab_grade_does_with_hidden_cases_after_the_due_date() {
    let gradescope = Gradescope::new("ekf-localization");
    let ada = 4201;
    let seed = student_seed("el2320", "4201");

    let correct = gradescope.grade(&[("ekf_localization.js", CORRECT)], &[ada], 7001);
    assert_eq!(correct, gradescope.graded_alone(CORRECT, &correct));
    assert_eq!(correct.score, Some(110.0));
    assert_eq!(correct.extra_data.seed, seed);
    assert!(correct.extra_data.grader.starts_with("estlab 0.1.0 plan "));
    assert!(
        correct.output.contains(&format!("seed {seed}")),
        "{}",
        correct.output
    );
    assert!(correct.tests.iter().all(|t| t.status == Status::Passed
        && t.visibility == Visibility::Visible
        && t.score == t.max_score));
    // Hidden cases were graded: the function tests count them.
    assert!(
        correct.tests[0].output.contains("hidden cases pass"),
        "{}",
        correct.tests[0].output
    );

    // Another student gets another variant; another submission other hidden cases; the
    // same submission graded again the same ones.
    let other = gradescope.grade(&[("mine.js", CORRECT)], &[4202], 7002);
    assert_ne!(other.extra_data.seed, seed);
    assert_eq!(other.score, Some(110.0));
    assert_ne!(other.extra_data.hidden_key, correct.extra_data.hidden_key);
    let again = gradescope.grade(&[("ekf_localization.js", CORRECT)], &[ada], 7001);
    assert_eq!(again.extra_data.hidden_key, correct.extra_data.hidden_key);
    // A group keeps one variant whoever uploads: its smallest user id.
    let group = gradescope.grade(
        &[("ekf_localization.js", CORRECT)],
        &[4300, ada, 4299],
        7005,
    );
    assert_eq!(group.extra_data.seed, seed);

    let mut later = 0;
    for name in [
        "bearing-not-wrapped",
        "odometry-first-step",
        "threshold-strict",
    ] {
        let (source, breaks) = mistaken(name);
        let results = gradescope.grade(&[("ekf_localization.js", &source)], &[ada], 7003);
        assert_eq!(
            results,
            gradescope.graded_alone(&source, &results),
            "{name}"
        );
        let score = results.score.unwrap();
        assert!(score < 110.0, "{name}: {score}");
        let broken = results
            .tests
            .iter()
            .find(|t| t.name.starts_with(&format!("{breaks}:")))
            .unwrap();
        assert_eq!(broken.status, Status::Failed, "{name}");
        assert!(broken.output.contains("Hint:"), "{name}: {}", broken.output);
        // What a failing hidden case says waits for the due date.
        for t in &results.tests {
            if t.visibility == Visibility::AfterDueDate {
                later += 1;
                assert!(t.name.ends_with(": the failing hidden cases"), "{}", t.name);
                assert_eq!((t.score, t.max_score), (0.0, 0.0));
                assert!(t.output.contains("a hidden case"), "{}", t.output);
                let visible = results
                    .tests
                    .iter()
                    .find(|v| t.name.starts_with(&v.name) && v.name != t.name)
                    .unwrap();
                assert!(visible.output.contains(HIDDEN_LATER), "{}", visible.output);
                assert!(
                    !visible.output.contains("a hidden case:"),
                    "{}",
                    visible.output
                );
            }
        }
    }

    assert!(later > 0, "no failing hidden case waits for the due date");

    for (what, source, says) in hostile() {
        let results = gradescope.grade(&[("ekf_localization.js", &source)], &[ada], 7004);
        assert_eq!(
            results,
            gradescope.graded_alone(&source, &results),
            "{what}"
        );
        assert!(results.score.unwrap() < 110.0, "{what}");
        let all: String = results.tests.iter().map(|t| t.output.as_str()).collect();
        assert!(all.contains(says), "{what}: {all}");
    }
}

/// The sensor-fusion exercise's class challenge on Gradescope: a test worth nothing that
/// gives the figure, and the figure on the assignment's leaderboard, lower the better;
/// the same as `estlab grade` gives with the package's secret and course.
#[test]
fn gradescope_puts_the_class_challenge_on_its_leaderboard() {
    let gradescope = Gradescope::new("sensor-fusion");
    let correct = include_str!("../../../tests/student/sensor_fusion/correct.js");
    let results = gradescope.grade(&[("sensor_fusion.js", correct)], &[4201], 7101);
    assert_eq!(results, gradescope.graded_alone(correct, &results));
    assert_eq!(results.score, Some(90.0));
    let [entry] = results.leaderboard.as_slice() else {
        panic!("{:?}", results.leaderboard);
    };
    assert_eq!(
        (entry.name.as_str(), entry.order.as_str()),
        ("Class challenge (m)", "asc")
    );
    assert!(entry.value > 0.0 && entry.value < 0.5, "{entry:?}");
    let test = results.tests.last().unwrap();
    assert!(
        test.name.starts_with("Class challenge (no points)"),
        "{}",
        test.name
    );
    assert_eq!((test.score, test.max_score), (0.0, 0.0));
    assert!(
        test.output.contains(&format!("{:.4} m", entry.value)),
        "{}",
        test.output
    );
}

#[test]
fn gradescope_says_which_file_it_wants_and_refuses_what_it_cannot_grade() {
    let gradescope = Gradescope::new("ekf-localization");
    let ada = [4201];
    // Several files: the one named like the starter is graded.
    let picked = gradescope.grade(
        &[
            ("notes.js", "// notes"),
            ("lab/ekf_localization.js", CORRECT),
        ],
        &ada,
        1,
    );
    assert_eq!(picked.score, Some(110.0));

    for (files, says) in [
        (
            vec![("a.js", CORRECT), ("b.js", CORRECT)],
            "several JavaScript files were submitted (a.js, b.js)",
        ),
        (
            vec![("report.pdf", "%PDF")],
            "no JavaScript file was submitted (found report.pdf)",
        ),
    ] {
        let results = gradescope.grade(&files, &ada, 2);
        assert_eq!(results.score, None, "{says}");
        assert!(results.tests.is_empty());
        assert!(results.output.contains(says), "{}", results.output);
    }
    let huge = "// x\n".repeat(60_000);
    let results = gradescope.grade(&[("ekf_localization.js", &huge)], &ada, 3);
    assert_eq!(results.score, None);
    assert!(
        results
            .output
            .contains("ekf_localization.js: 300000 bytes; a submission may have at most 256 KB"),
        "{}",
        results.output
    );

    // A package whose metadata is missing still writes results, and fails.
    std::fs::remove_file(gradescope.path("submission_metadata.json")).unwrap();
    let run = Command::new(gradescope.path("run_autograder"))
        .output()
        .unwrap();
    assert!(!run.status.success());
    let results: GradescopeResults = read(&gradescope.path("results/results.json"));
    assert!(
        results.output.contains("submission_metadata.json"),
        "{}",
        results.output
    );
}

// ---- PrairieLearn ----

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct Info {
    uuid: String,
    title: String,
    tags: Vec<String>,
    grading_method: String,
    external_grading_options: ExternalGrading,
}

#[derive(Deserialize)]
struct ExternalGrading {
    enabled: bool,
    image: String,
    entrypoint: Vec<String>,
    timeout: u32,
}

#[test]
fn prairielearn_grades_as_estlab_grade_does_from_the_question_folder() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pl");
    let secret = common::fixed_secret(&dir.path().join("server"));
    let said = succeeded(
        &estlab(&[
            "package",
            "prairielearn",
            "--secret",
            secret.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--image",
            "kth/estlab-ekf",
            "--workbench",
            "https://estlab.example.org/",
        ]),
        "estlab package prairielearn",
    );
    assert!(said.contains("docker build -t kth/estlab-ekf"), "{said}");
    let binary = out.join("grader/estlab");
    assert_static(&binary);

    // The image: the static binary where the entrypoint runs it.
    let dockerfile = std::fs::read_to_string(out.join("grader/Dockerfile")).unwrap();
    assert!(dockerfile.contains("\nFROM alpine:"), "{dockerfile}");
    assert!(
        dockerfile.contains("\nCOPY estlab /usr/local/bin/estlab\n"),
        "{dockerfile}"
    );
    let info: Info = read(&out.join("question/info.json"));
    assert_eq!(info.uuid.len(), 36);
    assert_eq!(info.grading_method, "External");
    let grading = &info.external_grading_options;
    assert!(grading.enabled && grading.timeout >= 10 && grading.timeout <= 600);
    assert_eq!(grading.image, "kth/estlab-ekf");
    assert_eq!(
        grading.entrypoint,
        [
            "/usr/local/bin/estlab",
            "autograde",
            "prairielearn",
            "--root",
            "/grade"
        ]
    );
    let html = std::fs::read_to_string(out.join("question/question.html")).unwrap();
    for part in [
        r#"<pl-file-editor file-name="ekf_localization.js" ace-mode="ace/mode/javascript" source-file-name="starter.js">"#,
        "<pl-external-grader-results>",
        "{{params.seed}}",
        "https://estlab.example.org/ekf/code?seed={{params.seed}}",
    ] {
        assert!(html.contains(part), "{part} not in\n{html}");
    }
    let starter = std::fs::read_to_string(out.join("question/starter.js")).unwrap();
    assert!(starter.contains("not implemented"));
    let server = std::fs::read_to_string(out.join("question/server.py")).unwrap();
    assert!(server.contains(r#"data["params"]["seed"]"#), "{server}");

    // A grading job: /grade laid out under a temporary root.
    let root = dir.path().join("grade");
    std::fs::create_dir_all(root.join("student")).unwrap();
    std::fs::create_dir_all(root.join("data")).unwrap();
    copy_dir(&out.join("question/tests"), &root.join("tests"));
    let secret = root.join("tests/secret");
    let entrypoint: Vec<String> = grading
        .entrypoint
        .iter()
        .map(|arg| arg.replace("/usr/local/bin/estlab", binary.to_str().unwrap()))
        .map(|arg| {
            if arg == "/grade" {
                root.display().to_string()
            } else {
                arg
            }
        })
        .collect();
    let grade = |source: Option<&str>, seed: u64| -> PrairieLearnResults {
        let _ = std::fs::remove_dir_all(root.join("results"));
        let student = root.join("student/ekf_localization.js");
        match source {
            Some(source) => std::fs::write(&student, source).unwrap(),
            None => {
                let _ = std::fs::remove_file(&student);
            }
        }
        let data = serde_json::json!({
            "params": { "seed": seed },
            "correct_answers": {},
            "submitted_answers": { "_files": [] },
            "format_errors": {},
            "variant_seed": seed,
            "options": {},
        });
        std::fs::write(root.join("data/data.json"), data.to_string()).unwrap();
        let run = Command::new(&entrypoint[0])
            .args(&entrypoint[1..])
            .output()
            .unwrap();
        succeeded(&run, "the entrypoint");
        read(&root.join("results/results.json"))
    };
    // `estlab grade` with the variant and the key the results name.
    let alone = |source: &str, graded: &PrairieLearnResults| -> PrairieLearnResults {
        let seed = graded.estlab.seed;
        let key = graded.estlab.hidden_key.expect("hidden cases were graded");
        let file = dir.path().join("alone.js");
        std::fs::write(&file, source).unwrap();
        let output = Command::new(&binary)
            .arg("grade")
            .arg(&file)
            .args(["--seed", &seed.to_string(), "--format", "prairielearn"])
            .args(["--javascript", "quickjs"])
            .arg("--secret")
            .arg(&secret)
            .args(["--submission", &key.to_string()])
            .output()
            .unwrap();
        serde_json::from_str(&succeeded(&output, "estlab grade")).unwrap()
    };

    let correct = grade(Some(CORRECT), 4242);
    assert_eq!(correct, alone(CORRECT, &correct));
    assert!(
        correct.gradable && correct.score == 1.0,
        "{}",
        correct.message
    );
    assert_eq!(correct.estlab.seed, 4242);
    assert!(correct.estlab.grader.starts_with("estlab 0.1.0 plan "));
    // A variant submitted again: the same file draws the same hidden cases (a regrade
    // agrees), any other file other ones, so what one attempt revealed of a hidden case
    // is of no use to the next.
    let again = grade(Some(CORRECT), 4242);
    assert_eq!(again.estlab.hidden_key, correct.estlab.hidden_key);
    let edited = grade(Some(&format!("{CORRECT}\n// one more line")), 4242);
    assert_ne!(edited.estlab.hidden_key, correct.estlab.hidden_key);
    for name in ["predict-transposed", "outlier-any-landmark"] {
        let (source, breaks) = mistaken(name);
        let results = grade(Some(&source), 99);
        assert_eq!(results, alone(&source, &results), "{name}");
        assert!(results.score < 1.0, "{name}");
        let broken = results
            .tests
            .iter()
            .find(|t| t.name.starts_with(&format!("{breaks}:")))
            .unwrap();
        assert!(broken.points < broken.max_points, "{name}");
    }
    let (_, source, _) = &hostile()[0];
    let thrown = grade(Some(source), 5);
    assert_eq!(thrown, alone(source, &thrown));

    let nothing = grade(None, 5);
    assert!(!nothing.gradable);
    assert!(
        nothing
            .format_errors
            .as_deref()
            .is_some_and(|e| e.contains("nothing was submitted")),
        "{:?}",
        nothing.format_errors
    );
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
    }
}

#[test]
fn packaging_refuses_a_dynamic_binary_an_existing_output_and_an_unknown_exercise() {
    let dir = tempfile::tempdir().unwrap();
    let zip = dir.path().join("autograder.zip");
    let dynamic = estlab(&[
        "package",
        "gradescope",
        "--out",
        zip.to_str().unwrap(),
        "--binary",
        env!("CARGO_BIN_EXE_estlab"),
    ]);
    assert!(!dynamic.status.success());
    assert!(
        text(&dynamic.stderr).contains("is dynamically linked"),
        "{}",
        text(&dynamic.stderr)
    );
    assert!(!zip.exists());

    // A static estlab built from other sources (here: the static build with another
    // source hash written into it) would package another grader: refused.
    let static_build = Path::new(env!("CARGO_BIN_EXE_estlab"))
        .parent()
        .and_then(Path::parent)
        .unwrap()
        .join("x86_64-unknown-linux-musl/release/estlab");
    let mut bytes = std::fs::read(&static_build).unwrap();
    let marker = b"(sources ";
    let at = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .expect("the version in the static build")
        + marker.len();
    bytes[at] = if bytes[at] == b'0' { b'1' } else { b'0' };
    let other = dir.path().join("estlab-other");
    std::fs::write(&other, &bytes).unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&other, std::fs::Permissions::from_mode(0o755)).unwrap();
    let stale = estlab(&[
        "package",
        "gradescope",
        "--out",
        zip.to_str().unwrap(),
        "--binary",
        other.to_str().unwrap(),
    ]);
    assert!(!stale.status.success());
    assert!(
        text(&stale.stderr).contains("it was built from other sources"),
        "{}",
        text(&stale.stderr)
    );
    assert!(!zip.exists());

    std::fs::write(&zip, "mine").unwrap();
    let existing = estlab(&["package", "gradescope", "--out", zip.to_str().unwrap()]);
    assert!(!existing.status.success());
    assert!(text(&existing.stderr).contains("autograder.zip"));
    assert_eq!(std::fs::read_to_string(&zip).unwrap(), "mine");

    let unknown = estlab(&[
        "package",
        "prairielearn",
        "--lab",
        "particle-filter",
        "--out",
        dir.path().join("pl").to_str().unwrap(),
    ]);
    assert!(!unknown.status.success());
    assert!(
        text(&unknown.stderr).contains("ekf-localization"),
        "{}",
        text(&unknown.stderr)
    );

    // A package's secret can be a server's, so that hidden cases stay those of earlier
    // submissions: the graders' versions then agree.
    let data = dir.path().join("data");
    std::fs::create_dir(&data).unwrap();
    std::fs::write(data.join("secret"), [7u8; 32]).unwrap();
    let kept = dir.path().join("kept.zip");
    succeeded(
        &estlab(&[
            "package",
            "gradescope",
            "--out",
            kept.to_str().unwrap(),
            "--secret",
            data.join("secret").to_str().unwrap(),
        ]),
        "estlab package --secret",
    );
    let mut archive = zip::ZipArchive::new(std::fs::File::open(&kept).unwrap()).unwrap();
    let mut secret = Vec::new();
    std::io::Read::read_to_end(&mut archive.by_name("secret").unwrap(), &mut secret).unwrap();
    assert_eq!(secret, [7u8; 32]);
}

/// The odometry exercise packaged: Gradescope grades `odometry.js` (picked by its name
/// among the scripts submitted) with that exercise's tests and hidden cases, exactly as
/// `estlab grade --lab odometry` does; PrairieLearn's question names that file and that
/// exercise's workbench.
#[test]
fn packages_of_the_odometry_exercise_grade_its_file_and_name_its_workbench() {
    const ODOMETRY: &str = student::odometry::CORRECT;
    let gradescope = Gradescope::new("odometry");
    let files = [("odometry.js", ODOMETRY), ("scratch.js", "// notes")];
    let correct = gradescope.grade(&files, &[4301], 8001);
    assert_eq!(correct, gradescope.graded_alone(ODOMETRY, &correct));
    assert_eq!(correct.extra_data.lab, Some(labs::Exercise::Odometry));
    assert!(correct.score.is_some_and(|score| score > 0.0));
    assert!(
        correct.tests.iter().all(|t| t.status == Status::Passed),
        "{:#?}",
        correct.tests
    );
    assert!(
        correct
            .tests
            .iter()
            .any(|t| t.name.starts_with("odometry_step")),
        "{:#?}",
        correct.tests
    );
    let wrong = gradescope.grade(
        &[("ekf_localization.js", CORRECT), ("x.js", "")],
        &[4301],
        8002,
    );
    assert_eq!(wrong.score, None, "{wrong:#?}");
    assert!(
        wrong
            .output
            .contains("submit only your odometry.js, or name the one to grade odometry.js"),
        "{}",
        wrong.output
    );

    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("question-package");
    succeeded(
        &estlab(&[
            "package",
            "prairielearn",
            "--lab",
            "odometry",
            "--out",
            out.to_str().unwrap(),
            "--workbench",
            "https://estlab.example.org",
        ]),
        "estlab package prairielearn --lab odometry",
    );
    let html = std::fs::read_to_string(out.join("question/question.html")).unwrap();
    for part in [
        r#"<pl-file-editor file-name="odometry.js""#,
        "https://estlab.example.org/odometry/code?seed={{params.seed}}",
    ] {
        assert!(html.contains(part), "{part} not in\n{html}");
    }
    let starter = std::fs::read_to_string(out.join("question/starter.js")).unwrap();
    assert!(starter.contains("function odometry_step"), "{starter}");
    let info: Info = read(&out.join("question/info.json"));
    assert!(info.title.starts_with("Odometry"), "{}", info.title);
    assert!(info.tags.contains(&"odometry".to_owned()));
}
