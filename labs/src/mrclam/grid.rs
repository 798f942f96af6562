//! A robot's recording on a fixed time grid, as the filters take it: the published files
//! sample odometry, readings and ground truth each at its own irregular times; the grid
//! runs at 50 Hz over the span the ground truth covers, each step with the commands
//! averaged over its interval, the readings taken in it, and the true pose at its end.

use super::{Measurement, Odometry, Pose, Robot, World};
use crate::angle;
use nalgebra::{Vector2, Vector3};
use serde::{Deserialize, Serialize};

/// The grid's rate, Hz.
pub const RATE: f64 = 50.0;

/// A commanded motion over a step: forward velocity [m/s] and angular velocity [rad/s].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Control {
    pub v: f64,
    pub omega: f64,
}

/// A reading of a post: the post's subject and where it stands [m], the measured range
/// [m] and bearing [rad].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reading {
    pub subject: u32,
    pub landmark: Vector2<f64>,
    pub range: f64,
    pub bearing: f64,
}

/// One step of the grid: it ends at `t` [s from the grid's start]; `control` is what was
/// commanded during it on average, `readings` what the camera saw during it, `truth` the
/// pose at its end (x, y, heading).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Step {
    pub t: f64,
    pub control: Control,
    pub readings: Vec<Reading>,
    pub truth: Vector3<f64>,
}

/// A robot's run on the grid. `steps[0]` is the start (no control, no readings); every
/// later step lasts `dt`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Run {
    pub dt: f64,
    pub steps: Vec<Step>,
    /// Readings left out: of another robot's barcode, or of a barcode nobody wears.
    pub skipped: usize,
}

impl Run {
    /// `robot`'s recording in `world` on the grid, from its first ground-truth pose to its
    /// last. `None` when the ground truth holds fewer than two poses.
    pub fn new(robot: &Robot, world: &World) -> Option<Run> {
        let (first, last) = (robot.truth.first()?, robot.truth.last()?);
        let dt = 1.0 / RATE;
        // (A span a whole number of steps long, give or take the rounding of its times,
        // ends on its last step.)
        let count = ((last.t - first.t) * RATE + 1e-6).floor() as usize + 1;
        if count < 2 {
            return None;
        }
        let time = |k: usize| first.t + k as f64 * dt;
        let mut truth = Interpolation::new(&robot.truth);
        let mut commands = Commands::new(&robot.odometry);
        let mut readings = robot.measurements.iter().peekable();
        // Readings before the grid's start are not the run's.
        while readings.next_if(|m| m.t <= first.t).is_some() {}
        let mut skipped = 0;
        let steps = (0..count)
            .map(|k| {
                let t = time(k);
                let mut taken = Vec::new();
                if k > 0 {
                    while let Some(m) = readings.next_if(|m| m.t <= t) {
                        match reading(m, world) {
                            Some(reading) => taken.push(reading),
                            None => skipped += 1,
                        }
                    }
                }
                Step {
                    t: k as f64 * dt,
                    control: if k == 0 {
                        Control::default()
                    } else {
                        commands.mean(time(k - 1), t)
                    },
                    readings: taken,
                    truth: truth.at(t),
                }
            })
            .collect();
        Some(Run { dt, steps, skipped })
    }

    /// The longest stretch of steps without a reading of a post: the times [s] of the
    /// last step with one before it (or the start) and the first after it (or the end).
    pub fn longest_blind_stretch(&self) -> (f64, f64) {
        let seen = self
            .steps
            .iter()
            .enumerate()
            .filter(|(k, step)| *k == 0 || !step.readings.is_empty())
            .map(|(_, step)| step.t)
            .chain(self.steps.last().map(|step| step.t));
        let mut longest = (0.0, 0.0);
        let mut previous = 0.0;
        for t in seen {
            if t - previous > longest.1 - longest.0 {
                longest = (previous, t);
            }
            previous = t;
        }
        longest
    }

    /// The poses of the ground truth, step by step.
    pub fn truths(&self) -> impl Iterator<Item = Vector3<f64>> + '_ {
        self.steps.iter().map(|step| step.truth)
    }
}

/// The reading `m` of a post, with the post's place; `None` for a barcode no post wears.
fn reading(m: &Measurement, world: &World) -> Option<Reading> {
    let post = world.post_of(m.barcode)?;
    Some(Reading {
        subject: post.subject,
        landmark: Vector2::new(post.x, post.y),
        range: m.range,
        bearing: m.bearing,
    })
}

/// The commands, each held from its time until the next's.
struct Commands<'a> {
    odometry: &'a [Odometry],
    /// The first command that may still be in force at the next interval's start.
    next: usize,
}

impl<'a> Commands<'a> {
    fn new(odometry: &'a [Odometry]) -> Self {
        Commands { odometry, next: 0 }
    }

    /// The commands' time average over [from, to] (nothing commanded counts as standing
    /// still). Intervals must come in the order of time.
    fn mean(&mut self, from: f64, to: f64) -> Control {
        let held = |i: usize| -> (f64, f64) {
            let end = self.odometry.get(i + 1).map_or(f64::INFINITY, |o| o.t);
            (self.odometry[i].t, end)
        };
        while self.next + 1 < self.odometry.len() && held(self.next).1 <= from {
            self.next += 1;
        }
        let (mut v, mut omega) = (0.0, 0.0);
        for i in self.next..self.odometry.len() {
            let (start, end) = held(i);
            if start >= to {
                break;
            }
            let overlap = end.min(to) - start.max(from);
            if overlap > 0.0 {
                v += self.odometry[i].v * overlap;
                omega += self.odometry[i].omega * overlap;
            }
        }
        Control {
            v: v / (to - from),
            omega: omega / (to - from),
        }
    }
}

/// The ground truth between its samples: straight lines, the heading by its wrapped
/// difference.
struct Interpolation<'a> {
    poses: &'a [Pose],
    /// The sample at or before the last time asked for.
    at: usize,
}

impl<'a> Interpolation<'a> {
    fn new(poses: &'a [Pose]) -> Self {
        Interpolation { poses, at: 0 }
    }

    /// The pose at `t`, within the samples' span; times must come in order.
    fn at(&mut self, t: f64) -> Vector3<f64> {
        while self.at + 1 < self.poses.len() && self.poses[self.at + 1].t <= t {
            self.at += 1;
        }
        let a = &self.poses[self.at];
        let Some(b) = self.poses.get(self.at + 1).filter(|b| b.t > a.t) else {
            return Vector3::new(a.x, a.y, a.theta);
        };
        let s = ((t - a.t) / (b.t - a.t)).clamp(0.0, 1.0);
        Vector3::new(
            a.x + s * (b.x - a.x),
            a.y + s * (b.y - a.y),
            angle::wrap(a.theta + s * angle::difference(b.theta, a.theta)),
        )
    }
}

/// The true pose at each of `times` (in order), interpolated between the samples of
/// `truth`.
pub fn truth_at(truth: &[Pose], times: impl Iterator<Item = f64>) -> Vec<Vector3<f64>> {
    let mut interpolation = Interpolation::new(truth);
    times.map(|t| interpolation.at(t)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mrclam::{Barcode, Post};

    fn world() -> World {
        World {
            posts: vec![Post {
                subject: 6,
                x: 1.0,
                y: 2.0,
                sd_x: 0.0,
                sd_y: 0.0,
            }],
            barcodes: vec![
                Barcode {
                    subject: 1,
                    barcode: 5,
                },
                Barcode {
                    subject: 6,
                    barcode: 63,
                },
            ],
        }
    }

    fn pose(t: f64, x: f64, theta: f64) -> Pose {
        Pose {
            t,
            x,
            y: 0.0,
            theta,
        }
    }

    #[test]
    fn commands_are_averaged_over_each_step_and_readings_fall_in_theirs() {
        let robot = Robot {
            odometry: vec![
                Odometry {
                    t: 100.0,
                    v: 0.2,
                    omega: 0.0,
                },
                Odometry {
                    t: 100.03,
                    v: 0.0,
                    omega: 1.0,
                },
            ],
            measurements: vec![
                Measurement {
                    t: 100.0,
                    barcode: 63,
                    range: 9.0,
                    bearing: 0.0,
                },
                Measurement {
                    t: 100.035,
                    barcode: 63,
                    range: 2.0,
                    bearing: 0.5,
                },
                Measurement {
                    t: 100.036,
                    barcode: 5,
                    range: 1.0,
                    bearing: 0.0,
                },
                Measurement {
                    t: 100.037,
                    barcode: 99,
                    range: 1.0,
                    bearing: 0.0,
                },
            ],
            truth: vec![pose(100.0, 0.0, 3.1), pose(100.1, 1.0, -3.1)],
        };
        let run = Run::new(&robot, &world()).unwrap();
        assert_eq!(run.steps.len(), 6);
        assert_eq!(run.skipped, 2);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
        assert!(close(run.steps[1].control.v, 0.2));
        // Step 2 spans [0.02, 0.04]: half of it at 0.2 m/s, half turning at 1 rad/s.
        assert!(close(run.steps[2].control.v, 0.1));
        assert!(close(run.steps[2].control.omega, 0.5));
        assert!(close(run.steps[3].control.omega, 1.0));
        assert!(run.steps[0].readings.is_empty() && run.steps[1].readings.is_empty());
        assert_eq!(run.steps[2].readings.len(), 1);
        assert_eq!(run.steps[2].readings[0].landmark, Vector2::new(1.0, 2.0));
        // Halfway between 3.1 and -3.1 the short way round is pi.
        assert!(close(run.steps[5].truth.x, 1.0));
        assert!(close(run.steps[5].truth.z, -3.1));
        assert!(close(run.steps[3].truth.x, 0.6));
        assert!(close(
            angle::difference(
                run.steps[3].truth.z,
                3.1 + 0.6 * (2.0 * std::f64::consts::PI - 6.2)
            ),
            0.0
        ));
    }
}
