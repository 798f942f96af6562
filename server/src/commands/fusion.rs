//! `estlab fusion`: the fusion filter over a trial (generated from a seed, one of the
//! Northstar report's from `--datasets`, or a file), and how good it is beside odometry
//! and the sensor alone.

use super::{file_name, print, read};
use crate::datasets::Datasets;
use crate::error::Error;
use labs::fusion::{
    Detector, Errors, NoiseModel, Settings, Summary, Trial, TrialParams, generate,
    run as run_filter, tune,
};
use serde::Serialize;
use std::path::PathBuf;

/// Fuse odometry with the indoor positioning sensor over a trial, and print the position
/// errors of the filter, of odometry and of the sensor alone, and how often the truth
/// lies inside the filter's 3-sigma ellipse (defaults: a generated trial of seed 1, the
/// filter's round settings).
#[derive(clap::Args)]
pub struct Args {
    /// A trial file (CSV of the report's columns: odom_*, ns_* or p1_*/p2_*, gt_*).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["report_trial", "seed", "waypoints"])]
    trial: Option<PathBuf>,
    /// One of the Northstar report's trials in the --datasets folder: trial1, trial2.
    #[arg(long, value_name = "NAME", requires = "datasets", conflicts_with_all = ["seed", "waypoints"])]
    report_trial: Option<String>,
    /// The folder of real data sets (its northstar/ holds the report's trial files).
    #[arg(long, value_name = "DIR")]
    datasets: Option<PathBuf>,
    /// The seed of a generated trial.
    #[arg(long)]
    seed: Option<u64>,
    /// How many waypoints a generated trial visits.
    #[arg(long)]
    waypoints: Option<usize>,
    /// Write the trial as CSV to this file too.
    #[arg(long, value_name = "FILE")]
    write_trial: Option<PathBuf>,
    /// k_xy: the process noise's standard deviation of position per metre moved.
    #[arg(long)]
    process_xy: Option<f64>,
    /// k_theta: the process noise's standard deviation of heading per metre moved and
    /// radian turned.
    #[arg(long)]
    process_theta: Option<f64>,
    /// c_xy: the sensor's standard deviation of x and y is c_xy / intensity.
    #[arg(long)]
    c_xy: Option<f64>,
    /// c_theta: its heading's, where the platforms are unknown, c_theta / intensity.
    #[arg(long)]
    c_theta: Option<f64>,
    /// Readings farther than this from the point under the detector are ignored, metres.
    #[arg(long)]
    field_of_view: Option<f64>,
    /// The gate's probability (chi-square, 3 degrees of freedom); 1 rejects nothing.
    #[arg(long)]
    gate: Option<f64>,
    /// Tune the process noise on this trial first (a grid of k_xy and k_theta).
    #[arg(long)]
    tune: bool,
    /// Print the settings and the summary as JSON.
    #[arg(long)]
    json: bool,
}

/// What `--json` prints.
#[derive(Serialize)]
struct Report {
    settings: Settings,
    summary: Summary,
}

pub fn run(args: &Args) -> Result<(), Error> {
    let (trial, described) = trial(args)?;
    if let Some(path) = &args.write_trial {
        std::fs::write(path, trial.to_csv()).map_err(Error::io(path))?;
    }
    let detector = Detector::default();
    let mut settings = settings(args);
    settings.validate()?;
    if args.tune {
        settings = tune(&trial, &settings, &detector).0;
    }
    let summary = Summary::of(&trial, &run_filter(&trial, &settings, &detector));
    if args.json {
        let json = serde_json::to_string_pretty(&Report { settings, summary })
            .expect("a report serialises");
        return print(&json);
    }
    print(&text(
        &described,
        trial.steps.len(),
        &settings,
        args.tune,
        &summary,
    ))
}

fn trial(args: &Args) -> Result<(Trial, String), Error> {
    if let Some(path) = &args.trial {
        let trial = Trial::parse(&read(path)?, &file_name(path))?;
        return Ok((trial, format!("{}", path.display())));
    }
    if let Some(name) = &args.report_trial {
        let dir = args.datasets.as_ref().expect("clap requires --datasets");
        let datasets = Datasets::load(dir)?;
        let trial = datasets.northstar_trial(name).ok_or_else(|| {
            let names: Vec<&str> = datasets.northstar.iter().map(|t| t.name.as_str()).collect();
            Error::Invalid(format!(
                "--report-trial {name}: {} holds {}",
                dir.join(crate::datasets::NORTHSTAR).display(),
                if names.is_empty() {
                    "no trial of the report".to_owned()
                } else {
                    names.join(", ")
                }
            ))
        })?;
        return Ok((trial.clone(), format!("the report's {name}")));
    }
    let d = TrialParams::default();
    let params = TrialParams {
        seed: args.seed.unwrap_or(d.seed),
        waypoints: args.waypoints.unwrap_or(d.waypoints),
        ..d
    };
    let trial = generate(&params)?;
    Ok((
        trial,
        format!(
            "generated (seed {}, {} waypoints)",
            params.seed, params.waypoints
        ),
    ))
}

fn settings(args: &Args) -> Settings {
    let d = Settings::default();
    Settings {
        process_xy: args.process_xy.unwrap_or(d.process_xy),
        process_theta: args.process_theta.unwrap_or(d.process_theta),
        noise: NoiseModel {
            c_xy: args.c_xy.unwrap_or(d.noise.c_xy),
            c_theta: args.c_theta.unwrap_or(d.noise.c_theta),
        },
        field_of_view: args.field_of_view.unwrap_or(d.field_of_view),
        gate: args.gate.unwrap_or(d.gate),
        ..d
    }
}

fn text(trial: &str, steps: usize, settings: &Settings, tuned: bool, summary: &Summary) -> String {
    let gate = match settings.gate_threshold() {
        threshold if threshold.is_finite() => format!("{} (chi2inv {threshold:.2})", settings.gate),
        _ => "none".to_owned(),
    };
    let mut out = vec![
        format!("trial: {trial}, {steps} steps"),
        format!(
            "settings{}: k_xy {}, k_theta {}, c_xy {}, c_theta {}, field of view {} m, gate {gate}",
            if tuned { " (tuned on this trial)" } else { "" },
            settings.process_xy,
            settings.process_theta,
            settings.noise.c_xy,
            settings.noise.c_theta,
            settings.field_of_view,
        ),
        String::new(),
        "position error (m)      mean      RMS      max   steps".to_owned(),
    ];
    let row = |name: &str, e: &Errors| {
        format!(
            "{name:<20} {:>8.4} {:>8.4} {:>8.4} {:>7}",
            e.mean, e.rms, e.max, e.steps
        )
    };
    out.push(row("filter", &summary.filter));
    out.push(row("odometry", &summary.odometry));
    if let Some(sensor) = &summary.sensor {
        out.push(row("sensor alone", sensor));
    }
    if let Some(report) = &summary.report {
        out.push(row("the report's filter", report));
    }
    out.push(String::new());
    out.push(format!(
        "truth inside the 3-sigma ellipse: {:.1} % of steps (98.9 % if the filter were consistent)",
        100.0 * summary.inside_three_sigma
    ));
    out.push(format!(
        "readings: {} used, {} outside the field of view, {} rejected by the gate",
        summary.used, summary.outside_view, summary.gated
    ));
    out.join("\n")
}
