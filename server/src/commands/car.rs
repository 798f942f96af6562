//! `estlab car`: the warm-up, a car on a line and its Kalman filter.

use super::{numbers, short};
use crate::error::Error;
use labs::car::{CarParams, run as run_car};

/// Simulate the warm-up car and run its Kalman filter (defaults: the lab's script).
#[derive(clap::Args)]
pub struct Args {
    #[arg(long)]
    seed: Option<u64>,
    #[arg(long)]
    steps: Option<usize>,
    /// Time step, seconds.
    #[arg(long)]
    dt: Option<f64>,
    /// The control input, the same at every step.
    #[arg(long)]
    u: Option<f64>,
    /// The true initial state: position,velocity.
    #[arg(long, value_parser = numbers::<2>)]
    x0: Option<[f64; 2]>,
    /// Simulated process noise, standard deviations: position,velocity.
    #[arg(long, value_parser = numbers::<2>)]
    process_std: Option<[f64; 2]>,
    /// Simulated measurement noise, standard deviation.
    #[arg(long)]
    measurement_std: Option<f64>,
    /// Diagonal of R, the process noise covariance the filter assumes (variances).
    #[arg(long = "R", value_parser = numbers::<2>)]
    r: Option<[f64; 2]>,
    /// Q, the measurement noise variance the filter assumes.
    #[arg(long = "Q")]
    q: Option<f64>,
    /// The filter's initial estimate: position,velocity.
    #[arg(long, value_parser = numbers::<2>)]
    mu0: Option<[f64; 2]>,
    /// Diagonal of the filter's initial covariance (variances).
    #[arg(long, value_parser = numbers::<2>)]
    sigma0: Option<[f64; 2]>,
    /// Print the whole run as JSON.
    #[arg(long)]
    json: bool,
}

fn diag([a, b]: [f64; 2]) -> [[f64; 2]; 2] {
    [[a, 0.0], [0.0, b]]
}

pub fn run(args: &Args) -> Result<(), Error> {
    let d = CarParams::default();
    let params = CarParams {
        seed: args.seed.unwrap_or(d.seed),
        steps: args.steps.unwrap_or(d.steps),
        dt: args.dt.unwrap_or(d.dt),
        u: args.u.unwrap_or(d.u),
        x0: args.x0.unwrap_or(d.x0),
        process_std: args.process_std.unwrap_or(d.process_std),
        measurement_std: args.measurement_std.unwrap_or(d.measurement_std),
        r: args.r.map_or(d.r, diag),
        q: args.q.unwrap_or(d.q),
        mu0: args.mu0.unwrap_or(d.mu0),
        sigma0: args.sigma0.map_or(d.sigma0, diag),
    };
    let result = run_car(&params)?;
    if args.json {
        println!("{}", serde_json::json!({ "params": params, "run": result }));
        return Ok(());
    }
    let last = result.steps.last().expect("a run has at least two steps");
    println!(
        "car: {} steps of {} s, seed {}",
        params.steps, params.dt, params.seed
    );
    println!(
        "simulated noise std: process ({}, {}), measurement {}",
        params.process_std[0], params.process_std[1], params.measurement_std
    );
    println!(
        "modelled: R = diag({}, {}), Q = {}, mu0 = ({}, {}), Sigma0 = diag({}, {})",
        short(params.r[0][0]),
        short(params.r[1][1]),
        short(params.q),
        params.mu0[0],
        params.mu0[1],
        params.sigma0[0][0],
        params.sigma0[1][1]
    );
    println!(
        "final: estimate ({:.4}, {:.4}), truth ({:.4}, {:.4}), sigma ({:.4}, {:.4})",
        last.mu.x,
        last.mu.y,
        last.truth.x,
        last.truth.y,
        last.sigma[(0, 0)].sqrt(),
        last.sigma[(1, 1)].sqrt()
    );
    println!(
        "error std over the second half: position {:.4} m, velocity {:.4} m/s",
        result.error_std[0], result.error_std[1]
    );
    Ok(())
}
