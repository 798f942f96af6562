//! Which of the files a student submitted on a platform is the one to grade.

use std::path::{Path, PathBuf};

/// The name of the student's file: the starter's, as the workbench downloads it.
pub const STUDENT_FILE: &str = "ekf_localization.js";
/// Folders below the submission's that are looked into (a zip of a folder adds one).
const DEPTH: usize = 4;
/// Files looked at, at most: a submission of thousands of files is not a lab's.
const FILES: usize = 1000;

/// The JavaScript file to grade among those under `dir`: the only `.js` file, or else the
/// one named like the starter. Hidden files and macOS's `__MACOSX` folders are not the
/// student's. The error says what was found, for the student.
pub fn student_file(dir: &Path) -> Result<PathBuf, String> {
    let mut found = Vec::new();
    walk(dir, 0, &mut found);
    let relative = |path: &PathBuf| path.strip_prefix(dir).unwrap_or(path).display().to_string();
    let scripts: Vec<&PathBuf> = found
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("js")))
        .collect();
    match scripts.as_slice() {
        [one] => Ok((*one).clone()),
        [] if found.is_empty() => Err(format!("nothing was submitted: submit your {STUDENT_FILE}")),
        [] => Err(format!(
            "no JavaScript file was submitted (found {}): submit your {STUDENT_FILE}",
            list(found.iter().map(relative))
        )),
        several => {
            let named: Vec<&&PathBuf> = several
                .iter()
                .filter(|p| p.file_name().is_some_and(|n| n == STUDENT_FILE))
                .collect();
            match named.as_slice() {
                [one] => Ok((**one).clone()),
                _ => Err(format!(
                    "several JavaScript files were submitted ({}): submit only your {STUDENT_FILE}, or name the one to grade {STUDENT_FILE}",
                    list(several.iter().map(|p| relative(p)))
                )),
            }
        }
    }
}

/// Regular files under `dir`, depth first in name order, skipping hidden entries and
/// `__MACOSX`; symbolic links are not followed.
fn walk(dir: &Path, depth: usize, found: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<_> = entries.filter_map(Result::ok).collect();
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        if found.len() >= FILES {
            return;
        }
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if name.starts_with('.') || name == "__MACOSX" {
            continue;
        }
        let Ok(kind) = entry.file_type() else {
            continue;
        };
        if kind.is_file() {
            found.push(entry.path());
        } else if kind.is_dir() && depth < DEPTH {
            walk(&entry.path(), depth + 1, found);
        }
    }
}

/// Names for a message: the first few, and how many more.
fn list(names: impl Iterator<Item = String>) -> String {
    let names: Vec<String> = names.collect();
    let mut text = names.iter().take(5).cloned().collect::<Vec<_>>().join(", ");
    if names.len() > 5 {
        text.push_str(&format!(" and {} more", names.len() - 5));
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(files: &[&str]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        for file in files {
            let path = dir.path().join(file);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, "x").unwrap();
        }
        dir
    }

    fn pick(files: &[&str]) -> Result<String, String> {
        let dir = folder(files);
        student_file(dir.path()).map(|p| p.strip_prefix(dir.path()).unwrap().display().to_string())
    }

    #[test]
    fn the_only_script_or_the_one_named_like_the_starter() {
        assert_eq!(pick(&["mine.js", "notes.txt"]).unwrap(), "mine.js");
        assert_eq!(pick(&["lab1/Filter.JS"]).unwrap(), "lab1/Filter.JS");
        assert_eq!(
            pick(&["a.js", "sub/ekf_localization.js"]).unwrap(),
            "sub/ekf_localization.js"
        );
        assert_eq!(
            pick(&[
                "ekf_localization.js",
                "__MACOSX/._ekf_localization.js",
                ".x.js"
            ])
            .unwrap(),
            "ekf_localization.js"
        );
    }

    #[test]
    fn none_or_several_say_what_was_found() {
        let none = pick(&["report.pdf", "notes.txt"]).unwrap_err();
        assert!(
            none.contains("no JavaScript file") && none.contains("notes.txt, report.pdf"),
            "{none}"
        );
        assert!(pick(&[]).unwrap_err().contains("nothing was submitted"));
        let several = pick(&["a.js", "b.js"]).unwrap_err();
        assert!(
            several.contains("several JavaScript files were submitted (a.js, b.js)")
                && several.contains("ekf_localization.js"),
            "{several}"
        );
        let twice = pick(&["x/ekf_localization.js", "y/ekf_localization.js"]).unwrap_err();
        assert!(twice.contains("several"), "{twice}");
        let deep = pick(&["a/b/c/d/e/f/deep.js"]).unwrap_err();
        assert!(deep.contains("nothing was submitted"), "{deep}");
    }
}
