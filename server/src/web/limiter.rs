//! Failed sign-ins, counted per address and per course over a sliding window: after a
//! burst of wrong codes the address (or the course, for codes that name one of its
//! people) is refused until the oldest failure leaves the window. Held in memory: a
//! restart forgets them, which costs an attacker a restart they cannot cause.

use jiff::{SignedDuration, Timestamp};
use std::collections::{HashMap, VecDeque};
use std::net::IpAddr;
use std::sync::Mutex;

/// The window over which failures are counted.
const WINDOW: SignedDuration = SignedDuration::from_mins(15);
/// Failures an address may have in the window.
const PER_ADDRESS: usize = 10;
/// Failures with codes of one course's people in the window (a class mistyping, or
/// someone trying codes from many addresses).
const PER_COURSE: usize = 50;
/// Keys kept at most; beyond it the quietest are forgotten first.
const MAX_KEYS: usize = 100_000;

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Key {
    Address(IpAddr),
    Course(String),
}

/// Which limit refused a sign-in, and for how long.
#[derive(Debug, PartialEq, Eq)]
pub struct Refusal {
    pub per_course: bool,
    pub minutes: i64,
}

#[derive(Default)]
pub struct SignInLimiter {
    failures: Mutex<HashMap<Key, VecDeque<Timestamp>>>,
}

impl SignInLimiter {
    /// Refuses when the address has had its share of failures.
    pub fn check_address(&self, address: IpAddr, now: Timestamp) -> Result<(), Refusal> {
        self.check(&Key::Address(address), PER_ADDRESS, now)
            .map_err(|minutes| Refusal {
                per_course: false,
                minutes,
            })
    }

    /// Refuses when the course has had its share of failures.
    pub fn check_course(&self, course: &str, now: Timestamp) -> Result<(), Refusal> {
        self.check(&Key::Course(course.to_string()), PER_COURSE, now)
            .map_err(|minutes| Refusal {
                per_course: true,
                minutes,
            })
    }

    /// Counts a failed sign-in from `address`, with a code of `course`'s people if known.
    pub fn failed(&self, address: IpAddr, course: Option<&str>, now: Timestamp) {
        let mut failures = self.failures.lock().unwrap_or_else(|e| e.into_inner());
        if failures.len() >= MAX_KEYS {
            failures.retain(|_, times| {
                times
                    .back()
                    .is_some_and(|t| now.duration_since(*t) < WINDOW)
            });
        }
        for key in [
            Some(Key::Address(address)),
            course.map(|c| Key::Course(c.to_string())),
        ]
        .into_iter()
        .flatten()
        {
            if failures.len() < MAX_KEYS || failures.contains_key(&key) {
                failures.entry(key).or_default().push_back(now);
            }
        }
    }

    /// `Err(minutes to wait)` when `key` has `limit` failures within the window.
    fn check(&self, key: &Key, limit: usize, now: Timestamp) -> Result<(), i64> {
        let mut failures = self.failures.lock().unwrap_or_else(|e| e.into_inner());
        let Some(times) = failures.get_mut(key) else {
            return Ok(());
        };
        while times
            .front()
            .is_some_and(|t| now.duration_since(*t) >= WINDOW)
        {
            times.pop_front();
        }
        if times.is_empty() {
            failures.remove(key);
            return Ok(());
        }
        if times.len() < limit {
            return Ok(());
        }
        let free_at = times[times.len() - limit] + WINDOW;
        let seconds = free_at.duration_since(now).as_secs().max(1);
        Err((seconds + 59) / 60)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_burst_of_failures_is_refused_until_it_leaves_the_window() {
        let limiter = SignInLimiter::default();
        let address: IpAddr = "192.0.2.7".parse().unwrap();
        let other: IpAddr = "192.0.2.8".parse().unwrap();
        let start: Timestamp = "2026-12-01T10:00Z".parse().unwrap();
        for i in 0..PER_ADDRESS {
            assert!(limiter.check_address(address, start).is_ok(), "failure {i}");
            limiter.failed(
                address,
                Some("el2320"),
                start + SignedDuration::from_secs(i as i64),
            );
        }
        assert_eq!(
            limiter.check_address(address, start + SignedDuration::from_mins(1)),
            Err(Refusal {
                per_course: false,
                minutes: 14
            })
        );
        assert!(limiter.check_address(other, start).is_ok());
        assert!(limiter.check_course("el2320", start).is_ok());
        assert!(
            limiter
                .check_address(address, start + WINDOW + SignedDuration::from_secs(5))
                .is_ok()
        );
    }

    #[test]
    fn a_course_is_refused_after_failures_from_many_addresses() {
        let limiter = SignInLimiter::default();
        let now: Timestamp = "2026-12-01T10:00Z".parse().unwrap();
        for i in 0..PER_COURSE {
            let address = IpAddr::from([10, 0, (i / 256) as u8, (i % 256) as u8]);
            limiter.failed(address, Some("el2320"), now);
            assert!(limiter.check_address(address, now).is_ok());
        }
        assert!(limiter.check_course("el2320", now).unwrap_err().per_course);
        assert!(limiter.check_course("other", now).is_ok());
    }
}
