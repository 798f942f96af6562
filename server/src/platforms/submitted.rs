//! Which of the files a student submitted on a platform is the one to grade.

use labs::Language;
use std::path::{Path, PathBuf};

/// Folders below the submission's that are looked into (a zip of a folder adds one).
const DEPTH: usize = 4;
/// Entries (files, folders, links) looked at, at most: a submission of thousands is not
/// a lab's, and walking it would only cost the grader's time.
const ENTRIES: usize = 1000;

/// The JavaScript file to grade among those under `dir`: the only `.js` file, or else the
/// one called `name` (the exercise's file, as the workbench downloads it). Hidden files
/// and macOS's `__MACOSX` folders are not the student's; links are not followed (a link to
/// the grader's own files grades nothing). The error says what was found, for the student.
pub fn student_file(dir: &Path, name: &str) -> Result<PathBuf, String> {
    let mut found = Found::default();
    found.walk(dir, 0).map_err(|TooMany| {
        format!("more than {ENTRIES} files and folders were submitted: submit your {name} alone")
    })?;
    let relative = |path: &PathBuf| path.strip_prefix(dir).unwrap_or(path).display().to_string();
    let scripts: Vec<&PathBuf> = found
        .files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("js")))
        .collect();
    match scripts.as_slice() {
        [one] => Ok((*one).clone()),
        [] if found.files.is_empty() && !found.skipped.is_empty() => Err(format!(
            "only links or special files were submitted ({}), which are not graded: submit your {name} itself",
            list(found.skipped.iter().map(relative))
        )),
        [] if found.files.is_empty() => Err(format!(
            "nothing was submitted (files more than {DEPTH} folders deep are not looked at): submit your {name}"
        )),
        [] => {
            let found_files = list(found.files.iter().map(relative));
            // A file in a language the packages do not grade: said as such.
            let other = found.files.iter().find_map(|path| {
                Language::of_file(&path.file_name()?.to_string_lossy())
                    .filter(|&language| language != Language::JavaScript)
            });
            Err(match other {
                Some(language) => format!(
                    "a {} file was submitted ({found_files}), and this grader takes JavaScript \
                     only: {} files are graded on an estlab server, whose sandbox the \
                     platform's container does not allow; submit your {name}",
                    language.title(),
                    language.title()
                ),
                None => format!(
                    "no JavaScript file was submitted (found {found_files}): submit your {name}"
                ),
            })
        }
        several => {
            let named: Vec<&&PathBuf> = several
                .iter()
                .filter(|p| p.file_name().is_some_and(|n| n == name))
                .collect();
            match named.as_slice() {
                [one] => Ok((**one).clone()),
                _ => Err(format!(
                    "several JavaScript files were submitted ({}): submit only your {name}, or name the one to grade {name}",
                    list(several.iter().map(|p| relative(p)))
                )),
            }
        }
    }
}

/// More than `ENTRIES` entries were submitted.
struct TooMany;

/// What a walk of the submission found.
#[derive(Default)]
struct Found {
    /// Regular files.
    files: Vec<PathBuf>,
    /// Links, sockets, pipes and devices: never read.
    skipped: Vec<PathBuf>,
    /// Entries seen, of every kind.
    entries: usize,
}

impl Found {
    /// Walks `dir` depth first in name order, skipping hidden entries and `__MACOSX`;
    /// refuses a submission of more than `ENTRIES` entries.
    fn walk(&mut self, dir: &Path, depth: usize) -> Result<(), TooMany> {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return Ok(());
        };
        let mut entries: Vec<_> = entries.filter_map(Result::ok).collect();
        entries.sort_by_key(|e| e.file_name());
        for entry in entries {
            self.entries += 1;
            if self.entries > ENTRIES {
                return Err(TooMany);
            }
            let name = entry.file_name();
            let name = name.to_string_lossy();
            if name.starts_with('.') || name == "__MACOSX" {
                continue;
            }
            // The entry's own type: a link is a link, whatever it points to.
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            if kind.is_file() {
                self.files.push(entry.path());
            } else if kind.is_dir() {
                if depth < DEPTH {
                    self.walk(&entry.path(), depth + 1)?;
                }
            } else {
                self.skipped.push(entry.path());
            }
        }
        Ok(())
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
    use std::os::unix::ffi::OsStrExt;

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
        student_file(dir.path(), "ekf_localization.js")
            .map(|p| p.strip_prefix(dir.path()).unwrap().display().to_string())
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
    fn links_pipes_and_floods_are_not_graded() {
        use std::os::unix::fs::symlink;
        let grader = tempfile::tempdir().unwrap();
        let secret = grader.path().join("secret");
        std::fs::write(&secret, [7u8; 32]).unwrap();

        // A link named like the starter, to the grader's secret: not read.
        let dir = tempfile::tempdir().unwrap();
        symlink(&secret, dir.path().join("ekf_localization.js")).unwrap();
        let error = student_file(dir.path(), "ekf_localization.js").unwrap_err();
        assert!(
            error.contains("only links or special files were submitted (ekf_localization.js)"),
            "{error}"
        );
        // Beside a real file, the link is passed over.
        std::fs::write(dir.path().join("mine.js"), "x").unwrap();
        assert!(
            student_file(dir.path(), "ekf_localization.js")
                .unwrap()
                .ends_with("mine.js")
        );

        // A linked folder is not entered; a named pipe is not opened.
        let dir = tempfile::tempdir().unwrap();
        symlink(grader.path(), dir.path().join("lab")).unwrap();
        let fifo = dir.path().join("pipe.js");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success());
        let error = student_file(dir.path(), "ekf_localization.js").unwrap_err();
        assert!(error.contains("lab, pipe.js"), "{error}");

        // A name that is not UTF-8 is still listed.
        let dir = tempfile::tempdir().unwrap();
        let odd = std::ffi::OsStr::from_bytes(b"r\xe9sum\xe9.txt");
        std::fs::write(dir.path().join(odd), "x").unwrap();
        let error = student_file(dir.path(), "ekf_localization.js").unwrap_err();
        assert!(
            error.contains("no JavaScript file was submitted (found r"),
            "{error}"
        );

        // A flood of empty folders or files is refused without walking it all.
        let dir = tempfile::tempdir().unwrap();
        for i in 0..=ENTRIES {
            std::fs::create_dir(dir.path().join(format!("d{i:04}"))).unwrap();
        }
        std::fs::write(dir.path().join("ekf_localization.js"), "x").unwrap();
        let error = student_file(dir.path(), "ekf_localization.js").unwrap_err();
        assert!(
            error.contains("more than 1000 files and folders"),
            "{error}"
        );
    }

    #[test]
    fn a_file_in_another_language_is_named_as_such() {
        let error = pick(&["ekf_localization.m", "notes.txt"]).unwrap_err();
        assert!(
            error.starts_with(
                "a MATLAB file was submitted (ekf_localization.m, notes.txt), and this grader \
                 takes JavaScript only"
            ),
            "{error}"
        );
        let error = pick(&["lab/odometry.py"]).unwrap_err();
        assert!(error.starts_with("a Python file was submitted"), "{error}");
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
        assert!(
            deep.contains("nothing was submitted (files more than 4 folders deep"),
            "{deep}"
        );
    }
}
