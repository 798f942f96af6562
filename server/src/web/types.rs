//! The types the browser reads, declared for its scripts: TypeScript generated from the
//! Rust types that serialise them, one file a type in `static/src/types/`, which the
//! scripts import in their JSDoc and the test command type-checks them against. A test
//! fails when the files there are not what the Rust types make; `ESTLAB_WRITE_TYPES=1
//! cargo test -p estlab --lib browser_types` writes them anew.

use super::{answers, codes, error, me, registry, report, reviews, setup, staff, submit};
use crate::store;
use labs::Exercise;
use labs::exercises::{Graded, Visit};
use labs::grading::{GradeResult, Job, Outputs};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use ts_rs::{Config, ExportError, TS, TypeVisitor};

/// Writes the declaration of every type the browser reads, and of the types they hold,
/// into `dir`. Panics when two types would be declared in one file (the same name).
pub fn export(dir: &Path) -> Result<(), ExportError> {
    // Integers reach the scripts as JavaScript numbers, whatever their width in Rust.
    let cfg = Config::new().with_out_dir(dir).with_large_int("number");
    let mut declared = Declarations {
        cfg: &cfg,
        files: HashMap::new(),
        error: None,
    };
    let d = &mut declared;
    // The grading: its result, the job the sandbox runs and what the sandbox reports.
    d.visit::<GradeResult>();
    d.visit::<Job>();
    d.visit::<Outputs>();
    // Each exercise's runs: what its loop reads and records.
    for exercise in Exercise::ALL {
        exercise.visit(RunTypes(d));
    }
    // The site, what `/api/me` says, a student's submissions.
    d.visit::<registry::Site>();
    d.visit::<me::About>();
    d.visit::<submit::Accepted>();
    d.visit::<store::Submission>();
    d.visit::<store::SubmissionSummary>();
    d.visit::<error::ErrorBody>();
    // The fusion page: the real trials the server offers, and what the wasm build gives.
    d.visit::<crate::datasets::NamedTrial>();
    d.visit::<labs::fusion::Settings>();
    d.visit::<labs::fusion::TrialParams>();
    d.visit::<labs::fusion::Summary>();
    d.visit::<labs::fusion::ReportFigures>();
    // The MRCLAM page: the real robots the server offers, and what the wasm build gives.
    d.visit::<crate::datasets::MrclamEntry>();
    d.visit::<labs::mrclam::simulate::DatasetParams>();
    d.visit::<labs::mrclam::run::Settings>();
    d.visit::<labs::mrclam::run::Kind>();
    d.visit::<labs::mrclam::run::Consistency>();
    d.visit::<labs::mrclam::belief::Readings>();
    // The staff's views and changes.
    d.visit::<setup::CourseView>();
    d.visit::<setup::StaffAdded>();
    d.visit::<setup::RosterAnswer>();
    d.visit::<codes::CodesFile>();
    d.visit::<codes::CodesStarted>();
    d.visit::<codes::CodesProgress>();
    d.visit::<setup::TokenMade>();
    d.visit::<setup::Revoked>();
    d.visit::<store::Assignment>();
    d.visit::<staff::ClassAnswer>();
    d.visit::<staff::StudentAnswer>();
    d.visit::<staff::RegradeStarted>();
    d.visit::<staff::RankingSet>();
    d.visit::<staff::LanguagesSet>();
    d.visit::<store::Regrade>();
    d.visit::<store::Granted>();
    d.visit::<store::Waived>();
    d.visit::<store::AuditEntry>();
    // The written questions: the sets, the answers, what the page sends.
    d.visit::<answers::Written>();
    d.visit::<answers::AnswerRequest>();
    d.visit::<answers::QuestionsRequest>();
    // Peer review: the rounds for staff, the sheets for students, what each sends.
    d.visit::<reviews::RoundView>();
    d.visit::<reviews::OpenRequest>();
    d.visit::<reviews::RoundAction>();
    d.visit::<reviews::StudentRound>();
    d.visit::<reviews::SheetView>();
    d.visit::<reviews::MarkRequest>();
    // The report: a student's, the class's, its runs, what students and staff send.
    d.visit::<report::ReportView>();
    d.visit::<report::ReportLine>();
    d.visit::<report::ReportRuns>();
    d.visit::<report::AnalysisRequest>();
    d.visit::<report::HandInRequest>();
    d.visit::<report::RubricRequest>();
    declared.error.map_or(Ok(()), Err)
}

/// Declares each type it visits and the types it holds, once each: a file a type, named
/// for the type, so two types of one name (`Status` of a test and of a submission) would
/// overwrite each other's file: one of them needs `#[ts(rename = "...")]`. (Two Rust types
/// may share one declaration, as serde_json's `Value` and `Map` share `JsonValue`.)
struct Declarations<'a> {
    cfg: &'a Config,
    files: HashMap<PathBuf, String>,
    error: Option<ExportError>,
}

impl TypeVisitor for Declarations<'_> {
    fn visit<T: TS + 'static + ?Sized>(&mut self) {
        let Some(file) = T::output_path() else {
            return; // a primitive, a list, a union of names: written where it is used
        };
        let text = match T::export_to_string(self.cfg) {
            Ok(text) => text,
            Err(error) => {
                self.error.get_or_insert(error);
                return;
            }
        };
        if let Some(other) = self.files.get(&file) {
            assert!(
                *other == text,
                "two types are declared as {}: rename one with #[ts(rename = \"...\")]",
                file.display()
            );
            return;
        }
        self.files.insert(file, text);
        if let Err(error) = T::export(self.cfg) {
            self.error.get_or_insert(error);
        }
        T::visit_dependencies(self);
    }
}

/// Declares an exercise's types of its runs.
struct RunTypes<'a, 'b>(&'a mut Declarations<'b>);

impl Visit for RunTypes<'_, '_> {
    type Output = ();

    fn visit<G: Graded>(self) {
        self.0.visit::<G::Run>();
        self.0.visit::<G::Record>();
    }
}

#[cfg(test)]
mod browser_types {
    use super::export;
    use std::collections::{BTreeMap, BTreeSet};
    use std::path::{Path, PathBuf};

    /// Every file under `dir` by its path there, with its text.
    fn files(dir: &Path) -> BTreeMap<PathBuf, String> {
        let mut found = BTreeMap::new();
        let mut folders = vec![dir.to_owned()];
        while let Some(folder) = folders.pop() {
            let Ok(entries) = std::fs::read_dir(&folder) else {
                continue;
            };
            for entry in entries {
                let path = entry.expect("a readable folder").path();
                if path.is_dir() {
                    folders.push(path);
                } else {
                    let text = std::fs::read_to_string(&path).expect("a readable file");
                    found.insert(path.strip_prefix(dir).unwrap().to_owned(), text);
                }
            }
        }
        found
    }

    #[test]
    fn the_scripts_declarations_are_what_the_rust_types_make() {
        let committed = Path::new(env!("CARGO_MANIFEST_DIR")).join("../static/src/types");
        if std::env::var_os("ESTLAB_WRITE_TYPES").is_some() {
            let _ = std::fs::remove_dir_all(&committed);
            export(&committed).expect("the declarations are written");
        }
        let made = tempfile::tempdir().unwrap();
        export(made.path()).expect("the declarations are written");
        let (made, committed) = (files(made.path()), files(&committed));
        let stale: BTreeSet<&PathBuf> = made
            .keys()
            .chain(committed.keys())
            .filter(|name| made.get(*name) != committed.get(*name))
            .collect();
        assert!(
            stale.is_empty(),
            "static/src/types/ is not what the Rust types make ({stale:?} differ): \
             `ESTLAB_WRITE_TYPES=1 cargo test -p estlab --lib browser_types` writes it anew"
        );
    }
}
