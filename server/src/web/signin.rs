//! Signing in with a personal code (or the link that carries it) and signing out. A
//! session lives in the database, so a restart signs nobody out; its key is in an
//! HttpOnly, SameSite=Lax cookie, `Secure` behind HTTPS.

use super::limiter::{self, Attempt, Refusal};
use super::pages::{Nav, html};
use super::viewer::{Viewer, session_key};
use super::{AppState, Error, SESSION_COOKIE, blocking};
use crate::courses::codes;
use crate::store::{CodeCheck, Member};
use askama::Template;
use axum::Form;
use axum::extract::State;
use axum::extract::rejection::FormRejection;
use axum::http::request::Parts;
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Redirect, Response};
use jiff::{SignedDuration, Timestamp};
use serde::Deserialize;
use std::net::IpAddr;
use std::sync::{Arc, LazyLock};
use std::time::Duration;
use tokio::sync::Semaphore;

/// How long a session lasts.
const SESSION: SignedDuration = SignedDuration::from_hours(30 * 24);

#[derive(Template)]
#[template(path = "signin.html")]
struct SignIn<'a> {
    page: &'a str,
    assets: super::assets::PageAssets<'a>,
    nav: Nav,
    problem: Option<String>,
}

#[derive(Deserialize)]
pub struct CodeForm {
    code: String,
}

pub async fn page(State(state): State<Arc<AppState>>, viewer: Viewer) -> Result<Response, Error> {
    render(&state, &viewer, StatusCode::OK, None).await
}

async fn render(
    state: &Arc<AppState>,
    viewer: &Viewer,
    status: StatusCode,
    problem: Option<String>,
) -> Result<Response, Error> {
    let page = SignIn {
        page: "signin",
        assets: state.assets.page("signin"),
        nav: Nav::of(state, viewer).await?,
        problem,
    };
    Ok((status, html(&page)?).into_response())
}

const WRONG_CODE: &str = "This code is not valid: it may be mistyped, replaced by a newer one, or (for a one-time link) used or expired. Ask your teacher for a new one if it keeps failing.";

/// Why a sign-in was refused: the answer's status and what the page says.
struct Refused(StatusCode, String);

impl Refused {
    fn too_many(refusal: &Refusal) -> Refused {
        Refused(
            StatusCode::TOO_MANY_REQUESTS,
            if refusal.guesses {
                format!(
                    "Too many codes that are nobody's from your address: such codes are refused for {} more minute(s). Check the code you were given, then try again.",
                    refusal.minutes
                )
            } else {
                format!(
                    "Too many wrong tries of this code from your address: it is refused for {} more minute(s). Check the code you were given, then try again.",
                    refusal.minutes
                )
            },
        )
    }

    fn wrong_code() -> Refused {
        Refused(StatusCode::UNAUTHORIZED, WRONG_CODE.into())
    }
}

/// Code checks at once: each takes a core and 19 MiB for Argon2id, so a burst of
/// sign-ins (or of guesses from many addresses) waits its turn instead of taking the
/// server's memory.
static CODE_CHECKS: LazyLock<Semaphore> =
    LazyLock::new(|| Semaphore::new(std::thread::available_parallelism().map_or(1, usize::from)));

/// How long a sign-in waits for its turn at a code check before it is told to try again.
const CHECK_WAIT: Duration = Duration::from_secs(10);

/// Checks a typed code within the limits. The code's selector is looked up first (no
/// hash is checked), so that the attempt counts as what it is: a try of someone's code
/// or a guess (`limiter`). It counts from the start (taken back if it succeeds), so
/// simultaneous attempts are held to the limit too.
async fn check(
    state: &Arc<AppState>,
    address: IpAddr,
    code: String,
    now: Timestamp,
) -> Result<Result<Member, Refused>, Error> {
    let Some(typed) = codes::read_code(&code) else {
        return Ok(Err(Refused::wrong_code()));
    };
    let secret = typed.secret.clone();
    let found = blocking(state, move |store| store.find_code(typed)).await?;
    let attempt = match &found {
        Some(found) => Attempt::Code(found.selector.clone()),
        None => Attempt::Guess,
    };
    let event = match blocking(state, move |store| {
        limiter::begin(store, address, &attempt, now)
    })
    .await?
    {
        Ok(event) => event,
        Err(refusal) => return Ok(Err(Refused::too_many(&refusal))),
    };
    let Ok(Ok(_turn)) = tokio::time::timeout(CHECK_WAIT, CODE_CHECKS.acquire()).await else {
        return Ok(Err(Refused(
            StatusCode::SERVICE_UNAVAILABLE,
            "Signing in is busy right now: try again in a minute.".into(),
        )));
    };
    let Some(found) = found else {
        // As slowly as a check of a secret takes: a selector of nobody's is not told apart.
        blocking(state, move |_| {
            codes::spend_like_a_check(&secret);
            Ok(())
        })
        .await?;
        return Ok(Err(Refused::wrong_code()));
    };
    match blocking(state, move |store| store.use_code(found, now)).await? {
        CodeCheck::Valid(member) => {
            // The code is spent (a once-only one is gone): the sign-in goes on whatever
            // happens to its count, which leaves the window in time.
            if let Err(err) = blocking(state, move |store| store.forget_event(event)).await {
                tracing::warn!("a sign-in's attempt stays counted: {err}");
            }
            Ok(Ok(member))
        }
        CodeCheck::Refused => Ok(Err(Refused::wrong_code())),
    }
}

pub async fn sign_in(
    State(state): State<Arc<AppState>>,
    parts: Parts,
    form: Result<Form<CodeForm>, FormRejection>,
) -> Result<Response, Error> {
    // Not the page's form (JSON, say, or too long): the page again, saying so.
    let form = match form {
        Ok(Form(form)) => form,
        Err(refused) => {
            let problem = format!(
                "Sign in with the form on this page: the request was not a sign-in form ({}).",
                refused.body_text()
            );
            return render(&state, &Viewer::Anonymous, refused.status(), Some(problem)).await;
        }
    };
    let now = state.clock.now();
    let address = super::address::client_address(&parts, state.behind_https);
    let member = match check(&state, address, form.code, now).await? {
        Ok(member) => member,
        Err(Refused(status, message)) => {
            return render(&state, &Viewer::Anonymous, status, Some(message)).await;
        }
    };
    let course = member.course.clone();
    let earlier = session_key(&parts);
    let key = blocking(&state, move |store| {
        if let Some(earlier) = earlier {
            store.end_session(&earlier)?;
        }
        store.start_session(member.id, now, now + SESSION)
    })
    .await?;
    tracing::info!(course, "signed in");
    let cookie = format!(
        "{SESSION_COOKIE}={key}; Path=/; HttpOnly; SameSite=Lax; Max-Age={}{}",
        SESSION.as_secs(),
        if state.behind_https { "; Secure" } else { "" }
    );
    Ok(([(header::SET_COOKIE, cookie)], Redirect::to("/me")).into_response())
}

pub async fn sign_out(State(state): State<Arc<AppState>>, parts: Parts) -> Result<Response, Error> {
    if let Some(key) = session_key(&parts) {
        blocking(&state, move |store| store.end_session(&key)).await?;
    }
    let cookie = format!(
        "{SESSION_COOKIE}=; Path=/; HttpOnly; SameSite=Lax; Max-Age=0{}",
        if state.behind_https { "; Secure" } else { "" }
    );
    Ok(([(header::SET_COOKIE, cookie)], Redirect::to("/")).into_response())
}
