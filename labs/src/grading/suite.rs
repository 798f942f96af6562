//! The test cases of a grading, for any exercise: the public suite every student shares,
//! the student's own variant (from their seed) and, on the server, hidden cases; and the
//! phases of the job that call the student's functions on them.

use super::contract::{Case, Contract};
use super::job::{CallJob, FunctionPhase};
use crate::rng::Rng;
use serde::{Deserialize, Serialize};

/// The seed of the public suite, the same for every student.
pub const PUBLIC_SEED: u64 = 2320;
/// Cases of each function in the public suite, in the student's variant and hidden.
pub const CASES_PER_FUNCTION: usize = 6;
/// How long the student's code may take over all the cases of one function.
pub const FUNCTION_LIMIT_MS: u32 = 2_000;

/// Where a case comes from, which decides what the student is shown of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Suite {
    /// The same for every student, shown in full.
    Public,
    /// The student's own variant (from their seed), shown in full.
    Variant,
    /// Drawn from the server's secret for this submission: a failure shows its hint, not
    /// its arguments or expected outputs.
    Hidden,
}

impl Suite {
    /// The mark in a case's id: `predict/p3`, `predict/s3`, `predict/h3`.
    fn mark(self) -> &'static str {
        match self {
            Suite::Public => "p",
            Suite::Variant => "s",
            Suite::Hidden => "h",
        }
    }
}

/// A case of the plan and the suite it belongs to.
#[derive(Clone, Debug)]
pub struct PlannedCase<C> {
    pub suite: Suite,
    pub case: Case<C>,
}

/// An exercise's case generator: `per_function` cases of every function from a seed, with
/// ids `function/number`.
pub type Generator<C> = fn(seed: u64, per_function: usize) -> Vec<Case<C>>;

/// A kind of case of one function: what it is about ("a landmark behind the robot"), and
/// a call of that kind drawn at random.
pub type Scenario<C> = (&'static str, fn(&mut Rng) -> C);

/// `per_function` cases of every function from `seed`: each function's cases cycle
/// through its scenarios (given in the contract's order), drawn from a random stream of
/// the function's own, so that changing one function's scenarios leaves the others'
/// cases as they were; each expects the reference's answer.
pub fn scenario_cases<C: Contract>(
    seed: u64,
    per_function: usize,
    scenarios: &[(&str, &[Scenario<C>])],
) -> Vec<Case<C>> {
    let mut cases = Vec::new();
    for (part, (function, kinds)) in scenarios.iter().enumerate() {
        let mut rng = Rng::substream(seed, part as u64 + 1);
        for k in 0..per_function {
            let (note, make) = kinds[k % kinds.len()];
            let call = make(&mut rng);
            let expected = call.reference_output().expect("generated calls are valid");
            cases.push(Case {
                id: format!("{function}/{}", k + 1),
                note: note.to_owned(),
                call,
                expected,
            });
        }
    }
    cases
}

/// The public suite, the variant of `seed` and the hidden cases of `hidden` (when there
/// is a secret), ordered by function as the contract lists them.
pub fn planned_cases<C: Contract>(
    generate: Generator<C>,
    seed: u64,
    hidden: Option<u64>,
) -> Vec<PlannedCase<C>> {
    let mut cases = suite(generate, PUBLIC_SEED, Suite::Public);
    cases.extend(suite(generate, seed, Suite::Variant));
    if let Some(hidden) = hidden {
        cases.extend(suite(generate, hidden, Suite::Hidden));
    }
    cases.sort_by_key(|planned| {
        C::FUNCTIONS
            .iter()
            .position(|f| *f == planned.case.call.function())
    });
    cases
}

/// The cases of one seed, their ids marked with the suite (`predict/p3` is public,
/// `predict/s3` the student's own, `predict/h3` hidden).
fn suite<C: Contract>(generate: Generator<C>, seed: u64, suite: Suite) -> Vec<PlannedCase<C>> {
    generate(seed, CASES_PER_FUNCTION)
        .into_iter()
        .map(|mut case| {
            let (function, number) = case.id.split_once('/').expect("ids are function/number");
            case.id = format!("{function}/{}{number}", suite.mark());
            PlannedCase { suite, case }
        })
        .collect()
}

/// The cases of one function.
pub fn cases_of<'a, C: Contract>(
    cases: &'a [PlannedCase<C>],
    function: &'a str,
) -> impl Iterator<Item = &'a PlannedCase<C>> + 'a {
    cases
        .iter()
        .filter(move |planned| planned.case.call.function() == function)
}

/// A phase per function: the arguments of its cases (never the expected outputs).
pub fn function_phases<C: Contract>(cases: &[PlannedCase<C>]) -> Vec<FunctionPhase> {
    C::FUNCTIONS
        .iter()
        .map(|&function| FunctionPhase {
            function: function.to_owned(),
            calls: cases_of(cases, function)
                .map(|PlannedCase { case, .. }| CallJob {
                    id: case.id.clone(),
                    args: case.call.arguments(),
                })
                .collect(),
            limit_ms: FUNCTION_LIMIT_MS,
        })
        .collect()
}
