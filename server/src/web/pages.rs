//! The pages, each an askama template over the base layout.

use super::assets::PageAssets;
use super::extract::Query;
use super::registry::{self, Group};
use super::viewer::Viewer;
use super::{AppState, Error, blocking};
use crate::datasets::{MrclamEntry, NamedTrial};
use askama::Template;
use axum::Json;
use axum::extract::State;
use axum::http::{HeaderMap, StatusCode, Uri, header};
use axum::response::{Html, IntoResponse, Response};
use labs::exercises::{Declaration, ekf_localization};
use labs::{Exercise, Language};
use std::sync::Arc;

#[derive(Template)]
#[template(path = "home.html")]
struct Home<'a> {
    page: &'a str,
    assets: PageAssets<'a>,
    nav: Nav,
}

#[derive(Template)]
#[template(path = "car.html")]
struct Car<'a> {
    page: &'a str,
    assets: PageAssets<'a>,
    nav: Nav,
}

#[derive(Template)]
#[template(path = "odometry.html")]
struct Odometry<'a> {
    page: &'a str,
    assets: PageAssets<'a>,
    nav: Nav,
}

#[derive(Template)]
#[template(path = "fusion.html")]
struct Fusion<'a> {
    page: &'a str,
    assets: PageAssets<'a>,
    nav: Nav,
    /// How many of the report's trials the server was given (`--datasets`).
    real_trials: usize,
    /// The languages `tuning()` can be copied in: (name, title).
    languages: Vec<(&'static str, &'static str)>,
}

#[derive(Template)]
#[template(path = "mrclam.html")]
struct Mrclam<'a> {
    page: &'a str,
    assets: PageAssets<'a>,
    nav: Nav,
    /// How many robots of the MRCLAM data sets the server was given (`--datasets`).
    real_robots: usize,
}

#[derive(Template)]
#[template(path = "ekf.html")]
struct Ekf<'a> {
    page: &'a str,
    assets: PageAssets<'a>,
    nav: Nav,
    /// The views of a whole run, as the exercise's workbench shows a student's.
    plots: &'static str,
}

#[derive(Template)]
#[template(path = "code.html")]
struct Code<'a> {
    page: &'a str,
    assets: PageAssets<'a>,
    nav: Nav,
    exercise: Exercise,
    declared: &'static Declaration,
    /// The workbench's own path, which its links go back to.
    path: &'a str,
    worker: &'a str,
    /// The languages a student may write the file in, each with its starter.
    languages: Vec<Written>,
}

/// A language of the workbench, as its choice and its starter show it.
struct Written {
    name: &'static str,
    title: &'static str,
    /// Its files' extension, which the upload's choice of files accepts.
    extension: &'static str,
    starter: &'static str,
}

#[derive(Template)]
#[template(path = "not_found.html")]
struct NotFound<'a> {
    page: &'a str,
    assets: PageAssets<'a>,
    nav: Nav,
    path: &'a str,
}

/// What the header shows: the pages of the navigation, and who is signed in.
pub struct Nav {
    /// Every page of the registry in its group (those with a `nav` title are linked).
    pub groups: &'static [Group],
    /// Whether the server runs courses (else submitting is open to anyone).
    pub courses: bool,
    /// The signed-in person's name (or id) and course.
    pub member: Option<(String, String)>,
}

impl Nav {
    /// The site's facts for the pages' scripts (JSON).
    pub fn site(&self) -> &'static str {
        registry::site()
    }

    pub async fn of(state: &AppState, viewer: &Viewer) -> Result<Nav, Error> {
        if let Some(member) = viewer.member() {
            let name = if member.name.is_empty() {
                member.login.clone()
            } else {
                member.name.clone()
            };
            return Ok(Nav {
                groups: registry::groups(),
                courses: true,
                member: Some((name, member.course.clone())),
            });
        }
        Ok(Nav {
            groups: registry::groups(),
            courses: blocking(state, |store| store.any_course()).await?,
            member: None,
        })
    }
}

/// A rendered page that browsers revalidate before they reuse it.
pub fn html(template: &impl Template) -> Result<Response, Error> {
    Ok((
        [(header::CACHE_CONTROL, "no-cache")],
        Html(template.render()?),
    )
        .into_response())
}

pub async fn home(State(state): State<Arc<AppState>>, viewer: Viewer) -> Result<Response, Error> {
    html(&Home {
        page: "home",
        assets: state.assets.page("home"),
        nav: Nav::of(&state, &viewer).await?,
    })
}

pub async fn car(State(state): State<Arc<AppState>>, viewer: Viewer) -> Result<Response, Error> {
    html(&Car {
        page: "car",
        assets: state.assets.page("car"),
        nav: Nav::of(&state, &viewer).await?,
    })
}

pub async fn odometry(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
) -> Result<Response, Error> {
    html(&Odometry {
        page: "odometry",
        assets: state.assets.page("odometry"),
        nav: Nav::of(&state, &viewer).await?,
    })
}

pub async fn fusion(State(state): State<Arc<AppState>>, viewer: Viewer) -> Result<Response, Error> {
    html(&Fusion {
        page: "fusion",
        assets: state.assets.page("fusion"),
        nav: Nav::of(&state, &viewer).await?,
        real_trials: state.datasets.northstar.len(),
        languages: Language::ALL
            .iter()
            .map(|language| (language.name(), language.title()))
            .collect(),
    })
}

/// The Northstar report's trials the server was given, for the fusion page (none without
/// `--datasets`). Anyone may read them: the pages that show them are public.
pub async fn northstar_trials(State(state): State<Arc<AppState>>) -> Json<Vec<NamedTrial>> {
    Json(state.datasets.northstar.clone())
}

pub async fn mrclam(State(state): State<Arc<AppState>>, viewer: Viewer) -> Result<Response, Error> {
    html(&Mrclam {
        page: "mrclam",
        assets: state.assets.page("mrclam"),
        nav: Nav::of(&state, &viewer).await?,
        real_robots: state.datasets.mrclam.len(),
    })
}

/// The robots of the MRCLAM data sets the server was given (none without `--datasets`).
/// Public, as the page that shows them is.
pub async fn mrclam_robots(State(state): State<Arc<AppState>>) -> Json<Vec<MrclamEntry>> {
    Json(state.datasets.mrclam.iter().map(|r| r.entry).collect())
}

/// Which robot of which MRCLAM data set: `?dataset=6&robot=1`.
#[derive(serde::Deserialize)]
pub struct MrclamQuery {
    dataset: u32,
    robot: u32,
}

/// One robot's recording on the grid, with the noise learned from it and the room's
/// posts, gzipped when the browser takes it so; 404 for a robot the server was not
/// given.
pub async fn mrclam_robot(
    State(state): State<Arc<AppState>>,
    Query(MrclamQuery { dataset, robot }): Query<MrclamQuery>,
    headers: HeaderMap,
) -> Result<Response, Error> {
    let found = state
        .datasets
        .mrclam_robot(dataset, robot)
        .ok_or_else(|| Error::NotFound(format!("robot {robot} of MRCLAM data set {dataset}")))?;
    let gzip = headers
        .get_all(header::ACCEPT_ENCODING)
        .iter()
        .filter_map(|value| value.to_str().ok())
        .flat_map(|value| value.split(','))
        .any(|coding| {
            // gzip, unless refused by a weight of 0 ("gzip;q=0").
            let mut parts = coding.split(';').map(str::trim);
            parts.next() == Some("gzip") && !parts.any(|p| p.replace(' ', "") == "q=0")
        });
    let vary = (header::VARY, "accept-encoding");
    let json = (header::CONTENT_TYPE, "application/json");
    Ok(if gzip {
        let encoding = (header::CONTENT_ENCODING, "gzip");
        ([json, encoding, vary], found.gzip.clone()).into_response()
    } else {
        ([json, vary], found.json.clone()).into_response()
    })
}

pub async fn ekf(State(state): State<Arc<AppState>>, viewer: Viewer) -> Result<Response, Error> {
    html(&Ekf {
        page: "ekf",
        assets: state.assets.page("ekf"),
        nav: Nav::of(&state, &viewer).await?,
        plots: ekf_localization::RUN_PLOTS,
    })
}

/// The workbench of an exercise.
pub async fn workbench(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    exercise: Exercise,
) -> Result<Response, Error> {
    let page = registry::workbench(exercise);
    html(&Code {
        page: &page.name,
        assets: state.assets.page(&page.name),
        nav: Nav::of(&state, &viewer).await?,
        exercise,
        declared: exercise.declaration(),
        path: &page.path,
        worker: state.assets.worker(),
        languages: Language::ALL
            .iter()
            .map(|&language| Written {
                name: language.name(),
                title: language.title(),
                extension: language.extension(),
                starter: exercise.declaration().starter(language),
            })
            .collect(),
    })
}

/// An exercise's starter file in a language, on its own, to download.
pub async fn starter(exercise: Exercise, language: Language) -> Response {
    let media_type = match language {
        Language::JavaScript => "text/javascript; charset=utf-8",
        Language::Python => "text/x-python; charset=utf-8",
        Language::Matlab => "text/x-matlab; charset=utf-8",
    };
    (
        [
            (header::CONTENT_TYPE, media_type),
            (header::CACHE_CONTROL, "no-cache"),
        ],
        exercise.declaration().starter(language),
    )
        .into_response()
}

pub async fn not_found(
    State(state): State<Arc<AppState>>,
    viewer: Viewer,
    uri: Uri,
) -> Result<Response, Error> {
    let page = NotFound {
        page: "",
        assets: state.assets.page("home"),
        nav: Nav::of(&state, &viewer).await?,
        path: uri.path(),
    };
    Ok((StatusCode::NOT_FOUND, html(&page)?).into_response())
}

/// The site's icon: a belief (an ellipse) round an estimate.
pub async fn icon() -> Response {
    const ICON: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 32 32"><ellipse cx="16" cy="16" rx="13" ry="8" transform="rotate(-30 16 16)" fill="none" stroke="#c62828" stroke-width="3"/><circle cx="16" cy="16" r="3.5" fill="#1d2125"/></svg>"##;
    (
        [
            (header::CONTENT_TYPE, "image/svg+xml"),
            (header::CACHE_CONTROL, "public, max-age=86400"),
        ],
        ICON,
    )
        .into_response()
}
