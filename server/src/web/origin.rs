//! Requests that change anything (submitting, signing in and out, staff actions) are
//! taken only from estlab's own pages, so that a page on another site cannot act in a
//! signed-in person's name. Browsers say where a request comes from in
//! `Sec-Fetch-Site` (all current ones) or `Origin` (every POST from a page); a request
//! with neither comes from a program, not from a page (a script with an API token, curl),
//! and rides on no one's cookie.

use super::Error;
use axum::extract::Request;
use axum::http::{HeaderMap, Method, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

pub async fn same_origin_only(request: Request, next: Next) -> Response {
    let safe = matches!(
        *request.method(),
        Method::GET | Method::HEAD | Method::OPTIONS
    );
    if !safe && let Err(refused) = check(request.headers()) {
        return refused.into_response();
    }
    next.run(request).await
}

fn check(headers: &HeaderMap) -> Result<(), Error> {
    let text = |name| headers.get(name).and_then(|v| v.to_str().ok());
    if let Some(site) = text("sec-fetch-site") {
        return match site {
            "same-origin" | "none" => Ok(()),
            other => Err(refused(&format!("Sec-Fetch-Site: {other}"))),
        };
    }
    let Some(origin) = text(header::ORIGIN.as_str()) else {
        return Ok(());
    };
    let host = text(header::HOST.as_str()).unwrap_or("");
    let authority = origin
        .strip_prefix("https://")
        .or_else(|| origin.strip_prefix("http://"));
    if authority.is_some_and(|authority| authority.eq_ignore_ascii_case(host)) {
        Ok(())
    } else {
        Err(refused(&format!("Origin: {origin}")))
    }
}

fn refused(what: &str) -> Error {
    Error::Forbidden(format!(
        "refused: this request came from another site ({what}); estlab takes changes only from its own pages"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use axum::http::HeaderValue;

    fn headers(pairs: &[(&'static str, &'static str)]) -> HeaderMap {
        let mut map = HeaderMap::new();
        for (name, value) in pairs {
            map.insert(*name, HeaderValue::from_static(value));
        }
        map
    }

    #[test]
    fn own_pages_and_programs_pass_other_sites_do_not() {
        let host = ("host", "estlab.example:8080");
        assert!(check(&headers(&[host, ("sec-fetch-site", "same-origin")])).is_ok());
        assert!(check(&headers(&[host, ("origin", "http://estlab.example:8080")])).is_ok());
        assert!(check(&headers(&[host])).is_ok());
        for refused in [
            headers(&[host, ("sec-fetch-site", "cross-site")]),
            headers(&[host, ("sec-fetch-site", "same-site")]),
            headers(&[host, ("origin", "http://evil.example")]),
            headers(&[host, ("origin", "null")]),
            headers(&[host, ("origin", "http://estlab.example:8080.evil.example")]),
        ] {
            let error = check(&refused).unwrap_err();
            assert!(error.to_string().contains("another site"), "{error}");
        }
    }
}
