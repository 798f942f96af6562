//! `estlab run SENSOR MAP`: the EKF over a data set, printing what the lab's script
//! printed.

use super::{file_name, numbers, print, read, short};
use crate::error::Error;
use labs::dataset::{Dataset, parse_map, parse_sensor_log};
use labs::ekf::{Run, Settings, UpdateMode, run as run_filter};
use std::path::PathBuf;
use std::time::Instant;

/// Run the EKF localization filter over an EL2320 data set (defaults: the lab's settings
/// for so_o3_ie).
#[derive(clap::Args)]
pub struct Args {
    /// The sensor file (so_*.txt).
    sensor: PathBuf,
    /// The map file (map_*.txt).
    map: PathBuf,
    /// Batch update instead of the sequential one.
    #[arg(long)]
    batch: bool,
    /// Use the landmark ids in the sensor file instead of maximum-likelihood association.
    #[arg(long)]
    known_associations: bool,
    /// Diagonal of R, the process noise covariance, as variances: x,y,theta.
    #[arg(long = "R", value_name = "X,Y,THETA", value_parser = numbers::<3>)]
    r: Option<[f64; 3]>,
    /// Diagonal of Q, the measurement noise covariance, as variances: range,bearing.
    #[arg(long = "Q", value_name = "RANGE,BEARING", value_parser = numbers::<2>)]
    q: Option<[f64; 2]>,
    /// delta_M of the outlier gate, Lambda_M = chi2inv(delta_M, 2); 1 rejects nothing.
    #[arg(long, value_name = "X")]
    delta_m: Option<f64>,
    /// Print the whole result as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &Args) -> Result<(), Error> {
    let map = parse_map(&read(&args.map)?, &file_name(&args.map))?;
    let log = parse_sensor_log(&read(&args.sensor)?, &file_name(&args.sensor), &map)?;
    let data = Dataset { map, log };
    let settings = settings(args);
    let start = Instant::now();
    let result = run_filter(&data, &settings)?;
    let elapsed = start.elapsed();
    if args.json {
        let json = serde_json::json!({ "settings": settings, "summary": result.summary, "steps": result.steps, "readings": result.readings });
        print(&json.to_string())?;
    } else {
        print_summary(args, &settings, &result, elapsed.as_secs_f64());
    }
    Ok(())
}

fn settings(args: &Args) -> Settings {
    let lab = Settings::lab_o3();
    let r = args.r.unwrap_or(lab.r.diagonal().into());
    let q = args.q.unwrap_or(lab.q.diagonal().into());
    Settings {
        mode: if args.batch {
            UpdateMode::Batch
        } else {
            UpdateMode::Sequential
        },
        known_associations: args.known_associations,
        delta_m: args.delta_m.unwrap_or(lab.delta_m),
        ..lab
    }
    .with_diagonals(r, q)
}

fn print_summary(args: &Args, settings: &Settings, result: &Run, seconds: f64) {
    let s = &result.summary;
    println!(
        "{} on {}: {} time steps, {} readings, {} update, {}",
        file_name(&args.sensor),
        file_name(&args.map),
        s.steps,
        s.readings,
        if args.batch { "batch" } else { "sequential" },
        if args.known_associations {
            "known associations"
        } else {
            "maximum-likelihood association"
        },
    );
    println!(
        "R = diag({}), Q = diag({}), delta_M = {} (Lambda_M = {:.4})",
        list(settings.r.diagonal().as_slice()),
        list(settings.q.diagonal().as_slice()),
        settings.delta_m,
        s.lambda_m
    );
    print!("{}", s.report());
    println!("time: {:.3} ms", seconds * 1e3);
}

fn list(values: &[f64]) -> String {
    values
        .iter()
        .map(|&v| short(v))
        .collect::<Vec<_>>()
        .join(", ")
}
