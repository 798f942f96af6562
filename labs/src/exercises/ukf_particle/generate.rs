//! Test cases generated from a seed, so that every student can have a variant of their
//! own. Each function's cases cycle through its scenarios, the situations where classic
//! mistakes show: a straight drive (omega = 0, where the arc's formula divides by zero),
//! driving backwards while turning (the absolute values in the control noise), headings
//! and bearings across +-pi (angles averaged as numbers, residuals not wrapped), sigma
//! points with alpha below 1 (the covariance weight's 1 - alpha^2 + beta), clouds of
//! uneven weights, and effective sizes either side of half the cloud.

use super::Case;
use super::contract::{Answer, Call, Mat2, Mat3, Vec2, Vec3};
use crate::grading::Contract;
use crate::grading::{self, scenario_cases};
use crate::rng::Rng;
use std::f64::consts::PI;

/// `per_function` cases of every student function, from `seed`.
pub fn generate(seed: u64, per_function: usize) -> Vec<Case> {
    scenario_cases(seed, per_function, &SCENARIOS)
}

type Scenario = grading::Scenario<Call>;

const SCENARIOS: [(&str, &[Scenario]); 12] = [
    (
        "motion",
        &[
            ("an arc", |rng| motion(rng, Drive::Arc)),
            ("a straight drive, omega = 0", |rng| {
                motion(rng, Drive::Straight)
            }),
            ("a turn across +-pi", |rng| motion(rng, Drive::AcrossPi)),
            ("a turn on the spot", |rng| motion(rng, Drive::Spin)),
        ],
    ),
    (
        "process_noise",
        &[
            ("an arc", |rng| process_noise(rng, Drive::Arc)),
            ("a straight drive, omega = 0", |rng| {
                process_noise(rng, Drive::Straight)
            }),
            ("driving backwards while turning", |rng| {
                process_noise(rng, Drive::Backwards)
            }),
        ],
    ),
    (
        "sigma_points",
        &[
            ("a correlated covariance, alpha below 1", |rng| {
                let alpha = rng_alpha(rng);
                sigma_points(rng, alpha)
            }),
            ("alpha = 1, kappa = 1", |rng| {
                let mut call = sigma_points(rng, 1.0);
                if let Call::SigmaPoints { kappa, .. } = &mut call {
                    *kappa = 1.0;
                }
                call
            }),
        ],
    ),
    (
        "ukf_predict",
        &[
            ("an arc from a heading near +-pi", |rng| {
                ukf_predict(rng, Drive::AcrossPi)
            }),
            ("an arc", |rng| ukf_predict(rng, Drive::Arc)),
            ("a straight drive, omega = 0", |rng| {
                ukf_predict(rng, Drive::Straight)
            }),
        ],
    ),
    (
        "ukf_update",
        &[
            ("a post behind the robot, its bearing near +-pi", |rng| {
                ukf_update(rng, Post::Behind)
            }),
            ("a post ahead", |rng| ukf_update(rng, Post::Ahead)),
            ("a reading far from the expected one", |rng| {
                ukf_update(rng, Post::Far)
            }),
            (
                "a post ahead, the update carrying the heading across +-pi",
                |rng| updated_across_pi(rng),
            ),
        ],
    ),
    (
        "sample_motion",
        &[
            ("a cloud driving an arc", |rng| {
                sample_motion(rng, Drive::Arc)
            }),
            ("a cloud driving straight, omega = 0", |rng| {
                sample_motion(rng, Drive::Straight)
            }),
            ("a cloud driving backwards while turning", |rng| {
                sample_motion(rng, Drive::Backwards)
            }),
            ("a cloud turning across +-pi", |rng| {
                sample_motion(rng, Drive::AcrossPi)
            }),
        ],
    ),
    (
        "particle_weights",
        &[
            ("uneven weights, a post behind the cloud", |rng| {
                particle_weights(rng, Post::Behind)
            }),
            ("uneven weights, a post ahead", |rng| {
                particle_weights(rng, Post::Ahead)
            }),
        ],
    ),
    (
        "needs_resampling",
        &[
            ("an even cloud", |rng| needs_resampling(rng, Spread::Even)),
            ("a cloud worth a little over half its count", |rng| {
                needs_resampling(rng, Spread::JustAbove)
            }),
            ("a cloud worth a little under half its count", |rng| {
                needs_resampling(rng, Spread::JustBelow)
            }),
            ("one particle with most of the weight", |rng| {
                needs_resampling(rng, Spread::OneHeavy)
            }),
        ],
    ),
    (
        "low_variance_resample",
        &[
            ("uneven weights", |rng| low_variance(rng, Spread::Uneven)),
            ("one particle with most of the weight", |rng| {
                low_variance(rng, Spread::OneHeavy)
            }),
            ("an offset near 1", |rng| {
                let mut call = low_variance(rng, Spread::Uneven);
                if let Call::LowVarianceResample { r, .. } = &mut call {
                    *r = rng.uniform_in(0.9, 1.0);
                }
                call
            }),
        ],
    ),
    (
        "particle_estimate",
        &[
            ("a cloud across +-pi", |rng| particle_estimate(rng, true)),
            ("uneven weights", |rng| particle_estimate(rng, false)),
        ],
    ),
    (
        "measurement_noise",
        &[
            ("the residuals of a camera", |rng| {
                measurement_noise(rng, 40)
            }),
            ("a few residuals, off centre", |rng| {
                measurement_noise(rng, 6)
            }),
        ],
    ),
    (
        "learn_alphas",
        &[
            (
                "a robot's commands and the motion its truth implies",
                |rng| learn_alphas(rng, false),
            ),
            (
                "errors that a free fit would give a negative alpha",
                |rng| learn_alphas(rng, true),
            ),
        ],
    ),
];

// ---- the motion ----

#[derive(Clone, Copy)]
enum Drive {
    Arc,
    Straight,
    /// Turning across +-pi, to end just past it.
    AcrossPi,
    Spin,
    Backwards,
}

/// A pose in a room of 5 x 10 m, heading anywhere.
fn any_pose(rng: &mut Rng) -> Vec3 {
    let heading = rng.uniform_in(-PI, PI);
    pose(rng, heading)
}

/// A pose in a room of 5 x 10 m.
fn pose(rng: &mut Rng, heading: f64) -> Vec3 {
    [rng.uniform_in(0.0, 5.0), rng.uniform_in(0.0, 10.0), heading]
}

/// A pose and a command of the kind `drive`, over a step of 0.1 to 1 s: long enough that
/// a wrong arc shows.
fn drive(rng: &mut Rng, drive: Drive) -> (Vec3, Vec2, f64) {
    let dt = rng.uniform_in(0.1, 1.0);
    let v = rng.uniform_in(0.1, 0.5);
    let omega = rng.uniform_in(0.3, 1.5) * if rng.chance(0.5) { 1.0 } else { -1.0 };
    match drive {
        Drive::Arc => (any_pose(rng), [v, omega], dt),
        Drive::Straight => (any_pose(rng), [v, 0.0], dt),
        Drive::Spin => (any_pose(rng), [0.0, omega], dt),
        Drive::Backwards => (any_pose(rng), [-v, omega], dt),
        Drive::AcrossPi => {
            // Ending just past +pi turning left (or -pi turning right), from just before
            // it: the step crosses it, and a belief's points about the end straddle it.
            let past = rng.uniform_in(0.003, 0.025) * omega.signum();
            let heading = crate::angle::wrap(omega.signum() * PI + past - omega * dt);
            (pose(rng, heading), [v, omega], dt)
        }
    }
}

fn motion(rng: &mut Rng, kind: Drive) -> Call {
    let (pose, u, dt) = drive(rng, kind);
    Call::Motion { pose, u, dt }
}

/// alpha1..alpha4 round those learned from data set 6: 0.05 to 0.3 for v's own, 0.01 to 0.1
/// for omega's into v, 0.2 to 1 for v's into omega, 0.05 to 0.4 for omega's own.
fn alphas(rng: &mut Rng) -> [f64; 4] {
    [
        rng.uniform_in(0.05, 0.3),
        rng.uniform_in(0.01, 0.1),
        rng.uniform_in(0.2, 1.0),
        rng.uniform_in(0.05, 0.4),
    ]
}

fn process_noise(rng: &mut Rng, kind: Drive) -> Call {
    let (mu, u, dt) = drive(rng, kind);
    Call::ProcessNoise {
        mu,
        u,
        dt,
        alphas: alphas(rng),
    }
}

// ---- the unscented filter ----

/// alpha of 0.3 to 0.9.
fn rng_alpha(rng: &mut Rng) -> f64 {
    rng.uniform_in(0.3, 0.9)
}

/// A covariance of a pose with correlations: A A^T + a little of the identity, standard
/// deviations of about `scale` metres and radians.
fn covariance(rng: &mut Rng, scale: f64) -> Mat3 {
    let a: [[f64; 3]; 3] =
        std::array::from_fn(|_| std::array::from_fn(|_| rng.uniform_in(-scale, scale)));
    let mut sigma = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            sigma[i][j] = (0..3).map(|k| a[i][k] * a[j][k]).sum::<f64>();
        }
        sigma[i][i] += 0.01 * scale * scale;
    }
    sigma
}

fn sigma_points(rng: &mut Rng, alpha: f64) -> Call {
    Call::SigmaPoints {
        mu: any_pose(rng),
        sigma: covariance(rng, 0.3),
        alpha,
        beta: 2.0,
        kappa: rng.uniform_in(0.0, 2.0),
    }
}

/// The noise a step adds, diagonal, of a few centimetres and degrees.
fn step_noise(rng: &mut Rng) -> Mat3 {
    let sd = [
        rng.uniform_in(0.005, 0.05),
        rng.uniform_in(0.005, 0.05),
        rng.uniform_in(0.005, 0.05),
    ];
    std::array::from_fn(|i| std::array::from_fn(|j| if i == j { sd[i] * sd[i] } else { 0.0 }))
}

fn ukf_predict(rng: &mut Rng, kind: Drive) -> Call {
    let (mu, u, dt) = drive(rng, kind);
    Call::UkfPredict {
        mu,
        sigma: covariance(rng, 0.15),
        u,
        dt,
        r: step_noise(rng),
    }
}

#[derive(Clone, Copy)]
enum Post {
    /// Behind the robot: the expected bearing near +-pi and the reading across it.
    Behind,
    Ahead,
    /// Ahead, read a metre and a half radian off.
    Far,
}

/// The camera's noise round data set 6's: 5 to 15 cm in range, 1 to 5 degrees in
/// bearing.
fn camera_noise(rng: &mut Rng) -> Mat2 {
    let (range, bearing) = (rng.uniform_in(0.05, 0.15), rng.uniform_in(0.017, 0.087));
    [[range * range, 0.0], [0.0, bearing * bearing]]
}

/// A post 1 to 4 m from `pose` at the side `post` says, and the reading of it with the
/// camera's noise (`q`'s standard deviations), or far off.
fn reading(rng: &mut Rng, pose: &Vec3, post: Post, q: &Mat2) -> (Vec2, Vec2) {
    let range = rng.uniform_in(1.0, 4.0);
    // Behind: the expected bearing just one side of +-pi and the reading just the other.
    let side = if rng.chance(0.5) { 1.0 } else { -1.0 };
    let bearing = match post {
        Post::Behind => side * (PI - rng.uniform_in(0.005, 0.03)),
        Post::Ahead | Post::Far => rng.uniform_in(-0.8, 0.8),
    };
    let direction = pose[2] + bearing;
    let landmark = [
        pose[0] + range * libm::cos(direction),
        pose[1] + range * libm::sin(direction),
    ];
    let noisy_range = q[0][0].sqrt() * rng.standard_normal();
    let (off_range, off_bearing) = match post {
        Post::Far => (1.5, 0.5),
        Post::Behind => (
            noisy_range,
            side * (PI - side * bearing + rng.uniform_in(0.005, 0.03)),
        ),
        Post::Ahead => (noisy_range, q[1][1].sqrt() * rng.standard_normal()),
    };
    let z = [range + off_range, crate::angle::wrap(bearing + off_bearing)];
    (z, landmark)
}

fn ukf_update(rng: &mut Rng, post: Post) -> Call {
    let mu_bar = any_pose(rng);
    ukf_update_from(rng, mu_bar, post)
}

/// An update whose heading starts a hair from +-pi and ends on the other side of it:
/// drawn until the reference's correction carries it across (half the draws do).
fn updated_across_pi(rng: &mut Rng) -> Call {
    loop {
        let side = if rng.chance(0.5) { 1.0 } else { -1.0 };
        let heading = side * (PI - rng.uniform_in(1e-5, 1e-3));
        let mu_bar = pose(rng, heading);
        let call = ukf_update_from(rng, mu_bar, Post::Ahead);
        if let Ok(Answer::Corrected(updated)) = call.reference()
            && updated.mu[2].signum() != side
        {
            return call;
        }
    }
}

/// An update of a belief about `mu_bar` by a reading of a post where `post` says.
fn ukf_update_from(rng: &mut Rng, mu_bar: Vec3, post: Post) -> Call {
    let q = camera_noise(rng);
    let (z, landmark) = reading(rng, &mu_bar, post, &q);
    Call::UkfUpdate {
        mu_bar,
        sigma_bar: covariance(rng, 0.1),
        z,
        landmark,
        q,
    }
}

// ---- the particle filter ----

/// A cloud of 8 to 20 particles about a pose: 10 to 30 cm and 0.05 to 0.2 rad apart,
/// their headings wrapped.
fn particles(rng: &mut Rng, centre: &Vec3) -> Vec<Vec3> {
    let n = 8 + (rng.uniform() * 13.0) as usize;
    let (spread, turn) = (rng.uniform_in(0.1, 0.3), rng.uniform_in(0.05, 0.2));
    (0..n)
        .map(|_| {
            [
                centre[0] + spread * rng.standard_normal(),
                centre[1] + spread * rng.standard_normal(),
                crate::angle::wrap(centre[2] + turn * rng.standard_normal()),
            ]
        })
        .collect()
}

/// `n` uneven weights that sum to 1.
fn uneven(rng: &mut Rng, n: usize) -> Vec<f64> {
    normalised((0..n).map(|_| rng.uniform_in(0.1, 1.0)).collect())
}

fn normalised(weights: Vec<f64>) -> Vec<f64> {
    let total: f64 = weights.iter().sum();
    weights.into_iter().map(|w| w / total).collect()
}

fn sample_motion(rng: &mut Rng, kind: Drive) -> Call {
    let (centre, u, dt) = drive(rng, kind);
    let particles = particles(rng, &centre);
    let normals = particles
        .iter()
        .map(|_| [rng.standard_normal(), rng.standard_normal()])
        .collect();
    Call::SampleMotion {
        particles,
        u,
        dt,
        alphas: alphas(rng),
        normals,
    }
}

fn particle_weights(rng: &mut Rng, post: Post) -> Call {
    let centre = any_pose(rng);
    let particles = particles(rng, &centre);
    let weights = uneven(rng, particles.len());
    // A camera a few times noisier than data set 6's, so that the cloud's likelihoods
    // stay within a few orders of magnitude of one another.
    let q = camera_noise(rng).map(|row| row.map(|v| 9.0 * v));
    let (z, landmark) = reading(rng, &centre, post, &q);
    Call::ParticleWeights {
        particles,
        weights,
        z,
        landmark,
        q,
    }
}

#[derive(Clone, Copy)]
enum Spread {
    Even,
    Uneven,
    /// The effective size 5 % to 20 % above half the count.
    JustAbove,
    /// 5 % to 20 % below it.
    JustBelow,
    OneHeavy,
}

/// Weights of 10 to 40 particles spread as `spread` says.
fn weights(rng: &mut Rng, spread: Spread) -> Vec<f64> {
    let n = 10 + (rng.uniform() * 31.0) as usize;
    match spread {
        Spread::Even => vec![1.0 / n as f64; n],
        Spread::Uneven => uneven(rng, n),
        Spread::OneHeavy => {
            let mut w: Vec<f64> = (0..n).map(|_| rng.uniform_in(0.01, 0.05)).collect();
            w[rng.index(n)] = 1.0;
            normalised(w)
        }
        Spread::JustAbove | Spread::JustBelow => {
            let share = match spread {
                Spread::JustAbove => 0.5 * rng.uniform_in(1.05, 1.2),
                _ => 0.5 * rng.uniform_in(0.8, 0.95),
            };
            let mut w = weights_with_size(n, share * n as f64);
            // Shuffled, so that the heavy one is not always first.
            let heavy = rng.index(n);
            w.swap(0, heavy);
            w
        }
    }
}

/// n weights whose effective size is `size` (1 < size < n): one weight a and the rest b,
/// with a + (n - 1) b = 1 and a^2 + (n - 1) b^2 = 1 / size.
fn weights_with_size(n: usize, size: f64) -> Vec<f64> {
    let m = (n - 1) as f64;
    // b solves (1 - m b)^2 + m b^2 = 1/size: (m^2 + m) b^2 - 2 m b + 1 - 1/size = 0.
    let (a2, b1, c0) = (m * m + m, -2.0 * m, 1.0 - 1.0 / size);
    let b = (-b1 - libm::sqrt(b1 * b1 - 4.0 * a2 * c0)) / (2.0 * a2);
    let mut w = vec![b; n];
    w[0] = 1.0 - m * b;
    w
}

fn needs_resampling(rng: &mut Rng, spread: Spread) -> Call {
    Call::NeedsResampling {
        weights: weights(rng, spread),
    }
}

fn low_variance(rng: &mut Rng, spread: Spread) -> Call {
    Call::LowVarianceResample {
        weights: weights(rng, spread),
        r: rng.uniform(),
    }
}

fn particle_estimate(rng: &mut Rng, across_pi: bool) -> Call {
    let heading = if across_pi {
        PI + rng.uniform_in(-0.05, 0.05)
    } else {
        rng.uniform_in(-2.5, 2.5)
    };
    let centre = pose(rng, crate::angle::wrap(heading));
    let particles = particles(rng, &centre);
    let weights = uneven(rng, particles.len());
    Call::ParticleEstimate { particles, weights }
}

// ---- the noise learned ----

/// `n` residuals of a camera (range, bearing wrapped), correlated a little, and not quite
/// centred (the ML estimate of a zero-mean model is not the sample covariance).
fn measurement_noise(rng: &mut Rng, n: usize) -> Call {
    let (sd_range, sd_bearing) = (rng.uniform_in(0.03, 0.15), rng.uniform_in(0.01, 0.08));
    let (bias_range, bias_bearing) = (rng.uniform_in(-0.05, 0.05), rng.uniform_in(-0.02, 0.02));
    let rho = rng.uniform_in(-0.5, 0.5);
    let residuals = (0..n)
        .map(|_| {
            let (a, b) = (rng.standard_normal(), rng.standard_normal());
            [
                bias_range + sd_range * a,
                bias_bearing + sd_bearing * (rho * a + libm::sqrt(1.0 - rho * rho) * b),
            ]
        })
        .collect();
    Call::MeasurementNoise { residuals }
}

/// 40 to 80 commands, a fifth of them standing still, and the motion the truth implies:
/// each command plus a normal error of the alphas' standard deviations; or (`negative`)
/// errors of exactly 0.3 |v| - 0.1 |omega| (the speed's) and 0.5 |omega| - 0.2 |v| (the
/// turn's), times sqrt(2 / pi), which a fit free of signs matches with a negative alpha.
fn learn_alphas(rng: &mut Rng, negative: bool) -> Call {
    let n = 40 + (rng.uniform() * 41.0) as usize;
    let true_alphas = alphas(rng);
    let scale = (2.0 / PI).sqrt();
    let (mut commanded, mut implied) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for _ in 0..n {
        let u = if rng.chance(0.2) {
            [0.0, 0.0]
        } else if negative {
            [rng.uniform_in(0.1, 0.3), rng.uniform_in(-0.2, 0.2)]
        } else {
            [rng.uniform_in(-0.1, 0.4), rng.uniform_in(-1.0, 1.0)]
        };
        let sign = |rng: &mut Rng| if rng.chance(0.5) { 1.0 } else { -1.0 };
        let (v, w) = (u[0].abs(), u[1].abs());
        let error = if negative {
            let moving = v > 0.0 || w > 0.0;
            let (ev, ew) = (0.3 * v - 0.1 * w, (0.5 * w - 0.2 * v).max(0.0));
            [
                sign(rng) * scale * ev * f64::from(u8::from(moving)),
                sign(rng) * scale * ew,
            ]
        } else {
            let [a1, a2, a3, a4] = true_alphas;
            [
                (a1 * v + a2 * w) * rng.standard_normal(),
                (a3 * v + a4 * w) * rng.standard_normal(),
            ]
        };
        commanded.push(u);
        implied.push([u[0] + error[0], u[1] + error[1]]);
    }
    Call::LearnAlphas { commanded, implied }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mrclam::particle::effective_size;

    /// The scenarios either side of half the cloud are on their sides.
    #[test]
    fn effective_sizes_fall_where_the_scenarios_say() {
        let mut rng = Rng::new(3);
        for _ in 0..500 {
            for (spread, above) in [(Spread::JustAbove, true), (Spread::JustBelow, false)] {
                let w = weights(&mut rng, spread);
                let half = 0.5 * w.len() as f64;
                assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
                assert_eq!(effective_size(&w) > half, above, "{w:?}");
            }
        }
        let w = weights_with_size(20, 7.5);
        assert!((effective_size(&w) - 7.5).abs() < 1e-9);
    }
}
