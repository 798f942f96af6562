//! Extractors of the API whose refusals answer as every API error does (`{"error": ...}`,
//! naming what was wrong), where axum's own answer with plain text: a request body too
//! large or cut off, a query string that does not parse.

use super::Error;
use axum::body::Bytes;
use axum::extract::{FromRequest, FromRequestParts, Request};
use axum::http::StatusCode;
use axum::http::request::Parts;
use serde::de::DeserializeOwned;

/// A request's body, read whole (within the router's limit); parsed by the handler once
/// it has checked who asks.
pub struct Body(Bytes);

impl<S: Send + Sync> FromRequest<S> for Body {
    type Rejection = Error;

    async fn from_request(request: Request, state: &S) -> Result<Body, Error> {
        Bytes::from_request(request, state)
            .await
            .map(Body)
            .map_err(|refused| {
                let message = format!("the request body: {}", refused.body_text());
                if refused.status() == StatusCode::PAYLOAD_TOO_LARGE {
                    Error::TooLarge(message)
                } else {
                    Error::BadRequest(message)
                }
            })
    }
}

impl Body {
    /// The body as JSON of type `T`; an error names `what` the body is and where it is
    /// wrong (serde names the field, the line and the column).
    pub fn json<T: DeserializeOwned>(&self, what: &str) -> Result<T, Error> {
        serde_json::from_slice(&self.0).map_err(|e| Error::BadRequest(format!("{what}: {e}")))
    }
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
