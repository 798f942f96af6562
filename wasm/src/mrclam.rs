//! The three filters on a robot of an MRCLAM-like data set: generated from a seed, or a
//! real robot's recording as the server sends it. Settings come in as JSON of
//! `labs::mrclam`'s types; results go out series by series as typed arrays, NaN where a
//! step has no value. Components of a pose are 0 x, 1 y, 2 theta.

use super::{from_json, to_js};
use labs::ekf::covariance_ellipse;
use labs::mrclam::belief::Belief;
use labs::mrclam::learn::Learned;
use labs::mrclam::run::{self, CONSISTENT_INSIDE, Consistency, Kind, Settings, StepConsistency};
use labs::mrclam::simulate::{self, DatasetParams};
use nalgebra::{Matrix2, Vector3};
use serde::Serialize;
use wasm_bindgen::prelude::*;

/// The most steps a run keeps the samples of (each as many as the particles).
const MAX_SNAPSHOTS: usize = 1000;

/// The defaults the page starts from, as JSON: `{dataset, settings, consistent_inside}`.
#[wasm_bindgen(js_name = mrclamDefaults)]
pub fn mrclam_defaults() -> String {
    #[derive(Serialize)]
    struct Defaults {
        dataset: DatasetParams,
        settings: Settings,
        /// The share of steps a consistent filter has inside its 3-sigma ellipse.
        consistent_inside: f64,
    }
    serde_json::to_string(&Defaults {
        dataset: DatasetParams::default(),
        settings: Settings::default(),
        consistent_inside: CONSISTENT_INSIDE,
    })
    .expect("defaults serialise")
}

/// A robot's recording on the grid, with the noise learned from it, held in wasm memory
/// so that runs cost only the filters.
#[wasm_bindgen]
pub struct MrclamRobot {
    inner: Learned,
}

impl MrclamRobot {
    fn series(&self, f: impl Fn(&labs::mrclam::grid::Step) -> f64) -> Vec<f64> {
        self.inner.run.steps.iter().map(f).collect()
    }
}

#[wasm_bindgen]
impl MrclamRobot {
    /// Robot `robot` (1 on) of the data set generated from `params` (JSON of
    /// `DatasetParams`).
    pub fn generate(params: &str, robot: usize) -> Result<MrclamRobot, JsError> {
        let params: DatasetParams = from_json("data set parameters", params)?;
        let (robots, world) = simulate::generate(&params).map_err(to_js)?;
        let recording = robot
            .checked_sub(1)
            .and_then(|i| robots.get(i))
            .ok_or_else(|| {
                JsError::new(&format!(
                    "robot {robot}: the data set has 1 to {}",
                    robots.len()
                ))
            })?;
        let inner = Learned::new(recording, &world).map_err(to_js)?;
        Ok(MrclamRobot { inner })
    }

    /// A recording as the server sends it (JSON of `Learned`).
    #[wasm_bindgen(js_name = fromJson)]
    pub fn from_json(json: &str) -> Result<MrclamRobot, JsError> {
        let inner: Learned = from_json("recording", json)?;
        if inner.run.steps.len() < 2 {
            return Err(JsError::new("recording: it has fewer than two steps"));
        }
        Ok(MrclamRobot { inner })
    }

    pub fn steps(&self) -> usize {
        self.inner.run.steps.len()
    }
    pub fn t(&self) -> Vec<f64> {
        self.series(|s| s.t)
    }
    pub fn truth(&self, component: usize) -> Vec<f64> {
        self.series(|s| s.truth[component.min(2)])
    }
    /// How many readings of posts each step holds.
    pub fn readings(&self) -> Vec<f64> {
        self.series(|s| s.readings.len() as f64)
    }
    /// The posts, as x, y pairs.
    pub fn posts(&self) -> Vec<f64> {
        self.inner.posts.iter().flat_map(|p| [p.x, p.y]).collect()
    }
    /// Dead reckoning's pose.
    #[wasm_bindgen(js_name = deadReckoning)]
    pub fn dead_reckoning(&self, component: usize) -> Vec<f64> {
        run::dead_reckoning(&self.inner.run)
            .iter()
            .map(|pose| pose[component.min(2)])
            .collect()
    }
    /// Dead reckoning's errors, as JSON of `labs::fusion::Errors`.
    pub fn drift(&self) -> String {
        serde_json::to_string(&run::drift(&self.inner.run)).expect("errors serialise")
    }
    /// The noise learned from the recording, as JSON of `Noise`.
    pub fn noise(&self) -> String {
        serde_json::to_string(&self.inner.noise).expect("noise serialises")
    }
    /// The longest stretch without a reading of a post: its start and end, seconds.
    #[wasm_bindgen(js_name = blindStretch)]
    pub fn blind_stretch(&self) -> Vec<f64> {
        let (from, to) = self.inner.run.longest_blind_stretch();
        vec![from, to]
    }

    /// A run of the filter `kind` (ekf, ukf, particle) with `settings` (JSON of
    /// `Settings`), keeping the filter's samples (particles, sigma points) at `snapshots`
    /// steps spread evenly over the run.
    pub fn run(
        &self,
        kind: &str,
        settings: &str,
        snapshots: usize,
    ) -> Result<MrclamFilterRun, JsError> {
        let kind: Kind = kind
            .parse()
            .map_err(|_| JsError::new(&format!("filter: {kind} is none of ekf, ukf, particle")))?;
        let settings: Settings = from_json("settings", settings)?;
        settings.validate().map_err(to_js)?;
        let run = &self.inner.run;
        let mut filter = run::make(kind, run, &self.inner.noise, &settings);
        let last = run.steps.len() - 1;
        if snapshots > MAX_SNAPSHOTS {
            return Err(JsError::new(&format!("snapshots: at most {MAX_SNAPSHOTS}")));
        }
        let wanted: Vec<usize> = match snapshots.min(run.steps.len()) {
            0 => Vec::new(),
            1 => vec![0],
            n => (0..n).map(|i| (i * last + (n - 1) / 2) / (n - 1)).collect(),
        };
        let mut samples = Vec::with_capacity(wanted.len());
        let (beliefs, readings) = run::watch(run, filter.as_mut(), |k, filter| {
            if wanted.get(samples.len()) == Some(&k) {
                samples.push(xy(&filter.samples()));
            }
        });
        let steps = beliefs
            .iter()
            .zip(run.truths())
            .map(|(belief, truth)| StepConsistency::of(belief, &truth))
            .collect();
        let summary = Summary {
            consistency: Consistency::of(run, &beliefs),
            readings,
        };
        Ok(MrclamFilterRun {
            beliefs,
            steps,
            summary,
            snapshot_steps: wanted.iter().map(|&k| k as f64).collect(),
            samples,
        })
    }
}

/// Poses as x, y pairs.
fn xy(poses: &[Vector3<f64>]) -> Vec<f64> {
    poses.iter().flat_map(|p| [p.x, p.y]).collect()
}

/// A run summed up: how it compares with the truth, and what became of the readings.
#[derive(Serialize)]
struct Summary {
    consistency: Consistency,
    readings: labs::mrclam::belief::Readings,
}

/// A whole run of one filter, series by series.
#[wasm_bindgen]
pub struct MrclamFilterRun {
    beliefs: Vec<Belief>,
    steps: Vec<StepConsistency>,
    summary: Summary,
    snapshot_steps: Vec<f64>,
    samples: Vec<Vec<f64>>,
}

impl MrclamFilterRun {
    fn series(&self, f: impl Fn(&Belief) -> f64) -> Vec<f64> {
        self.beliefs.iter().map(f).collect()
    }
}

#[wasm_bindgen]
impl MrclamFilterRun {
    pub fn estimate(&self, component: usize) -> Vec<f64> {
        self.series(|b| b.mean[component.min(2)])
    }
    /// The square root of the diagonal of Sigma.
    pub fn std(&self, component: usize) -> Vec<f64> {
        let i = component.min(2);
        self.series(|b| b.covariance[(i, i)].sqrt())
    }
    /// The distance from the truth, metres.
    #[wasm_bindgen(js_name = positionError)]
    pub fn position_error(&self) -> Vec<f64> {
        self.steps.iter().map(|s| s.position_error).collect()
    }
    /// The NEES of each step (NaN where the covariance is not positive definite).
    pub fn nees(&self) -> Vec<f64> {
        self.steps
            .iter()
            .map(|s| s.nees.unwrap_or(f64::NAN))
            .collect()
    }
    /// 1 where the truth lies inside the 3-sigma ellipse, else 0.
    pub fn inside(&self) -> Vec<u8> {
        self.steps
            .iter()
            .map(|s| u8::from(s.inside_three_sigma))
            .collect()
    }
    /// The summary as JSON: `{consistency, readings}`.
    pub fn summary(&self) -> String {
        serde_json::to_string(&self.summary).expect("a summary serialises")
    }
    /// The `k`-sigma ellipse of the position covariance at `step`, as closed x, y pairs.
    pub fn ellipse(&self, step: usize, k: f64, segments: usize) -> Vec<f64> {
        let Some(belief) = self.beliefs.get(step) else {
            return Vec::new();
        };
        let sigma: Matrix2<f64> = belief.covariance.fixed_view::<2, 2>(0, 0).into();
        covariance_ellipse(&belief.mean.xy(), &sigma, k, segments)
            .iter()
            .flat_map(|p| [p.x, p.y])
            .collect()
    }
    /// The steps whose samples were kept.
    #[wasm_bindgen(js_name = snapshotSteps)]
    pub fn snapshot_steps(&self) -> Vec<f64> {
        self.snapshot_steps.clone()
    }
    /// The samples kept at the `i`-th snapshot, as x, y pairs (none for the EKF).
    pub fn samples(&self, i: usize) -> Vec<f64> {
        self.samples.get(i).cloned().unwrap_or_default()
    }
}
