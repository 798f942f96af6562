//! New data sets in the EL2320 format, from a seed, of each of the lab's three kinds.
//!
//! The statistics follow the original files: time step, trajectory length and speed,
//! sensor range and field of view, noise levels, outlier rate and size, so that the lab's
//! settings and bounds apply unchanged. The geometry varies with the seed, and so does
//! every noise draw.

use super::{Dataset, Encoders, Reading, SensorLog, Step};
use crate::Error;
use crate::angle::wrap;
use crate::ekf::{Landmark, Map, Robot, Settings, calculate_odometry};
use crate::rng::Rng;
use nalgebra::{Vector2, Vector3};
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// The three kinds of data set of the lab.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Kind {
    /// Like `so_o3_ie`: an indoor loop past a few landmarks, accurate readings, lightly
    /// noisy odometry.
    O3,
    /// Like `so_pb_10_outlier`: a large circle inside a ring of 10 landmarks, noisy
    /// readings with some gross outliers, noisy odometry.
    Outliers,
    /// Like `so_pb_40_no`: the same circle inside a ring of 40 landmarks, and no
    /// odometry at all.
    NoOdometry,
}

impl Kind {
    pub const ALL: [Kind; 3] = [Kind::O3, Kind::Outliers, Kind::NoOdometry];

    /// The name on the command line and in the browser.
    pub fn name(self) -> &'static str {
        match self {
            Kind::O3 => "o3",
            Kind::Outliers => "outliers",
            Kind::NoOdometry => "no-odometry",
        }
    }

    pub fn from_name(name: &str) -> Result<Kind, Error> {
        Kind::ALL
            .into_iter()
            .find(|kind| kind.name() == name)
            .ok_or_else(|| {
                Error::invalid(
                    "kind",
                    format!("'{name}' is none of o3, outliers, no-odometry"),
                )
            })
    }

    /// The lab's filter settings for this kind of data.
    pub fn lab_settings(self) -> Settings {
        match self {
            Kind::O3 => Settings::lab_o3(),
            Kind::Outliers => Settings::lab_outliers(),
            Kind::NoOdometry => Settings::lab_no_odometry(),
        }
    }
}

/// A stretch of driving at constant speed and turn rate, a whole number of time steps.
struct Leg {
    steps: usize,
    v: f64,
    omega: f64,
}

impl Leg {
    fn stand(seconds: f64, dt: f64) -> Leg {
        Leg {
            steps: (seconds / dt).round() as usize,
            v: 0.0,
            omega: 0.0,
        }
    }

    fn straight(distance: f64, v: f64, dt: f64) -> Leg {
        let steps = (distance / (v * dt)).round().max(1.0);
        Leg {
            steps: steps as usize,
            v: distance / (steps * dt),
            omega: 0.0,
        }
    }

    /// Turns on the spot by `angle` (left when positive) at about `rate` rad/s.
    fn turn_on_the_spot(angle: f64, rate: f64, dt: f64) -> Leg {
        let steps = (angle.abs() / (rate * dt)).round().max(1.0);
        Leg {
            steps: steps as usize,
            v: 0.0,
            omega: angle / (steps * dt),
        }
    }

    /// Drives an arc of `radius` through `angle` (left when positive) at about `v`.
    fn arc(angle: f64, radius: f64, v: f64, dt: f64) -> Leg {
        let steps = (angle.abs() * radius / (v * dt)).round().max(1.0);
        let omega = angle / (steps * dt);
        Leg {
            steps: steps as usize,
            v: omega.abs() * radius,
            omega,
        }
    }
}

/// The range-bearing sensor.
struct Sensor {
    max_range: f64,
    /// Landmarks are seen at bearings in [min, max).
    field_of_view: (f64, f64),
    /// Standard deviations of the range and bearing noise.
    noise: [f64; 2],
    outlier_rate: f64,
    /// Mean and standard deviation of the offset of an outlier's range and bearing.
    outlier_range: (f64, f64),
    outlier_bearing: (f64, f64),
}

/// Everything that differs between the kinds.
struct Scenario {
    dt: f64,
    landmarks: Vec<Vector2<f64>>,
    legs: Vec<Leg>,
    sensor: Sensor,
    /// Relative standard deviation of each wheel's travel per step; `None`: no odometry.
    wheel_slip: Option<f64>,
}

/// Simulates a data set of this kind; the same seed gives the same data set.
pub fn simulate(kind: Kind, seed: u64) -> Dataset {
    let scenario = match kind {
        Kind::O3 => indoor_loop(&mut Rng::substream(seed, 1)),
        Kind::Outliers => ring(
            &mut Rng::substream(seed, 1),
            10,
            0.2,
            0.2,
            (5.0, 0.2),
            (1.0, 0.25),
        ),
        Kind::NoOdometry => ring(
            &mut Rng::substream(seed, 1),
            40,
            1.0,
            0.1,
            (3.0, 0.1),
            (10.0, 0.1),
        ),
    };
    let map = Map::new(
        (1..)
            .zip(&scenario.landmarks)
            .map(|(id, &position)| Landmark {
                id,
                position: position.map(round),
            })
            .collect(),
    )
    .expect("simulated landmarks have distinct ids and finite positions");
    let log = drive(
        &scenario,
        &map,
        &mut Rng::substream(seed, 2),
        &mut Rng::substream(seed, 3),
    );
    Dataset { map, log }
}

/// The indoor loop of `so_o3_ie`: counter-clockwise round a rectangle of about 22 x 6 m at
/// about 0.47 m/s (dt = 0.2 s, some 590 steps), landmarks inside the loop, a sensor that
/// looks to the left (bearings in [0, pi)) up to 10 m, noise 0.01 m and 0.01 rad, no
/// outliers, wheel slip 0.5 %.
fn indoor_loop(rng: &mut Rng) -> Scenario {
    let dt = 0.2;
    let length = rng.uniform_in(20.0, 24.0);
    let width = rng.uniform_in(5.5, 7.0);
    let v = rng.uniform_in(0.43, 0.51);
    let corner = 0.4;
    let turn = || Leg::arc(FRAC_PI_2, corner, v, dt);
    let legs = vec![
        Leg::straight(length - corner, v, dt),
        turn(),
        Leg::straight(width - 2.0 * corner, v, dt),
        turn(),
        Leg::straight(length - 2.0 * corner, v, dt),
        turn(),
        Leg::straight(width - 2.0 * corner - 0.3, v, dt),
    ];
    let count = 14 + (rng.uniform() * 5.0) as usize;
    let landmarks = scatter(rng, count, (1.0, length - 1.0), (1.0, width - 1.0), 1.2);
    Scenario {
        dt,
        landmarks,
        legs,
        sensor: Sensor {
            max_range: 10.0,
            field_of_view: (0.0, PI),
            noise: [0.01, 0.01],
            outlier_rate: 0.0,
            outlier_range: (0.0, 0.0),
            outlier_bearing: (0.0, 0.0),
        },
        wheel_slip: Some(0.005),
    }
}

/// The big circle of the pentagon data sets. The robot stands for 3 s, turns on the spot
/// (0.5 rad/s) away from the centre of a ring of `count` landmarks of radius 20 m, drives
/// out to a circle of radius about 18 m round that centre, turns onto it and drives it
/// once (about 113 m at about 0.48 m/s). It sees all round up to 10 m, so 1-2 of 10 or
/// 6-7 of 40 landmarks at a time; 3 % of the readings are outliers, their range and
/// bearing offset by the given (mean, std). With odometry (dt < 1 s), each wheel slips by
/// 4.5 % of its travel.
fn ring(
    rng: &mut Rng,
    count: usize,
    dt: f64,
    noise: f64,
    outlier_range: (f64, f64),
    outlier_bearing: (f64, f64),
) -> Scenario {
    let radius = rng.uniform_in(17.6, 18.4);
    let v = rng.uniform_in(0.46, 0.5);
    // Counter-clockwise round a centre ahead to the left of the start, or clockwise round
    // one ahead to the right; the start about 2.5 m inside the circle.
    let side = if rng.chance(0.5) { 1.0 } else { -1.0 };
    let towards_centre = side * rng.uniform_in(0.5, 1.0);
    let distance = rng.uniform_in(15.0, 16.2);
    let centre = distance * Vector2::new(libm::cos(towards_centre), libm::sin(towards_centre));
    let phase = rng.uniform_in(0.0, TAU / count as f64);
    let landmarks = (0..count)
        .map(|k| {
            let angle = phase + TAU * k as f64 / count as f64;
            centre + 20.0 * Vector2::new(libm::cos(angle), libm::sin(angle))
        })
        .collect();
    let legs = vec![
        Leg::stand(3.0, dt),
        Leg::turn_on_the_spot(wrap(towards_centre + PI), 0.5, dt),
        Leg::straight(radius - distance, v, dt),
        Leg::turn_on_the_spot(side * FRAC_PI_2, 0.5, dt),
        Leg::arc(side * TAU, radius, v, dt),
    ];
    Scenario {
        dt,
        landmarks,
        legs,
        sensor: Sensor {
            max_range: 10.0,
            field_of_view: (-PI, PI),
            noise: [noise, noise],
            outlier_rate: 0.03,
            outlier_range,
            outlier_bearing,
        },
        wheel_slip: (dt < 1.0).then_some(0.045),
    }
}

/// `count` points uniformly in a rectangle, each at least `spacing` from the others.
fn scatter(
    rng: &mut Rng,
    count: usize,
    xs: (f64, f64),
    ys: (f64, f64),
    spacing: f64,
) -> Vec<Vector2<f64>> {
    let mut points: Vec<Vector2<f64>> = Vec::with_capacity(count);
    while points.len() < count {
        let p = Vector2::new(rng.uniform_in(xs.0, xs.1), rng.uniform_in(ys.0, ys.1));
        if points.iter().all(|q| (p - q).norm() >= spacing) {
            points.push(p);
        }
    }
    points
}

/// Drives the legs from the origin, heading 0, counting encoder ticks (with wheel slip,
/// drawn from `slip`) and reading the landmarks (noise drawn from `noise`).
fn drive(scenario: &Scenario, map: &Map, slip: &mut Rng, noise: &mut Rng) -> SensorLog {
    let robot = Robot::EL2320;
    let metres_per_tick = TAU * robot.right_radius / robot.ticks_per_revolution;
    let commands = scenario
        .legs
        .iter()
        .flat_map(|leg| (0..leg.steps).map(|_| (leg.v, leg.omega)));

    let mut truth = Vector3::zeros();
    let mut travelled = [0.0_f64; 2];
    let mut dead_reckoning = Vector3::zeros();
    let mut steps = vec![observe(
        scenario,
        map,
        0.0,
        truth,
        Encoders {
            right: 0.0,
            left: 0.0,
        },
        dead_reckoning,
        noise,
    )];
    for (k, (v, omega)) in commands.enumerate() {
        let dt = scenario.dt;
        truth = unicycle(truth, v, omega, dt);
        let mut encoders = Encoders {
            right: 0.0,
            left: 0.0,
        };
        if let Some(relative) = scenario.wheel_slip {
            let previous = steps.last().map_or(encoders, |s: &Step| s.encoders);
            for (wheel, sign) in travelled.iter_mut().zip([1.0, -1.0]) {
                let distance = (v + sign * omega * robot.wheel_base / 2.0) * dt;
                *wheel += slip.normal(distance, relative * distance.abs());
            }
            encoders = Encoders {
                right: (travelled[0] / metres_per_tick).round(),
                left: (travelled[1] / metres_per_tick).round(),
            };
            let u = calculate_odometry(
                encoders.right - previous.right,
                encoders.left - previous.left,
                &robot,
                dt,
                &dead_reckoning,
            );
            dead_reckoning += u;
            dead_reckoning.z = wrap(dead_reckoning.z);
        }
        let t = round((k + 1) as f64 * dt);
        steps.push(observe(
            scenario,
            map,
            t,
            truth,
            encoders,
            dead_reckoning,
            noise,
        ));
    }
    SensorLog { steps }
}

/// The pose after driving at speed `v` and turn rate `omega` for `dt`, exactly (on an arc).
fn unicycle(pose: Vector3<f64>, v: f64, omega: f64, dt: f64) -> Vector3<f64> {
    let theta = pose.z;
    let turned = theta + omega * dt;
    let step = if omega.abs() < 1e-12 {
        Vector2::new(v * dt * libm::cos(theta), v * dt * libm::sin(theta))
    } else {
        let r = v / omega;
        Vector2::new(
            r * (libm::sin(turned) - libm::sin(theta)),
            r * (libm::cos(theta) - libm::cos(turned)),
        )
    };
    Vector3::new(pose.x + step.x, pose.y + step.y, wrap(turned))
}

/// One line of the sensor file: the readings of every landmark in view.
fn observe(
    scenario: &Scenario,
    map: &Map,
    t: f64,
    truth: Vector3<f64>,
    encoders: Encoders,
    dead_reckoning: Vector3<f64>,
    rng: &mut Rng,
) -> Step {
    let sensor = &scenario.sensor;
    let mut readings = Vec::new();
    for (landmark, l) in map.landmarks().iter().enumerate() {
        let d = l.position - truth.xy();
        let range = d.norm();
        let bearing = wrap(libm::atan2(d.y, d.x) - truth.z);
        let (low, high) = sensor.field_of_view;
        if range > sensor.max_range || bearing < low || bearing >= high {
            continue;
        }
        let mut z = Vector2::new(
            rng.normal(range, sensor.noise[0]),
            rng.normal(bearing, sensor.noise[1]),
        );
        if rng.chance(sensor.outlier_rate) {
            z.x += rng.normal(sensor.outlier_range.0, sensor.outlier_range.1);
            z.y += rng.normal(sensor.outlier_bearing.0, sensor.outlier_bearing.1);
        }
        readings.push(Reading {
            id: l.id,
            landmark,
            z: z.map(round),
        });
    }
    Step {
        t,
        odometry: dead_reckoning.map(round),
        encoders,
        truth: Vector3::new(round(truth.x), round(truth.y), round(truth.z)),
        readings,
    }
}

/// To the micrometre (or microradian, or microsecond), as the files are written.
fn round(value: f64) -> f64 {
    (value * 1e6).round() / 1e6
}
