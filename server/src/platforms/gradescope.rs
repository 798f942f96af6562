//! Gradescope's autograder: the zip an instructor uploads, and the grading of one
//! submission inside it.
//!
//! Gradescope unpacks the zip into `/autograder/source`, runs `setup.sh` once when it
//! builds the image, then for every submission runs `run_autograder` with the student's
//! files in `/autograder/submission` and `/autograder/submission_metadata.json` beside
//! them, and shows `/autograder/results/results.json`.

use super::{Drawn, GradescopeResults, PackagedGrader, SECRET, SETTINGS, Settings, write_graded};
use crate::error::Error;
use labs::grading::student_seed;
use serde::Deserialize;
use std::io::Write;
use std::path::Path;
use zip::write::SimpleFileOptions;

/// Run once, as root, when Gradescope builds the autograder's image.
const SETUP: &str = r#"#!/usr/bin/env bash
# Gradescope runs this once, when it builds the autograder's image: estlab is one
# statically linked program, so there is nothing to install; check that it runs here.
set -euo pipefail
cd "$(dirname "$0")"
chmod 0755 estlab run_autograder
./estlab --version
"#;

/// Run for every submission, as `/autograder/run_autograder` (or from `source/`).
const RUN: &str = r#"#!/usr/bin/env bash
# Gradescope runs this for every submission: estlab finds the student's .js file in
# submission/, takes the student's variant from submission_metadata.json, grades it and
# writes results/results.json.
set -uo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
case "$here" in
  */source) root="${here%/source}" ;;
  *) root="$here" ;;
esac
exec "$root/source/estlab" autograde gradescope --root "$root"
"#;

/// The zip Gradescope's "Configure Autograder" page takes.
pub fn package(binary: &[u8], settings: &Settings, secret: &[u8]) -> Result<Vec<u8>, Error> {
    let settings = serde_json::to_string_pretty(settings).expect("settings serialise") + "\n";
    let files: [(&str, &[u8], u32); 5] = [
        ("setup.sh", SETUP.as_bytes(), 0o755),
        ("run_autograder", RUN.as_bytes(), 0o755),
        ("estlab", binary, 0o755),
        (SETTINGS, settings.as_bytes(), 0o644),
        (SECRET, secret, 0o600),
    ];
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    for (name, bytes, mode) in files {
        let options = SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated)
            .unix_permissions(mode);
        let failed = |e: zip::result::ZipError| Error::Invalid(format!("{name}: {e}"));
        zip.start_file(name, options).map_err(failed)?;
        zip.write_all(bytes)
            .map_err(|e| Error::Invalid(format!("{name}: {e}")))?;
    }
    Ok(zip
        .finish()
        .map_err(|e| Error::Invalid(e.to_string()))?
        .into_inner())
}

/// What estlab reads of `submission_metadata.json` (Gradescope writes more).
#[derive(Deserialize)]
struct Metadata {
    /// The submission's id: draws its hidden cases.
    id: i64,
    users: Vec<User>,
}

#[derive(Deserialize)]
struct User {
    /// The user's Gradescope id.
    id: i64,
}

/// Grades the submission under `root` (Gradescope's `/autograder`) and writes its
/// results. The variant is the submitter's Gradescope user id within the package's
/// course (for a group the smallest of its members' ids, so that whoever uploads, the
/// group keeps its variant); the results name its seed, which the workbench opens with
/// `?seed=N` on the exercise's workbench. When the package or the metadata cannot be read, the results say
/// so (worth nothing) and the error is returned.
pub fn autograde(root: &Path) -> Result<(), Error> {
    write_graded(root, graded(root), GradescopeResults::unreadable)
}

fn graded(root: &Path) -> Result<GradescopeResults, Error> {
    let grader = PackagedGrader::read(&root.join("source"))?;
    let metadata_path = root.join("submission_metadata.json");
    let metadata: Metadata = std::fs::read_to_string(&metadata_path)
        .map_err(Error::io(&metadata_path))
        .and_then(|text| {
            serde_json::from_str(&text)
                .map_err(|e| Error::Invalid(format!("{}: {e}", metadata_path.display())))
        })?;
    let Some(user) = metadata.users.iter().map(|user| user.id).min() else {
        return Err(Error::Invalid(format!(
            "{}: no users: whose submission is this?",
            metadata_path.display()
        )));
    };
    let seed = student_seed(&grader.settings.course, &user.to_string());
    let (result, key) = grader.grade(
        &root.join("submission"),
        seed,
        Drawn::GradescopeSubmission(metadata.id),
    );
    Ok(GradescopeResults::of(&result, &grader.version, key))
}
