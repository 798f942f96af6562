//! A course's exercise handed on: the gradebook as CSV or XLSX for the university's
//! system, each student's result as Gradescope's or PrairieLearn's `results.json`, and
//! every student's source in one zip for an external plagiarism check. Each student's
//! entry is their submission that counts (the latest when none is graded).

mod archive;
mod gradebook;

pub use gradebook::{HandIn, inert};

use super::class::{self, ClassView, StudentRow};
use crate::platforms::{GradescopeResults, PrairieLearnResults};
use crate::store::{self, Store, Submission};
use archive::{FileNames, zip_of};
use labs::Language;
use std::collections::HashMap;

/// What an export holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum Format {
    /// The gradebook: a row per student.
    Csv,
    /// The gradebook as an Excel workbook.
    Xlsx,
    /// A zip of `ID/results.json` in Gradescope's format.
    Gradescope,
    /// A zip of `ID/results.json` in PrairieLearn's format.
    Prairielearn,
    /// A zip of `ID.js` (or `ID.py`), each student's source.
    Sources,
}

impl Format {
    /// The file name an export is offered under.
    pub fn file_name(self, course: &str, lab: &str) -> String {
        match self {
            Format::Csv => format!("{course}-{lab}-grades.csv"),
            Format::Xlsx => format!("{course}-{lab}-grades.xlsx"),
            Format::Gradescope => format!("{course}-{lab}-gradescope.zip"),
            Format::Prairielearn => format!("{course}-{lab}-prairielearn.zip"),
            Format::Sources => format!("{course}-{lab}-sources.zip"),
        }
    }

    pub fn content_type(self) -> &'static str {
        match self {
            Format::Csv => "text/csv; charset=utf-8",
            Format::Xlsx => "application/vnd.openxmlformats-officedocument.spreadsheetml.sheet",
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

fn file_names(view: &ClassView) -> FileNames {
    FileNames::of(view.students.iter().map(|s| s.id.as_str()))
}

/// Every student's result in a platform's format (`ID/results.json`), naming the grader
/// that graded it.
pub fn results(view: &ClassView, graded: &HashMap<i64, Submission>, format: Format) -> Vec<u8> {
    let names = file_names(view);
    let files =
        view.students
            .iter()
            .filter_map(|s| {
                let submission = graded.get(&exported(s)?)?;
                let result = submission.result.as_ref()?;
                let grader = submission.grader.as_deref().unwrap_or("estlab");
                let json =
                    match format {
                        // The server draws a submission's hidden cases from its id.
                        Format::Prairielearn => serde_json::to_vec_pretty(
                            &PrairieLearnResults::of(result, grader, Some(submission.summary.id)),
                        ),
                        _ => serde_json::to_vec_pretty(&GradescopeResults::of(
                            result,
                            grader,
                            Some(submission.summary.id),
                        )),
                    };
                Some((
                    s.id.clone(),
                    format!("{}/results.json", names.get(&s.id)),
                    json.expect("results serialise"),
                ))
            })
            .collect();
    zip_of(&names, files)
}

/// Every student's source (`ID.js`, or `ID.py` for a file in Python).
pub fn sources(view: &ClassView, sources: &HashMap<i64, (Language, String)>) -> Vec<u8> {
    let names = file_names(view);
    let files = view
        .students
        .iter()
        .filter_map(|s| {
            let (language, source) = sources.get(&exported(s)?)?;
            Some((
                s.id.clone(),
                format!("{}.{}", names.get(&s.id), language.extension()),
                source.clone().into_bytes(),
            ))
        })
        .collect();
    zip_of(&names, files)
}

/// An export of a course's exercise, as the web and the command line make it; `None`
/// when the course has not opened the exercise.
pub fn make(
    store: &Store,
    course: &str,
    lab: labs::Exercise,
    format: Format,
) -> Result<Option<Vec<u8>>, store::Error> {
    let Some(view) = class::load(store, course, lab)? else {
        return Ok(None);
    };
    let ids: Vec<i64> = view.students.iter().filter_map(exported).collect();
    Ok(Some(match format {
        Format::Csv => gradebook::csv(&view, &HandIn::load(store, course, lab)?),
        Format::Xlsx => gradebook::xlsx(&view, &HandIn::load(store, course, lab)?),
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
                if let Some(submission) = store.get(id, true)? {
                    let language = submission.summary.language;
                    if let Some(source) = submission.source {
                        texts.insert(id, (language, source));
                    }
                }
            }
            sources(&view, &texts)
        }
    }))
}
