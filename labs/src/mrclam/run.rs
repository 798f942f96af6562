//! A filter driven along a run: the beliefs step by step, and what they come to against
//! the ground truth.

use super::belief::{Belief, Filter, Readings};
use super::ekf::Ekf;
use super::grid::Run;
use super::motion::{self, Noise};
use super::particle::{self, PARTICLES, ParticleFilter};
use super::ukf::Ukf;
use crate::angle;
use crate::error::Error;
use crate::fusion::Errors;
use crate::rng::Rng;
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

/// Which filter.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, strum::EnumString, ts_rs::TS,
)]
#[serde(rename_all = "kebab-case")]
#[strum(serialize_all = "kebab-case")]
#[ts(rename = "MrclamFilter")]
pub enum Kind {
    Ekf,
    Ukf,
    Particle,
}

impl Kind {
    pub const ALL: [Kind; 3] = [Kind::Ekf, Kind::Ukf, Kind::Particle];

    pub fn name(self) -> &'static str {
        match self {
            Kind::Ekf => "EKF",
            Kind::Ukf => "UKF",
            Kind::Particle => "particle filter",
        }
    }
}

/// What the filters are run with besides the noise.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
#[serde(default)]
#[ts(rename = "MrclamSettings")]
pub struct Settings {
    /// R2 is scaled by rho (`Noise::with_measurement_scale`).
    pub rho: f64,
    /// The particle filter's particles.
    #[ts(type = "number")]
    pub particles: usize,
    /// The seed of its random numbers.
    #[ts(type = "number")]
    pub seed: u64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            rho: 1.0,
            particles: PARTICLES,
            seed: 1,
        }
    }
}

/// The most particles a run may have.
pub const MAX_PARTICLES: usize = 100_000;

impl Settings {
    pub fn validate(&self) -> Result<(), Error> {
        if !(self.rho.is_finite() && self.rho > 0.0) {
            return Err(Error::invalid("rho", "a positive number"));
        }
        if !(1..=MAX_PARTICLES).contains(&self.particles) {
            return Err(Error::invalid("particles", format!("1 to {MAX_PARTICLES}")));
        }
        Ok(())
    }
}

/// The filter `kind` at the run's start, with `noise` (R2 scaled by the settings' rho).
pub fn make(kind: Kind, run: &Run, noise: &Noise, settings: &Settings) -> Box<dyn Filter> {
    let start = start(run);
    let noise = noise.with_measurement_scale(settings.rho);
    match kind {
        Kind::Ekf => Box::new(Ekf::new(start, noise)),
        Kind::Ukf => Box::new(Ukf::new(start, noise)),
        Kind::Particle => {
            let particles = particle::Settings {
                particles: settings.particles,
                ..particle::Settings::default()
            };
            Box::new(ParticleFilter::new(
                start,
                noise,
                particles,
                Rng::new(settings.seed),
            ))
        }
    }
}

/// A filter's beliefs after every step of the run (the first, its start), and what became
/// of the readings.
pub fn filter<F: Filter + ?Sized>(run: &Run, filter: &mut F) -> (Vec<Belief>, Readings) {
    watch(run, filter, |_, _| {})
}

/// `filter`, with `each(k, filter)` called after every step k (0, the start, too).
pub fn watch<F: Filter + ?Sized>(
    run: &Run,
    filter: &mut F,
    mut each: impl FnMut(usize, &F),
) -> (Vec<Belief>, Readings) {
    let mut beliefs = Vec::with_capacity(run.steps.len());
    let mut readings = Readings::default();
    beliefs.push(filter.belief());
    each(0, filter);
    for (k, step) in run.steps.iter().enumerate().skip(1) {
        filter.predict(step.control, run.dt);
        readings += filter.update(&step.readings);
        beliefs.push(filter.belief());
        each(k, filter);
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

/// How far dead reckoning strays from the truth.
pub fn drift(run: &Run) -> Errors {
    let poses = dead_reckoning(run);
    Errors::of(
        poses
            .iter()
            .zip(run.truths())
            .map(|(pose, truth)| ((*pose).into(), truth.into())),
    )
    .expect("a run has steps")
}

/// How a filter's beliefs along a run compare with the truth.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
#[ts(rename = "MrclamConsistency")]
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
            let step = StepConsistency::of(belief, &truth);
            if let Some(n) = step.nees {
                nees += n;
                nees_steps += 1;
            }
            inside += usize::from(step.inside_three_sigma);
        }
        Consistency {
            errors,
            nees: nees / nees_steps.max(1) as f64,
            inside_three_sigma: inside as f64 / beliefs.len() as f64,
        }
    }
}

/// How one step's belief compares with the truth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepConsistency {
    /// The distance of the mean from the true position, metres.
    pub position_error: f64,
    /// e^T Sigma^-1 e; `None` where the covariance is not positive definite.
    pub nees: Option<f64>,
    pub inside_three_sigma: bool,
}

impl StepConsistency {
    /// Through Cholesky factors: a covariance not positive definite (a particle cloud
    /// collapsed onto a few poses) has no NEES at that step, and no ellipse the truth
    /// could be inside.
    pub fn of(belief: &Belief, truth: &Vector3<f64>) -> StepConsistency {
        let e = error(&belief.mean, truth);
        let nees = belief
            .covariance
            .cholesky()
            .map(|factor| e.dot(&factor.solve(&e)));
        let position: Matrix2<f64> = belief.covariance.fixed_view::<2, 2>(0, 0).into();
        let p: Vector2<f64> = e.fixed_rows::<2>(0).into();
        let inside_three_sigma = position
            .cholesky()
            .is_some_and(|factor| p.dot(&factor.solve(&p)) <= 9.0);
        StepConsistency {
            position_error: libm::hypot(e.x, e.y),
            nees,
            inside_three_sigma,
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
