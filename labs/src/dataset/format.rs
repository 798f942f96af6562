//! The EL2320 text formats, read as the real files are (CRLF or LF, blank lines, tabs,
//! numbers written as `7` or `7.000000`, bearings not always wrapped), and written so that
//! this parser and the lab's MATLAB code read them back.
//!
//! Map: one landmark per line, `id x y`.
//! Sensor log: one time step per line,
//! `t odom_x odom_y odom_theta enc_R enc_L true_x true_y true_theta n (id bearing range)*n`.

use super::{Encoders, Reading, SensorLog, Step};
use crate::Error;
use crate::ekf::{Landmark, Map};
use crate::text::{Line, Times, lines};
use nalgebra::{Vector2, Vector3};
use std::fmt::Write;

const MAP_COLUMNS: [&str; 3] = ["id", "x", "y"];
const STEP_COLUMNS: [&str; 10] = [
    "t",
    "odom_x",
    "odom_y",
    "odom_theta",
    "enc_R",
    "enc_L",
    "true_x",
    "true_y",
    "true_theta",
    "n",
];
const READING_COLUMNS: [&str; 3] = ["id", "bearing", "range"];

/// Reads a map file; `file` names it in error messages.
pub fn parse_map(text: &str, file: &str) -> Result<Map, Error> {
    let mut landmarks: Vec<(usize, Landmark)> = Vec::new();
    for line in lines(text, file) {
        if line.tokens.len() != MAP_COLUMNS.len() {
            return Err(line.error(format!(
                "expected 3 values (id x y), found {}",
                line.tokens.len()
            )));
        }
        let id = line.whole(0, "id")?;
        if let Some((first, _)) = landmarks.iter().find(|(_, l)| l.id == id) {
            return Err(line.error(format!(
                "landmark id {id} appears again (first on line {first})"
            )));
        }
        let position = Vector2::new(line.number(1, "x")?, line.number(2, "y")?);
        landmarks.push((line.number, Landmark { id, position }));
    }
    if landmarks.is_empty() {
        return Err(Error::parse(file, 0, "the map has no landmarks"));
    }
    Map::new(landmarks.into_iter().map(|(_, l)| l).collect())
}

/// Reads a sensor log whose readings refer to the landmarks of `map`; `file` names it in
/// error messages.
pub fn parse_sensor_log(text: &str, file: &str, map: &Map) -> Result<SensorLog, Error> {
    let mut steps: Vec<Step> = Vec::new();
    let mut times = Times::default();
    for line in lines(text, file) {
        let step = line.step(map)?;
        times.next(&line, step.t)?;
        steps.push(step);
    }
    if steps.is_empty() {
        return Err(Error::parse(file, 0, "the sensor file has no time steps"));
    }
    Ok(SensorLog { steps })
}

/// Writes a map file.
pub fn write_map(map: &Map) -> String {
    let mut text = String::new();
    for landmark in map.landmarks() {
        let _ = writeln!(
            text,
            "{} {} {}",
            landmark.id, landmark.position.x, landmark.position.y
        );
    }
    text
}

/// Writes a sensor log, every number in its shortest form that reads back exactly.
pub fn write_sensor_log(log: &SensorLog) -> String {
    let mut text = String::new();
    for step in &log.steps {
        let (o, e, g) = (&step.odometry, &step.encoders, &step.truth);
        let _ = write!(
            text,
            "{} {} {} {} {} {} {} {} {} {}",
            step.t,
            o.x,
            o.y,
            o.z,
            e.right,
            e.left,
            g.x,
            g.y,
            g.z,
            step.readings.len()
        );
        for reading in &step.readings {
            let _ = write!(text, " {} {} {}", reading.id, reading.z.y, reading.z.x);
        }
        text.push('\n');
    }
    text
}

impl Line<'_> {
    fn step(&self, map: &Map) -> Result<Step, Error> {
        let fixed = STEP_COLUMNS.len();
        if self.tokens.len() < fixed {
            return Err(self.error(format!(
                "expected at least {fixed} values ({}), found {}",
                STEP_COLUMNS.join(" "),
                self.tokens.len()
            )));
        }
        let mut values = [0.0; 9];
        for (i, value) in values.iter_mut().enumerate() {
            *value = self.number(i, STEP_COLUMNS[i])?;
        }
        let n = self.whole(9, "n, the number of readings")? as usize;
        let expected = fixed + READING_COLUMNS.len() * n;
        if self.tokens.len() != expected {
            let found = self.tokens.len();
            let detail = if found < expected {
                let complete = (found - fixed) / READING_COLUMNS.len();
                format!("reading {} of {n} is incomplete", complete + 1)
            } else {
                format!("{} values too many", found - expected)
            };
            return Err(self.error(format!(
                "n = {n} readings (id bearing range each) need {expected} values on the line, found {found}: {detail}"
            )));
        }
        let readings = (0..n)
            .map(|k| self.reading(fixed + READING_COLUMNS.len() * k, k + 1, map))
            .collect::<Result<Vec<_>, _>>()?;
        let [t, ox, oy, otheta, enc_right, enc_left, tx, ty, ttheta] = values;
        Ok(Step {
            t,
            odometry: Vector3::new(ox, oy, otheta),
            encoders: Encoders {
                right: enc_right,
                left: enc_left,
            },
            truth: Vector3::new(tx, ty, ttheta),
            readings,
        })
    }

    /// Reading `k` (1-based), whose id starts at token `at`.
    fn reading(&self, at: usize, k: usize, map: &Map) -> Result<Reading, Error> {
        // The column names are formatted only for a message.
        let id = self.whole(at, format_args!("reading {k} id"))?;
        let bearing = self.number(at + 1, format_args!("reading {k} bearing"))?;
        let range = self.number(at + 2, format_args!("reading {k} range"))?;
        let landmark = map.index_of(id).ok_or_else(|| {
            self.error(format!(
                "reading {k} is of landmark id {id}, which is not on the map (its ids: {})",
                map.describe_ids()
            ))
        })?;
        if range < 0.0 {
            return Err(self.error(format!("reading {k} has a negative range, {range}")));
        }
        Ok(Reading {
            id,
            landmark,
            z: Vector2::new(range, bearing),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MAP: &str = "1 1 1\r\n2\t4 1\r\n\r\n   5    6 1\n";

    fn map() -> Map {
        parse_map(MAP, "map.txt").unwrap()
    }

    fn sensor_error(text: &str) -> String {
        parse_sensor_log(text, "so.txt", &map())
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn reads_crlf_tabs_blank_lines_and_float_ids() {
        let map = map();
        assert_eq!(map.len(), 3);
        assert_eq!(map.landmarks()[2].id, 5);
        let log = parse_sensor_log(
            "0.000000 0 0 0 1.000000 10.000000 0 0 0 2.000000 5.000000 -2.7 5.4 1 4.2 9.1 \r\n\r\n0.2 0 0 0 9 13 0 0 0 0\r\n",
            "so.txt",
            &map,
        )
        .unwrap();
        assert_eq!(log.steps.len(), 2);
        let reading = log.steps[0].readings[0];
        assert_eq!((reading.id, reading.landmark), (5, 2));
        assert_eq!(reading.z, Vector2::new(5.4, -2.7));
        assert_eq!(
            log.steps[1].encoders,
            Encoders {
                right: 9.0,
                left: 13.0
            }
        );
    }

    #[test]
    fn map_rejections_name_file_line_and_problem() {
        let err = |text| parse_map(text, "map.txt").unwrap_err().to_string();
        assert_eq!(
            err("1 1 1\n2 4\n"),
            "map.txt:2: expected 3 values (id x y), found 2"
        );
        assert_eq!(
            err("1 1 1\n2 4 x\n"),
            "map.txt:2: value 3 (y) is 'x', which is not a finite number"
        );
        assert_eq!(
            err("1.5 1 1\n"),
            "map.txt:1: value 1 (id) is '1.5', which is not a whole number >= 0"
        );
        assert_eq!(
            err("1 1 1\n\n1 2 2\n"),
            "map.txt:3: landmark id 1 appears again (first on line 1)"
        );
        assert_eq!(
            err("1 nan 1\n"),
            "map.txt:1: value 2 (x) is 'nan', which is not a finite number"
        );
        assert_eq!(err("\n\r\n"), "map.txt: the map has no landmarks");
    }

    #[test]
    fn sensor_rejections_name_file_line_and_problem() {
        assert_eq!(
            sensor_error("0 0 0 0 0 0 0 0 0\n"),
            "so.txt:1: expected at least 10 values (t odom_x odom_y odom_theta enc_R enc_L true_x true_y true_theta n), found 9"
        );
        assert_eq!(
            sensor_error("0 0 0 0 0 0 0 0 0 2 1 0.5 3\n"),
            "so.txt:1: n = 2 readings (id bearing range each) need 16 values on the line, found 13: reading 2 of 2 is incomplete"
        );
        assert_eq!(
            sensor_error("0 0 0 0 0 0 0 0 0 1 1 0.5 3 7\n"),
            "so.txt:1: n = 1 readings (id bearing range each) need 13 values on the line, found 14: 1 values too many"
        );
        assert_eq!(
            sensor_error("0 0 0 0 abc 0 0 0 0 0\n"),
            "so.txt:1: value 5 (enc_R) is 'abc', which is not a finite number"
        );
        assert_eq!(
            sensor_error("0 0 0 0 0 0 0 0 0 1 1 0.5 3\n0.2 0 0 0 0 0 0 0 0 1 1 zz 3\n"),
            "so.txt:2: value 12 (reading 1 bearing) is 'zz', which is not a finite number"
        );
        assert_eq!(
            sensor_error("0 0 0 0 0 0 0 0 0 1 3 0.5 3\n"),
            "so.txt:1: reading 1 is of landmark id 3, which is not on the map (its ids: 1-2, 5)"
        );
        assert_eq!(
            sensor_error("0.4 0 0 0 0 0 0 0 0 0\n\n0.2 0 0 0 0 0 0 0 0 0\n"),
            "so.txt:3: time goes backwards: t = 0.2 here, but t = 0.4 on line 1"
        );
        assert_eq!(
            sensor_error("0 0 0 0 0 0 0 0 0 -1\n"),
            "so.txt:1: value 10 (n, the number of readings) is '-1', which is not a whole number >= 0"
        );
        assert_eq!(
            sensor_error("0 0 0 0 0 0 0 0 0 1 1 0.5 -3\n"),
            "so.txt:1: reading 1 has a negative range, -3"
        );
        assert_eq!(
            sensor_error(""),
            "so.txt: the sensor file has no time steps"
        );
    }

    #[test]
    fn what_is_written_reads_back_identically() {
        let map = map();
        let text = "0 0 0 0 0 0 0 0 0 2 5 -2.7 5.4 1 4.2 9.1\n0.2 0.001 -0.0000001 3.5 9 13 0.1 1e-300 -3.14 0\n";
        let log = parse_sensor_log(text, "so.txt", &map).unwrap();
        let written = write_sensor_log(&log);
        assert_eq!(parse_sensor_log(&written, "so.txt", &map).unwrap(), log);
        assert_eq!(parse_map(&write_map(&map), "map.txt").unwrap(), map);
    }
}
