//! Closed-form quantities along one flight of a [`LinearModel`] (between two impacts): the
//! rigorous extrema of linear functionals of the state, the integral of a quadratic form of
//! the state, and the eigenvalues of a monodromy matrix of any size.
//!
//! The same methods as the unit's fixed-size [`crate::flow::ForcedFlow`], on the model's
//! augmented matrix `Â` (`(2n + P) × (2n + P)`, `P` the forcing's phase states: two without
//! harmonics): on pieces of the flight no longer than `1/max(Kω, |λ|)` (`K` the forcing's
//! highest order) every functional `c · z(t)` *is* its degree-24 Taylor polynomial to machine
//! precision, and its extrema are found among the piece's ends and the roots of its derivative
//! (by the unit's exclusion search); integrals of quadratic forms come from Van Loan's block
//! exponential.

use crate::flow::{polynomial_extrema, Extrema, MAX_PIECES, TAIL_TOLERANCE, TAYLOR_DEGREE};
use crate::model::LinearModel;
use crate::orbit::{SCHUR_EPSILON, SCHUR_ITERATIONS, SCHUR_SHIFTS};
use nalgebra::{Complex, DMatrix, DVector};

/// The augmented flow of a [`LinearModel`] at one frequency, with the rate that sets the
/// length of the pieces of the extremum search.
#[derive(Debug, Clone)]
pub struct ModelFlight {
    augmented: DMatrix<f64>,
    rate: f64,
}

impl ModelFlight {
    /// The flow of `model` at `omega` (> 0).
    pub fn new(model: &LinearModel, omega: f64) -> Self {
        let augmented = model.augmented_matrix(omega);
        let n = model.dofs();
        // |λ|² ≤ ‖M⁻¹K‖ + |λ| ‖M⁻¹C‖ for every eigenvalue of the quadratic pencil (row norms of
        // the acceleration rows of A).
        let row_norm = |col: usize| {
            (n..2 * n)
                .map(|i| (col..col + n).map(|j| augmented[(i, j)].abs()).sum::<f64>())
                .fold(0.0, f64::max)
        };
        let (k, c) = (row_norm(0), row_norm(n));
        let natural = 0.5 * (c + (c * c + 4.0 * k).sqrt());
        let fastest = match model.forcing().highest_order() {
            1 => omega,
            order => f64::from(order) * omega,
        };
        Self {
            augmented,
            rate: natural.max(fastest),
        }
    }

    /// The flow of the augmented matrix `augmented` whose eigenvalues and forcing turn no
    /// faster than `rate` (the length of the extremum search's pieces, `1/rate`).
    pub(crate) fn from_matrix(augmented: DMatrix<f64>, rate: f64) -> Self {
        Self { augmented, rate }
    }

    /// The rate that sets the extremum search's pieces: the fastest of the flow's eigenvalue
    /// bound and the forcing's highest frequency.
    pub(crate) fn rate(&self) -> f64 {
        self.rate
    }

    /// The augmented matrix `Â`.
    pub fn augmented_matrix(&self) -> &DMatrix<f64> {
        &self.augmented
    }

    /// Extrema of the linear functionals `c · z(t)` over `t ∈ [0, duration]` from the augmented
    /// state `start`, ends included, with the guarantee of the unit's fixed-size search (`ForcedFlow::extrema`):
    /// no extremum can fall between samples.
    ///
    /// # Panics
    /// If `start` or a functional does not have `2n + P` entries.
    pub fn extrema(
        &self,
        start: &DVector<f64>,
        duration: f64,
        functionals: &[DVector<f64>],
    ) -> Vec<Extrema> {
        self.mixed_extrema(start, duration, functionals, &[])
    }

    /// [`Self::extrema`] for the functionals whose `critical` flag is false (missing flags
    /// count as false), and for the others the extrema over the flight's *interior critical
    /// points* only, as [`crate::flow::ForcedFlow::critical_extrema`]: a functional monotone
    /// along the whole flight has `max = −∞`, `min = +∞` (and `NaN` times).
    ///
    /// # Panics
    /// If `start` or a functional does not have `2n + P` entries.
    pub fn mixed_extrema(
        &self,
        start: &DVector<f64>,
        duration: f64,
        functionals: &[DVector<f64>],
        critical: &[bool],
    ) -> Vec<Extrema> {
        let critical_only = |i: usize| critical.get(i).copied().unwrap_or(false);
        let mut found: Vec<Extrema> = functionals
            .iter()
            .enumerate()
            .map(|(i, c)| {
                if critical_only(i) {
                    Extrema {
                        max: f64::NEG_INFINITY,
                        argmax: f64::NAN,
                        min: f64::INFINITY,
                        argmin: f64::NAN,
                    }
                } else {
                    Extrema::at_start(c.dot(start))
                }
            })
            .collect();
        if duration <= 0.0 || functionals.is_empty() {
            return found;
        }
        let mut pieces = (duration * self.rate).ceil().max(1.0) as usize;
        let mut rows: Vec<Vec<DVector<f64>>> = Vec::with_capacity(functionals.len());
        let h = loop {
            let h = duration / pieces as f64;
            let step_t = (&self.augmented * h).transpose();
            rows.clear();
            let mut tail: f64 = 0.0;
            for c in functionals {
                let mut row = Vec::with_capacity(TAYLOR_DEGREE + 1);
                row.push(c.clone());
                for k in 1..=TAYLOR_DEGREE {
                    let next = &step_t * &row[k - 1] / k as f64;
                    row.push(next);
                }
                let size = c.lp_norm(1).max(f64::MIN_POSITIVE);
                tail = tail.max(
                    (row[TAYLOR_DEGREE].lp_norm(1) + row[TAYLOR_DEGREE - 1].lp_norm(1)) / size,
                );
                rows.push(row);
            }
            if tail <= TAIL_TOLERANCE || pieces >= MAX_PIECES {
                break h;
            }
            pieces *= 2;
        };
        let step = (&self.augmented * h).exp();
        let mut z = start.clone();
        let mut poly = [0.0; TAYLOR_DEGREE + 1];
        for piece in 0..pieces {
            let t0 = piece as f64 * h;
            for (i, (row, ext)) in rows.iter().zip(found.iter_mut()).enumerate() {
                for (pk, rk) in poly.iter_mut().zip(row.iter()) {
                    *pk = rk.dot(&z);
                }
                polynomial_extrema(&poly, ext, t0, h, critical_only(i));
            }
            z = &step * z;
        }
        found
    }

    /// `W = ∫₀^τ z(t) z(t)ᵀ dt` along the exact flow from `start`, in closed form by Van
    /// Loan's block exponential: `exp([[−Â, z₀z₀ᵀ], [0, Âᵀ]] τ) = [[·, G], [0, e^{Âᵀτ}]]` and
    /// `∫₀^τ e^{Âs} z₀z₀ᵀ e^{Âᵀs} ds = e^{Âτ} G`. Any quadratic rate `zᵀQz` (`Q` symmetric)
    /// integrates to `Σ Q_ij W_ij`: one exponential serves every energy term of a flight.
    ///
    /// # Panics
    /// If `start` does not have `2n + P` entries.
    pub fn second_moment(&self, start: &DVector<f64>, tau: f64) -> DMatrix<f64> {
        let m = self.augmented.nrows();
        let mut c = DMatrix::zeros(2 * m, 2 * m);
        c.view_mut((0, 0), (m, m)).copy_from(&(-&self.augmented));
        c.view_mut((0, m), (m, m))
            .copy_from(&(start * start.transpose()));
        c.view_mut((m, m), (m, m))
            .copy_from(&self.augmented.transpose());
        let ex = (c * tau).exp();
        ex.view((m, m), (m, m)).transpose() * ex.view((0, m), (m, m))
    }
}

/// The eigenvalues of a square matrix by the real Schur form with a bounded QR iteration,
/// with the fallbacks of the unit's closed-form eigenvalues (the transpose, then shifted copies):
/// `None` for a non-finite matrix or when every attempt fails.
pub fn eigenvalues(m: &DMatrix<f64>) -> Option<Vec<Complex<f64>>> {
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    let n = m.nrows();
    let scale = m.amax().max(f64::MIN_POSITIVE);
    let identity = DMatrix::<f64>::identity(n, n);
    let attempts = [
        (m.clone(), 0.0),
        (m.transpose(), 0.0),
        (
            m + &identity * (SCHUR_SHIFTS[0] * scale),
            SCHUR_SHIFTS[0] * scale,
        ),
        (
            m + &identity * (SCHUR_SHIFTS[1] * scale),
            SCHUR_SHIFTS[1] * scale,
        ),
    ];
    for (matrix, shift) in attempts {
        if let Some(schur) =
            nalgebra::linalg::Schur::try_new(matrix, SCHUR_EPSILON, SCHUR_ITERATIONS)
        {
            return Some(
                schur
                    .complex_eigenvalues()
                    .iter()
                    .map(|l| l - shift)
                    .collect(),
            );
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::{join, Augmented, ForcedFlow};
    use crate::test_models::{damped_paper_unit, paper_stops};
    use nalgebra::{Vector2, Vector4};

    /// On the unit, the general extremum search finds the fixed-size one's extrema (same
    /// method, matrices of another size): equal to a few ulps of the motion.
    #[test]
    fn extrema_of_the_unit_equal_the_fixed_size_flows() {
        let unit = damped_paper_unit();
        let model = LinearModel::unit(&unit, &paper_stops()).unwrap_or_else(|e| panic!("{e}"));
        let omega = 1.3;
        let fixed = ForcedFlow::new(&unit, omega);
        let general = ModelFlight::new(&model, omega);
        let x = Vector4::new(0.2, -0.4, 1.1, -0.7);
        let p = Vector2::new(0.6, 0.8);
        let c = Augmented::new(-1.0, 1.0, 0.0, 0.0, 0.0, 0.0);
        let e1 = fixed.extrema(&join(&x, &p), 7.0, &[c])[0];
        let start = DVector::from_column_slice(join(&x, &p).as_slice());
        let e2 = general.extrema(&start, 7.0, &[DVector::from_column_slice(c.as_slice())])[0];
        assert!((e1.max - e2.max).abs() < 1e-13, "{e1:?} {e2:?}");
        assert!((e1.min - e2.min).abs() < 1e-13, "{e1:?} {e2:?}");
        assert!((e1.argmax - e2.argmax).abs() < 1e-6 && (e1.argmin - e2.argmin).abs() < 1e-6);
    }

    /// `∫₀^τ p₀² dt` with `p₀ = cos(ωt)`: `τ/2 + sin(2ωτ)/(4ω)`, and `∫₀^τ p₀ p₁ dt` with
    /// `p₁ = sin(ωt)`: `sin²(ωτ)/(2ω)`, by hand, from the flight's second moment.
    #[test]
    fn second_moment_of_the_forcing_phase_is_exact() {
        let model = LinearModel::unit(&damped_paper_unit(), &paper_stops())
            .unwrap_or_else(|e| panic!("{e}"));
        let omega = 1.7;
        let flight = ModelFlight::new(&model, omega);
        let start = DVector::from_vec(vec![0.3, 0.1, -0.2, 0.4, 1.0, 0.0]);
        let tau = 2.3;
        let moment = flight.second_moment(&start, tau);
        let exact = tau / 2.0 + (2.0 * omega * tau).sin() / (4.0 * omega);
        assert!((moment[(4, 4)] - exact).abs() < 1e-13);
        let cross = (omega * tau).sin().powi(2) / (2.0 * omega);
        assert!((moment[(4, 5)] - cross).abs() < 1e-13);
        assert!((moment[(5, 4)] - cross).abs() < 1e-13);
    }
}
