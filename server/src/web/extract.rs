//! Extractors of the API whose refusals answer as every API error does (`{"error": ...}`,
//! naming what was wrong), where axum's own answer with plain text: a request body too
//! large or cut off, a query string that does not parse.

use super::Error;
use super::connections::BodyTooSlow;
use super::viewer::Viewer;
use axum::extract::{FromRequest, FromRequestParts, Request};
use axum::http::request::Parts;
use serde::de::DeserializeOwned;
use std::convert::Infallible;
use std::sync::LazyLock;
use tokio::sync::Semaphore;

/// The largest request body: a submission of the largest source, JSON-escaped.
pub const MAX_BODY: usize = 4 << 20;

/// Bodies read at once for people nobody vouches for (a server without courses takes
/// submissions from anyone), and for people signed in or holding a token: each takes up
/// to `MAX_BODY` of memory while it arrives, so together they stay within a few hundred
/// megabytes however many connections send one. A body waits its turn within its
/// deadline.
static ANONYMOUS_BODIES: LazyLock<Semaphore> = LazyLock::new(|| Semaphore::new(16));
static SIGNED_IN_BODIES: LazyLock<Semaphore> = LazyLock::new(|| Semaphore::new(64));

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
        let turns = match viewer {
            Viewer::Anonymous => &ANONYMOUS_BODIES,
            Viewer::Member(_) | Viewer::Token(_) => &SIGNED_IN_BODIES,
        };
        let _turn = turns
            .acquire()
            .await
            .map_err(|e| Error::BadRequest(format!("{what}: {e}")))?;
        let bytes = axum::body::to_bytes(self.0, MAX_BODY)
            .await
            .map_err(|e| refused(what, &e))?;
        serde_json::from_slice(&bytes).map_err(|e| Error::BadRequest(format!("{what}: {e}")))
    }
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
