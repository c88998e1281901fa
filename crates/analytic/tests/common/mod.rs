//! Helpers shared by the integration tests.

/// The length of the polyline through `points`, each `(α, …)` with `α` an angle (its
/// differences taken modulo 2π, in `(−π, π]`): the sum of its chords.
pub fn chord_length(points: &[Vec<f64>]) -> f64 {
    points
        .windows(2)
        .map(|w| {
            w[0].iter()
                .zip(&w[1])
                .enumerate()
                .map(|(k, (a, b))| {
                    let d = if k == 0 {
                        (b - a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                            - std::f64::consts::PI
                    } else {
                        b - a
                    };
                    d * d
                })
                .sum::<f64>()
                .sqrt()
        })
        .sum()
}
