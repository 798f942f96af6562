use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};

/// What can go wrong while answering a request.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("rendering a page: {0}")]
    Template(#[from] askama::Error),
    /// The built browser assets are missing or unreadable (at start-up).
    #[error("{0}")]
    Assets(String),
}

impl IntoResponse for Error {
    fn into_response(self) -> Response {
        eprintln!("estlab: {self}");
        (
            StatusCode::INTERNAL_SERVER_ERROR,
            "estlab could not answer this request; the server log says why.\n",
        )
            .into_response()
    }
}
