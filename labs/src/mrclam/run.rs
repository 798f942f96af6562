//! A filter driven along a run: the beliefs step by step, and what they come to against
//! the ground truth.

use super::belief::{Belief, Filter, Readings};
use super::grid::Run;
use super::motion;
use crate::angle;
use crate::fusion::Errors;
use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};
use serde::{Deserialize, Serialize};

/// The standard deviations of the belief every filter starts from, about the first true
/// pose: x and y [m], heading [rad].
pub const START_SD: [f64; 3] = [0.01, 0.01, 0.01];

/// The belief at the run's start: its first true pose, `START_SD` about it.
pub fn start(run: &Run) -> Belief {
    Belief {
        mean: run.steps[0].truth,
        covariance: Matrix3::from_diagonal(&Vector3::from(START_SD.map(|sd| sd * sd))),
    }
}

/// A filter's beliefs after every step of the run (the first, its start), and what became
/// of the readings.
pub fn filter<F: Filter + ?Sized>(run: &Run, filter: &mut F) -> (Vec<Belief>, Readings) {
    let mut beliefs = Vec::with_capacity(run.steps.len());
    let mut readings = Readings::default();
    beliefs.push(filter.belief());
    for step in &run.steps[1..] {
        filter.predict(step.control, run.dt);
        readings += filter.update(&step.readings);
        beliefs.push(filter.belief());
    }
    (beliefs, readings)
}

/// Dead reckoning: the commands alone, from the first true pose.
pub fn dead_reckoning(run: &Run) -> Vec<Vector3<f64>> {
    let mut pose = run.steps[0].truth;
    std::iter::once(pose)
        .chain(run.steps[1..].iter().map(|step| {
            pose = motion::step(&pose, step.control, run.dt);
            pose
        }))
        .collect()
}

/// How a filter's beliefs along a run compare with the truth.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Consistency {
    /// Position errors [m].
    pub errors: Errors,
    /// The mean normalised estimation error squared of the pose, e^T Sigma^-1 e with the
    /// heading's error wrapped: 3 for a consistent filter.
    pub nees: f64,
    /// The share of steps whose true position lies inside the belief's 3-sigma ellipse
    /// (1 - exp(-9/2), 98.9 %, for a consistent filter).
    pub inside_three_sigma: f64,
}

/// The share of steps a consistent filter has inside its 3-sigma ellipse.
pub const CONSISTENT_INSIDE: f64 = 0.988_891_003_461_758_6;

impl Consistency {
    /// The beliefs against the run's truth, step by step.
    pub fn of(run: &Run, beliefs: &[Belief]) -> Consistency {
        let pairs = || beliefs.iter().zip(run.truths());
        let errors =
            Errors::of(pairs().map(|(b, t)| (b.mean.into(), t.into()))).expect("a run has steps");
        let (mut nees, mut nees_steps, mut inside) = (0.0, 0usize, 0usize);
        for (belief, truth) in pairs() {
            let e = error(&belief.mean, &truth);
            // Through Cholesky factors: a covariance not positive definite (a particle
            // cloud collapsed onto a few poses) has no NEES at that step, and no ellipse
            // the truth could be inside.
            if let Some(factor) = belief.covariance.cholesky() {
                nees += e.dot(&factor.solve(&e));
                nees_steps += 1;
            }
            let position: Matrix2<f64> = belief.covariance.fixed_view::<2, 2>(0, 0).into();
            if let Some(factor) = position.cholesky() {
                let p: Vector2<f64> = e.fixed_rows::<2>(0).into();
                if p.dot(&factor.solve(&p)) <= 9.0 {
                    inside += 1;
                }
            }
        }
        Consistency {
            errors,
            nees: nees / nees_steps.max(1) as f64,
            inside_three_sigma: inside as f64 / beliefs.len() as f64,
        }
    }
}

/// The pose error `mean - truth`, the heading's wrapped.
pub fn error(mean: &Vector3<f64>, truth: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(
        mean.x - truth.x,
        mean.y - truth.y,
        angle::difference(mean.z, truth.z),
    )
}
