//! Paths: the wheel increments of every step, made from a named shape.
//!
//! Every shape is driven as a real robot would be: straight legs (both wheels roll the
//! same distance), turns on the spot (the wheels roll equal distances in opposite
//! directions, the centre stays put) and arcs of constant radius (the outer wheel rolls
//! further). A segment is cut into the fewest equal steps in which the robot's centre
//! (on a turn on the spot, each wheel) moves at most `speed`:
//!
//! - a straight leg of length L: n = ceil(L / speed) steps, each wheel L / n per step;
//! - a turn on the spot by alpha (counter-clockwise positive): each wheel rolls the arc
//!   a = alpha b / 2 in total, n = ceil(|a| / speed) steps of ds_r = a / n, ds_l = -a / n;
//! - an arc of radius R turning by alpha: the centre travels s = R |alpha|, in
//!   n = max(ceil(s / speed), ceil(|alpha| / 10 degrees)) steps (the midpoint model is
//!   exact for a straight step and close for a short arc, so no step of an arc turns by
//!   more than 10 degrees) of ds = s / n and dtheta = alpha / n, that is
//!   ds_r = ds + dtheta b / 2, ds_l = ds - dtheta b / 2.
//!
//! Counter-clockwise is a left turn: the heading grows, seen from above with x to the
//! right and y up. Every shape but the polyline starts at the origin heading along +x.

use super::motion::Increment;
use crate::Error;
use crate::angle::wrap;
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// The most steps a path may take.
pub const MAX_STEPS: usize = 100_000;
/// The most points a polyline may have.
pub const MAX_POINTS: usize = 10_000;
/// The largest length, radius or coordinate of a shape, metres.
pub const MAX_SIZE: f64 = 1e6;
/// The largest turn one step of an arc may take: 10 degrees.
pub const MAX_ARC_TURN: f64 = PI / 18.0;

/// Which way a closed shape goes round.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Direction {
    /// Right turns: the heading decreases.
    Clockwise,
    /// Left turns: the heading increases.
    CounterClockwise,
}

impl Direction {
    /// +1 counter-clockwise, -1 clockwise: the sign of the heading's change.
    pub fn sign(self) -> f64 {
        match self {
            Direction::Clockwise => -1.0,
            Direction::CounterClockwise => 1.0,
        }
    }
}

/// A named path and its size. In JSON: `{"kind": "square", "side": 4, "direction":
/// "clockwise"}`, `{"kind": "polyline", "points": [[0, 0], [1, 0]]}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Shape {
    /// Straight ahead along +x for `length` metres.
    Line { length: f64 },
    /// One full circle of `radius`, starting along +x (its centre at (0, radius)
    /// counter-clockwise, (0, -radius) clockwise).
    Circle { radius: f64, direction: Direction },
    /// Four legs of `side` metres, each followed by a quarter turn on the spot, back to
    /// the start pose: the UMBmark square.
    Square { side: f64, direction: Direction },
    /// A counter-clockwise circle of `radius` then a clockwise one, meeting at the start.
    FigureEight { radius: f64 },
    /// From the first point, facing the second, to every next point in turn: turn on the
    /// spot to face it (the shorter way round), then drive to it. Points that repeat the
    /// one before are skipped.
    Polyline { points: Vec<[f64; 2]> },
}

impl Default for Shape {
    fn default() -> Self {
        Shape::Square {
            side: 4.0,
            direction: Direction::CounterClockwise,
        }
    }
}

impl Shape {
    /// Checks the shape's size, naming the field (`shape.side`, `shape.points`, ...).
    pub fn validate(&self) -> Result<(), Error> {
        let size = |field: &str, value: f64| {
            if value.is_finite() && value > 0.0 && value <= MAX_SIZE {
                Ok(())
            } else {
                Err(Error::invalid(
                    field,
                    format!("must lie in (0, {MAX_SIZE:e}] metres, got {value}"),
                ))
            }
        };
        match self {
            Shape::Line { length } => size("shape.length", *length),
            Shape::Circle { radius, .. } | Shape::FigureEight { radius } => {
                size("shape.radius", *radius)
            }
            Shape::Square { side, .. } => size("shape.side", *side),
            Shape::Polyline { points } => {
                if points.len() > MAX_POINTS {
                    return Err(Error::invalid(
                        "shape.points",
                        format!("at most {MAX_POINTS} points, got {}", points.len()),
                    ));
                }
                if let Some(k) = points
                    .iter()
                    .position(|p| !p.iter().all(|v| v.is_finite() && v.abs() <= MAX_SIZE))
                {
                    return Err(Error::invalid(
                        "shape.points",
                        format!(
                            "point {k} must be finite and within {MAX_SIZE:e} metres of the origin"
                        ),
                    ));
                }
                if distinct(points).len() < 2 {
                    return Err(Error::invalid(
                        "shape.points",
                        format!(
                            "needs at least 2 distinct points, got {} of {} given",
                            distinct(points).len(),
                            points.len()
                        ),
                    ));
                }
                Ok(())
            }
        }
    }

    /// A short description for people: "square of side 4 m, counter-clockwise".
    pub fn describe(&self) -> String {
        let turn = |d: &Direction| match d {
            Direction::Clockwise => "clockwise",
            Direction::CounterClockwise => "counter-clockwise",
        };
        match self {
            Shape::Line { length } => format!("line of {length} m"),
            Shape::Circle { radius, direction } => {
                format!("circle of radius {radius} m, {}", turn(direction))
            }
            Shape::Square { side, direction } => {
                format!("square of side {side} m, {}", turn(direction))
            }
            Shape::FigureEight { radius } => format!("figure eight of radius {radius} m"),
            Shape::Polyline { points } => format!("polyline of {} points", points.len()),
        }
    }
}

/// The points without those that repeat the one before.
fn distinct(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut kept: Vec<[f64; 2]> = Vec::with_capacity(points.len());
    for p in points {
        if kept.last() != Some(p) {
            kept.push(*p);
        }
    }
    kept
}

/// Where a path starts and how far each wheel rolls at every step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Path {
    /// The start pose (x, y, theta).
    pub start: [f64; 3],
    pub increments: Vec<Increment>,
}

/// One piece of a shape, before it is cut into steps.
#[derive(Clone, Copy, Debug)]
enum Segment {
    Straight(f64),
    /// A turn on the spot by this angle (counter-clockwise positive).
    Turn(f64),
    /// An arc of this radius turning by this angle.
    Arc(f64, f64),
}

/// The number of steps that cover `distance` with none longer than `speed`; at least 1.
/// (The 1e-9 keeps 4 m at 0.05 m per step at 80 steps, whichever way the quotient rounds.)
fn steps_for(distance: f64, speed: f64) -> f64 {
    libm::ceil(distance / speed - 1e-9).max(1.0)
}

impl Segment {
    fn steps(self, speed: f64, wheel_base: f64) -> f64 {
        match self {
            Segment::Straight(length) => steps_for(length, speed),
            Segment::Turn(angle) => steps_for((angle * wheel_base / 2.0).abs(), speed),
            Segment::Arc(radius, angle) => steps_for(radius * angle.abs(), speed)
                .max(libm::ceil(angle.abs() / MAX_ARC_TURN - 1e-9)),
        }
    }

    fn push(self, steps: usize, wheel_base: f64, increments: &mut Vec<Increment>) {
        let n = steps as f64;
        let increment = match self {
            Segment::Straight(length) => Increment::new(length / n, length / n),
            Segment::Turn(angle) => {
                let a = angle * wheel_base / 2.0 / n;
                Increment::new(a, -a)
            }
            Segment::Arc(radius, angle) => {
                let (ds, dtheta) = (radius * angle.abs() / n, angle / n);
                Increment::new(
                    ds + dtheta * wheel_base / 2.0,
                    ds - dtheta * wheel_base / 2.0,
                )
            }
        };
        increments.extend(std::iter::repeat_n(increment, steps));
    }
}

/// Checks the speed (metres per step) and the wheel base, naming the field.
pub(crate) fn check_speed_and_wheel_base(speed: f64, wheel_base: f64) -> Result<(), Error> {
    if !(speed.is_finite() && speed > 0.0 && speed <= MAX_SIZE) {
        return Err(Error::invalid(
            "speed",
            format!("must lie in (0, {MAX_SIZE:e}] metres per step, got {speed}"),
        ));
    }
    if !(wheel_base.is_finite() && (1e-3..=1e3).contains(&wheel_base)) {
        return Err(Error::invalid(
            "wheel_base",
            format!("must lie in [0.001, 1000] metres, got {wheel_base}"),
        ));
    }
    Ok(())
}

impl Path {
    /// The path of `shape` driven at `speed` (metres per step: the most the robot's
    /// centre moves in a step, or on a turn on the spot each wheel) by a robot with wheel
    /// base `wheel_base`. Refuses a path of more than [`MAX_STEPS`] steps.
    pub fn new(shape: &Shape, speed: f64, wheel_base: f64) -> Result<Path, Error> {
        shape.validate()?;
        check_speed_and_wheel_base(speed, wheel_base)?;
        let (start, segments) = match shape {
            Shape::Line { length } => ([0.0; 3], vec![Segment::Straight(*length)]),
            Shape::Circle { radius, direction } => (
                [0.0; 3],
                vec![Segment::Arc(*radius, direction.sign() * TAU)],
            ),
            Shape::Square { side, direction } => (
                [0.0; 3],
                [
                    Segment::Straight(*side),
                    Segment::Turn(direction.sign() * FRAC_PI_2),
                ]
                .repeat(4),
            ),
            Shape::FigureEight { radius } => (
                [0.0; 3],
                vec![Segment::Arc(*radius, TAU), Segment::Arc(*radius, -TAU)],
            ),
            Shape::Polyline { points } => polyline(&distinct(points)),
        };
        let counts: Vec<f64> = segments
            .iter()
            .map(|s| s.steps(speed, wheel_base))
            .collect();
        let total: f64 = counts.iter().sum();
        if total > MAX_STEPS as f64 {
            return Err(Error::invalid(
                "speed",
                format!(
                    "at {speed} m per step this path takes {total:.0} steps, more than the \
                     {MAX_STEPS} allowed: drive faster or make the path shorter"
                ),
            ));
        }
        let mut increments = Vec::with_capacity(total as usize);
        for (segment, count) in segments.into_iter().zip(counts) {
            segment.push(count as usize, wheel_base, &mut increments);
        }
        Ok(Path { start, increments })
    }

    /// The number of steps.
    pub fn steps(&self) -> usize {
        self.increments.len()
    }
}

/// A polyline's start pose (its first point, facing the second) and segments: turn to
/// face each next point (by the wrapped difference of bearings, so never more than half a
/// turn), then drive to it.
fn polyline(points: &[[f64; 2]]) -> ([f64; 3], Vec<Segment>) {
    let bearing = |a: [f64; 2], b: [f64; 2]| libm::atan2(b[1] - a[1], b[0] - a[0]);
    let distance = |a: [f64; 2], b: [f64; 2]| libm::hypot(b[0] - a[0], b[1] - a[1]);
    let mut heading = wrap(bearing(points[0], points[1]));
    let start = [points[0][0], points[0][1], heading];
    let mut segments = Vec::with_capacity(2 * points.len());
    for pair in points.windows(2) {
        let next = wrap(bearing(pair[0], pair[1]));
        let turn = wrap(next - heading);
        if turn != 0.0 {
            segments.push(Segment::Turn(turn));
        }
        segments.push(Segment::Straight(distance(pair[0], pair[1])));
        heading = next;
    }
    (start, segments)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wheel_sums(path: &Path) -> (f64, f64) {
        path.increments
            .iter()
            .fold((0.0, 0.0), |(r, l), i| (r + i.right, l + i.left))
    }

    #[test]
    fn a_square_is_four_legs_and_four_quarter_turns() {
        let b = 0.5;
        let path = Path::new(
            &Shape::Square {
                side: 4.0,
                direction: Direction::Clockwise,
            },
            0.05,
            b,
        )
        .unwrap();
        // A quarter turn rolls each wheel pi/2 * b/2 = 0.3927 m: 8 steps of 0.049 m.
        assert_eq!(path.steps(), 4 * (80 + 8));
        assert_eq!(path.increments[0], Increment::new(0.05, 0.05));
        let turn = path.increments[80];
        assert!((turn.right + FRAC_PI_2 * b / 2.0 / 8.0).abs() < 1e-15);
        assert_eq!(turn.left, -turn.right);
        let (right, left) = wheel_sums(&path);
        // Clockwise: the left wheel rolls further, by 2 pi * b/2 on each side.
        assert!((left - right - TAU * b).abs() < 1e-12, "{left} {right}");
        assert!(
            path.increments
                .iter()
                .all(|i| i.right.abs().max(i.left.abs()) <= 0.05 + 1e-15)
        );
    }

    #[test]
    fn an_arc_steps_no_more_than_the_speed_or_ten_degrees() {
        // A small circle at a high speed: limited by the turn, 36 steps.
        let small = Shape::Circle {
            radius: 0.1,
            direction: Direction::CounterClockwise,
        };
        assert_eq!(Path::new(&small, 1.0, 0.3).unwrap().steps(), 36);
        // A large one: limited by the speed, ceil(2 pi 10 / 0.1) = 629 steps.
        let large = Shape::Circle {
            radius: 10.0,
            direction: Direction::Clockwise,
        };
        let path = Path::new(&large, 0.1, 0.3).unwrap();
        assert_eq!(path.steps(), 629);
        let (right, left) = wheel_sums(&path);
        // Each wheel rolls round its own circle, of radius 10 -+ b/2.
        assert!((right - TAU * 9.85).abs() < 1e-9 && (left - TAU * 10.15).abs() < 1e-9);
    }

    #[test]
    fn a_polyline_starts_facing_its_second_point_and_turns_the_short_way() {
        let points = vec![[1.0, 1.0], [1.0, 1.0], [1.0, 3.0], [0.0, 3.0], [0.0, 3.0]];
        let path = Path::new(&Shape::Polyline { points }, 0.5, 0.4).unwrap();
        assert_eq!(path.start, [1.0, 1.0, FRAC_PI_2]);
        // 2 m ahead (4 steps), a left quarter turn (wheels 0.314 m: 1 step), 1 m (2 steps).
        assert_eq!(path.steps(), 7);
        assert!(path.increments[4].right > 0.0 && path.increments[4].left < 0.0);
        let points = vec![[0.0, 0.0], [1.0, 0.0], [1.0, -1.0]];
        let path = Path::new(&Shape::Polyline { points }, 0.5, 0.4).unwrap();
        assert!(path.increments[2].right < 0.0, "a right turn");
    }

    #[test]
    fn nonsense_is_refused_naming_the_field() {
        let message =
            |shape: Shape, speed: f64, b: f64| Path::new(&shape, speed, b).unwrap_err().to_string();
        let line = Shape::Line { length: 1.0 };
        assert_eq!(
            message(line.clone(), 0.0, 0.5),
            "speed: must lie in (0, 1e6] metres per step, got 0"
        );
        assert_eq!(
            message(line.clone(), f64::NAN, 0.5),
            "speed: must lie in (0, 1e6] metres per step, got NaN"
        );
        assert_eq!(
            message(line.clone(), 0.1, 0.0),
            "wheel_base: must lie in [0.001, 1000] metres, got 0"
        );
        assert_eq!(
            message(line, 1e-6, 0.5),
            "speed: at 0.000001 m per step this path takes 1000000 steps, more than the \
             100000 allowed: drive faster or make the path shorter"
        );
        assert_eq!(
            message(Shape::Line { length: -1.0 }, 0.1, 0.5),
            "shape.length: must lie in (0, 1e6] metres, got -1"
        );
        assert_eq!(
            message(
                Shape::FigureEight {
                    radius: f64::INFINITY
                },
                0.1,
                0.5
            ),
            "shape.radius: must lie in (0, 1e6] metres, got inf"
        );
        assert_eq!(
            message(
                Shape::Square {
                    side: 0.0,
                    direction: Direction::Clockwise
                },
                0.1,
                0.5
            ),
            "shape.side: must lie in (0, 1e6] metres, got 0"
        );
        assert_eq!(
            message(
                Shape::Polyline {
                    points: vec![[0.0, 0.0]]
                },
                0.1,
                0.5
            ),
            "shape.points: needs at least 2 distinct points, got 1 of 1 given"
        );
        assert_eq!(
            message(
                Shape::Polyline {
                    points: vec![[2.0, 1.0], [2.0, 1.0]]
                },
                0.1,
                0.5
            ),
            "shape.points: needs at least 2 distinct points, got 1 of 2 given"
        );
        assert_eq!(
            message(
                Shape::Polyline {
                    points: vec![[0.0, 0.0], [f64::NAN, 1.0]]
                },
                0.1,
                0.5
            ),
            "shape.points: point 1 must be finite and within 1e6 metres of the origin"
        );
        assert_eq!(
            message(
                Shape::Polyline {
                    points: vec![[0.0, 0.0]; MAX_POINTS + 1]
                },
                0.1,
                0.5
            ),
            "shape.points: at most 10000 points, got 10001"
        );
    }

    #[test]
    fn shapes_read_from_json() {
        let shape: Shape =
            serde_json::from_str(r#"{"kind": "square", "side": 2, "direction": "clockwise"}"#)
                .unwrap();
        assert_eq!(
            shape,
            Shape::Square {
                side: 2.0,
                direction: Direction::Clockwise
            }
        );
        let shape: Shape =
            serde_json::from_str(r#"{"kind": "figure-eight", "radius": 1.5}"#).unwrap();
        assert_eq!(shape, Shape::FigureEight { radius: 1.5 });
        let shape: Shape =
            serde_json::from_str(r#"{"kind": "polyline", "points": [[0, 0], [1, 2]]}"#).unwrap();
        assert_eq!(
            shape,
            Shape::Polyline {
                points: vec![[0.0, 0.0], [1.0, 2.0]]
            }
        );
    }
}
