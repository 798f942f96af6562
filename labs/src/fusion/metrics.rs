//! How good an estimate is: position errors against ground truth, consistency, and the
//! search for settings that tuning is.

use super::filter::{Estimate, Settings, Use, inside_three_sigma, run};
use super::sensor::Detector;
use super::trial::Trial;
use serde::{Deserialize, Serialize};

/// The report's own figures on its two trials, mean position errors in metres: its
/// Kalman estimate, odometry alone, Northstar alone (its files give them back to the last
/// digit: `labs/tests/northstar_trials.rs`).
pub const REPORT_FIGURES: [ReportFigures; 2] = [
    ReportFigures {
        trial: "trial1",
        kalman: 0.139,
        odometry: 0.292,
        sensor: 0.155,
    },
    ReportFigures {
        trial: "trial2",
        kalman: 0.057,
        odometry: 0.082,
        sensor: 0.123,
    },
];

/// The report's mean position errors on one of its trials, metres.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, ts_rs::TS)]
pub struct ReportFigures {
    /// The trial's name, as its files begin (`trial1_odometry_northstar.csv`).
    pub trial: &'static str,
    pub kalman: f64,
    pub odometry: f64,
    pub sensor: f64,
}

/// Position errors against ground truth over a trial's steps, metres.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
#[ts(rename = "PositionErrors")]
pub struct Errors {
    /// The mean distance to the truth (what the report calls its error).
    pub mean: f64,
    /// The root mean square distance.
    pub rms: f64,
    pub max: f64,
    /// How many steps the figures are over.
    pub steps: usize,
}

impl Errors {
    /// The errors of `poses` against `truths`, pairwise; `None` when there are none.
    pub fn of(pairs: impl Iterator<Item = ([f64; 3], [f64; 3])>) -> Option<Errors> {
        let distances: Vec<f64> = pairs
            .map(|(pose, truth)| libm::hypot(pose[0] - truth[0], pose[1] - truth[1]))
            .collect();
        let n = distances.len() as f64;
        (!distances.is_empty()).then(|| Errors {
            mean: distances.iter().sum::<f64>() / n,
            rms: (distances.iter().map(|d| d * d).sum::<f64>() / n).sqrt(),
            max: distances.iter().copied().fold(0.0, f64::max),
            steps: distances.len(),
        })
    }
}

/// A run of the filter over a trial, summed up.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
#[ts(rename = "FusionSummary")]
pub struct Summary {
    pub filter: Errors,
    /// The odometry's own pose.
    pub odometry: Errors,
    /// The sensor alone, over the steps with a reading (in view or not).
    pub sensor: Option<Errors>,
    /// The report's own estimate, where the trial has it.
    pub report: Option<Errors>,
    /// The share of steps whose true position lies inside the estimate's 3-sigma ellipse
    /// (98.9 % for a consistent filter).
    pub inside_three_sigma: f64,
    /// How many readings corrected the estimate, lay outside the field of view, were
    /// rejected by the gate.
    pub used: usize,
    pub outside_view: usize,
    pub gated: usize,
}

impl Summary {
    pub fn of(trial: &Trial, estimates: &[Estimate]) -> Summary {
        let truths = || trial.steps.iter().map(|s| s.truth);
        let count = |kind: fn(&Use) -> bool| estimates.iter().filter(|e| kind(&e.reading)).count();
        let inside = estimates
            .iter()
            .zip(truths())
            .filter(|(e, truth)| inside_three_sigma(e.pose, &e.sigma, *truth))
            .count();
        Summary {
            filter: Errors::of(estimates.iter().map(|e| e.pose).zip(truths()))
                .expect("a trial has steps"),
            odometry: Errors::of(trial.steps.iter().map(|s| s.odometry).zip(truths()))
                .expect("a trial has steps"),
            sensor: Errors::of(
                estimates
                    .iter()
                    .zip(truths())
                    .filter_map(|(e, truth)| e.measurement.map(|m| (m.pose, truth))),
            ),
            report: Errors::of(
                trial
                    .steps
                    .iter()
                    .filter_map(|s| s.report.map(|r| (r, s.truth))),
            ),
            inside_three_sigma: inside as f64 / estimates.len() as f64,
            used: count(|u| matches!(u, Use::Used { .. })),
            outside_view: count(|u| matches!(u, Use::OutsideView)),
            gated: count(|u| matches!(u, Use::Gated { .. })),
        }
    }
}

/// The process noise values tuning tries, for each of `k_xy` and `k_theta`.
pub const TUNING_GRID: [f64; 6] = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5];

/// Tuning: of every pair of process noise constants on [`TUNING_GRID`] (the rest of
/// `base` kept), the one whose filter has the least mean error on `trial`, and that
/// error. Ties go to the first pair on the grid.
pub fn tune(trial: &Trial, base: &Settings, detector: &Detector) -> (Settings, f64) {
    let mut best = (*base, f64::INFINITY);
    for process_xy in TUNING_GRID {
        for process_theta in TUNING_GRID {
            let settings = Settings {
                process_xy,
                process_theta,
                ..*base
            };
            let estimates = run(trial, &settings, detector);
            let mean = Summary::of(trial, &estimates).filter.mean;
            if mean < best.1 {
                best = (settings, mean);
            }
        }
    }
    best
}
