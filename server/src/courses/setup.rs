//! Setting a course up, the same from the command line (`estlab course`) and from the
//! web (the course's page, for its instructors): the staff and their one-time links, the
//! roster (previewed, then imported) and the students' sign-in codes, the exercises
//! opened with their dates and policies, and the API tokens. Every change is written to
//! the course's audit log with who made it.

use super::codes::{self, NewCode};
use super::deadline::Policy;
use super::export::inert;
use super::ids;
use super::questions;
use super::roster;
use crate::store::{self, Member, NewMember, Role, RosterChange, Store};
use jiff::{SignedDuration, Timestamp};
use labs::Exercise;

/// What setting a course up can fail with.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Input to correct; the message names what is wrong (a roster's line, a field).
    #[error("{0}")]
    Invalid(String),
    #[error(transparent)]
    Store(#[from] store::Error),
}

/// How long a one-time staff link stays valid.
pub const STAFF_LINK: SignedDuration = SignedDuration::from_hours(7 * 24);

/// The longest email address there is (RFC 5321's path limit).
const MAX_EMAIL: usize = 254;

/// The columns of a codes file, one student a line, for a mail merge.
const CODES_HEADER: [&str; 5] = ["id", "name", "email", "code", "link"];

/// The setting under which the server records its public address, for sign-in links
/// made while it runs or by `estlab course`.
pub const PUBLIC_URL: &str = "public_url";

/// The address people reach the server at, as it last started (`estlab serve`'s).
pub fn public_url(store: &Store) -> Result<String, store::Error> {
    Ok(store
        .setting(PUBLIC_URL)?
        .unwrap_or_else(|| "http://127.0.0.1:8080".into()))
}

/// A sign-in link: the code after '#', which the browser keeps to itself.
pub fn link(url: &str, code: &NewCode) -> String {
    format!("{url}/signin#{}", code.text)
}

/// One person's changes to one course, at one moment: `actor` is how the audit log
/// names them (an email, an API token, the command line's user).
pub struct Setup<'a> {
    pub store: &'a Store,
    pub course: &'a str,
    pub actor: &'a str,
    pub now: Timestamp,
}

/// A roster read and compared with the course's: what importing it adds, updates and
/// drops (`change`), before or after it was applied.
pub struct RosterPlan {
    pub students: usize,
    pub change: RosterChange,
}

impl RosterPlan {
    /// The change in a line: `3 new, 1 updated, 0 unchanged, 2 marked dropped (a, b)`.
    pub fn summary(&self) -> String {
        let change = &self.change;
        format!(
            "{} students; {} new, {} updated, {} unchanged, {} marked dropped{}",
            self.students,
            change.added.len(),
            change.updated.len(),
            change.unchanged,
            change.dropped.len(),
            listed(&change.dropped),
        )
    }
}

/// ` (a, b)` for the ids given, shown safely; nothing for none.
fn listed(logins: &[String]) -> String {
    if logins.is_empty() {
        return String::new();
    }
    // Ids stored before the roster checked them may hold characters that reorder or
    // hide what is printed around them.
    let shown: Vec<String> = logins.iter().map(|id| ids::shown(id)).collect();
    format!(" ({})", shown.join(", "))
}

impl Setup<'_> {
    pub(super) fn audit(&self, kind: &str, detail: &str) -> Result<(), Error> {
        Ok(self
            .store
            .audit(self.course, self.actor, kind, detail, self.now)?)
    }

    /// Adds an instructor or assistant (or changes their role and name) and gives them a
    /// new one-time sign-in link, valid for `STAFF_LINK`.
    pub fn staff(&self, email: &str, name: &str, role: Role, url: &str) -> Result<String, Error> {
        if !role.is_staff() {
            return Err(Error::Invalid(
                "staff are instructors or assistants; students come from the roster".into(),
            ));
        }
        let email = ids::normalise_text(email.trim());
        let name = ids::normalise_text(name.trim());
        if email.is_empty() || email.chars().count() > MAX_EMAIL {
            return Err(Error::Invalid(format!(
                "the email: staff sign in with theirs, of 1 to {MAX_EMAIL} characters"
            )));
        }
        for (what, text) in [("email", &email), ("name", &name)] {
            if let Some(problem) = ids::text_problem(text) {
                return Err(Error::Invalid(format!("the {what} {text:?} {problem}")));
            }
        }
        let member = self.store.add_member(
            self.course,
            &NewMember {
                login: &email,
                name: &name,
                email: &email,
                role,
            },
        )?;
        let code = codes::new_code();
        self.store.add_code(
            member.id,
            &code,
            true,
            Some(self.now + STAFF_LINK),
            self.now,
        )?;
        self.audit(
            "staff",
            &format!("{email} is {}; sign-in link", role.as_str()),
        )?;
        Ok(link(url, &code))
    }

    /// Reads a roster (`file` names it in messages) and works out what importing it
    /// would change, changing nothing.
    pub fn preview_roster(&self, file: &str, text: &str) -> Result<RosterPlan, Error> {
        let students = self.read_roster(file, text)?;
        Ok(RosterPlan {
            students: students.len(),
            change: self.store.preview_roster(self.course, &students)?,
        })
    }

    /// Imports a roster (`file` names it in messages and the audit log): the new students
    /// are added (they need codes: `codes`), known ones updated, those missing marked
    /// dropped.
    pub fn import_roster(&self, file: &str, text: &str) -> Result<RosterPlan, Error> {
        let students = self.read_roster(file, text)?;
        let change = self.store.import_roster(self.course, &students)?;
        self.audit(
            "roster",
            &format!(
                "{file}: {} new, {} updated, {} dropped{}",
                change.added.len(),
                change.updated.len(),
                change.dropped.len(),
                listed(&change.dropped),
            ),
        )?;
        Ok(RosterPlan {
            students: students.len(),
            change,
        })
    }

    fn read_roster(&self, file: &str, text: &str) -> Result<Vec<roster::Student>, Error> {
        let on_roster: Vec<String> = self
            .store
            .members(self.course)?
            .into_iter()
            .filter(|m| !m.role.is_staff())
            .map(|m| m.login)
            .collect();
        roster::read(text, &on_roster)
            .map_err(|problem| Error::Invalid(format!("{file}: {problem}")))
    }

    /// The students of these ids, for new codes; a member of staff is refused (their
    /// link comes with `staff`).
    pub fn students(&self, logins: &[String]) -> Result<Vec<Member>, Error> {
        logins
            .iter()
            .map(|login| {
                let member = self.store.member(self.course, login)?;
                if member.role.is_staff() {
                    return Err(Error::Invalid(format!(
                        "{} is {} of {}: staff get a new sign-in link, not a code",
                        ids::shown(login),
                        member.role.as_str(),
                        self.course
                    )));
                }
                Ok(member)
            })
            .collect()
    }

    /// New sign-in codes for these students (their earlier codes stop working), as the
    /// CSV a mail merge reads: id, name, email, code, link. The codes are stored hashed
    /// only: this is the one time they can be read. `reissued` students are named in the
    /// audit log (new students' codes are part of their import). `made` is told how many
    /// are made after each, and may stop the making with an error.
    pub fn codes(
        &self,
        students: &[Member],
        reissued: &[String],
        url: &str,
        made: &mut dyn FnMut(usize) -> Result<(), Error>,
    ) -> Result<Vec<u8>, Error> {
        let mut csv = csv::Writer::from_writer(Vec::new());
        csv.write_record(CODES_HEADER).expect("writing to memory");
        for (done, member) in students.iter().enumerate() {
            made(done)?;
            let code = codes::new_code();
            self.store
                .add_code(member.id, &code, false, None, self.now)?;
            if reissued.contains(&member.login) {
                self.audit(
                    "roster",
                    &format!("new code for {}", ids::shown(&member.login)),
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
        Ok(csv.into_inner().expect("writing to memory"))
    }

    /// Opens an exercise (or changes its dates and policy); the cutoff may not come
    /// before the due date.
    pub fn assign(&self, exercise: Exercise, policy: &Policy) -> Result<(), Error> {
        if policy.cutoff < policy.due {
            return Err(Error::Invalid(format!(
                "the cutoff {} is before the due date {}: the cutoff is the last moment a late submission is taken",
                policy.cutoff, policy.due
            )));
        }
        self.store.assign(self.course, exercise, policy)?;
        self.audit(
            "assign",
            &format!(
                "{exercise}: due {}, cutoff {}, {:.0} %/day late, counts {}",
                policy.due,
                policy.cutoff,
                policy.penalty_per_day * 100.0,
                policy.counts.as_str()
            ),
        )
    }

    /// Gives an exercise's assignment the question sets `texts` (TOML, in order; `None`:
    /// the exercise's own), each read and checked first; how many questions it then has.
    pub fn set_questions(
        &self,
        exercise: Exercise,
        texts: Option<Vec<String>>,
    ) -> Result<usize, Error> {
        let sets = match &texts {
            Some(texts) => questions::read_all(texts),
            None => questions::read_all(&questions::own(exercise)),
        }
        .map_err(Error::Invalid)?;
        if !self
            .store
            .set_questions(self.course, exercise, texts.as_deref())?
        {
            return Err(Error::Invalid(format!(
                "{} has not opened {exercise}: open it first",
                self.course
            )));
        }
        let count = sets.iter().map(|s| s.questions.len()).sum();
        let titles: Vec<&str> = sets.iter().map(|s| s.title.as_str()).collect();
        self.audit(
            "questions",
            &format!(
                "{exercise}: {} ({count} questions{})",
                inert(&titles.join("; ")),
                if texts.is_none() {
                    ", the exercise's own"
                } else {
                    ""
                }
            ),
        )?;
        Ok(count)
    }

    /// A new API token of a staff role: its id and the token, shown this once.
    pub fn token(&self, role: Role) -> Result<(i64, String), Error> {
        if !role.is_staff() {
            return Err(Error::Invalid(
                "API tokens are for staff: the role is instructor or assistant".into(),
            ));
        }
        let (id, token) = self.store.create_token(self.course, role, self.now)?;
        self.audit("token", &format!("token {id} made ({})", role.as_str()))?;
        Ok((id, token))
    }

    /// Revokes a token of the course; false when the course has no token of that id.
    pub fn revoke(&self, id: i64) -> Result<bool, Error> {
        let revoked = self.store.revoke_token(self.course, id, self.now)?;
        if revoked {
            self.audit("token", &format!("token {id} revoked"))?;
        }
        Ok(revoked)
    }
}
