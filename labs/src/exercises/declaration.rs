//! What an exercise declares once, in its folder, for everything that lists exercises:
//! its names and texts ([`Declaration`]) and its types ([`Graded`]).

use super::interface::MatlabConventions;
use crate::Language;
use crate::grading::{Contract, ExercisePlan, Generator, Hidden, Reach};
use ts_rs::TS;

/// An exercise's names and texts, and its JavaScript: the pages, the workbench, the
/// platforms' packages, the harness and the command line read them from here.
#[derive(Debug)]
pub struct Declaration {
    /// `odometry`: the name the API, the command line, the store and the packages use.
    pub name: &'static str,
    /// What a person calls it: "Odometry and its error propagation".
    pub title: &'static str,
    /// The student's file, as the workbench downloads it and the packages look for it.
    pub file_name: &'static str,
    /// The harness's loop its runs go to (the `loop` of its run phases): `path`.
    pub run_loop: &'static str,
    /// What its runs are, in words.
    pub runs: Runs,
    pub workbench: Workbench,
    /// What the student writes, in words, as the platforms' question lists it: "one step
    /// of odometry, its Jacobians, ...".
    pub functions: &'static str,
    /// The template of the files a student starts from (`web/starter.txt`: see
    /// [`super::starter`]): every function of the contract, each throwing "not
    /// implemented", and the conventions in each language.
    pub starter_template: &'static str,
    /// The starters it makes, as committed: `web/starter.js`, `web/starter.py`,
    /// `web/starter.m`.
    pub starters: Starters,
    /// The harness's loop for its runs (`web/loop.js`), which registers itself with the
    /// harness under [`Declaration::run_loop`] before any student code runs.
    pub harness_loop: &'static str,
    /// Where the lab's MATLAB functions differ from the contract.
    pub matlab: MatlabConventions,
    /// The written questions an assignment of the exercise starts with, each set a TOML
    /// file of `questions/` (the server's `courses::questions` reads them), in order.
    pub questions: &'static [&'static str],
    /// The runs of its loop a student's report shows, each run on the whole of its data
    /// set with the student's code and a box for their analysis beside it, in order (the
    /// lab's report of four runs); none when the exercise asks for no report.
    pub report: &'static [ReportRun],
}

/// A run of the exercise's loop that a student's report shows.
#[derive(Debug)]
pub struct ReportRun {
    /// The run's name in the plan: `o3/sequential`.
    pub run: &'static str,
    /// What the report calls it: "o3, sequential update".
    pub title: &'static str,
    /// What the student is asked to analyse beside it (Markdown).
    pub ask: &'static str,
}

/// An exercise's starter file in each language.
#[derive(Debug)]
pub struct Starters {
    pub javascript: &'static str,
    pub python: &'static str,
    pub matlab: &'static str,
}

impl Declaration {
    /// The file a student starts from in `language`.
    pub fn starter(&self, language: Language) -> &'static str {
        match language {
            Language::JavaScript => self.starters.javascript,
            Language::Python => self.starters.python,
            Language::Matlab => self.starters.matlab,
        }
    }
}

/// An exercise's runs of its loop, in words.
#[derive(Debug)]
pub struct Runs {
    /// "paths", "data sets": what a result graded without hidden cases has not run on.
    pub noun: &'static str,
    /// What the server's runs did, for the student's view of a result, with `{whose}`
    /// for "your" or "the student's": "drove {whose} functions along paths".
    pub hidden: &'static str,
    /// What the grader does with the runs, for the platforms' question: "drives your
    /// functions along whole paths against the reference".
    pub graded: &'static str,
}

/// The exercise's workbench page, where students write and run their code.
#[derive(Debug)]
pub struct Workbench {
    /// `/odometry/code`.
    pub path: &'static str,
    /// Its heading and title: "Your odometry".
    pub heading: &'static str,
    /// Its link in the site's navigation.
    pub nav: &'static str,
    /// Its card on the home page, a paragraph that may hold TeX (`\(R\)`).
    pub card: &'static str,
    /// What the student does here: HTML, the paragraph under the heading.
    pub intro: &'static str,
    /// The label of the button that runs the student's code on the runs: "Run paths".
    pub run_button: &'static str,
    /// The heading of the runs' section: "Your odometry along the paths".
    pub runs_heading: &'static str,
    /// What the runs' choice is called: "Path".
    pub run_choice: &'static str,
    /// The markup the workbench's view of a run (`web/workbench.js`) draws into, under the
    /// runs' choice (from `web/`: odometry's `run_view.html`, the EKF's summary and
    /// `plots.html`).
    pub run_view: &'static str,
    /// The exercise's experiment page, which the workbench links to and the navigation
    /// groups with it: `/odometry`.
    pub experiments: &'static str,
}

/// An exercise's types: its calls (and with them its mistakes) and its plan. The registry reaches an
/// exercise through these; nothing outside its folder names them.
pub trait Graded: 'static {
    const DECLARATION: Declaration;
    /// One call of one of its student functions.
    type Call: Contract;
    /// Everything one grading checks.
    type Plan: ExercisePlan;
    /// The data of one run of its loop (in a [`RunPhase`](crate::grading::RunPhase)) and
    /// what the loop records, which the loop in `web/loop.js` reads and writes: the browser's
    /// scripts are checked against their TypeScript declarations.
    type Run: TS + 'static;
    type Record: TS + 'static;
    /// Test cases of every student function from a seed.
    const GENERATE: Generator<Self::Call>;

    /// The plan of the variant `seed`; with `hidden`, hidden cases (and runs) drawn from it
    /// besides, as the server grades (and, for an exercise with a class challenge, the
    /// class's held-out run). Its runs go as far into their data as `reach` says (an
    /// exercise whose runs are short runs them whole either way).
    fn plan(seed: u64, hidden: Option<Hidden>, reach: Reach) -> Self::Plan;
}

/// Something done with an exercise's [`Graded`] type, whichever exercise it is
/// ([`super::Exercise::visit`]).
pub trait Visit {
    type Output;
    fn visit<G: Graded>(self) -> Self::Output;
}
