//! Fusing odometry with an indoor positioning sensor: the student contract (seven
//! functions: the pose from two platforms, the heading's standard deviation by error
//! propagation, the measurement noise, the field of view, the prediction from odometry
//! increments, the gate's Mahalanobis distance and the update; `web/starter.js`,
//! `README.md`), its case generator, the hints for its classic mistakes, and the runs of
//! the harness's fusion loop (`web/loop.js`), held to the reference filter's beliefs
//! along two generated trials. The reference answers all come from the model in
//! [`crate::fusion`].

mod contract;
mod generate;
mod grade;
mod hints;
mod job;
mod plan;

pub use contract::{Call, FUNCTIONS};
pub use generate::generate;
pub use grade::{first_departure, grade};
pub use hints::HintKind;
pub use job::TrialRecord;
pub use plan::{LOOP_FUNCTIONS, Plan, RUN_LIMIT_MS, TrialSpec};

/// A test case of this exercise.
pub type Case = crate::grading::Case<Call>;

use crate::exercises::interface::MatlabConventions;
use crate::exercises::{Declaration, Graded, Runs, Starters, Workbench};
use crate::grading::{Hidden, Reach};

/// The exercise, as the registry knows it.
pub struct SensorFusion;

impl Graded for SensorFusion {
    const DECLARATION: Declaration = Declaration {
        name: "sensor-fusion",
        title: "Fusing odometry with an indoor positioning sensor",
        file_name: "sensor_fusion.js",
        run_loop: "fusion",
        runs: Runs {
            noun: "trials",
            hidden: "ran {whose} filter over trials",
            graded: "runs your functions as a filter over whole trials against the reference",
        },
        workbench: Workbench {
            path: "/fusion/code",
            heading: "Your sensor fusion",
            nav: "Your fusion code",
            card: "Write the pieces of a Kalman filter that fuses wheel odometry with an \
                   indoor positioning sensor in JavaScript: the pose from two infrared \
                   platforms, the heading's noise by error propagation, the measurement noise \
                   and field of view, the prediction from odometry increments, the gate and \
                   the update. Run them on test cases and over the trials the grader runs, \
                   with a hint where a classic mistake explains a failure, and submit them.",
            intro: include_str!("web/intro.html"),
            run_button: "Run trials",
            runs_heading: "Your filter over the trials",
            run_choice: "Trial",
            run_view: include_str!("web/run_view.html"),
            experiments: "/fusion",
        },
        functions: "the pose from the two platforms, the heading's standard deviation by error \
                    propagation, the measurement noise, the field of view, the prediction \
                    from odometry increments, the gate's Mahalanobis distance and the update",
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
    type Run = job::TrialRun;
    type Record = job::TrialRecord;
    const GENERATE: crate::grading::Generator<Call> = generate;

    /// Its trials are whole whatever the reach: a few hundred to 1,500 steps.
    fn plan(seed: u64, hidden: Option<Hidden>, _: Reach) -> Plan {
        Plan::new(seed, hidden)
    }
}
