//! `estlab grade`: grade one student file, as the server would.

use super::{print, read};
use crate::error::Error;
use crate::grading::{Secret, grader_version};
use crate::platforms::{GradescopeResults, PrairieLearnResults};
use crate::sandbox::{Code, JavaScript, Sandbox, check_size, cores};
use labs::grading::{DEFAULT_COURSE, GradeResult, student_seed};
use labs::{Exercise, Language};
use std::path::PathBuf;
use std::str::FromStr;

/// Grade a student's file (JavaScript, Python with NumPy, or MATLAB in GNU Octave) and
/// print the result. The exit code is 0 whenever a result was produced, whatever the score.
#[derive(clap::Args)]
pub struct Args {
    /// The exercise, by name.
    #[arg(long, value_parser = Exercise::from_str, default_value_t = Exercise::default())]
    lab: Exercise,
    /// The student's file: `.js` is JavaScript, `.py` Python and `.m` MATLAB, unless
    /// --language says.
    file: PathBuf,
    /// The file's language, when its name does not tell it.
    #[arg(long, value_parser = Language::from_str)]
    language: Option<Language>,
    /// The engine of students' JavaScript: V8 in the operating system's sandbox, on the
    /// whole data sets (QuickJS where that sandbox does not start), or QuickJS always,
    /// on their first readings, as the platform packages grade.
    #[arg(long, value_enum, default_value_t)]
    javascript: JavaScript,
    /// The seed of the student's variant (as the browser shows it).
    #[arg(long, conflicts_with = "student")]
    seed: Option<u64>,
    /// Or the student's id, whose variant within --course is graded.
    #[arg(long)]
    student: Option<String>,
    /// The course: the student's variant within it, and with --secret its class's
    /// held-out run (a package's course on a platform).
    #[arg(long, default_value = DEFAULT_COURSE)]
    course: String,
    /// A secret file (the server's `DATA/secret`, or a package's) to grade hidden cases
    /// as the server or the package does; without one only the shown cases are graded.
    #[arg(long)]
    secret: Option<PathBuf>,
    /// With --secret: the key that draws the hidden cases (a submission's id on the
    /// server; the `hidden_key` a package's results name).
    #[arg(long, requires = "secret", default_value_t = 0)]
    submission: i64,
    #[arg(long, value_enum, default_value_t = Format::Json)]
    format: Format,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum Format {
    /// The whole result, with every failing case in detail.
    Json,
    /// Gradescope's results.json.
    Gradescope,
    /// PrairieLearn's results.json.
    Prairielearn,
    /// The score and every test's message, for a person.
    Text,
}

pub fn run(args: &Args) -> Result<(), Error> {
    let source = read(&args.file)?;
    check_size(&source)
        .map_err(|problem| Error::Invalid(format!("{}: {problem}", args.file.display())))?;
    let name = args.file.file_name().unwrap_or_default().to_string_lossy();
    let language = args
        .language
        .or_else(|| Language::of_file(&name))
        .unwrap_or_default();
    let seed = match (&args.seed, &args.student) {
        (Some(seed), _) => *seed,
        (None, Some(student)) => student_seed(&args.course, student),
        (None, None) => 1,
    };
    let secret = args.secret.as_deref().map(Secret::read).transpose()?;
    let sandbox = Sandbox::current(cores())
        .map_err(Error::io("the estlab executable"))?
        .with_javascript(args.javascript);
    let grader = grader_version(
        args.lab,
        secret.as_ref(),
        sandbox.reach(Language::JavaScript),
    );
    // Without a secret there are no hidden cases: the result says so.
    let key = secret.is_some().then_some(args.submission);
    let hidden = secret.map(|secret| secret.hidden(args.submission, &args.course));
    let code = Code {
        language,
        text: &source,
    };
    let result = sandbox.grade(args.lab, code, seed, hidden);
    let text = match args.format {
        Format::Json => serde_json::to_string_pretty(&result),
        Format::Gradescope => {
            serde_json::to_string_pretty(&GradescopeResults::of(&result, &grader, key))
        }
        Format::Prairielearn => {
            serde_json::to_string_pretty(&PrairieLearnResults::of(&result, &grader, key))
        }
        Format::Text => Ok(result
            .tests
            .iter()
            .map(|t| {
                format!(
                    "\n{} [{}/{}]\n{}",
                    t.name, t.points, t.max_points, t.message
                )
            })
            .fold(
                if result.hidden_cases {
                    result.summary()
                } else {
                    format!(
                        "{}\n{}",
                        result.summary(),
                        GradeResult::shown_only(args.lab)
                    )
                },
                |text, test| text + "\n" + &test,
            )),
    }
    .expect("results serialise");
    print(&text)
}
