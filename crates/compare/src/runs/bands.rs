//! Attenuation bands: the frequency ranges where the transmittance is below 0 dB.

/// Ranges `[from, to]` of `omegas` (ascending) where `t(ω) < 0`, from sampled values: a band
/// starts at the first sample below 0 dB and ends at the last one. A band still open at the
/// last sample has `to = ∞`. Samples with no value (`None`) end a band. When `refine` is given,
/// every crossing between two finite samples of opposite sign is refined by bisection on it.
pub fn bands(
    omegas: &[f64],
    values: &[Option<f64>],
    refine: Option<&dyn Fn(f64) -> f64>,
) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut start: Option<f64> = None;
    for i in 0..omegas.len() {
        let below = values[i].is_some_and(|t| t < 0.0);
        match (start, below) {
            (None, true) => {
                let from = match (i, refine) {
                    (0, _) => omegas[0],
                    (_, Some(f)) if values[i - 1].is_some() => {
                        crossing(f, omegas[i - 1], omegas[i])
                    }
                    _ => omegas[i],
                };
                start = Some(from);
            }
            (Some(from), false) => {
                let to = match refine {
                    Some(f) if values[i].is_some() => crossing(f, omegas[i - 1], omegas[i]),
                    _ => omegas[i - 1],
                };
                out.push((from, to));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(from) = start {
        out.push((from, f64::INFINITY));
    }
    out
}

/// Band edges are refined to this width, rad/s: far below any frequency the figures or the
/// report resolve.
const EDGE_RESOLUTION: f64 = 1e-12;

/// Bisection steps at most: 60 halvings take a bracket of any size that fits a frequency axis
/// below [`EDGE_RESOLUTION`].
const EDGE_BISECTIONS: usize = 60;

/// The zero of `f` between `a` and `b` (opposite signs), by bisection to [`EDGE_RESOLUTION`].
fn crossing(f: &dyn Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let fa = f(a);
    for _ in 0..EDGE_BISECTIONS {
        let m = 0.5 * (a + b);
        if (f(m) < 0.0) == (fa < 0.0) {
            a = m;
        } else {
            b = m;
        }
        if b - a < EDGE_RESOLUTION {
            break;
        }
    }
    0.5 * (a + b)
}

/// Formats bands as `1.500–2.200, 2.900–∞` (rad/s).
pub fn describe(bands: &[(f64, f64)]) -> String {
    if bands.is_empty() {
        return "none".to_owned();
    }
    bands
        .iter()
        .map(|(a, b)| {
            if b.is_infinite() {
                format!("{a:.3}–∞")
            } else {
                format!("{a:.3}–{b:.3}")
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_of_a_known_function() {
        // t(ω) = (ω − 1)(ω − 2)(ω − 3): negative on (−∞,1) ∪ (2,3).
        let f = |w: f64| (w - 1.0) * (w - 2.0) * (w - 3.0);
        let omegas: Vec<f64> = (0..=40).map(|i| 0.1 * i as f64 + 0.05).collect();
        let values: Vec<Option<f64>> = omegas.iter().map(|&w| Some(f(w))).collect();
        let b = bands(&omegas, &values, Some(&f));
        assert_eq!(b.len(), 2);
        assert_eq!(b[0].0, 0.05);
        assert!((b[0].1 - 1.0).abs() < 1e-10);
        assert!((b[1].0 - 2.0).abs() < 1e-10 && (b[1].1 - 3.0).abs() < 1e-10);
        let coarse = bands(&omegas, &values, None);
        assert!((coarse[0].1 - 0.95).abs() < 1e-12);
        assert_eq!(describe(&[(1.0, f64::INFINITY)]), "1.000–∞");
    }
}
