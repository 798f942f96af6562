//! `estlab mrclam`: the EKF, the UKF and the particle filter on a robot of the UTIAS MRCLAM
//! data sets (from `--datasets`) or of one generated from a seed, with the noise learned
//! from the robot's own recording; how close each comes to the ground truth, how
//! consistent it is, and how long it took.

use super::print;
use crate::datasets;
use crate::error::Error;
use labs::fusion::Errors;
use labs::mrclam::belief::Readings;
use labs::mrclam::grid::RATE;
use labs::mrclam::learn::Learned;
use labs::mrclam::motion::Noise;
use labs::mrclam::particle;
use labs::mrclam::run::{self, CONSISTENT_INSIDE, Consistency, Kind, Settings};
use labs::mrclam::simulate::{self, DatasetParams};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Which {
    Ekf,
    Ukf,
    Particle,
    All,
}

impl Which {
    fn takes(self, kind: Kind) -> bool {
        match self {
            Which::Ekf => kind == Kind::Ekf,
            Which::Ukf => kind == Kind::Ukf,
            Which::Particle => kind == Kind::Particle,
            Which::All => true,
        }
    }
}

/// Localize a robot of a UTIAS MRCLAM data set (or of one generated from a seed) with
/// the EKF, the UKF or the particle filter (known correspondences, a chi-square gate at
/// 99.9 %, the noise learned from the robot's own recording, the data on a 50 Hz grid),
/// and print each filter's RMS position error, NEES, the share of steps with the truth
/// inside its 3-sigma ellipse, and its time, beside dead reckoning's error.
#[derive(clap::Args)]
pub struct Args {
    /// The folder of real data sets: its mrclam/MRCLAM_DatasetN/ holds the files as
    /// published. Without it, a data set generated from --seed.
    #[arg(long, value_name = "DIR")]
    datasets: Option<PathBuf>,
    /// Which data set (the N of MRCLAM_DatasetN; default 6, the one the shared data
    /// holds).
    #[arg(long, requires = "datasets")]
    dataset: Option<u32>,
    /// The seed of a generated data set (three robots, two minutes).
    #[arg(long, conflicts_with_all = ["datasets", "dataset"])]
    generate: Option<u64>,
    /// Which robot, 1 to 5.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=5))]
    robot: u32,
    /// Which filter.
    #[arg(long, value_enum, default_value_t = Which::All)]
    filter: Which,
    /// The particle filter's particles.
    #[arg(long, default_value_t = particle::PARTICLES as u64, value_parser = clap::value_parser!(u64).range(1..=run::MAX_PARTICLES as u64))]
    particles: u64,
    /// The seed of the particle filter's random numbers.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// rho: the learned R2 is scaled by it (the one tuning knob: above 1 the filters trust
    /// the camera less against the odometry).
    #[arg(long, default_value_t = 1.0)]
    rho: f64,
    /// Print the learned noise (the alphas and R2) too.
    #[arg(long)]
    learn_noise: bool,
    /// Write the robot's recording as the filters take it (the 50 Hz grid, the learned
    /// noise and the posts, JSON of labs' `Learned`) to this file too.
    #[arg(long, value_name = "FILE")]
    write_recording: Option<PathBuf>,
    /// Print the report as JSON.
    #[arg(long)]
    json: bool,
}

/// A filter's run over the robot's recording, summed up.
#[derive(Debug, Serialize, Deserialize)]
pub struct FilterReport {
    pub filter: String,
    pub consistency: Consistency,
    pub readings: Readings,
    /// The filter's time over the whole run, seconds (this machine's, this run's).
    pub seconds: f64,
}

/// What `--json` prints.
#[derive(Debug, Serialize, Deserialize)]
pub struct Report {
    /// The data set: "MRCLAM data set 6", or "generated from seed 1".
    pub dataset: String,
    pub robot: u32,
    pub steps: usize,
    pub seconds_of_data: f64,
    /// The longest stretch without a reading of a post, seconds from the start.
    pub blind_stretch: (f64, f64),
    /// The noise learned from the robot's recording (before rho).
    pub noise: Noise,
    pub rho: f64,
    pub dead_reckoning: Errors,
    pub filters: Vec<FilterReport>,
}

pub fn run(args: &Args) -> Result<(), Error> {
    let settings = Settings {
        rho: args.rho,
        particles: args.particles as usize,
        seed: args.seed,
    };
    settings.validate()?;
    let (robot, world, dataset) = match &args.datasets {
        Some(dir) => {
            let dataset = args.dataset.unwrap_or(6);
            let (robot, world) = datasets::mrclam(dir, dataset, args.robot)?;
            (robot, world, format!("MRCLAM data set {dataset}"))
        }
        None => {
            let params = DatasetParams {
                seed: args.generate.unwrap_or(1),
                ..DatasetParams::default()
            };
            let (mut robots, world) = simulate::generate(&params)?;
            if args.robot > params.robots {
                return Err(Error::Invalid(format!(
                    "--robot {}: a generated data set has robots 1 to {}",
                    args.robot, params.robots
                )));
            }
            let robot = robots.swap_remove(args.robot as usize - 1);
            (robot, world, format!("generated from seed {}", params.seed))
        }
    };
    let recording = Learned::new(&robot, &world)
        .map_err(|e| Error::Invalid(format!("robot {} of {dataset}: {e}", args.robot)))?;
    if let Some(path) = &args.write_recording {
        let json = serde_json::to_vec(&recording).expect("a recording serialises");
        std::fs::write(path, json).map_err(Error::io(path))?;
    }
    let (grid, learned) = (&recording.run, recording.noise);
    let dead_reckoning = run::drift(grid);
    let filters = Kind::ALL
        .into_iter()
        .filter(|kind| args.filter.takes(*kind))
        .map(|kind| {
            let mut filter = run::make(kind, grid, &learned, &settings);
            let clock = Instant::now();
            let (beliefs, readings) = run::filter(grid, filter.as_mut());
            let seconds = clock.elapsed().as_secs_f64();
            FilterReport {
                filter: kind.name().to_owned(),
                consistency: Consistency::of(grid, &beliefs),
                readings,
                seconds,
            }
        })
        .collect();
    let report = Report {
        dataset,
        robot: args.robot,
        steps: grid.steps.len(),
        seconds_of_data: grid.steps.last().map_or(0.0, |step| step.t),
        blind_stretch: grid.longest_blind_stretch(),
        noise: learned,
        rho: args.rho,
        dead_reckoning,
        filters,
    };
    if args.json {
        let json = serde_json::to_string_pretty(&report).expect("a report serialises");
        return print(&json);
    }
    print(&text(&report, args.learn_noise))
}

fn text(report: &Report, learned: bool) -> String {
    let mut lines = vec![
        format!(
            "{}, robot {}: {:.1} s of ground truth, {} steps at {RATE} Hz; no post in sight \
             from {:.1} s to {:.1} s.",
            report.dataset,
            report.robot,
            report.seconds_of_data,
            report.steps,
            report.blind_stretch.0,
            report.blind_stretch.1,
        ),
        format!(
            "Dead reckoning (the commands alone): RMS {:.3} m, largest {:.2} m.",
            report.dead_reckoning.rms, report.dead_reckoning.max
        ),
    ];
    if learned {
        let [a1, a2, a3, a4] = report.noise.alphas;
        let r = report.noise.measurement;
        lines.push(format!(
            "Learned noise: alpha = {a1:.4}, {a2:.4}, {a3:.4}, {a4:.4}; R2 = [[{:.3e}, {:.3e}], \
             [{:.3e}, {:.3e}]] (range sd {:.3} m, bearing sd {:.4} rad); rho = {}.",
            r[(0, 0)],
            r[(0, 1)],
            r[(1, 0)],
            r[(1, 1)],
            r[(0, 0)].sqrt(),
            r[(1, 1)].sqrt(),
            report.rho
        ));
    }
    lines.push(format!(
        "{:<16} {:>8} {:>8} {:>8} {:>9} {:>10} {:>9} {:>8}",
        "filter", "RMS m", "mean m", "max m", "NEES", "in 3sigma", "rejected", "time s"
    ));
    for f in &report.filters {
        let c = &f.consistency;
        lines.push(format!(
            "{:<16} {:>8.3} {:>8.3} {:>8.3} {:>9.1} {:>9.1}% {:>9} {:>8.3}",
            f.filter,
            c.errors.rms,
            c.errors.mean,
            c.errors.max,
            c.nees,
            100.0 * c.inside_three_sigma,
            f.readings.rejected,
            f.seconds
        ));
    }
    lines.push(format!(
        "A consistent filter has a NEES of 3 and the truth inside its 3-sigma ellipse at {:.1} % \
         of the steps.",
        100.0 * CONSISTENT_INSIDE
    ));
    lines.join("\n")
}
