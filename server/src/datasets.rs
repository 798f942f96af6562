//! Real data sets found in a folder an instructor names (`--datasets DIR`): estlab never
//! ships them, and the pages and commands work on generated data without them.
//!
//! `DIR/northstar/` holds the Northstar report's trials, each as its two files,
//! `trialN_odometry_northstar.csv` (odometry and the sensor's pose) and
//! `trialN_kalman_groundtruth.csv` (the report's Kalman estimate and ground truth), as
//! `../shared/data/README.md` describes them; `DIR/mrclam/MRCLAM_DatasetN/` the UTIAS
//! MRCLAM data sets' files as published (`RobotR_Odometry.dat`, `RobotR_Measurement.dat`,
//! `RobotR_Groundtruth.dat`, `Landmark_Groundtruth.dat`, `Barcodes.dat`).

use crate::error::Error;
use axum::body::Bytes;
use labs::fusion::Trial;
use labs::mrclam::format::{parse_robot, parse_world};
use labs::mrclam::learn::Learned;
use labs::mrclam::{Robot, World};
use serde::Serialize;
use std::path::Path;
use ts_rs::TS;

/// The folder of the Northstar trials within the data sets folder.
pub const NORTHSTAR: &str = "northstar";
const SENSOR_FILE: &str = "_odometry_northstar.csv";
const ESTIMATE_FILE: &str = "_kalman_groundtruth.csv";

/// A real trial of the Northstar report.
#[derive(Clone, Debug, Serialize, TS)]
pub struct NamedTrial {
    /// The trial's name, from its files': `trial1` for `trial1_odometry_northstar.csv`.
    pub name: String,
    pub trial: Trial,
}

/// The folder of the MRCLAM data sets within the data sets folder.
pub const MRCLAM: &str = "mrclam";

/// A robot of an MRCLAM data set: on the grid the filters take, with the noise learned
/// from its recording and the room's posts (`labs`' `Learned`), as the page reads it:
/// JSON (some megabytes a robot) and the same gzipped (a fifth of that), both made once
/// at the start, so that a request costs the server no work.
#[derive(Clone, Debug)]
pub struct MrclamRobot {
    pub entry: MrclamEntry,
    pub json: Bytes,
    pub gzip: Bytes,
}

/// What the page lists of a robot of an MRCLAM data set.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, TS)]
pub struct MrclamEntry {
    pub dataset: u32,
    pub robot: u32,
    /// How many steps of the 50 Hz grid its ground truth spans.
    pub steps: usize,
}

/// Everything found in the data sets folder.
#[derive(Clone, Debug, Default)]
pub struct Datasets {
    /// The Northstar report's trials, by name.
    pub northstar: Vec<NamedTrial>,
    /// The MRCLAM data sets' robots, by data set and robot.
    pub mrclam: Vec<MrclamRobot>,
}

impl Datasets {
    /// Reads what `dir` holds. A folder that is missing is an error (it was named on
    /// purpose); a trial whose second file is missing or that does not parse is one too,
    /// naming the file and line.
    pub fn load(dir: &Path) -> Result<Datasets, Error> {
        if !dir.is_dir() {
            return Err(Error::Invalid(format!(
                "--datasets {}: no such folder",
                dir.display()
            )));
        }
        Ok(Datasets {
            northstar: northstar_trials(&dir.join(NORTHSTAR))?,
            mrclam: mrclam_robots(dir)?,
        })
    }

    /// Robot `robot` of MRCLAM data set `dataset`.
    pub fn mrclam_robot(&self, dataset: u32, robot: u32) -> Option<&MrclamRobot> {
        self.mrclam
            .iter()
            .find(|r| r.entry.dataset == dataset && r.entry.robot == robot)
    }

    /// The Northstar trial of that name.
    pub fn northstar_trial(&self, name: &str) -> Option<&Trial> {
        self.northstar
            .iter()
            .find(|t| t.name == name)
            .map(|t| &t.trial)
    }
}

/// Robot `robot` of MRCLAM data set `dataset` in the data sets folder `dir`, and its room.
/// A missing file is an error naming it; so is a line that does not parse.
pub fn mrclam(dir: &Path, dataset: u32, robot: u32) -> Result<(Robot, World), Error> {
    let folder = dir.join("mrclam").join(format!("MRCLAM_Dataset{dataset}"));
    if !folder.is_dir() {
        return Err(Error::Invalid(format!(
            "{}: no such folder (data set {dataset} of MRCLAM, as published)",
            folder.display()
        )));
    }
    let file = |name: String| -> Result<(String, String), Error> {
        let path = folder.join(name);
        Ok((read(&path)?, path.display().to_string()))
    };
    let [odometry, measurements, truth] = ["Odometry", "Measurement", "Groundtruth"]
        .map(|kind| file(format!("Robot{robot}_{kind}.dat")));
    let (odometry, measurements, truth) = (odometry?, measurements?, truth?);
    let (posts, barcodes) = (
        file("Landmark_Groundtruth.dat".to_owned())?,
        file("Barcodes.dat".to_owned())?,
    );
    fn as_str((text, name): &(String, String)) -> (&str, &str) {
        (text, name)
    }
    let robot = parse_robot(as_str(&odometry), as_str(&measurements), as_str(&truth))?;
    let world = parse_world(as_str(&posts), as_str(&barcodes))?;
    Ok((robot, world))
}

/// Every robot of every data set in `dir/mrclam/` (a folder `MRCLAM_DatasetN` each, a
/// robot for each `RobotR_Odometry.dat` in it).
fn mrclam_robots(dir: &Path) -> Result<Vec<MrclamRobot>, Error> {
    let folder = dir.join(MRCLAM);
    if !folder.is_dir() {
        return Ok(Vec::new());
    }
    let numbered = |dir: &Path, prefix: &str, suffix: &str| -> Result<Vec<u32>, Error> {
        let mut numbers: Vec<u32> = std::fs::read_dir(dir)
            .map_err(Error::io(dir))?
            .filter_map(|entry| entry.ok()?.file_name().into_string().ok())
            .filter_map(|name| {
                let number: u32 = name
                    .strip_prefix(prefix)?
                    .strip_suffix(suffix)?
                    .parse()
                    .ok()?;
                // Only as written back (not MRCLAM_Dataset06), the name the files are read by.
                (format!("{prefix}{number}{suffix}") == name).then_some(number)
            })
            .collect();
        numbers.sort_unstable();
        Ok(numbers)
    };
    let mut robots = Vec::new();
    for dataset in numbered(&folder, "MRCLAM_Dataset", "")? {
        let set = folder.join(format!("MRCLAM_Dataset{dataset}"));
        for robot in numbered(&set, "Robot", "_Odometry.dat")? {
            let (recording, world) = mrclam(dir, dataset, robot)?;
            let learned = Learned::new(&recording, &world)
                .map_err(|e| Error::Invalid(format!("{}, robot {robot}: {e}", set.display())))?;
            let json = serde_json::to_vec(&learned).expect("a recording serialises");
            robots.push(MrclamRobot {
                entry: MrclamEntry {
                    dataset,
                    robot,
                    steps: learned.run.steps.len(),
                },
                gzip: gzipped(&json).map_err(Error::io(&set))?.into(),
                json: json.into(),
            });
        }
    }
    Ok(robots)
}

/// `bytes` gzipped.
fn gzipped(bytes: &[u8]) -> std::io::Result<Vec<u8>> {
    use std::io::Write;
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    encoder.write_all(bytes)?;
    encoder.finish()
}

fn northstar_trials(dir: &Path) -> Result<Vec<NamedTrial>, Error> {
    if !dir.is_dir() {
        return Ok(Vec::new());
    }
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map_err(Error::io(dir))?
        .filter_map(|entry| entry.ok())
        .filter_map(|entry| {
            let file = entry.file_name().into_string().ok()?;
            file.strip_suffix(SENSOR_FILE).map(str::to_owned)
        })
        .collect();
    names.sort();
    names
        .into_iter()
        .map(|name| {
            let sensor = dir.join(format!("{name}{SENSOR_FILE}"));
            let estimate = dir.join(format!("{name}{ESTIMATE_FILE}"));
            let trial = Trial::from_report(
                (&read(&sensor)?, &sensor.display().to_string()),
                (&read(&estimate)?, &estimate.display().to_string()),
            )?;
            Ok(NamedTrial { name, trial })
        })
        .collect()
}

/// The text of a data file, at most 64 MiB.
fn read(path: &Path) -> Result<String, Error> {
    const MAX_BYTES: u64 = 64 << 20;
    let size = std::fs::metadata(path).map_err(Error::io(path))?.len();
    if size > MAX_BYTES {
        return Err(Error::Invalid(format!(
            "{}: {size} bytes, more than a data file may have ({MAX_BYTES})",
            path.display()
        )));
    }
    std::fs::read_to_string(path).map_err(Error::io(path))
}
