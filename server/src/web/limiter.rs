//! Failed sign-ins, counted per address and per course over a sliding window. After a
//! burst of wrong codes from one address, that address is refused until the oldest
//! failure leaves the window. After a burst of wrong codes for one course's people (from
//! many addresses), every address that has itself failed recently is refused for that
//! course: someone trying codes from many addresses gets one try per address, while the
//! class, typing their codes right the first time, signs in as usual (so no student can
//! lock the course by failing on purpose). An IPv6 client is counted by its /64, which it
//! usually holds whole. Held in memory: a restart forgets them.

use jiff::{SignedDuration, Timestamp};
use std::collections::{HashMap, VecDeque};
use std::net::IpAddr;
use std::sync::Mutex;

/// The window over which failures are counted.
const WINDOW: SignedDuration = SignedDuration::from_mins(15);
/// Failed (and pending) sign-ins an address may have in the window: enough for a room of
/// students behind one address who mistype now and then.
const PER_ADDRESS: usize = 30;
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

/// What an address is counted as: itself (IPv4), or its /64 (IPv6).
fn block(address: IpAddr) -> IpAddr {
    match address {
        IpAddr::V6(v6) if v6.to_ipv4_mapped().is_none() => {
            let mut octets = v6.octets();
            octets[8..].fill(0);
            IpAddr::from(octets)
        }
        IpAddr::V6(v6) => IpAddr::V4(v6.to_ipv4_mapped().expect("mapped")),
        v4 => v4,
    }
}

#[derive(Default)]
pub struct SignInLimiter {
    failures: Mutex<HashMap<Key, VecDeque<Timestamp>>>,
}

impl SignInLimiter {
    /// Starts a sign-in from `address` at `now`, counted as a failure until it succeeds
    /// (`succeeded`), so that a burst of simultaneous attempts is held to the limit too;
    /// refused when the address has had its share.
    pub fn begin(&self, address: IpAddr, now: Timestamp) -> Result<(), Refusal> {
        let key = Key::Address(block(address));
        self.check(&key, PER_ADDRESS, now)
            .map_err(|minutes| Refusal {
                per_course: false,
                minutes,
            })?;
        self.record(key, now);
        Ok(())
    }

    /// Takes back the failure `begin` counted for a sign-in that succeeded.
    pub fn succeeded(&self, address: IpAddr, now: Timestamp) {
        let mut failures = self.failures.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(times) = failures.get_mut(&Key::Address(block(address)))
            && let Some(i) = times.iter().rposition(|t| *t == now)
        {
            times.remove(i);
        }
    }

    /// Refuses an address that has failed recently when the course has had its share
    /// of failures.
    pub fn check_course(
        &self,
        course: &str,
        address: IpAddr,
        now: Timestamp,
    ) -> Result<(), Refusal> {
        // Besides the attempt under way (counted by `begin`), has it failed recently?
        if self.check(&Key::Address(block(address)), 2, now).is_ok() {
            return Ok(());
        }
        self.check(&Key::Course(course.to_string()), PER_COURSE, now)
            .map_err(|minutes| Refusal {
                per_course: true,
                minutes,
            })
    }

    /// Counts a failed sign-in with a code of `course`'s people (the address's failure
    /// was counted when it began).
    pub fn failed_for_course(&self, course: &str, now: Timestamp) {
        self.record(Key::Course(course.to_string()), now);
    }

    fn record(&self, key: Key, now: Timestamp) {
        let mut failures = self.failures.lock().unwrap_or_else(|e| e.into_inner());
        if failures.len() >= MAX_KEYS {
            failures.retain(|_, times| {
                times
                    .back()
                    .is_some_and(|t| now.duration_since(*t) < WINDOW)
            });
        }
        if failures.len() < MAX_KEYS || failures.contains_key(&key) {
            failures.entry(key).or_default().push_back(now);
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

    fn at(text: &str) -> Timestamp {
        text.parse().unwrap()
    }

    #[test]
    fn a_burst_of_attempts_is_held_to_the_limit_until_it_leaves_the_window() {
        let limiter = SignInLimiter::default();
        let address: IpAddr = "192.0.2.7".parse().unwrap();
        let other: IpAddr = "192.0.2.8".parse().unwrap();
        let start = at("2026-12-01T10:00Z");
        // All at once, none finished yet: the limit holds all the same.
        for i in 0..PER_ADDRESS {
            assert!(limiter.begin(address, start).is_ok(), "attempt {i}");
        }
        assert_eq!(
            limiter.begin(address, start + SignedDuration::from_mins(1)),
            Err(Refusal {
                per_course: false,
                minutes: 14
            })
        );
        assert!(limiter.begin(other, start).is_ok());
        assert!(
            limiter
                .begin(address, start + WINDOW + SignedDuration::from_secs(5))
                .is_ok()
        );
    }

    #[test]
    fn a_sign_in_that_succeeds_is_not_counted() {
        let limiter = SignInLimiter::default();
        let address: IpAddr = "192.0.2.7".parse().unwrap();
        let start = at("2026-12-01T10:00Z");
        for i in 0..3 * PER_ADDRESS {
            let now = start + SignedDuration::from_secs(i as i64);
            assert!(limiter.begin(address, now).is_ok(), "sign-in {i}");
            limiter.succeeded(address, now);
        }
    }

    #[test]
    fn after_failures_from_many_addresses_a_course_refuses_those_that_failed_only() {
        let limiter = SignInLimiter::default();
        let now = at("2026-12-01T10:00Z");
        let failing = |i: usize| IpAddr::from([10, 0, (i / 256) as u8, (i % 256) as u8]);
        for i in 0..PER_COURSE {
            limiter.begin(failing(i), now).unwrap();
            limiter.failed_for_course("el2320", now);
        }
        // One that failed before tries again.
        limiter.begin(failing(3), now).unwrap();
        let refusal = limiter.check_course("el2320", failing(3), now).unwrap_err();
        assert!(refusal.per_course);
        assert_eq!(refusal.minutes, 15);
        // A student who has not failed signs in; another course is not concerned.
        let fresh = IpAddr::from([192, 0, 2, 1]);
        limiter.begin(fresh, now).unwrap();
        assert!(limiter.check_course("el2320", fresh, now).is_ok());
        assert!(limiter.check_course("other", failing(3), now).is_ok());
    }

    #[test]
    fn an_ipv6_client_is_counted_by_its_slash_64() {
        let limiter = SignInLimiter::default();
        let now = at("2026-12-01T10:00Z");
        for i in 0..PER_ADDRESS {
            let address: IpAddr = format!("2001:db8:1:2::{:x}", i + 1).parse().unwrap();
            limiter.begin(address, now).unwrap();
        }
        let same_block: IpAddr = "2001:db8:1:2:ffff::9".parse().unwrap();
        let other_block: IpAddr = "2001:db8:1:3::1".parse().unwrap();
        assert!(limiter.begin(same_block, now).is_err());
        assert!(limiter.begin(other_block, now).is_ok());
        let mapped: IpAddr = "::ffff:192.0.2.7".parse().unwrap();
        assert_eq!(block(mapped), IpAddr::from([192, 0, 2, 7]));
    }
}
