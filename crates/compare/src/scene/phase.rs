//! The base phase: the base moves as `u_g cos(ωt + α)`; phases are compared on the circle.

use std::f64::consts::{PI, TAU};

/// `angle` wrapped to `(−π, π]`.
pub fn wrap(angle: f64) -> f64 {
    let w = angle.rem_euclid(TAU);
    if w > PI {
        w - TAU
    } else {
        w
    }
}

/// The distance between two phases on the circle, in `[0, π]`.
pub fn distance(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapping_and_distance_on_the_circle() {
        assert_eq!(wrap(PI), PI);
        assert!((wrap(-PI) - PI).abs() < 1e-15);
        assert!((wrap(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-15);
        assert!((distance(0.1, TAU - 0.1) - 0.2).abs() < 1e-15);
        assert!((distance(0.0, PI) - PI).abs() < 1e-15);
        assert_eq!(distance(1.0, 1.0), 0.0);
    }
}
