//! Angles: radians, wrapped to [-pi, pi).

use std::f64::consts::{PI, TAU};

/// Wraps an angle to [-pi, pi).
#[inline]
pub fn wrap(angle: f64) -> f64 {
    if (-PI..PI).contains(&angle) {
        return angle;
    }
    let wrapped = angle - TAU * libm::floor((angle + PI) / TAU);
    // Rounding can land exactly on +pi, which belongs to the other end of the interval.
    if wrapped >= PI {
        wrapped - TAU
    } else {
        wrapped
    }
}

/// The difference `a - b` of two angles, wrapped: how far apart two headings are.
#[inline]
pub fn difference(a: f64, b: f64) -> f64 {
    wrap(a - b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wraps_into_the_half_open_interval() {
        assert_eq!(wrap(PI), -PI);
        assert_eq!(wrap(-PI), -PI);
        assert_eq!(wrap(0.0), 0.0);
        assert!((wrap(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-15);
        assert!((wrap(-7.0 * PI / 2.0) - PI / 2.0).abs() < 1e-15);
        for k in -50..50 {
            let a = f64::from(k) * 0.77;
            let w = wrap(a);
            assert!((-PI..PI).contains(&w), "{a} wrapped to {w}");
            assert!(libm::sin(w - a).abs() < 1e-12 && libm::cos(w - a) > 0.0);
        }
    }

    #[test]
    fn difference_is_the_short_way_round() {
        assert!((difference(3.1, -3.1) - (6.2 - TAU)).abs() < 1e-12);
        assert!((difference(-3.1, 3.1) - (TAU - 6.2)).abs() < 1e-12);
    }
}
