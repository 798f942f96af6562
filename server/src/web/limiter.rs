//! Sign-in attempts, counted over a sliding window by address and by what was tried: a
//! code of someone's (its selector matches a row) is counted for that address and that
//! code only, and a guess (a selector of nobody's) for that address's guesses. A key that
//! has used its share is refused until its oldest attempt leaves the window.
//!
//! So a refusal is earned by the key that gets it, and no one can turn it against a
//! classmate, from elsewhere or from the same address (a classroom behind one NAT): wrong
//! secrets of one's own code lock out that code from that address only, and guesses lock
//! out guesses only, never a code that is someone's. Locking a classmate's code takes its
//! selector, the first third of their code. Guessing is held off by the codes themselves
//! (120 random bits, 80 of them behind Argon2id), by the pace of the checks (one per
//! core, `signin::CODE_CHECKS`) and by refusing the guesses of an address over its share
//! before any hash is checked. An IPv6 client is counted by its /64, which it usually
//! holds whole. Held in memory: a restart forgets them.

use super::address::block;
use jiff::{SignedDuration, Timestamp};
use std::collections::{HashMap, VecDeque};
use std::net::IpAddr;
use std::sync::Mutex;

/// The window over which attempts are counted.
const WINDOW: SignedDuration = SignedDuration::from_mins(15);
/// Failed (and pending) attempts with one code from one address in the window: enough
/// for someone who mistypes now and then.
const PER_CODE: usize = 10;
/// Failed guesses (codes of nobody's, a mistyped selector among them) an address may have
/// in the window: enough for a room of students behind one address who mistype.
const GUESSES: usize = 30;
/// Keys kept at most; beyond it the quietest are forgotten first.
const MAX_KEYS: usize = 100_000;

/// What a sign-in tried, as the limiter counts it.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Attempt {
    /// A code whose selector is someone's: counted for that selector.
    Code(String),
    /// A code whose selector is nobody's.
    Guess,
}

impl Attempt {
    fn share(&self) -> usize {
        match self {
            Attempt::Code(_) => PER_CODE,
            Attempt::Guess => GUESSES,
        }
    }
}

/// How long a refused attempt waits, and what was refused.
#[derive(Debug, PartialEq, Eq)]
pub struct Refusal {
    pub minutes: i64,
    /// Whether guesses were refused (else one code).
    pub guesses: bool,
}

type Key = (IpAddr, Attempt);

#[derive(Default)]
pub struct SignInLimiter {
    attempts: Mutex<HashMap<Key, VecDeque<Timestamp>>>,
}

impl SignInLimiter {
    /// Starts `attempt` from `address` at `now`, counted as a failure until it succeeds
    /// (`succeeded`), so that a burst of simultaneous attempts is held to the limit too;
    /// refused when the address has had its share of such attempts.
    pub fn begin(&self, address: IpAddr, attempt: &Attempt, now: Timestamp) -> Result<(), Refusal> {
        let key = (block(address), attempt.clone());
        let share = attempt.share();
        let mut attempts = self.attempts.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(times) = attempts.get_mut(&key) {
            while times
                .front()
                .is_some_and(|t| now.duration_since(*t) >= WINDOW)
            {
                times.pop_front();
            }
            if times.len() >= share {
                let free_at = times[times.len() - share] + WINDOW;
                let seconds = free_at.duration_since(now).as_secs().max(1);
                return Err(Refusal {
                    minutes: (seconds + 59) / 60,
                    guesses: *attempt == Attempt::Guess,
                });
            }
        }
        if attempts.len() >= MAX_KEYS {
            attempts.retain(|_, times| {
                times
                    .back()
                    .is_some_and(|t| now.duration_since(*t) < WINDOW)
            });
        }
        if attempts.len() < MAX_KEYS || attempts.contains_key(&key) {
            attempts.entry(key).or_default().push_back(now);
        }
        Ok(())
    }

    /// Takes back the attempt `begin` counted for a sign-in that succeeded.
    pub fn succeeded(&self, address: IpAddr, attempt: &Attempt, now: Timestamp) {
        let mut attempts = self.attempts.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(times) = attempts.get_mut(&(block(address), attempt.clone()))
            && let Some(i) = times.iter().rposition(|t| *t == now)
        {
            times.remove(i);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(text: &str) -> Timestamp {
        text.parse().unwrap()
    }

    fn code(selector: &str) -> Attempt {
        Attempt::Code(selector.to_owned())
    }

    #[test]
    fn a_burst_of_attempts_is_held_to_the_limit_until_it_leaves_the_window() {
        let limiter = SignInLimiter::default();
        let address: IpAddr = "192.0.2.7".parse().unwrap();
        let other: IpAddr = "192.0.2.8".parse().unwrap();
        let start = at("2026-12-01T10:00Z");
        // All at once, none finished yet: the limit holds all the same.
        for i in 0..GUESSES {
            assert!(
                limiter.begin(address, &Attempt::Guess, start).is_ok(),
                "guess {i}"
            );
        }
        assert_eq!(
            limiter.begin(
                address,
                &Attempt::Guess,
                start + SignedDuration::from_mins(1)
            ),
            Err(Refusal {
                minutes: 14,
                guesses: true
            })
        );
        assert!(limiter.begin(other, &Attempt::Guess, start).is_ok());
        assert!(
            limiter
                .begin(
                    address,
                    &Attempt::Guess,
                    start + WINDOW + SignedDuration::from_secs(5)
                )
                .is_ok()
        );
    }

    #[test]
    fn a_sign_in_that_succeeds_is_not_counted() {
        let limiter = SignInLimiter::default();
        let address: IpAddr = "192.0.2.7".parse().unwrap();
        let start = at("2026-12-01T10:00Z");
        for i in 0..3 * PER_CODE {
            let now = start + SignedDuration::from_secs(i as i64);
            assert!(
                limiter.begin(address, &code("AAAA0000"), now).is_ok(),
                "sign-in {i}"
            );
            limiter.succeeded(address, &code("AAAA0000"), now);
        }
    }

    #[test]
    fn attempts_from_other_addresses_never_refuse_an_address() {
        let limiter = SignInLimiter::default();
        let now = at("2026-12-01T10:00Z");
        let classroom: IpAddr = "192.0.2.1".parse().unwrap();
        limiter.begin(classroom, &code("AAAA0000"), now).unwrap();
        for i in 0..10 * GUESSES {
            let elsewhere = IpAddr::from([10, 0, (i / 256) as u8, (i % 256) as u8]);
            limiter.begin(elsewhere, &code("AAAA0000"), now).unwrap();
            limiter.begin(elsewhere, &Attempt::Guess, now).unwrap();
        }
        for i in 1..PER_CODE {
            assert!(
                limiter.begin(classroom, &code("AAAA0000"), now).is_ok(),
                "attempt {i}"
            );
        }
        assert!(limiter.begin(classroom, &code("AAAA0000"), now).is_err());
    }

    #[test]
    fn behind_one_address_one_code_or_guesses_locked_out_lock_out_nothing_else() {
        let limiter = SignInLimiter::default();
        let now = at("2026-12-01T10:00Z");
        let classroom: IpAddr = "192.0.2.1".parse().unwrap();
        for _ in 0..PER_CODE {
            limiter.begin(classroom, &code("MALLORY0"), now).unwrap();
        }
        for _ in 0..GUESSES {
            limiter.begin(classroom, &Attempt::Guess, now).unwrap();
        }
        assert_eq!(
            limiter.begin(classroom, &code("MALLORY0"), now),
            Err(Refusal {
                minutes: 15,
                guesses: false
            })
        );
        assert!(limiter.begin(classroom, &Attempt::Guess, now).is_err());
        assert!(limiter.begin(classroom, &code("CLASSMAT"), now).is_ok());
    }

    #[test]
    fn an_ipv6_client_is_counted_by_its_slash_64() {
        let limiter = SignInLimiter::default();
        let now = at("2026-12-01T10:00Z");
        for i in 0..GUESSES {
            let address: IpAddr = format!("2001:db8:1:2::{:x}", i + 1).parse().unwrap();
            limiter.begin(address, &Attempt::Guess, now).unwrap();
        }
        let same_block: IpAddr = "2001:db8:1:2:ffff::9".parse().unwrap();
        let other_block: IpAddr = "2001:db8:1:3::1".parse().unwrap();
        assert!(limiter.begin(same_block, &Attempt::Guess, now).is_err());
        assert!(limiter.begin(other_block, &Attempt::Guess, now).is_ok());
    }
}
