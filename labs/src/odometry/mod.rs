//! Odometry and how its error grows: the reference model of the exercise on
//! proprioceptive localization of a differential-drive robot.
//!
//! A robot that counts its wheels' turns knows how far each wheel rolled, and from that
//! how it moved: the pose `p = (x, y, theta)` follows from the wheel distances `ds_r`,
//! `ds_l` and the wheel base `b` ([`step`]). Nothing outside the robot corrects it, so
//! every error of a wheel's distance stays in the pose for good, and errors of heading
//! turn into errors of position that grow with every metre driven. The exercise makes
//! this visible in three ways:
//!
//! 1. **Propagation** ([`propagate`]): the covariance of the pose after every step, to
//!    first order, from the two Jacobians of the step ([`pose_jacobian`],
//!    [`increment_jacobian`]) and a wheel noise whose variance grows with the distance
//!    rolled ([`wheel_noise`]):
//!
//!    Sigma_p' = F_p Sigma_p F_p' + F_delta Sigma_delta F_delta'.
//!
//!    On a straight line the variance along the path grows in proportion to the
//!    distance, the variance across it with its cube (heading errors, themselves growing
//!    with the distance, each swing the rest of the path sideways).
//! 2. **Monte Carlo** ([`monte_carlo`]): many robots whose wheels really slip, beside the
//!    propagated covariance. With little noise the cloud of final poses has the
//!    propagated covariance and the share of them inside its 3-sigma ellipse is the 98.9 %
//!    a Gaussian promises. With a large heading uncertainty the cloud bends into a
//!    banana, which no Gaussian in (x, y) describes: the linearisation fails.
//! 3. **Systematic errors** ([`systematic`], [`umbmark`]): unequal wheels and a wrong
//!    wheel base, the errors averaging cannot remove, and the UMBmark square driven both
//!    ways round that measures them.
//!
//! Paths are made from a named [`Shape`] (line, circle, square, figure eight, or a
//! polyline a user draws) driven at a given distance per step ([`Path`]).
//!
//! Everything is pure computation and deterministic: the random parts take a seed and
//! the crate's portable [`crate::rng::Rng`], and every transcendental function comes from
//! `libm`, so the browser gets the command line's numbers bit for bit. Parameters and
//! results serialise with serde; matrices do so as arrays of rows, poses as
//! `[x, y, theta]` with theta wrapped to [-pi, pi).

mod covariance;
mod monte_carlo;
mod motion;
mod params;
mod path;
mod propagation;
mod systematic;
mod umbmark;

pub use covariance::{from_rows, propagate_covariance, propagate_through, to_rows, wheel_noise};
pub use monte_carlo::{
    Cloud, MAX_CLOUD_POSES, MAX_ROBOT_STEPS, MAX_ROBOTS, MonteCarlo, MonteCarloParams,
    gaussian_share_inside, monte_carlo,
};
pub use motion::{Increment, increment_jacobian, pose_jacobian, step};
pub use params::{MAX_K, MAX_SIGMA0, OdometryParams};
pub use path::{Direction, MAX_ARC_TURN, MAX_POINTS, MAX_SIZE, MAX_STEPS, Path, Shape};
pub use propagation::{Propagation, propagate};
pub use systematic::{SYSTEMATIC_RANGE, SystematicErrors, SystematicRun, systematic};
pub use umbmark::{MAX_RUN_POSES, MAX_RUNS, Umbmark, UmbmarkDirection, UmbmarkParams, umbmark};
