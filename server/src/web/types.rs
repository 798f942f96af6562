//! The types the browser reads, declared for its scripts: TypeScript generated from the
//! Rust types that serialise them, one file a type in `static/src/types/`, which the
//! scripts import in their JSDoc and the test command type-checks them against. A test
//! fails when the files there are not what the Rust types make; `ESTLAB_WRITE_TYPES=1
//! cargo test -p estlab --lib browser_types` writes them anew.

use super::{error, me, registry, setup, staff, submit};
use crate::store;
use labs::Exercise;
use labs::exercises::{Graded, Visit};
use labs::grading::{GradeResult, Job, Outputs};
use std::path::Path;
use ts_rs::{Config, ExportError, TS};

/// Writes the declaration of every type the browser reads, and of the types they hold,
/// into `dir`.
pub fn export(dir: &Path) -> Result<(), ExportError> {
    // Integers reach the scripts as JavaScript numbers, whatever their width in Rust.
    let cfg = Config::new().with_out_dir(dir).with_large_int("number");
    // The grading: its result, the job the sandbox runs and what the sandbox reports.
    GradeResult::export_all(&cfg)?;
    Job::export_all(&cfg)?;
    Outputs::export_all(&cfg)?;
    // Each exercise's runs: what its loop reads and records.
    for exercise in Exercise::ALL {
        exercise.visit(RunTypes(&cfg))?;
    }
    // The site, what `/api/me` says, a student's submissions.
    registry::Site::export_all(&cfg)?;
    me::About::export_all(&cfg)?;
    submit::Accepted::export_all(&cfg)?;
    store::Submission::export_all(&cfg)?;
    store::SubmissionSummary::export_all(&cfg)?;
    error::ErrorBody::export_all(&cfg)?;
    // The staff's views and changes.
    setup::CourseView::export_all(&cfg)?;
    setup::StaffAdded::export_all(&cfg)?;
    setup::RosterAnswer::export_all(&cfg)?;
    setup::CodesFile::export_all(&cfg)?;
    setup::TokenMade::export_all(&cfg)?;
    setup::Revoked::export_all(&cfg)?;
    store::Assignment::export_all(&cfg)?;
    staff::ClassAnswer::export_all(&cfg)?;
    staff::StudentAnswer::export_all(&cfg)?;
    staff::RegradeStarted::export_all(&cfg)?;
    store::Regrade::export_all(&cfg)?;
    store::Granted::export_all(&cfg)?;
    store::Waived::export_all(&cfg)?;
    store::AuditEntry::export_all(&cfg)?;
    Ok(())
}

/// Exports an exercise's types of its runs.
struct RunTypes<'a>(&'a Config);

impl Visit for RunTypes<'_> {
    type Output = Result<(), ExportError>;

    fn visit<G: Graded>(self) -> Self::Output {
        G::Run::export_all(self.0)?;
        G::Record::export_all(self.0)
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
