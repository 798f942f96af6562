//! `estlab simulate`: a new data set in the EL2320 format.

use crate::error::Error;
use labs::dataset::{Kind, simulate, write_map, write_sensor_log};
use std::path::PathBuf;

/// Write a simulated data set (a map and a sensor file) of one of the lab's three kinds.
#[derive(clap::Args)]
pub struct Args {
    /// o3 (indoor, accurate), outliers (noisy, gross outliers) or no-odometry.
    #[arg(long, value_parser = |name: &str| Kind::from_name(name).map_err(|e| e.to_string()))]
    kind: Kind,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The directory to write map_<kind>_<seed>.txt and so_<kind>_<seed>.txt into.
    #[arg(long)]
    out: PathBuf,
}

pub fn run(args: &Args) -> Result<(), Error> {
    let data = simulate(args.kind, args.seed);
    std::fs::create_dir_all(&args.out).map_err(Error::io(&args.out))?;
    let stem = format!("{}_{}", args.kind.name(), args.seed);
    for (prefix, text) in [
        ("map", write_map(&data.map)),
        ("so", write_sensor_log(&data.log)),
    ] {
        let path = args.out.join(format!("{prefix}_{stem}.txt"));
        std::fs::write(&path, text).map_err(Error::io(&path))?;
        println!("{}", path.display());
    }
    Ok(())
}
