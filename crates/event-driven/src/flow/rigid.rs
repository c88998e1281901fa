//! Rigid modes: the directions in which a structure moves as a rigid body, held by neither a
//! spring nor a dashpot (a free mass in a clearance, an impact damper's ball).
//!
//! A rigid mode is a vector `r` of the common null space `R` of `K` and `C`: `K r = C r = 0`.
//! On it the state matrix `A = [[0, I], [−M⁻¹K, −M⁻¹C]]` has the eigenvalue 0 with a `2 × 2`
//! Jordan block (`A (r, 0) = 0`, `A (0, r) = (r, 0)`: the position grows as `v t`), so `A`
//! has no basis of eigenvectors and the modal flow alone cannot describe it. The flow splits
//! the state space instead into two invariant subspaces:
//!
//! - the rigid subspace `{(R q, R p)}`: `A (R q, R p) = (R p, 0)`;
//! - its complement `{(u, v) : Rᵀ M u = Rᵀ M v = 0}` (the `M`-orthogonal complement of `R`
//!   in positions and in velocities): `Rᵀ M (−M⁻¹(K u + C v)) = −(K R)ᵀ u − (C R)ᵀ v = 0`
//!   when `Rᵀ K = 0` and `Rᵀ C = 0`, which holds for the symmetric `K` and `C` of a
//!   structure (a flow whose `R` is not also a left null space of `K` and `C` is refused,
//!   [`FlowError::UnbalancedRigidModes`]).
//!
//! On the complement the motion is the elastic modal flow: with an orthonormal basis `Q` of
//! `{u : Rᵀ M u = 0}`, `M⁻¹K Q = Q K_r` and `M⁻¹C Q = Q C_r` (`K_r = Qᵀ M⁻¹ K Q`,
//! `C_r = Qᵀ M⁻¹ C Q`), so the elastic rates are the eigenvalues of the reduced
//! `[[0, I], [−K_r, −C_r]]`, none of them the rigid zeros, and each elastic eigenvector comes
//! from the quadratic pencil as for any flow (`(λ²M + λC + K) φ = 0` with `λ ≠ 0` gives
//! `λ² Rᵀ M φ = 0`: it lies in the complement). The columns `V_e` of the elastic modes and
//! `S = [(R, 0), (0, R)]` of the rigid ones form a basis `W = [V_e | S]` of the state space;
//! the rows of `W⁻¹` give a state's elastic modal coordinates (its first rows) and its rigid
//! coordinates `q`, `p` (the last `2r`).
//!
//! On the rigid subspace `Rᵀ M R q̈ = Rᵀ f(t)`: the rigid coordinates move as free bodies,
//! `q̈ = g(t)`, `g = X_p (0, M⁻¹ f)` (`X_p` the velocity rows of `W⁻¹`). For the forcing
//! `g(t) = Re(F e^{iωt}) + g₀` (`F = g_c − i g_s` from `f_c cos ωt + f_s sin ωt`, `g₀` from a
//! constant force) a flight from `(q₀, p₀)` at `t₀` is, exactly,
//!
//! `q(s) = h_q + h_p s + g₀ s²/2 + Re(P e^{iωt₀} e^{iωs})`,
//! `p(s) = h_p + g₀ s + Re(iω P e^{iωt₀} e^{iωs})`,
//!
//! with the particular solution's amplitude `P = −F/ω²` and the deviations from it at the
//! start `h_q = q₀ − Re(P e^{iωt₀})`, `h_p = p₀ − Re(iω P e^{iωt₀})`: its homogeneous part
//! is the flow `(1, s; 0, 1)` of a rigid body, its particular part the zero-mean harmonic
//! response. A linear functional `a·q + b·p` of it is so a polynomial `α + β s + γ s²` (a
//! term of rate 0) plus a term of rate `iω`, which the exponential sums of [`crate::expsum`]
//! hold as they are (their terms are polynomials times exponentials), and search with their
//! guarantee (the polynomial's derivatives enter every bound).
//!
//! Each higher harmonic `Re(F_k e^{ikωt})` of the forcing adds its own particular solution
//! `P_k = −F_k/(kω)²` the same way (a rigid mode's rate 0 meets no `kω > 0`): a term of rate
//! `ikω` in the position, `ikω P_k` in the velocity, and in every functional.
//!
//! A constant force on a rigid mode (`g₀ ≠ 0`) accelerates it without bound: a flight stays
//! exact, but no steady state exists ([`FlowError::RigidDrift`] from
//! [`LinearFlow::linear_steady_state`](super::LinearFlow::linear_steady_state)). Without it
//! the linear steady state is a family: the zero-mean particular solution plus any constant
//! rigid position.

use super::{FlowError, C64};
use nalgebra::{DMatrix, DVector};

/// The fundamental's forcing `(f_c, f_s, f₀)` on `cos ωt`, `sin ωt` and the constant.
pub(crate) type Forcing<'a> = (&'a DVector<f64>, &'a DVector<f64>, &'a DVector<f64>);

/// A higher harmonic of the forcing: its rate `kω` and amplitudes `(f_c,k, f_s,k)`.
pub(crate) type HarmonicForce<'a> = (f64, &'a DVector<f64>, &'a DVector<f64>);

/// Singular values of `K` (and of `C` on `K`'s null space) at most this many times the
/// largest are rounding of an exact zero: a thousand rounding units, far above the few units
/// a singular matrix's computed singular values carry, far below any physical ratio of
/// stiffnesses (or dampings) that a model would hold.
pub(crate) const RIGID_ROUNDING: f64 = 1e3 * f64::EPSILON;

/// The rigid modes of a flow, prepared for its flights.
#[derive(Debug, Clone)]
pub(crate) struct RigidModes {
    /// `R` (`n × r`): the rigid shapes as columns, orthonormal.
    pub(crate) shapes: DMatrix<f64>,
    /// Rows `r × 2n` of `W⁻¹` giving the rigid positions `q = X_q y`.
    pub(crate) position_rows: DMatrix<f64>,
    /// Rows `r × 2n` of `W⁻¹` giving the rigid velocities `p = X_p y`.
    pub(crate) velocity_rows: DMatrix<f64>,
    /// The particular solution's amplitudes `P_j = −F_j/ω²` of the harmonic forcing.
    pub(crate) forced: Vec<C64>,
    /// Per higher harmonic, its rate `kω` and its particular solution's amplitudes
    /// `P_kj = −F_kj/(kω)²`.
    pub(crate) harmonics: Vec<(f64, Vec<C64>)>,
    /// The constant accelerations `g₀_j` of the constant force.
    pub(crate) constant: Vec<f64>,
}

/// The orthonormal basis of the right null space of `matrix` (`rows × cols`, `rows ≥ cols`)
/// to [`RIGID_ROUNDING`] of its largest singular value (the whole space for a zero matrix).
fn null_space(matrix: &DMatrix<f64>) -> DMatrix<f64> {
    let cols = matrix.ncols();
    if cols == 0 {
        return DMatrix::zeros(0, 0);
    }
    let largest = matrix.amax();
    if largest == 0.0 {
        return DMatrix::identity(cols, cols);
    }
    let svd = matrix.clone().svd(false, true);
    let (Some(v_t), values) = (svd.v_t, svd.singular_values) else {
        return DMatrix::zeros(cols, 0);
    };
    let top = values.iter().fold(0.0, |m: f64, &s| m.max(s));
    let null: Vec<usize> = (0..values.len())
        .filter(|&i| values[i] <= RIGID_ROUNDING * top)
        .collect();
    // A thin SVD of a wide matrix would hide null directions; every caller's is tall or
    // square, so that `v_t` is square.
    debug_assert_eq!(v_t.nrows(), cols);
    DMatrix::from_fn(cols, null.len(), |i, j| v_t[(null[j], i)])
}

/// The rigid shapes `R` (`n × r`, orthonormal columns; `r = 0` for a structure without rigid
/// modes): the common null space of `stiffness` and `damping`.
///
/// # Errors
/// [`FlowError::UnbalancedRigidModes`] when `R` is not also a left null space of both.
pub(crate) fn shapes(
    stiffness: &DMatrix<f64>,
    damping: Option<&DMatrix<f64>>,
) -> Result<DMatrix<f64>, FlowError> {
    let n = stiffness.nrows();
    let held = null_space(stiffness);
    if held.ncols() == 0 {
        return Ok(DMatrix::zeros(n, 0));
    }
    let shapes = match damping {
        Some(c) => {
            let on_null = c * &held;
            let scale = c.amax();
            // `C` on `K`'s null space, relative to `C` itself: a dashpot that holds a body
            // leaves it no rigid mode.
            let combination = if on_null.amax() <= RIGID_ROUNDING * scale {
                DMatrix::identity(held.ncols(), held.ncols())
            } else {
                let mut scaled = on_null;
                if scale > 0.0 {
                    scaled /= scale;
                }
                // `n × r_K` with `n ≥ r_K`: a tall matrix, its null space in full.
                let svd = scaled.clone().svd(false, true);
                let values = svd.singular_values;
                let v_t = svd.v_t.ok_or(FlowError::NoConvergence)?;
                let null: Vec<usize> = (0..values.len())
                    .filter(|&i| values[i] <= RIGID_ROUNDING)
                    .collect();
                DMatrix::from_fn(held.ncols(), null.len(), |i, j| v_t[(null[j], i)])
            };
            &held * combination
        }
        None => held,
    };
    let r = shapes.ncols();
    if r == 0 {
        return Ok(shapes);
    }
    let left = |m: &DMatrix<f64>| (shapes.transpose() * m).amax() <= RIGID_ROUNDING * m.amax();
    if !left(stiffness) || damping.is_some_and(|c| !left(c)) {
        return Err(FlowError::UnbalancedRigidModes(r));
    }
    Ok(shapes)
}

/// The elastic system's first-order matrix `[[0, I], [−K_r, −C_r]]` on an orthonormal basis
/// `Q` of the complement `{u : Rᵀ M u = 0}` of the rigid `shapes` (`K_r = Qᵀ M⁻¹ K Q`,
/// `C_r = Qᵀ M⁻¹ C Q`): its eigenvalues are the flow's elastic rates.
pub(crate) fn reduced_system(
    mass: &DMatrix<f64>,
    minv: &DMatrix<f64>,
    stiffness: &DMatrix<f64>,
    damping: Option<&DMatrix<f64>>,
    shapes: &DMatrix<f64>,
) -> DMatrix<f64> {
    let n = mass.nrows();
    // The complement is `(Mᵀ R)⊥`: the eigenvectors of the projector onto it with eigenvalue 1.
    let x = mass.transpose() * shapes;
    let gram = (x.transpose() * &x)
        .try_inverse()
        .unwrap_or_else(|| DMatrix::zeros(x.ncols(), x.ncols()));
    let projector = DMatrix::identity(n, n) - &x * gram * x.transpose();
    let eigen = nalgebra::SymmetricEigen::new(projector);
    let kept: Vec<usize> = (0..n).filter(|&i| eigen.eigenvalues[i] > 0.5).collect();
    let q = DMatrix::from_fn(n, kept.len(), |i, j| eigen.eigenvectors[(i, kept[j])]);
    let m = q.ncols();
    let mut a = DMatrix::<f64>::zeros(2 * m, 2 * m);
    a.view_mut((0, m), (m, m)).fill_with_identity();
    let kr = q.transpose() * (minv * (stiffness * &q));
    a.view_mut((m, 0), (m, m)).copy_from(&(-kr));
    if let Some(c) = damping {
        let cr = q.transpose() * (minv * (c * &q));
        a.view_mut((m, m), (m, m)).copy_from(&(-cr));
    }
    a
}

impl RigidModes {
    /// The rigid modes of `shapes` given the rows of `W⁻¹` that extract their coordinates
    /// (`rows`, `2r × 2n`: positions then velocities), `M⁻¹`, the forcing and its higher
    /// harmonics.
    pub(crate) fn new(
        shapes: DMatrix<f64>,
        rows: &DMatrix<C64>,
        minv: &DMatrix<f64>,
        ((forcing_cos, forcing_sin, forcing_constant), harmonics): (
            Forcing<'_>,
            &[HarmonicForce<'_>],
        ),
        omega: f64,
    ) -> Self {
        let r = shapes.ncols();
        let n = shapes.nrows();
        let position_rows = DMatrix::from_fn(r, 2 * n, |j, i| rows[(j, i)].re);
        let velocity_rows = DMatrix::from_fn(r, 2 * n, |j, i| rows[(r + j, i)].re);
        let acceleration = |f: &DVector<f64>| -> Vec<f64> {
            let a = minv * f;
            (0..r)
                .map(|j| (0..n).map(|i| velocity_rows[(j, n + i)] * a[i]).sum())
                .collect()
        };
        let (gc, gs, constant) = (
            acceleration(forcing_cos),
            acceleration(forcing_sin),
            acceleration(forcing_constant),
        );
        let particular = |gc: &[f64], gs: &[f64], rate: f64| -> Vec<C64> {
            gc.iter()
                .zip(gs)
                .map(|(&c, &s)| -C64::new(c, -s) / (rate * rate))
                .collect()
        };
        let forced = particular(&gc, &gs, omega);
        let harmonics = harmonics
            .iter()
            .map(|&(rate, cos, sin)| {
                (
                    rate,
                    particular(&acceleration(cos), &acceleration(sin), rate),
                )
            })
            .collect();
        RigidModes {
            shapes,
            position_rows,
            velocity_rows,
            forced,
            harmonics,
            constant,
        }
    }

    /// Rigid modes `r`.
    pub(crate) fn count(&self) -> usize {
        self.shapes.ncols()
    }

    /// Entries per rigid mode in a flight's start ([`Self::start`]): the deviations, the
    /// fundamental's particular amplitude, then each harmonic's.
    fn stride(&self) -> usize {
        2 + self.harmonics.len()
    }

    /// A flight's start in the general form: the modes' coordinates `elastic`, then per
    /// rigid mode [`Self::stride`] entries, `h_q + i h_p` (the deviations from the particular
    /// solution), `P e^{iωt₀}` (the particular solution's amplitude at the start) and each
    /// harmonic's `P_k e^{ikωt₀}`, from state `y` at forcing phase `e^{iωt₀}` and the
    /// harmonics' phases `e^{ikωt₀}`.
    #[cold]
    #[inline(never)]
    pub(crate) fn start(
        &self,
        elastic: DVector<C64>,
        y: &DVector<f64>,
        (phase, harmonic_phases): (C64, &[C64]),
        omega: f64,
    ) -> DVector<C64> {
        let count = elastic.len();
        let stride = self.stride();
        let mut out = elastic.resize_vertically(count + stride * self.count(), C64::default());
        for j in 0..self.count() {
            let at = count + stride * j;
            let q = self.position_rows.row(j).dot(&y.transpose());
            let p = self.velocity_rows.row(j).dot(&y.transpose());
            let forced = self.forced[j] * phase;
            let (mut hq, mut hp) = (q - forced.re, p - (forced * C64::new(0.0, omega)).re);
            for (h, ((rate, amplitudes), &phase)) in
                self.harmonics.iter().zip(harmonic_phases).enumerate()
            {
                let forced = amplitudes[j] * phase;
                hq -= forced.re;
                hp -= (forced * C64::new(0.0, *rate)).re;
                out[at + 2 + h] = forced;
            }
            out[at] = C64::new(hq, hp);
            out[at + 1] = forced;
        }
        out
    }

    /// Rigid mode `j`'s position and velocity at `s` into a flight whose start on it is
    /// `(h_q + i h_p, P e^{iωt₀}, P_k e^{ikωt₀}…)` ([`Self::start`]), given the forcing's
    /// `e^{iωs}` and the harmonics' `e^{ikωs}`.
    fn at(
        &self,
        j: usize,
        start: &[C64],
        s: f64,
        (ep, harmonic_exps): (C64, &[C64]),
        omega: f64,
    ) -> (f64, f64) {
        let (deviation, forced) = (start[0], start[1]);
        let g0 = self.constant[j];
        let oscillating = forced * ep;
        let mut q = deviation.re + deviation.im * s + 0.5 * g0 * s * s + oscillating.re;
        let mut p = deviation.im + g0 * s + (oscillating * C64::new(0.0, omega)).re;
        for (((rate, _), &forced), &e) in self.harmonics.iter().zip(&start[2..]).zip(harmonic_exps)
        {
            let oscillating = forced * e;
            q += oscillating.re;
            p += (oscillating * C64::new(0.0, *rate)).re;
        }
        (q, p)
    }

    /// Adds the rigid modes' state at `s` into `y` (length `2n`), from their `starts`
    /// ([`Self::stride`] entries each, [`Self::start`]), given the forcing's `e^{iωs}` and
    /// the harmonics' `e^{ikωs}`.
    #[cold]
    #[inline(never)]
    pub(crate) fn add_state(
        &self,
        starts: &[C64],
        s: f64,
        exps: (C64, &[C64]),
        omega: f64,
        y: &mut [f64],
    ) {
        let n = self.shapes.nrows();
        for (j, start) in starts.chunks_exact(self.stride()).enumerate() {
            let (q, p) = self.at(j, start, s, exps, omega);
            for i in 0..n {
                let shape = self.shapes[(i, j)];
                y[i] += shape * q;
                y[n + i] += shape * p;
            }
        }
    }

    /// The functional `c · y`'s modal `weights` followed by its weights `a_j + i b_j` on the
    /// rigid coordinates: `c · (R q, R p) = Σ_j a_j q_j + b_j p_j`.
    pub(crate) fn weights(&self, weights: DVector<C64>, c: &DVector<f64>) -> DVector<C64> {
        let n = self.shapes.nrows();
        let count = weights.len();
        let mut out = weights.resize_vertically(count + self.count(), C64::default());
        for j in 0..self.count() {
            let column = self.shapes.column(j);
            let a = (0..n).map(|i| c[i] * column[i]).sum();
            let b = (0..n).map(|i| c[n + i] * column[i]).sum();
            out[count + j] = C64::new(a, b);
        }
        out
    }

    /// The terms of `Σ_j a_j q_j(s) + b_j p_j(s)` for the functional's rigid `weights`
    /// (`a_j + i b_j`) over a flight from `starts` ([`Self::start`]): each mode's polynomial
    /// `α + β s + γ s²` (rate 0), its oscillating part `(a + iωb) P e^{iωt₀}` (rate `iω`) and
    /// each harmonic's `(a + ikωb) P_k e^{ikωt₀}` (rate `ikω`).
    #[cold]
    #[inline(never)]
    pub(crate) fn terms(
        &self,
        weights: &[C64],
        starts: &[C64],
        omega: f64,
        out: &mut Vec<crate::expsum::Term>,
    ) {
        let zero = C64::default();
        let real = |v: f64| C64::new(v, 0.0);
        for (j, (w, start)) in weights
            .iter()
            .zip(starts.chunks_exact(self.stride()))
            .enumerate()
        {
            let (a, b) = (w.re, w.im);
            let (deviation, forced) = (start[0], start[1]);
            let g0 = self.constant[j];
            out.push(crate::expsum::Term {
                poly: [
                    real(a * deviation.re + b * deviation.im),
                    real(a * deviation.im + b * g0),
                    real(0.5 * a * g0),
                    zero,
                ],
                rate: zero,
            });
            out.push(crate::expsum::Term {
                poly: [C64::new(a, omega * b) * forced, zero, zero, zero],
                rate: C64::new(0.0, omega),
            });
            for ((rate, _), &forced) in self.harmonics.iter().zip(&start[2..]) {
                out.push(crate::expsum::Term {
                    poly: [C64::new(a, rate * b) * forced, zero, zero, zero],
                    rate: C64::new(0.0, *rate),
                });
            }
        }
    }

    /// Adds the rigid part of the propagator `e^{As}` into `out` (`2n × 2n`): `q ← q + s p`,
    /// `p ← p` on the rigid coordinates, `R (X_q + s X_p)` on the position rows and `R X_p`
    /// on the velocity rows.
    pub(crate) fn add_propagator(&self, s: f64, out: &mut DMatrix<f64>) {
        let n = self.shapes.nrows();
        for j in 0..self.count() {
            for c in 0..2 * n {
                let (xq, xp) = (self.position_rows[(j, c)], self.velocity_rows[(j, c)]);
                let moved = xq + s * xp;
                for i in 0..n {
                    let shape = self.shapes[(i, j)];
                    out[(i, c)] += shape * moved;
                    out[(n + i, c)] += shape * xp;
                }
            }
        }
    }

    /// The rigid part of the linear steady state at time `t`: the zero-mean particular
    /// solution `q = Re(P e^{iωt}) + Σ_k Re(P_k e^{ikωt})`, `p` its derivative, added into
    /// `y`, given the phases `e^{iωt}` and the harmonics' `e^{ikωt}`.
    ///
    /// # Errors
    /// [`FlowError::RigidDrift`] when a constant force acts on a rigid mode.
    pub(crate) fn add_steady_state(
        &self,
        (phase, harmonic_phases): (C64, &[C64]),
        omega: f64,
        y: &mut [f64],
    ) -> Result<(), FlowError> {
        if let Some(j) = self.constant.iter().position(|&g| g != 0.0) {
            return Err(FlowError::RigidDrift(j));
        }
        let starts: Vec<C64> = (0..self.count())
            .flat_map(|j| {
                let harmonics = self
                    .harmonics
                    .iter()
                    .zip(harmonic_phases)
                    .map(move |((_, amplitudes), &phase)| amplitudes[j] * phase);
                [C64::default(), self.forced[j] * phase]
                    .into_iter()
                    .chain(harmonics)
            })
            .collect();
        let ones = vec![C64::new(1.0, 0.0); self.harmonics.len()];
        self.add_state(&starts, 0.0, (C64::new(1.0, 0.0), &ones), omega, y);
        Ok(())
    }
}

/// The rigid modes of a model, from its matrices: the query lives with the flow that finds
/// them, so that the model does not depend on the flow.
impl crate::Model {
    /// Rigid modes `r` of the structure: the dimension of the common null space of its
    /// stiffness and damping matrices (`K r = C r = 0`), one per direction a free body (held
    /// by neither a spring nor a dashpot, e.g. a mass in a clearance with contact pairs only)
    /// moves in. The simulator flies them exactly as rigid bodies ([`crate::LinearFlow`]); a
    /// steady state without impacts on them is a family ([`crate::SteadyState::family`]).
    ///
    /// # Errors
    /// [`FlowError::UnbalancedRigidModes`] when
    /// that null space is not also a left null space of both (non-symmetric matrices).
    pub fn rigid_modes(&self) -> Result<usize, FlowError> {
        shapes(&self.stiffness, self.damping.as_ref()).map(|r| r.ncols())
    }
}
