//! A course's exercise handed on: the gradebook as CSV for the university's system, each
//! student's result as Gradescope's or PrairieLearn's `results.json`, and every
//! student's source in one zip for an external plagiarism check. Each student's entry is
//! their submission that counts (the latest when none is graded).

use super::class::{self, ClassView, StudentRow};
use crate::store::{self, Store, Submission};
use std::collections::HashMap;
use std::io::{Cursor, Write};
use zip::write::SimpleFileOptions;

/// What an export holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum Format {
    /// The gradebook: a row per student.
    Csv,
    /// A zip of `ID/results.json` in Gradescope's format.
    Gradescope,
    /// A zip of `ID/results.json` in PrairieLearn's format.
    Prairielearn,
    /// A zip of `ID.js`, each student's source.
    Sources,
}

impl Format {
    /// The file name an export is offered under.
    pub fn file_name(self, course: &str, lab: &str) -> String {
        match self {
            Format::Csv => format!("{course}-{lab}-grades.csv"),
            Format::Gradescope => format!("{course}-{lab}-gradescope.zip"),
            Format::Prairielearn => format!("{course}-{lab}-prairielearn.zip"),
            Format::Sources => format!("{course}-{lab}-sources.zip"),
        }
    }

    pub fn content_type(self) -> &'static str {
        match self {
            Format::Csv => "text/csv; charset=utf-8",
            _ => "application/zip",
        }
    }
}

/// The submission an export takes for a student: the one that counts, or the latest.
pub fn exported(student: &StudentRow) -> Option<i64> {
    student
        .counting
        .as_ref()
        .or(student.latest.as_ref())
        .map(|s| s.id)
}

/// The gradebook. Columns: `id, name, email, status (enrolled or dropped), submissions,
/// score (of the submission that counts, in [0, 1]), late_penalty (its share lost),
/// final_score (score × (1 − late_penalty)), submitted_at (UTC)`; empty for a student
/// with no graded submission.
pub fn gradebook(view: &ClassView) -> Vec<u8> {
    let mut csv = csv::Writer::from_writer(Vec::new());
    let header = [
        "id",
        "name",
        "email",
        "status",
        "submissions",
        "score",
        "late_penalty",
        "final_score",
        "submitted_at",
    ];
    csv.write_record(header).expect("writing to memory");
    let number = |value: Option<f64>| value.map_or_else(String::new, |v| format!("{v:.4}"));
    for s in &view.students {
        let counting = s.counting.as_ref();
        csv.write_record([
            inert(&s.id),
            inert(&s.name),
            inert(&s.email),
            if s.dropped { "dropped" } else { "enrolled" }.to_string(),
            s.submissions.to_string(),
            number(counting.and_then(|c| c.score)),
            number(counting.map(|c| c.penalty)),
            number(counting.and_then(|c| c.final_score)),
            counting.map_or_else(String::new, |c| c.submitted_at.clone()),
        ])
        .expect("writing to memory");
    }
    csv.into_inner().expect("writing to memory")
}

/// A text cell a spreadsheet will not run: one that starts like a formula (`=`, `+`, `-`,
/// `@`, a tab or a carriage return) gets a leading `'`, which spreadsheets show as text.
pub fn inert(text: &str) -> String {
    if text.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        format!("'{text}")
    } else {
        text.to_string()
    }
}

/// A zip of one file per student with an exported submission.
fn zip_of(files: impl IntoIterator<Item = (String, Vec<u8>)>) -> Vec<u8> {
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    for (name, bytes) in files {
        zip.start_file(name, options).expect("writing to memory");
        zip.write_all(&bytes).expect("writing to memory");
    }
    zip.finish().expect("writing to memory").into_inner()
}

/// Every student's result in a platform's format (`ID/results.json`), naming the grader
/// that graded it.
pub fn results(view: &ClassView, graded: &HashMap<i64, Submission>, format: Format) -> Vec<u8> {
    zip_of(view.students.iter().filter_map(|s| {
        let submission = graded.get(&exported(s)?)?;
        let result = submission.result.as_ref()?;
        let grader = submission.grader.as_deref().unwrap_or("estlab");
        let json = match format {
            // The server draws a submission's hidden cases from its id.
            Format::Prairielearn => {
                serde_json::to_vec_pretty(&result.prairielearn(grader, Some(submission.summary.id)))
            }
            _ => serde_json::to_vec_pretty(&result.gradescope(grader, Some(submission.summary.id))),
        };
        Some((
            format!("{}/results.json", s.id),
            json.expect("results serialise"),
        ))
    }))
}

/// Every student's source (`ID.js`).
pub fn sources(view: &ClassView, sources: &HashMap<i64, String>) -> Vec<u8> {
    zip_of(view.students.iter().filter_map(|s| {
        let source = sources.get(&exported(s)?)?;
        Some((format!("{}.js", s.id), source.clone().into_bytes()))
    }))
}

/// An export of a course's exercise, as the web and the command line make it; `None`
/// when the course has not opened the exercise.
pub fn make(
    store: &Store,
    course: &str,
    lab: &str,
    format: Format,
) -> Result<Option<Vec<u8>>, store::Error> {
    let Some(view) = class::load(store, course, lab)? else {
        return Ok(None);
    };
    let ids: Vec<i64> = view.students.iter().filter_map(exported).collect();
    Ok(Some(match format {
        Format::Csv => gradebook(&view),
        Format::Gradescope | Format::Prairielearn => {
            let mut graded = HashMap::new();
            for id in ids {
                if let Some(submission) = store.get(id, false)? {
                    graded.insert(id, submission);
                }
            }
            results(&view, &graded, format)
        }
        Format::Sources => {
            let mut texts = HashMap::new();
            for id in ids {
                if let Some(source) = store.get(id, true)?.and_then(|s| s.source) {
                    texts.insert(id, source);
                }
            }
            sources(&view, &texts)
        }
    }))
}

#[cfg(test)]
mod tests {
    use super::inert;

    #[test]
    fn a_cell_that_looks_like_a_formula_is_kept_as_text() {
        assert_eq!(
            inert("=HYPERLINK(\"http://x\")"),
            "'=HYPERLINK(\"http://x\")"
        );
        assert_eq!(inert("+46 8 790 60 00"), "'+46 8 790 60 00");
        assert_eq!(inert("@SUM(A1)"), "'@SUM(A1)");
        assert_eq!(inert("-1"), "'-1");
        assert_eq!(inert("Ada Lovelace"), "Ada Lovelace");
        assert_eq!(inert("u1"), "u1");
    }
}
