//! Fusing odometry with the indoor positioning sensor: trials (generated, the report's
//! files the server offers, or the user's CSV) and whole runs of the filter.
//!
//! Settings come in as JSON of `labs::fusion`'s own types (missing fields take their
//! defaults); results go out series by series as typed arrays, NaN where a step has no
//! value. Components of a pose are 0 x, 1 y, 2 theta.

use super::{from_json, to_js};
use labs::ekf::covariance_ellipse;
use labs::fusion::{
    self, Detector, Estimate, REPORT_FIGURES, Reading, ReportFigures, Settings, Summary, Trial,
    TrialParams, Use,
};
use nalgebra::{Matrix2, Vector2};
use serde::Serialize;
use std::collections::BTreeMap;
use wasm_bindgen::prelude::*;

/// The defaults the page starts from, as JSON: `{settings, trial}`.
#[wasm_bindgen(js_name = fusionDefaults)]
pub fn fusion_defaults() -> String {
    #[derive(Serialize)]
    struct Defaults {
        settings: Settings,
        trial: TrialParams,
        /// The report's published figures by its trials' names, trial1 and trial2.
        report_figures: BTreeMap<&'static str, ReportFigures>,
    }
    serde_json::to_string(&Defaults {
        settings: Settings::default(),
        trial: TrialParams::default(),
        report_figures: REPORT_FIGURES
            .map(|figures| (figures.trial, figures))
            .into(),
    })
    .expect("defaults serialise")
}

/// The gate on the Mahalanobis distance at probability `gate`: `chi2inv(gate, 3)`,
/// infinite at 1, to show beside the gate's control.
#[wasm_bindgen(js_name = fusionGateThreshold)]
pub fn fusion_gate_threshold(gate: f64) -> f64 {
    fusion::filter::chi2inv_3(gate)
}

/// A trial, held in wasm memory so that re-runs cost only the filter.
#[wasm_bindgen]
pub struct FusionTrial {
    inner: Trial,
}

impl From<Trial> for FusionTrial {
    fn from(inner: Trial) -> FusionTrial {
        FusionTrial { inner }
    }
}

impl FusionTrial {
    fn series(&self, f: impl Fn(&fusion::Step) -> f64) -> Vec<f64> {
        self.inner.steps.iter().map(f).collect()
    }
}

#[wasm_bindgen]
impl FusionTrial {
    /// A trial generated from `params` (JSON of `TrialParams`).
    pub fn generate(params: &str) -> Result<FusionTrial, JsError> {
        let params: TrialParams = from_json("trial parameters", params)?;
        Ok(FusionTrial {
            inner: fusion::generate(&params).map_err(to_js)?,
        })
    }

    /// A trial as the server sends it (JSON of `Trial`).
    #[wasm_bindgen(js_name = fromJson)]
    pub fn from_json(json: &str) -> Result<FusionTrial, JsError> {
        let inner: Trial = from_json("trial", json)?;
        if inner.steps.is_empty() {
            return Err(JsError::new("trial: it has no steps"));
        }
        Ok(FusionTrial { inner })
    }

    /// The user's own trial file; an error names the file, line and column.
    #[wasm_bindgen(js_name = parseCsv)]
    pub fn parse_csv(text: &str, name: &str) -> Result<FusionTrial, JsError> {
        Ok(FusionTrial {
            inner: Trial::parse(text, name).map_err(to_js)?,
        })
    }

    /// The trial as CSV, for download.
    pub fn csv(&self) -> String {
        self.inner.to_csv()
    }
    pub fn steps(&self) -> usize {
        self.inner.steps.len()
    }
    pub fn t(&self) -> Vec<f64> {
        self.series(|s| s.t)
    }
    pub fn truth(&self, component: usize) -> Vec<f64> {
        self.series(|s| s.truth[component.min(2)])
    }
    /// The odometry's own pose.
    pub fn odometry(&self, component: usize) -> Vec<f64> {
        self.series(|s| s.odometry[component.min(2)])
    }
    /// Whether the trial holds the report's own estimate.
    #[wasm_bindgen(js_name = hasReport)]
    pub fn has_report(&self) -> bool {
        self.inner.steps.iter().any(|s| s.report.is_some())
    }
    /// The report's own estimate.
    pub fn report(&self, component: usize) -> Vec<f64> {
        self.series(|s| s.report.map_or(f64::NAN, |r| r[component.min(2)]))
    }
    /// The weaker platform's intensity of each reading (NaN: no reading, or a reading of
    /// the pose alone).
    pub fn intensity(&self) -> Vec<f64> {
        self.series(|s| match s.reading {
            Some(Reading::Platforms([a, b])) => a.intensity.min(b.intensity),
            _ => f64::NAN,
        })
    }

    /// Runs the filter with `settings` (JSON of `Settings`).
    pub fn run(&self, settings: &str) -> Result<FusionRun, JsError> {
        let settings = settings_of(settings)?;
        let estimates = fusion::run(&self.inner, &settings, &Detector::default());
        Ok(FusionRun::new(&self.inner, estimates))
    }

    /// Tunes the process noise on this trial from `settings` (JSON of `Settings`):
    /// JSON of `{settings, mean}`.
    pub fn tune(&self, settings: &str) -> Result<String, JsError> {
        #[derive(Serialize)]
        struct Tuned {
            settings: Settings,
            mean: f64,
        }
        let base = settings_of(settings)?;
        let (settings, mean) = fusion::tune(&self.inner, &base, &Detector::default());
        Ok(serde_json::to_string(&Tuned { settings, mean }).expect("settings serialise"))
    }
}

fn settings_of(json: &str) -> Result<Settings, JsError> {
    let settings: Settings = from_json("settings", json)?;
    settings.validate().map_err(to_js)?;
    Ok(settings)
}

/// A whole run of the filter, series by series.
#[wasm_bindgen]
pub struct FusionRun {
    estimates: Vec<Estimate>,
    summary: Summary,
}

impl FusionRun {
    /// The filter's `estimates` over (the first steps of) `trial`, summed up.
    pub(crate) fn new(trial: &Trial, estimates: Vec<Estimate>) -> FusionRun {
        FusionRun {
            summary: Summary::of(trial, &estimates),
            estimates,
        }
    }

    fn series(&self, f: impl Fn(&Estimate) -> f64) -> Vec<f64> {
        self.estimates.iter().map(f).collect()
    }
}

#[wasm_bindgen]
impl FusionRun {
    pub fn estimate(&self, component: usize) -> Vec<f64> {
        self.series(|e| e.pose[component.min(2)])
    }
    /// The square root of the diagonal of Sigma.
    pub fn std(&self, component: usize) -> Vec<f64> {
        let i = component.min(2);
        self.series(|e| e.sigma[i][i].sqrt())
    }
    /// The measured pose of each step's reading (NaN: none).
    pub fn measurement(&self, component: usize) -> Vec<f64> {
        self.series(|e| e.measurement.map_or(f64::NAN, |m| m.pose[component.min(2)]))
    }
    /// The standard deviation of x and y of each step's reading (NaN: none).
    #[wasm_bindgen(js_name = measurementSigma)]
    pub fn measurement_sigma(&self) -> Vec<f64> {
        self.series(|e| e.measurement.map_or(f64::NAN, |m| m.sigma_xy))
    }
    /// What became of each step's reading: 0 none, 1 outside the field of view, 2 gated,
    /// 3 used.
    #[wasm_bindgen(js_name = readingUse)]
    pub fn reading_use(&self) -> Vec<u8> {
        self.estimates
            .iter()
            .map(|e| match e.reading {
                Use::NoReading => 0,
                Use::OutsideView => 1,
                Use::Gated { .. } => 2,
                Use::Used { .. } => 3,
            })
            .collect()
    }
    /// The Mahalanobis distance of each step's reading (NaN: none, or outside the view).
    pub fn mahalanobis(&self) -> Vec<f64> {
        self.series(|e| match e.reading {
            Use::Gated { distance } | Use::Used { distance } => distance,
            Use::NoReading | Use::OutsideView => f64::NAN,
        })
    }
    /// The `k`-sigma ellipses of the position covariance at every `every`-th step, as
    /// x, y pairs one after the other, each closed and followed by a NaN pair.
    pub fn ellipses(&self, every: usize, k: f64, segments: usize) -> Vec<f64> {
        let mut xy = Vec::new();
        for e in self.estimates.iter().step_by(every.max(1)) {
            let s = &e.sigma;
            let sigma = Matrix2::new(s[0][0], s[0][1], s[1][0], s[1][1]);
            let centre = Vector2::new(e.pose[0], e.pose[1]);
            for p in covariance_ellipse(&centre, &sigma, k, segments) {
                xy.extend([p.x, p.y]);
            }
            xy.extend([f64::NAN, f64::NAN]);
        }
        xy
    }
    /// The summary as JSON of `labs::fusion::Summary`.
    pub fn summary(&self) -> String {
        serde_json::to_string(&self.summary).expect("a summary serialises")
    }
}
