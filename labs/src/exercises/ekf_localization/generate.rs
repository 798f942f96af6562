//! Test cases generated from a seed, so that every student can have a variant of their
//! own. Each function's cases cycle through its scenarios, the regions where classic
//! mistakes show: headings and bearings near +-pi, landmarks behind the robot, the first
//! and the last landmark (0- versus 1-based indices), unequal wheels, a zero time step,
//! outliers, readings just inside the outlier threshold and one exactly on it. Readings
//! where a plausible wrong association rule picks another landmark than the likelihood
//! (the nearest in Mahalanobis distance, the nearest innovation) and where the outlier
//! decision differs between the associated landmark and the others are constructed, not
//! left to chance: random readings almost never tell these rules apart.

use super::Case;
use super::contract::{Call, Mat2, TwoRows, Vec2, Vec3, vector3};
use crate::angle::wrap;
use crate::ekf::{self, Belief, Candidate, Landmark};
use crate::grading::{self, matrix_of, rows, scenario_cases};
use crate::rng::Rng;
use nalgebra::{Matrix3, Vector2, Vector3};
use std::f64::consts::PI;

/// `per_function` cases of every student function, from `seed`.
pub fn generate(seed: u64, per_function: usize) -> Vec<Case> {
    scenario_cases(seed, per_function, &SCENARIOS)
}

type Scenario = grading::Scenario<Call>;

const SCENARIOS: [(&str, &[Scenario]); 8] = [
    (
        "calculate_odometry",
        &[
            ("driving forward", |rng| odometry(rng, Motion::Forward)),
            ("turning on the spot", |rng| {
                odometry(rng, Motion::OnTheSpot)
            }),
            ("wheels of unequal radius", |rng| {
                odometry(rng, Motion::UnequalWheels)
            }),
            ("heading near +-pi", |rng| {
                odometry(rng, Motion::HeadingNearPi)
            }),
            ("the first step: delta_t = 0", |rng| {
                odometry(rng, Motion::FirstStep)
            }),
        ],
    ),
    (
        "predict",
        &[
            ("a general step", |rng| prediction(rng, false)),
            ("the heading crosses +-pi", |rng| prediction(rng, true)),
        ],
    ),
    (
        "observation_model",
        &[
            ("a landmark ahead", |rng| {
                observation(rng, Sight::Anywhere, false)
            }),
            ("a landmark behind the robot", |rng| {
                observation(rng, Sight::Behind, false)
            }),
            ("the first landmark", |rng| {
                observation(rng, Sight::First, false)
            }),
            ("the last landmark", |rng| {
                observation(rng, Sight::Last, false)
            }),
        ],
    ),
    (
        "jacobian_observation_model",
        &[
            ("a landmark ahead", |rng| {
                observation(rng, Sight::Anywhere, true)
            }),
            ("a landmark behind the robot", |rng| {
                observation(rng, Sight::Behind, true)
            }),
            ("the first landmark", |rng| {
                observation(rng, Sight::First, true)
            }),
            ("the last landmark", |rng| {
                observation(rng, Sight::Last, true)
            }),
        ],
    ),
    (
        "associate",
        &[
            (
                "a good reading of an inner landmark, the first and the last beyond the gate",
                good_reading,
            ),
            ("a gross outlier", |rng| association(rng, Reading::Outlier)),
            (
                "the likelihood's normalisation decides: the most likely landmark is not the \
                 nearest in Mahalanobis distance, and Lambda_M lies between their distances",
                |rng| ambiguous_reading(rng, Rival::NearestMahalanobis),
            ),
            (
                "a landmark behind the robot, read just inside the threshold",
                |rng| association(rng, Reading::BehindJustInside),
            ),
            ("D_M exactly on Lambda_M = 0", |_| threshold_boundary()),
            (
                "the landmark of the shortest innovation is not the most likely \
                 (Lambda_M = Infinity)",
                |rng| ambiguous_reading(rng, Rival::NearestInnovation),
            ),
        ],
    ),
    (
        "batch_associate",
        &[
            ("readings with outliers", |rng| {
                batch_association(rng, false)
            }),
            ("no outlier rejection (Lambda_M = Infinity)", |rng| {
                batch_association(rng, true)
            }),
        ],
    ),
    ("update", &[("one reading", single_update)]),
    (
        "batch_update",
        &[("all inliers of a time step", stacked_update)],
    ),
];

// ---- random building blocks ----

fn any_heading(rng: &mut Rng) -> f64 {
    rng.uniform_in(-PI, PI)
}

/// A heading within 0.05 rad of +-pi.
fn near_pi(rng: &mut Rng) -> f64 {
    wrap(PI + rng.uniform_in(-0.05, 0.05))
}

fn pose(rng: &mut Rng, heading: f64) -> Vec3 {
    [
        rng.uniform_in(-5.0, 5.0),
        rng.uniform_in(-5.0, 5.0),
        heading,
    ]
}

/// A random covariance L L' + eps I, entries of a size between `low` and `high`.
fn covariance(rng: &mut Rng, low: f64, high: f64) -> Matrix3<f64> {
    let scale = rng.uniform_in(low, high);
    let mut l = Matrix3::zeros();
    for i in 0..3 {
        for j in 0..=i {
            l[(i, j)] = rng.normal(0.0, scale.sqrt());
        }
    }
    let sigma = l * l.transpose() + Matrix3::identity() * (scale * 1e-3);
    (sigma + sigma.transpose()) * 0.5
}

fn diag2(a: f64, b: f64) -> Mat2 {
    [[a, 0.0], [0.0, b]]
}

/// A measurement noise covariance of range std 0.05-0.3 m, bearing std 0.02-0.2 rad.
fn measurement_noise(rng: &mut Rng) -> Mat2 {
    diag2(
        rng.uniform_in(0.05, 0.3).powi(2),
        rng.uniform_in(0.02, 0.2).powi(2),
    )
}

/// A map of 5-10 landmarks within 10 m of `x`, at least 1.5 m apart and from `x`.
fn landmarks(rng: &mut Rng, x: &Vec3) -> TwoRows {
    let n = 5 + (rng.uniform() * 6.0) as usize;
    let mut points: Vec<Vector2<f64>> = Vec::with_capacity(n);
    let centre = Vector2::new(x[0], x[1]);
    while points.len() < n {
        let p = centre + Vector2::new(rng.uniform_in(-10.0, 10.0), rng.uniform_in(-10.0, 10.0));
        if (p - centre).norm() >= 1.5 && points.iter().all(|q| (p - q).norm() >= 1.5) {
            points.push(p);
        }
    }
    [
        points.iter().map(|p| p.x).collect(),
        points.iter().map(|p| p.y).collect(),
    ]
}

/// Moves landmark `j` of `m` to a point straight behind the pose `x` (bearing within
/// 0.05 rad of +-pi).
fn put_behind(rng: &mut Rng, m: &mut TwoRows, j: usize, x: &Vec3) {
    let direction = x[2] + PI + rng.uniform_in(-0.05, 0.05);
    let distance = rng.uniform_in(2.0, 8.0);
    m[0][j] = x[0] + distance * libm::cos(direction);
    m[1][j] = x[1] + distance * libm::sin(direction);
}

// ---- one builder per function ----

enum Motion {
    Forward,
    OnTheSpot,
    UnequalWheels,
    HeadingNearPi,
    FirstStep,
}

fn odometry(rng: &mut Rng, motion: Motion) -> Call {
    let e_t = [512.0, 1024.0, 2048.0, 4096.0][rng.index(4)];
    let r = rng.uniform_in(0.05, 0.3);
    let (r_r, r_l) = match motion {
        Motion::UnequalWheels => (r, r * rng.uniform_in(0.8, 0.95)),
        _ => (r, r),
    };
    let ticks = (rng.uniform_in(50.0, 600.0) as i64) as f64;
    let (e_r, e_l) = match motion {
        Motion::OnTheSpot => (ticks, -ticks),
        _ => (ticks, (ticks * rng.uniform_in(0.7, 1.0)).round()),
    };
    let heading = match motion {
        Motion::HeadingNearPi => near_pi(rng),
        _ => any_heading(rng),
    };
    Call::CalculateOdometry {
        e_r,
        e_l,
        e_t,
        b: rng.uniform_in(0.1, 0.5),
        r_r,
        r_l,
        delta_t: if matches!(motion, Motion::FirstStep) {
            0.0
        } else {
            rng.uniform_in(0.05, 1.0)
        },
        mu: pose(rng, heading),
    }
}

fn prediction(rng: &mut Rng, cross_pi: bool) -> Call {
    let heading = if cross_pi {
        PI - rng.uniform_in(0.01, 0.1)
    } else {
        any_heading(rng)
    };
    let turn = if cross_pi {
        rng.uniform_in(0.15, 0.4)
    } else {
        rng.uniform_in(-0.3, 0.3)
    };
    let distance = rng.uniform_in(0.0, 0.5);
    let u = [
        distance * libm::cos(heading),
        distance * libm::sin(heading),
        turn,
    ];
    let r = [
        rng.uniform_in(0.01, 0.2),
        rng.uniform_in(0.01, 0.2),
        rng.uniform_in(0.005, 0.1),
    ];
    Call::Predict {
        mu: pose(rng, heading),
        sigma: rows(&covariance(rng, 1e-4, 1.0)),
        u,
        r: rows(&Matrix3::from_diagonal(&Vector3::from(
            r.map(|s: f64| s * s),
        ))),
    }
}

enum Sight {
    Anywhere,
    Behind,
    First,
    Last,
}

fn observation(rng: &mut Rng, sight: Sight, jacobian: bool) -> Call {
    let heading = any_heading(rng);
    let x = pose(rng, heading);
    let mut m = landmarks(rng, &x);
    let n = m[0].len();
    let j = match sight {
        Sight::First => 0,
        Sight::Last => n - 1,
        Sight::Anywhere | Sight::Behind => rng.index(n),
    };
    if matches!(sight, Sight::Behind) {
        // Behind, and where atan2(dy, dx) - theta itself lies outside [-pi, pi), so that
        // a bearing left unwrapped shows: about half the places behind are so (none when
        // theta is within 0.05 of 0, hence the bound).
        for _ in 0..64 {
            put_behind(rng, &mut m, j, &x);
            let raw = libm::atan2(m[1][j] - x[1], m[0][j] - x[0]) - x[2];
            if !(-PI..PI).contains(&raw) {
                break;
            }
        }
    }
    if !jacobian {
        return Call::ObservationModel { x, m, j };
    }
    let z_hat = ekf::observation_model(&vector3(&x), &Vector2::new(m[0][j], m[1][j]));
    Call::JacobianObservationModel {
        x,
        m,
        j,
        z_hat: z_hat.into(),
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Reading {
    Outlier,
    BehindJustInside,
}

/// A predicted belief, a map, and a reading of landmark `c` from a pose drawn from the
/// belief, with measurement noise drawn from `q`.
struct Scene {
    mu_bar: Vec3,
    sigma_bar: Matrix3<f64>,
    m: TwoRows,
    q: Mat2,
}

fn scene(rng: &mut Rng) -> Scene {
    scene_with(rng, 1e-4, 1e-2)
}

/// A scene whose covariance has entries of a size between `low` and `high`.
fn scene_with(rng: &mut Rng, low: f64, high: f64) -> Scene {
    let heading = any_heading(rng);
    let mu_bar = pose(rng, heading);
    let m = landmarks(rng, &mu_bar);
    Scene {
        mu_bar,
        sigma_bar: covariance(rng, low, high),
        m,
        q: measurement_noise(rng),
    }
}

impl Scene {
    /// A noisy reading of landmark `j`.
    fn reading(&self, rng: &mut Rng, j: usize) -> Vec2 {
        let chol = self
            .sigma_bar
            .cholesky()
            .expect("covariances are positive definite")
            .l();
        let truth = vector3(&self.mu_bar) + chol * Vector3::from_fn(|_, _| rng.standard_normal());
        let z = ekf::observation_model(&truth, &Vector2::new(self.m[0][j], self.m[1][j]));
        [
            rng.normal(z.x, self.q[0][0].sqrt()),
            rng.normal(z.y, self.q[1][1].sqrt()),
        ]
    }

    fn belief(&self) -> Belief {
        Belief::new(vector3(&self.mu_bar), self.sigma_bar)
    }

    /// The reference's association of the reading `z`.
    fn associate(&self, z: Vec2, lambda_m: f64) -> ekf::Association {
        ekf::associate(
            &self.belief(),
            &Vector2::from(z),
            &contract_map(&self.m),
            lambda_m,
            &matrix_of(&self.q),
        )
    }

    /// The call of `associate` with the reading `z_i`.
    fn into_call(self, z_i: Vec2, lambda_m: f64) -> Call {
        Call::Associate {
            mu_bar: self.mu_bar,
            sigma_bar: rows(&self.sigma_bar),
            z_i,
            m: self.m,
            lambda_m,
            q: self.q,
        }
    }

    /// A reading on which the lab's rule and `rival` associate different landmarks, each
    /// rule by a clear margin, at distances where psi does not underflow; `None` when no
    /// pair of landmarks has one. Along the segment z(t) = z_hat_a + t (z_hat_b - z_hat_a)
    /// in measurement space each rule prefers landmark a up to some t and b beyond it;
    /// between the two rules' crossings they disagree, and the midpoint is taken. Pairs
    /// close in measurement space come first: their readings are plausible for both.
    fn separating(&self, rival: Rival) -> Option<Vec2> {
        let mu = vector3(&self.mu_bar);
        let z_hat: Vec<Vector2<f64>> = (0..self.m[0].len())
            .map(|j| ekf::observation_model(&mu, &Vector2::new(self.m[0][j], self.m[1][j])))
            .collect();
        let towards = |a: usize, b: usize| {
            let d = z_hat[b] - z_hat[a];
            Vector2::new(d.x, wrap(d.y))
        };
        let n = z_hat.len();
        let mut pairs: Vec<(usize, usize)> = (0..n)
            .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
            .collect();
        pairs.sort_by(|p, q| {
            let gap = |&(a, b): &(usize, usize)| towards(a, b).norm_squared();
            gap(p).total_cmp(&gap(q))
        });
        let belief = self.belief();
        let q = matrix_of(&self.q);
        for (a, b) in pairs {
            let at = |t: f64| {
                let z = z_hat[a] + towards(a, b) * t;
                [z.x, wrap(z.y)]
            };
            // The two landmarks alone, as landmarks 0 and 1.
            let landmark = |j: usize, id| Landmark {
                id,
                position: Vector2::new(self.m[0][j], self.m[1][j]),
            };
            let both = ekf::Map::new(vec![landmark(a, 1), landmark(b, 2)]).ok()?;
            // Where `rank` starts to prefer b, by bisection.
            let crossing = |rank: &dyn Fn(&Candidate) -> f64| {
                let (mut low, mut high) = (0.0, 1.0);
                for _ in 0..40 {
                    let mid = (low + high) / 2.0;
                    let z = Vector2::from(at(mid));
                    let cands = ekf::associate(&belief, &z, &both, f64::INFINITY, &q).candidates;
                    if rank(&cands[1]) < rank(&cands[0]) {
                        high = mid;
                    } else {
                        low = mid;
                    }
                }
                (low + high) / 2.0
            };
            let z = at((crossing(&likelihood_rank) + crossing(&|c| rival.rank(c))) / 2.0);
            let cands = self.associate(z, f64::INFINITY).candidates;
            let (c, r) = (
                best(&cands, likelihood_rank),
                best(&cands, |c| rival.rank(c)),
            );
            let clear = |rank: &dyn Fn(&Candidate) -> f64, winner: usize, loser: usize| {
                let (w, l) = (rank(&cands[winner]), rank(&cands[loser]));
                l - w > 1e-6 * (1.0 + w.abs())
            };
            if c != r
                && [c, r].iter().all(|j| [a, b].contains(j))
                && clear(&likelihood_rank, c, r)
                && clear(&|cand| rival.rank(cand), r, c)
                && cands[c].mahalanobis.max(cands[r].mahalanobis) < 200.0
            {
                return Some(z);
            }
        }
        None
    }

    /// The reading `z` moved along the innovation of its most likely landmark until that
    /// innovation's D_M is `target`: an outlier of a chosen size, or an inlier just inside
    /// the threshold. Targets stay below ~1400, where psi itself would underflow and an
    /// implementation that takes the argmax of psi could no longer tell the landmarks
    /// apart.
    fn stretched(&self, z: Vec2, target: f64) -> Vec2 {
        let map = contract_map(&self.m);
        let m = ekf::most_likely(
            &self.belief(),
            &Vector2::from(z),
            &map,
            f64::INFINITY,
            &matrix_of(&self.q),
        );
        let nu = m.candidate.nu;
        let stretch = (target / m.candidate.mahalanobis.max(1e-12)).sqrt();
        let z_hat = Vector2::from(z) - nu;
        [z_hat.x + stretch * nu.x, wrap(z_hat.y + stretch * nu.y)]
    }
}

/// A threshold Lambda_M of the lab's kind, chi2inv(delta_M, 2).
fn lab_threshold(rng: &mut Rng) -> f64 {
    ekf::lambda_m([0.95, 0.99, 0.999][rng.index(3)])
}

fn association(rng: &mut Rng, kind: Reading) -> Call {
    let mut s = scene(rng);
    let j = rng.index(s.m[0].len());
    if kind == Reading::BehindJustInside {
        put_behind(rng, &mut s.m, j, &s.mu_bar);
    }
    let z_i = s.reading(rng, j);
    let lambda_m = lab_threshold(rng);
    let target = match kind {
        Reading::Outlier => rng.uniform_in(1.5 * lambda_m, 400.0),
        Reading::BehindJustInside => 0.97 * lambda_m,
    };
    let z_i = s.stretched(z_i, target);
    s.into_call(z_i, lambda_m)
}

/// A reading of an inner landmark, associated with it and inside the gate, while the
/// first and the last landmark lie beyond the gate: an outlier decision made on the
/// first, the last or any landmark instead of the associated one shows. Nearly every
/// scene is so; the others are drawn again.
fn good_reading(rng: &mut Rng) -> Call {
    loop {
        let s = scene(rng);
        let last = s.m[0].len() - 1;
        let j = 1 + rng.index(last - 1);
        let z_i = s.reading(rng, j);
        let lambda_m = lab_threshold(rng);
        let a = s.associate(z_i, lambda_m);
        let beyond = |k: usize| a.candidates[k].mahalanobis >= lambda_m;
        if a.c == j && !a.outlier && beyond(0) && beyond(last) {
            return s.into_call(z_i, lambda_m);
        }
    }
}

/// A plausible wrong rule for choosing the landmark of a reading, instead of the lab's
/// largest likelihood psi_j.
#[derive(Clone, Copy)]
enum Rival {
    /// The smallest Mahalanobis distance D_j: the likelihood without its normalisation.
    NearestMahalanobis,
    /// The shortest innovation |nu_j|, metres and radians added up.
    NearestInnovation,
}

impl Rival {
    /// How the rule ranks a landmark, lower preferred.
    fn rank(self, cand: &Candidate) -> f64 {
        match self {
            Rival::NearestMahalanobis => cand.mahalanobis,
            Rival::NearestInnovation => cand.nu.norm_squared(),
        }
    }
}

/// The lab's rank of a landmark, lower preferred: -2 ln psi_j = D_j + ln det(2 pi S_j),
/// psi_j = det(2 pi S_j)^(-1/2) exp(-D_j / 2), less the constant ln (2 pi)^2.
fn likelihood_rank(cand: &Candidate) -> f64 {
    cand.mahalanobis + libm::log(cand.s.determinant())
}

/// The landmark `rank` prefers (the first of equals).
fn best(cands: &[Candidate], rank: impl Fn(&Candidate) -> f64) -> usize {
    (1..cands.len()).fold(0, |c, j| {
        if rank(&cands[j]) < rank(&cands[c]) {
            j
        } else {
            c
        }
    })
}

/// A reading on which `rival` associates another landmark than the lab's rule, in a scene
/// of an uncertain pose (where the landmarks' S_j differ most). For the nearest in
/// Mahalanobis distance, Lambda_M lies halfway between its D and the associated
/// landmark's, so that the associated landmark is an outlier and the rival's is not:
/// a decision made on the smallest D shows too. For the shortest innovation there is no
/// rejection. Scenes without such a reading (rare) are drawn again.
fn ambiguous_reading(rng: &mut Rng, rival: Rival) -> Call {
    loop {
        let s = scene_with(rng, 1e-2, 1e-1);
        let Some(z_i) = s.separating(rival) else {
            continue;
        };
        let lambda_m = match rival {
            Rival::NearestMahalanobis => {
                let cands = s.associate(z_i, f64::INFINITY).candidates;
                let d = |j: usize| cands[j].mahalanobis;
                (d(best(&cands, likelihood_rank)) + d(best(&cands, |c| rival.rank(c)))) / 2.0
            }
            Rival::NearestInnovation => f64::INFINITY,
        };
        return s.into_call(z_i, lambda_m);
    }
}

fn contract_map(m: &TwoRows) -> ekf::Map {
    super::contract::map(m).expect("generated maps are valid")
}

/// A reading of a landmark 5 m straight ahead that is exactly what the belief predicts:
/// every implementation computes D_M = 0 exactly, which is an outlier for Lambda_M = 0
/// only if the test is D_M >= Lambda_M.
fn threshold_boundary() -> Call {
    Call::Associate {
        mu_bar: [0.0, 0.0, 0.0],
        sigma_bar: rows(&(Matrix3::identity() * 0.01)),
        z_i: [5.0, 0.0],
        m: [vec![5.0, -3.0, 0.0], vec![0.0, 4.0, -6.0]],
        lambda_m: 0.0,
        q: diag2(0.01, 0.0025),
    }
}

fn batch_association(rng: &mut Rng, no_rejection: bool) -> Call {
    let mut s = scene(rng);
    let n_landmarks = s.m[0].len();
    let behind = rng.index(n_landmarks);
    put_behind(rng, &mut s.m, behind, &s.mu_bar);
    let n = 3 + rng.index(6);
    let mut z: TwoRows = [Vec::with_capacity(n), Vec::with_capacity(n)];
    // The first two readings, where the scene has them, are ones a wrong association
    // rule gets wrong; every third reading is an outlier.
    let rivals = [Rival::NearestMahalanobis, Rival::NearestInnovation];
    for k in 0..n {
        let j = rng.index(n_landmarks);
        let mut reading = s.reading(rng, j);
        if k % 3 == 2 {
            reading = s.stretched(reading, rng.uniform_in(30.0, 400.0));
        } else if let Some(constructed) = rivals.get(k).and_then(|&r| s.separating(r)) {
            reading = constructed;
        }
        z[0].push(reading[0]);
        z[1].push(reading[1]);
    }
    Call::BatchAssociate {
        mu_bar: s.mu_bar,
        sigma_bar: rows(&s.sigma_bar),
        z,
        m: s.m,
        lambda_m: if no_rejection {
            f64::INFINITY
        } else {
            ekf::lambda_m(0.999)
        },
        q: s.q,
    }
}

fn single_update(rng: &mut Rng) -> Call {
    let s = scene(rng);
    let j = rng.index(s.m[0].len());
    let z = s.reading(rng, j);
    let cand = ekf::associate(
        &s.belief(),
        &Vector2::from(z),
        &contract_map(&s.m),
        f64::INFINITY,
        &matrix_of(&s.q),
    )
    .candidates[j];
    Call::Update {
        mu_bar: s.mu_bar,
        sigma_bar: rows(&s.sigma_bar),
        h: std::array::from_fn(|i| std::array::from_fn(|k| cand.h[(i, k)])),
        s: std::array::from_fn(|i| std::array::from_fn(|k| cand.s[(i, k)])),
        nu: cand.nu.into(),
    }
}

fn stacked_update(rng: &mut Rng) -> Call {
    let s = scene(rng);
    let n = 1 + rng.index(6);
    let belief = s.belief();
    let map = contract_map(&s.m);
    let mut h_bar = Vec::with_capacity(2 * n);
    let mut nu_bar = Vec::with_capacity(2 * n);
    for _ in 0..n {
        let j = rng.index(s.m[0].len());
        let z = s.reading(rng, j);
        let m = ekf::most_likely(
            &belief,
            &Vector2::from(z),
            &map,
            f64::INFINITY,
            &matrix_of(&s.q),
        );
        h_bar.extend((0..2).map(|i| std::array::from_fn(|k| m.candidate.h[(i, k)])));
        nu_bar.extend(m.candidate.nu.iter());
    }
    let size = 2 * n;
    let q_bar = (0..size)
        .map(|r| {
            (0..size)
                .map(|c| {
                    if r / 2 == c / 2 {
                        s.q[r % 2][c % 2]
                    } else {
                        0.0
                    }
                })
                .collect()
        })
        .collect();
    Call::BatchUpdate {
        mu_bar: s.mu_bar,
        sigma_bar: rows(&belief.sigma),
        h_bar,
        q_bar,
        nu_bar,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grading::{Contract, Tolerance};

    #[test]
    fn the_same_seed_gives_the_same_cases() {
        assert_eq!(generate(9, 12), generate(9, 12));
        assert_ne!(generate(9, 12), generate(10, 12));
    }

    /// The expected outputs of the geometric functions by their textbook formulas, written
    /// out here apart from the reference's code. The association and the updates get the
    /// same check from a whole straightforward implementation in
    /// `labs/tests/fair_tolerance.rs`.
    fn by_hand(call: &Call) -> Option<serde_json::Value> {
        use serde_json::json;
        let wrap = |a: f64| (a + PI).rem_euclid(2.0 * PI) - PI;
        let offset = |x: &Vec3, m: &TwoRows, j: usize| (m[0][j] - x[0], m[1][j] - x[1]);
        Some(match call {
            Call::CalculateOdometry {
                e_r,
                e_l,
                e_t,
                b,
                r_r,
                r_l,
                delta_t,
                mu,
            } => {
                if *delta_t == 0.0 {
                    json!([0.0, 0.0, 0.0])
                } else {
                    // The arc each wheel rolled: the robot's advance is their mean, its
                    // turn their difference over the wheel base.
                    let right = 2.0 * PI * r_r * e_r / e_t;
                    let left = 2.0 * PI * r_l * e_l / e_t;
                    let advance = (right + left) / 2.0;
                    json!([
                        advance * mu[2].cos(),
                        advance * mu[2].sin(),
                        wrap((right - left) / b)
                    ])
                }
            }
            Call::Predict { mu, sigma, u, r } => {
                let g = Matrix3::new(1.0, 0.0, -u[1], 0.0, 1.0, u[0], 0.0, 0.0, 1.0);
                let sigma_bar = g * matrix_of(sigma) * g.transpose() + matrix_of(r);
                let rows: Vec<[f64; 3]> = (0..3)
                    .map(|i| [sigma_bar[(i, 0)], sigma_bar[(i, 1)], sigma_bar[(i, 2)]])
                    .collect();
                json!({
                    "mu_bar": [mu[0] + u[0], mu[1] + u[1], wrap(mu[2] + u[2])],
                    "sigma_bar": rows,
                })
            }
            Call::ObservationModel { x, m, j } => {
                let (dx, dy) = offset(x, m, *j);
                json!([dx.hypot(dy), wrap(dy.atan2(dx) - x[2])])
            }
            Call::JacobianObservationModel { x, m, j, .. } => {
                let (dx, dy) = offset(x, m, *j);
                let r2 = dx * dx + dy * dy;
                let r = r2.sqrt();
                json!([[-dx / r, -dy / r, 0.0], [dy / r2, -dx / r2, -1.0]])
            }
            _ => return None,
        })
    }

    #[test]
    fn every_case_survives_json_and_the_geometric_ones_match_the_formulas() {
        let mut by_function = std::collections::BTreeMap::new();
        for case in generate(4, 12) {
            let json = serde_json::to_string(&case).unwrap();
            let back: Case = serde_json::from_str(&json).unwrap();
            assert_eq!(back, case);
            if let Some(expected) = by_hand(&case.call) {
                let mismatches = case.check(&expected, Tolerance::default());
                assert!(mismatches.is_empty(), "{}: {mismatches:#?}", case.id);
                *by_function.entry(case.call.function()).or_insert(0) += 1;
            }
        }
        assert_eq!(by_function.values().collect::<Vec<_>>(), [&12; 4]);
    }

    fn outputs(function: &str) -> Vec<(Call, serde_json::Value)> {
        generate(21, 30)
            .into_iter()
            .filter(|c| c.call.function() == function)
            .map(|c| (c.call, c.expected))
            .collect()
    }

    #[test]
    fn the_interesting_regions_are_covered() {
        // Bearings near +-pi.
        let near = |b: f64| b.abs() > PI - 0.06;
        assert!(
            outputs("observation_model")
                .iter()
                .any(|(_, z)| near(z[1].as_f64().unwrap()))
        );
        // Headings that cross +-pi in the prediction.
        assert!(outputs("predict").iter().any(|(call, out)| {
            let Call::Predict { mu, .. } = call else {
                unreachable!()
            };
            mu[2] > 3.0 && out["mu_bar"][2].as_f64().unwrap() < 0.0
        }));
        // Outliers, inliers, readings within 5 % below the threshold, the boundary itself.
        let assoc = outputs("associate");
        let outlier = |out: &serde_json::Value| out["outlier"].as_bool().unwrap();
        assert!(assoc.iter().any(|(_, out)| outlier(out)));
        assert!(assoc.iter().any(|(_, out)| !outlier(out)));
        let just_inside = assoc.iter().any(|(call, out)| {
            let Call::Associate {
                mu_bar,
                sigma_bar,
                z_i,
                m,
                lambda_m,
                q,
            } = call
            else {
                unreachable!()
            };
            let belief = Belief::new(vector3(mu_bar), matrix_of(sigma_bar));
            let a = ekf::associate(
                &belief,
                &Vector2::from(*z_i),
                &contract_map(m),
                *lambda_m,
                &matrix_of(q),
            );
            let d = a.candidates[a.c].mahalanobis;
            !outlier(out) && d > 0.95 * lambda_m && d < *lambda_m
        });
        assert!(just_inside);
        assert!(assoc.iter().any(
            |(call, out)| matches!(call, Call::Associate { lambda_m, .. } if *lambda_m == 0.0)
                && outlier(out)
        ));
        // Both ends of the map, so that a 1-based index shows.
        let js: Vec<usize> = outputs("observation_model")
            .iter()
            .map(|(call, _)| match call {
                Call::ObservationModel { j, .. } => *j,
                _ => unreachable!(),
            })
            .collect();
        assert!(js.contains(&0));
        // A zero time step.
        assert!(outputs("calculate_odometry").iter().any(|(call, u)| {
            matches!(call, Call::CalculateOdometry { delta_t, .. } if *delta_t == 0.0)
                && u == &serde_json::json!([0.0, 0.0, 0.0])
        }));
    }
}
