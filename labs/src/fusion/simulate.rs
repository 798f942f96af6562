//! Trials made from a seed, like the report's: a robot driven from waypoint to waypoint
//! in short moves with pauses between them, its odometry slipping, the detector reading
//! its platforms every 0.28 s, and now and then a second robot in view.

use super::sensor::Detector;
use super::trial::{Reading, Step, Trial};
use crate::Error;
use crate::angle::wrap;
use crate::rng::Rng;
use nalgebra::{Vector2, Vector3};
use serde::{Deserialize, Serialize};

/// What a generated trial depends on. Lengths in metres, times in seconds.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
#[serde(default)]
pub struct TrialParams {
    pub seed: u64,
    /// How many waypoints the robot visits, drawn in the room.
    pub waypoints: usize,
    /// Half the side of the square room around the point under the detector.
    pub room: f64,
    /// The time between two steps (and two readings).
    pub period: f64,
    pub speed: f64,
    /// Radians a second, turning on the spot.
    pub turn_rate: f64,
    /// The longest move before a pause.
    pub move_length: f64,
    pub pause: f64,
    /// The odometry's random error: standard deviation per metre moved (and per metre
    /// or radian, of the heading).
    pub slip: f64,
    /// The standard deviation of the odometry's systematic errors of scale (distance and
    /// turn), drawn once a trial.
    pub scale_error: f64,
    /// The chance that a second robot is in view during a move.
    pub other_robot: f64,
    pub detector: Detector,
}

impl Default for TrialParams {
    fn default() -> Self {
        TrialParams {
            seed: 1,
            waypoints: 12,
            room: 2.6,
            period: 0.28,
            speed: 0.25,
            turn_rate: 1.0,
            move_length: 0.35,
            pause: 1.0,
            slip: 0.03,
            scale_error: 0.03,
            other_robot: 0.05,
            detector: Detector::default(),
        }
    }
}

/// The most waypoints a trial may have.
pub const MAX_WAYPOINTS: usize = 200;

impl TrialParams {
    pub fn validate(&self) -> Result<(), Error> {
        if !(1..=MAX_WAYPOINTS).contains(&self.waypoints) {
            return Err(Error::invalid(
                "waypoints",
                format!("must be 1 to {MAX_WAYPOINTS}"),
            ));
        }
        let positive = [
            ("room", self.room, 20.0),
            ("period", self.period, 10.0),
            ("speed", self.speed, 5.0),
            ("turn_rate", self.turn_rate, 10.0),
            ("move_length", self.move_length, 20.0),
        ];
        for (field, value, most) in positive {
            if !(value > 0.0 && value <= most) {
                return Err(Error::invalid(field, format!("must be in (0, {most}]")));
            }
        }
        let others = [
            ("pause", self.pause, 60.0),
            ("slip", self.slip, 1.0),
            ("scale_error", self.scale_error, 0.5),
            ("other_robot", self.other_robot, 1.0),
        ];
        for (field, value, most) in others {
            if !(0.0..=most).contains(&value) {
                return Err(Error::invalid(field, format!("must be in [0, {most}]")));
            }
        }
        Ok(())
    }
}

/// A trial from its parameters (checked first).
pub fn generate(params: &TrialParams) -> Result<Trial, Error> {
    params.validate()?;
    let mut route = Rng::substream(params.seed, 1);
    let mut slip = Rng::substream(params.seed, 2);
    let sensor = Rng::substream(params.seed, 3);
    let mut others = Rng::substream(params.seed, 4);
    let scale = [0, 1].map(|_| 1.0 + params.scale_error * slip.standard_normal());

    let mut robot = Robot {
        params,
        truth: Vector3::zeros(),
        odometry: Vector3::zeros(),
        scale,
        slip,
        sensor,
        steps: Vec::new(),
        other: None,
    };
    robot.record();
    for _ in 0..params.waypoints {
        let goal = Vector2::new(
            route.uniform_in(-params.room, params.room),
            route.uniform_in(-params.room, params.room),
        );
        robot.other = others
            .chance(params.other_robot)
            .then(|| Vector2::new(others.uniform_in(-1.5, 1.5), others.uniform_in(-1.5, 1.5)));
        robot.go_to(goal);
    }
    Ok(Trial { steps: robot.steps })
}

struct Robot<'a> {
    params: &'a TrialParams,
    truth: Vector3<f64>,
    odometry: Vector3<f64>,
    /// The odometry's systematic scale of distance and of turn.
    scale: [f64; 2],
    slip: Rng,
    sensor: Rng,
    steps: Vec<Step>,
    /// A second robot in view during this move.
    other: Option<Vector2<f64>>,
}

impl Robot<'_> {
    /// Turns towards `goal`, then drives there in moves of at most `move_length`, pausing
    /// after each.
    fn go_to(&mut self, goal: Vector2<f64>) {
        let p = self.params;
        let to_goal = goal - self.truth.xy();
        let turn = wrap(libm::atan2(to_goal.y, to_goal.x) - self.truth.z);
        let turn_steps = (turn.abs() / (p.turn_rate * p.period)).ceil() as usize;
        for _ in 0..turn_steps {
            self.step(0.0, turn / turn_steps as f64);
        }
        let mut left = to_goal.norm();
        while left > 1e-9 {
            let length = left.min(p.move_length);
            let steps = (length / (p.speed * p.period)).ceil() as usize;
            for _ in 0..steps {
                self.step(length / steps as f64, 0.0);
            }
            left -= length;
            for _ in 0..(p.pause / p.period).round() as usize {
                self.step(0.0, 0.0);
            }
        }
    }

    /// One period: the robot moves `ds` ahead and turns by `dtheta` (the chord of the
    /// arc), its odometry counts the motion with its scale errors and slip, the detector
    /// reads.
    fn step(&mut self, ds: f64, dtheta: f64) {
        let p = self.params;
        self.truth = advance(&self.truth, ds, dtheta);
        let (odo_ds, odo_dtheta) = if ds == 0.0 && dtheta == 0.0 {
            (0.0, 0.0)
        } else {
            (
                ds * self.scale[0] + p.slip * ds * self.slip.standard_normal(),
                dtheta * self.scale[1] + p.slip * (ds + dtheta.abs()) * self.slip.standard_normal(),
            )
        };
        self.odometry = advance(&self.odometry, odo_ds, odo_dtheta);
        self.record();
    }

    fn record(&mut self) {
        let reading = self
            .params
            .detector
            .read(&self.truth, self.other, &mut self.sensor)
            .map(Reading::Platforms);
        self.steps.push(Step {
            t: self.steps.len() as f64 * self.params.period,
            odometry: self.odometry.into(),
            reading,
            truth: self.truth.into(),
            report: None,
        });
    }
}

/// A pose moved `ds` along its heading halfway through a turn of `dtheta`.
fn advance(pose: &Vector3<f64>, ds: f64, dtheta: f64) -> Vector3<f64> {
    let (sin, cos) = libm::sincos(pose.z + dtheta / 2.0);
    Vector3::new(pose.x + ds * cos, pose.y + ds * sin, wrap(pose.z + dtheta))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fusion::filter::{Settings, run};
    use crate::fusion::metrics::Summary;

    #[test]
    fn a_seed_makes_one_trial_and_its_file_reads_back() {
        let params = TrialParams::default();
        let trial = generate(&params).unwrap();
        assert_eq!(trial, generate(&params).unwrap());
        assert_ne!(trial, generate(&TrialParams { seed: 2, ..params }).unwrap());
        assert!(trial.steps.len() > 300, "{} steps", trial.steps.len());
        let back = Trial::parse(&trial.to_csv(), "trial.csv").unwrap();
        assert_eq!(back.steps.len(), trial.steps.len());
        for (a, b) in trial.steps.iter().zip(&back.steps) {
            assert!(
                a.truth
                    .iter()
                    .zip(b.truth)
                    .all(|(x, y)| (x - y).abs() < 1e-6)
            );
            assert_eq!(a.reading.is_some(), b.reading.is_some());
        }
    }

    #[test]
    fn the_robot_pauses_and_leaves_the_field_of_view() {
        let trial = generate(&TrialParams::default()).unwrap();
        let still = trial
            .steps
            .windows(2)
            .filter(|w| w[0].truth == w[1].truth)
            .count();
        assert!(still > trial.steps.len() / 5, "{still} still steps");
        let outside = trial
            .steps
            .iter()
            .filter(|s| Vector2::new(s.truth[0], s.truth[1]).norm() > 2.0)
            .count();
        assert!(outside > 0 && outside < trial.steps.len());
    }

    /// On generated trials the filter beats both its sources and is about consistent.
    #[test]
    fn the_filter_beats_odometry_and_the_sensor_alone() {
        for seed in 1..=5 {
            let trial = generate(&TrialParams {
                seed,
                ..TrialParams::default()
            })
            .unwrap();
            let estimates = run(&trial, &Settings::default(), &Detector::default());
            let summary = Summary::of(&trial, &estimates);
            assert!(
                summary.filter.mean < summary.odometry.mean,
                "{seed}: {summary:?}"
            );
            assert!(
                summary.filter.mean < summary.sensor.unwrap().mean,
                "{seed}: {summary:?}"
            );
            assert!(summary.inside_three_sigma > 0.8, "{seed}: {summary:?}");
        }
    }
}
