//! Hints for the classic mistakes of the exercise on the unscented Kalman filter and the
//! particle filter: when a failing output is exactly what a mistake gives, say which.
//! Each check recomputes the answer with the mistake made, from the parts of the model in
//! [`crate::mrclam`] (the sigma points and their weights, the weighted means and
//! covariances, the arc, the likelihood) put together the wrong way, and compares the
//! student's output with it.

use super::contract::{
    Answer, Call, Corrected, Estimate, Prediction, SigmaPoints, Vec2, Vec3, belief, cloud, control,
    control_noise, spread,
};
use crate::angle::{difference, wrap};
use crate::grading::{
    Common, Contract, Hint, Mismatch, Mistake, form_hint, holds_non_finite, matrix_of, rows,
    the_only,
};
use crate::mrclam::belief::Belief;
use crate::mrclam::motion::{self, jacobian_control};
use crate::mrclam::particle::{self, estimate, weigh};
use crate::mrclam::ukf::{self, HEADING, POINTS, SPREAD};
use crate::mrclam::{learn, sensor};
use nalgebra::{Matrix2, Matrix3, SVector, Vector2, Vector3};
use serde_json::Value;

/// A classic mistake of the exercise, named uniquely across the exercises.
#[derive(Clone, Copy, Debug, PartialEq, Eq, strum::IntoStaticStr, strum::VariantArray)]
#[strum(serialize_all = "snake_case")]
pub enum HintKind {
    /// v/omega (...) at omega = 0.
    StraightLineDividedByZero,
    ArcHeadingNotWrapped,
    /// alpha1 v + alpha2 omega without the absolute values.
    ControlNoiseSigns,
    /// The standard deviations where the variances belong, or the other way round.
    ControlVarianceAsDeviation,
    /// n_v drawn into omega and n_omega into v.
    ControlNormalsSwapped,
    /// wc[0] = wm[0]: without 1 - alpha^2 + beta.
    SigmaCovarianceWeight,
    /// The Cholesky factor of Sigma, not of (n + lambda) Sigma.
    SigmaRootUnscaled,
    /// The columns of the upper factor (MATLAB's chol(A) without 'lower').
    SigmaRootUpper,
    /// sum w theta: a heading or bearing averaged as a number.
    AnglesAveragedAsNumbers,
    /// The sigma points' deviations of angle from the mean not wrapped.
    SigmaDeviationsNotWrapped,
    /// R (or Q) not added to the points' covariance.
    UnscentedNoiseLeftOut,
    /// z - z_hat with its bearing not wrapped.
    UkfInnovationNotWrapped,
    /// mu_bar + K nu with its heading not wrapped.
    UpdatedHeadingNotWrapped,
    /// The likelihood's bearing residual not wrapped.
    LikelihoodBearingNotWrapped,
    /// w p(z | x) returned without dividing by their sum.
    ParticleWeightsNotNormalised,
    /// The likelihood alone: the weights before the reading dropped.
    PriorWeightsDropped,
    /// Resampling whatever the effective size.
    ResamplesEveryStep,
    /// The comb at r + m/N rather than (r + m)/N.
    ResampleOffsetNotScaled,
    /// Indices counted from 1.
    ResampleIndicesFromOne,
    /// The cloud's mean and covariance unweighted.
    EstimateWeightsIgnored,
    /// Divided by n - 1.
    NoiseSampleCovariance,
    /// The residuals' mean taken off first.
    NoiseResidualsCentred,
    /// The fit of |error| without sqrt(pi/2).
    AlphasWithoutScale,
    /// The fit of the signed errors.
    AlphasSignedErrors,
    /// A negative coefficient of the free fit kept.
    AlphasNegativeKept,
    #[strum(serialize = "ukf_particle_keeps_state")]
    KeepsState,
}

impl Mistake for HintKind {
    fn text(self) -> &'static str {
        match self {
            HintKind::StraightLineDividedByZero => {
                "Driving straight (omega = 0) gives NaN or Infinity: the arc's v/omega \
                 (-sin theta + sin(theta + omega dt)) divides zero by zero there. Its limit \
                 as omega -> 0 is the straight line, x' = x + v dt cos theta, y' = y + v dt \
                 sin theta: take that branch when omega is 0 (and in the arc's derivatives \
                 their limits)."
            }
            HintKind::ArcHeadingNotWrapped => {
                "The new heading lies outside [-pi, pi): wrap theta + omega dt, for example \
                 as a - 2 pi floor((a + pi) / (2 pi)), minding that JavaScript's % keeps \
                 the sign of its left operand."
            }
            HintKind::ControlNoiseSigns => {
                "Driving backwards or turning right gave the noise another size: the \
                 standard deviations are alpha1 |v| + alpha2 |omega| and alpha3 |v| + \
                 alpha4 |omega|, with the absolute values, so that a negative speed does not \
                 cancel the turn's share of the noise."
            }
            HintKind::ControlVarianceAsDeviation => {
                "A standard deviation and a variance are mixed up: M = diag((alpha1 |v| + \
                 alpha2 |omega|)^2, (alpha3 |v| + alpha4 |omega|)^2) holds variances, the \
                 squares; a particle's drawn control is v + (alpha1 |v| + alpha2 |omega|) \
                 n_v, the standard deviation times the normal draw, not squared."
            }
            HintKind::ControlNormalsSwapped => {
                "The two draws of a particle are used the other way round: normals[i][0] \
                 perturbs v and normals[i][1] perturbs omega."
            }
            HintKind::SigmaCovarianceWeight => {
                "The first covariance weight is the first mean weight: wc[0] = lambda / (n \
                 + lambda) + (1 - alpha^2 + beta). The added 1 - alpha^2 + beta (2 for \
                 alpha = 1, beta = 2) weighs the spread about the centre point, and leaving \
                 it out makes the filter too confident."
            }
            HintKind::SigmaRootUnscaled => {
                "The points lie the square root of Sigma from the mean, not of (n + lambda) \
                 Sigma: with lambda = alpha^2 (n + kappa) - n, take the Cholesky factor of \
                 (n + lambda) Sigma (or sqrt(n + lambda) times that of Sigma), so that the \
                 weighted points have Sigma as their covariance."
            }
            HintKind::SigmaRootUpper => {
                "The points follow the rows of the square root where its columns belong: \
                 take the columns of the lower Cholesky factor L, L L^T = (n + lambda) \
                 Sigma (MATLAB's chol(A, 'lower'), NumPy's np.linalg.cholesky). MATLAB's \
                 chol(A) gives the upper factor, whose columns are other points."
            }
            HintKind::AnglesAveragedAsNumbers => {
                "An angle was averaged as a number: points or particles either side of +-pi \
                 (3.1 and -3.1) average to 0, the opposite direction. Average the sines and \
                 cosines, atan2(sum w sin(a), sum w cos(a)), for the heading and the \
                 bearing, and wrap the deviations from that mean."
            }
            HintKind::SigmaDeviationsNotWrapped => {
                "The covariance holds a deviation of angle that was not wrapped: a point at \
                 3.1 rad is 0.08 rad from a mean at -3.1, not 6.2. Wrap every deviation of a \
                 heading or bearing from its mean before the outer products."
            }
            HintKind::UnscentedNoiseLeftOut => {
                "The noise is missing from the unscented covariance: the prediction's is \
                 sum wc (X - mu_bar)(X - mu_bar)^T + R, the reading's S = sum wc (Z - \
                 z_hat)(Z - z_hat)^T + Q."
            }
            HintKind::UkfInnovationNotWrapped => {
                "The innovation's bearing was not wrapped: z - z_hat near +-pi is a small \
                 angle, not almost 2 pi. Wrap it before the gain moves the mean by it."
            }
            HintKind::UpdatedHeadingNotWrapped => {
                "The updated heading lies outside [-pi, pi): the correction K nu can carry \
                 mu_bar's heading across +-pi, so wrap the heading of mu_bar + K nu."
            }
            HintKind::LikelihoodBearingNotWrapped => {
                "The likelihood treats a bearing residual near 2 pi as a huge error: a post \
                 behind the robot is read at +pi from one particle and -pi from another. \
                 Wrap the bearing's residual before exp(-nu^T Q^-1 nu / 2)."
            }
            HintKind::ParticleWeightsNotNormalised => {
                "The weights do not sum to one: after multiplying each by its likelihood, \
                 divide them by their sum (the effective size and the estimate assume it)."
            }
            HintKind::PriorWeightsDropped => {
                "The new weights forget the old ones: a reading multiplies each particle's \
                 weight by its likelihood, w_i p(z | x_i), since the weights carry every \
                 reading since the cloud was last resampled."
            }
            HintKind::ResamplesEveryStep => {
                "The cloud is resampled when it need not be: resample only when the \
                 effective sample size 1 / sum w^2 falls below half the particles. \
                 Resampling at every step throws away particles, and with them the cloud's \
                 spread, for nothing."
            }
            HintKind::ResampleOffsetNotScaled => {
                "The comb's teeth run past the end: with one draw r in [0, 1), the teeth \
                 stand at (r + m) / N for m = 0..N-1, all in [0, 1). At r + m/N the last \
                 teeth fall beyond the total weight and pick the last particle."
            }
            HintKind::ResampleIndicesFromOne => {
                "The indices count from 1: in JavaScript and Python the first particle is \
                 index 0."
            }
            HintKind::EstimateWeightsIgnored => {
                "The cloud's mean and covariance ignore the weights: mu = sum w_i x_i (the \
                 heading atan2(sum w sin, sum w cos)) and Sigma = sum w_i d_i d_i^T."
            }
            HintKind::NoiseSampleCovariance => {
                "Q was divided by n - 1: the maximum-likelihood estimate of a zero-mean \
                 noise's covariance is the mean outer product, sum r r^T / n."
            }
            HintKind::NoiseResidualsCentred => {
                "The residuals' mean was taken off first: the camera's noise is modelled \
                 with mean zero, so Q = sum r r^T / n about zero. A bias in the readings is \
                 part of the error the filter must allow for."
            }
            HintKind::AlphasWithoutScale => {
                "The alphas come out sqrt(2/pi) (0.8) of what they should: for a zero-mean \
                 normal error of standard deviation sd, the mean of |e| is sd sqrt(2/pi), so \
                 fit sqrt(pi/2) |v_implied - v| ~ a1 |v| + a2 |omega| (and alike for omega)."
            }
            HintKind::AlphasSignedErrors => {
                "The fit is of the signed errors, which average to zero whatever the noise: \
                 the alphas give a standard deviation, so fit its size, sqrt(pi/2) \
                 |v_implied - v| ~ a1 |v| + a2 |omega| and sqrt(pi/2) |omega_implied - omega| \
                 ~ a3 |v| + a4 |omega|."
            }
            HintKind::AlphasNegativeKept => {
                "An alpha came out negative: a standard deviation alpha1 |v| + alpha2 \
                 |omega| cannot grow smaller as the robot turns faster. Where the free \
                 least-squares fit gives a negative coefficient, fit each term alone (its \
                 coefficient 0 or more) and keep the one with the smaller squared error."
            }
            HintKind::KeepsState => {
                "The function answered a call differently when it was made again in a fresh \
                 copy of your file: it keeps something between calls, or draws random numbers \
                 of its own (Math.random, multinomial resampling). The harness gives every \
                 random number the filter uses: the normal draws and the comb's offset r."
            }
        }
    }
}

/// The classic mistake that explains a failing output, if one does (and only one).
pub fn diagnose(
    call: &Call,
    expected: &Answer,
    got: &Value,
    mismatches: &[Mismatch],
) -> Option<Hint> {
    if mismatches.is_empty() {
        return None;
    }
    if holds_non_finite(got) {
        return Some(if straight(call) {
            HintKind::StraightLineDividedByZero.hint()
        } else {
            Common::NotFinite.hint()
        });
    }
    let not_wrapped = match call {
        Call::UkfUpdate { .. } => HintKind::UpdatedHeadingNotWrapped,
        _ => HintKind::ArcHeadingNotWrapped,
    };
    if let Some(hint) = form_hint(call, expected, got, mismatches, None, not_wrapped.kind()) {
        return Some(hint);
    }
    the_only(
        mistakes(call, expected)
            .into_iter()
            .filter(|(_, alternative)| alternative != expected && call.answers(alternative, got))
            .map(|(kind, _)| kind),
    )
}

/// Whether the call drives a straight line: where v/omega divides by zero.
fn straight(call: &Call) -> bool {
    match call {
        Call::Motion { u, .. }
        | Call::ProcessNoise { u, .. }
        | Call::UkfPredict { u, .. }
        | Call::SampleMotion { u, .. } => u[1] == 0.0 && u[0] != 0.0,
        _ => false,
    }
}

/// What each classic mistake makes of this call's answer.
fn mistakes(call: &Call, expected: &Answer) -> Vec<(HintKind, Answer)> {
    match call {
        Call::Motion { .. } => Vec::new(),
        Call::ProcessNoise { mu, u, dt, alphas } => {
            let v = jacobian_control(&Vector3::from(*mu), control(u), *dt);
            let through = |[a, b]: [f64; 2]| {
                Answer::Matrix3(rows(&(v * Matrix2::new(a, 0.0, 0.0, b) * v.transpose())))
            };
            let [sd_v, sd_omega] = signed_sd(alphas, u);
            let [abs_v, abs_omega] = control_noise(alphas).control_sd(control(u));
            vec![
                (
                    HintKind::ControlNoiseSigns,
                    through([sd_v * sd_v, sd_omega * sd_omega]),
                ),
                (
                    HintKind::ControlVarianceAsDeviation,
                    through([abs_v, abs_omega]),
                ),
            ]
        }
        Call::SigmaPoints {
            mu,
            sigma,
            alpha,
            beta,
            kappa,
        } => {
            let spread = spread(*alpha, *beta, *kappa);
            let Answer::SigmaPoints(right) = expected else {
                return Vec::new();
            };
            let (wm, _) = spread.weights();
            let root = |scale: f64, upper: bool| {
                let Some(l) = (matrix_of(sigma) * scale).cholesky() else {
                    return Answer::SigmaPoints(right.clone());
                };
                let l = l.l();
                let factor = if upper { l.transpose() } else { l };
                let mu = Vector3::from(*mu);
                let mut x: Vec<Vec3> = vec![mu.into(); POINTS];
                for i in 0..3 {
                    x[1 + i] = (mu + factor.column(i)).into();
                    x[4 + i] = (mu - factor.column(i)).into();
                }
                Answer::SigmaPoints(SigmaPoints { x, ..right.clone() })
            };
            let scale = 3.0 + alpha * alpha * (3.0 + kappa) - 3.0;
            vec![
                (
                    HintKind::SigmaCovarianceWeight,
                    Answer::SigmaPoints(SigmaPoints {
                        wc: wm.to_vec(),
                        ..right.clone()
                    }),
                ),
                (HintKind::SigmaRootUnscaled, root(1.0, false)),
                (HintKind::SigmaRootUpper, root(scale, true)),
            ]
        }
        Call::UkfPredict {
            mu,
            sigma,
            u,
            dt,
            r,
        } => {
            let arc = |p: &Vector3<f64>| motion::step(p, control(u), *dt);
            let Some(points) = SPREAD.points(&belief(mu, sigma)) else {
                return Vec::new();
            };
            let moved = points.map(|p| arc(&p));
            let r = matrix_of(r);
            let predicted = |mean_angle, deviation_angle, noise: &Matrix3<f64>| {
                let (m, c) = unscented(&moved, mean_angle, deviation_angle);
                let c = c + noise;
                Answer::Prediction(Prediction {
                    mu_bar: m.into(),
                    sigma_bar: rows(&((c + c.transpose()) * 0.5)),
                })
            };
            vec![
                (
                    HintKind::AnglesAveragedAsNumbers,
                    predicted(None, HEADING, &r),
                ),
                (HintKind::AnglesAveragedAsNumbers, predicted(None, None, &r)),
                (
                    HintKind::SigmaDeviationsNotWrapped,
                    predicted(HEADING, None, &r),
                ),
                (
                    HintKind::UnscentedNoiseLeftOut,
                    predicted(HEADING, HEADING, &Matrix3::zeros()),
                ),
                (
                    HintKind::SigmaCovarianceWeight,
                    predicted_with_weights(&moved, &r),
                ),
            ]
        }
        Call::UkfUpdate {
            mu_bar,
            sigma_bar,
            z,
            landmark,
            q,
        } => {
            let prior = belief(mu_bar, sigma_bar);
            let q = matrix_of(q);
            let variant = |mistake: UpdateMistake| {
                corrected(
                    &prior,
                    &Vector2::from(*landmark),
                    &Vector2::from(*z),
                    &q,
                    mistake,
                )
            };
            [
                (
                    HintKind::AnglesAveragedAsNumbers,
                    UpdateMistake::BearingAveraged,
                ),
                (
                    HintKind::SigmaDeviationsNotWrapped,
                    UpdateMistake::DeviationsNotWrapped,
                ),
                (
                    HintKind::UkfInnovationNotWrapped,
                    UpdateMistake::InnovationNotWrapped,
                ),
                (HintKind::UnscentedNoiseLeftOut, UpdateMistake::NoQ),
            ]
            .into_iter()
            .filter_map(|(kind, mistake)| variant(mistake).map(|answer| (kind, answer)))
            .collect()
        }
        Call::SampleMotion {
            particles,
            u,
            dt,
            alphas,
            normals,
        } => {
            let [abs_v, abs_omega] = control_noise(alphas).control_sd(control(u));
            let sampled = |sd: [f64; 2], swapped: bool, wrapped: bool| {
                Answer::Particles(
                    particles
                        .iter()
                        .zip(normals)
                        .map(|(p, &[a, b])| {
                            let n = if swapped { [b, a] } else { [a, b] };
                            let moved = particle::moved(
                                &particle::Particle::new(Vector3::from(*p)),
                                control(u),
                                sd,
                                n,
                                *dt,
                            )
                            .pose;
                            let heading = if wrapped {
                                moved.z
                            } else {
                                p[2] + (u[1] + sd[1] * n[1]) * dt
                            };
                            [moved.x, moved.y, heading]
                        })
                        .collect(),
                )
            };
            vec![
                (
                    HintKind::ControlNoiseSigns,
                    sampled(signed_sd(alphas, u), false, true),
                ),
                (
                    HintKind::ControlVarianceAsDeviation,
                    sampled([abs_v * abs_v, abs_omega * abs_omega], false, true),
                ),
                (
                    HintKind::ControlNormalsSwapped,
                    sampled([abs_v, abs_omega], true, true),
                ),
            ]
        }
        Call::ParticleWeights {
            particles,
            weights,
            z,
            landmark,
            q,
        } => {
            let Some(q_inverse) = matrix_of(q).try_inverse() else {
                return Vec::new();
            };
            let (z, post) = (Vector2::from(*z), Vector2::from(*landmark));
            let likelihood = |pose: &Vec3, wrapped: bool| {
                let expected = sensor::expected(&Vector3::from(*pose), &post);
                let nu = if wrapped {
                    sensor::innovation(&z, &expected)
                } else {
                    z - expected
                };
                libm::exp(-0.5 * sensor::mahalanobis(&nu, &q_inverse))
            };
            let unnormalised = particles
                .iter()
                .zip(weights)
                .map(|(p, w)| w * likelihood(p, true))
                .collect();
            let normalised = |raw: Vec<f64>| {
                let total: f64 = raw.iter().sum();
                Answer::Weights(raw.iter().map(|w| w / total).collect())
            };
            let mut alone = vec![1.0; particles.len()];
            weigh(&cloud(particles), &mut alone, (&z, &post), &q_inverse);
            vec![
                (
                    HintKind::ParticleWeightsNotNormalised,
                    Answer::Weights(unnormalised),
                ),
                (HintKind::PriorWeightsDropped, Answer::Weights(alone)),
                (
                    HintKind::LikelihoodBearingNotWrapped,
                    normalised(
                        particles
                            .iter()
                            .zip(weights)
                            .map(|(p, w)| w * likelihood(p, false))
                            .collect(),
                    ),
                ),
            ]
        }
        Call::NeedsResampling { .. } => {
            vec![(HintKind::ResamplesEveryStep, Answer::Flag(true))]
        }
        Call::LowVarianceResample { weights, r } => {
            let n = weights.len();
            let Answer::Indices(right) = expected else {
                return Vec::new();
            };
            // The teeth at r + m/N: past the total weight they stay on the last particle.
            let mut teeth = Vec::with_capacity(n);
            let (mut i, mut cumulative) = (0, weights[0]);
            for m in 0..n {
                let tooth = r + m as f64 / n as f64;
                while tooth > cumulative && i + 1 < n {
                    i += 1;
                    cumulative += weights[i];
                }
                teeth.push(i);
            }
            vec![
                (HintKind::ResampleOffsetNotScaled, Answer::Indices(teeth)),
                (
                    HintKind::ResampleIndicesFromOne,
                    Answer::Indices(right.iter().map(|i| i + 1).collect()),
                ),
            ]
        }
        Call::ParticleEstimate { particles, weights } => {
            let n = particles.len();
            let points: Vec<Vector3<f64>> = particles.iter().map(|p| Vector3::from(*p)).collect();
            let as_numbers = |wrapped: bool| {
                let mean: Vector3<f64> = points.iter().zip(weights).map(|(p, w)| p * *w).sum();
                let sigma: Matrix3<f64> = points
                    .iter()
                    .zip(weights)
                    .map(|(p, w)| {
                        let mut d = p - mean;
                        if wrapped {
                            d.z = wrap(d.z);
                        }
                        d * d.transpose() * *w
                    })
                    .sum();
                estimate_answer(&Belief {
                    mean,
                    covariance: sigma,
                })
            };
            let even = vec![1.0 / n as f64; n];
            vec![
                (HintKind::AnglesAveragedAsNumbers, as_numbers(true)),
                (HintKind::AnglesAveragedAsNumbers, as_numbers(false)),
                (
                    HintKind::EstimateWeightsIgnored,
                    estimate_answer(&estimate(&cloud(particles), &even)),
                ),
            ]
        }
        Call::LearnAlphas { commanded, implied } => {
            let Answer::Alphas(right) = expected else {
                return Vec::new();
            };
            let scale = (std::f64::consts::PI / 2.0).sqrt();
            let sizes = |u: &Vec2| [u[0].abs(), u[1].abs()];
            // The two fits of `error` (of v, of omega) by `fit`.
            let fitted = |fit: &Fit, error: &dyn Fn(f64) -> f64| {
                let rows: Vec<[f64; 2]> = commanded.iter().map(sizes).collect();
                let ys = |i: usize| -> Vec<f64> {
                    commanded
                        .iter()
                        .zip(implied)
                        .map(|(u, m)| error(m[i] - u[i]))
                        .collect()
                };
                let [a1, a2] = fit(&rows, &ys(0));
                let [a3, a4] = fit(&rows, &ys(1));
                Answer::Alphas([a1, a2, a3, a4])
            };
            let bounded = |rows: &[[f64; 2]], ys: &[f64]| {
                learn::fit(rows.iter().copied(), ys.iter().copied())
            };
            vec![
                (
                    HintKind::AlphasWithoutScale,
                    Answer::Alphas(right.map(|a| a / scale)),
                ),
                (
                    HintKind::AlphasSignedErrors,
                    fitted(&bounded, &|e| scale * e),
                ),
                (
                    HintKind::AlphasNegativeKept,
                    fitted(&free_fit, &|e| scale * e.abs()),
                ),
            ]
        }
        Call::MeasurementNoise { residuals } => {
            let n = residuals.len() as f64;
            let outer = |r: &Vec2, mean: &Vector2<f64>| {
                let d = Vector2::from(*r) - mean;
                d * d.transpose()
            };
            let sum = |mean: &Vector2<f64>| -> Matrix2<f64> {
                residuals.iter().map(|r| outer(r, mean)).sum()
            };
            let mean = residuals
                .iter()
                .map(|r| Vector2::from(*r))
                .sum::<Vector2<f64>>()
                / n;
            vec![
                (
                    HintKind::NoiseSampleCovariance,
                    Answer::Matrix2(rows(&(sum(&Vector2::zeros()) / (n - 1.0)))),
                ),
                (
                    HintKind::NoiseResidualsCentred,
                    Answer::Matrix2(rows(&(sum(&mean) / n))),
                ),
                (
                    HintKind::NoiseResidualsCentred,
                    Answer::Matrix2(rows(&(sum(&mean) / (n - 1.0)))),
                ),
            ]
        }
    }
}

/// A least-squares fit of the rows to the ys, (a, b) of y ~ a x1 + b x2.
type Fit = dyn Fn(&[[f64; 2]], &[f64]) -> [f64; 2];

/// The least-squares (a, b) of y ~ a x1 + b x2, signs free (zeros where the normal
/// equations have no solution).
fn free_fit(rows: &[[f64; 2]], ys: &[f64]) -> [f64; 2] {
    let (mut xtx, mut xty) = (Matrix2::zeros(), Vector2::zeros());
    for (row, y) in rows.iter().zip(ys) {
        let x = Vector2::from(*row);
        xtx += x * x.transpose();
        xty += x * *y;
    }
    xtx.try_inverse()
        .map_or([0.0, 0.0], |inverse| (inverse * xty).into())
}

/// The control noise's standard deviations without the absolute values.
fn signed_sd(alphas: &[f64; 4], u: &Vec2) -> [f64; 2] {
    let [a1, a2, a3, a4] = *alphas;
    [a1 * u[0] + a2 * u[1], a3 * u[0] + a4 * u[1]]
}

fn estimate_answer(belief: &Belief) -> Answer {
    Answer::Estimate(Estimate {
        mu: belief.mean.into(),
        sigma: rows(&belief.covariance),
    })
}

/// The points' weighted mean and covariance with SPREAD's weights, the mean's angle (if
/// any) averaged as an angle, the deviations' angle (if any) wrapped.
fn unscented<const D: usize>(
    points: &[SVector<f64, D>; POINTS],
    mean_angle: Option<usize>,
    deviation_angle: Option<usize>,
) -> (SVector<f64, D>, nalgebra::SMatrix<f64, D, D>) {
    let (wm, wc) = SPREAD.weights();
    let mean = ukf::mean(points, &wm, mean_angle);
    let side = (points, &mean, deviation_angle);
    (mean, ukf::cross_covariance(side, side, &wc))
}

/// The prediction with the mean's weights for the covariance too (wc[0] = wm[0]).
fn predicted_with_weights(moved: &[Vector3<f64>; POINTS], r: &Matrix3<f64>) -> Answer {
    let (wm, _) = SPREAD.weights();
    let mean = ukf::mean(moved, &wm, HEADING);
    let side = (moved, &mean, HEADING);
    let c = ukf::cross_covariance(side, side, &wm) + r;
    Answer::Prediction(Prediction {
        mu_bar: mean.into(),
        sigma_bar: rows(&((c + c.transpose()) * 0.5)),
    })
}

#[derive(Clone, Copy, PartialEq)]
enum UpdateMistake {
    BearingAveraged,
    DeviationsNotWrapped,
    InnovationNotWrapped,
    NoQ,
}

/// The unscented update of `prior` by the reading `z` of the post at `landmark`, with one
/// mistake made; none where a covariance cannot be factored or inverted.
fn corrected(
    prior: &Belief,
    landmark: &Vector2<f64>,
    z: &Vector2<f64>,
    q: &Matrix2<f64>,
    mistake: UpdateMistake,
) -> Option<Answer> {
    let points = SPREAD.points(prior)?;
    let seen = points.map(|p| sensor::expected(&p, landmark));
    let (wm, wc) = SPREAD.weights();
    let mean_angle = (mistake != UpdateMistake::BearingAveraged).then_some(1);
    let deviation_angle = (mistake != UpdateMistake::DeviationsNotWrapped).then_some(1);
    let expected = ukf::mean(&seen, &wm, mean_angle);
    let reading = (&seen, &expected, deviation_angle);
    let noise = if mistake == UpdateMistake::NoQ {
        Matrix2::zeros()
    } else {
        *q
    };
    let s = ukf::cross_covariance(reading, reading, &wc) + noise;
    let state_angle = (mistake != UpdateMistake::DeviationsNotWrapped).then_some(2);
    let t = ukf::cross_covariance((&points, &prior.mean, state_angle), reading, &wc);
    let mut nu = z - expected;
    if mistake != UpdateMistake::InnovationNotWrapped {
        nu.y = difference(z.y, expected.y);
    }
    let inverse = s.try_inverse()?;
    let k = t * inverse;
    let mut mean = prior.mean + k * nu;
    mean.z = wrap(mean.z);
    let sigma = prior.covariance - k * s * k.transpose();
    Some(Answer::Corrected(Corrected {
        mu: mean.into(),
        sigma: rows(&((sigma + sigma.transpose()) * 0.5)),
        d2: sensor::mahalanobis(&nu, &inverse),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exercises::ukf_particle::generate;
    use crate::grading::testing::each_mistake_gets_its_hint;
    use strum::VariantArray;

    /// Every mistake made in a case gets its own hint, unless another mistake gives the
    /// same answer there (then none); every mistake shows in the cases of every seed; and
    /// a right answer gets no hint. (A heading out of [-pi, pi) and a division by zero are
    /// told by their form, and a function that keeps state by its repeat: none of them is
    /// an answer made here.)
    #[test]
    fn each_mistake_gets_its_hint_and_a_right_answer_none() {
        let shown_in_every_seed: Vec<HintKind> = HintKind::VARIANTS
            .iter()
            .copied()
            .filter(|kind| {
                !matches!(
                    kind,
                    HintKind::ArcHeadingNotWrapped
                        | HintKind::UpdatedHeadingNotWrapped
                        | HintKind::StraightLineDividedByZero
                        | HintKind::KeepsState
                )
            })
            .collect();
        each_mistake_gets_its_hint(
            generate,
            1..=40,
            mistakes,
            |_, _, _| false,
            &shown_in_every_seed,
        );
    }
}
