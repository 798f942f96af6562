//! The indoor positioning sensor: a detector on the ceiling that sees two infrared
//! platforms on the robot, and what its readings are worth.
//!
//! Each platform's reading is its position `(x_i, y_i)` in the room and an intensity
//! `I_i`, the brighter the better. The robot's pose follows from the two ([`combine`]):
//!
//! ```text
//! w_i   = I_i / (I_1 + I_2)                    (the weights sum to one)
//! (x, y) = w_1 (x_1, y_1) + w_2 (x_2, y_2)      (the intensity-weighted mean)
//! theta = atan2(y_1 - y_2, x_1 - x_2)           (platform 1 is the front one)
//! ```
//!
//! Its noise ([`NoiseModel`]): each platform's standard deviation in x and in y is about
//! inversely proportional to its intensity, `sigma_i = c_xy / I_i`, and the larger of the
//! two serves for both coordinates of the mean. The heading's standard deviation comes
//! from first-order error propagation through the arctangent ([`heading_sigma`]), cross
//! terms neglected; where the platforms are unknown (the report's trials give the pose
//! alone) it is approximated by a scaled inverse of the weaker intensity,
//! `sigma_theta = c_theta / I_min`.
//!
//! The detector ([`Detector`]) sees a circle of about 2 m around the point under it.
//! The intensity falls with the distance to it and with the angle between a platform's
//! tilted face and the line to it ([`Detector::intensity`]), so a platform that faces
//! the detector reads far better than one that faces away; readings skew inwards beyond
//! about 1.5 m, are garbage or missing outside the field of view, and saturate when a
//! second robot is in view ([`Detector::read`]).

use crate::Error;
use crate::rng::Rng;
use nalgebra::{Vector2, Vector3};
use serde::{Deserialize, Serialize};

/// One platform as the detector reports it: its position in the room (metres) and its
/// intensity (the detector's counts).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
pub struct Platform {
    pub x: f64,
    pub y: f64,
    pub intensity: f64,
}

/// A pose measured by the sensor and its standard deviations.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
pub struct Measurement {
    /// `[x, y, theta]`, theta in [-pi, pi).
    pub pose: [f64; 3],
    /// The standard deviation of x and of y, metres.
    pub sigma_xy: f64,
    /// The standard deviation of theta, radians.
    pub sigma_theta: f64,
}

/// The constants of the measurement noise: `sigma_xy = c_xy / I`, `sigma_theta =
/// c_theta / I`.
///
/// The report found about 90 and 100 in its detector's units. For `c_theta` estlab
/// takes what error propagation gives its own platforms: with both at the weaker
/// intensity, `sigma_theta = sqrt(2) c_xy / (L I)`, and with the platforms `L = 0.5 m`
/// apart that is about `255 / I`; 250 rounds it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
pub struct NoiseModel {
    pub c_xy: f64,
    pub c_theta: f64,
}

impl Default for NoiseModel {
    fn default() -> Self {
        NoiseModel {
            c_xy: 90.0,
            c_theta: 250.0,
        }
    }
}

impl NoiseModel {
    pub fn validate(&self) -> Result<(), Error> {
        for (field, value) in [("c_xy", self.c_xy), ("c_theta", self.c_theta)] {
            if !(value.is_finite() && value > 0.0 && value <= 1e6) {
                return Err(Error::invalid(field, "must be a number in (0, 1e6]"));
            }
        }
        Ok(())
    }

    /// A platform's standard deviation in x and in y: `sigma_i = c_xy / I_i`.
    pub fn platform_sigma(&self, platform: &Platform) -> f64 {
        self.c_xy / platform.intensity
    }

    /// The measurement the two platforms make: the intensity-weighted mean, the heading
    /// along the line from platform 2 to platform 1, the weaker platform's standard
    /// deviation for x and y, and the heading's by error propagation.
    pub fn measure(&self, platforms: &[Platform; 2]) -> Measurement {
        let sigmas = platforms.map(|p| self.platform_sigma(&p));
        Measurement {
            pose: combine(platforms).into(),
            sigma_xy: sigmas[0].max(sigmas[1]),
            sigma_theta: heading_sigma(platforms, sigmas),
        }
    }

    /// A pose measured without its platforms (the report's trials): the intensity is
    /// what the detector gives a platform there, and both standard deviations follow
    /// from it, `c_xy / I` and `c_theta / I`.
    pub fn measure_pose(&self, pose: [f64; 3], detector: &Detector) -> Measurement {
        let intensity = detector.expected_intensity(Vector2::new(pose[0], pose[1]));
        Measurement {
            pose,
            sigma_xy: self.c_xy / intensity,
            sigma_theta: self.c_theta / intensity,
        }
    }
}

/// The robot's pose from its two platforms: the intensity-weighted mean of their
/// positions and `theta = atan2(y_1 - y_2, x_1 - x_2)`.
pub fn combine(platforms: &[Platform; 2]) -> Vector3<f64> {
    let [p1, p2] = platforms;
    let total = p1.intensity + p2.intensity;
    let (w1, w2) = (p1.intensity / total, p2.intensity / total);
    Vector3::new(
        w1 * p1.x + w2 * p2.x,
        w1 * p1.y + w2 * p2.y,
        libm::atan2(p1.y - p2.y, p1.x - p2.x),
    )
}

/// The heading's standard deviation by first-order error propagation through
/// `theta = atan2(dy, dx)`, `dx = x_1 - x_2`, `dy = y_1 - y_2`, `L^2 = dx^2 + dy^2`:
///
/// ```text
/// d theta / d x_1 = -dy / L^2    d theta / d y_1 =  dx / L^2
/// d theta / d x_2 =  dy / L^2    d theta / d y_2 = -dx / L^2
/// sigma_theta^2 = sum_i (d theta / d x_i sigma_i)^2 + (d theta / d y_i sigma_i)^2
///               = (sigma_1^2 + sigma_2^2) / L^2
/// ```
///
/// `sigmas` are the platforms' own standard deviations (the same in x and y).
pub fn heading_sigma(platforms: &[Platform; 2], sigmas: [f64; 2]) -> f64 {
    let [p1, p2] = platforms;
    let (dx, dy) = (p1.x - p2.x, p1.y - p2.y);
    let l2 = dx * dx + dy * dy;
    let partials = [
        (-dy / l2, dx / l2, sigmas[0]),
        (dy / l2, -dx / l2, sigmas[1]),
    ];
    partials
        .iter()
        .map(|(d_x, d_y, sigma)| (d_x * sigma).powi(2) + (d_y * sigma).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The detector, the platforms on the robot and how they are seen. Lengths in metres,
/// angles in radians; the detector is above the room's origin.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, ts_rs::TS)]
pub struct Detector {
    /// Height of the ceiling above the platforms.
    pub height: f64,
    /// The intensity of a platform right under the detector, facing straight up.
    pub peak_intensity: f64,
    /// The largest intensity the detector reports (a second robot in view drives it
    /// there).
    pub saturation: f64,
    /// The radius of the circle around the point under the detector that it sees.
    pub field_of_view: f64,
    /// Beyond this distance readings skew towards the point under the detector.
    pub skew_from: f64,
    /// How much: metres of skew per square metre beyond `skew_from`.
    pub skew: f64,
    /// How far ahead of and behind the robot's centre the platforms sit (platform 1 in
    /// front).
    pub platform_offset: f64,
    /// How far each platform's face is tilted towards the front of the robot.
    pub tilt: f64,
    /// The platforms' true noise: `sigma_i = noise / I_i` in x and in y.
    pub noise: f64,
    /// The relative noise of a reported intensity.
    pub intensity_noise: f64,
    /// The chance that the detector reports garbage for a robot outside its field of view
    /// (otherwise it reports nothing).
    pub garbage: f64,
}

impl Default for Detector {
    fn default() -> Self {
        Detector {
            height: 2.4,
            peak_intensity: 3400.0,
            saturation: 4000.0,
            field_of_view: 2.0,
            skew_from: 1.5,
            skew: 0.3,
            platform_offset: 0.25,
            tilt: 20f64.to_radians(),
            noise: 90.0,
            intensity_noise: 0.05,
            garbage: 0.3,
        }
    }
}

impl Detector {
    /// The platforms' true positions for a robot at `pose`, front one first.
    pub fn platform_positions(&self, pose: &Vector3<f64>) -> [Vector2<f64>; 2] {
        let (sin, cos) = libm::sincos(pose.z);
        let ahead = Vector2::new(cos, sin) * self.platform_offset;
        let centre = pose.xy();
        [centre + ahead, centre - ahead]
    }

    /// The intensity of a platform at `position` on a robot heading `heading`:
    ///
    /// I = I_0 (h / rho)^3 cos^2(gamma),   rho = sqrt(d^2 + h^2),
    ///
    /// the light falling with the square of the distance `rho` and the detector seeing
    /// the spot at the angle `h / rho` off its axis, and `gamma` the angle between the
    /// platform's face (tilted by `tilt` towards the robot's front) and the line to the
    /// detector; a face turned away gives nothing.
    pub fn intensity(&self, position: Vector2<f64>, heading: f64) -> f64 {
        let h = self.height;
        let rho = (position.norm_squared() + h * h).sqrt();
        let (sin_tilt, cos_tilt) = libm::sincos(self.tilt);
        let (sin, cos) = libm::sincos(heading);
        let face = [sin_tilt * cos, sin_tilt * sin, cos_tilt];
        let to_detector = [-position.x / rho, -position.y / rho, h / rho];
        let cos_gamma: f64 = face.iter().zip(to_detector).map(|(a, b)| a * b).sum();
        self.peak_intensity * (h / rho).powi(3) * cos_gamma.max(0.0).powi(2)
    }

    /// The intensity a platform at `position` has on a robot whose heading is unknown,
    /// taken side-on to the detector (its face tilted neither towards nor away):
    /// `I_0 (h / rho)^5 cos^2(tilt)`.
    pub fn expected_intensity(&self, position: Vector2<f64>) -> f64 {
        let h = self.height;
        let rho = (position.norm_squared() + h * h).sqrt();
        self.peak_intensity * (h / rho).powi(5) * libm::cos(self.tilt).powi(2)
    }

    /// How far a reading at `distance` from the point under the detector is pulled
    /// towards it: `skew (d - d_skew)^2` beyond `d_skew`, nothing within.
    pub fn skew_at(&self, distance: f64) -> f64 {
        let beyond = (distance - self.skew_from).max(0.0);
        self.skew * beyond * beyond
    }

    /// What the detector reports for a robot at `pose`: both platforms, or nothing.
    /// Outside the field of view it reports nothing or, with chance `garbage`, spots
    /// that have little to do with the robot; `other_robot` is a second robot in view,
    /// whose light the detector cannot tell apart: it saturates, and both spots land
    /// between the two robots.
    pub fn read(
        &self,
        pose: &Vector3<f64>,
        other_robot: Option<Vector2<f64>>,
        rng: &mut Rng,
    ) -> Option<[Platform; 2]> {
        let outside = pose.xy().norm() > self.field_of_view;
        if outside && !rng.chance(self.garbage) {
            return None;
        }
        let positions = self.platform_positions(pose);
        Some(positions.map(|truth| {
            let intensity = self.intensity(truth, pose.z);
            let distance = truth.norm();
            let mut seen = truth - truth.normalize() * self.skew_at(distance).min(distance);
            let mut reported = intensity * (1.0 + self.intensity_noise * rng.standard_normal());
            if outside {
                // Stray light: a spot anywhere within a metre of where it should be.
                seen += Vector2::new(rng.uniform_in(-1.0, 1.0), rng.uniform_in(-1.0, 1.0));
            }
            if let Some(other) = other_robot {
                seen = (seen + other) / 2.0;
                reported = self.saturation;
            }
            let sigma = self.noise / intensity.max(1.0);
            Platform {
                x: seen.x + sigma * rng.standard_normal(),
                y: seen.y + sigma * rng.standard_normal(),
                intensity: reported.clamp(1.0, self.saturation),
            }
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn platform(x: f64, y: f64, intensity: f64) -> Platform {
        Platform { x, y, intensity }
    }

    #[test]
    fn the_pose_is_the_weighted_mean_and_the_line_between() {
        let pose = combine(&[platform(1.0, 2.0, 3000.0), platform(0.0, 2.0, 1000.0)]);
        assert!((pose - Vector3::new(0.75, 2.0, 0.0)).norm() < 1e-15);
        let pose = combine(&[platform(0.0, 1.0, 500.0), platform(0.0, 1.5, 500.0)]);
        assert!((pose - Vector3::new(0.0, 1.25, -FRAC_PI_2)).norm() < 1e-15);
    }

    #[test]
    fn the_weaker_platform_sets_the_position_noise() {
        let model = NoiseModel::default();
        let m = model.measure(&[platform(0.25, 0.0, 3000.0), platform(-0.25, 0.0, 900.0)]);
        assert!((m.sigma_xy - 0.1).abs() < 1e-15);
        // (sigma_1^2 + sigma_2^2) / L^2 with L = 0.5.
        let expected = ((0.03f64.powi(2) + 0.1f64.powi(2)) / 0.25).sqrt();
        assert!((m.sigma_theta - expected).abs() < 1e-15);
    }

    /// Error propagation against a Monte Carlo of the two platforms' noise: the heading's
    /// sample standard deviation is within sampling error of the propagated one.
    #[test]
    fn the_heading_sigma_is_what_the_platforms_noise_gives() {
        let mut rng = Rng::new(5);
        for (platforms, sigmas) in [
            (
                [platform(0.3, 0.1, 1.0), platform(-0.2, -0.1, 1.0)],
                [0.01, 0.02],
            ),
            (
                [platform(1.0, 1.5, 1.0), platform(1.2, 1.0, 1.0)],
                [0.03, 0.005],
            ),
        ] {
            let truth = combine(&platforms).z;
            let n = 100_000;
            let variance = (0..n)
                .map(|_| {
                    let noisy = [0, 1].map(|i| {
                        platform(
                            platforms[i].x + sigmas[i] * rng.standard_normal(),
                            platforms[i].y + sigmas[i] * rng.standard_normal(),
                            1.0,
                        )
                    });
                    crate::angle::difference(combine(&noisy).z, truth).powi(2)
                })
                .sum::<f64>()
                / f64::from(n);
            let propagated = heading_sigma(&platforms, sigmas);
            // The sample variance of n normal deviates is off by about sqrt(2 / n) of
            // itself; four of those, plus the linearisation's small bias.
            let relative = (variance.sqrt() / propagated - 1.0).abs();
            assert!(relative < 0.01, "{} vs {propagated}", variance.sqrt());
        }
    }

    #[test]
    fn intensity_falls_with_distance_and_with_a_face_turned_away() {
        let detector = Detector::default();
        let under = detector.intensity(Vector2::zeros(), 0.0);
        let mut last = under;
        for d in [0.5, 1.0, 1.5, 2.0, 2.5] {
            let away = detector.intensity(Vector2::new(d, 0.0), 0.0);
            assert!(away < last, "at {d}");
            last = away;
        }
        let facing = detector.intensity(Vector2::new(2.0, 0.0), PI);
        let turned_away = detector.intensity(Vector2::new(2.0, 0.0), 0.0);
        assert!(facing > 3.0 * turned_away, "{facing} vs {turned_away}");
    }

    /// The report's facts: the spread of readings against the distance is about linear in
    /// the inverse of the intensity, and nothing useful comes from beyond the field of
    /// view.
    #[test]
    fn the_sensor_model_has_the_reports_facts() {
        let detector = Detector::default();
        let mut rng = Rng::new(9);
        for d in [0.0, 0.5, 1.0, 1.4] {
            let pose = Vector3::new(d, 0.0, FRAC_PI_2);
            let n = 20_000;
            let (mut spread, mut inverse_intensity) = (0.0, 0.0);
            for _ in 0..n {
                let readings = detector.read(&pose, None, &mut rng).expect("in view");
                for p in readings {
                    let truth = detector.platform_positions(&pose);
                    let nearest = truth
                        .iter()
                        .map(|t| (t - Vector2::new(p.x, p.y)).norm_squared())
                        .fold(f64::INFINITY, f64::min);
                    spread += nearest;
                    inverse_intensity += 1.0 / p.intensity;
                }
            }
            // Two coordinates each: E|e|^2 = 2 sigma^2 with sigma = 90 / I.
            let sigma = (spread / f64::from(2 * n) / 2.0).sqrt();
            let constant = sigma / (inverse_intensity / f64::from(2 * n));
            assert!(
                (constant - 90.0).abs() < 3.0,
                "at {d}: sigma I = {constant}"
            );
        }
        let outside = Vector3::new(2.5, 0.0, 0.0);
        let errors: Vec<f64> = (0..1000)
            .filter_map(|_| detector.read(&outside, None, &mut rng))
            .map(|readings| (combine(&readings).xy() - outside.xy()).norm())
            .collect();
        assert!(
            (200..400).contains(&errors.len()),
            "{} garbage readings of 1000",
            errors.len()
        );
        let mean = errors.iter().sum::<f64>() / errors.len() as f64;
        assert!(mean > 0.4, "garbage {mean} m off on average");
    }

    #[test]
    fn a_second_robot_saturates_the_detector() {
        let detector = Detector::default();
        let mut rng = Rng::new(2);
        let pose = Vector3::new(0.5, 0.5, 0.0);
        let readings = detector
            .read(&pose, Some(Vector2::new(-0.5, 0.5)), &mut rng)
            .unwrap();
        assert!(readings.iter().all(|p| p.intensity == detector.saturation));
        assert!(combine(&readings).x.abs() < 0.1);
    }
}
