//! MRCLAM's text files as published: CRLF lines, a header of comment lines starting with
//! `#`, then one record a line, its values separated by tabs and spaces.
//!
//! - `RobotN_Odometry.dat`: `t v omega`
//! - `RobotN_Measurement.dat`: `t barcode range bearing`
//! - `RobotN_Groundtruth.dat`: `t x y theta`
//! - `Landmark_Groundtruth.dat`: `subject x y sd_x sd_y`
//! - `Barcodes.dat`: `subject barcode`
//!
//! Times are seconds since 1970 and never go backwards within a file (a camera frame's
//! readings share a time).

use super::{Barcode, Measurement, Odometry, Pose, Post, Robot, World};
use crate::Error;
use crate::text::{Line, Times, lines};

/// Reads a robot's three files, each given as (text, the file's name for messages).
pub fn parse_robot(
    odometry: (&str, &str),
    measurements: (&str, &str),
    truth: (&str, &str),
) -> Result<Robot, Error> {
    Ok(Robot {
        odometry: parse_odometry(odometry.0, odometry.1)?,
        measurements: parse_measurements(measurements.0, measurements.1)?,
        truth: parse_truth(truth.0, truth.1)?,
    })
}

/// Reads the posts' file (`Landmark_Groundtruth.dat`) and the barcodes' (`Barcodes.dat`),
/// each given as (text, the file's name for messages).
pub fn parse_world(posts: (&str, &str), barcodes: (&str, &str)) -> Result<World, Error> {
    Ok(World {
        posts: parse_posts(posts.0, posts.1)?,
        barcodes: parse_barcodes(barcodes.0, barcodes.1)?,
    })
}

pub fn parse_odometry(text: &str, file: &str) -> Result<Vec<Odometry>, Error> {
    in_time(text, file, ["t", "v", "omega"], |[t, v, omega], _| {
        Ok(Odometry { t, v, omega })
    })
}

pub fn parse_measurements(text: &str, file: &str) -> Result<Vec<Measurement>, Error> {
    let columns = ["t", "barcode", "range", "bearing"];
    in_time(text, file, columns, |[t, _, range, bearing], line| {
        Ok(Measurement {
            t,
            barcode: line.whole(1, "barcode")?,
            range,
            bearing,
        })
    })
}

pub fn parse_truth(text: &str, file: &str) -> Result<Vec<Pose>, Error> {
    in_time(
        text,
        file,
        ["t", "x", "y", "theta"],
        |[t, x, y, theta], _| Ok(Pose { t, x, y, theta }),
    )
}

pub fn parse_posts(text: &str, file: &str) -> Result<Vec<Post>, Error> {
    let mut posts: Vec<(usize, Post)> = Vec::new();
    for (line, [_, x, y, sd_x, sd_y]) in records(text, file, ["subject", "x", "y", "sd_x", "sd_y"])?
    {
        let subject = line.whole(0, "subject")?;
        if let Some((first, _)) = posts.iter().find(|(_, post)| post.subject == subject) {
            return Err(line.error(format!(
                "subject {subject} appears again (first on line {first})"
            )));
        }
        posts.push((
            line.number,
            Post {
                subject,
                x,
                y,
                sd_x,
                sd_y,
            },
        ));
    }
    nonempty(posts.into_iter().map(|(_, post)| post).collect(), file)
}

pub fn parse_barcodes(text: &str, file: &str) -> Result<Vec<Barcode>, Error> {
    let mut barcodes: Vec<(usize, Barcode)> = Vec::new();
    for (line, _) in records(text, file, ["subject", "barcode"])? {
        let read = Barcode {
            subject: line.whole(0, "subject")?,
            barcode: line.whole(1, "barcode")?,
        };
        if let Some((first, _)) = barcodes
            .iter()
            .find(|(_, known)| known.subject == read.subject || known.barcode == read.barcode)
        {
            return Err(line.error(format!(
                "subject {} or barcode {} appears again (first on line {first})",
                read.subject, read.barcode
            )));
        }
        barcodes.push((line.number, read));
    }
    nonempty(barcodes.into_iter().map(|(_, b)| b).collect(), file)
}

/// The records of a file whose first value is a time that never goes backwards, each made
/// by `make` from its values and its line.
fn in_time<const N: usize, T>(
    text: &str,
    file: &str,
    columns: [&str; N],
    make: impl Fn([f64; N], &Line) -> Result<T, Error>,
) -> Result<Vec<T>, Error> {
    let mut made = Vec::new();
    let mut times = Times::default();
    for (line, values) in records(text, file, columns)? {
        times.next(&line, values[0])?;
        made.push(make(values, &line)?);
    }
    nonempty(made, file)
}

/// The lines of `text` that are neither blank nor comments, each with its `N` finite
/// numbers (named by `columns` in messages).
fn records<'a, const N: usize>(
    text: &'a str,
    file: &'a str,
    columns: [&str; N],
) -> Result<Vec<(Line<'a>, [f64; N])>, Error> {
    lines(text, file)
        .filter(|line| !line.tokens[0].starts_with('#'))
        .map(|line| {
            if line.tokens.len() != N {
                return Err(line.error(format!(
                    "expected {N} values ({}), found {}",
                    columns.join(" "),
                    line.tokens.len()
                )));
            }
            let mut values = [0.0; N];
            for (i, value) in values.iter_mut().enumerate() {
                *value = line.number(i, columns[i])?;
            }
            Ok((line, values))
        })
        .collect()
}

fn nonempty<T>(records: Vec<T>, file: &str) -> Result<Vec<T>, Error> {
    if records.is_empty() {
        return Err(Error::parse(file, 0, "the file has no records"));
    }
    Ok(records)
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "# UTIAS Multi-Robot Cooperative Localization and Mapping Dataset\r\n\
                          # Odometry Data Fomat:\r\n";

    #[test]
    fn crlf_tabs_and_comments_are_read_as_published() {
        let text = format!(
            "{HEADER}1248444187.156 \t  0.086 \t -0.398 \r\n\r\n1248444187.186 \t 0.1 \t 0 \r\n"
        );
        let read = parse_odometry(&text, "Robot1_Odometry.dat").unwrap();
        assert_eq!(
            read,
            [
                Odometry {
                    t: 1248444187.156,
                    v: 0.086,
                    omega: -0.398
                },
                Odometry {
                    t: 1248444187.186,
                    v: 0.1,
                    omega: 0.0
                },
            ]
        );
    }

    #[test]
    fn a_bad_line_is_named_with_its_file_line_and_value() {
        let message = |text: &str| parse_measurements(text, "m.dat").unwrap_err().to_string();
        assert_eq!(
            message("# header\n1.0 14 3.7\n"),
            "m.dat:2: expected 4 values (t barcode range bearing), found 3"
        );
        assert_eq!(
            message("1.0 14 3.7 x\n"),
            "m.dat:1: value 4 (bearing) is 'x', which is not a finite number"
        );
        assert_eq!(
            message("1.0 14.5 3.7 0.1\n"),
            "m.dat:1: value 2 (barcode) is '14.5', which is not a whole number >= 0"
        );
        assert_eq!(
            message("2.0 14 3.7 0.1\n1.0 14 3.7 0.1\n"),
            "m.dat:2: time goes backwards: t = 1 here, but t = 2 on line 1"
        );
        assert_eq!(
            message("# only a header\n"),
            "m.dat: the file has no records"
        );
    }

    #[test]
    fn subjects_and_barcodes_are_each_named_once() {
        let posts = "6 0.5 -4.2 0.0001 0.0002\n6 0.6 -4.4 0.0001 0.0002\n";
        assert_eq!(
            parse_posts(posts, "l.dat").unwrap_err().to_string(),
            "l.dat:2: subject 6 appears again (first on line 1)"
        );
        let barcodes = "1 5\n2 5\n";
        assert_eq!(
            parse_barcodes(barcodes, "b.dat").unwrap_err().to_string(),
            "b.dat:2: subject 2 or barcode 5 appears again (first on line 1)"
        );
        let world = parse_world(
            ("6 0.5 -4.2 0.0001 0.0002\n", "l.dat"),
            ("1 5\n6 27\n", "b.dat"),
        )
        .unwrap();
        assert_eq!(world.subject_of(27), Some(6));
        assert_eq!(world.post_of(27).map(|post| post.x), Some(0.5));
        assert_eq!(world.post_of(5), None);
        assert_eq!(world.subject_of(99), None);
    }
}
