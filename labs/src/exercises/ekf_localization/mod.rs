//! EKF localization of a differential-drive robot (EL2320 Lab 1, part II): the student
//! contract (eight functions and `init`, `README.md`), its case generator and the
//! original EL2320 fixtures, the hints for its classic mistakes, and the data-set runs of
//! the lab's filter loop (`web/loop.js`) held to the lab's bounds.

mod contract;
mod el2320;
mod generate;
mod grade;
mod hints;
mod job;
mod plan;

pub use contract::{Call, FUNCTIONS, Mat2, Mat2x3, Mat3, TwoRows, Vec2, Vec3};
pub use el2320::{FIXTURE_FILES, load_fixtures};
pub use generate::generate;
pub use grade::{grade, student_run};
pub use hints::HintKind;
pub use job::{FilterRecord, FilterRun, Mode, RobotJob, StepJob};
pub use plan::{Plan, RunSpec, bound, graded_readings, mode_name, run_name, shows_the_lesson};

/// A test case of this exercise.
pub type Case = crate::grading::Case<Call>;

use crate::exercises::interface::MatlabConventions;
use crate::exercises::{Declaration, Graded, ReportRun, Runs, Starters, Workbench};
use crate::grading::{Hidden, Reach};

/// The views of a whole run (`static/src/ekf/runview.js` draws them), on the workbench
/// and on the experiment page alike.
pub const RUN_PLOTS: &str = include_str!("web/plots.html");

/// The exercise, as the registry knows it.
pub struct EkfLocalization;

impl Graded for EkfLocalization {
    const DECLARATION: Declaration = Declaration {
        name: "ekf-localization",
        title: "EKF localization",
        file_name: "ekf_localization.js",
        run_loop: "filter",
        runs: Runs {
            noun: "data sets",
            hidden: "ran {whose} filter on data sets",
            graded: "runs whole data sets against the lab's error bounds",
        },
        workbench: Workbench {
            path: "/ekf/code",
            heading: "Your EKF localization",
            nav: "Your EKF code",
            card: "Write the lab's functions yourself, in JavaScript, in the browser: run them \
                   on test cases made for you and on the three data sets against the lab's \
                   bounds, with a hint where a classic mistake explains a failure, and submit \
                   them to be graded.",
            intro: include_str!("web/intro.html"),
            run_button: "Run data sets",
            runs_heading: "Your filter on the data sets",
            run_choice: "Run",
            run_view: concat!(
                "  <pre class=\"summary\" id=\"summary\"></pre>\n",
                include_str!("web/plots.html")
            ),
            experiments: "/ekf",
        },
        functions: "the odometry, the prediction, the observation model and its Jacobian, the \
                    maximum-likelihood association with the outlier test, and the sequential \
                    and batch updates",
        starter_template: include_str!("web/starter.txt"),
        starters: Starters {
            javascript: include_str!("web/starter.js"),
            python: include_str!("web/starter.py"),
            matlab: include_str!("web/starter.m"),
        },
        harness_loop: include_str!("web/loop.js"),
        matlab: MatlabConventions {
            index_arguments: &[
                ("observation_model", "j"),
                ("jacobian_observation_model", "j"),
            ],
            stacked_outputs: &[("associate", "nu"), ("associate", "S"), ("associate", "H")],
            globals: &[
                ("M", "map"),
                ("Lambda_M", "lambda_m"),
                ("Q", "Q"),
                ("R", "R"),
            ],
            trailing: &[("jacobian_observation_model", 1.0)],
        },
        questions: &[
            include_str!("questions/part-1.toml"),
            include_str!("questions/part-2.toml"),
        ],
        report: &[
            ReportRun {
                run: "o3/sequential",
                title: "o3, sequential update",
                ask: "Why do the estimate and its $3\\sigma$ ellipses look as they do on this data set, \
                      beside the runs on the other two?",
            },
            ReportRun {
                run: "outliers/sequential",
                title: "Outliers, sequential update",
                ask: "How do the outliers show in the run, and what does the outlier gate \
                      $\\Lambda_M$ do with them?",
            },
            ReportRun {
                run: "no-odometry/sequential",
                title: "No odometry, sequential update",
                ask: "Without odometry, why does the sequential update go wrong where the batch \
                      update does not?",
            },
            ReportRun {
                run: "no-odometry/batch",
                title: "No odometry, batch update",
                ask: "Why does the batch update cope without odometry, and what do its errors \
                      and covariance show?",
            },
        ],
    };
    type Call = Call;
    type Plan = Plan;
    type Run = job::FilterRun;
    type Record = job::FilterRecord;
    const GENERATE: crate::grading::Generator<Call> = generate;

    fn plan(seed: u64, hidden: Option<Hidden>, reach: Reach) -> Plan {
        Plan::reaching(seed, hidden.map(|h| h.cases), reach)
    }
}
