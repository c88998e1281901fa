//! The periodic forcing of a [`crate::LinearModel`]: a fundamental harmonic and any higher
//! harmonics of integer order, all of the period `2π/ω`, and the phase states that carry them
//! in the augmented state.
//!
//! **The force.** With `θ = ωt + α`,
//!
//! ```text
//! f(t) = f_c cos θ + (f_s + ω f_ω) sin θ
//!      + Σ_k [ f_c,k cos(kθ + φ_k) + (f_s,k + kω f_ω,k) sin(kθ + φ_k) ]
//! ```
//!
//! over the listed harmonics, each of order `k ≥ 2` ([`Harmonic`]). The `ω`-proportional sine
//! parts carry base dashpots: a base motion `u_g(t) = a cos(kθ + φ)` acting through a spring
//! `k_o` and a dashpot `c_o` pushes with `k_o a cos(kθ + φ) − c_o kω a sin(kθ + φ)`, so a
//! harmonic's `sine_per_omega` is per unit of *its own* frequency `kω`: the harmonic of the base
//! motion has `f_c = k_o a`, `f_s = 0`, `f_ω = −c_o a` and phase `φ`, the same vectors per unit
//! amplitude as the fundamental's. The phase `φ_k` places a harmonic against the fundamental
//! (`0.3 cos(2ωt + 0.5)` has `φ = 0.5`); with a dashpot it cannot be folded into `f_c` and
//! `f_s`, whose cosine part would then grow with `ω`.
//!
//! **The phase states.** The augmented state is `z = (u, u̇, p)`,
//! `p = (cos θ, sin θ, cos k₁θ, sin k₁θ, …)`: two states for the fundamental, then two per
//! harmonic in the order of [`HarmonicForcing::harmonics`] ([`HarmonicForcing::orders`]
//! lists `1, k₁, k₂, …`). Each pair turns at its own rate, `d/dt (cos kθ, sin kθ) =
//! kω J (cos kθ, sin kθ)`, `J = [[0, −1], [1, 0]]`, and the force is linear in `p`:
//! `f = F(ω) p`, the columns of `F` ([`HarmonicForcing::columns`]) being `f_c` and
//! `f_s + ω f_ω` for the fundamental and, for harmonic `k` (the angle sum expanded),
//! `f_c,k cos φ_k + s_k sin φ_k` and `s_k cos φ_k − f_c,k sin φ_k`, `s_k = f_s,k + kω f_ω,k`.
//! So `Â = [[A, B], [0, W]]` with `B = [[0], [M⁻¹F(ω)]]` and `W = diag(ωJ, k₁ωJ, …)`.
//!
//! **Derivatives.** `Â` is affine in `ω`: `dÂ/dω` holds `M⁻¹F'` with `F'` the columns `0`,
//! `f_ω` for the fundamental and `k f_ω,k sin φ_k`, `k f_ω,k cos φ_k` for harmonic `k`
//! ([`HarmonicForcing::columns_rate`]), and the rotation blocks `diag(J, k₁J, …)`: exact for
//! continuation in `ω`. At the first impact the phase states are `p(α) = (cos kα, sin kα)` for
//! each order ([`phase_pair`], [`phase_state`]), whose derivative in the base phase `α` is
//! `k (−sin kα, cos kα)` ([`slope_pair`]).
//!
//! A forcing without harmonics has the two phase states of the fundamental alone: the same
//! augmented size `2n + 2`, matrices and results as a purely harmonic forcing.

use nalgebra::{DMatrix, DVector};

/// One higher harmonic of a [`HarmonicForcing`], of integer order `k ≥ 2`:
/// `f_k(t) = f_c cos(kθ + φ) + (f_s + kω f_ω) sin(kθ + φ)`, `θ = ωt + α`.
///
/// `sine_per_omega` is per unit of the harmonic's own frequency `kω`: a base motion
/// `a cos(kθ + φ)` through a spring `k_o` and a dashpot `c_o` has `cosine = k_o a`,
/// `sine = 0`, `sine_per_omega = −c_o a` and `phase = φ` (see the module's derivation).
#[derive(Debug, Clone, PartialEq)]
pub struct Harmonic {
    /// The order `k ≥ 2`: the harmonic turns at `kω`. Each order appears once in a forcing.
    pub order: u32,
    /// `f_c`: amplitude of the cosine part.
    pub cosine: DVector<f64>,
    /// `f_s`: the frequency-independent amplitude of the sine part.
    pub sine: DVector<f64>,
    /// `f_ω`: the sine amplitude per unit of the harmonic's frequency `kω`.
    pub sine_per_omega: DVector<f64>,
    /// `φ`: the harmonic's phase against the fundamental, radians (finite).
    pub phase: f64,
}

impl Harmonic {
    /// The sine amplitude at `omega`: `f_s + kω f_ω`.
    pub fn sine_at(&self, omega: f64) -> DVector<f64> {
        &self.sine + &self.sine_per_omega * (f64::from(self.order) * omega)
    }

    /// The force's amplitudes on `(cos kθ, sin kθ)` at `omega`: the angle sum of
    /// `f_c cos(kθ + φ) + s sin(kθ + φ)` expanded, `(f_c cos φ + s sin φ, s cos φ − f_c sin φ)`
    /// with `s = f_s + kω f_ω`; `(f_c, s)` exactly when `φ = 0`.
    pub fn columns_at(&self, omega: f64) -> (DVector<f64>, DVector<f64>) {
        let sine = self.sine_at(omega);
        if self.phase == 0.0 {
            return (self.cosine.clone(), sine);
        }
        let (s, c) = self.phase.sin_cos();
        (&self.cosine * c + &sine * s, &sine * c - &self.cosine * s)
    }

    /// `d/dω` of [`Harmonic::columns_at`]: `k f_ω (sin φ, cos φ)`.
    pub fn columns_rate(&self) -> (DVector<f64>, DVector<f64>) {
        let rate = &self.sine_per_omega * f64::from(self.order);
        let (s, c) = self.phase.sin_cos();
        (&rate * s, &rate * c)
    }
}

/// Periodic forcing of period `2π/ω`: the fundamental
/// `f(t) = f_c cos θ + (f_s + ω f_ω) sin θ`, `θ = ωt + α`, and the higher harmonics
/// `harmonics` ([`Harmonic`], integer orders `k ≥ 2`, each once), summed.
///
/// The `ω`-proportional sine parts carry base dashpots (`−c ω u_g sin θ` for the fundamental,
/// `−c kω a sin(kθ + φ)` for a harmonic), so that the derivative in `ω` stays exact for
/// continuation: `∂f/∂ω = f_ω sin θ + Σ k f_ω,k sin(kθ + φ_k)` at fixed `θ`. The derivation
/// of the phase states is in the module's documentation.
#[derive(Debug, Clone, PartialEq)]
pub struct HarmonicForcing {
    /// `f_c`: amplitude of the fundamental's cosine part.
    pub cosine: DVector<f64>,
    /// `f_s`: the frequency-independent amplitude of the fundamental's sine part.
    pub sine: DVector<f64>,
    /// `f_ω`: the fundamental's sine amplitude per unit `ω`.
    pub sine_per_omega: DVector<f64>,
    /// The higher harmonics, in the order of their phase states (empty: the fundamental
    /// alone).
    pub harmonics: Vec<Harmonic>,
}

impl HarmonicForcing {
    /// The fundamental alone: `f_c cos θ + (f_s + ω f_ω) sin θ`, no harmonics.
    pub fn fundamental(
        cosine: DVector<f64>,
        sine: DVector<f64>,
        sine_per_omega: DVector<f64>,
    ) -> Self {
        Self {
            cosine,
            sine,
            sine_per_omega,
            harmonics: Vec::new(),
        }
    }

    /// The fundamental's sine amplitude at `omega`: `f_s + ω f_ω`.
    pub fn sine_at(&self, omega: f64) -> DVector<f64> {
        &self.sine + &self.sine_per_omega * omega
    }

    /// The order of each pair of phase states: `1` (the fundamental), then each harmonic's
    /// order in the order of [`HarmonicForcing::harmonics`].
    pub fn orders(&self) -> Vec<u32> {
        std::iter::once(1)
            .chain(self.harmonics.iter().map(|h| h.order))
            .collect()
    }

    /// Number of phase states: two for the fundamental and two per harmonic.
    pub fn phase_states(&self) -> usize {
        2 * (1 + self.harmonics.len())
    }

    /// The highest order of a harmonic that exerts a force (some entry of its vectors not
    /// zero), 1 otherwise: the forcing's fastest frequency is this times `ω`, which sets the
    /// multi-start's grid and `α` scan and the pieces of the flights' extremum search. A
    /// harmonic of amplitude zero does not count, so that it changes no result.
    pub fn highest_order(&self) -> u32 {
        self.harmonics
            .iter()
            .filter(|h| {
                [&h.cosine, &h.sine, &h.sine_per_omega]
                    .iter()
                    .any(|v| v.iter().any(|&x| x != 0.0))
            })
            .map(|h| h.order)
            .fold(1, u32::max)
    }

    /// `F(ω)` (`n ×` [`HarmonicForcing::phase_states`]): the force is `f = F(ω) p` on the
    /// phase states `p` (columns `f_c`, `f_s + ω f_ω`, then [`Harmonic::columns_at`] of each
    /// harmonic).
    pub fn columns(&self, omega: f64) -> DMatrix<f64> {
        let mut f = DMatrix::zeros(self.cosine.len(), self.phase_states());
        f.set_column(0, &self.cosine);
        f.set_column(1, &self.sine_at(omega));
        for (i, h) in self.harmonics.iter().enumerate() {
            let (c, s) = h.columns_at(omega);
            f.set_column(2 + 2 * i, &c);
            f.set_column(3 + 2 * i, &s);
        }
        f
    }

    /// `dF/dω` of [`HarmonicForcing::columns`]: `0`, `f_ω`, then [`Harmonic::columns_rate`]
    /// of each harmonic (exact: `F` is affine in `ω`).
    pub fn columns_rate(&self) -> DMatrix<f64> {
        let mut f = DMatrix::zeros(self.cosine.len(), self.phase_states());
        f.set_column(1, &self.sine_per_omega);
        for (i, h) in self.harmonics.iter().enumerate() {
            let (c, s) = h.columns_rate();
            f.set_column(2 + 2 * i, &c);
            f.set_column(3 + 2 * i, &s);
        }
        f
    }
}

/// The phase states `(cos kα, sin kα)` of order `k` at `θ = alpha` (`(cos α, sin α)` exactly
/// for order 1).
pub fn phase_pair(order: u32, alpha: f64) -> (f64, f64) {
    if order == 1 {
        (alpha.cos(), alpha.sin())
    } else {
        let (s, c) = (f64::from(order) * alpha).sin_cos();
        (c, s)
    }
}

/// `d/dα` of [`phase_pair`]: `k (−sin kα, cos kα)` (`(−sin α, cos α)` exactly for order 1).
pub fn slope_pair(order: u32, alpha: f64) -> (f64, f64) {
    if order == 1 {
        (-alpha.sin(), alpha.cos())
    } else {
        let k = f64::from(order);
        let (s, c) = (k * alpha).sin_cos();
        (-k * s, k * c)
    }
}

/// What the phase rows of an augmented vector hold: written in place
/// ([`PhaseRows::write`]), so that an evaluation of the cycle equations allocates nothing for
/// them.
#[derive(Debug, Clone, Copy)]
pub(crate) enum PhaseRows<'a> {
    /// The phase states at the base phase `α`: [`phase_pair`] of each order.
    At(f64),
    /// Their derivative in `α`: [`slope_pair`] of each order.
    Slope(f64),
    /// Zero: the phase at the first impact does not move.
    Still,
    /// The given entries, one per phase state.
    Given(&'a [f64]),
}

impl PhaseRows<'_> {
    /// Writes the rows into `rows`, two per order of `orders` (`Given` writes its entries).
    ///
    /// # Panics
    /// If `rows` is shorter than the entries written.
    #[inline]
    pub(crate) fn write(self, orders: &[u32], rows: &mut [f64]) {
        match self {
            Self::Given(values) => rows[..values.len()].copy_from_slice(values),
            Self::Still => rows.fill(0.0),
            Self::At(alpha) | Self::Slope(alpha) => {
                for (pair, &k) in rows.chunks_exact_mut(2).zip(orders) {
                    let (c, s) = match self {
                        Self::At(_) => phase_pair(k, alpha),
                        _ => slope_pair(k, alpha),
                    };
                    pair[0] = c;
                    pair[1] = s;
                }
            }
        }
    }
}

/// The phase states at `θ = alpha` of pairs of the given `orders`: `(cos kθ, sin kθ)` of each
/// order, in order.
pub fn phase_state(orders: &[u32], alpha: f64) -> Vec<f64> {
    orders
        .iter()
        .flat_map(|&k| {
            let (c, s) = phase_pair(k, alpha);
            [c, s]
        })
        .collect()
}

/// Samples per period of the highest order in [`trig_extremes`]' search: the extrema of a
/// trigonometric polynomial of degree `K` are at most `2K` critical points, so 32 samples per
/// shortest period put at least eight between any two that are a quarter of that period
/// apart, and each is polished from its nearest sample by Newton.
const SAMPLES_PER_PERIOD: usize = 32;

/// Newton steps polishing each sampled extremum of [`trig_extremes`]: from within half a
/// sample spacing, quadratic convergence reaches rounding in three or four.
const POLISH_STEPS: usize = 8;

/// `(min, max)` over `θ` of the trigonometric polynomial `Σ a cos kθ + b sin kθ` of the terms
/// `(k, a, b)`. Terms with `a = b = 0` are left out; a single term of order 1 then gives
/// `(−√(a² + b²), √(a² + b²))` in closed form (bit for bit a purely harmonic motion's);
/// otherwise the polynomial is sampled at [`SAMPLES_PER_PERIOD`] points per period of its
/// highest order and every sampled local extremum polished by Newton on the derivative (a step
/// kept only when it improves the value).
pub(crate) fn trig_extremes(terms: &[(u32, f64, f64)]) -> (f64, f64) {
    // Terms of amplitude zero change nothing: left out, so that a zero harmonic keeps the
    // closed form of the fundamental alone.
    let terms: Vec<(u32, f64, f64)> = terms
        .iter()
        .copied()
        .filter(|&(_, a, b)| a != 0.0 || b != 0.0)
        .collect();
    match terms.as_slice() {
        [] => return (0.0, 0.0),
        [(1, a, b)] => {
            let amplitude = a.hypot(*b);
            return (-amplitude, amplitude);
        }
        _ => {}
    }
    let value = |theta: f64, derivative: u32| {
        terms.iter().fold(0.0, |sum, &(k, a, b)| {
            let kf = f64::from(k);
            let (s, c) = (kf * theta).sin_cos();
            // The `derivative`-th derivative of a cos kθ + b sin kθ.
            let (dc, ds) = match derivative % 4 {
                0 => (c, s),
                1 => (-s, c),
                2 => (-c, -s),
                _ => (s, -c),
            };
            sum + kf.powi(derivative as i32) * (a * dc + b * ds)
        })
    };
    let highest = terms.iter().map(|t| t.0).fold(1, u32::max) as usize;
    let samples = SAMPLES_PER_PERIOD * highest;
    let h = std::f64::consts::TAU / samples as f64;
    let values: Vec<f64> = (0..samples).map(|i| value(i as f64 * h, 0)).collect();
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..samples {
        let (before, here, after) = (
            values[(i + samples - 1) % samples],
            values[i],
            values[(i + 1) % samples],
        );
        let peak = here >= before && here >= after;
        let trough = here <= before && here <= after;
        if !(peak || trough) {
            low = low.min(here);
            high = high.max(here);
            continue;
        }
        let mut theta = i as f64 * h;
        let mut best = here;
        for _ in 0..POLISH_STEPS {
            let curvature = value(theta, 2);
            if curvature == 0.0 {
                break;
            }
            let step = -value(theta, 1) / curvature;
            if !step.is_finite() || step.abs() > h {
                break;
            }
            let next = value(theta + step, 0);
            let better = if peak { next > best } else { next < best };
            if !better {
                break;
            }
            theta += step;
            best = next;
        }
        low = low.min(best);
        high = high.max(best);
    }
    (low, high)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `cos θ + cos 2θ` has the maximum 2 at `θ = 0` and the minimum `−9/8` where
    /// `cos θ = −1/4` (`2c² + c − 1` least at `c = −1/4`); `sin 3θ − 0.5 cos 2θ`, shifted so
    /// that no extremum falls on a sample, against a fine scan.
    #[test]
    fn extremes_of_trigonometric_polynomials() {
        let (low, high) = trig_extremes(&[(1, 1.0, 0.0), (2, 1.0, 0.0)]);
        assert!((high - 2.0).abs() <= 4.0 * f64::EPSILON, "{high}");
        assert!((low + 1.125).abs() <= 4.0 * f64::EPSILON, "{low}");
        let terms = [(1, 0.3, 0.7), (3, 0.0, 1.0), (2, -0.5, 0.1)];
        let (low, high) = trig_extremes(&terms);
        let f = |t: f64| {
            0.3 * t.cos() + 0.7 * t.sin() + (3.0 * t).sin() - 0.5 * (2.0 * t).cos()
                + 0.1 * (2.0 * t).sin()
        };
        let fine = 1_000_000;
        let (mut l, mut u) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..fine {
            let v = f(std::f64::consts::TAU * i as f64 / fine as f64);
            l = l.min(v);
            u = u.max(v);
        }
        // The scan's own error: h²/8 · max|f''| ≤ (2π/10⁶)²/8 · 11.3 ≈ 6e-11.
        assert!(high >= u - 1e-14 && high - u <= 1e-10, "{high} vs {u}");
        assert!(low <= l + 1e-14 && l - low <= 1e-10, "{low} vs {l}");
    }

    /// The phase states and their slope in `α`: order 1 bit for bit `(cos α, sin α)` and
    /// `(−sin α, cos α)`; the slope against a central difference.
    #[test]
    fn phase_states_and_their_slope() {
        let alpha = 0.83;
        let orders = [1, 3, 2];
        let p = phase_state(&orders, alpha);
        assert_eq!(p[0].to_bits(), alpha.cos().to_bits());
        assert_eq!(p[1].to_bits(), alpha.sin().to_bits());
        assert!((p[2] - (3.0 * alpha).cos()).abs() <= f64::EPSILON);
        let slope: Vec<f64> = orders
            .iter()
            .flat_map(|&k| {
                let (c, s) = slope_pair(k, alpha);
                [c, s]
            })
            .collect();
        assert_eq!(slope[0].to_bits(), (-alpha.sin()).to_bits());
        let step = 1e-6;
        let (up, down) = (
            phase_state(&orders, alpha + step),
            phase_state(&orders, alpha - step),
        );
        for i in 0..6 {
            let quotient = (up[i] - down[i]) / (2.0 * step);
            // Truncation k³h²/6 ≤ 5e-12, rounding ε/h ≈ 2e-10.
            assert!(
                (quotient - slope[i]).abs() <= 1e-9,
                "{i}: {quotient} vs {}",
                slope[i]
            );
        }
    }
}
