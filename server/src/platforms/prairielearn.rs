//! PrairieLearn's external grader: the grader image's folder and the question's folder an
//! instructor copies into the course repository, and the grading of one submission.
//!
//! For every submission PrairieLearn starts the question's image with the student's
//! files in `/grade/student`, the question's `tests/` folder in `/grade/tests` and the
//! question's data in `/grade/data/data.json`, runs the entrypoint, and reads
//! `/grade/results/results.json`.

use super::{Drawn, PackagedGrader, PrairieLearnResults, SECRET, Settings, write_graded};
use crate::error::Error;
use labs::Exercise;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Where the image keeps estlab.
pub const BINARY: &str = "/usr/local/bin/estlab";
/// Seconds PrairieLearn gives a grading: a correct file takes about one on two cores; a
/// file whose every function loops until its time limit about 16 on two cores and 29 on
/// one (BENCHMARKS.md), so this leaves room on a busy grading host.
const TIMEOUT: u32 = 120;

/// The question's `info.json`: the fields estlab writes.
#[derive(Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct Info {
    pub uuid: String,
    pub title: String,
    pub topic: String,
    pub tags: Vec<String>,
    #[serde(rename = "type")]
    pub kind: String,
    pub single_variant: bool,
    pub grading_method: String,
    pub external_grading_options: ExternalGrading,
}

#[derive(Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct ExternalGrading {
    pub enabled: bool,
    pub image: String,
    pub entrypoint: Vec<String>,
    pub timeout: u32,
}

/// What the package holds besides the question's files.
pub struct Package<'a> {
    pub binary: &'a [u8],
    pub settings: &'a Settings,
    pub secret: &'a [u8],
    /// The grader image's name, as the instructor will build and push it.
    pub image: &'a str,
    /// The question's UUID (PrairieLearn tells questions apart by it).
    pub uuid: String,
    /// The starter file the editor opens with.
    pub starter: &'a str,
    /// Where students can run the tests in their browser, if the course has a site.
    pub workbench: Option<&'a str>,
}

/// Writes the package into `out`, which must not exist yet: `grader/` (the image's
/// Dockerfile and estlab), `question/` (info.json, question.html, server.py, the starter,
/// and tests/ with the settings and the secret) and a README.
pub fn package(out: &Path, package: &Package) -> Result<(), Error> {
    std::fs::create_dir(out).map_err(Error::io(out))?;
    let grader = out.join("grader");
    let question = out.join("question");
    let tests = question.join("tests");
    for dir in [&grader, &question, &tests] {
        std::fs::create_dir(dir).map_err(Error::io(dir))?;
    }
    let exercise = package.settings.lab;
    let info = Info {
        uuid: package.uuid.clone(),
        title: format!("{} (estlab)", exercise.title()),
        topic: "Localization".to_owned(),
        tags: vec!["estlab".to_owned(), package.settings.lab.name().to_owned()],
        kind: "v3".to_owned(),
        single_variant: false,
        grading_method: "External".to_owned(),
        external_grading_options: ExternalGrading {
            enabled: true,
            image: package.image.to_owned(),
            entrypoint: [BINARY, "autograde", "prairielearn", "--root", "/grade"]
                .map(str::to_owned)
                .to_vec(),
            timeout: TIMEOUT,
        },
    };
    let info = serde_json::to_string_pretty(&info).expect("info serialises") + "\n";
    let (dockerfile, html) = (
        dockerfile(exercise),
        question_html(exercise, package.workbench),
    );
    let readme = readme(exercise, package.image);
    let files: [(&Path, &str, &[u8], u32); 8] = [
        (&grader, "Dockerfile", dockerfile.as_bytes(), 0o644),
        (&grader, "estlab", package.binary, 0o755),
        (&question, "info.json", info.as_bytes(), 0o644),
        (&question, "question.html", html.as_bytes(), 0o644),
        (&question, "server.py", SERVER_PY.as_bytes(), 0o644),
        (&question, STARTER, package.starter.as_bytes(), 0o644),
        (&tests, SECRET, package.secret, 0o600),
        (out, "README.md", readme.as_bytes(), 0o644),
    ];
    for (dir, name, bytes, mode) in files {
        write(&dir.join(name), bytes, mode)?;
    }
    package.settings.write(&tests)
}

/// The starter's file name inside the question folder.
const STARTER: &str = "starter.js";

fn write(path: &Path, bytes: &[u8], mode: u32) -> Result<(), Error> {
    use std::io::Write;
    use std::os::unix::fs::OpenOptionsExt;
    let mut file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(mode)
        .open(path)
        .map_err(Error::io(path))?;
    file.write_all(bytes).map_err(Error::io(path))
}

fn dockerfile(exercise: Exercise) -> String {
    format!(
        "# The grader image of estlab's question \"{}\" for PrairieLearn: estlab is one\n\
         # statically linked program, so a small base image does. Build it from this folder:\n\
         #   docker build -t IMAGE .\n\
         # and push it where PrairieLearn pulls images from (Docker Hub for prairielearn.com).\n\
         FROM alpine:3.21\n\
         COPY estlab {BINARY}\n\
         RUN chmod 0755 {BINARY} && {BINARY} --version\n",
        exercise.title()
    )
}

/// The variant's seed, made from PrairieLearn's variant seed when the variant is made and
/// shown in the question; the grader reads it back from `data.json`.
const SERVER_PY: &str = r#"# estlab's question: each variant gets its own seed (its test cases' numbers);
# estlab's grader reads it back from /grade/data/data.json.


def generate(data):
    data["params"]["seed"] = int(data["variant_seed"]) % (2**53)
"#;

fn question_html(exercise: Exercise, workbench: Option<&str>) -> String {
    let page = crate::web::workbench_path(exercise);
    let file = exercise.file_name();
    let declared = exercise.declaration();
    let (functions, runs) = (declared.functions, declared.runs.graded);
    let run = match workbench {
        Some(url) => format!(
            "Run the tests of your variant in your browser, as often as you like, in\n    \
             <a href=\"{url}{page}?seed={{{{params.seed}}}}\" target=\"_blank\">estlab's workbench</a>\n    \
             before you submit here."
        ),
        None => format!(
            "Run the tests of your variant in your browser in estlab's workbench\n    \
             (<code>{page}?seed=…</code> with your seed) before you submit here."
        ),
    };
    format!(
        r#"<pl-question-panel>
  <p>
    Implement the functions of the exercise "{title}" in <code>{file}</code>:
    {functions}. Each function is described in the file.
  </p>
  <p>
    Your variant is seed <strong>{{{{params.seed}}}}</strong>. {run}
    The grader also checks hidden cases and {runs}.
  </p>
  <pl-file-editor file-name="{file}" ace-mode="ace/mode/javascript" source-file-name="{STARTER}"></pl-file-editor>
</pl-question-panel>

<pl-submission-panel>
  <pl-external-grader-results></pl-external-grader-results>
  <pl-file-preview></pl-file-preview>
</pl-submission-panel>
"#,
        title = exercise.title()
    )
}

fn readme(exercise: Exercise, image: &str) -> String {
    let title = exercise.title();
    let folder = exercise.file_name().trim_end_matches(".js");
    format!(
        "# estlab's question \"{title}\" for PrairieLearn\n\n\
         1. Build the grader image from `grader/` and push it where your PrairieLearn pulls\n   \
         images from:\n\n       \
         docker build -t {image} grader/\n       \
         docker push {image}\n\n   \
         (On prairielearn.com, images come from Docker Hub; sync them on the course's\n   \
         \"Sync\" page.)\n\
         2. Copy `question/` into your course repository as `questions/{folder}/`\n   \
         and add it to an assessment. `question/tests/` holds the secret that draws the\n   \
         hidden cases: PrairieLearn never shows that folder to students.\n\
         3. To regrade after a new estlab, build and push the new image under the same name\n   \
         and regrade the question from the assessment's page.\n"
    )
}

/// What estlab reads of `data.json` (PrairieLearn writes more).
#[derive(Deserialize)]
struct Data {
    #[serde(default)]
    params: Params,
    variant_seed: Option<u64>,
}

#[derive(Default, Deserialize)]
struct Params {
    seed: Option<u64>,
}

/// Grades the submission under `root` (PrairieLearn's `/grade`) and writes its results.
/// The variant is the seed `server.py` made (PrairieLearn's variant seed, if the question
/// has no such `server.py`); the hidden cases are drawn from it and the file (see
/// [`Drawn`]). When the package or the data cannot be read, the results say so (not
/// gradable, which costs no attempt) and the error is returned.
pub fn autograde(root: &Path) -> Result<(), Error> {
    write_graded(root, graded(root), PrairieLearnResults::unreadable)
}

fn graded(root: &Path) -> Result<PrairieLearnResults, Error> {
    let grader = PackagedGrader::read(&root.join("tests"))?;
    let path = root.join("data").join("data.json");
    let text = std::fs::read_to_string(&path).map_err(Error::io(&path))?;
    let data: Data = serde_json::from_str(&text)
        .map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))?;
    let seed = data.params.seed.or(data.variant_seed).ok_or_else(|| {
        Error::Invalid(format!(
            "{}: neither params.seed nor variant_seed",
            path.display()
        ))
    })? & ((1 << 53) - 1);
    let (result, key) = grader.grade(
        &root.join("student"),
        seed,
        Drawn::PrairieLearnVariant(seed),
    );
    Ok(PrairieLearnResults::of(&result, &grader.version, key))
}
