//! Leases on gradings, so that several grader processes share one database's queue. A
//! grader claims a submission (or a regrade's item) for a while, renews the lease while it
//! grades, and writes the result only while it still holds it: a grader that died leaves
//! its work to another once the lease has run out, and a grader that lost its lease (it
//! stalled past it) has its result refused, so that a grading is written once. Which
//! grading comes next is each grader's choice (`grading::fair`); a claim by id is atomic
//! on both engines (an `UPDATE` whose condition the second claimant finds false), so two
//! graders choosing the same one cost one of them a wasted turn, never a double grading.
//! Lease times are milliseconds since 1970 by the graders' clocks, which are kept in step
//! (NTP) far closer than a lease's length.

use super::db::params;
use super::submissions::{Status, Unfinished};
use super::{Error, Store, ToGrade, known_exercises, named};
use jiff::Timestamp;
use labs::Language;
use std::collections::HashSet;
use std::time::Duration;

/// Who holds a lease: one grader process, as `host/space/pid/tag`: its machine's name, the
/// process ids it is numbered among (the machine's boot and its PID namespace: two
/// containers of one host name number their processes apart), its process id, and a
/// random tag that tells it from an earlier process of the same id.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Holder(String);

impl Holder {
    /// The name of this process, as a holder of leases.
    pub fn this_process() -> Holder {
        let mut tag = [0u8; 4];
        // Without the system's random source the tag is zero: the id and the host still
        // tell this process from every one running beside it.
        let _ = getrandom::fill(&mut tag);
        let tag: String = tag.iter().map(|b| format!("{b:02x}")).collect();
        Holder(format!("{}/{}/{tag}", process_space(), std::process::id()))
    }

    pub fn as_str(&self) -> &str {
        &self.0
    }

    /// A holder of the name `name`, for the tests.
    #[cfg(test)]
    pub(super) fn named(name: &str) -> Holder {
        Holder(name.into())
    }

    /// The process space (`host/space`) and the process id a holder's name gives.
    fn process(name: &str) -> Option<(&str, i32)> {
        let mut parts = name.rsplitn(3, '/');
        let (_tag, pid, space) = (parts.next()?, parts.next()?, parts.next()?);
        Some((space, pid.parse().ok()?))
    }
}

/// Where this process's id means this process: `host/boot.namespace`, this machine's name
/// (the kernel's, or `localhost`), the id of its boot and the inode of its PID namespace
/// (each `-` where it cannot be read).
fn process_space() -> String {
    let read = |path: &str| {
        std::fs::read_to_string(path)
            .map(|text| text.trim().to_owned())
            .ok()
            .filter(|text| !text.is_empty() && !text.contains('/'))
    };
    let host = read("/proc/sys/kernel/hostname").unwrap_or_else(|| "localhost".into());
    let boot = read("/proc/sys/kernel/random/boot_id").unwrap_or_else(|| "-".into());
    let namespace = std::fs::metadata("/proc/self/ns/pid")
        .map(|meta| std::os::unix::fs::MetadataExt::ino(&meta).to_string())
        .unwrap_or_else(|_| "-".into());
    format!("{host}/{boot}.{namespace}")
}

/// Whether a process of this machine is running.
fn is_running(pid: i32) -> bool {
    // SAFETY: signal 0 only checks that the process exists (and may be signalled).
    let sent = unsafe { libc::kill(pid, 0) };
    sent == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

pub(super) fn millis(at: Timestamp) -> i64 {
    at.as_millisecond()
}

/// A lease as it is taken or renewed: by whom, from when, for how long.
#[derive(Clone, Copy, Debug)]
pub struct Lease<'a> {
    pub holder: &'a Holder,
    pub from: Timestamp,
    pub length: Duration,
}

impl Lease<'_> {
    /// Its end, in milliseconds since 1970.
    pub(super) fn until(&self) -> i64 {
        millis(self.from).saturating_add(i64::try_from(self.length.as_millis()).unwrap_or(i64::MAX))
    }
}

/// A submission waiting to be graded, as a grader finds it.
#[derive(Debug, PartialEq)]
pub struct Claimable {
    pub submission: Unfinished,
    /// The grader the web process that took it grades with (none: taken before graders
    /// had leases, by this release or an earlier one).
    pub wanted_grader: Option<String>,
    pub language: Language,
}

impl Store {
    /// The submissions a grader may take at `now`: queued, or being graded under a lease
    /// that has run out; of the exercises this release grades; oldest first.
    pub fn claimable(&self, now: Timestamp) -> Result<Vec<Claimable>, Error> {
        Ok(self.connection().query_map(
            "SELECT id, course, student, wanted_grader, language FROM submissions
             WHERE status != 'graded' AND (status = 'queued' OR lease_until < ?2)
             AND lab IN (SELECT value FROM json_each(?1)) ORDER BY id",
            params![known_exercises(), millis(now)],
            |row| {
                Ok(Claimable {
                    submission: Unfinished {
                        id: row.get(0)?,
                        course: row.get(1)?,
                        student: row.get(2)?,
                    },
                    wanted_grader: row.get(3)?,
                    language: named(row, 4)?,
                })
            },
        )?)
    }

    /// Claims a submission under `lease`, marking it as being graded, and returns what
    /// grading needs; none when it is graded already or another grader holds it.
    pub fn claim_submission(&self, id: i64, lease: &Lease) -> Result<Option<ToGrade>, Error> {
        let claimed = self.connection().execute(
            "UPDATE submissions SET status = ?2, leased_by = ?3, lease_until = ?4
             WHERE id = ?1 AND (status = 'queued'
                OR (status = 'grading' AND (lease_until < ?5 OR leased_by = ?3)))",
            params![
                id,
                Status::Grading.as_str(),
                lease.holder.as_str(),
                lease.until(),
                millis(lease.from)
            ],
        )?;
        if claimed == 0 {
            return Ok(None);
        }
        self.to_grade(id).map(Some)
    }

    /// Claims a regrade's item under `lease`; false when it is done or another grader
    /// holds it.
    pub fn claim_regrade_item(
        &self,
        regrade: i64,
        submission: i64,
        lease: &Lease,
    ) -> Result<bool, Error> {
        let claimed = self.connection().execute(
            "UPDATE regrade_items SET leased_by = ?3, lease_until = ?4
             WHERE regrade = ?1 AND submission = ?2 AND done = 0
             AND (lease_until < ?5 OR leased_by = ?3)",
            params![
                regrade,
                submission,
                lease.holder.as_str(),
                lease.until(),
                millis(lease.from)
            ],
        )?;
        Ok(claimed == 1)
    }

    /// Renews a lease on a submission being graded; false when its holder lost it.
    pub fn renew_submission(&self, id: i64, lease: &Lease) -> Result<bool, Error> {
        let renewed = self.connection().execute(
            "UPDATE submissions SET lease_until = ?3
             WHERE id = ?1 AND leased_by = ?2 AND status = 'grading'",
            params![id, lease.holder.as_str(), lease.until()],
        )?;
        Ok(renewed == 1)
    }

    /// Renews a lease on a regrade's item; false when its holder lost it.
    pub fn renew_regrade_item(
        &self,
        regrade: i64,
        submission: i64,
        lease: &Lease,
    ) -> Result<bool, Error> {
        let renewed = self.connection().execute(
            "UPDATE regrade_items SET lease_until = ?4
             WHERE regrade = ?1 AND submission = ?2 AND leased_by = ?3 AND done = 0",
            params![regrade, submission, lease.holder.as_str(), lease.until()],
        )?;
        Ok(renewed == 1)
    }

    /// Ends the leases of graders of this machine (of this process space) that are no
    /// longer running, and of an earlier process of this one's id (a container's first
    /// process, started again): a grader or server killed here and started again takes its
    /// work back at once rather than after the lease. Returns how many holders ended. A
    /// holder whose process id another process has since taken keeps its lease until it
    /// runs out.
    pub fn end_leases_of_the_dead(&self, me: &Holder) -> Result<usize, Error> {
        let here = process_space();
        let my_pid = i32::try_from(std::process::id()).unwrap_or(-1);
        let holders: Vec<String> = self.connection().query_map(
            "SELECT leased_by FROM submissions WHERE status = 'grading' AND leased_by IS NOT NULL
             UNION SELECT leased_by FROM regrade_items WHERE done = 0 AND leased_by IS NOT NULL",
            (),
            |row| row.get(0),
        )?;
        let dead: Vec<&String> = holders
            .iter()
            .filter(|name| {
                Holder::process(name).is_some_and(|(space, pid)| {
                    space == here && (!is_running(pid) || (pid == my_pid && *name != me.as_str()))
                })
            })
            .collect();
        for name in &dead {
            self.transaction(|connection| {
                connection.execute(
                    "UPDATE submissions SET lease_until = 0 WHERE leased_by = ?1",
                    [name.as_str()],
                )?;
                connection.execute(
                    "UPDATE regrade_items SET lease_until = 0 WHERE leased_by = ?1",
                    [name.as_str()],
                )?;
                Ok(())
            })?;
        }
        Ok(dead.len())
    }
}

impl Store {
    /// Gives back a regrade's item whose sandbox did not start here, for any grader.
    pub fn release_regrade_item(
        &self,
        regrade: i64,
        submission: i64,
        holder: &Holder,
    ) -> Result<(), Error> {
        self.connection().execute(
            "UPDATE regrade_items SET leased_by = NULL, lease_until = 0
             WHERE regrade = ?1 AND submission = ?2 AND leased_by = ?3 AND done = 0",
            params![regrade, submission, holder.as_str()],
        )?;
        Ok(())
    }

    /// Says that `holder` runs, grading with the versions `versions` the files in
    /// `languages`, as of `now`; forgets graders not seen for a day.
    pub fn heartbeat(
        &self,
        holder: &Holder,
        (versions, languages): (&[&str], &[Language]),
        now: Timestamp,
    ) -> Result<(), Error> {
        let versions = serde_json::to_string(versions).expect("names serialise");
        let languages = serde_json::to_string(languages).expect("names serialise");
        let connection = self.connection();
        connection.execute(
            "INSERT INTO graders (holder, versions, languages, seen) VALUES (?1, ?2, ?3, ?4)
             ON CONFLICT (holder) DO UPDATE SET versions = excluded.versions,
             languages = excluded.languages, seen = excluded.seen",
            params![holder.as_str(), versions, languages, millis(now)],
        )?;
        connection.execute(
            "DELETE FROM graders WHERE seen < ?1",
            [millis(now) - 24 * 3600 * 1000],
        )?;
        Ok(())
    }

    /// The versions graders seen since `since` grade with.
    pub fn live_versions(&self, since: Timestamp) -> Result<HashSet<String>, Error> {
        self.of_live_graders("versions", since)
    }

    /// The languages whose files graders seen since `since` grade.
    pub fn live_languages(&self, since: Timestamp) -> Result<HashSet<Language>, Error> {
        self.of_live_graders("languages", since)
    }

    /// The union of a JSON array column of the graders seen since `since`.
    fn of_live_graders<T: serde::de::DeserializeOwned + Eq + std::hash::Hash>(
        &self,
        column: &str,
        since: Timestamp,
    ) -> Result<HashSet<T>, Error> {
        let lists: Vec<String> = self.connection().query_map(
            &format!("SELECT {column} FROM graders WHERE seen >= ?1"),
            [millis(since)],
            |row| row.get(0),
        )?;
        Ok(lists
            .iter()
            .filter_map(|list| serde_json::from_str::<Vec<T>>(list).ok())
            .flatten()
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store::{NewSubmission, test_store};
    use labs::grading::GradeResult;
    use labs::{Exercise, Language};

    fn submit(store: &Store, student: &str) -> i64 {
        store
            .insert(
                &NewSubmission {
                    course: "el2320",
                    student,
                    member: None,
                    lab: Exercise::Odometry,
                    seed: 3,
                    language: Language::JavaScript,
                    source: "// mine",
                    submitted_at: Timestamp::UNIX_EPOCH,
                    late_seconds: 0,
                    penalty: 0.0,
                    grader: "estlab test plan 0",
                },
                Timestamp::MAX,
            )
            .unwrap()
    }

    fn holder(name: &str) -> Holder {
        Holder::named(name)
    }

    use crate::store::test_lease as lease;

    fn result() -> GradeResult {
        GradeResult::not_gradable(Exercise::Odometry, 3, "a test's result")
    }

    /// One grader holds a submission until its lease runs out; the other's claim, renewal
    /// and result are refused meanwhile; after the lease, the other may take it, and then
    /// the first one's result is refused.
    #[test]
    fn a_lease_is_held_by_one_grader_and_taken_over_once_it_runs_out() {
        let dir = tempfile::tempdir().unwrap();
        let store = test_store(dir.path());
        let id = submit(&store, "ada");
        let (one, other) = (holder("a/1/x"), holder("b/1/y"));
        let t0 = Timestamp::from_second(1_000_000).unwrap();
        let waiting = store.claimable(t0).unwrap();
        assert_eq!(waiting.len(), 1);
        assert_eq!(
            waiting[0].wanted_grader.as_deref(),
            Some("estlab test plan 0")
        );

        let job = store.claim_submission(id, &lease(&one, t0)).unwrap();
        assert_eq!(job.unwrap().source, "// mine");
        assert!(store.claimable(t0).unwrap().is_empty());
        assert!(
            store
                .claim_submission(id, &lease(&other, t0))
                .unwrap()
                .is_none()
        );
        assert!(!store.renew_submission(id, &lease(&other, t0)).unwrap());
        assert!(matches!(
            store.finish_grading(id, &result(), None, &other),
            Err(Error::LeaseLost(_))
        ));

        // Renewed, it holds past its first end.
        let t1 = t0 + jiff::SignedDuration::from_secs(25);
        assert!(store.renew_submission(id, &lease(&one, t1)).unwrap());
        let t2 = t0 + jiff::SignedDuration::from_secs(40);
        assert!(store.claimable(t2).unwrap().is_empty());
        // Run out, another takes it, and the first one's late result is refused.
        let t3 = t1 + jiff::SignedDuration::from_secs(31);
        assert_eq!(store.claimable(t3).unwrap().len(), 1);
        assert!(
            store
                .claim_submission(id, &lease(&other, t3))
                .unwrap()
                .is_some()
        );
        assert!(matches!(
            store.finish_grading(id, &result(), None, &one),
            Err(Error::LeaseLost(_))
        ));
        store.finish_grading(id, &result(), None, &other).unwrap();
        // Written once: graded, nobody's to claim or write again.
        assert!(matches!(
            store.finish_grading(id, &result(), None, &other),
            Err(Error::LeaseLost(_))
        ));
        assert!(
            store
                .claim_submission(id, &lease(&one, t3))
                .unwrap()
                .is_none()
        );
        assert!(store.claimable(t3).unwrap().is_empty());
    }

    /// A grader whose sandbox did not start gives the submission back at once.
    #[test]
    fn a_submission_given_back_is_claimable_at_once() {
        let dir = tempfile::tempdir().unwrap();
        let store = test_store(dir.path());
        let id = submit(&store, "ada");
        let (one, other) = (holder("a/1/x"), holder("b/1/y"));
        let t0 = Timestamp::from_second(1_000_000).unwrap();
        store
            .claim_submission(id, &lease(&one, t0))
            .unwrap()
            .unwrap();
        store.back_to_queue(id, &other).unwrap();
        assert!(store.claimable(t0).unwrap().is_empty(), "not its to give");
        store.back_to_queue(id, &one).unwrap();
        assert_eq!(store.claimable(t0).unwrap().len(), 1);
        assert!(
            store
                .claim_submission(id, &lease(&other, t0))
                .unwrap()
                .is_some()
        );
    }

    /// Leases of a process of this machine that is not running, or of an earlier process
    /// of this one's id, end at once; those of a running one, or of another machine (or
    /// PID namespace), are kept.
    #[test]
    fn the_leases_of_a_dead_process_of_this_machine_end() {
        let dir = tempfile::tempdir().unwrap();
        let store = test_store(dir.path());
        let ids: Vec<i64> = ["ada", "grace", "alan", "barbara"]
            .iter()
            .map(|student| submit(&store, student))
            .collect();
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead_pid = child.id();
        child.wait().unwrap();
        let here = process_space();
        let me = Holder::this_process();
        let holders = [
            holder(&format!("{here}/{dead_pid}/x")),
            me.clone(),
            holder(&format!("elsewhere.{here}/{dead_pid}/x")),
            holder(&format!("{here}/{}/earlier", std::process::id())),
        ];
        let now = Timestamp::now();
        for (id, holder) in ids.iter().zip(&holders) {
            store
                .claim_submission(*id, &lease(holder, now))
                .unwrap()
                .unwrap();
        }
        assert_eq!(store.end_leases_of_the_dead(&me).unwrap(), 2);
        let free: Vec<i64> = store
            .claimable(now)
            .unwrap()
            .iter()
            .map(|c| c.submission.id)
            .collect();
        assert_eq!(free, [ids[0], ids[3]]);
    }

    /// A grader's versions count as running while it is seen, and a day after it was last
    /// seen it is forgotten.
    #[test]
    fn the_versions_of_graders_seen_lately_are_running() {
        let dir = tempfile::tempdir().unwrap();
        let store = test_store(dir.path());
        let t0 = Timestamp::from_second(1_800_000_000).unwrap();
        let minute = jiff::SignedDuration::from_mins(1);
        store
            .heartbeat(
                &holder("a/1/x"),
                (
                    &["estlab 1 plan a", "estlab 1 plan b"],
                    &[Language::JavaScript],
                ),
                t0,
            )
            .unwrap();
        store
            .heartbeat(
                &holder("b/1/y"),
                (&["estlab 2 plan a"], &[Language::Python]),
                t0 + minute,
            )
            .unwrap();
        let running = store.live_versions(t0 + minute).unwrap();
        assert_eq!(running, HashSet::from(["estlab 2 plan a".to_owned()]));
        assert_eq!(store.live_versions(t0).unwrap().len(), 3);
        let languages = store.live_languages(t0 + minute).unwrap();
        assert_eq!(languages, HashSet::from([Language::Python]));
        assert_eq!(store.live_languages(t0).unwrap().len(), 2);
        store
            .heartbeat(
                &holder("b/1/y"),
                (&["estlab 2 plan a"], &[Language::Python]),
                t0 + minute * (25 * 60),
            )
            .unwrap();
        let kept: i64 = store
            .connection()
            .query_row("SELECT count(*) FROM graders", (), |row| row.get(0))
            .unwrap();
        assert_eq!(kept, 1);
    }

    #[test]
    fn a_holder_names_its_host_and_process() {
        let me = Holder::this_process();
        let (space, pid) = Holder::process(me.as_str()).unwrap();
        assert_eq!(space, process_space());
        assert_eq!(pid as u32, std::process::id());
        assert!(is_running(pid));
        assert_eq!(Holder::process("a/b.c/12/ff"), Some(("a/b.c", 12)));
        assert_eq!(Holder::process("nonsense"), None);
    }
}
