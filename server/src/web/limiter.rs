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
//! holds whole. Counted in the database (`store::rates`): every web process behind a load
//! balancer counts the same attempts, and a restart forgets none.

use super::address::block;
use crate::store::{Error, Event, Store, Window};
use jiff::{SignedDuration, Timestamp};
use std::net::IpAddr;

/// The window over which attempts are counted.
const WINDOW: SignedDuration = SignedDuration::from_mins(15);
/// Failed (and pending) attempts with one code from one address in the window: enough
/// for someone who mistypes now and then.
const PER_CODE: usize = 10;
/// Failed guesses (codes of nobody's, a mistyped selector among them) an address may have
/// in the window: enough for a room of students behind one address who mistype.
const GUESSES: usize = 30;

/// What a sign-in tried, as the limiter counts it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Attempt {
    /// A code whose selector is someone's: counted for that selector.
    Code(String),
    /// A code whose selector is nobody's.
    Guess,
}

impl Attempt {
    fn window(&self) -> Window {
        let (scope, share) = match self {
            Attempt::Code(_) => ("signin code", PER_CODE),
            Attempt::Guess => ("signin guess", GUESSES),
        };
        Window {
            scope,
            share,
            length: WINDOW,
        }
    }

    /// What it is counted under, from `address`.
    fn key(&self, address: IpAddr) -> String {
        match self {
            Attempt::Code(selector) => format!("{} {selector}", block(address)),
            Attempt::Guess => block(address).to_string(),
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

/// Starts `attempt` from `address` at `now`, counted as a failure until it succeeds (its
/// event taken back: `Store::forget_event`), so that a burst of simultaneous attempts is
/// held to the limit too; refused when the address has had its share of such attempts.
pub fn begin(
    store: &Store,
    address: IpAddr,
    attempt: &Attempt,
    now: Timestamp,
) -> Result<Result<Event, Refusal>, Error> {
    let counted = store.count_event(&attempt.window(), &attempt.key(address), now)?;
    Ok(counted.map_err(|free_at| {
        let seconds = free_at.duration_since(now).as_secs().max(1);
        Refusal {
            minutes: (seconds + 59) / 60,
            guesses: *attempt == Attempt::Guess,
        }
    }))
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
        let dir = tempfile::tempdir().unwrap();
        let store = crate::store::test_store(dir.path());
        let address: IpAddr = "192.0.2.7".parse().unwrap();
        let other: IpAddr = "192.0.2.8".parse().unwrap();
        let start = at("2026-12-01T10:00Z");
        // All at once, none finished yet: the limit holds all the same.
        for i in 0..GUESSES {
            assert!(
                begin(&store, address, &Attempt::Guess, start)
                    .unwrap()
                    .is_ok(),
                "guess {i}"
            );
        }
        assert_eq!(
            begin(
                &store,
                address,
                &Attempt::Guess,
                start + SignedDuration::from_mins(1)
            )
            .unwrap(),
            Err(Refusal {
                minutes: 14,
                guesses: true
            })
        );
        assert!(
            begin(&store, other, &Attempt::Guess, start)
                .unwrap()
                .is_ok()
        );
        assert!(
            begin(
                &store,
                address,
                &Attempt::Guess,
                start + WINDOW + SignedDuration::from_secs(5)
            )
            .unwrap()
            .is_ok()
        );
    }

    #[test]
    fn a_sign_in_that_succeeds_is_not_counted() {
        let dir = tempfile::tempdir().unwrap();
        let store = crate::store::test_store(dir.path());
        let address: IpAddr = "192.0.2.7".parse().unwrap();
        let start = at("2026-12-01T10:00Z");
        for i in 0..3 * PER_CODE {
            let now = start + SignedDuration::from_secs(i as i64);
            let attempt = begin(&store, address, &code("AAAA0000"), now).unwrap();
            let event = attempt.unwrap_or_else(|refused| panic!("sign-in {i}: {refused:?}"));
            store.forget_event(event).unwrap();
        }
    }

    #[test]
    fn attempts_from_other_addresses_never_refuse_an_address() {
        let dir = tempfile::tempdir().unwrap();
        let store = crate::store::test_store(dir.path());
        let now = at("2026-12-01T10:00Z");
        let classroom: IpAddr = "192.0.2.1".parse().unwrap();
        begin(&store, classroom, &code("AAAA0000"), now)
            .unwrap()
            .unwrap();
        for i in 0..10 * GUESSES {
            let elsewhere = IpAddr::from([10, 0, (i / 256) as u8, (i % 256) as u8]);
            begin(&store, elsewhere, &code("AAAA0000"), now)
                .unwrap()
                .unwrap();
            begin(&store, elsewhere, &Attempt::Guess, now)
                .unwrap()
                .unwrap();
        }
        for i in 1..PER_CODE {
            assert!(
                begin(&store, classroom, &code("AAAA0000"), now)
                    .unwrap()
                    .is_ok(),
                "attempt {i}"
            );
        }
        assert!(
            begin(&store, classroom, &code("AAAA0000"), now)
                .unwrap()
                .is_err()
        );
    }

    #[test]
    fn behind_one_address_one_code_or_guesses_locked_out_lock_out_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let store = crate::store::test_store(dir.path());
        let now = at("2026-12-01T10:00Z");
        let classroom: IpAddr = "192.0.2.1".parse().unwrap();
        for _ in 0..PER_CODE {
            begin(&store, classroom, &code("MALLORY0"), now)
                .unwrap()
                .unwrap();
        }
        for _ in 0..GUESSES {
            begin(&store, classroom, &Attempt::Guess, now)
                .unwrap()
                .unwrap();
        }
        assert_eq!(
            begin(&store, classroom, &code("MALLORY0"), now).unwrap(),
            Err(Refusal {
                minutes: 15,
                guesses: false
            })
        );
        assert!(
            begin(&store, classroom, &Attempt::Guess, now)
                .unwrap()
                .is_err()
        );
        assert!(
            begin(&store, classroom, &code("CLASSMAT"), now)
                .unwrap()
                .is_ok()
        );
    }

    #[test]
    fn an_ipv6_client_is_counted_by_its_slash_64() {
        let dir = tempfile::tempdir().unwrap();
        let store = crate::store::test_store(dir.path());
        let now = at("2026-12-01T10:00Z");
        for i in 0..GUESSES {
            let address: IpAddr = format!("2001:db8:1:2::{:x}", i + 1).parse().unwrap();
            begin(&store, address, &Attempt::Guess, now)
                .unwrap()
                .unwrap();
        }
        let same_block: IpAddr = "2001:db8:1:2:ffff::9".parse().unwrap();
        let other_block: IpAddr = "2001:db8:1:3::1".parse().unwrap();
        assert!(
            begin(&store, same_block, &Attempt::Guess, now)
                .unwrap()
                .is_err()
        );
        assert!(
            begin(&store, other_block, &Attempt::Guess, now)
                .unwrap()
                .is_ok()
        );
    }
}
