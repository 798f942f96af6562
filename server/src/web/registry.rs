//! The registry of the site's pages: those of `static/pages.json` (each page's path, the
//! script the asset build bundles for it, which `static/build.mjs` reads from the same
//! file, its link in the navigation, its card on the home page) and every exercise's
//! workbench, made from the exercise's declaration and placed after the exercise's
//! experiment page. The router serves every page of the registry ([`MethodRouter`]s by
//! name, in `web::router`), and a test checks that each has a handler.

use labs::grading::DEFAULT_COURSE;
use labs::{Exercise, Language};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::LazyLock;
use ts_rs::TS;

const REGISTRY: &str = include_str!("../../../static/pages.json");

/// The file (its `about` says what it is for, to a person reading it).
#[derive(Debug, Deserialize)]
struct Registry {
    pages: Vec<Page>,
}

/// A page of the site.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Page {
    /// How the server's code names it.
    pub name: String,
    /// Its route (axum's syntax: `/courses/{course}/{lab}`).
    pub path: String,
    /// Its script in the asset manifest (`static/src/pages/<script>.js`).
    pub script: String,
    /// Its link in the site's navigation, if it has one.
    #[serde(default)]
    pub nav: Option<String>,
    /// Its card on the home page, if it has one.
    #[serde(default)]
    pub card: Option<Card>,
    /// For a workbench: the exercise whose functions it tests and submits.
    #[serde(skip)]
    pub exercise: Option<Exercise>,
}

/// Every workbench's script, `static/src/pages/code.js`.
const WORKBENCH_SCRIPT: &str = "code";

impl Page {
    /// The workbench of an exercise, as its declaration describes it.
    fn workbench(exercise: Exercise) -> Page {
        let declared = &exercise.declaration().workbench;
        Page {
            name: format!("{exercise}-code"),
            path: declared.path.to_owned(),
            script: WORKBENCH_SCRIPT.to_owned(),
            nav: Some(declared.nav.to_owned()),
            card: Some(Card {
                title: declared.heading.to_owned(),
                text: declared.card.to_owned(),
            }),
            exercise: Some(exercise),
        }
    }
}

impl Page {
    /// A workbench's starter file in `language`, to download: `/ekf/starter.js` (and
    /// `/ekf/starter.py`) beside `/ekf/code`.
    pub fn starter_path(&self, language: Language) -> Option<String> {
        self.exercise?;
        let folder = self.path.strip_suffix("/code")?;
        Some(format!("{folder}/starter.{}", language.extension()))
    }
}

/// A page's card on the home page.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Card {
    pub title: String,
    /// Text, with formulas between `\(` and `\)` for KaTeX.
    pub text: String,
}

static PAGES: LazyLock<Vec<Page>> = LazyLock::new(|| {
    let registry: Registry = serde_json::from_str(REGISTRY)
        .unwrap_or_else(|e| panic!("static/pages.json does not read: {e}"));
    let mut pages = Vec::new();
    for page in registry.pages {
        let path = page.path.clone();
        pages.push(page);
        pages.extend(
            Exercise::ALL
                .iter()
                .filter(|exercise| exercise.declaration().workbench.experiments == path)
                .map(|&exercise| Page::workbench(exercise)),
        );
    }
    pages
});

/// Every page, in the order of the navigation and the home page.
pub fn pages() -> &'static [Page] {
    &PAGES
}

/// Pages the navigation and the home page show together: an exercise's experiment page
/// with its workbench, or a page on its own.
#[derive(Debug)]
pub struct Group {
    pub pages: Vec<&'static Page>,
}

impl Group {
    /// The group's first page: the experiment page, or the page on its own.
    pub fn lead(&self) -> &'static Page {
        self.pages[0]
    }

    /// The workbenches of the group (after its lead).
    pub fn rest(&self) -> &[&'static Page] {
        &self.pages[1..]
    }
}

static GROUPS: LazyLock<Vec<Group>> = LazyLock::new(|| {
    let mut groups: Vec<Group> = Vec::new();
    for page in pages() {
        match groups.last_mut() {
            Some(group) if page.exercise.is_some() => group.pages.push(page),
            _ => groups.push(Group { pages: vec![page] }),
        }
    }
    groups
});

/// What the pages' scripts learn from the server rather than repeat: the course a variant
/// belongs to unless another is named, and every exercise's texts. Each page carries it
/// (`base.html`, read by `static/src/site.js`).
#[derive(Serialize, TS)]
pub(super) struct Site {
    course: &'static str,
    exercises: BTreeMap<&'static str, ExerciseTexts>,
}

#[derive(Serialize, TS)]
pub(super) struct ExerciseTexts {
    title: &'static str,
    /// Its workbench's path.
    workbench: &'static str,
    /// What the server's runs did, with `{whose}` for whose code it ran.
    hidden_runs: &'static str,
}

static SITE: LazyLock<String> = LazyLock::new(|| {
    let site = Site {
        course: DEFAULT_COURSE,
        exercises: Exercise::ALL
            .iter()
            .map(|exercise| {
                let declared = exercise.declaration();
                let texts = ExerciseTexts {
                    title: declared.title,
                    workbench: declared.workbench.path,
                    hidden_runs: declared.runs.hidden,
                };
                (declared.name, texts)
            })
            .collect(),
    };
    // Inside a script element: no "</" can end it early.
    serde_json::to_string(&site)
        .expect("the site serialises")
        .replace('<', "\\u003c")
});

/// The site's facts for the pages' scripts, as JSON to put in a script element.
pub fn site() -> &'static str {
    &SITE
}

/// Every page in its group, in the order of the navigation and the home page.
pub fn groups() -> &'static [Group] {
    &GROUPS
}

/// The page called `name`.
pub fn page(name: &str) -> &'static Page {
    pages()
        .iter()
        .find(|page| page.name == name)
        .unwrap_or_else(|| panic!("static/pages.json has no page {name:?}"))
}

/// The workbench of an exercise.
pub fn workbench(exercise: Exercise) -> &'static Page {
    pages()
        .iter()
        .find(|page| page.exercise == Some(exercise))
        .unwrap_or_else(|| {
            panic!(
                "no workbench of {exercise}: its experiment page is not a page of static/pages.json"
            )
        })
}

/// The scripts of the pages, each once.
pub fn scripts() -> Vec<&'static str> {
    let mut scripts: Vec<&str> = Vec::new();
    for page in pages() {
        if !scripts.contains(&page.script.as_str()) {
            scripts.push(&page.script);
        }
    }
    scripts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_exercise_has_one_workbench_and_names_are_unique() {
        for &exercise in Exercise::ALL {
            let workbenches = pages()
                .iter()
                .filter(|page| page.exercise == Some(exercise))
                .count();
            assert_eq!(workbenches, 1, "{exercise}");
            for &language in Language::ALL {
                assert!(workbench(exercise).starter_path(language).is_some());
            }
        }
        for (i, page) in pages().iter().enumerate() {
            assert!(
                pages()[..i].iter().all(|other| other.name != page.name),
                "{} twice",
                page.name
            );
            assert!(page.path.starts_with('/'), "{}", page.path);
        }
    }
}
