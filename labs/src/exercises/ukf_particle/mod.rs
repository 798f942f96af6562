//! The unscented Kalman filter and the particle filter on MRCLAM-like data: the student
//! contract (twelve functions: the unicycle's arc and its process noise, the sigma points
//! and their weights, the UKF's prediction and update, the particle filter's motion
//! sampling, weighting, resampling test, low-variance resampling and estimate, and the
//! noise learned from data: the camera's from residuals, the control's alphas; `web/starter.js`, `README.md`), its case
//! generator, the hints for its classic mistakes, and the runs of the harness's loop
//! (`web/loop.js`): a UKF and a particle filter, every random number given by the
//! harness, held to the reference filters' beliefs step by step. The reference answers
//! all come from the model in [`crate::mrclam`].

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
pub use job::{FilterRecord, FilterRun, RunFilter};
pub use plan::{FilterSpec, PARTICLES, Plan, RUN_LIMIT_MS};

/// A test case of this exercise.
pub type Case = crate::grading::Case<Call>;

use crate::exercises::interface::MatlabConventions;
use crate::exercises::{Declaration, Graded, Runs, Starters, Workbench};
use crate::grading::{Hidden, Reach};

/// The exercise, as the registry knows it.
pub struct UkfParticle;

impl Graded for UkfParticle {
    const DECLARATION: Declaration = Declaration {
        name: "ukf-particle",
        title: "The unscented Kalman filter and the particle filter",
        file_name: "ukf_particle.js",
        run_loop: "mrclam",
        runs: Runs {
            noun: "runs",
            hidden: "ran {whose} filters along generated robots",
            graded: "strings your functions into a UKF and a particle filter along generated \
                     robots against the reference",
        },
        workbench: Workbench {
            path: "/mrclam/code",
            heading: "Your UKF and particle filter",
            nav: "Your UKF and particle filter",
            card: "Write an unscented Kalman filter and a particle filter for a robot among \
                   barcoded posts, as in the MRCLAM data set: the unicycle's arc and its \
                   process noise, the sigma points and their weights \\(w_m, w_c\\), the \
                   unscented prediction and update with angles averaged as angles, the \
                   particles' motion, weights and low-variance resampling, the cloud's \
                   estimate, and the noise learned from data. Run them on test \
                   cases and as whole filters, held to the reference step by step, with a \
                   hint where a classic mistake explains a failure, and submit them.",
            intro: include_str!("web/intro.html"),
            run_button: "Run filters",
            runs_heading: "Your filters along the generated robots",
            run_choice: "Run",
            run_view: include_str!("web/run_view.html"),
            experiments: "/mrclam",
        },
        functions: "the unicycle's arc and its process noise, the sigma points and their \
                    weights, the UKF's prediction and update, the particle filter's motion \
                    sampling, weighting, resampling test, low-variance resampling and \
                    estimate, and the noise learned from data (the camera's from residuals, \
                    the control's alphas by least squares)",
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
    type Run = job::FilterRun;
    type Record = job::FilterRecord;
    const GENERATE: crate::grading::Generator<Call> = generate;

    /// Its runs are whole whatever the reach: a few hundred steps.
    fn plan(seed: u64, hidden: Option<Hidden>, _: Reach) -> Plan {
        Plan::new(seed, hidden)
    }
}
