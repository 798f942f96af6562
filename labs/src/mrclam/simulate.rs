//! MRCLAM-like data sets made from a seed, so that the filters, the page and the exercise
//! run without the real files: a room with its posts, robots driving at random among
//! them, each recording what a robot of the data set records (its commanded odometry at
//! about 70 Hz, its camera's readings of the posts and robots in its field of view, its
//! pose from motion capture at about 60 Hz), with noise of known size.

use super::grid::{Control, truth_at};
use super::motion::{self, Noise};
use super::{Barcode, FIRST_POST, Measurement, Odometry, Pose, Post, Robot, World};
use crate::angle;
use crate::error::Error;
use crate::rng::Rng;
use nalgebra::{Matrix2, Vector2, Vector3};
use serde::{Deserialize, Serialize};

/// What a generated data set is made of.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
#[ts(rename = "MrclamDatasetParams")]
pub struct DatasetParams {
    #[ts(type = "number")]
    pub seed: u64,
    /// How many robots drive in the room, 1 to 5.
    pub robots: u32,
    /// How many posts stand in it, 1 to 15.
    pub posts: u32,
    /// How long the robots drive, seconds.
    pub duration: f64,
    /// The room's width (x) and length (y), metres, its corner at the origin.
    pub room: [f64; 2],
    /// The true noise: of the robots' motion about their commands, and of their cameras.
    pub noise: Noise,
}

impl Default for DatasetParams {
    /// Three robots among fifteen posts for two minutes in a 5 x 10 m room (the part of
    /// the UTIAS room data set 6's robots drive in); the noise near what data set 6's
    /// recordings teach.
    fn default() -> Self {
        DatasetParams {
            seed: 1,
            robots: 3,
            posts: 15,
            duration: 120.0,
            room: [5.0, 10.0],
            noise: Noise {
                alphas: [0.2, 0.02, 0.8, 0.2],
                measurement: Matrix2::new(0.08 * 0.08, 0.0, 0.0, 0.02 * 0.02),
            },
        }
    }
}

/// The camera: what it can see and how often it looks.
const FIELD_OF_VIEW: f64 = 0.55;
const RANGE: (f64, f64) = (0.5, 8.0);
const FRAME: f64 = 0.2;
/// The share of the subjects in view a frame reads (the rest go unrecognised).
const RECOGNISED: f64 = 0.15;
/// The robots' top speeds: forward [m/s], turning [rad/s].
const TOP_SPEED: (f64, f64) = (0.09, 0.4);
/// Keep this far from the walls, metres.
const MARGIN: f64 = 0.6;
/// The most a robot's wheels are off: its speed by a share, its turn by rad/s.
const SYSTEMATIC: (f64, f64) = (0.05, 0.01);
/// How many random places a post or a robot's start is tried at before the room is
/// found too crowded.
const PLACES_TRIED: usize = 10_000;
/// Motion capture's jitter: position [m] and heading [rad].
const CAPTURE_SD: (f64, f64) = (0.001, 0.005);

/// A data set made from `params`: each robot's recording, and the room.
pub fn generate(params: &DatasetParams) -> Result<(Vec<Robot>, World), Error> {
    validate(params)?;
    let world = room(params)?;
    let mut paths: Vec<Path> = (0..params.robots)
        .map(|r| drive(params, r, &world))
        .collect::<Result<_, _>>()?;
    let truths: Vec<Vec<(f64, Vector3<f64>)>> = paths.iter().map(|p| p.poses.clone()).collect();
    for (r, path) in paths.iter_mut().enumerate() {
        path.measurements = camera(params, r, &truths, &world);
    }
    let robots = paths
        .into_iter()
        .enumerate()
        .map(|(r, path)| Robot {
            truth: capture(params, r as u32, &path.poses),
            odometry: path.odometry,
            measurements: path.measurements,
        })
        .collect();
    Ok((robots, world))
}

fn validate(params: &DatasetParams) -> Result<(), Error> {
    let invalid = |field: &str, message: &str| Err(Error::invalid(field, message));
    if !(1..=5).contains(&params.robots) {
        return invalid("robots", "1 to 5");
    }
    if !(1..=15).contains(&params.posts) {
        return invalid("posts", "1 to 15");
    }
    if !(params.duration.is_finite() && (1.0..=3600.0).contains(&params.duration)) {
        return invalid("duration", "1 to 3600 s");
    }
    if !params
        .room
        .iter()
        .all(|side| side.is_finite() && (3.0..=50.0).contains(side))
    {
        return invalid("room", "sides of 3 to 50 m");
    }
    let n = params.noise;
    if !(n
        .alphas
        .iter()
        .all(|a| a.is_finite() && (0.0..=5.0).contains(a))
        && n.measurement.iter().all(|v| v.is_finite())
        && n.measurement[(0, 0)] > 0.0
        && n.measurement[(1, 1)] > 0.0
        && n.measurement.determinant() > 0.0)
    {
        return invalid("noise", "alphas of 0 to 5 and R2 positive definite");
    }
    Ok(())
}

/// The posts, at random in the room (no two within half a metre), and the barcodes: the
/// robots wear 1 to 5, the posts 6 on, each a different two-digit barcode.
fn room(params: &DatasetParams) -> Result<World, Error> {
    let mut rng = Rng::substream(params.seed, 1);
    let [width, length] = params.room;
    let mut posts: Vec<Post> = Vec::new();
    for _ in 0..PLACES_TRIED {
        if posts.len() == params.posts as usize {
            break;
        }
        let (x, y) = (
            rng.uniform_in(0.2, width - 0.2),
            rng.uniform_in(0.2, length - 0.2),
        );
        if posts.iter().all(|p| libm::hypot(p.x - x, p.y - y) > 0.5) {
            posts.push(Post {
                subject: FIRST_POST + posts.len() as u32,
                x,
                y,
                sd_x: 0.0,
                sd_y: 0.0,
            });
        }
    }
    if posts.len() < params.posts as usize {
        return Err(Error::invalid(
            "posts",
            "too many for the room: no place left half a metre from the others",
        ));
    }
    let subjects = (1..=params.robots).chain(posts.iter().map(|p| p.subject));
    let mut codes: Vec<u32> = (10..100).collect();
    let barcodes = subjects
        .map(|subject| {
            let pick = rng.index(codes.len());
            Barcode {
                subject,
                barcode: codes.swap_remove(pick),
            }
        })
        .collect();
    Ok(World { posts, barcodes })
}

/// A robot's drive: its commands and its true poses, each with its time.
struct Path {
    odometry: Vec<Odometry>,
    /// The true pose after each odometry interval, from the start.
    poses: Vec<(f64, Vector3<f64>)>,
    measurements: Vec<Measurement>,
}

/// Robot `r` drives at random: stretches of a few seconds at a random speed and turn
/// (now and then a pause), turning back towards the room's middle near a wall. Commands
/// come at irregular times about 70 times a second; the robot's true motion over each is
/// the command, as its wheels really carry it out (a few per cent off in speed, a little
/// off in turn: what makes dead reckoning drift), plus a draw of the control noise.
fn drive(params: &DatasetParams, r: u32, world: &World) -> Result<Path, Error> {
    let mut rng = Rng::substream(params.seed, 10 + u64::from(r));
    let speed_scale = rng.uniform_in(1.0 - SYSTEMATIC.0, 1.0 + SYSTEMATIC.0);
    let turn_offset = rng.uniform_in(-SYSTEMATIC.1, SYSTEMATIC.1);
    let [width, length] = params.room;
    let centre = Vector2::new(width / 2.0, length / 2.0);
    let mut pose = start(&mut rng, params, world)?;
    let (mut t, mut until) = (0.0, 0.0);
    let mut command = Control::default();
    let mut odometry = Vec::new();
    let mut poses = vec![(0.0, pose)];
    while t < params.duration {
        let near_wall = pose.x < MARGIN
            || pose.y < MARGIN
            || pose.x > width - MARGIN
            || pose.y > length - MARGIN;
        let towards = angle::difference(libm::atan2(centre.y - pose.y, centre.x - pose.x), pose.z);
        if near_wall && towards.abs() > 0.5 {
            command = Control {
                v: 0.02,
                omega: TOP_SPEED.1 * towards.signum(),
            };
            until = t;
        } else if t >= until {
            command = if rng.chance(0.15) {
                Control::default()
            } else {
                Control {
                    v: rng.uniform_in(0.03, TOP_SPEED.0),
                    omega: rng.uniform_in(-TOP_SPEED.1, TOP_SPEED.1),
                }
            };
            until = t + rng.uniform_in(1.0, 8.0);
        }
        let dt = rng.uniform_in(0.008, 0.020);
        odometry.push(Odometry {
            t,
            v: round(command.v, 3),
            omega: round(command.omega, 3),
        });
        let [sd_v, sd_omega] = params.noise.control_sd(command);
        let moving = command.v != 0.0 || command.omega != 0.0;
        let actual = Control {
            v: speed_scale * command.v + sd_v * rng.standard_normal(),
            omega: command.omega
                + if moving { turn_offset } else { 0.0 }
                + sd_omega * rng.standard_normal(),
        };
        pose = motion::step(&pose, actual, dt);
        t += dt;
        poses.push((t, pose));
    }
    Ok(Path {
        odometry,
        poses,
        measurements: Vec::new(),
    })
}

/// A start in the room, clear of the walls and the posts, facing anywhere.
fn start(rng: &mut Rng, params: &DatasetParams, world: &World) -> Result<Vector3<f64>, Error> {
    let [width, length] = params.room;
    for _ in 0..PLACES_TRIED {
        let x = rng.uniform_in(MARGIN, width - MARGIN);
        let y = rng.uniform_in(MARGIN, length - MARGIN);
        if world
            .posts
            .iter()
            .all(|p| libm::hypot(p.x - x, p.y - y) > 0.5)
        {
            return Ok(Vector3::new(
                x,
                y,
                rng.uniform_in(-std::f64::consts::PI, std::f64::consts::PI),
            ));
        }
    }
    Err(Error::invalid(
        "room",
        "no place for a robot to start clear of the walls and half a metre from every post",
    ))
}

/// `value` to `digits` decimals, as the published files hold it.
fn round(value: f64, digits: i32) -> f64 {
    let scale = 10f64.powi(digits);
    libm::round(value * scale) / scale
}

/// Robot `r`'s camera: a frame every `FRAME` s; of the posts and other robots within its
/// field of view and range, a share recognised, each read with the camera's noise.
fn camera(
    params: &DatasetParams,
    r: usize,
    truths: &[Vec<(f64, Vector3<f64>)>],
    world: &World,
) -> Vec<Measurement> {
    let mut rng = Rng::substream(params.seed, 20 + r as u64);
    let sd = [
        params.noise.measurement[(0, 0)].sqrt(),
        params.noise.measurement[(1, 1)].sqrt(),
    ];
    let at = |path: &[(f64, Vector3<f64>)], t: f64| {
        let i = path
            .partition_point(|(time, _)| *time <= t)
            .saturating_sub(1);
        path[i].1
    };
    // Every subject the camera may see, with its subject number.
    let posts = world
        .posts
        .iter()
        .map(|p| (p.subject, Seen::Post(Vector2::new(p.x, p.y))));
    let robots = truths
        .iter()
        .enumerate()
        .filter(|(other, _)| *other != r)
        .map(|(other, path)| (other as u32 + 1, Seen::Robot(path)));
    let subjects: Vec<(u32, Seen)> = posts.chain(robots).collect();
    let barcode = |subject: u32| {
        world
            .barcodes
            .iter()
            .find(|b| b.subject == subject)
            .map(|b| b.barcode)
            .expect("every subject wears a barcode")
    };
    let mut readings = Vec::new();
    let mut t = rng.uniform_in(0.0, FRAME);
    while t < params.duration {
        let pose = at(&truths[r], t);
        for (subject, place) in &subjects {
            let place = match place {
                Seen::Post(place) => *place,
                Seen::Robot(path) => at(path, t).xy(),
            };
            let seen = super::sensor::expected(&pose, &place);
            let in_view = seen.y.abs() < FIELD_OF_VIEW && (RANGE.0..RANGE.1).contains(&seen.x);
            if in_view && rng.chance(RECOGNISED) {
                readings.push(Measurement {
                    t: round(t, 3),
                    barcode: barcode(*subject),
                    range: round(seen.x + sd[0] * rng.standard_normal(), 3),
                    bearing: round(angle::wrap(seen.y + sd[1] * rng.standard_normal()), 3),
                });
            }
        }
        t += FRAME;
    }
    readings
}

/// What a camera may see: a post where it stands, a robot along its path.
enum Seen<'a> {
    Post(Vector2<f64>),
    Robot(&'a [(f64, Vector3<f64>)]),
}

/// Motion capture of robot `r`'s path: about 60 poses a second (interpolated along the
/// path), each with a little jitter, the published decimals.
fn capture(params: &DatasetParams, r: u32, path: &[(f64, Vector3<f64>)]) -> Vec<Pose> {
    let mut rng = Rng::substream(params.seed, 30 + u64::from(r));
    let end = path.last().map_or(0.0, |(t, _)| *t);
    let mut times = Vec::new();
    let mut t = 0.0;
    while t <= end {
        times.push(t);
        t += rng.uniform_in(0.012, 0.020);
    }
    let path: Vec<Pose> = path
        .iter()
        .map(|(t, pose)| Pose {
            t: *t,
            x: pose.x,
            y: pose.y,
            theta: pose.z,
        })
        .collect();
    let poses = truth_at(&path, times.iter().copied());
    times
        .iter()
        .zip(poses)
        .map(|(t, pose)| Pose {
            t: round(*t, 3),
            x: round(pose.x + CAPTURE_SD.0 * rng.standard_normal(), 7),
            y: round(pose.y + CAPTURE_SD.0 * rng.standard_normal(), 7),
            theta: round(
                angle::wrap(pose.z + CAPTURE_SD.1 * rng.standard_normal()),
                4,
            ),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mrclam::grid::Run;
    use crate::mrclam::run::{self, Consistency};
    use crate::mrclam::{ekf::Ekf, learn};

    /// The same seed gives the same data set; another seed another.
    #[test]
    fn a_seed_makes_one_data_set() {
        let params = DatasetParams {
            duration: 20.0,
            ..DatasetParams::default()
        };
        assert_eq!(generate(&params).unwrap(), generate(&params).unwrap());
        let other = DatasetParams {
            seed: 2,
            ..params.clone()
        };
        assert_ne!(generate(&params).unwrap().0, generate(&other).unwrap().0);
    }

    /// The most crowded room the parameters allow ends, on every seed: a data set, or
    /// an error naming what did not fit (never a search without end).
    #[test]
    fn the_most_crowded_room_ends() {
        for seed in 1..=20 {
            let crowded = DatasetParams {
                seed,
                room: [3.0, 3.0],
                posts: 15,
                robots: 5,
                duration: 1.0,
                ..DatasetParams::default()
            };
            if let Err(refused) = generate(&crowded) {
                let refused = refused.to_string();
                assert!(
                    refused.starts_with("posts: too many") || refused.starts_with("room: no place"),
                    "{refused}"
                );
            }
        }
    }

    /// Robots stay in the room, record at about the published rates, read posts only in
    /// their camera's view, and the noise learned from a recording is near the true one.
    #[test]
    fn the_recordings_are_like_the_published_ones() {
        let params = DatasetParams::default();
        let (robots, world) = generate(&params).unwrap();
        assert_eq!(robots.len(), 3);
        assert_eq!(world.posts.len(), 15);
        for robot in &robots {
            let rate = |n: usize| n as f64 / params.duration;
            assert!(
                (55.0..90.0).contains(&rate(robot.odometry.len())),
                "{}",
                robot.odometry.len()
            );
            assert!(
                (45.0..75.0).contains(&rate(robot.truth.len())),
                "{}",
                robot.truth.len()
            );
            assert!(
                (0.5..5.0).contains(&rate(robot.measurements.len())),
                "{}",
                robot.measurements.len()
            );
            for pose in &robot.truth {
                assert!(
                    (0.0..5.0).contains(&pose.x) && (0.0..10.0).contains(&pose.y),
                    "{pose:?}"
                );
            }
            for m in &robot.measurements {
                assert!(
                    m.bearing.abs() < FIELD_OF_VIEW + 0.1 && m.range < RANGE.1 + 0.5,
                    "{m:?}"
                );
                assert!(world.subject_of(m.barcode).is_some());
            }
            let grid = Run::new(robot, &world).unwrap();
            let learned = learn::noise(robot, &world, &grid).unwrap();
            let range_sd = learned.measurement[(0, 0)].sqrt();
            assert!((0.06..0.10).contains(&range_sd), "range sd {range_sd}");
        }
    }

    /// On a generated data set the EKF with the true noise localizes the robot to a few
    /// centimetres where its commands alone drift off.
    #[test]
    fn the_ekf_localizes_a_generated_robot() {
        let params = DatasetParams::default();
        let (robots, world) = generate(&params).unwrap();
        let grid = Run::new(&robots[0], &world).unwrap();
        let (beliefs, _) = run::filter(&grid, &mut Ekf::new(run::start(&grid), params.noise));
        let c = Consistency::of(&grid, &beliefs);
        let drift = run::drift(&grid);
        assert!(
            c.errors.rms < 0.1 && c.errors.rms < drift.rms / 3.0,
            "{c:?} against {drift:?}"
        );
    }
}
