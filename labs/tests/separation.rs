//! The generated cases of `associate` tell the lab's rule apart from the plausible wrong
//! ones in every seed's variant: random readings almost never do (see BENCHMARKS.md, "The
//! mistake catalogue"), so the generator constructs them. Each wrong rule is recomputed
//! here from the expected output (every landmark's nu_j and S_j) and must disagree with it
//! in at least one case of the seed. The same rules written as JavaScript, with the
//! student harness, are in `server/tests/mistakes.rs`.

use labs::exercises::ekf_localization::{Call, generate};
use nalgebra::{Matrix2, Vector2};
use serde_json::Value;

/// Cases of each function in a student's variant (`grading::plan::CASES_PER_FUNCTION`).
const PER_FUNCTION: usize = 6;
const SEEDS: u64 = 200;

/// Every landmark's (nu_j, D_j = nu_j^T S_j^-1 nu_j) from the expected output.
fn landmarks(expected: &Value) -> Vec<(Vector2<f64>, f64)> {
    let nus: Vec<[f64; 2]> = serde_json::from_value(expected["nu"].clone()).unwrap();
    let ss: Vec<[[f64; 2]; 2]> = serde_json::from_value(expected["S"].clone()).unwrap();
    nus.iter()
        .zip(&ss)
        .map(|(nu, s)| {
            let nu = Vector2::from(*nu);
            let s = Matrix2::from_fn(|i, j| s[i][j]);
            (nu, nu.dot(&(s.try_inverse().unwrap() * nu)))
        })
        .collect()
}

/// The first landmark of the smallest rank.
fn argmin(ranks: impl Iterator<Item = f64>) -> usize {
    ranks
        .enumerate()
        .fold(
            (0, f64::INFINITY),
            |best, (j, r)| if r < best.1 { (j, r) } else { best },
        )
        .0
}

/// What `associate` returns under a rule: (c, outlier).
type Rule = fn(&[(Vector2<f64>, f64)], usize, f64) -> (usize, bool);

const RULES: [(&str, Rule); 6] = [
    ("the smallest Mahalanobis distance", |l, _, lambda| {
        let c = argmin(l.iter().map(|(_, d)| *d));
        (c, l[c].1 >= lambda)
    }),
    ("the shortest innovation", |l, _, lambda| {
        let c = argmin(l.iter().map(|(nu, _)| nu.norm_squared()));
        (c, l[c].1 >= lambda)
    }),
    ("the outlier flag of the first landmark", |l, c, lambda| {
        (c, l[0].1 >= lambda)
    }),
    ("the outlier flag of the last landmark", |l, c, lambda| {
        (c, l[l.len() - 1].1 >= lambda)
    }),
    ("the outlier flag of any landmark", |l, c, lambda| {
        (c, l.iter().any(|(_, d)| *d >= lambda))
    }),
    (
        "an outlier only when no landmark is within the gate",
        |l, c, lambda| (c, l.iter().all(|(_, d)| *d >= lambda)),
    ),
];

#[test]
fn every_wrong_association_rule_fails_a_case_of_every_seed() {
    let mut missed = Vec::new();
    for seed in 1..=SEEDS {
        let cases: Vec<_> = generate(seed, PER_FUNCTION)
            .into_iter()
            .filter_map(|case| match case.call {
                Call::Associate { lambda_m, .. } => Some((lambda_m, case.expected)),
                _ => None,
            })
            .collect();
        for (name, rule) in RULES {
            let separated = cases.iter().any(|(lambda_m, expected)| {
                let c = expected["c"].as_u64().unwrap() as usize;
                let outlier = expected["outlier"].as_bool().unwrap();
                rule(&landmarks(expected), c, *lambda_m) != (c, outlier)
            });
            if !separated {
                missed.push(format!("seed {seed}: {name}"));
            }
        }
    }
    assert!(
        missed.is_empty(),
        "rules no case of the seed tells from the lab's:\n{}",
        missed.join("\n")
    );
}
