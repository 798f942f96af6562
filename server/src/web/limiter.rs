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
    /// Refuses when the address has had its share of failures.
    pub fn check_address(&self, address: IpAddr, now: Timestamp) -> Result<(), Refusal> {
        self.check(&Key::Address(block(address)), PER_ADDRESS, now)
            .map_err(|minutes| Refusal {
                per_course: false,
                minutes,
            })
    }

    /// Refuses an address that has failed recently when the course has had its share
    /// of failures.
    pub fn check_course(
        &self,
        course: &str,
        address: IpAddr,
        now: Timestamp,
    ) -> Result<(), Refusal> {
        if self.check(&Key::Address(block(address)), 1, now).is_ok() {
            return Ok(());
        }
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
            Some(Key::Address(block(address))),
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
        assert!(limiter.check_course("el2320", address, start).is_ok());
        assert!(
            limiter
                .check_address(address, start + WINDOW + SignedDuration::from_secs(5))
                .is_ok()
        );
    }

    #[test]
    fn after_failures_from_many_addresses_a_course_refuses_those_that_failed_only() {
        let limiter = SignInLimiter::default();
        let now: Timestamp = "2026-12-01T10:00Z".parse().unwrap();
        let failing = |i: usize| IpAddr::from([10, 0, (i / 256) as u8, (i % 256) as u8]);
        for i in 0..PER_COURSE {
            limiter.failed(failing(i), Some("el2320"), now);
            assert!(limiter.check_address(failing(i), now).is_ok());
        }
        let refusal = limiter.check_course("el2320", failing(3), now).unwrap_err();
        assert!(refusal.per_course);
        assert_eq!(refusal.minutes, 15);
        // A student who has not failed signs in; another course is not concerned.
        let fresh = IpAddr::from([192, 0, 2, 1]);
        assert!(limiter.check_course("el2320", fresh, now).is_ok());
        assert!(limiter.check_course("other", failing(3), now).is_ok());
    }

    #[test]
    fn an_ipv6_client_is_counted_by_its_slash_64() {
        let limiter = SignInLimiter::default();
        let now: Timestamp = "2026-12-01T10:00Z".parse().unwrap();
        for i in 0..PER_ADDRESS {
            let address: IpAddr = format!("2001:db8:1:2::{:x}", i + 1).parse().unwrap();
            limiter.failed(address, None, now);
        }
        let same_block: IpAddr = "2001:db8:1:2:ffff::9".parse().unwrap();
        let other_block: IpAddr = "2001:db8:1:3::1".parse().unwrap();
        assert!(limiter.check_address(same_block, now).is_err());
        assert!(limiter.check_address(other_block, now).is_ok());
        let mapped: IpAddr = "::ffff:192.0.2.7".parse().unwrap();
        assert_eq!(block(mapped), IpAddr::from([192, 0, 2, 7]));
    }
}
