//! `estlab grade-class`: a class's files, collected elsewhere (an LMS download: a folder
//! with one file per student, named by the student's id), graded as the server grades
//! them, each with that student's variant.

use super::grading::default_parallel;
use super::{file_name, print};
use crate::courses::export::inert;
use crate::error::Error;
use crate::sandbox::{Code, JavaScript, Sandbox, check_size, cores};
use indicatif::{ProgressBar, ProgressStyle};
use labs::grading::{DEFAULT_COURSE, GradeResult, student_seed};
use labs::{Exercise, Language};
use std::collections::HashMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Grade every student's file in a folder and write a CSV of the grades, with one JSON
/// result per student beside it.
#[derive(clap::Args)]
pub struct Args {
    /// The folder: one file per student, named by the student's id and its language's
    /// extension (u123.js, u124.py, u125.m).
    dir: PathBuf,
    /// The exercise; for now the EKF localization exercise.
    #[arg(long, value_parser = Exercise::from_str, default_value_t = Exercise::default())]
    lab: Exercise,
    /// The course, whose students' variants are graded.
    #[arg(long, default_value = DEFAULT_COURSE)]
    course: String,
    /// The grades; the JSON results go to a folder of the same name without `.csv`.
    #[arg(long, default_value = "grades.csv")]
    out: PathBuf,
    /// Files graded at once (each in a worker process of its own).
    #[arg(long, default_value_t = default_parallel())]
    parallel: usize,
    /// The engine of students' JavaScript: V8 in the operating system's sandbox, on the
    /// whole data sets (QuickJS where that sandbox does not start), or QuickJS always,
    /// on their first readings, as the platform packages grade.
    #[arg(long, value_enum, default_value_t)]
    javascript: JavaScript,
}

/// One student's file.
struct Entry {
    id: String,
    path: PathBuf,
    /// Why the file was not graded, when it was not (a second file of the same id).
    refused: Option<String>,
}

/// What became of one file.
enum Outcome {
    Graded(GradeResult),
    /// Never graded: not text, too large, or not the only file of its student.
    Unreadable(String),
}

struct Row {
    id: String,
    file: String,
    outcome: Outcome,
}

/// The student files of a folder, by name: every visible regular file, its id the name
/// without the extension.
fn entries(dir: &Path) -> Result<Vec<Entry>, Error> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(Error::io(dir))?
        .filter_map(Result::ok)
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .map(|e| e.path())
        .filter(|p| !file_name(p).starts_with('.'))
        .collect();
    paths.sort();
    let id = |p: &Path| {
        p.file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
    };
    let mut count: HashMap<String, Vec<String>> = HashMap::new();
    for path in &paths {
        count.entry(id(path)).or_default().push(file_name(path));
    }
    Ok(paths
        .iter()
        .map(|path| {
            let files = &count[&id(path)];
            Entry {
                id: id(path),
                path: path.clone(),
                refused: (files.len() > 1).then(|| {
                    format!(
                        "more than one file for this student ({}): keep one",
                        files.join(", ")
                    )
                }),
            }
        })
        .collect())
}

fn grade_one(sandbox: &Sandbox, exercise: Exercise, course: &str, entry: &Entry) -> Outcome {
    if let Some(reason) = &entry.refused {
        return Outcome::Unreadable(reason.clone());
    }
    let bytes = match std::fs::read(&entry.path) {
        Ok(bytes) => bytes,
        Err(e) => return Outcome::Unreadable(format!("unreadable: {e}")),
    };
    let Ok(source) = String::from_utf8(bytes) else {
        return Outcome::Unreadable(
            "not UTF-8 text (a binary file, or another encoding): save it as UTF-8".into(),
        );
    };
    if let Err(problem) = check_size(&source) {
        return Outcome::Unreadable(problem.to_string());
    }
    // The language by the file's extension: JavaScript unless it says another.
    let language = Language::of_file(&file_name(&entry.path)).unwrap_or_default();
    Outcome::Graded(sandbox.grade(
        exercise,
        Code {
            language,
            text: &source,
        },
        student_seed(course, &entry.id),
        None,
    ))
}

/// Shows the progress: a bar with the count, the rate and the time left on a terminal,
/// a plain line per file otherwise.
enum Progress {
    Bar(ProgressBar),
    Lines { total: usize, done: AtomicUsize },
}

impl Progress {
    fn new(total: usize) -> Progress {
        if std::io::stderr().is_terminal() {
            let bar = ProgressBar::new(total as u64);
            bar.set_style(
                ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} files, {per_sec}, {eta} left {msg}",
                )
                .expect("a valid template"),
            );
            Progress::Bar(bar)
        } else {
            Progress::Lines {
                total,
                done: AtomicUsize::new(0),
            }
        }
    }

    fn graded(&self, row: &Row) {
        match self {
            Progress::Bar(bar) => {
                bar.set_message(row.id.clone());
                bar.inc(1);
            }
            Progress::Lines { total, done } => {
                let done = done.fetch_add(1, Ordering::Relaxed) + 1;
                eprintln!("[{done}/{total}] {}: {}", row.id, describe(&row.outcome));
            }
        }
    }

    fn finish(&self) {
        if let Progress::Bar(bar) = self {
            bar.finish_and_clear();
        }
    }
}

fn describe(outcome: &Outcome) -> String {
    match outcome {
        Outcome::Graded(result) => result.summary(),
        Outcome::Unreadable(reason) => format!("not graded: {reason}"),
    }
}

pub fn run(args: &Args) -> Result<(), Error> {
    let entries = entries(&args.dir)?;
    if entries.is_empty() {
        return Err(Error::Invalid(format!(
            "{} holds no student file",
            args.dir.display()
        )));
    }
    let parallel = args.parallel.clamp(1, cores());
    let sandbox = Sandbox::current(cores() / parallel)
        .map_err(Error::io("the estlab executable"))?
        .with_javascript(args.javascript);
    let started = Instant::now();
    let progress = Progress::new(entries.len());
    let next = AtomicUsize::new(0);
    let rows: Mutex<Vec<Option<Row>>> = Mutex::new(entries.iter().map(|_| None).collect());
    std::thread::scope(|scope| {
        for _ in 0..parallel.min(entries.len()) {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(entry) = entries.get(i) else { break };
                    let row = Row {
                        id: entry.id.clone(),
                        file: file_name(&entry.path),
                        outcome: grade_one(&sandbox, args.lab, &args.course, entry),
                    };
                    progress.graded(&row);
                    rows.lock().unwrap_or_else(|e| e.into_inner())[i] = Some(row);
                }
            });
        }
    });
    progress.finish();
    let rows: Vec<Row> = rows
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_iter()
        .map(|row| row.expect("every file graded"))
        .collect();
    let results_dir = args.out.with_extension("");
    write_results(&rows, &results_dir, args.lab, &args.course)?;
    write_csv(&rows, &args.out)?;
    print(&summary(
        &rows,
        args.lab,
        &args.out,
        &results_dir,
        started.elapsed().as_secs_f64(),
    ))
}

/// `ID.json` per student: the whole result, as `estlab grade` prints it.
fn write_results(rows: &[Row], dir: &Path, exercise: Exercise, course: &str) -> Result<(), Error> {
    std::fs::create_dir_all(dir).map_err(Error::io(dir))?;
    for row in rows {
        let result = match &row.outcome {
            Outcome::Graded(result) => result.clone(),
            Outcome::Unreadable(reason) => {
                GradeResult::not_gradable(exercise, student_seed(course, &row.id), reason)
            }
        };
        let path = dir.join(format!("{}.json", row.id));
        let text = serde_json::to_string_pretty(&result).expect("results serialise");
        std::fs::write(&path, text).map_err(Error::io(&path))?;
    }
    Ok(())
}

/// The grades: a row per file, a column per test with its points.
fn write_csv(rows: &[Row], path: &Path) -> Result<(), Error> {
    let mut tests: Vec<&str> = Vec::new();
    for row in rows {
        if let Outcome::Graded(result) = &row.outcome {
            for test in &result.tests {
                if !tests.contains(&test.name.as_str()) {
                    tests.push(&test.name);
                }
            }
        }
    }
    let mut csv = csv::Writer::from_path(path)
        .map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))?;
    let mut header = vec![
        "id",
        "file",
        "status",
        "score",
        "points",
        "max_points",
        "reason",
    ];
    header.extend(&tests);
    let failed = |e: csv::Error| Error::Invalid(format!("{}: {e}", path.display()));
    csv.write_record(&header).map_err(failed)?;
    for row in rows {
        let mut record = vec![inert(&row.id), inert(&row.file)];
        match &row.outcome {
            Outcome::Graded(result) if result.gradable => {
                record.extend([
                    "graded".into(),
                    format!("{:.4}", result.score),
                    format!("{}", result.points),
                    format!("{}", result.max_points),
                    String::new(),
                ]);
                record.extend(tests.iter().map(|name| {
                    result
                        .tests
                        .iter()
                        .find(|t| t.name == *name)
                        .map_or_else(String::new, |t| format!("{}", t.points))
                }));
            }
            Outcome::Graded(result) => record.extend([
                "not gradable".into(),
                String::new(),
                String::new(),
                String::new(),
                result.reason.clone().unwrap_or_default(),
            ]),
            Outcome::Unreadable(reason) => record.extend([
                "not graded".into(),
                String::new(),
                String::new(),
                String::new(),
                reason.clone(),
            ]),
        }
        record.resize(header.len(), String::new());
        csv.write_record(&record).map_err(failed)?;
    }
    csv.flush().map_err(Error::io(path))
}

fn summary(rows: &[Row], exercise: Exercise, csv: &Path, results: &Path, seconds: f64) -> String {
    let scores: Vec<f64> = rows
        .iter()
        .filter_map(|row| match &row.outcome {
            Outcome::Graded(result) if result.gradable => Some(result.score),
            _ => None,
        })
        .collect();
    let not_gradable = rows
        .iter()
        .filter(|row| matches!(&row.outcome, Outcome::Graded(result) if !result.gradable))
        .count();
    let not_graded = rows.len() - scores.len() - not_gradable;
    let mean = if scores.is_empty() {
        "no score".to_string()
    } else {
        format!(
            "mean score {:.3}",
            scores.iter().sum::<f64>() / scores.len() as f64
        )
    };
    format!(
        "{} files: {} graded ({mean}), {not_gradable} not gradable, {not_graded} not graded\n\
         {} and {}/ID.json written; {seconds:.1} s, {:.2} files per second\n{}",
        rows.len(),
        scores.len(),
        csv.display(),
        results.display(),
        rows.len() as f64 / seconds.max(1e-9),
        GradeResult::shown_only(exercise)
    )
}
