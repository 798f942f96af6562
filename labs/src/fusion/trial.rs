//! A trial: what the robot's odometry said, what the sensor read, where the robot truly
//! was, step by step; and its files.
//!
//! A trial file is CSV with a header naming its columns, the report's names:
//!
//! | columns | what | needed |
//! | --- | --- | --- |
//! | `t` | time, seconds | no (the row's number otherwise) |
//! | `odom_x, odom_y, odom_theta` | the odometry's own pose | yes |
//! | `ns_x, ns_y, ns_theta` | the sensor's pose | no |
//! | `p1_x, p1_y, p1_i, p2_x, p2_y, p2_i` | the two platforms and their intensities | no |
//! | `gt_x, gt_y, gt_theta` | ground truth | yes |
//! | `kf_x, kf_y, kf_theta` | the report's own Kalman estimate | no |
//!
//! A field left empty is a step without a reading. Where a step has its platforms the
//! filter uses them; where it has only the sensor's pose (the report's trials), the
//! pose. The report's trials come as two files side by side (odometry and sensor; Kalman
//! estimate and ground truth), which [`Trial::from_report`] joins.

use super::sensor::{Platform, combine};
use crate::Error;
use serde::{Deserialize, Serialize};

/// What the sensor gave at a step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
#[ts(rename = "SensorReading")]
#[serde(rename_all = "snake_case")]
pub enum Reading {
    /// Both platforms, front one first.
    Platforms([Platform; 2]),
    /// A pose alone, `[x, y, theta]`.
    Pose([f64; 3]),
}

/// One step of a trial. Poses are `[x, y, theta]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
#[ts(rename = "TrialStep")]
pub struct Step {
    pub t: f64,
    /// The odometry's own pose: only its increments from step to step are trusted.
    pub odometry: [f64; 3],
    pub reading: Option<Reading>,
    pub truth: [f64; 3],
    /// The report's own estimate, where the trial is one of the report's.
    pub report: Option<[f64; 3]>,
}

/// A whole trial.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
pub struct Trial {
    pub steps: Vec<Step>,
}

/// The longest trial a file may hold.
pub const MAX_STEPS: usize = 100_000;

const TIME: &str = "t";
const ODOMETRY: [&str; 3] = ["odom_x", "odom_y", "odom_theta"];
const SENSOR: [&str; 3] = ["ns_x", "ns_y", "ns_theta"];
const PLATFORMS: [&str; 6] = ["p1_x", "p1_y", "p1_i", "p2_x", "p2_y", "p2_i"];
const TRUTH: [&str; 3] = ["gt_x", "gt_y", "gt_theta"];
const REPORT: [&str; 3] = ["kf_x", "kf_y", "kf_theta"];

impl Trial {
    /// Reads a trial file (the module's columns); `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Trial, Error> {
        Table::parse(text, file)?.trial()
    }

    /// Joins the report's two files of a trial (odometry and sensor; Kalman estimate and
    /// ground truth), row by row.
    pub fn from_report(
        (sensor, sensor_file): (&str, &str),
        (estimate, estimate_file): (&str, &str),
    ) -> Result<Trial, Error> {
        let left = Table::parse(sensor, sensor_file)?;
        let right = Table::parse(estimate, estimate_file)?;
        left.beside(right)?.trial()
    }

    /// The trial as a file of the module's columns (the platforms where they were read).
    pub fn to_csv(&self) -> String {
        let columns: Vec<&str> = [TIME]
            .into_iter()
            .chain(ODOMETRY)
            .chain(SENSOR)
            .chain(PLATFORMS)
            .chain(TRUTH)
            .collect();
        let mut out = columns.join(",") + "\n";
        for step in &self.steps {
            let mut fields = vec![format!("{}", step.t)];
            fields.extend(step.odometry.iter().map(number));
            let (pose, platforms): (Option<[f64; 3]>, Option<&[Platform; 2]>) = match &step.reading
            {
                Some(Reading::Platforms(platforms)) => {
                    (Some(combine(platforms).into()), Some(platforms))
                }
                Some(Reading::Pose(pose)) => (Some(*pose), None),
                None => (None, None),
            };
            let blank = |n| vec![String::new(); n];
            fields.extend(pose.map_or_else(|| blank(3), |p| p.iter().map(number).collect()));
            fields.extend(platforms.map_or_else(
                || blank(6),
                |ps| {
                    ps.iter()
                        .flat_map(|p| [p.x, p.y, p.intensity])
                        .map(|v| number(&v))
                        .collect()
                },
            ));
            fields.extend(step.truth.iter().map(number));
            out += &fields.join(",");
            out.push('\n');
        }
        out
    }
}

fn number(value: &f64) -> String {
    format!("{value:.6}")
}

/// A CSV file read as named columns of optional numbers.
struct Table {
    file: String,
    columns: Vec<String>,
    /// (line number, one field per column)
    rows: Vec<(usize, Vec<Option<f64>>)>,
}

impl Table {
    fn parse(text: &str, file: &str) -> Result<Table, Error> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, line)| (i + 1, line.trim()))
            .filter(|(_, line)| !line.is_empty());
        let Some((_, header)) = lines.next() else {
            return Err(Error::parse(file, 0, "the file is empty"));
        };
        let columns: Vec<String> = header.split(',').map(|c| c.trim().to_owned()).collect();
        for (i, column) in columns.iter().enumerate() {
            if columns[..i].contains(column) {
                return Err(Error::parse(
                    file,
                    1,
                    format!("column '{column}' appears twice"),
                ));
            }
        }
        let mut rows = Vec::new();
        for (line, text) in lines {
            if rows.len() == MAX_STEPS {
                return Err(Error::parse(
                    file,
                    line,
                    format!("a trial has at most {MAX_STEPS} steps"),
                ));
            }
            let fields: Vec<&str> = text.split(',').map(str::trim).collect();
            if fields.len() != columns.len() {
                return Err(Error::parse(
                    file,
                    line,
                    format!(
                        "expected {} fields, as the header names, found {}",
                        columns.len(),
                        fields.len()
                    ),
                ));
            }
            let values = fields
                .iter()
                .zip(&columns)
                .map(|(field, column)| match *field {
                    "" | "NaN" | "nan" => Ok(None),
                    field => match field.parse::<f64>() {
                        Ok(value) if value.is_finite() => Ok(Some(value)),
                        _ => Err(Error::parse(
                            file,
                            line,
                            format!("{column} is '{field}', which is not a finite number"),
                        )),
                    },
                })
                .collect::<Result<_, _>>()?;
            rows.push((line, values));
        }
        Ok(Table {
            file: file.to_owned(),
            columns,
            rows,
        })
    }

    /// The two tables' columns side by side (the same number of rows).
    fn beside(mut self, other: Table) -> Result<Table, Error> {
        if self.rows.len() != other.rows.len() {
            return Err(Error::parse(
                &other.file,
                0,
                format!(
                    "has {} rows where {} has {}",
                    other.rows.len(),
                    self.file,
                    self.rows.len()
                ),
            ));
        }
        if let Some(column) = other.columns.iter().find(|c| self.columns.contains(c)) {
            return Err(Error::parse(
                &other.file,
                1,
                format!("column '{column}' is in {} too", self.file),
            ));
        }
        self.columns.extend(other.columns);
        for ((_, row), (_, more)) in self.rows.iter_mut().zip(other.rows) {
            row.extend(more);
        }
        Ok(self)
    }

    fn index(&self, column: &str) -> Option<usize> {
        self.columns.iter().position(|c| c == column)
    }

    fn indices<const N: usize>(&self, names: [&str; N]) -> Option<[usize; N]> {
        let found: Vec<usize> = names.iter().filter_map(|n| self.index(n)).collect();
        found.try_into().ok()
    }

    fn required<const N: usize>(&self, names: [&str; N]) -> Result<[usize; N], Error> {
        self.indices(names).ok_or_else(|| {
            let missing: Vec<&str> = names
                .into_iter()
                .filter(|n| self.index(n).is_none())
                .collect();
            Error::parse(&self.file, 1, format!("no column {}", missing.join(", ")))
        })
    }

    fn trial(&self) -> Result<Trial, Error> {
        let odometry = self.required(ODOMETRY)?;
        let truth = self.required(TRUTH)?;
        let time = self.index(TIME);
        let sensor = self.indices(SENSOR);
        let platforms = self.indices(PLATFORMS);
        let report = self.indices(REPORT);
        let steps = self
            .rows
            .iter()
            .enumerate()
            .map(|(k, (line, row))| {
                let error = |message: String| Error::parse(&self.file, *line, message);
                let all = |columns: [usize; 3], what: &str| -> Result<Option<[f64; 3]>, Error> {
                    let values = columns.map(|c| row[c]);
                    match values {
                        [Some(a), Some(b), Some(c)] => Ok(Some([a, b, c])),
                        [None, None, None] => Ok(None),
                        _ => Err(error(format!("{what} is neither whole nor empty"))),
                    }
                };
                let needed = |columns: [usize; 3], what: &str| {
                    all(columns, what)?.ok_or_else(|| error(format!("{what} is empty")))
                };
                let platforms = match platforms {
                    Some(columns) => {
                        let first = all([columns[0], columns[1], columns[2]], "platform 1")?;
                        let second = all([columns[3], columns[4], columns[5]], "platform 2")?;
                        match (first, second) {
                            (Some([x1, y1, i1]), Some([x2, y2, i2])) => {
                                if i1 <= 0.0 || i2 <= 0.0 {
                                    return Err(error("an intensity is not positive".into()));
                                }
                                Some([
                                    Platform {
                                        x: x1,
                                        y: y1,
                                        intensity: i1,
                                    },
                                    Platform {
                                        x: x2,
                                        y: y2,
                                        intensity: i2,
                                    },
                                ])
                            }
                            (None, None) => None,
                            _ => {
                                return Err(error("one platform is read and the other not".into()));
                            }
                        }
                    }
                    None => None,
                };
                let pose = sensor
                    .map(|columns| all(columns, "the sensor's pose"))
                    .transpose()?
                    .flatten();
                Ok(Step {
                    t: time.and_then(|c| row[c]).unwrap_or(k as f64),
                    odometry: needed(odometry, "the odometry")?,
                    reading: platforms
                        .map(Reading::Platforms)
                        .or(pose.map(Reading::Pose)),
                    truth: needed(truth, "the ground truth")?,
                    report: report
                        .map(|columns| all(columns, "the report's estimate"))
                        .transpose()?
                        .flatten(),
                })
            })
            .collect::<Result<Vec<_>, Error>>()?;
        if steps.is_empty() {
            return Err(Error::parse(&self.file, 0, "the trial has no steps"));
        }
        Ok(Trial { steps })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_reports_two_files_side_by_side() {
        let trial = Trial::from_report(
            (
                "odom_x,odom_y,odom_theta,ns_x,ns_y,ns_theta\n0,0,0,0.01,0.02,0.03\n0.2,0.2,0.7,0.21,0.22,0.6\n",
                "a.csv",
            ),
            (
                "kf_x,kf_y,kf_theta,gt_x,gt_y,gt_theta\n0,0,0,0,0,0\n0.2,0.2,0.7,0.22,0.2,0.75\n",
                "b.csv",
            ),
        )
        .unwrap();
        assert_eq!(trial.steps.len(), 2);
        assert_eq!(trial.steps[1].t, 1.0);
        assert_eq!(
            trial.steps[1].reading,
            Some(Reading::Pose([0.21, 0.22, 0.6]))
        );
        assert_eq!(trial.steps[1].truth, [0.22, 0.2, 0.75]);
        assert_eq!(trial.steps[1].report, Some([0.2, 0.2, 0.7]));
    }

    #[test]
    fn errors_name_the_file_line_and_column() {
        let text = "odom_x,odom_y,odom_theta,gt_x,gt_y,gt_theta\n0,0,0,0,0,0\n0,x,0,0,0,0\n";
        let err = Trial::parse(text, "t.csv").unwrap_err().to_string();
        assert_eq!(err, "t.csv:3: odom_y is 'x', which is not a finite number");
        let err = Trial::parse("odom_x,odom_y,gt_x,gt_y,gt_theta\n", "t.csv").unwrap_err();
        assert_eq!(err.to_string(), "t.csv:1: no column odom_theta");
        let err = Trial::parse(
            "odom_x,odom_y,odom_theta,gt_x,gt_y,gt_theta\n0,0,0,0,0\n",
            "t.csv",
        );
        assert_eq!(
            err.unwrap_err().to_string(),
            "t.csv:2: expected 6 fields, as the header names, found 5"
        );
        let text =
            "odom_x,odom_y,odom_theta,ns_x,ns_y,ns_theta,gt_x,gt_y,gt_theta\n0,0,0,1,,0,0,0,0\n";
        let err = Trial::parse(text, "t.csv").unwrap_err().to_string();
        assert_eq!(err, "t.csv:2: the sensor's pose is neither whole nor empty");
        let err = Trial::from_report(("odom_x\n1\n", "a.csv"), ("gt_x\n", "b.csv")).unwrap_err();
        assert_eq!(err.to_string(), "b.csv: has 0 rows where a.csv has 1");
    }
}
