//! The web application: the pages, rendered with askama, and the built browser assets.

mod api;
mod assets;
mod error;
mod pages;

pub use assets::Assets;
pub use error::Error;

use crate::submissions::Grader;
use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::http::{HeaderValue, header};
use axum::routing::{get, post};
use std::sync::Arc;
use tower_http::compression::CompressionLayer;
use tower_http::set_header::SetResponseHeaderLayer;

/// What every request handler can reach.
pub struct AppState {
    pub assets: Assets,
    pub grader: Arc<Grader>,
}

/// The largest request body: a submission of the largest source, JSON-escaped.
const MAX_BODY: usize = 4 << 20;

/// Scripts from this origin only (and the wasm module they compile); styles may be
/// inline, as the plotting and formula libraries set them on elements.
const CONTENT_SECURITY_POLICY: &str = "default-src 'self'; script-src 'self' 'wasm-unsafe-eval'; \
    style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; font-src 'self'; \
    object-src 'none'; base-uri 'none'; frame-ancestors 'none'";

pub fn router(state: Arc<AppState>) -> Router {
    let static_files = assets::service(state.assets.dir());
    Router::new()
        .route("/", get(pages::home))
        .route("/car", get(pages::car))
        .route("/ekf", get(pages::ekf))
        .route("/ekf/code", get(pages::code))
        .route("/ekf/starter.js", get(pages::starter))
        .route("/api/submissions", post(api::submit))
        .route("/api/submissions/{id}", get(api::submission))
        .route("/healthz", get(|| async { "ok" }))
        .route("/favicon.svg", get(pages::icon))
        .route("/favicon.ico", get(pages::icon))
        .nest_service("/static", static_files)
        .fallback(pages::not_found)
        .layer(DefaultBodyLimit::max(MAX_BODY))
        .layer(CompressionLayer::new())
        .layer(SetResponseHeaderLayer::if_not_present(
            header::CONTENT_SECURITY_POLICY,
            HeaderValue::from_static(CONTENT_SECURITY_POLICY),
        ))
        .layer(SetResponseHeaderLayer::if_not_present(
            header::X_CONTENT_TYPE_OPTIONS,
            HeaderValue::from_static("nosniff"),
        ))
        .with_state(state)
}
