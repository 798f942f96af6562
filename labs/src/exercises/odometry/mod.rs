//! Odometry and how its error grows: the student contract (five functions: one step of
//! odometry, its two Jacobians, the wheels' noise and one step of covariance propagation;
//! `web/starter.js`, `README.md`), its case generator, the hints for its classic
//! mistakes, and the runs of the harness's path loop (`web/loop.js`), held to the reference's poses and
//! covariances along a square and a figure eight. The reference answers all come from
//! the model in [`crate::odometry`].

mod contract;
mod generate;
mod grade;
mod hints;
mod job;
mod plan;

pub use contract::{Call, FUNCTIONS, Mat2, Mat3, Mat3x2, Vec3};
pub use generate::generate;
pub use grade::grade;
pub use hints::HintKind;
pub use job::{PathRecord, PathRun};
pub use plan::{PATH_FUNCTIONS, PathSpec, Plan, RUN_LIMIT_MS};

/// A test case of this exercise.
pub type Case = crate::grading::Case<Call>;

use crate::exercises::interface::MatlabConventions;
use crate::exercises::{Declaration, Graded, Runs, Starters, Workbench};
use crate::grading::{Hidden, Reach};

/// The exercise, as the registry knows it.
pub struct Odometry;

impl Graded for Odometry {
    const DECLARATION: Declaration = Declaration {
        name: "odometry",
        title: "Odometry and its error propagation",
        file_name: "odometry.js",
        run_loop: "path",
        runs: Runs {
            noun: "paths",
            hidden: "drove {whose} functions along paths",
            graded: "drives your functions along whole paths against the reference",
        },
        workbench: Workbench {
            path: "/odometry/code",
            heading: "Your odometry",
            nav: "Your odometry code",
            card: "Write the step of odometry, its two Jacobians, the wheels' noise and the \
                   propagation of the pose's covariance in JavaScript: run them on test cases \
                   made for you and along the paths the grader drives, with a hint where a \
                   classic mistake explains a failure, and submit them to be graded.",
            intro: include_str!("web/intro.html"),
            run_button: "Run paths",
            runs_heading: "Your odometry along the paths",
            run_choice: "Path",
            run_view: include_str!("web/run_view.html"),
            experiments: "/odometry",
        },
        functions: "one step of odometry, its Jacobians with respect to the pose and to the \
                    wheels' distances, the wheels' noise, and one step of the propagation of \
                    the pose's covariance",
        starter_template: include_str!("web/starter.txt"),
        starters: Starters {
            javascript: include_str!("web/starter.js"),
            python: include_str!("web/starter.py"),
            matlab: include_str!("web/starter.m"),
        },
        harness_loop: include_str!("web/loop.js"),
        matlab: MatlabConventions::NONE,
        questions: &[include_str!("questions/questions.toml")],
        report: &[],
    };
    type Call = Call;
    type Plan = Plan;
    type Run = job::PathRun;
    type Record = job::PathRecord;
    const GENERATE: crate::grading::Generator<Call> = generate;

    /// Its paths are a few hundred steps: whole whatever the reach.
    fn plan(seed: u64, hidden: Option<Hidden>, _: Reach) -> Plan {
        Plan::new(seed, hidden.map(|h| h.cases))
    }
}
