//! The documented rules at their boundaries, where random inputs never land: a reading
//! whose Mahalanobis distance equals Lambda_M is an outlier (D >= Lambda_M), two equally
//! likely landmarks go to the first of them in the map, and every heading that leaves
//! predict, update or batch_update lies in [-pi, pi).

use labs::ekf::{
    Belief, Landmark, Map, associate, batch_associate, batch_update, most_likely,
    observation_model, predict, update,
};
use nalgebra::{Matrix2, Matrix2x3, Matrix3, Vector2, Vector3};
use std::f64::consts::PI;

fn map(positions: &[(f64, f64)]) -> Map {
    Map::new(
        (1..)
            .zip(positions)
            .map(|(id, &(x, y))| Landmark {
                id,
                position: Vector2::new(x, y),
            })
            .collect(),
    )
    .unwrap()
}

/// At the origin, facing along x, with a covariance that treats +y and -y alike.
fn belief_at_origin() -> Belief {
    Belief::new(
        Vector3::zeros(),
        Matrix3::from_diagonal(&Vector3::new(0.04, 0.09, 0.01)),
    )
}

fn q() -> Matrix2<f64> {
    Matrix2::new(0.01, 0.0, 0.0, 0.0025)
}

/// The association of `z` by all three functions that make it: the landmark index and
/// the outlier flag of each.
fn decisions(bar: &Belief, z: Vector2<f64>, map: &Map, lambda_m: f64) -> [(usize, bool); 3] {
    let full = associate(bar, &z, map, lambda_m, &q());
    let fast = most_likely(bar, &z, map, lambda_m, &q());
    let batch = batch_associate(bar, &[z], map, lambda_m, &q());
    [
        (full.c, full.outlier),
        (fast.c, fast.outlier),
        (batch[0].c, batch[0].outlier),
    ]
}

#[test]
fn a_distance_exactly_on_lambda_m_is_an_outlier_and_one_just_below_is_not() {
    let bar = belief_at_origin();
    let map = map(&[(4.0, 3.0), (-2.0, 6.0), (1.0, -7.0)]);
    let z = Vector2::new(5.3, 0.7);
    let winner = associate(&bar, &z, &map, f64::INFINITY, &q());
    assert_eq!(winner.c, 0);
    // Lambda_M is the computed distance itself, so the two are equal to the last bit.
    let d = winner.candidates[0].mahalanobis;
    assert!(d > 1.0, "a reading well off its landmark: D = {d}");

    assert_eq!(decisions(&bar, z, &map, d), [(0, true); 3], "D = Lambda_M");
    assert_eq!(
        decisions(&bar, z, &map, d.next_up()),
        [(0, false); 3],
        "D just below Lambda_M"
    );
    assert_eq!(
        decisions(&bar, z, &map, d.next_down()),
        [(0, true); 3],
        "D just above Lambda_M"
    );
}

#[test]
fn a_reading_exactly_as_predicted_is_an_outlier_when_lambda_m_is_zero() {
    let bar = belief_at_origin();
    let map = map(&[(4.0, 3.0), (-2.0, 6.0)]);
    // The reading the first landmark predicts: D = 0 exactly.
    let z = observation_model(&bar.mu, &map.landmarks()[0].position);
    assert_eq!(
        associate(&bar, &z, &map, 0.0, &q()).candidates[0].mahalanobis,
        0.0
    );
    assert_eq!(decisions(&bar, z, &map, 0.0), [(0, true); 3]);
    assert_eq!(decisions(&bar, z, &map, f64::INFINITY), [(0, false); 3]);
}

/// The association of a reading straight ahead between the landmarks at `ahead_left`
/// and its mirror image, with other landmarks before them in the map; the index of the
/// pair's first landmark is `first`.
fn tie(positions: &[(f64, f64)], first: usize) {
    let bar = belief_at_origin();
    let map = map(positions);
    let z = Vector2::new(5.0, 0.0);
    let all = associate(&bar, &z, &map, f64::INFINITY, &q());
    let (a, b) = (&all.candidates[first], &all.candidates[first + 1]);
    // The two landmarks are exactly as likely: same distance, same det S.
    assert_eq!(a.mahalanobis, b.mahalanobis);
    assert_eq!(a.s.determinant(), b.s.determinant());
    assert_eq!(
        decisions(&bar, z, &map, f64::INFINITY),
        [(first, false); 3],
        "{positions:?}"
    );
}

#[test]
fn equally_likely_landmarks_go_to_the_first_in_the_map() {
    let (left, right) = ((4.75, 1.5), (4.75, -1.5));
    tie(&[left, right], 0);
    tie(&[right, left], 0);
    // After a landmark at exactly the measured range but far off in bearing, which the
    // fast association scores first.
    tie(&[(0.0, 5.0), left, right], 1);
    tie(&[(-3.0, 4.0), (20.0, 20.0), right, left], 2);
    // Two landmarks at the same place.
    tie(&[(0.0, 5.0), left, left], 1);
}

fn assert_wrapped_near(angle: f64, expected: f64, what: &str) {
    assert!(
        (-PI..PI).contains(&angle),
        "{what}: {angle} not in [-pi, pi)"
    );
    assert!(
        (angle - expected).abs() < 1e-12,
        "{what}: {angle}, expected {expected}"
    );
}

#[test]
fn predict_wraps_the_heading_across_and_onto_pi() {
    let r = Matrix3::from_diagonal_element(1e-4);
    let at = |theta: f64| Belief::new(Vector3::new(1.0, 2.0, theta), Matrix3::identity() * 0.01);
    let heading =
        |theta: f64, turn: f64| predict(&at(theta), &Vector3::new(0.1, 0.0, turn), &r).mu.z;

    assert_wrapped_near(heading(PI - 0.01, 0.02), -PI + 0.01, "left across pi");
    assert_wrapped_near(heading(-PI + 0.01, -0.02), PI - 0.01, "right across -pi");
    // pi/2 + pi/2 is pi exactly, which belongs to the other end.
    assert_eq!(heading(PI / 2.0, PI / 2.0), -PI);
    assert_eq!(heading(-PI, 0.0), -PI);
}

/// A belief heading just short of pi and a bearing reading that turns it past pi: the
/// innovation says the robot faces 0.01 rad further left than believed.
fn across_pi() -> (Belief, Matrix2x3<f64>, Vector2<f64>, Matrix2<f64>) {
    let bar = Belief::new(
        Vector3::new(0.0, 0.0, PI - 0.001),
        Matrix3::identity() * 0.01,
    );
    // Only the heading is seen: the bearing falls by what the heading rises.
    let h = Matrix2x3::new(0.0, 0.0, 0.0, 0.0, 0.0, -1.0);
    let nu = Vector2::new(0.0, -0.02);
    let q = Matrix2::new(1.0, 0.0, 0.0, 0.01);
    (bar, h, nu, q)
}

#[test]
fn update_and_batch_update_wrap_the_heading_across_pi() {
    let (bar, h, nu, q) = across_pi();
    // Sigma_theta = Q_bearing: the estimate moves half way, by 0.01.
    let expected = -PI + 0.009;
    let s = h * bar.sigma * h.transpose() + q;
    let sequential = update(&bar, &h, &s, &nu).unwrap();
    assert_wrapped_near(sequential.mu.z, expected, "update");
    let batch = batch_update(&bar, [(&h, &nu)], &q).unwrap();
    assert_wrapped_near(batch.mu.z, expected, "batch_update");
    // Two readings that each say so: two thirds of the way, still past pi.
    let batch = batch_update(&bar, [(&h, &nu), (&h, &nu)], &q).unwrap();
    assert_wrapped_near(
        batch.mu.z,
        wrap_by_hand(PI - 0.001 + 0.02 * 2.0 / 3.0),
        "batch of two",
    );
}

fn wrap_by_hand(angle: f64) -> f64 {
    (angle + PI).rem_euclid(2.0 * PI) - PI
}

#[test]
fn update_and_batch_update_wrap_the_heading_across_minus_pi() {
    let (mut bar, h, nu, q) = across_pi();
    bar.mu.z = -PI + 0.001;
    let nu = -nu;
    let s = h * bar.sigma * h.transpose() + q;
    assert_wrapped_near(
        update(&bar, &h, &s, &nu).unwrap().mu.z,
        PI - 0.009,
        "update",
    );
    assert_wrapped_near(
        batch_update(&bar, [(&h, &nu)], &q).unwrap().mu.z,
        PI - 0.009,
        "batch_update",
    );
}
