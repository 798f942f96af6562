//! `estlab course`: setting up and running a course from the server's machine. Each
//! command works on the server's database (`--data`, `--database`), also while it runs.

use super::data::Data;
use super::{file_name, print, read};
use crate::courses::check_course_name;
use crate::courses::deadline::{Counts, Policy, parse_moment, parse_penalty};
use crate::courses::export::Format;
use crate::courses::questions;
use crate::courses::setup::{self, Setup};
use crate::error::Error;
use crate::store::{Member, Role, Store};
use jiff::Timestamp;
use labs::Exercise;
use std::io::Write;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// Set up and run a course: its staff, roster, assignments and API tokens.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
    #[command(flatten)]
    data: Data,
    /// The address people reach the server at, for sign-in links (default: the one the
    /// server last started with).
    #[arg(long, value_name = "URL", global = true)]
    url: Option<String>,
}

#[derive(clap::Subcommand)]
enum Command {
    /// Create a course (or give it a new title) and print a one-time sign-in link for
    /// its first instructor.
    Create {
        course: String,
        #[arg(long)]
        title: String,
        /// The instructor's email (their sign-in name).
        #[arg(long, default_value = "instructor")]
        instructor: String,
    },
    /// Add an instructor or assistant (or change their role) and print a one-time
    /// sign-in link for them.
    Staff {
        course: String,
        email: String,
        #[arg(long, value_enum)]
        role: StaffRole,
        #[arg(long, default_value = "")]
        name: String,
    },
    /// Import the roster (CSV with a header: id, name, email) and write each new
    /// student's sign-in code to a CSV for a mail merge; students missing from the file
    /// are marked dropped. With --reissue, give those students new codes.
    Roster {
        course: String,
        /// The roster; may be left out with --reissue.
        file: Option<PathBuf>,
        /// Give this student a new code (their old one stops working); repeatable.
        #[arg(long, value_name = "ID")]
        reissue: Vec<String>,
        /// Where the codes go (default: beside the roster, NAME-codes.csv); never
        /// overwritten, readable by you only.
        #[arg(long, value_name = "CODES.csv")]
        out: Option<PathBuf>,
    },
    /// Open an exercise for the course with its deadline and late policy.
    Assign {
        course: String,
        #[arg(value_parser = Exercise::from_str)]
        lab: Exercise,
        /// The due date, with its time zone: 2026-12-15T23:59+01:00.
        #[arg(long, value_parser = parse_moment)]
        due: Timestamp,
        /// The share of the score lost per day late, or part of a day: 10%/day.
        #[arg(long, value_parser = parse_penalty, default_value = "0%/day")]
        late_penalty: f64,
        /// The last moment a (late) submission is taken (default: the due date).
        #[arg(long, value_parser = parse_moment)]
        cutoff: Option<Timestamp>,
        /// Which submission's score counts.
        #[arg(long, value_enum, default_value_t = Counts::Best)]
        counts: Counts,
    },
    /// Give an exercise's assignment its written questions: question sets in TOML, in
    /// order (see DESIGN.md, "The written hand-in"), or with --own the exercise's own.
    Questions {
        course: String,
        #[arg(value_parser = Exercise::from_str)]
        lab: Exercise,
        /// The sets, one TOML file each.
        #[arg(required_unless_present = "own", conflicts_with = "own")]
        files: Vec<PathBuf>,
        /// The exercise's own sets again.
        #[arg(long)]
        own: bool,
    },
    /// Print an API token for scripts (shown once, stored hashed), or revoke one.
    Token {
        course: String,
        #[arg(long, value_enum, required_unless_present = "revoke")]
        role: Option<StaffRole>,
        /// Revoke the token of this id (estlab course show lists them).
        #[arg(long, value_name = "ID", conflicts_with = "role")]
        revoke: Option<i64>,
    },
    /// Export an exercise's grades, results or sources.
    Export {
        course: String,
        #[arg(value_parser = Exercise::from_str)]
        lab: Exercise,
        #[arg(long, value_enum)]
        format: Format,
        /// Where the export goes (a CSV, an XLSX or a zip); an existing file is not
        /// overwritten.
        #[arg(long, value_name = "PATH")]
        out: PathBuf,
    },
    /// List the courses.
    List,
    /// Print what a course has set up: staff, roster, assignments, tokens.
    Show { course: String },
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum StaffRole {
    Instructor,
    Assistant,
}

impl From<StaffRole> for Role {
    fn from(role: StaffRole) -> Role {
        match role {
            StaffRole::Instructor => Role::Instructor,
            StaffRole::Assistant => Role::Assistant,
        }
    }
}

/// Who acts, as the audit log names a command: the command line and the system user.
fn actor() -> String {
    let user = ["USER", "LOGNAME"]
        .iter()
        .find_map(|name| std::env::var(name).ok())
        // SAFETY: getuid has no preconditions and cannot fail.
        .unwrap_or_else(|| format!("uid {}", unsafe { libc::getuid() }));
    format!("command line ({user})")
}

impl From<setup::Error> for Error {
    fn from(error: setup::Error) -> Error {
        match error {
            setup::Error::Invalid(message) => Error::Invalid(message),
            setup::Error::Store(error) => Error::Store(error),
        }
    }
}

pub fn run(args: &Args) -> Result<(), Error> {
    let store = args.data.open()?;
    let actor = actor();
    let url = || -> Result<String, Error> {
        Ok(match &args.url {
            Some(url) => url.trim_end_matches('/').to_string(),
            None => setup::public_url(&store)?,
        })
    };
    let setup = |course| Setup {
        store: &store,
        course,
        actor: &actor,
        now: Timestamp::now(),
    };
    match &args.command {
        Command::Create {
            course,
            title,
            instructor,
        } => {
            check_course_name(course).map_err(Error::Invalid)?;
            let setup = setup(course);
            let created = store.create_course(course, title, setup.now)?;
            store.audit(
                course,
                &actor,
                "course",
                &format!("title {title:?}"),
                setup.now,
            )?;
            let link = setup.staff(instructor, "", Role::Instructor, &url()?)?;
            print(&format!(
                "{} course {course} ({title}).\nSign-in link for {instructor} (instructor; once, within 7 days):\n{link}",
                if created { "Created" } else { "Updated" }
            ))
        }
        Command::Staff {
            course,
            email,
            role,
            name,
        } => {
            store.course(course)?;
            let role = Role::from(*role);
            let link = setup(course).staff(email, name, role, &url()?)?;
            print(&format!(
                "{email} is {} of {course}.\nSign-in link (once, within 7 days):\n{link}",
                role.as_str()
            ))
        }
        Command::Roster {
            course,
            file,
            reissue,
            out,
        } => {
            store.course(course)?;
            roster_command(
                &setup(course),
                file.as_deref(),
                reissue,
                out.as_deref(),
                &url()?,
            )
        }
        Command::Assign {
            course,
            lab,
            due,
            late_penalty,
            cutoff,
            counts,
        } => {
            store.course(course)?;
            let policy = Policy {
                due: *due,
                cutoff: cutoff.unwrap_or(*due),
                penalty_per_day: *late_penalty,
                counts: *counts,
            };
            // The one rule assign checks: the cutoff comes after the due date.
            setup(course)
                .assign(*lab, &policy)
                .map_err(|error| match error {
                    setup::Error::Invalid(problem) => {
                        Error::Invalid(format!("--cutoff: {problem}"))
                    }
                    other => other.into(),
                })?;
            print(&format!(
                "{lab} is open in {course}: due {due}, taken until {}, {:.0} % off per day late, the {} submission counts.",
                policy.cutoff,
                late_penalty * 100.0,
                counts.as_str()
            ))
        }
        Command::Questions {
            course,
            lab,
            files,
            own,
        } => {
            store.course(course)?;
            let texts = if *own {
                None
            } else {
                let mut texts = Vec::with_capacity(files.len());
                for file in files {
                    let text = read(file)?;
                    // Read here first, so that a problem names its file.
                    questions::read(&text)
                        .map_err(|e| Error::Invalid(format!("{}: {e}", file.display())))?;
                    texts.push(text);
                }
                Some(texts)
            };
            let count = setup(course).set_questions(*lab, texts)?;
            print(&format!(
                "{lab} in {course} has {count} written questions{}.",
                if *own { ", the exercise's own" } else { "" }
            ))
        }
        Command::Token {
            course,
            role,
            revoke,
        } => {
            store.course(course)?;
            if let Some(id) = revoke {
                return if setup(course).revoke(*id)? {
                    print(&format!("Token {id} of {course} is revoked."))
                } else {
                    Err(Error::Invalid(format!(
                        "{course} has no token {id} (estlab course show {course} lists them)"
                    )))
                };
            }
            let role = Role::from(role.expect("clap requires --role without --revoke"));
            let (id, token) = setup(course).token(role)?;
            print(&format!(
                "API token {id} ({} of {course}); shown once, send it as `Authorization: Bearer TOKEN`:\n{token}",
                role.as_str()
            ))
        }
        Command::Export {
            course,
            lab,
            format,
            out,
        } => {
            store.course(course)?;
            if out.exists() {
                return Err(Error::Invalid(format!(
                    "{} exists already: name a new file with --out",
                    out.display()
                )));
            }
            let bytes = crate::courses::export::make(&store, course, *lab, *format)?.ok_or_else(|| {
                Error::Invalid(format!(
                    "{course} has not opened {lab} (estlab course assign {course} {lab} --due ...)"
                ))
            })?;
            std::fs::write(out, &bytes).map_err(Error::io(out))?;
            print(&format!(
                "{} ({} bytes) written",
                out.display(),
                bytes.len()
            ))
        }
        Command::List => {
            let courses = store.courses()?;
            if courses.is_empty() {
                return print("No course yet: estlab course create NAME --title TITLE makes one.");
            }
            let lines: Vec<String> = courses
                .iter()
                .map(|c| format!("{}\t{}", c.name, c.title))
                .collect();
            print(&lines.join("\n"))
        }
        Command::Show { course } => print(&show(&store, course)?),
    }
}

fn roster_command(
    setup: &Setup,
    file: Option<&Path>,
    reissue: &[String],
    out: Option<&Path>,
    url: &str,
) -> Result<(), Error> {
    let Some(out) = out
        .map(Path::to_path_buf)
        .or_else(|| file.map(codes_file_beside))
    else {
        return Err(Error::Invalid(
            "say where the new codes go with --out CODES.csv".into(),
        ));
    };
    if file.is_none() && reissue.is_empty() {
        return Err(Error::Invalid(
            "give a roster file, or --reissue ID for the students who need a new code".into(),
        ));
    }
    if out.exists() {
        return Err(Error::Invalid(format!(
            "{} exists already: codes are shown once, so name a new file with --out",
            out.display()
        )));
    }
    let mut summary = Vec::new();
    let mut needing: Vec<Member> = Vec::new();
    if let Some(file) = file {
        let plan = setup.import_roster(&file_name(file), &read(file)?)?;
        summary.push(format!("{}: {}", file.display(), plan.summary()));
        needing.extend(plan.change.added);
    }
    for member in setup.students(reissue)? {
        if !needing.iter().any(|m| m.id == member.id) {
            needing.push(member);
        }
    }
    let bytes = setup.codes(&needing, reissue, url, &mut |_| Ok(()))?;
    write_private(&out, &bytes)?;
    summary.push(format!(
        "{} sign-in code(s) written to {} (shown once: send them, then delete the file)",
        needing.len(),
        out.display()
    ));
    print(&summary.join("\n"))
}

fn codes_file_beside(roster: &Path) -> PathBuf {
    let stem = roster
        .file_stem()
        .map_or_else(|| "roster".into(), |s| s.to_string_lossy().into_owned());
    roster.with_file_name(format!("{stem}-codes.csv"))
}

/// Writes a new file readable by its owner only.
fn write_private(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let mut file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o600)
        .open(path)
        .map_err(Error::io(path))?;
    file.write_all(bytes).map_err(Error::io(path))
}

fn show(store: &Store, course: &str) -> Result<String, Error> {
    let found = store.course(course)?;
    let members = store.members(course)?;
    let mut lines = vec![format!("{} ({})", found.name, found.title)];
    lines.push("Staff:".into());
    for m in members.iter().filter(|m| m.role.is_staff()) {
        lines.push(format!("  {} ({})", m.login, m.role.as_str()));
    }
    let students: Vec<&Member> = members.iter().filter(|m| !m.role.is_staff()).collect();
    let dropped = students.iter().filter(|m| m.dropped).count();
    lines.push(format!(
        "Students: {} on the roster, {dropped} dropped",
        students.len() - dropped
    ));
    let assignments = store.assignments(course)?;
    lines.push("Assignments:".into());
    if assignments.is_empty() {
        lines.push("  none (estlab course assign)".into());
    }
    for a in &assignments {
        let submissions = store.course_submissions(course, a.lab)?;
        lines.push(format!(
            "  {}: due {}, cutoff {}, {:.0} %/day late, counts {}; {} submission(s)",
            a.lab,
            a.policy.due,
            a.policy.cutoff,
            a.policy.penalty_per_day * 100.0,
            a.policy.counts.as_str(),
            submissions.len()
        ));
    }
    let tokens = store.tokens(course)?;
    lines.push("API tokens:".into());
    if tokens.is_empty() {
        lines.push("  none".into());
    }
    for t in &tokens {
        lines.push(format!(
            "  {} ({}, made {}){}",
            t.id,
            t.role.as_str(),
            t.created_at,
            if t.revoked { ", revoked" } else { "" }
        ));
    }
    Ok(lines.join("\n"))
}
