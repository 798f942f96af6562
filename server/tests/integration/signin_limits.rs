//! The sign-in limits cannot be turned against a classmate: the real web application
//! (as `access.rs` builds it), with the test clock, asked as an attacker with many
//! addresses and as the students of a classroom behind one address.
//!
//! - `wrong_codes_from_many_addresses_do_not_lock_a_classroom_out`: issue 21's case, 52
//!   wrong codes from 50 IPv6 /64s, then a classmate's right code from the classroom's
//!   address, which had a typo, gets in;
//! - `a_code_is_limited_by_its_own_wrong_tries_from_that_address_only`: 10 wrong tries
//!   of one code from one address refuse that code there, the right one included, and
//!   nothing else;
//! - `behind_one_address_no_student_locks_a_classmate_out`: a student who spends every
//!   limit from the classroom's address locks out no classmate there.

use crate::common;

use axum::http::StatusCode;
use common::*;
use estlab::courses::codes::new_code;
use jiff::SignedDuration;
use std::net::{IpAddr, Ipv6Addr, SocketAddr};

/// A code with a real selector and a wrong secret: its last characters changed.
fn wrong_secret(code: &str) -> String {
    let (head, tail) = code.split_at(code.len() - 4);
    let wrong = if tail == "0000" { "1111" } else { "0000" };
    format!("{head}{wrong}")
}

/// The attacker's `i`th address: one IPv6 /64 each.
fn attacker(i: u16) -> SocketAddr {
    SocketAddr::new(
        IpAddr::V6(Ipv6Addr::new(0x2001, 0xdb8, 0x21, i, 0, 0, 0, 1)),
        9,
    )
}

/// Proves issue 21's case: a student with 50 addresses sends 52 wrong codes (their own
/// code with wrong secrets, then codes nobody has), and a classmate whose address (the
/// classroom's, shared) had a typo a minute before still signs in with the right code,
/// as does another classmate there and the attacker's own right code.
#[tokio::test(flavor = "multi_thread")]
async fn wrong_codes_from_many_addresses_do_not_lock_a_classroom_out() {
    let app = App::new();
    let start = app.now();
    app.open_course("el2320");
    let mallory = app.enrol("el2320", "u-mallory");
    let classmate = app.enrol("el2320", "u-classmate");
    let neighbour = app.enrol("el2320", "u-neighbour");
    let mallory_code = app.code(&mallory);
    let classmate_code = app.code(&classmate);
    let neighbour_code = app.code(&neighbour);
    let classroom = peer(192, 0, 2, 50);

    // The classroom's typo: the classmate's own code, one character wrong.
    let typo = app
        .send(Req::sign_in(&wrong_secret(&classmate_code)).sent_from(classroom))
        .await;
    assert_eq!(typo.status, StatusCode::UNAUTHORIZED, "{}", typo.body);

    app.clock.set(start + SignedDuration::from_mins(1));
    let wrong = wrong_secret(&mallory_code);
    for i in 0..52u16 {
        let answer = app
            .send(Req::sign_in(&wrong).sent_from(attacker(i % 50)))
            .await;
        assert_eq!(answer.status, StatusCode::UNAUTHORIZED, "wrong code {i}");
    }
    // Codes nobody has, from the same addresses, change nothing either.
    for i in 0..10u16 {
        let answer = app
            .send(Req::sign_in(&new_code().text).sent_from(attacker(i)))
            .await;
        assert_eq!(answer.status, StatusCode::UNAUTHORIZED, "unknown code {i}");
    }

    app.sign_in(&classmate_code, classroom).await;
    app.sign_in(&neighbour_code, classroom).await;
    app.sign_in(&mallory_code, attacker(3)).await;
}

/// Proves that a code tried wrong 10 times from one address is refused there, the right
/// code too, for as long as those tries are in the window, while from the same address
/// a classmate signs in, and the same code signs in from elsewhere.
#[tokio::test(flavor = "multi_thread")]
async fn a_code_is_limited_by_its_own_wrong_tries_from_that_address_only() {
    let app = App::new();
    let start = app.now();
    app.open_course("el2320");
    let mallory = app.enrol("el2320", "u-mallory");
    let classmate = app.enrol("el2320", "u-classmate");
    let mallory_code = app.code(&mallory);
    let classmate_code = app.code(&classmate);
    let wrong = wrong_secret(&mallory_code);
    for i in 0..10 {
        let answer = app.send(Req::sign_in(&wrong).sent_from(attacker(0))).await;
        assert_eq!(answer.status, StatusCode::UNAUTHORIZED, "wrong code {i}");
    }
    let refused = app
        .send(Req::sign_in(&mallory_code).sent_from(attacker(0)))
        .await;
    assert_eq!(
        refused.status,
        StatusCode::TOO_MANY_REQUESTS,
        "{}",
        refused.body
    );
    assert!(
        refused
            .body
            .contains("wrong tries of this code from your address"),
        "{}",
        refused.body
    );
    assert_eq!(refused.session(), None);

    app.sign_in(&classmate_code, attacker(0)).await;
    app.sign_in(&mallory_code, attacker(1)).await;
    app.clock
        .set(start + SignedDuration::from_mins(15) + SignedDuration::from_secs(1));
    app.sign_in(&mallory_code, attacker(0)).await;
}

/// Proves issue 21's "also behind one address": from a classroom's one address, a student
/// spends the limits of their own code and of guesses (codes of nobody's), and every
/// classmate there still signs in with their code, the one who had a typo included.
#[tokio::test(flavor = "multi_thread")]
async fn behind_one_address_no_student_locks_a_classmate_out() {
    let app = App::new();
    app.open_course("el2320");
    let mallory = app.enrol("el2320", "u-mallory");
    let classmate = app.enrol("el2320", "u-classmate");
    let neighbour = app.enrol("el2320", "u-neighbour");
    let mallory_code = app.code(&mallory);
    let classmate_code = app.code(&classmate);
    let neighbour_code = app.code(&neighbour);
    let classroom = peer(192, 0, 2, 50);
    let typo = app
        .send(Req::sign_in(&wrong_secret(&classmate_code)).sent_from(classroom))
        .await;
    assert_eq!(typo.status, StatusCode::UNAUTHORIZED, "{}", typo.body);

    let wrong = wrong_secret(&mallory_code);
    for i in 0..12 {
        let answer = app.send(Req::sign_in(&wrong).sent_from(classroom)).await;
        let expected = if i < 10 {
            StatusCode::UNAUTHORIZED
        } else {
            StatusCode::TOO_MANY_REQUESTS
        };
        assert_eq!(answer.status, expected, "own code, wrong, {i}");
    }
    for i in 0..32 {
        let answer = app
            .send(Req::sign_in(&new_code().text).sent_from(classroom))
            .await;
        let expected = if i < 30 {
            StatusCode::UNAUTHORIZED
        } else {
            StatusCode::TOO_MANY_REQUESTS
        };
        assert_eq!(answer.status, expected, "a guess, {i}: {}", answer.body);
        if i == 31 {
            assert!(
                answer.body.contains("codes that are nobody"),
                "{}",
                answer.body
            );
        }
    }

    app.sign_in(&classmate_code, classroom).await;
    app.sign_in(&neighbour_code, classroom).await;
}
