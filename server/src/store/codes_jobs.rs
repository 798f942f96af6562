//! Sign-in codes made in the background: a roster's new students' codes, or new codes for
//! students who lost theirs. Each code is stored hashed with Argon2id (about 0.1 s of CPU
//! each), so a large class's take minutes, longer than a request may: a job of the web
//! process that was asked makes them under its lease (`leases`), counts how many it has
//! made, and keeps the codes file until the instructor has fetched it once.

use super::db::{OptionalExtension, params};
use super::leases::{Holder, Lease, millis};
use super::{Error, Store};
use jiff::Timestamp;

/// A job of codes as its instructor sees it.
#[derive(Debug, PartialEq)]
pub struct CodesJob {
    pub total: usize,
    pub done: usize,
    /// The codes file (as the web layer wrote it), this once: when the job has ended and
    /// it was not fetched before.
    pub file: Option<String>,
    /// Fetched before: its codes are not shown again.
    pub fetched: bool,
    /// Why it stopped before its end.
    pub failed: Option<String>,
}

impl Store {
    /// A new job of `total` codes for `course`, leased to the process that makes them.
    pub fn start_codes_job(&self, course: &str, total: usize, lease: &Lease) -> Result<i64, Error> {
        Ok(self.connection().query_row(
            "INSERT INTO codes_jobs (course, total, leased_by, lease_until)
             VALUES (?1, ?2, ?3, ?4) RETURNING id",
            params![course, total as i64, lease.holder.as_str(), lease.until()],
            |row| row.get(0),
        )?)
    }

    /// Says that `done` codes of job `id` are made, and renews its lease; false when the
    /// lease was lost (the job is then said to have failed: the maker stops).
    pub fn codes_job_made(&self, id: i64, done: usize, lease: &Lease) -> Result<bool, Error> {
        let changed = self.connection().execute(
            "UPDATE codes_jobs SET done = ?2, lease_until = ?3
             WHERE id = ?1 AND leased_by = ?4 AND failed IS NULL",
            params![id, done as i64, lease.until(), lease.holder.as_str()],
        )?;
        Ok(changed == 1)
    }

    /// Ends job `id`: its codes file, or why it stopped.
    pub fn end_codes_job(
        &self,
        id: i64,
        ended: Result<&str, &str>,
        holder: &Holder,
    ) -> Result<(), Error> {
        let (file, failed) = match ended {
            Ok(file) => (Some(file), None),
            Err(why) => (None, Some(why)),
        };
        self.connection().execute(
            "UPDATE codes_jobs SET file = ?2, failed = ?3, leased_by = NULL, lease_until = 0,
             done = CASE WHEN CAST(?2 AS TEXT) IS NULL THEN done ELSE total END
             WHERE id = ?1 AND leased_by = ?4 AND failed IS NULL",
            params![id, file, failed, holder.as_str()],
        )?;
        Ok(())
    }

    /// Job `id` of `course` as of `now`, its codes file handed over this once (and then
    /// forgotten); a job whose maker's lease ran out has failed. None: no such job there.
    pub fn take_codes_job(
        &self,
        course: &str,
        id: i64,
        now: Timestamp,
    ) -> Result<Option<CodesJob>, Error> {
        self.transaction(|transaction| {
            transaction.execute(
                "UPDATE codes_jobs SET failed = 'the server stopped while it made the codes: give the students without one new codes'
                 WHERE id = ?1 AND course = ?2 AND leased_by IS NOT NULL AND lease_until < ?3
                 AND failed IS NULL",
                params![id, course, millis(now)],
            )?;
            let job = transaction
                .query_row(
                    "SELECT total, done, file, fetched, failed FROM codes_jobs
                     WHERE id = ?1 AND course = ?2",
                    params![id, course],
                    |row| {
                        Ok(CodesJob {
                            total: row.get::<_, i64>(0)? as usize,
                            done: row.get::<_, i64>(1)? as usize,
                            file: row.get(2)?,
                            fetched: row.get::<_, i64>(3)? != 0,
                            failed: row.get(4)?,
                        })
                    },
                )
                .optional()?;
            if job.as_ref().is_some_and(|job| job.file.is_some()) {
                transaction.execute(
                    "UPDATE codes_jobs SET file = NULL, fetched = 1 WHERE id = ?1",
                    params![id],
                )?;
            }
            Ok(job)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store::test_lease as lease;

    /// A store with a course, and a job of 3 codes of it leased to this process at `now`.
    fn a_job(dir: &std::path::Path, now: Timestamp) -> (Store, Holder, i64) {
        let store = super::super::test_store(dir);
        store
            .create_course("el2320", "Applied Estimation", now)
            .unwrap();
        let me = Holder::this_process();
        let id = store
            .start_codes_job("el2320", 3, &lease(&me, now))
            .unwrap();
        (store, me, id)
    }

    #[test]
    fn the_codes_file_is_handed_over_once() {
        let dir = tempfile::tempdir().unwrap();
        let now = Timestamp::from_second(1_800_000_000).unwrap();
        let (store, me, id) = a_job(dir.path(), now);
        assert!(store.codes_job_made(id, 2, &lease(&me, now)).unwrap());
        let making = store.take_codes_job("el2320", id, now).unwrap().unwrap();
        assert_eq!((making.total, making.done, making.file), (3, 2, None));
        assert_eq!(store.take_codes_job("other", id, now).unwrap(), None);
        store.end_codes_job(id, Ok("the file"), &me).unwrap();
        let ended = store.take_codes_job("el2320", id, now).unwrap().unwrap();
        assert_eq!((ended.done, ended.file.as_deref()), (3, Some("the file")));
        let again = store.take_codes_job("el2320", id, now).unwrap().unwrap();
        assert_eq!((again.file, again.fetched), (None, true));
    }

    #[test]
    fn a_job_whose_maker_stopped_has_failed() {
        let dir = tempfile::tempdir().unwrap();
        let now = Timestamp::from_second(1_800_000_000).unwrap();
        let (store, me, id) = a_job(dir.path(), now);
        let later = now + jiff::SignedDuration::from_mins(1);
        let job = store.take_codes_job("el2320", id, later).unwrap().unwrap();
        assert!(job.failed.unwrap().starts_with("the server stopped"));
        // Its maker, if it comes back, is told to stop.
        assert!(!store.codes_job_made(id, 3, &lease(&me, later)).unwrap());
    }
}
