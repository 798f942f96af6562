//! What a grading of the sensor-fusion exercise consists of, from a seed: the test cases
//! of every student function (see [`crate::grading::planned_cases`]), two generated
//! trials with the reference filter's beliefs along them, on the server the class's
//! held-out trials of the challenge, and the job the JavaScript harness carries out with
//! the student's code.

use super::SensorFusion;
use super::contract::Call;
use super::generate::generate;
use super::grade::grade;
use super::job::{FilterSettings, TrialRecord, TrialRun, TrialStepData};
use crate::Exercise;
use crate::exercises::Graded;
use crate::fusion::{
    self, Detector, Estimate, NoiseModel, Reading, Settings, Summary, Trial, TrialParams, Use,
};
use crate::grading::{
    ExercisePlan, GradeResult, Hidden, Job, Outputs, PlannedCase, RunPhase, function_phases,
    planned_cases,
};
use crate::rng::Rng;

/// How long the student's code may take over one whole run of the fusion loop.
pub const RUN_LIMIT_MS: u32 = 5_000;

/// The functions the fusion loop calls, in the order it calls them at a step.
pub const LOOP_FUNCTIONS: [&str; 6] = [
    "predict",
    "combine_platforms",
    "in_field_of_view",
    "measurement_noise",
    "mahalanobis",
    "update",
];

/// The function the loop calls first over a held-out trial, for the filter's settings.
pub const TUNING: &str = "tuning";

/// What the runs over the class's held-out trials are called: `held-out-1` and on.
pub const HELD_OUT: &str = "held-out";

/// The class's held-out trials: the half-side of the room (metres) and the chance that
/// another robot is in view during a move, from a small quiet room to a wide one that
/// leaves the field of view, with little to much traffic. One trial ranks partly by luck
/// (a trial where another robot confuses the sensor can undo good settings); the mean
/// over these five ranks settings that are better on average higher (BENCHMARKS.md).
const HELD_OUT_ROOMS: [(f64, f64); 5] =
    [(2.0, 0.0), (2.3, 0.4), (2.6, 0.2), (2.9, 0.3), (3.2, 0.1)];

/// The waypoints of each held-out trial: about 380 steps.
const HELD_OUT_WAYPOINTS: usize = 5;

/// The part of a seed's random numbers the trials are drawn from (ASCII "trial").
const TRIALS: u64 = 0x74_7269_616c;
/// The part of a class's seed the held-out trial is drawn from (ASCII "heldout").
const HELD_OUT_TRIAL: u64 = 0x68_656c_646f_7574;

/// Everything one grading checks, made from the student's seed (and, on the server, a
/// seed of hidden cases).
#[derive(Clone, Debug)]
pub struct Plan {
    pub seed: u64,
    /// The seed of the hidden cases and trials, known to the server only.
    pub hidden: Option<u64>,
    pub cases: Vec<PlannedCase<Call>>,
    pub runs: Vec<TrialSpec>,
    /// The class's held-out trials, on the server.
    pub held_out: Option<HeldOut>,
}

/// The trials a class's filters are ranked on (the class challenge): drawn from the
/// class's seed, never shown; the student's filter runs over each with the settings
/// their `tuning()` chooses, and the reference's with its default settings, for
/// comparison.
#[derive(Clone, Debug)]
pub struct HeldOut {
    /// One a room of [`HELD_OUT_ROOMS`], in its order.
    pub trials: Vec<HeldOutTrial>,
}

/// One of the class's held-out trials.
#[derive(Clone, Debug)]
pub struct HeldOutTrial {
    /// The run's name: `held-out-1` and on.
    pub name: String,
    pub trial: Trial,
    /// The reference filter's figures over it, with its default settings.
    pub reference: Summary,
}

impl HeldOut {
    /// A tour of a few waypoints in each room of [`HELD_OUT_ROOMS`]: the kind of trial
    /// the two graded ones are.
    pub fn new(class: u64) -> HeldOut {
        let mut rng = Rng::substream(class, HELD_OUT_TRIAL);
        let trials = HELD_OUT_ROOMS
            .iter()
            .enumerate()
            .map(|(i, &(room, other_robot))| {
                let params = TrialParams {
                    seed: (rng.uniform() * 1e9) as u64,
                    waypoints: HELD_OUT_WAYPOINTS,
                    room,
                    other_robot,
                    ..TrialParams::default()
                };
                let trial =
                    fusion::generate(&params).expect("the held-out trials' parameters are valid");
                let estimates = fusion::run(&trial, &Settings::default(), &Detector::default());
                HeldOutTrial {
                    name: format!("{HELD_OUT}-{}", i + 1),
                    reference: Summary::of(&trial, &estimates),
                    trial,
                }
            })
            .collect();
        HeldOut { trials }
    }

    /// The steps of all the trials.
    pub fn steps(&self) -> usize {
        self.trials.iter().map(|t| t.trial.steps.len()).sum()
    }
}

impl HeldOutTrial {
    fn job(&self) -> RunPhase {
        let functions: Vec<&str> = std::iter::once(TUNING).chain(LOOP_FUNCTIONS).collect();
        RunPhase::new(
            SensorFusion::DECLARATION.run_loop,
            &self.name,
            &functions,
            RUN_LIMIT_MS,
            &trial_run(&self.trial, &Settings::default(), None),
        )
    }
}

/// A run of the fusion loop with the student's functions.
#[derive(Clone, Debug)]
pub struct TrialSpec {
    /// `busy-room`, `wide-tour`.
    pub name: String,
    pub trial: Trial,
    pub settings: Settings,
    /// The reference filter's belief after every step.
    pub reference: Vec<Estimate>,
}

impl Plan {
    /// The public suite, the variant of `seed`, and two trials drawn from `seed` (from
    /// `hidden` instead when there is one, as on the server): a busy room, where a second
    /// robot often saturates the detector (the gate has work to do), and a wide tour, which
    /// leaves the field of view for long stretches (the odometry alone carries the
    /// filter there, and its readings beyond the edge must be ignored).
    pub fn new(seed: u64, hidden: Option<Hidden>) -> Plan {
        let mut rng = Rng::substream(hidden.map_or(seed, |h| h.cases), TRIALS);
        let busy = trial(&mut rng, "busy-room", (6, 2.2, 0.3), |u| {
            matches!(u, Use::Gated { .. })
        });
        let wide = trial(&mut rng, "wide-tour", (5, 3.2, 0.1), |u| {
            matches!(u, Use::OutsideView)
        });
        let cases = hidden.map(|h| h.cases);
        Plan {
            seed,
            hidden: cases,
            cases: planned_cases(generate, seed, cases),
            runs: vec![busy, wide],
            held_out: hidden.map(|h| HeldOut::new(h.class)),
        }
    }

    pub fn run(&self, name: &str) -> Option<&TrialSpec> {
        self.runs.iter().find(|run| run.name == name)
    }
}

impl ExercisePlan for Plan {
    fn exercise(&self) -> Exercise {
        Exercise::SensorFusion
    }

    fn seed(&self) -> u64 {
        self.seed
    }

    /// What the harness needs to call the student's code: the arguments of every case (not
    /// the expected outputs) and the settings, odometry and readings of every trial (not
    /// the truth or the reference's beliefs).
    fn job(&self) -> Job {
        Job {
            functions: function_phases(&self.cases),
            runs: self
                .runs
                .iter()
                .map(TrialSpec::job)
                .chain(
                    self.held_out
                        .iter()
                        .flat_map(|h| h.trials.iter().map(HeldOutTrial::job)),
                )
                .collect(),
        }
    }

    fn grade(&self, outputs: &Outputs) -> GradeResult {
        grade(self, outputs)
    }
}

/// A trial of `waypoints` in a room of half-side `room`, a second robot in view during a
/// move with chance `other_robot`, and the filter's settings drawn round: k_xy and
/// k_theta of 0.02 to 0.2, c_xy of 70 to 110, a field of view of 1.8 to 2.2 m, a gate at
/// 99.9 %. Trials are drawn until one gives the reference filter's branch `shows` work
/// (and more than 20 readings to use): a trial where it has none tests nothing of it.
fn trial(
    rng: &mut Rng,
    name: &str,
    (waypoints, room, other_robot): (usize, f64, f64),
    shows: fn(&Use) -> bool,
) -> TrialSpec {
    let settings = Settings {
        process_xy: rounded(rng.uniform_in(0.02, 0.2), 100.0),
        process_theta: rounded(rng.uniform_in(0.02, 0.2), 100.0),
        noise: NoiseModel {
            c_xy: libm::round(rng.uniform_in(70.0, 110.0)),
            ..NoiseModel::default()
        },
        field_of_view: rounded(rng.uniform_in(1.8, 2.2), 10.0),
        ..Settings::default()
    };
    loop {
        let params = TrialParams {
            seed: (rng.uniform() * 1e9) as u64,
            waypoints,
            room,
            other_robot,
            ..TrialParams::default()
        };
        let trial = fusion::generate(&params).expect("the drawn trials are valid");
        let reference = fusion::run(&trial, &settings, &Detector::default());
        let count = |kind: fn(&Use) -> bool| reference.iter().filter(|e| kind(&e.reading)).count();
        if count(shows) > 0 && count(|u| matches!(u, Use::Used { .. })) > 20 {
            return TrialSpec {
                name: name.to_owned(),
                trial,
                settings,
                reference,
            };
        }
    }
}

/// `value` to the nearest 1 / `per`.
fn rounded(value: f64, per: f64) -> f64 {
    libm::round(value * per) / per
}

impl TrialSpec {
    pub fn steps(&self) -> usize {
        self.trial.steps.len()
    }

    /// The reference's record of the run, as the loop records the student's.
    pub fn reference_record(&self) -> TrialRecord {
        TrialRecord {
            tuning: None,
            poses: self.reference.iter().map(|e| e.pose).collect(),
            covariances: self.reference.iter().map(|e| e.sigma).collect(),
        }
    }

    fn job(&self) -> RunPhase {
        let s = &self.settings;
        let settings = FilterSettings {
            k_xy: s.process_xy,
            k_theta: s.process_theta,
            c_xy: s.noise.c_xy,
            field_of_view: s.field_of_view,
            lambda: s.gate_threshold(),
        };
        RunPhase::new(
            SensorFusion::DECLARATION.run_loop,
            &self.name,
            &LOOP_FUNCTIONS,
            RUN_LIMIT_MS,
            &trial_run(&self.trial, s, Some(settings)),
        )
    }
}

/// What the loop gets of `trial`: where it starts (the odometry's first pose, with the
/// standard deviations of `start`), the filter's `settings` (none: `tuning()` chooses),
/// and the odometry and readings of every step; not the truth.
fn trial_run(trial: &Trial, start: &Settings, settings: Option<FilterSettings>) -> TrialRun {
    let sigma = start.start_sigma;
    TrialRun {
        start: trial.steps[0].odometry,
        start_sigma: [
            [sigma[0] * sigma[0], 0.0, 0.0],
            [0.0, sigma[1] * sigma[1], 0.0],
            [0.0, 0.0, sigma[2] * sigma[2]],
        ],
        settings,
        steps: trial
            .steps
            .iter()
            .map(|step| TrialStepData {
                odom: step.odometry,
                platforms: match step.reading {
                    Some(Reading::Platforms(ps)) => Some(ps.map(|p| [p.x, p.y, p.intensity])),
                    _ => None,
                },
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every trial takes a few hundred steps, and the plans of different seeds differ.
    #[test]
    fn the_trials_take_a_few_hundred_steps() {
        for seed in 1..=100 {
            let plan = Plan::new(seed, None);
            for run in &plan.runs {
                assert!(
                    (100..=1500).contains(&run.steps()),
                    "seed {seed}, {}: {} steps",
                    run.name,
                    run.steps()
                );
            }
        }
        assert_ne!(
            Plan::new(1, None).runs[0].trial,
            Plan::new(2, None).runs[0].trial
        );
        let hidden = |cases, class| Some(Hidden { cases, class });
        assert_eq!(
            Plan::new(1, hidden(5, 9)).runs[1].trial,
            Plan::new(2, hidden(5, 8)).runs[1].trial
        );
    }

    /// The held-out trials are the class's: the same for every submission of the class,
    /// others for another class, in no plan the browser grades, and runs without
    /// settings (the student's `tuning()` gives them).
    #[test]
    fn the_held_out_trials_are_the_classes() {
        let hidden = |cases, class| Some(Hidden { cases, class });
        let trial = |plan: Plan| {
            plan.held_out.expect("on the server").trials[2]
                .trial
                .clone()
        };
        assert_eq!(
            trial(Plan::new(1, hidden(5, 9))),
            trial(Plan::new(2, hidden(6, 9)))
        );
        assert_ne!(
            trial(Plan::new(1, hidden(5, 9))),
            trial(Plan::new(1, hidden(5, 8)))
        );
        assert!(Plan::new(1, None).held_out.is_none());
        let job = Plan::new(1, hidden(5, 9)).job();
        let names: Vec<&str> = job.runs.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "busy-room",
                "wide-tour",
                "held-out-1",
                "held-out-2",
                "held-out-3",
                "held-out-4",
                "held-out-5"
            ]
        );
        for held_out in &job.runs[2..] {
            assert_eq!(held_out.functions[0], TUNING);
            assert_eq!(held_out.data["settings"], serde_json::Value::Null);
        }
        assert!(!serde_json::to_string(&job).unwrap().contains("truth"));
    }
}
