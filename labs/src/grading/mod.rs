//! Grading a student's implementation of an exercise, and what every exercise shares.
//!
//! A [`Plan`] made from the exercise and the student's seed holds the test cases and the
//! runs of the exercise's loop; its [`Plan::job`] goes to the JavaScript harness
//! (`static/src/harness.js`), which calls the student's code in a sandbox (a Web Worker in
//! the browser, QuickJS in a worker process on the server) and reports [`Outputs`];
//! [`Plan::grade`] turns those into a [`GradeResult`]. The browser and the server run the
//! same harness on the same job and grade with this same code, so they reach the same
//! verdict.
//!
//! Shared by every exercise: the [`Contract`] its calls implement, the comparison of
//! outputs ([`compare`]), the suites of cases and their phases ([`planned_cases`]), the
//! tests of the functions ([`function_tests`]), hints, the job, the outputs and the
//! result. What is an exercise's own is under [`crate::exercises`], and this layer names
//! none of them.

mod beliefs;
mod compare;
mod contract;
mod dialect;
mod functions;
mod hints;
pub mod infinity;
mod job;
mod outputs;
mod result;
mod suite;
#[cfg(test)]
pub(crate) mod testing;

pub use beliefs::{BeliefTolerance, Beliefs, STEP_BY_STEP, first_departure, follows};
pub use compare::{
    HEADING_TURNS, Kind, Mismatch, Problem, Shape, Tolerance, compare, heading_within_turns,
    matrix, numbers, pose, range_bearing, repeat,
};
pub use contract::{Case, Contract, matrix_of, rows};
pub use functions::{FunctionVerdicts, function_tests};
pub use hints::{
    Common, Hint, HintKind, Mistake, describe, form_hint, holds_non_finite, negated, the_only,
    transpose,
};
pub use job::{CallJob, FunctionPhase, Job, Phase, PhaseKind, RunPhase};
pub use outputs::{
    CallResult, Cause, FunctionOutput, Outputs, PhaseOutput, Reports, RunOutput, Stopped,
};
pub use result::{Challenge, Failure, GradeResult, POINTS, Status, Subject, Test, Visibility};
pub use suite::{
    CASES_PER_FUNCTION, FUNCTION_LIMIT_MS, Generator, PUBLIC_SEED, PlannedCase, Scenario, Suite,
    cases_of, function_phases, planned_cases, scenario_cases,
};

use crate::Exercise;
use crate::exercises::{Graded, Visit};
use std::any::Any;
use std::fmt::Debug;
use std::sync::Arc;

/// The course a student's variant belongs to unless another is named.
pub const DEFAULT_COURSE: &str = "el2320";

/// The seed of a student's variant: the same for the same course and student, on every
/// machine (FNV-1a over both names), a whole number below 2^53 so JavaScript holds it.
pub fn student_seed(course: &str, student: &str) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in course.bytes().chain([0]).chain(student.trim().bytes()) {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
    hash & ((1 << 53) - 1)
}

/// What a grading on the server draws from its secret, which students never see: the
/// submission's own hidden cases (and runs), and the run its whole class is measured on
/// (the class challenge: the same for every submission of a course, so their figures rank).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Hidden {
    pub cases: u64,
    pub class: u64,
}

/// Everything one grading of an exercise checks, made from the student's seed and, on the
/// server, what it draws from its secret: the exercise's own plan ([`ExercisePlan`]).
#[derive(Clone, Debug)]
pub struct Plan(Arc<dyn ExercisePlan>);

/// An exercise's plan of a grading: its cases and runs, the job they make and the grading
/// of what the harness reported.
pub trait ExercisePlan: Any + Debug + Send + Sync {
    fn exercise(&self) -> Exercise;

    /// The seed of the student's variant.
    fn seed(&self) -> u64;

    /// What the harness carries out with the student's code.
    fn job(&self) -> Job;

    /// Grades what the harness reported; tests whose outputs are missing fail as not run.
    fn grade(&self, outputs: &Outputs) -> GradeResult;
}

/// How much of each data set a grading's runs go through, as fast as the engine that
/// runs the student's code is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Reach {
    /// The first few hundred readings: what an interpreter (QuickJS, Python, Octave) gets
    /// through within its budget, and what the browser checks.
    #[default]
    Prefix,
    /// Every reading (JavaScript on V8).
    Whole,
}

/// The plan of an exercise, made by its [`Graded`](crate::exercises::Graded) type.
struct Planned {
    seed: u64,
    hidden: Option<Hidden>,
    reach: Reach,
}

impl Visit for Planned {
    type Output = Plan;
    fn visit<G: Graded>(self) -> Plan {
        Plan(Arc::new(G::plan(self.seed, self.hidden, self.reach)))
    }
}

impl Plan {
    /// The plan of `exercise` for the variant `seed`; with `hidden`, hidden cases (and
    /// runs) drawn from it besides, as the server grades. Its runs go through the first
    /// readings of each data set ([`Reach::Prefix`]).
    pub fn new(exercise: Exercise, seed: u64, hidden: Option<Hidden>) -> Plan {
        Plan::reaching(exercise, seed, hidden, Reach::Prefix)
    }

    /// The plan, its runs going as far into each data set as `reach` says.
    pub fn reaching(exercise: Exercise, seed: u64, hidden: Option<Hidden>, reach: Reach) -> Plan {
        exercise.visit(Planned {
            seed,
            hidden,
            reach,
        })
    }

    pub fn exercise(&self) -> Exercise {
        self.0.exercise()
    }

    pub fn seed(&self) -> u64 {
        self.0.seed()
    }

    /// What the harness carries out with the student's code.
    pub fn job(&self) -> Job {
        self.0.job()
    }

    /// Grades what the harness reported; tests whose outputs are missing fail as not run.
    pub fn grade(&self, outputs: &Outputs) -> GradeResult {
        self.0.grade(outputs)
    }

    /// The exercise's own plan, when it is an `E` (a view of one exercise's runs asks).
    pub fn of<E: ExercisePlan>(&self) -> Option<&E> {
        let plan: &dyn Any = self.0.as_ref();
        plan.downcast_ref()
    }
}
