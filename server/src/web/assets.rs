//! The built browser assets (`scripts/build-web` writes them): content-hashed files,
//! served with long cache lifetimes and precompressed, and the manifest that names each
//! page's script and style.

use super::Error;
use super::registry;
use axum::extract::Request;
use axum::http::{HeaderValue, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use serde::Deserialize;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use tower_http::services::ServeDir;

/// `manifest.json`: file names relative to the asset directory.
#[derive(Debug, Deserialize)]
struct Manifest {
    /// The stylesheet of every page.
    style: String,
    /// The script of each page.
    scripts: HashMap<String, String>,
    /// The Web Worker that runs students' code.
    worker: String,
    /// What each page's script needs before it can draw (its chunks, its wasm module),
    /// for the page to ask for at once.
    preloads: HashMap<String, Vec<Preload>>,
}

/// A file a page asks for before its script does.
#[derive(Debug, Deserialize)]
pub struct Preload {
    pub kind: PreloadKind,
    /// Below `/static/`.
    pub path: String,
}

#[derive(Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum PreloadKind {
    /// A chunk the script imports: `<link rel="modulepreload">`.
    Module,
    /// The wasm module the script fetches: `<link rel="preload" as="fetch">`, so that it
    /// downloads beside the script instead of after it.
    Wasm,
}

impl Preload {
    pub fn is_wasm(&self) -> bool {
        self.kind == PreloadKind::Wasm
    }
}

/// What a page links to.
#[derive(Debug)]
pub struct PageAssets<'a> {
    pub style: &'a str,
    pub script: &'a str,
    pub preloads: &'a [Preload],
}

/// The name of the Web Worker that runs students' code starts so.
const WORKER_PREFIX: &str = "student-worker-";

/// The worker compiles the student's file (`new Function`), and nothing else: no network,
/// no further scripts.
const WORKER_POLICY: &str = "default-src 'none'; script-src 'unsafe-eval'";

#[derive(Debug)]
pub struct Assets {
    dir: PathBuf,
    manifest: Manifest,
}

impl Assets {
    /// Reads `manifest.json` in `dir`; an error says how to build the assets when they are
    /// not there.
    pub fn load(dir: &Path) -> Result<Assets, Error> {
        let manifest = dir.join("manifest.json");
        let broken = |problem: String| Error::Assets(format!("{}: {problem}", manifest.display()));
        let text = std::fs::read_to_string(&manifest).map_err(|e| {
            broken(format!(
                "{e}; the browser assets are not built there (scripts/build-web builds them, or pass --static DIR)"
            ))
        })?;
        let manifest: Manifest = serde_json::from_str(&text).map_err(|e| broken(e.to_string()))?;
        for script in registry::scripts() {
            if !manifest.scripts.contains_key(script) {
                return Err(broken(format!(
                    "the script '{script}' of the pages is missing"
                )));
            }
        }
        Ok(Assets {
            dir: dir.to_owned(),
            manifest,
        })
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The path of the Web Worker that runs students' code, below `/static/`.
    pub fn worker(&self) -> &str {
        &self.manifest.worker
    }

    /// The assets of the page of the registry called `name`.
    pub fn page(&self, name: &str) -> PageAssets<'_> {
        let script = &registry::page(name).script;
        PageAssets {
            style: &self.manifest.style,
            script: &self.manifest.scripts[script],
            preloads: self
                .manifest
                .preloads
                .get(script)
                .map_or(&[], Vec::as_slice),
        }
    }
}

/// Every file name carries a hash of its content, so a file never changes under its
/// name and may be cached for a year. The student worker gets a policy of its own.
pub fn service(dir: &Path) -> axum::routing::MethodRouter {
    let files = ServeDir::new(dir).precompressed_br().precompressed_gzip();
    axum::routing::get_service(files).layer(axum::middleware::from_fn(headers))
}

/// The longest path below `/static/` looked for: the built files' are far shorter, and
/// a long enough one fails in the file system (`ENAMETOOLONG`), which would answer 500.
const LONGEST_PATH: usize = 255;

async fn headers(request: Request, next: Next) -> Response {
    if request.uri().path().len() > LONGEST_PATH {
        return StatusCode::NOT_FOUND.into_response();
    }
    let worker = request.uri().path().contains(WORKER_PREFIX);
    let mut response = next.run(request).await;
    if response.status() == StatusCode::OK {
        let headers = response.headers_mut();
        headers.insert(
            header::CACHE_CONTROL,
            HeaderValue::from_static("public, max-age=31536000, immutable"),
        );
        if worker {
            headers.insert(
                header::CONTENT_SECURITY_POLICY,
                HeaderValue::from_static(WORKER_POLICY),
            );
        }
    }
    response
}
