//! The zips of an export: one file per student (`ID.js` or `ID.py`, `ID/results.json`), unpacked on
//! Windows, macOS and Linux and read by plagiarism checkers. A student's file is named by
//! their id when the id is safe as a file name everywhere (`ids::is_safe`) and no other
//! id of the course differs from it only in case; otherwise, for ids stored before the
//! roster checked them, by an escaped form with a stable suffix (`ALICE~3fa94c0e1b2d`),
//! and the zip then holds `names.csv` saying whose file is whose.

use super::gradebook::inert;
use crate::courses::ids;
use sha2::{Digest, Sha256};
use std::collections::HashMap;
use std::io::{Cursor, Write};
use zip::write::SimpleFileOptions;

/// How many characters of an id an escaped name keeps, to be recognised by.
const KEPT: usize = 32;
/// Hex digits of the id's SHA-256 after the `~`: 48 bits, so that two ids of one course
/// meet by chance less than once in a billion classes.
const SUFFIX: usize = 12;

/// Each student's file name (without its extension) in an export of a course.
pub struct FileNames {
    names: HashMap<String, String>,
    /// Whether some name is not the id.
    escaped: bool,
}

impl FileNames {
    /// The names for the ids of a course's roster (all of them, whoever submitted, so
    /// that a student's name does not depend on who else submitted).
    pub fn of<'a>(ids: impl IntoIterator<Item = &'a str> + Clone) -> FileNames {
        let mut folds: HashMap<String, usize> = HashMap::new();
        for id in ids.clone() {
            *folds.entry(ids::fold(id)).or_default() += 1;
        }
        let mut escaped = false;
        let names = ids
            .into_iter()
            .map(|id| {
                let alone = folds[&ids::fold(id)] == 1;
                let name = if alone && ids::is_safe(id) {
                    id.to_string()
                } else {
                    escaped = true;
                    escape(id)
                };
                (id.to_string(), name)
            })
            .collect();
        FileNames { names, escaped }
    }

    /// The name of an id's file (an id from elsewhere is escaped).
    pub fn get(&self, id: &str) -> String {
        self.names.get(id).cloned().unwrap_or_else(|| escape(id))
    }
}

/// A name for an id that cannot be its own: its ASCII letters and digits (others become
/// `_`), then `~` and the start of the id's SHA-256. `~` is in no id the roster takes, so
/// an escaped name is never another student's own; it has no dot, so it is no device name
/// on Windows (`CON.x` is the console); and the suffix tells apart ids that differ only
/// in case or in what was escaped.
fn escape(id: &str) -> String {
    let kept: String = id
        .chars()
        .take(KEPT)
        .enumerate()
        .map(|(i, c)| match c {
            'a'..='z' | 'A'..='Z' | '0'..='9' => c,
            '-' | '_' if i > 0 => c,
            _ => '_',
        })
        .collect();
    let digest = Sha256::digest(id.as_bytes());
    let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
    format!("{kept}~{}", &hex[..SUFFIX])
}

/// A zip of the files given (name and bytes), and `names.csv` (`file, id`, the ids shown
/// escaped) when a name is not its student's id.
pub fn zip_of(names: &FileNames, files: Vec<(String, String, Vec<u8>)>) -> Vec<u8> {
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    let mut index = csv::Writer::from_writer(Vec::new());
    index
        .write_record(["file", "id"])
        .expect("writing to memory");
    for (id, file, bytes) in &files {
        index
            .write_record([inert(file), inert(&ids::shown(id))])
            .expect("writing to memory");
        zip.start_file(file.as_str(), options)
            .expect("writing to memory");
        zip.write_all(bytes).expect("writing to memory");
    }
    if names.escaped {
        zip.start_file("names.csv", options)
            .expect("writing to memory");
        zip.write_all(&index.into_inner().expect("writing to memory"))
            .expect("writing to memory");
    }
    zip.finish().expect("writing to memory").into_inner()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_safe_id_names_its_file_and_an_unsafe_one_is_escaped_stably() {
        let roster = [
            "u1",
            "alice",
            "ALICE",
            "CON",
            "a\"<>b",
            "u1\u{202e}sj.exe",
            "x\u{ff0f}y",
            "-rf",
            "josé",
        ];
        let names = FileNames::of(roster);
        assert!(names.escaped);
        assert_eq!(names.get("u1"), "u1");
        assert_eq!(names.get("josé"), "josé");
        let mut folded = std::collections::HashSet::new();
        for id in roster {
            let name = names.get(id);
            assert!(folded.insert(ids::fold(&name)), "{name} twice");
            if id != name {
                assert!(
                    name.contains('~') && name.is_ascii() && !name.contains('.'),
                    "{name}"
                );
                assert!(!name.starts_with(['-', '.']), "{name}");
            }
        }
        assert!(names.get("alice").starts_with("alice~"));
        assert!(names.get("CON").starts_with("CON~"));
        assert_eq!(names.get("a\"<>b").split('~').next(), Some("a___b"));
        // The same id gets the same name in another export of the course.
        assert_eq!(FileNames::of(roster).get("ALICE"), names.get("ALICE"));
        assert!(!FileNames::of(["u1", "u2"]).escaped);
    }
}
