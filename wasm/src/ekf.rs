//! EKF localization: data sets (simulated or the user's files) and whole runs.

use super::{from_json, seed, to_js};
use labs::dataset::{self, Kind, parse_map, parse_sensor_log, write_map, write_sensor_log};
use labs::ekf::{self, Settings, UpdateMode, covariance_ellipse, reading_position};
use nalgebra::{Matrix2, Vector3};
use serde::{Deserialize, Serialize};
use wasm_bindgen::prelude::*;

/// What the browser's controls set; the rest of the settings are the lab's.
#[derive(Serialize, Deserialize)]
struct Controls {
    mode: UpdateMode,
    known_associations: bool,
    /// Diagonal of R, variances (x, y, theta).
    r: [f64; 3],
    /// Diagonal of Q, variances (range, bearing).
    q: [f64; 2],
    delta_m: f64,
}

/// `Lambda_M = chi2inv(delta_M, 2)`, to show beside the delta_M control.
#[wasm_bindgen(js_name = lambdaM)]
pub fn lambda_m(delta_m: f64) -> f64 {
    ekf::lambda_m(delta_m)
}

/// A map and a sensor log, held in wasm memory so that re-runs cost only the filter.
#[wasm_bindgen]
pub struct Dataset {
    inner: dataset::Dataset,
    /// The kind it was simulated as; `None` for the user's own files.
    kind: Option<Kind>,
}

impl Dataset {
    pub(crate) fn of_kind(inner: dataset::Dataset, kind: Kind) -> Dataset {
        Dataset {
            inner,
            kind: Some(kind),
        }
    }
}

#[wasm_bindgen]
impl Dataset {
    /// A simulated data set: `kind` is o3, outliers or no-odometry.
    pub fn simulate(kind: &str, seed_value: f64) -> Result<Dataset, JsError> {
        let kind = Kind::from_name(kind).map_err(to_js)?;
        Ok(Dataset::of_kind(
            dataset::simulate(kind, seed(seed_value)?),
            kind,
        ))
    }

    /// The user's own EL2320 files; an error carries the parser's message, which names
    /// the file and the line.
    pub fn parse(
        map_text: &str,
        map_name: &str,
        sensor_text: &str,
        sensor_name: &str,
    ) -> Result<Dataset, JsError> {
        let map = parse_map(map_text, map_name).map_err(to_js)?;
        let log = parse_sensor_log(sensor_text, sensor_name, &map).map_err(to_js)?;
        Ok(Dataset {
            inner: dataset::Dataset { map, log },
            kind: None,
        })
    }

    /// The lab's settings for this kind of data (o3's for the user's files), as JSON of
    /// `{mode, known_associations, r, q, delta_m}`.
    #[wasm_bindgen(js_name = labSettings)]
    pub fn lab_settings(&self) -> String {
        let lab = self.kind.unwrap_or(Kind::O3).lab_settings();
        let controls = Controls {
            mode: lab.mode,
            known_associations: lab.known_associations,
            r: lab.r.diagonal().into(),
            q: lab.q.diagonal().into(),
            delta_m: lab.delta_m,
        };
        serde_json::to_string(&controls).expect("controls serialise")
    }

    #[wasm_bindgen(js_name = landmarkX)]
    pub fn landmark_x(&self) -> Vec<f64> {
        self.inner
            .map
            .landmarks()
            .iter()
            .map(|l| l.position.x)
            .collect()
    }
    #[wasm_bindgen(js_name = landmarkY)]
    pub fn landmark_y(&self) -> Vec<f64> {
        self.inner
            .map
            .landmarks()
            .iter()
            .map(|l| l.position.y)
            .collect()
    }
    #[wasm_bindgen(js_name = landmarkIds)]
    pub fn landmark_ids(&self) -> Vec<u32> {
        self.inner.map.landmarks().iter().map(|l| l.id).collect()
    }
    pub fn steps(&self) -> usize {
        self.inner.log.steps.len()
    }
    pub fn readings(&self) -> usize {
        self.inner.log.readings()
    }
    /// The map in the EL2320 format, for download.
    #[wasm_bindgen(js_name = mapFile)]
    pub fn map_file(&self) -> String {
        write_map(&self.inner.map)
    }
    /// The sensor log in the EL2320 format, for download.
    #[wasm_bindgen(js_name = sensorFile)]
    pub fn sensor_file(&self) -> String {
        write_sensor_log(&self.inner.log)
    }

    /// Runs the filter with `controls` (JSON, as `labSettings` returns it).
    pub fn run(&self, controls: &str) -> Result<EkfRun, JsError> {
        let c: Controls = from_json("settings", controls)?;
        let settings = Settings {
            mode: c.mode,
            known_associations: c.known_associations,
            delta_m: c.delta_m,
            ..self.kind.unwrap_or(Kind::O3).lab_settings()
        }
        .with_diagonals(c.r, c.q);
        Ok(EkfRun {
            inner: ekf::run(&self.inner, &settings).map_err(to_js)?,
        })
    }
}

/// A whole run, series by series. Components: 0 x, 1 y, 2 theta.
#[wasm_bindgen]
pub struct EkfRun {
    inner: ekf::Run,
}

impl From<ekf::Run> for EkfRun {
    fn from(inner: ekf::Run) -> EkfRun {
        EkfRun { inner }
    }
}

impl EkfRun {
    fn series(&self, f: impl Fn(&ekf::StepEstimate) -> f64) -> Vec<f64> {
        self.inner.steps.iter().map(f).collect()
    }

    fn component(
        &self,
        component: usize,
        f: impl Fn(&ekf::StepEstimate) -> Vector3<f64>,
    ) -> Vec<f64> {
        let i = component.min(2);
        self.series(|s| f(s)[i])
    }

    fn reading_series<T>(&self, f: impl Fn(&ekf::ReadingOutcome) -> T) -> Vec<T> {
        self.inner.readings.iter().map(f).collect()
    }
}

#[wasm_bindgen]
impl EkfRun {
    pub fn t(&self) -> Vec<f64> {
        self.series(|s| s.t)
    }
    /// The estimate mu.
    pub fn estimate(&self, component: usize) -> Vec<f64> {
        self.component(component, |s| s.mu)
    }
    pub fn truth(&self, component: usize) -> Vec<f64> {
        self.component(component, |s| s.truth)
    }
    /// The pose from the encoders alone.
    pub fn odometry(&self, component: usize) -> Vec<f64> {
        self.component(component, |s| s.odometry)
    }
    /// mu - truth, theta wrapped.
    pub fn error(&self, component: usize) -> Vec<f64> {
        self.component(component, |s| s.error)
    }
    /// The square root of the diagonal of Sigma.
    pub fn std(&self, component: usize) -> Vec<f64> {
        self.component(component, |s| s.std_dev())
    }
    /// The diagonal of Sigma.
    pub fn variance(&self, component: usize) -> Vec<f64> {
        self.component(component, |s| s.sigma.diagonal())
    }

    /// The `k`-sigma ellipses of the position covariance at every `every`-th step, as
    /// x, y pairs one after the other, each ellipse closed and followed by a NaN pair.
    pub fn ellipses(&self, every: usize, k: f64, segments: usize) -> Vec<f64> {
        let mut xy = Vec::new();
        for step in self.inner.steps.iter().step_by(every.max(1)) {
            let sigma = Matrix2::from(step.sigma.fixed_view::<2, 2>(0, 0));
            for p in covariance_ellipse(&step.mu.xy(), &sigma, k, segments) {
                xy.extend([p.x, p.y]);
            }
            xy.extend([f64::NAN, f64::NAN]);
        }
        xy
    }

    /// The time step of each reading.
    #[wasm_bindgen(js_name = readingStep)]
    pub fn reading_step(&self) -> Vec<u32> {
        self.reading_series(|r| r.step as u32)
    }
    /// The landmark (map index) each reading was associated with.
    #[wasm_bindgen(js_name = readingAssociation)]
    pub fn reading_association(&self) -> Vec<u32> {
        self.reading_series(|r| r.c as u32)
    }
    /// The landmark (map index) that truly produced each reading.
    #[wasm_bindgen(js_name = readingTruth)]
    pub fn reading_truth(&self) -> Vec<u32> {
        self.reading_series(|r| r.truth as u32)
    }
    /// 1 where the reading was rejected as an outlier.
    #[wasm_bindgen(js_name = readingOutlier)]
    pub fn reading_outlier(&self) -> Vec<u8> {
        self.reading_series(|r| u8::from(r.outlier))
    }
    #[wasm_bindgen(js_name = readingMahalanobis)]
    pub fn reading_mahalanobis(&self) -> Vec<f64> {
        self.reading_series(|r| r.mahalanobis)
    }
    /// Where each reading points from the estimate of its time step: x, y pairs.
    #[wasm_bindgen(js_name = readingPosition)]
    pub fn reading_position(&self) -> Vec<f64> {
        let steps = &self.inner.steps;
        self.inner
            .readings
            .iter()
            .flat_map(|r| {
                let p = reading_position(&steps[r.step].mu, &r.z);
                [p.x, p.y]
            })
            .collect()
    }

    /// The summary as JSON (mean error, mean absolute error, counts).
    pub fn summary(&self) -> String {
        serde_json::to_string(&self.inner.summary).expect("a summary serialises")
    }
    /// The lines the lab's script printed, plus the rejections.
    pub fn report(&self) -> String {
        self.inner.summary.report()
    }
    #[wasm_bindgen(js_name = lambdaM)]
    pub fn lambda_m(&self) -> f64 {
        self.inner.summary.lambda_m
    }
}
