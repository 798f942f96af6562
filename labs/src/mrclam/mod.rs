//! The UTIAS Multi-Robot Cooperative Localization and Mapping data set (MRCLAM): iRobot
//! Create robots driving in a 15 x 8 m room among barcoded landmark posts, each robot
//! with its commanded odometry (forward and angular velocity), its camera's
//! range-bearing readings of the barcodes it sees, and its pose from motion capture.
//! Read as published (`format`); the files themselves are never shipped.
//!
//! Every subject of the room (robots 1 to 5, posts 6 to 20) wears a barcode; a reading
//! names the barcode it saw, which [`World::subject_of`] turns into the subject (data set
//! 6 has three readings of barcodes no subject wears: misreadings, for a filter to skip).

pub mod belief;
pub mod ekf;
pub mod format;
pub mod grid;
pub mod learn;
pub mod motion;
pub mod particle;
pub mod run;
pub mod sensor;
pub mod simulate;
pub mod ukf;

use serde::{Deserialize, Serialize};

/// A commanded motion: from `t` on, forward velocity `v` [m/s] and angular velocity
/// `omega` [rad/s].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Odometry {
    pub t: f64,
    pub v: f64,
    pub omega: f64,
}

/// A reading of the camera at `t`: the barcode it saw, at `range` [m] and `bearing`
/// [rad] from the robot's heading.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Measurement {
    pub t: f64,
    pub barcode: u32,
    pub range: f64,
    pub bearing: f64,
}

/// A robot's pose at `t` from motion capture: position [m] and heading [rad].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    pub t: f64,
    pub x: f64,
    pub y: f64,
    pub theta: f64,
}

/// A landmark post, where motion capture found it: its subject number, position [m] and
/// the standard deviations of that position [m].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Post {
    pub subject: u32,
    pub x: f64,
    pub y: f64,
    pub sd_x: f64,
    pub sd_y: f64,
}

/// Which barcode a subject wears.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Barcode {
    pub subject: u32,
    pub barcode: u32,
}

/// What one robot recorded, each in the order of time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Robot {
    pub odometry: Vec<Odometry>,
    pub measurements: Vec<Measurement>,
    pub truth: Vec<Pose>,
}

/// The room every robot of a data set shares: its posts and everyone's barcodes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct World {
    pub posts: Vec<Post>,
    pub barcodes: Vec<Barcode>,
}

/// The first subject number of a post: 1 to 5 are the robots.
pub const FIRST_POST: u32 = 6;

impl World {
    /// The subject that wears `barcode`.
    pub fn subject_of(&self, barcode: u32) -> Option<u32> {
        self.barcodes
            .iter()
            .find(|b| b.barcode == barcode)
            .map(|b| b.subject)
    }

    /// The post that wears `barcode` (`None` for a robot's barcode or an unknown one).
    pub fn post_of(&self, barcode: u32) -> Option<&Post> {
        let subject = self.subject_of(barcode)?;
        self.posts.iter().find(|post| post.subject == subject)
    }
}
