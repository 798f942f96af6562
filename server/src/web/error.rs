use axum::Json;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use serde_json::json;

/// What can go wrong while answering a request.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("rendering a page: {0}")]
    Template(#[from] askama::Error),
    /// The built browser assets are missing or unreadable (at start-up).
    #[error("{0}")]
    Assets(String),
    #[error(transparent)]
    Submissions(#[from] crate::submissions::Error),
    /// A request the client should correct; the message names the field.
    #[error("{0}")]
    BadRequest(String),
    #[error("{0}")]
    TooLarge(String),
    #[error("{0}")]
    NotFound(String),
    /// The request conflicts with what is stored (a submission still being graded).
    #[error("{0}")]
    Conflict(String),
}

impl IntoResponse for Error {
    fn into_response(self) -> Response {
        let status = match self {
            Error::BadRequest(_) => StatusCode::BAD_REQUEST,
            Error::TooLarge(_) => StatusCode::PAYLOAD_TOO_LARGE,
            Error::NotFound(_) => StatusCode::NOT_FOUND,
            Error::Conflict(_) => StatusCode::CONFLICT,
            Error::Template(_) | Error::Assets(_) | Error::Submissions(_) => {
                eprintln!("estlab: {self}");
                return (
                    StatusCode::INTERNAL_SERVER_ERROR,
                    "estlab could not answer this request; the server log says why.\n",
                )
                    .into_response();
            }
        };
        (status, Json(json!({ "error": self.to_string() }))).into_response()
    }
}
