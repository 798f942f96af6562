//! What a grading of the odometry exercise consists of, from a seed: the test cases of
//! every student function (see [`crate::grading::planned_cases`]), two runs of the path
//! loop with the reference's poses and covariances along them, and the job the JavaScript
//! harness carries out with the student's code.

use super::Odometry;
use super::contract::Call;
use super::generate::{generate, wheel_constants};
use super::grade::grade;
use super::job::PathRun;
use crate::Exercise;
use crate::exercises::Graded;
use crate::grading::{
    ExercisePlan, GradeResult, Job, Outputs, PlannedCase, RunPhase, function_phases, planned_cases,
};
use crate::odometry::{Direction, OdometryParams, Propagation, Shape, propagate};
use crate::rng::Rng;

/// How long the student's code may take over one whole run of the path loop.
pub const RUN_LIMIT_MS: u32 = 5_000;

/// The functions the path loop calls, in the order it calls them at every step.
pub const PATH_FUNCTIONS: [&str; 5] = [
    "pose_jacobian",
    "increment_jacobian",
    "wheel_noise",
    "propagate",
    "odometry_step",
];

/// The part of a seed's random numbers the paths are drawn from (ASCII "path").
const PATHS: u64 = 0x7061_7468;

/// Everything one grading checks, made from the student's seed (and, on the server, a
/// seed of hidden cases).
#[derive(Clone, Debug)]
pub struct Plan {
    pub seed: u64,
    /// The seed of the hidden cases and paths, known to the server only.
    pub hidden: Option<u64>,
    pub cases: Vec<PlannedCase<Call>>,
    pub runs: Vec<PathSpec>,
}

/// A run of the path loop with the student's functions.
#[derive(Clone, Debug)]
pub struct PathSpec {
    /// `square`, `figure-eight`.
    pub name: String,
    /// The path, the robot and its wheels' noise, from an exact start.
    pub params: OdometryParams,
    /// The reference's poses and covariances: the start, then after every step.
    pub reference: Propagation,
}

impl Plan {
    /// The public suite, the variant of `seed`, and two paths drawn from `seed` (from
    /// `hidden` instead when there is one, as on the server), which tell different
    /// mistakes: a square driven counter-clockwise, whose turns on the spot roll the left
    /// wheel backwards (so the wheel noise needs its absolute value), and a figure eight,
    /// whose arcs turn both ways while moving (so the step must follow the heading
    /// halfway through the turn; on the square's straight legs and turns on the spot any
    /// heading gives the same).
    pub fn new(seed: u64, hidden: Option<u64>) -> Plan {
        let mut rng = Rng::substream(hidden.unwrap_or(seed), PATHS);
        let square = path(&mut rng, "square", |rng| Shape::Square {
            side: rounded(rng.uniform_in(1.5, 3.0), 100.0),
            direction: Direction::CounterClockwise,
        });
        let figure_eight = path(&mut rng, "figure-eight", |rng| Shape::FigureEight {
            radius: rounded(rng.uniform_in(0.6, 1.5), 100.0),
        });
        Plan {
            seed,
            hidden,
            cases: planned_cases(generate, seed, hidden),
            runs: vec![square, figure_eight],
        }
    }

    pub fn run(&self, name: &str) -> Option<&PathSpec> {
        self.runs.iter().find(|run| run.name == name)
    }
}

impl ExercisePlan for Plan {
    fn exercise(&self) -> Exercise {
        Exercise::Odometry
    }

    fn seed(&self) -> u64 {
        self.seed
    }

    /// What the harness needs to call the student's code: the arguments of every case (not
    /// the expected outputs) and the wheels of every path (not the reference's poses).
    fn job(&self) -> Job {
        Job {
            functions: function_phases(&self.cases),
            runs: self.runs.iter().map(PathSpec::job).collect(),
        }
    }

    fn grade(&self, outputs: &Outputs) -> GradeResult {
        grade(self, outputs)
    }
}

/// A path of the shape `shape` draws, driven by a robot drawn alike: a wheel base of 0.2
/// to 0.6 m, 0.04 to 0.08 m per step (a few hundred steps), wheel constants of 1e-5 to
/// 1e-2 m, one 1.4 to 3 times the other. Sizes are rounded to centimetres, the speed to
/// millimetres, so that a message shows them as they are.
fn path(rng: &mut Rng, name: &str, shape: impl Fn(&mut Rng) -> Shape) -> PathSpec {
    let wheel_base = rounded(rng.uniform_in(0.2, 0.6), 100.0);
    let speed = rounded(rng.uniform_in(0.04, 0.08), 1000.0);
    let (k_r, k_l) = wheel_constants(rng);
    let params = OdometryParams {
        shape: shape(rng),
        speed,
        wheel_base,
        k_r,
        k_l,
        sigma0: [[0.0; 3]; 3],
    };
    let reference = propagate(&params).expect("the drawn paths are valid");
    PathSpec {
        name: name.to_owned(),
        params,
        reference,
    }
}

/// `value` to the nearest 1 / `per`.
fn rounded(value: f64, per: f64) -> f64 {
    libm::round(value * per) / per
}

impl PathSpec {
    /// The number of steps.
    pub fn steps(&self) -> usize {
        self.reference.path.steps()
    }

    fn job(&self) -> RunPhase {
        let data = PathRun {
            start: self.reference.path.start,
            b: self.params.wheel_base,
            k_r: self.params.k_r,
            k_l: self.params.k_l,
            steps: self
                .reference
                .path
                .increments
                .iter()
                .map(|increment| [increment.right, increment.left])
                .collect(),
        };
        RunPhase::new(
            Odometry::DECLARATION.run_loop,
            &self.name,
            &PATH_FUNCTIONS,
            RUN_LIMIT_MS,
            &data,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every path takes a few hundred steps; the square's turns on the spot roll the left
    /// wheel backwards, which the figure eight never does; and only the figure eight's
    /// steps both move and turn, where the heading a step follows matters.
    #[test]
    fn the_paths_take_a_few_hundred_steps_and_each_tells_its_mistakes() {
        for seed in 1..=200 {
            let plan = Plan::new(seed, None);
            for run in &plan.runs {
                assert!(
                    (80..=700).contains(&run.steps()),
                    "seed {seed}, {}: {} steps",
                    run.name,
                    run.steps()
                );
                let increments = &run.reference.path.increments;
                let backwards = increments.iter().any(|i| i.right < 0.0 || i.left < 0.0);
                let arcs = increments
                    .iter()
                    .any(|i| i.right != i.left && i.right != -i.left);
                let square = run.name == "square";
                assert_eq!(
                    (backwards, arcs),
                    (square, !square),
                    "seed {seed}, {}",
                    run.name
                );
            }
        }
    }
}
