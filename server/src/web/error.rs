use crate::store;
use axum::Json;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use ts_rs::TS;

/// What can go wrong while answering a request.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("rendering a page: {0}")]
    Template(#[from] askama::Error),
    /// The built browser assets are missing or unreadable (at start-up).
    #[error("{0}")]
    Assets(String),
    #[error(transparent)]
    Store(#[from] store::Error),
    /// A request the client should correct; the message names the field.
    #[error("{0}")]
    BadRequest(String),
    #[error("{0}")]
    TooLarge(String),
    /// The request's body did not arrive within its deadline.
    #[error("{0}")]
    TimedOut(String),
    /// Not there, or not the asker's to see: the two answer alike.
    #[error("{0}")]
    NotFound(String),
    /// The request conflicts with what is stored (a submission still being graded).
    #[error("{0}")]
    Conflict(String),
    /// Signing in is needed, or the credentials given are not valid.
    #[error("{0}")]
    Unauthorized(String),
    /// Signed in, but not allowed (a member of staff submitting, a cutoff passed, a
    /// request from another site).
    #[error("{0}")]
    Forbidden(String),
    #[error("{0}")]
    TooManyRequests(String),
    /// What the request needs of this server is not there now (a language whose sandbox
    /// does not start on this machine).
    #[error("{0}")]
    Unavailable(String),
}

/// What a failure of the server's own says: the cause is in its log.
const INTERNAL: &str = "estlab could not answer this request; the server log says why";

/// The body of every error answer of the API.
#[derive(Serialize, TS)]
pub(super) struct ErrorBody {
    error: String,
}

impl IntoResponse for Error {
    fn into_response(self) -> Response {
        let status = match &self {
            Error::BadRequest(_) => StatusCode::BAD_REQUEST,
            Error::TooLarge(_) => StatusCode::PAYLOAD_TOO_LARGE,
            Error::TimedOut(_) => StatusCode::REQUEST_TIMEOUT,
            Error::NotFound(_) => StatusCode::NOT_FOUND,
            Error::Conflict(_) => StatusCode::CONFLICT,
            Error::Unauthorized(_) => StatusCode::UNAUTHORIZED,
            Error::Forbidden(_) => StatusCode::FORBIDDEN,
            Error::TooManyRequests(_) => StatusCode::TOO_MANY_REQUESTS,
            Error::Unavailable(_) => StatusCode::SERVICE_UNAVAILABLE,
            // What the store says of the request, once for every handler.
            Error::Store(error) if error.kind() == store::Kind::Missing => StatusCode::NOT_FOUND,
            Error::Store(error) if error.kind() == store::Kind::Conflict => StatusCode::CONFLICT,
            Error::Template(_) | Error::Assets(_) | Error::Store(_) => {
                // The cause goes to the log, never to the asker (it may name files or
                // the database); the answer has the API's shape all the same.
                tracing::error!("{self}");
                return (
                    StatusCode::INTERNAL_SERVER_ERROR,
                    Json(ErrorBody {
                        error: INTERNAL.into(),
                    }),
                )
                    .into_response();
            }
        };
        (
            status,
            Json(ErrorBody {
                error: self.to_string(),
            }),
        )
            .into_response()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test]
    async fn a_failure_of_the_server_answers_as_every_api_error_without_its_cause() {
        let response =
            Error::Assets("/srv/estlab/static/manifest.json: gone".into()).into_response();
        assert_eq!(response.status(), StatusCode::INTERNAL_SERVER_ERROR);
        assert_eq!(
            response.headers()[axum::http::header::CONTENT_TYPE],
            "application/json"
        );
        let body = axum::body::to_bytes(response.into_body(), 1 << 16)
            .await
            .unwrap();
        assert_eq!(
            body,
            r#"{"error":"estlab could not answer this request; the server log says why"}"#
        );
    }
}
