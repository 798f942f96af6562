//! Grading in the browser: the same plan, the same comparison and the same result as on
//! the server, from the same seed. The student's code runs in a Web Worker, driven by
//! the harness with the job written here; its outputs come back to `grade`. What an
//! exercise's workbench draws of its runs is the exercise's own (its folder's `wasm.rs`,
//! more methods of [`Grader`]).

use super::{exercise, from_json, seed};
use labs::Language;
use labs::grading::{self, Plan, Reach, Reports};
use wasm_bindgen::prelude::*;

/// The seed of a student's own variant within a course, as the server computes it.
#[wasm_bindgen(js_name = studentSeed)]
pub fn student_seed(course: &str, student: &str) -> f64 {
    grading::student_seed(course, student) as f64
}

/// Everything one grading of an exercise checks, made from a seed.
#[wasm_bindgen]
pub struct Grader {
    plan: Plan,
}

#[wasm_bindgen]
impl Grader {
    /// The grader of the exercise `lab` (by name) for the variant `seed_value`.
    #[wasm_bindgen(constructor)]
    pub fn new(lab: &str, seed_value: f64) -> Result<Grader, JsError> {
        Ok(Grader {
            plan: Plan::new(exercise(lab)?, seed(seed_value)?, None),
        })
    }

    /// The grader of `lab` for the variant `seed_value` whose runs go through the whole
    /// of each data set, as a student's report shows them.
    pub fn whole(lab: &str, seed_value: f64) -> Result<Grader, JsError> {
        Ok(Grader {
            plan: Plan::reaching(exercise(lab)?, seed(seed_value)?, None, Reach::Whole),
        })
    }

    /// What the harness needs (JSON): every call's arguments and every run's data.
    pub fn job(&self) -> String {
        serde_json::to_string(&self.plan.job()).expect("jobs serialise")
    }

    /// The result (JSON) for the harness's outputs (JSON: `{ functions, runs }`, each
    /// phase's report as the worker gave it) of a file in `language` (whose terms its
    /// hints use); functions and runs missing from the outputs fail as not run, and a
    /// report that does not read fails its phase, as on the server.
    pub fn grade(&self, outputs: &str, language: &str) -> Result<String, JsError> {
        let reports: Reports = from_json("outputs", outputs)?;
        let language: Language = language.parse()?;
        let result = self.plan.grade(&reports.outputs()).in_language(language);
        Ok(serde_json::to_string(&result).expect("results serialise"))
    }
}

impl Grader {
    /// The plan, for an exercise's own views of its runs (its folder's `wasm.rs`).
    pub(crate) fn plan(&self) -> &Plan {
        &self.plan
    }
}
