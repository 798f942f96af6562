//! `/metrics`: this process's sandbox metrics (`grading::metrics`) for Prometheus, to
//! whoever sends the token of the data directory's `metrics-token` as `Authorization:
//! Bearer TOKEN`; 401 to anyone else (the queue's depths say how busy a course is). The
//! same route serves `estlab grader --metrics ADDR`.

use super::Error;
use super::viewer::bearer;
use crate::grading::Grader;
use axum::Router;
use axum::http::{HeaderMap, HeaderValue, header};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use sha2::{Digest, Sha256};
use std::sync::Arc;

/// The text format's media type, as Prometheus asks for it.
const TEXT_FORMAT: &str = "application/openmetrics-text; version=1.0.0; charset=utf-8";

/// The metrics of `grader`, to the holder of the token.
pub async fn scrape(grader: Arc<Grader>, headers: HeaderMap) -> Result<Response, Error> {
    // Compared as digests, so the time taken tells nothing of the token.
    let sent = bearer(&headers).map(|token| Sha256::digest(token.as_bytes()));
    if sent != Some(Sha256::digest(grader.metrics_token().as_bytes())) {
        return Err(Error::Unauthorized(
            "send the token of the data directory's metrics-token as Authorization: Bearer"
                .to_owned(),
        ));
    }
    let mut response = grader.metrics().into_response();
    response
        .headers_mut()
        .insert(header::CONTENT_TYPE, HeaderValue::from_static(TEXT_FORMAT));
    Ok(response)
}

/// A server of `/metrics` alone, for a grader process.
pub fn router(grader: Arc<Grader>) -> Router {
    Router::new().route(
        "/metrics",
        get(move |headers| scrape(Arc::clone(&grader), headers)),
    )
}
