//! Who is asking: nobody, a signed-in member of a course (the session cookie), or a
//! script with a course's API token (`Authorization: Bearer ...`). Every handler that
//! reads or changes anything a course owns takes a `Viewer` and asks it.

use super::{AppState, Error, blocking};
use crate::store::{Member, Role, TokenInfo};
use axum::extract::FromRequestParts;
use axum::http::request::Parts;
use axum::http::{HeaderMap, header};
use std::sync::Arc;

/// The session cookie's name.
pub const SESSION_COOKIE: &str = "estlab_session";

pub enum Viewer {
    Anonymous,
    Member(Member),
    Token(TokenInfo),
}

impl Viewer {
    /// The signed-in member, if any.
    pub fn member(&self) -> Option<&Member> {
        match self {
            Viewer::Member(member) => Some(member),
            _ => None,
        }
    }

    /// Whether the viewer reads and acts for the staff of `course`.
    pub fn is_staff_of(&self, course: &str) -> bool {
        match self {
            Viewer::Member(member) => member.role.is_staff() && member.course == course,
            Viewer::Token(token) => token.course == course,
            Viewer::Anonymous => false,
        }
    }

    /// Whether the viewer is one of `course`'s people: its staff (or a token of it), or a
    /// member of it.
    pub fn of_course(&self, course: &str) -> bool {
        self.is_staff_of(course) || self.member().is_some_and(|m| m.course == course)
    }

    /// Nothing, for the staff of `course`; for anyone else the answer a course that does
    /// not exist gets, so that nobody learns which courses exist.
    pub fn staff_of(&self, course: &str) -> Result<(), Error> {
        if self.is_staff_of(course) {
            Ok(())
        } else {
            Err(Error::NotFound(format!("there is no course {course:?}")))
        }
    }

    /// Nothing, for the instructors of `course` (signed in, or with an instructor's API
    /// token): they set the course up. Its assistants are told so; anyone else gets the
    /// answer a course that does not exist gets.
    pub fn instructor_of(&self, course: &str) -> Result<(), Error> {
        self.staff_of(course)?;
        let role = match self {
            Viewer::Member(member) => member.role,
            Viewer::Token(token) => token.role,
            Viewer::Anonymous => Role::Student,
        };
        if role == Role::Instructor {
            Ok(())
        } else {
            Err(Error::Forbidden(format!(
                "only the instructors of {course} change its set-up"
            )))
        }
    }

    /// Who acts, as the audit log names them.
    pub fn actor(&self) -> String {
        match self {
            Viewer::Member(member) => member.login.clone(),
            Viewer::Token(token) => format!("API token {}", token.id),
            Viewer::Anonymous => "nobody".into(),
        }
    }
}

/// The value of the session cookie in a `Cookie` header, if there is one.
pub fn session_key(parts: &Parts) -> Option<String> {
    parts
        .headers
        .get_all(header::COOKIE)
        .iter()
        .filter_map(|value| value.to_str().ok())
        .flat_map(|value| value.split(';'))
        .filter_map(|pair| pair.trim().split_once('='))
        .find(|(name, _)| *name == SESSION_COOKIE)
        .map(|(_, value)| value.to_string())
        .filter(|value| value.len() == 64 && value.bytes().all(|b| b.is_ascii_hexdigit()))
}

/// An API token in an `Authorization: Bearer` header, if there is one. Another scheme
/// (a proxy's Basic authentication) is not estlab's and is left alone.
pub(super) fn bearer(headers: &HeaderMap) -> Option<String> {
    headers
        .get(header::AUTHORIZATION)?
        .to_str()
        .ok()?
        .strip_prefix("Bearer ")
        .map(|token| token.trim().to_string())
}

impl FromRequestParts<Arc<AppState>> for Viewer {
    type Rejection = Error;

    async fn from_request_parts(parts: &mut Parts, state: &Arc<AppState>) -> Result<Viewer, Error> {
        let now = state.clock.now();
        if let Some(token) = bearer(&parts.headers) {
            let found = blocking(state, move |store| store.token(&token)).await?;
            return found.map(Viewer::Token).ok_or_else(|| {
                Error::Unauthorized("the API token is unknown or has been revoked".into())
            });
        }
        let Some(key) = session_key(parts) else {
            return Ok(Viewer::Anonymous);
        };
        let member = blocking(state, move |store| store.session(&key, now)).await?;
        Ok(member.map_or(Viewer::Anonymous, Viewer::Member))
    }
}
