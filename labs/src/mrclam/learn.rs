//! The noise learned from the data itself: the control noise's alphas from how far the
//! motion the ground truth implies strays from the commanded one, and the camera's R2 from
//! the readings' residuals against the ground truth.

use super::grid::{Control, Run, truth_at};
use super::motion::Noise;
use super::sensor;
use super::{Post, Robot, World};
use crate::angle;
use crate::error::Error;
use nalgebra::{Matrix2, Vector2};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The motion the ground truth implies over each step of the run, beside the commanded
/// one: (commanded, implied). The heading's change over the step gives omega; the chord
/// between the two positions, projected on the mean heading and lengthened to the arc
/// (chord = arc * sin(delta/2) / (delta/2)), gives v.
pub fn implied_controls(run: &Run) -> Vec<(Control, Control)> {
    run.steps
        .windows(2)
        .map(|pair| {
            let (a, b) = (pair[0].truth, pair[1].truth);
            let delta = angle::difference(b.z, a.z);
            let heading = a.z + delta / 2.0;
            let along = (b.x - a.x) * libm::cos(heading) + (b.y - a.y) * libm::sin(heading);
            let half = delta / 2.0;
            let arc = if half.abs() < 1e-9 {
                along
            } else {
                along * half / libm::sin(half)
            };
            (
                pair[1].control,
                Control {
                    v: arc / run.dt,
                    omega: delta / run.dt,
                },
            )
        })
        .collect()
}

/// The alphas by least squares. For a zero-mean normal error of standard deviation sd,
/// E|e| = sd sqrt(2/pi); so sqrt(pi/2) |v_implied - v| ~ alpha1 |v| + alpha2 |omega| and
/// sqrt(pi/2) |omega_implied - omega| ~ alpha3 |v| + alpha4 |omega|, two linear fits
/// (alphas kept non-negative) over the steps where the robot was commanded to move.
pub fn alphas(pairs: &[(Control, Control)]) -> [f64; 4] {
    let scale = (PI / 2.0).sqrt();
    let moving = || pairs.iter().filter(|(u, _)| u.v != 0.0 || u.omega != 0.0);
    let rows = || moving().map(|(u, _)| [u.v.abs(), u.omega.abs()]);
    let v = fit(rows(), moving().map(|(u, m)| scale * (m.v - u.v).abs()));
    let omega = fit(
        rows(),
        moving().map(|(u, m)| scale * (m.omega - u.omega).abs()),
    );
    [v[0], v[1], omega[0], omega[1]]
}

/// The non-negative least-squares coefficients (a, b) of y ~ a x1 + b x2.
pub fn fit(rows: impl Iterator<Item = [f64; 2]>, ys: impl Iterator<Item = f64>) -> [f64; 2] {
    let (mut xtx, mut xty) = (Matrix2::zeros(), Vector2::zeros());
    for (row, y) in rows.zip(ys) {
        let x = Vector2::from(row);
        xtx += x * x.transpose();
        xty += x * y;
    }
    let one = |i: usize| {
        let a = if xtx[(i, i)] > 0.0 {
            (xty[i] / xtx[(i, i)]).max(0.0)
        } else {
            0.0
        };
        let mut ab = [0.0; 2];
        ab[i] = a;
        ab
    };
    match xtx.try_inverse().map(|inverse| inverse * xty) {
        Some(ab) if ab.x >= 0.0 && ab.y >= 0.0 => [ab.x, ab.y],
        _ => {
            let sse = |ab: [f64; 2]| {
                // Compared through the normal equations: y^T y is common to both.
                let ab = Vector2::from(ab);
                (ab.transpose() * xtx * ab).x - 2.0 * ab.dot(&xty)
            };
            let (a, b) = (one(0), one(1));
            if sse(a) <= sse(b) { a } else { b }
        }
    }
}

/// The residuals (range, bearing wrapped) of every reading of a post against what the
/// camera would have seen from the true pose at the reading's time, within the truth's
/// span.
pub fn residuals(robot: &Robot, world: &World) -> Vec<Vector2<f64>> {
    let (Some(first), Some(last)) = (robot.truth.first(), robot.truth.last()) else {
        return Vec::new();
    };
    let readings: Vec<_> = robot
        .measurements
        .iter()
        .filter(|m| (first.t..=last.t).contains(&m.t))
        .filter_map(|m| world.post_of(m.barcode).map(|post| (m, post)))
        .collect();
    let truths = truth_at(&robot.truth, readings.iter().map(|(m, _)| m.t));
    readings
        .iter()
        .zip(truths)
        .map(|((m, post), pose)| {
            let expected = sensor::expected(&pose, &Vector2::new(post.x, post.y));
            sensor::innovation(&Vector2::new(m.range, m.bearing), &expected)
        })
        .collect()
}

/// R2 by maximum likelihood for zero-mean normal residuals: their mean outer product;
/// `None` without residuals, or when they do not make it positive definite (all alike).
pub fn measurement(residuals: &[Vector2<f64>]) -> Option<Matrix2<f64>> {
    let n = residuals.len() as f64;
    let r2 = residuals
        .iter()
        .map(|r| r * r.transpose())
        .sum::<Matrix2<f64>>()
        / n;
    (!residuals.is_empty() && r2.cholesky().is_some()).then_some(r2)
}

/// Everything learned from one robot's recording; `None` when its readings of posts
/// cannot teach R2 (none within the ground truth's span, or too few).
pub fn noise(robot: &Robot, world: &World, run: &Run) -> Option<Noise> {
    Some(Noise {
        alphas: alphas(&implied_controls(run)),
        measurement: measurement(&residuals(robot, world))?,
    })
}

/// A robot's recording as the filters and the page take it: on the grid, with the noise
/// learned from it and the room's posts.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Learned {
    pub run: Run,
    pub noise: Noise,
    pub posts: Vec<Post>,
}

impl Learned {
    /// The recording on the grid with what it teaches; an error (naming the field
    /// `recording`) when its ground truth holds fewer than two poses, or its readings of
    /// posts cannot teach the camera's noise.
    pub fn new(robot: &Robot, world: &World) -> Result<Learned, Error> {
        let run = Run::new(robot, world).ok_or_else(|| {
            Error::invalid("recording", "its ground truth holds fewer than two poses")
        })?;
        let noise = noise(robot, world, &run).ok_or_else(|| {
            Error::invalid(
                "recording",
                "too few readings of posts within its ground truth to learn the camera's noise",
            )
        })?;
        Ok(Learned {
            noise,
            posts: world.posts.clone(),
            run,
        })
    }
}
