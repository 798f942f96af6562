//! `estlab course`: setting up and running a course from the server's machine. Each
//! command works on the database in the data directory, also while the server runs.

use super::{file_name, print, read};
use crate::commands::serve::PUBLIC_URL;
use crate::courses::codes::{self, NewCode};
use crate::courses::deadline::{Counts, Policy, parse_moment, parse_penalty};
use crate::courses::export::{Format, inert};
use crate::courses::{check_course_name, ids, roster};
use crate::error::Error;
use crate::store::{Member, NewMember, Role, Store};
use jiff::{SignedDuration, Timestamp};
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
    /// The server's data directory.
    #[arg(
        long = "data",
        value_name = "DIR",
        default_value = "data",
        global = true
    )]
    data_dir: PathBuf,
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

/// How long a one-time staff link stays valid.
const STAFF_LINK: SignedDuration = SignedDuration::from_hours(7 * 24);

pub fn run(args: &Args) -> Result<(), Error> {
    let store = Store::open(&args.data_dir)?;
    let now = Timestamp::now();
    let url = || -> Result<String, Error> {
        Ok(match &args.url {
            Some(url) => url.trim_end_matches('/').to_string(),
            None => store
                .setting(PUBLIC_URL)?
                .unwrap_or_else(|| "http://127.0.0.1:8080".into()),
        })
    };
    match &args.command {
        Command::Create {
            course,
            title,
            instructor,
        } => {
            check_course_name(course).map_err(Error::Invalid)?;
            let created = store.create_course(course, title, now)?;
            store.audit(
                course,
                &actor(),
                "course",
                &format!("title {title:?}; sign-in link for {instructor}"),
                now,
            )?;
            let member = store.add_member(
                course,
                &NewMember {
                    login: instructor,
                    name: "",
                    email: instructor,
                    role: Role::Instructor,
                },
            )?;
            let link = staff_link(&store, &member, now, &url()?)?;
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
            let member = store.add_member(
                course,
                &NewMember {
                    login: email,
                    name,
                    email,
                    role,
                },
            )?;
            let link = staff_link(&store, &member, now, &url()?)?;
            store.audit(
                course,
                &actor(),
                "staff",
                &format!("{email} is {}; sign-in link", role.as_str()),
                now,
            )?;
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
        } => roster_command(
            &store,
            course,
            file.as_deref(),
            reissue,
            out.as_deref(),
            now,
            &url()?,
        ),
        Command::Assign {
            course,
            lab,
            due,
            late_penalty,
            cutoff,
            counts,
        } => {
            store.course(course)?;
            let cutoff = cutoff.unwrap_or(*due);
            if cutoff < *due {
                return Err(Error::Invalid(format!(
                    "--cutoff {cutoff} is before --due {due}: the cutoff is the last moment a late submission is taken"
                )));
            }
            let policy = Policy {
                due: *due,
                cutoff,
                penalty_per_day: *late_penalty,
                counts: *counts,
            };
            store.assign(course, lab.name(), &policy)?;
            store.audit(
                course,
                &actor(),
                "assign",
                &format!(
                    "{lab}: due {due}, cutoff {cutoff}, {:.0} %/day late, counts {}",
                    late_penalty * 100.0,
                    counts.as_str()
                ),
                now,
            )?;
            print(&format!(
                "{lab} is open in {course}: due {due}, taken until {cutoff}, {:.0} % off per day late, the {} submission counts.",
                late_penalty * 100.0,
                counts.as_str()
            ))
        }
        Command::Token {
            course,
            role,
            revoke,
        } => {
            store.course(course)?;
            if let Some(id) = revoke {
                return if store.revoke_token(course, *id, now)? {
                    store.audit(
                        course,
                        &actor(),
                        "token",
                        &format!("token {id} revoked"),
                        now,
                    )?;
                    print(&format!("Token {id} of {course} is revoked."))
                } else {
                    Err(Error::Invalid(format!(
                        "{course} has no token {id} (estlab course show {course} lists them)"
                    )))
                };
            }
            let role = Role::from(role.expect("clap requires --role without --revoke"));
            let (id, token) = store.create_token(course, role, now)?;
            store.audit(
                course,
                &actor(),
                "token",
                &format!("token {id} made ({})", role.as_str()),
                now,
            )?;
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
            let bytes = crate::courses::export::make(&store, course, lab.name(), *format)?.ok_or_else(|| {
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

fn staff_link(store: &Store, member: &Member, now: Timestamp, url: &str) -> Result<String, Error> {
    let code = codes::new_code();
    store.add_code(member.id, &code, true, Some(now + STAFF_LINK), now)?;
    Ok(link(url, &code))
}

/// A sign-in link: the code after '#', which the browser keeps to itself.
fn link(url: &str, code: &NewCode) -> String {
    format!("{url}/signin#{}", code.text)
}

fn roster_command(
    store: &Store,
    course: &str,
    file: Option<&Path>,
    reissue: &[String],
    out: Option<&Path>,
    now: Timestamp,
    url: &str,
) -> Result<(), Error> {
    store.course(course)?;
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
        let text = read(file)?;
        let on_roster: Vec<String> = store
            .members(course)?
            .into_iter()
            .filter(|m| !m.role.is_staff())
            .map(|m| m.login)
            .collect();
        let students = roster::read(&text, &on_roster)
            .map_err(|problem| Error::Invalid(format!("{}: {problem}", file.display())))?;
        let change = store.import_roster(course, &students)?;
        // Ids stored before the roster checked them may hold characters that reorder
        // or hide what is printed around them.
        let dropped = if change.dropped.is_empty() {
            String::new()
        } else {
            let shown: Vec<String> = change.dropped.iter().map(|id| ids::shown(id)).collect();
            format!(" ({})", shown.join(", "))
        };
        store.audit(
            course,
            &actor(),
            "roster",
            &format!(
                "{}: {} new, {} updated, {} dropped{dropped}",
                file_name(file),
                change.added.len(),
                change.updated,
                change.dropped.len(),
            ),
            now,
        )?;
        summary.push(format!(
            "{}: {} students; {} new, {} updated, {} unchanged, {} marked dropped{dropped}",
            file.display(),
            students.len(),
            change.added.len(),
            change.updated,
            change.unchanged,
            change.dropped.len(),
        ));
        needing.extend(change.added);
    }
    for id in reissue {
        let member = store.member(course, id)?;
        if member.role.is_staff() {
            return Err(Error::Invalid(format!(
                "{id} is {} of {course}: estlab course staff gives staff a new link",
                member.role.as_str()
            )));
        }
        if !needing.iter().any(|m| m.id == member.id) {
            needing.push(member);
        }
    }
    let mut csv = csv::Writer::from_writer(Vec::new());
    csv.write_record(["id", "name", "email", "code", "link"])
        .expect("writing to memory");
    for member in &needing {
        let code = codes::new_code();
        store.add_code(member.id, &code, false, None, now)?;
        if reissue.contains(&member.login) {
            store.audit(
                course,
                &actor(),
                "roster",
                &format!("new code for {}", ids::shown(&member.login)),
                now,
            )?;
        }
        csv.write_record([
            inert(&member.login),
            inert(&member.name),
            inert(&member.email),
            code.text.clone(),
            link(url, &code),
        ])
        .expect("writing to memory");
    }
    let bytes = csv.into_inner().expect("writing to memory");
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
        let submissions = store.course_submissions(course, &a.lab)?;
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
