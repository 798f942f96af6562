//! The grading tolerance (1e-9) is fair: a straightforward implementation of every student
//! function, written as a student would (the textbook formulas, general matrix inverses,
//! the likelihood psi itself rather than its logarithm), agrees with the reference on
//! every generated case to 1e-11, a hundredth of the tolerance.

use labs::exercises::ekf_localization::{Call, generate};
use labs::grading::Tolerance;
use nalgebra::{DMatrix, DVector};
use serde_json::{Value, json};
use std::f64::consts::PI;

fn wrap(a: f64) -> f64 {
    (a + PI).rem_euclid(2.0 * PI) - PI
}

fn rows(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

fn mat<const C: usize>(a: &[[f64; C]]) -> DMatrix<f64> {
    DMatrix::from_fn(a.len(), C, |i, j| a[i][j])
}

fn observe(x: &[f64; 3], mx: f64, my: f64) -> (f64, f64, DMatrix<f64>) {
    let (dx, dy) = (mx - x[0], my - x[1]);
    let r = (dx * dx + dy * dy).sqrt();
    let b = wrap(dy.atan2(dx) - x[2]);
    let h = DMatrix::from_row_slice(
        2,
        3,
        &[-dx / r, -dy / r, 0.0, dy / (r * r), -dx / (r * r), -1.0],
    );
    (r, b, h)
}

/// What one landmark predicts about a reading.
struct Candidate {
    nu: DVector<f64>,
    s: DMatrix<f64>,
    h: DMatrix<f64>,
    /// psi = det(2 pi S)^(-1/2) exp(-D / 2)
    psi: f64,
    /// D = nu' S^-1 nu
    d: f64,
}

/// Every landmark's candidate.
fn per_landmark(
    mu: &[f64; 3],
    sigma: &DMatrix<f64>,
    z: (f64, f64),
    m: &[Vec<f64>; 2],
    q: &DMatrix<f64>,
) -> Vec<Candidate> {
    (0..m[0].len())
        .map(|j| {
            let (r, b, h) = observe(mu, m[0][j], m[1][j]);
            let s = &h * sigma * h.transpose() + q;
            let nu = DVector::from_vec(vec![z.0 - r, wrap(z.1 - b)]);
            let d = (nu.transpose() * s.clone().try_inverse().unwrap() * &nu)[(0, 0)];
            let psi = (2.0 * PI * &s).determinant().powf(-0.5) * (-d / 2.0).exp();
            Candidate { nu, s, h, psi, d }
        })
        .collect()
}

/// The first index of the largest psi, as MATLAB's max returns it.
fn argmax(list: &[Candidate]) -> usize {
    (1..list.len()).fold(0, |c, j| if list[j].psi > list[c].psi { j } else { c })
}

fn straightforward(call: &Call) -> Value {
    match call {
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
                return json!([0.0, 0.0, 0.0]);
            }
            let wr = 2.0 * PI * e_r / (e_t * delta_t);
            let wl = 2.0 * PI * e_l / (e_t * delta_t);
            let v = (wr * r_r + wl * r_l) / 2.0;
            let w = (wr * r_r - wl * r_l) / b;
            // The turn is an angle like any other: wrapped, as the contract says.
            json!([
                v * delta_t * mu[2].cos(),
                v * delta_t * mu[2].sin(),
                wrap(w * delta_t)
            ])
        }
        Call::Predict { mu, sigma, u, r } => {
            let g =
                DMatrix::from_row_slice(3, 3, &[1.0, 0.0, -u[1], 0.0, 1.0, u[0], 0.0, 0.0, 1.0]);
            let sigma_bar = &g * mat(sigma) * g.transpose() + mat(r);
            json!({ "mu_bar": [mu[0] + u[0], mu[1] + u[1], wrap(mu[2] + u[2])], "sigma_bar": rows(&sigma_bar) })
        }
        Call::ObservationModel { x, m, j } => {
            let (r, b, _) = observe(x, m[0][*j], m[1][*j]);
            json!([r, b])
        }
        Call::JacobianObservationModel { x, m, j, .. } => {
            json!(rows(&observe(x, m[0][*j], m[1][*j]).2))
        }
        Call::Associate {
            mu_bar,
            sigma_bar,
            z_i,
            m,
            lambda_m,
            q,
        } => {
            let list = per_landmark(mu_bar, &mat(sigma_bar), (z_i[0], z_i[1]), m, &mat(q));
            let c = argmax(&list);
            json!({
                "c": c,
                "outlier": list[c].d >= *lambda_m,
                "nu": list.iter().map(|l| l.nu.as_slice().to_vec()).collect::<Vec<_>>(),
                "S": list.iter().map(|l| rows(&l.s)).collect::<Vec<_>>(),
                "H": list.iter().map(|l| rows(&l.h)).collect::<Vec<_>>(),
            })
        }
        Call::BatchAssociate {
            mu_bar,
            sigma_bar,
            z,
            m,
            lambda_m,
            q,
        } => {
            let (mut c, mut outlier, mut nu_bar, mut h_bar) = (vec![], vec![], vec![], vec![]);
            for (&range, &bearing) in z[0].iter().zip(&z[1]) {
                let list = per_landmark(mu_bar, &mat(sigma_bar), (range, bearing), m, &mat(q));
                let best = argmax(&list);
                c.push(best);
                outlier.push(list[best].d >= *lambda_m);
                nu_bar.extend(list[best].nu.iter().copied());
                h_bar.extend(rows(&list[best].h));
            }
            json!({ "c": c, "outlier": outlier, "nu_bar": nu_bar, "H_bar": h_bar })
        }
        Call::Update {
            mu_bar,
            sigma_bar,
            h,
            s,
            nu,
        } => posterior(
            mu_bar,
            &mat(sigma_bar),
            &mat(h),
            &mat(s),
            &DVector::from_row_slice(nu),
        ),
        Call::BatchUpdate {
            mu_bar,
            sigma_bar,
            h_bar,
            q_bar,
            nu_bar,
        } => {
            let h = mat(h_bar);
            let q = DMatrix::from_fn(q_bar.len(), q_bar.len(), |i, j| q_bar[i][j]);
            let s = &h * mat(sigma_bar) * h.transpose() + q;
            posterior(
                mu_bar,
                &mat(sigma_bar),
                &h,
                &s,
                &DVector::from_row_slice(nu_bar),
            )
        }
    }
}

/// K = Sigma H' S^-1, mu = mu_bar + K nu, Sigma = (I - K H) Sigma_bar symmetrised.
fn posterior(
    mu_bar: &[f64; 3],
    sigma_bar: &DMatrix<f64>,
    h: &DMatrix<f64>,
    s: &DMatrix<f64>,
    nu: &DVector<f64>,
) -> Value {
    let k = sigma_bar * h.transpose() * s.clone().try_inverse().unwrap();
    let mu = DVector::from_row_slice(mu_bar) + &k * nu;
    let sigma = (DMatrix::identity(3, 3) - &k * h) * sigma_bar;
    let sigma = (&sigma + sigma.transpose()) / 2.0;
    json!({ "mu": [mu[0], mu[1], wrap(mu[2])], "sigma": rows(&sigma) })
}

#[test]
fn a_straightforward_implementation_agrees_far_inside_the_tolerance() {
    let tight = Tolerance {
        absolute: 1e-11,
        relative: 1e-11,
    };
    for seed in 1..=6 {
        for case in generate(seed, 40) {
            let got = straightforward(&case.call);
            let mismatches = case.check(&got, tight);
            assert!(
                mismatches.is_empty(),
                "seed {seed} {} ({}): {mismatches:#?}",
                case.id,
                case.note
            );
        }
    }
}
