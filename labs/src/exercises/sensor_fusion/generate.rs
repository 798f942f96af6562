//! Test cases generated from a seed, so that every student can have a variant of their
//! own. Each function's cases cycle through its scenarios, the situations where classic
//! mistakes show: one platform far brighter than the other (the weights, the weaker
//! platform's noise), platforms lined up along an axis or not (the partial derivatives),
//! headings across +-pi (wrapping), poses exactly on the edge of the field of view, just
//! inside it and in the corners of the square around it, a filter whose heading differs
//! from the odometry's (the frame of the increment), and readings near and far from the
//! prediction.

use super::Case;
use super::contract::{Call, PlatformReading};
use crate::fusion::filter::{Settings, predict};
use crate::fusion::sensor::Detector;
use crate::grading::{self, rows, scenario_cases};
use crate::rng::Rng;
use nalgebra::{Matrix3, Vector2, Vector3};
use std::f64::consts::PI;

/// `per_function` cases of every student function, from `seed`.
pub fn generate(seed: u64, per_function: usize) -> Vec<Case> {
    scenario_cases(seed, per_function, &SCENARIOS)
}

type Scenario = grading::Scenario<Call>;

const SCENARIOS: [(&str, &[Scenario]); 7] = [
    (
        "combine_platforms",
        &[
            ("a robot in view, its platforms read unequally", |rng| {
                let (p1, p2) = platforms(rng, Heading::Any, Brightness::Unequal);
                Call::CombinePlatforms { p1, p2 }
            }),
            ("a robot heading close to +-pi", |rng| {
                let (p1, p2) = platforms(rng, Heading::NearPi, Brightness::Unequal);
                Call::CombinePlatforms { p1, p2 }
            }),
            ("one platform far brighter than the other", |rng| {
                let (p1, p2) = platforms(rng, Heading::Any, Brightness::OneFar);
                Call::CombinePlatforms { p1, p2 }
            }),
        ],
    ),
    (
        "heading_sigma",
        &[
            ("platforms read unequally", |rng| {
                let (p1, p2) = platforms(rng, Heading::Any, Brightness::Unequal);
                Call::HeadingSigma {
                    p1,
                    p2,
                    c_xy: c_xy(rng),
                }
            }),
            ("one platform far weaker than the other", |rng| {
                let (p1, p2) = platforms(rng, Heading::Any, Brightness::OneFar);
                Call::HeadingSigma {
                    p1,
                    p2,
                    c_xy: c_xy(rng),
                }
            }),
            ("a robot heading close to +-pi", |rng| {
                let (p1, p2) = platforms(rng, Heading::NearPi, Brightness::Unequal);
                Call::HeadingSigma {
                    p1,
                    p2,
                    c_xy: c_xy(rng),
                }
            }),
        ],
    ),
    (
        "measurement_noise",
        &[
            ("platforms read unequally", |rng| {
                let (p1, p2) = platforms(rng, Heading::Any, Brightness::Unequal);
                Call::MeasurementNoise {
                    p1,
                    p2,
                    c_xy: c_xy(rng),
                }
            }),
            ("one platform far weaker than the other", |rng| {
                let (p1, p2) = platforms(rng, Heading::Any, Brightness::OneFar);
                Call::MeasurementNoise {
                    p1,
                    p2,
                    c_xy: c_xy(rng),
                }
            }),
        ],
    ),
    (
        "in_field_of_view",
        &[
            ("exactly on the edge of the field of view", |rng| {
                view(rng, Place::OnTheEdge)
            }),
            ("just inside the edge", |rng| view(rng, Place::JustInside)),
            ("just outside the edge", |rng| view(rng, Place::JustOutside)),
            ("in view, more than sqrt(radius) away", |rng| {
                view(rng, Place::BeyondRootRadius)
            }),
            (
                "in a corner of the square around the field of view",
                |rng| view(rng, Place::Corner),
            ),
            ("right under the detector", |rng| view(rng, Place::Under)),
        ],
    ),
    (
        "predict",
        &[
            (
                "a move ahead, the filter's heading off the odometry's",
                |rng| prediction(rng, Motion::Ahead),
            ),
            ("a turn on the spot", |rng| prediction(rng, Motion::Spin)),
            ("an arc across +-pi", |rng| {
                prediction(rng, Motion::AcrossPi)
            }),
            ("standing still", |rng| prediction(rng, Motion::Still)),
            ("a long move after a drive", |rng| {
                prediction(rng, Motion::Long)
            }),
        ],
    ),
    (
        "mahalanobis",
        &[
            ("a reading close to the prediction", |rng| {
                let (mu_bar, sigma_bar, z, q) = reading(rng, Reading::Close);
                Call::Mahalanobis {
                    mu_bar,
                    sigma_bar,
                    z,
                    q,
                }
            }),
            ("a reading far from the prediction", |rng| {
                let (mu_bar, sigma_bar, z, q) = reading(rng, Reading::Far);
                Call::Mahalanobis {
                    mu_bar,
                    sigma_bar,
                    z,
                    q,
                }
            }),
            ("prediction and reading on either side of +-pi", |rng| {
                let (mu_bar, sigma_bar, z, q) = reading(rng, Reading::AcrossPi);
                Call::Mahalanobis {
                    mu_bar,
                    sigma_bar,
                    z,
                    q,
                }
            }),
        ],
    ),
    (
        "update",
        &[
            ("a reading close to the prediction", |rng| {
                let (mu_bar, sigma_bar, z, q) = reading(rng, Reading::Close);
                Call::Update {
                    mu_bar,
                    sigma_bar,
                    z,
                    q,
                }
            }),
            ("prediction and reading on either side of +-pi", |rng| {
                let (mu_bar, sigma_bar, z, q) = reading(rng, Reading::AcrossPi);
                Call::Update {
                    mu_bar,
                    sigma_bar,
                    z,
                    q,
                }
            }),
            ("a noisy reading of a confident prediction", |rng| {
                let (mu_bar, sigma_bar, z, q) = reading(rng, Reading::Noisy);
                Call::Update {
                    mu_bar,
                    sigma_bar,
                    z,
                    q,
                }
            }),
        ],
    ),
];

// ---- the platforms ----

#[derive(Clone, Copy)]
enum Heading {
    Any,
    /// Within 0.1 rad of +-pi.
    NearPi,
}

#[derive(Clone, Copy)]
enum Brightness {
    /// As the detector reads them, give or take a third.
    Unequal,
    /// One 3 to 6 times the other.
    OneFar,
}

/// A constant of the noise model around the report's 90.
fn c_xy(rng: &mut Rng) -> f64 {
    rng.uniform_in(50.0, 150.0)
}

/// The two platforms' readings of a robot within 2 m of the point under the detector:
/// 0.3 to 0.8 m apart, a few centimetres of noise, intensities as the detector gives
/// them.
fn platforms(
    rng: &mut Rng,
    heading: Heading,
    brightness: Brightness,
) -> (PlatformReading, PlatformReading) {
    let detector = Detector::default();
    let (r, bearing) = (rng.uniform_in(0.0, 2.0), rng.uniform_in(-PI, PI));
    let centre = Vector2::new(r * libm::cos(bearing), r * libm::sin(bearing));
    let theta = match heading {
        Heading::Any => rng.uniform_in(-PI, PI),
        Heading::NearPi => PI + rng.uniform_in(-0.1, 0.1),
    };
    let half = rng.uniform_in(0.15, 0.4);
    let ahead = Vector2::new(libm::cos(theta), libm::sin(theta)) * half;
    let (f1, f2) = match brightness {
        Brightness::Unequal => (rng.uniform_in(0.7, 1.3), rng.uniform_in(0.7, 1.3)),
        Brightness::OneFar => {
            let ratio = rng.uniform_in(3.0, 6.0);
            if rng.chance(0.5) {
                (1.0, 1.0 / ratio)
            } else {
                (1.0 / ratio, 1.0)
            }
        }
    };
    let mut read = |at: Vector2<f64>, factor: f64| -> PlatformReading {
        let intensity = (detector.intensity(at, theta) * factor).max(50.0);
        let x = at.x + rng.normal(0.0, 0.02);
        let y = at.y + rng.normal(0.0, 0.02);
        [x, y, libm::round(intensity)]
    };
    (read(centre + ahead, f1), read(centre - ahead, f2))
}

// ---- the field of view ----

#[derive(Clone, Copy)]
enum Place {
    OnTheEdge,
    JustInside,
    JustOutside,
    BeyondRootRadius,
    Corner,
    Under,
}

/// A pose somewhere about the field of view of a radius of 1.5 to 3 m. On the edge, the
/// pose is one whose distance is exactly the radius in floating point: (0.6 r, 0.8 r) for
/// r = 0.625, or (+-r, 0), (0, +-r) for r = 0.5 or 1. A radius of at most 1 m there keeps
/// the edge in view for the squared distance compared with the radius itself (r^2 <= r),
/// so that only the boundary left out fails the case: the mistakes, both answering false,
/// would not be told apart beyond 1 m.
fn view(rng: &mut Rng, place: Place) -> Call {
    let sign = |rng: &mut Rng| if rng.chance(0.5) { 1.0 } else { -1.0 };
    let theta = rng.uniform_in(-PI, PI);
    let (radius, x, y) = match place {
        Place::OnTheEdge => {
            let radius = [0.625, 0.5, 1.0][(rng.uniform() * 3.0) as usize];
            let (x, y) = if radius == 0.625 {
                (0.375, 0.5)
            } else if rng.chance(0.5) {
                (radius, 0.0)
            } else {
                (0.0, radius)
            };
            (radius, sign(rng) * x, sign(rng) * y)
        }
        _ => {
            let radius = rng.uniform_in(1.5, 3.0);
            let distance = match place {
                Place::JustInside => radius - rng.uniform_in(0.001, 0.02),
                Place::JustOutside => radius + rng.uniform_in(0.001, 0.02),
                Place::BeyondRootRadius => rng.uniform_in(radius.sqrt() + 0.05, radius - 0.05),
                Place::Under => rng.uniform_in(0.0, 0.3),
                // In the square's corner: |x|, |y| <= radius, distance > radius.
                _ => radius * rng.uniform_in(1.1, 1.35),
            };
            let bearing = match place {
                Place::Corner => PI / 4.0 + rng.uniform_in(-0.1, 0.1),
                _ => rng.uniform_in(0.0, PI / 2.0),
            };
            (
                radius,
                sign(rng) * distance * libm::cos(bearing),
                sign(rng) * distance * libm::sin(bearing),
            )
        }
    };
    Call::InFieldOfView {
        z: [x, y, theta],
        radius,
    }
}

// ---- the prediction ----

#[derive(Clone, Copy)]
enum Motion {
    Ahead,
    Spin,
    AcrossPi,
    Still,
    Long,
}

/// Process noise constants of 0.01 to 0.3.
fn process(rng: &mut Rng) -> (f64, f64) {
    (rng.uniform_in(0.01, 0.3), rng.uniform_in(0.01, 0.3))
}

/// A covariance as a filter has it: a few steps of prediction from a small start.
fn belief_covariance(rng: &mut Rng, steps: usize) -> Matrix3<f64> {
    let mut sigma = Matrix3::from_diagonal(&Vector3::new(
        rng.uniform_in(1e-4, 1e-2),
        rng.uniform_in(1e-4, 1e-2),
        rng.uniform_in(1e-4, 1e-2),
    ));
    let (process_xy, process_theta) = process(rng);
    let settings = Settings {
        process_xy,
        process_theta,
        ..Settings::default()
    };
    for _ in 0..steps {
        let mu = Vector3::new(0.0, 0.0, rng.uniform_in(-PI, PI));
        let u = Vector3::new(
            rng.uniform_in(0.0, 0.3),
            rng.uniform_in(-0.05, 0.05),
            rng.uniform_in(-0.3, 0.3),
        );
        sigma = predict(&mu, &sigma, &u, &settings).1;
    }
    sigma
}

/// A prediction from a belief whose heading is 0.2 to 1 rad off the odometry's (the
/// filter has corrected it), with the odometry moving as `motion` says.
fn prediction(rng: &mut Rng, motion: Motion) -> Call {
    let odom_prev = [
        rng.uniform_in(-3.0, 3.0),
        rng.uniform_in(-3.0, 3.0),
        rng.uniform_in(-PI, PI),
    ];
    let (ahead, turn) = match motion {
        Motion::Ahead => (rng.uniform_in(0.05, 0.3), 0.0),
        Motion::Spin => (
            0.0,
            rng.uniform_in(0.1, 0.8) * if rng.chance(0.5) { 1.0 } else { -1.0 },
        ),
        Motion::AcrossPi => (rng.uniform_in(0.05, 0.2), rng.uniform_in(0.2, 0.5)),
        Motion::Still => (0.0, 0.0),
        Motion::Long => (rng.uniform_in(0.5, 1.5), rng.uniform_in(-0.5, 0.5)),
    };
    let (sin, cos) = libm::sincos(odom_prev[2] + turn / 2.0);
    let odom = [
        odom_prev[0] + ahead * cos,
        odom_prev[1] + ahead * sin,
        crate::angle::wrap(odom_prev[2] + turn),
    ];
    let off = rng.uniform_in(0.2, 1.0) * if rng.chance(0.5) { 1.0 } else { -1.0 };
    let mu_theta = match motion {
        // Close enough to pi that the turn crosses it.
        Motion::AcrossPi => PI - rng.uniform_in(0.01, 0.15),
        _ => crate::angle::wrap(odom_prev[2] + off),
    };
    let mu = [
        odom_prev[0] + rng.uniform_in(-0.3, 0.3),
        odom_prev[1] + rng.uniform_in(-0.3, 0.3),
        mu_theta,
    ];
    let steps = if matches!(motion, Motion::Long) {
        30
    } else {
        5
    };
    let (k_xy, k_theta) = process(rng);
    Call::Predict {
        mu,
        sigma: rows(&belief_covariance(rng, steps)),
        odom_prev,
        odom,
        k_xy,
        k_theta,
    }
}

// ---- readings and the belief they meet ----

#[derive(Clone, Copy)]
enum Reading {
    /// Within about a standard deviation.
    Close,
    /// Many standard deviations away.
    Far,
    /// The belief's heading near +pi, the reading's across it.
    AcrossPi,
    /// Q much larger than Sigma_bar.
    Noisy,
}

type Meeting = ([f64; 3], [[f64; 3]; 3], [f64; 3], [[f64; 3]; 3]);

fn reading(rng: &mut Rng, kind: Reading) -> Meeting {
    let sigma = belief_covariance(rng, 5);
    let sigma_xy = match kind {
        Reading::Noisy => rng.uniform_in(0.3, 0.6),
        _ => rng.uniform_in(0.02, 0.12),
    };
    let sigma_theta = 2.5 * sigma_xy;
    let q = Matrix3::from_diagonal(&Vector3::new(
        sigma_xy * sigma_xy,
        sigma_xy * sigma_xy,
        sigma_theta * sigma_theta,
    ));
    let theta = match kind {
        Reading::AcrossPi => PI - rng.uniform_in(0.01, 0.05),
        _ => rng.uniform_in(-PI, PI),
    };
    let mu = [rng.uniform_in(-2.0, 2.0), rng.uniform_in(-2.0, 2.0), theta];
    let spread = (sigma + q).diagonal().map(f64::sqrt);
    let scale = match kind {
        Reading::Far => rng.uniform_in(4.0, 8.0),
        _ => rng.uniform_in(0.3, 1.2),
    };
    let mut offset =
        Vector3::from_fn(|i, _| spread[i] * scale * if rng.chance(0.5) { 1.0 } else { -1.0 });
    if let Reading::AcrossPi = kind {
        // Across +pi: the reading's heading is past it, wrapped to near -pi.
        offset.z = rng.uniform_in(0.06, 0.15);
    }
    let z = [
        mu[0] + offset.x,
        mu[1] + offset.y,
        crate::angle::wrap(mu[2] + offset.z),
    ];
    (mu, rows(&sigma), z, rows(&q))
}
