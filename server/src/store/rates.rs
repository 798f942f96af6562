//! Limits over a sliding window, counted in the database so that every web process
//! behind a load balancer counts the same events: the sign-in attempts of an address
//! (`web::limiter`), the phases an asker runs on the server (`web::phases`). An event is
//! a row (its scope, its key, its moment); a key that has had its share in the window is
//! refused until its oldest one there leaves it. Counting and adding are one transaction,
//! so that a burst of simultaneous requests, to whichever process, is held to the share
//! too, and touches the key's own rows only (on PostgreSQL a serializable transaction
//! over the whole scope would lose races to every other key's); the rows of a scope that
//! left their window are deleted after each event, outside it.

use super::db::{OptionalExtension, params};
use super::{Error, Store};
use jiff::{SignedDuration, Timestamp};

/// A limit: at most `share` events of one key in any `length` of time.
#[derive(Clone, Copy, Debug)]
pub struct Window {
    /// What is counted, the same name in every process (`signin code`, `phase`).
    pub scope: &'static str,
    pub share: usize,
    pub length: SignedDuration,
}

/// An event counted, which may be taken back (`forget_event`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Event(i64);

impl Store {
    /// Counts an event of `key` at `now`, unless the key has had its share of the window
    /// already: then the moment its oldest event there leaves it (when the next is let).
    pub fn count_event(
        &self,
        window: &Window,
        key: &str,
        now: Timestamp,
    ) -> Result<Result<Event, Timestamp>, Error> {
        let now = now.as_millisecond();
        let length = window.length.as_millis() as i64;
        let share = i64::try_from(window.share).unwrap_or(i64::MAX);
        let counted = self.transaction(|connection| {
            connection.execute(
                "DELETE FROM rate_events WHERE scope = ?1 AND key = ?2 AND at <= ?3",
                params![window.scope, key, now - length],
            )?;
            if share == 0 {
                return Ok(Err(
                    Timestamp::from_millisecond(now + length).unwrap_or(Timestamp::MAX)
                ));
            }
            // The share-th newest event in the window: while there is one, the key waits
            // for it to leave.
            let full: Option<i64> = connection
                .query_row(
                    "SELECT at FROM rate_events WHERE scope = ?1 AND key = ?2
                     ORDER BY at DESC, id DESC LIMIT 1 OFFSET ?3",
                    params![window.scope, key, share - 1],
                    |row| row.get(0),
                )
                .optional()?;
            if let Some(at) = full {
                let free = Timestamp::from_millisecond(at + length).unwrap_or(Timestamp::MAX);
                return Ok(Err(free));
            }
            let id = connection.query_row(
                "INSERT INTO rate_events (scope, key, at) VALUES (?1, ?2, ?3) RETURNING id",
                params![window.scope, key, now],
                |row| row.get(0),
            )?;
            Ok(Ok(Event(id)))
        })?;
        self.connection().execute(
            "DELETE FROM rate_events WHERE scope = ?1 AND at <= ?2",
            params![window.scope, now - length],
        )?;
        Ok(counted)
    }

    /// Takes back an event counted (a sign-in that succeeded is not held against anyone).
    pub fn forget_event(&self, event: Event) -> Result<(), Error> {
        self.connection()
            .execute("DELETE FROM rate_events WHERE id = ?1", [event.0])?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::store::test_store;

    const WINDOW: Window = Window {
        scope: "test",
        share: 3,
        length: SignedDuration::from_mins(1),
    };

    fn at(seconds: i64) -> Timestamp {
        Timestamp::from_second(1_800_000_000 + seconds).unwrap()
    }

    /// A key is let its share, then refused until its oldest event leaves the window; one
    /// taken back frees its place; other keys and scopes count apart.
    #[test]
    fn a_key_has_its_share_of_the_window() {
        let dir = tempfile::tempdir().unwrap();
        let store = test_store(dir.path());
        store.count_event(&WINDOW, "ada", at(0)).unwrap().unwrap();
        store.count_event(&WINDOW, "ada", at(10)).unwrap().unwrap();
        let third = store.count_event(&WINDOW, "ada", at(20)).unwrap().unwrap();
        assert_eq!(
            store.count_event(&WINDOW, "ada", at(30)).unwrap(),
            Err(at(60))
        );
        assert!(store.count_event(&WINDOW, "grace", at(30)).unwrap().is_ok());
        let other = Window {
            scope: "other",
            ..WINDOW
        };
        assert!(store.count_event(&other, "ada", at(30)).unwrap().is_ok());

        store.forget_event(third).unwrap();
        assert!(store.count_event(&WINDOW, "ada", at(31)).unwrap().is_ok());
        // Full again; the first leaves the window at 60, the second at 70.
        assert_eq!(
            store.count_event(&WINDOW, "ada", at(40)).unwrap(),
            Err(at(60))
        );
        assert!(store.count_event(&WINDOW, "ada", at(60)).unwrap().is_ok());
        assert_eq!(
            store.count_event(&WINDOW, "ada", at(61)).unwrap(),
            Err(at(70))
        );
        // Rows out of their window are gone.
        let left: i64 = store
            .connection()
            .query_row(
                "SELECT count(*) FROM rate_events WHERE scope = 'test'",
                (),
                |row| row.get(0),
            )
            .unwrap();
        assert_eq!(left, 4);
    }
}
