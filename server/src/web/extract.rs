//! Extractors of the API whose refusals answer as every API error does (`{"error": ...}`,
//! naming what was wrong), where axum's own answer with plain text: a request body too
//! large or cut off, a query string that does not parse.

use super::Error;
use super::connections::BodyTooSlow;
use super::viewer::Viewer;
use axum::extract::{FromRequest, FromRequestParts, Request};
use axum::http::request::Parts;
use serde::de::DeserializeOwned;
use std::collections::HashMap;
use std::convert::Infallible;
use std::sync::{Arc, LazyLock, Mutex};
use tokio::sync::{OwnedSemaphorePermit, Semaphore, SemaphorePermit};

/// The largest request body: a submission of the largest source, JSON-escaped.
pub const MAX_BODY: usize = 4 << 20;

/// Bodies read at once for people nobody vouches for (a server without courses takes
/// submissions from anyone), and for people signed in or holding a token: each takes up
/// to `MAX_BODY` of memory while it arrives, so together they stay within a few hundred
/// megabytes however many connections send one. A body waits its turn within its
/// deadline.
static ANONYMOUS_BODIES: LazyLock<Semaphore> = LazyLock::new(|| Semaphore::new(16));
static SIGNED_IN_BODIES: LazyLock<Semaphore> = LazyLock::new(|| Semaphore::new(64));

/// Bodies one person signed in (or one token) reads at once, before their place in the
/// shared pool: the rest of one person's bodies wait on their own turns, so that a
/// person sending many bodies slowly costs only themselves.
const PER_PERSON: usize = 2;

/// The turns of each person reading bodies now, by who they are.
static PEOPLE: LazyLock<Mutex<HashMap<String, Arc<Semaphore>>>> = LazyLock::new(Mutex::default);

/// A body's turn to be read: its person's (when someone is signed in), then the pool's.
struct Turn {
    _pool: SemaphorePermit<'static>,
    own: Option<(String, OwnedSemaphorePermit)>,
}

impl Turn {
    async fn take(viewer: &Viewer) -> Result<Turn, tokio::sync::AcquireError> {
        let person = match viewer {
            Viewer::Anonymous => None,
            Viewer::Member(member) => Some(format!("member {}", member.id)),
            Viewer::Token(token) => Some(format!("token {}", token.id)),
        };
        let own = match person {
            Some(person) => {
                let turns = Arc::clone(
                    people()
                        .entry(person.clone())
                        .or_insert_with(|| Arc::new(Semaphore::new(PER_PERSON))),
                );
                Some((person, turns.acquire_owned().await?))
            }
            None => None,
        };
        let pool = match viewer {
            Viewer::Anonymous => &ANONYMOUS_BODIES,
            Viewer::Member(_) | Viewer::Token(_) => &SIGNED_IN_BODIES,
        };
        Ok(Turn {
            _pool: pool.acquire().await?,
            own,
        })
    }
}

impl Drop for Turn {
    /// Gives back the person's turn, and forgets the person once nobody of theirs waits.
    fn drop(&mut self) {
        if let Some((person, permit)) = self.own.take() {
            let turns = Arc::clone(permit.semaphore());
            drop(permit);
            let mut people = people();
            // Held by the map and here alone: no body of theirs reads or waits.
            if Arc::strong_count(&turns) == 2 {
                people.remove(&person);
            }
        }
    }
}

fn people() -> std::sync::MutexGuard<'static, HashMap<String, Arc<Semaphore>>> {
    // Inserts and removes never panic halfway; a poisoned map is still whole.
    PEOPLE.lock().unwrap_or_else(|e| e.into_inner())
}

/// The client's address, as the limits count it (see `address::client_address`).
pub struct ClientAddress(pub std::net::IpAddr);

impl FromRequestParts<std::sync::Arc<super::AppState>> for ClientAddress {
    type Rejection = Infallible;

    async fn from_request_parts(
        parts: &mut Parts,
        state: &std::sync::Arc<super::AppState>,
    ) -> Result<Self, Self::Rejection> {
        Ok(ClientAddress(super::address::client_address(
            parts,
            state.behind_https,
        )))
    }
}

/// A request's body, not yet read: the handler reads it (`json`) once it has checked who
/// asks, so nobody can make the server buffer a body they may not send.
pub struct Body(axum::body::Body);

impl<S: Send + Sync> FromRequest<S> for Body {
    type Rejection = Infallible;

    async fn from_request(request: Request, _: &S) -> Result<Body, Infallible> {
        Ok(Body(request.into_body()))
    }
}

impl Body {
    /// Reads the body, at most `MAX_BODY`, as JSON of type `T`; an error names `what` the
    /// body is and where it is wrong (serde names the field, the line and the column).
    pub async fn json<T: DeserializeOwned>(self, viewer: &Viewer, what: &str) -> Result<T, Error> {
        let _turn = Turn::take(viewer)
            .await
            .map_err(|e| Error::BadRequest(format!("{what}: {e}")))?;
        let bytes = axum::body::to_bytes(self.0, MAX_BODY)
            .await
            .map_err(|e| refused(what, &e))?;
        let value = serde_json::from_slice(&bytes)
            .map_err(|e| Error::BadRequest(format!("{what}: {e}")))?;
        // No field takes it, no engine reads it, and PostgreSQL's text cannot keep it.
        if let Some(nul) = escaped_nul(&bytes) {
            return Err(Error::BadRequest(format!(
                "field `{}`: line {} holds a NUL character (byte 0), which no text here may hold: send plain text",
                nul.field, nul.line
            )));
        }
        Ok(value)
    }
}

/// Where a JSON text holds a NUL character (only written `\u0000`: JSON holds no raw
/// control character): the member whose string holds it, and the line of that string.
#[derive(Debug, PartialEq)]
struct Nul {
    field: String,
    line: usize,
}

/// The first NUL character of a JSON text (`json`, already read as valid), if any: its
/// strings are scanned escape by escape, each member's name remembered for the value
/// after it.
fn escaped_nul(json: &[u8]) -> Option<Nul> {
    let mut field = String::new();
    let mut at = 0;
    while let Some(open) = json[at..].iter().position(|&b| b == b'"') {
        let start = at + open + 1;
        let (mut end, mut line, mut nul) = (start, 1, None);
        while end < json.len() && json[end] != b'"' {
            if json[end] == b'\\' {
                match json.get(end + 1) {
                    Some(b'n') => line += 1,
                    Some(b'u') if json.get(end + 2..end + 6) == Some(b"0000") => {
                        nul.get_or_insert(line);
                    }
                    _ => {}
                }
                end += 2;
            } else {
                end += 1;
            }
        }
        let next = json[(end + 1).min(json.len())..]
            .iter()
            .find(|b| !b.is_ascii_whitespace());
        let is_name = next == Some(&b':');
        let text = String::from_utf8_lossy(&json[start..end.min(json.len())]);
        if let Some(line) = nul {
            let field = if is_name {
                format!("{text} (a name)")
            } else {
                field
            };
            return Some(Nul { field, line });
        }
        if is_name {
            field = text.into_owned();
        }
        at = end + 1;
        if at >= json.len() {
            break;
        }
    }
    None
}

/// Why a body could not be read: too large, too slow, or cut off.
fn refused(what: &str, error: &axum::Error) -> Error {
    let mut cause: Option<&(dyn std::error::Error + 'static)> = Some(error);
    while let Some(e) = cause {
        if e.is::<BodyTooSlow>() {
            return Error::TimedOut(format!("{what}: {e}"));
        }
        if e.is::<http_body_util::LengthLimitError>() {
            return Error::TooLarge(format!("{what}: larger than {} MiB", MAX_BODY >> 20));
        }
        cause = e.source();
    }
    Error::BadRequest(format!("{what}: {error}"))
}

/// A query string parsed into `T`.
pub struct Query<T>(pub T);

impl<T: DeserializeOwned, S: Send + Sync> FromRequestParts<S> for Query<T> {
    type Rejection = Error;

    async fn from_request_parts(parts: &mut Parts, state: &S) -> Result<Query<T>, Error> {
        axum::extract::Query::<T>::from_request_parts(parts, state)
            .await
            .map(|axum::extract::Query(value)| Query(value))
            .map_err(|refused| Error::BadRequest(format!("the query: {}", refused.body_text())))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nul(json: &str) -> Option<Nul> {
        escaped_nul(json.as_bytes())
    }

    #[test]
    fn a_nul_character_is_found_with_its_member_and_line() {
        assert_eq!(
            nul(r#"{"lab": "odometry", "source": "a\nb\u0000c"}"#),
            Some(Nul {
                field: "source".into(),
                line: 2
            })
        );
        assert_eq!(
            nul(r#"{"marks": [{"comment": "\u0000"}]}"#),
            Some(Nul {
                field: "comment".into(),
                line: 1
            })
        );
        // The text `\u0000` (an escaped backslash, then `u0000`) is no NUL character.
        assert_eq!(nul(r#"{"source": "let s = '\\u0000';\n"}"#), None);
        assert_eq!(nul(r#"{"source": "\"\u0001\"", "n": 0}"#), None);
        assert_eq!(nul("[]"), None);
    }
}
