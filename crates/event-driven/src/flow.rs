//! The closed-form flow of a linear system `M ü + C u̇ + K u = f_c cos ωt + f_s sin ωt + f₀`
//! between events, by its complex modal decomposition.
//!
//! With the first-order state `y = (u, u̇)` and `A = [[0, I], [−M⁻¹K, −M⁻¹C]] = V Λ V⁻¹`,
//! the modal coordinates `z = V⁻¹ y` obey `ż_k = λ_k z_k + g⁺_k e^{iωt} + g⁻_k e^{−iωt} + g⁰_k`,
//! whose exact solution over a time `s` is
//! `z_k(s) = e^{λ_k s} z_k(0) + Σ G_k φ(λ_k, μ, s)`, `φ(λ, μ, s) = ∫₀ˢ e^{λ(s−σ)} e^{μσ} dσ`.
//! `φ` is evaluated in a form that stays finite when `μ = λ` (exact resonance of an undamped
//! mode): as `(e^{μs} − e^{λs})/(μ − λ)` when `|μ − λ| T` is large, and as
//! `e^{λs}(s + δs²/2 + δ²s³/6)`, `δ = μ − λ`, when it is below `10⁻⁴`.
//! Away from resonance (every `|μ − λ| T` above `10⁻⁴`) a flight is written instead as the
//! steady forced response `z_p(t)` plus the deviation from it, `z(s) = e^{λs} ∘ (z(0) − z_p(t₀))
//! + z_p(t₀ + s)`: the same motion with one exponential per mode and one for the forcing, which
//! is what the event search evaluates over and over. Conjugate modes of the real system are
//! folded into one (`Re Σ = 2 Re` of one of each pair), halving the exponentials again.
//! The eigenvectors come from the quadratic pencil: `(λ²M + λC + K) φ = 0`, `v = (φ, λφ)`.

use crate::expsum::{summarize_block, ExpSum, ModeTerm, Summary, Term, LANES};
use nalgebra::{Complex, DMatrix, DVector};
use thiserror::Error;

type C64 = Complex<f64>;

/// Why a flow could not be built.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FlowError {
    /// The mass matrix is singular.
    #[error("the mass matrix is singular")]
    SingularMass,
    /// The system matrix is defective (repeated eigenvalues without a full set of
    /// eigenvectors, e.g. exactly critical damping): the modal flow does not exist.
    #[error("the system is defective (e.g. exactly critically damped): condition number {0:e}")]
    Defective(f64),
    /// The system matrix has a non-finite entry (masses, stiffnesses or dampings whose
    /// ratios overflow).
    #[error("the system matrix is not finite (masses, stiffnesses or dampings out of range)")]
    NotFinite,
    /// The eigenvalue iteration did not converge.
    #[error("the eigenvalues of the system matrix did not converge")]
    NoConvergence,
}

/// Below this `|μ − λ|·T` a forcing rate counts as resonant with a mode.
const RESONANCE: f64 = 1e-4;

/// A modal basis whose condition number (Frobenius) reaches this is defective (e.g. exactly
/// critically damped): modal coordinates would lose more than ten of the sixteen digits.
const DEFECTIVE_CONDITION: f64 = 1e10;

/// Iteration cap of each Schur decomposition tried for the eigenvalues (nalgebra's QR
/// iterations; a convergent one takes a few per eigenvalue).
const SCHUR_ITERATIONS: usize = 1000;

/// Shifts (times the matrix's largest entry) of the retries when the Schur iteration on the
/// matrix and its transpose fails: a shift moves the spectrum off a symmetric configuration
/// that stalls the iteration; 0.37 is deliberately not a simple fraction.
const SCHUR_SHIFTS: [f64; 2] = [0.5, -0.37];

/// The modal flow of one linear system at one forcing frequency.
#[derive(Debug, Clone)]
pub struct LinearFlow {
    /// Degrees of freedom `n`; the state has `2n` entries.
    dofs: usize,
    omega: f64,
    period: f64,
    /// Eigenvalues `λ_k` of `A`.
    rates: Vec<C64>,
    /// Eigenvectors as columns.
    modes: DMatrix<C64>,
    /// `V⁻¹`.
    inverse: DMatrix<C64>,
    /// `V⁻¹` row by row (row `k` at `k·2n..(k + 1)·2n`), real and imaginary parts apart: the
    /// modal coordinates of a state as contiguous dot products.
    inverse_rows: (Vec<f64>, Vec<f64>),
    /// `V⁻¹` column by column over the kept modes only (column `j` at
    /// `j·kept..(j + 1)·kept`, in the order of `kept`): a jump of state entry `j` as one
    /// contiguous run of products ([`Self::add_jump`]).
    kept_inverse_columns: Vec<C64>,
    /// The eigenvectors column by column (column `k` at `k·2n..(k + 1)·2n`), real and
    /// imaginary parts apart: a state from its modal coordinates as contiguous sums.
    mode_columns: (Vec<f64>, Vec<f64>),
    /// Modal forcing on `e^{+iωt}`, `e^{−iωt}` and the constant.
    plus: DVector<C64>,
    minus: DVector<C64>,
    constant: DVector<C64>,
    /// The modes that carry a real motion: one of each conjugate pair (weight 2) and every
    /// real mode (weight 1), so that `Re Σ_all = Σ_kept weight · Re`.
    kept: Vec<(usize, f64)>,
    /// Per kept mode, `|Re λ| + |Im λ|` and its cube `(r · r) · r`, for [`Flight::summarize`].
    kept_sizes: Vec<(f64, f64)>,
    /// Per kept mode, [`LinearFlow::kept_peaks`].
    kept_peaks: Vec<(f64, f64)>,
    /// The modes as [`Flight::summarize_all`] adds them, every kept mode then the forcing
    /// (their deviations zero: a flight writes its own), formed once for the flow; `None`
    /// where it gives no joint summaries (a rate grows, no mode is kept, or a kept mode has
    /// rate zero). Formed once: building them and checking the rates at every flight would
    /// cost a chain some 3 % of its instructions.
    joint_modes: Option<Vec<ModeTerm>>,
    /// The forced steady response, when no mode is resonant with the forcing.
    steady: Option<SteadyResponse>,
}

/// The forced steady response in modal coordinates,
/// `z_p(t) = P⁺ e^{iωt} + P⁻ e^{−iωt} + P⁰`, `P^±_k = g^±_k/(±iω − λ_k)`, `P⁰_k = −g⁰_k/λ_k`.
#[derive(Debug, Clone)]
struct SteadyResponse {
    plus: Vec<C64>,
    minus: Vec<C64>,
    constant: Vec<C64>,
}

impl SteadyResponse {
    /// Kept mode `j`'s coordinate `(h_j e^{λ_j s} + P⁺_j F + P⁻_j F̄ + P⁰_j)·weight` from its
    /// decayed deviation `h_j e^{λ_j s}` and the forcing's phase `F` at `s`: the one form
    /// of it ([`Flight::state_at`] adds the state from these, [`Flight::modal_state`] hands
    /// them out; [`pair_coordinates_avx`] packs the same operations two modes at a time).
    #[inline(always)]
    fn coordinate(&self, j: usize, decayed: C64, forced: C64, weight: f64) -> C64 {
        (decayed + self.plus[j] * forced + self.minus[j] * forced.conj() + self.constant[j])
            * weight
    }

    /// The response of the kept modes only, in the order of `kept` (contiguous, as the
    /// flights' deviations are).
    fn of_kept(self, kept: &[(usize, f64)]) -> Self {
        let pick = |v: &[C64]| kept.iter().map(|&(k, _)| v[k]).collect();
        Self {
            plus: pick(&self.plus),
            minus: pick(&self.minus),
            constant: pick(&self.constant),
        }
    }
}

/// A linear functional `c · y` of the state, prepared for fast flights: its modal weights
/// `Vᵀc` and, when the flow has a steady response, that response's contribution
/// `Re(forced e^{iωt}) + constant`.
#[derive(Debug, Clone)]
pub struct Functional {
    weights: DVector<C64>,
    forced: C64,
    constant: f64,
}

/// Several functionals prepared for [`Flight::summarize_all`]: in blocks of [`LANES`]
/// functionals, per kept mode, their modal weights `[Re w₀, …, Re w₃, Im w₀, …, Im w₃]`, then
/// their forced parts likewise (a last block filled up with zeros), and each functional's
/// constant.
#[derive(Debug, Clone, Default)]
pub(crate) struct JointWeights {
    count: usize,
    blocks: Vec<[f64; 2 * LANES]>,
    constant: Vec<f64>,
}

/// A flight: the flow from a given state at a given forcing phase.
#[derive(Debug, Clone)]
pub struct Flight<'a> {
    flow: &'a LinearFlow,
    form: Form<'a>,
}

#[derive(Debug, Clone)]
enum Form<'a> {
    /// `z(s) = e^{λs} ∘ h + z_p(t₀ + s)`: the deviation `h = z(0) − z_p(t₀)` from the steady
    /// response decays (or persists) mode by mode; `phase = e^{iωt₀}`. `deviation` holds the
    /// kept modes' only, in the order of [`LinearFlow::kept`] (contiguous: the loops over
    /// them read it in order).
    Steady {
        response: &'a SteadyResponse,
        deviation: Vec<C64>,
        phase: C64,
    },
    /// `z(s) = e^{λs} ∘ z(0) + Σ G φ(λ, μ, s)`, finite at resonance. The forcing
    /// coefficients carry the start phase: `G⁺ = g⁺ e^{iωt₀}`, `G⁻ = g⁻ e^{−iωt₀}`.
    General {
        start: DVector<C64>,
        plus: DVector<C64>,
        minus: DVector<C64>,
    },
}

/// `φ(λ, μ, s) = ∫₀ˢ e^{λ(s−σ)} e^{μσ} dσ` as terms in `s`, resonance-safe.
fn phi_terms(lambda: C64, mu: C64, period: f64, scale: C64, out: &mut Vec<Term>) {
    let delta = mu - lambda;
    let zero = C64::new(0.0, 0.0);
    if resonant(delta, period) {
        out.push(Term {
            poly: [
                zero,
                scale,
                scale * delta / 2.0,
                scale * delta * delta / 6.0,
            ],
            rate: lambda,
        });
    } else {
        let c = scale / delta;
        out.push(Term {
            poly: [c, zero, zero, zero],
            rate: mu,
        });
        out.push(Term {
            poly: [-c, zero, zero, zero],
            rate: lambda,
        });
    }
}

/// Whether a forcing rate `μ = λ + δ` counts as resonant with the mode of rate `λ`.
fn resonant(delta: C64, period: f64) -> bool {
    (delta.re.abs() + delta.im.abs()) * period <= RESONANCE
}

/// Value of `φ(λ, μ, s)` given `e^{λs}` and `e^{μs}`.
fn phi_shared(lambda: C64, el: C64, mu: C64, em: C64, s: f64, period: f64) -> C64 {
    let delta = mu - lambda;
    if resonant(delta, period) {
        el * (s + delta * (s * s / 2.0) + delta * delta * (s * s * s / 6.0))
    } else {
        (em - el) / delta
    }
}

/// `e^{μ s}`, skipping the real exponential for purely oscillatory rates.
#[inline]
fn cexp(mu: C64, s: f64) -> C64 {
    let (sin, cos) = crate::trig::sin_cos(mu.im * s);
    let r = if mu.re == 0.0 { 1.0 } else { (mu.re * s).exp() };
    C64::new(r * cos, r * sin)
}

/// The eigenvalues of the system matrix `a`, by the real Schur form with a bounded QR
/// iteration; when it does not converge, on the transpose, then on shifted copies `a + σI`
/// (nalgebra's unbounded iteration can cycle forever on some finite matrices).
pub(crate) fn eigenvalues(a: &DMatrix<f64>) -> Result<Vec<C64>, FlowError> {
    if !a.iter().all(|v| v.is_finite()) {
        return Err(FlowError::NotFinite);
    }
    let n = a.nrows();
    // A system of no coordinates (a structure held on its stops in every direction) has no
    // rates.
    if n == 0 {
        return Ok(Vec::new());
    }
    let scale = a.amax().max(f64::MIN_POSITIVE);
    let identity = DMatrix::<f64>::identity(n, n);
    for (matrix, shift) in [
        (a.clone(), 0.0),
        (a.transpose(), 0.0),
        (
            a + &identity * (SCHUR_SHIFTS[0] * scale),
            SCHUR_SHIFTS[0] * scale,
        ),
        (
            a - &identity * (-SCHUR_SHIFTS[1] * scale),
            SCHUR_SHIFTS[1] * scale,
        ),
    ] {
        if let Some(schur) =
            nalgebra::linalg::Schur::try_new(matrix, f64::EPSILON, SCHUR_ITERATIONS)
        {
            return Ok(schur
                .complex_eigenvalues()
                .iter()
                .map(|l| l - shift)
                .collect());
        }
    }
    Err(FlowError::NoConvergence)
}

/// Real parts of an undamped system's oscillating rates at most this many times `ε·|μ|` are
/// rounding (the Schur form leaves a few `1e-17` where they are zero) and are made exactly 0.
/// Far above the Schur form's rounding (a few `ε·|μ|`), far below any real damping's share
/// (a damping ratio of `1e-13`).
pub(crate) const CONSERVATIVE_ROUNDING: f64 = 1e3;

/// The rates of a system with no damping terms: its oscillating modes (`im μ ≠ 0`) conserve
/// energy, so a real part at rounding level ([`CONSERVATIVE_ROUNDING`]) is made exactly 0;
/// conjugate pairs stay exact conjugates. An undamped flight then counts as bounded and is
/// searched on the fixed grid of cached exponentials, not the horizon grid's fresh ones (the
/// `steady_sweep` example, half its runs undamped, shows the gain: see the performance page,
/// `docs/performance.md`).
fn conservative_rates(rates: &mut [C64]) {
    for r in rates.iter_mut() {
        if r.im != 0.0 && r.re.abs() <= CONSERVATIVE_ROUNDING * f64::EPSILON * r.norm() {
            r.re = 0.0;
        }
    }
}

/// `M⁻¹` and the first-order system matrix `A = [0 I; −M⁻¹K −M⁻¹C]` (no `C` block without
/// `damping`) of `M ü + C u̇ + K u`.
///
/// # Errors
/// [`FlowError::SingularMass`] when `mass` has no inverse.
fn first_order(
    mass: &DMatrix<f64>,
    damping: Option<&DMatrix<f64>>,
    stiffness: &DMatrix<f64>,
) -> Result<(DMatrix<f64>, DMatrix<f64>), FlowError> {
    let n = mass.nrows();
    let minv = mass.clone().try_inverse().ok_or(FlowError::SingularMass)?;
    let mut a = DMatrix::<f64>::zeros(2 * n, 2 * n);
    a.view_mut((0, n), (n, n)).fill_with_identity();
    a.view_mut((n, 0), (n, n))
        .copy_from(&(-(&minv * stiffness)));
    if let Some(c) = damping {
        a.view_mut((n, n), (n, n)).copy_from(&(-(&minv * c)));
    }
    Ok((minv, a))
}

impl LinearFlow {
    /// The free flow of `model` (its masses, dampings, stiffnesses and forcing, no constant
    /// force) at forcing frequency `omega`: the flight between its events.
    ///
    /// # Errors
    /// As [`LinearFlow::new`].
    pub(crate) fn of_model(model: &crate::Model, omega: f64) -> Result<Self, FlowError> {
        LinearFlow::new(
            &model.mass,
            model.damping.as_ref(),
            &model.stiffness,
            &model.forcing_cos,
            &model.forcing_sin,
            &DVector::zeros(model.mass.nrows()),
            omega,
        )
    }

    /// The flow of `M ü + C u̇ + K u = f_c cos ωt + f_s sin ωt + f₀` (`damping` `None`: no
    /// damping terms at all).
    pub fn new(
        mass: &DMatrix<f64>,
        damping: Option<&DMatrix<f64>>,
        stiffness: &DMatrix<f64>,
        forcing_cos: &DVector<f64>,
        forcing_sin: &DVector<f64>,
        forcing_constant: &DVector<f64>,
        omega: f64,
    ) -> Result<Self, FlowError> {
        let n = mass.nrows();
        let (minv, a) = first_order(mass, damping, stiffness)?;
        let mut rates = eigenvalues(&a)?;
        if damping.is_none() {
            conservative_rates(&mut rates);
        }
        let mut modes = DMatrix::<C64>::zeros(2 * n, 2 * n);
        let mc = mass.map(|v| C64::new(v, 0.0));
        let kc = stiffness.map(|v| C64::new(v, 0.0));
        let cc = damping.map(|c| c.map(|v| C64::new(v, 0.0)));
        for (k, &lambda) in rates.iter().enumerate() {
            let mut pencil = &mc * (lambda * lambda) + &kc;
            if let Some(c) = &cc {
                pencil += c * lambda;
            }
            let svd = pencil.svd(false, true);
            let v_t = svd.v_t.ok_or(FlowError::Defective(f64::INFINITY))?;
            let (imin, _) =
                svd.singular_values
                    .iter()
                    .enumerate()
                    .fold(
                        (0, f64::INFINITY),
                        |acc, (i, &s)| if s < acc.1 { (i, s) } else { acc },
                    );
            let shape: DVector<C64> = v_t.row(imin).adjoint();
            for i in 0..n {
                modes[(i, k)] = shape[i];
                modes[(n + i, k)] = shape[i] * lambda;
            }
        }
        let inverse = modes
            .clone()
            .try_inverse()
            .ok_or(FlowError::Defective(f64::INFINITY))?;
        let condition = modes.norm() * inverse.norm();
        if condition.is_nan() || condition >= DEFECTIVE_CONDITION {
            return Err(FlowError::Defective(condition));
        }
        let lift = |f: DVector<C64>| {
            let mut b = DVector::<C64>::zeros(2 * n);
            let accel = minv.map(|v| C64::new(v, 0.0)) * f;
            b.rows_mut(n, n).copy_from(&accel);
            &inverse * b
        };
        // f_c cos ωt + f_s sin ωt = (F e^{iωt} + F̄ e^{−iωt})/2 with F = f_c − i f_s.
        let f = DVector::from_fn(n, |i, _| C64::new(forcing_cos[i], -forcing_sin[i]) * 0.5);
        let plus = lift(f.clone());
        let minus = lift(f.map(|c| c.conj()));
        let constant = lift(forcing_constant.map(|v| C64::new(v, 0.0)));
        let period = std::f64::consts::TAU / omega;
        // A real system has real rates and exact conjugate pairs (real Schur form); fold each
        // pair into one mode of weight 2. Anything else keeps every mode.
        let partner = |k: usize| rates.iter().position(|r| *r == rates[k].conj());
        let pairs_exact = rates
            .iter()
            .enumerate()
            .all(|(k, r)| r.im == 0.0 || partner(k).is_some());
        let kept: Vec<(usize, f64)> = if pairs_exact {
            rates
                .iter()
                .enumerate()
                .filter(|(_, r)| r.im >= 0.0)
                .map(|(k, r)| (k, if r.im > 0.0 { 2.0 } else { 1.0 }))
                .collect()
        } else {
            (0..rates.len()).map(|k| (k, 1.0)).collect()
        };
        let kept_sizes: Vec<(f64, f64)> = kept
            .iter()
            .map(|&(k, _)| {
                let rate = rates[k].re.abs() + rates[k].im.abs();
                (rate, rate * rate * rate)
            })
            .collect();
        let w = C64::new(0.0, omega);
        let has_constant = constant.iter().any(|c| *c != C64::default());
        let steady = rates
            .iter()
            .all(|&l| {
                let forced_at_zero = has_constant && resonant(-l, period);
                !(resonant(w - l, period) || resonant(-w - l, period) || forced_at_zero)
            })
            .then(|| SteadyResponse {
                plus: rates
                    .iter()
                    .zip(plus.iter())
                    .map(|(&l, &g)| g / (w - l))
                    .collect(),
                minus: rates
                    .iter()
                    .zip(minus.iter())
                    .map(|(&l, &g)| g / (-w - l))
                    .collect(),
                constant: rates
                    .iter()
                    .zip(constant.iter())
                    .map(|(&l, &g)| if has_constant { -g / l } else { C64::default() })
                    .collect(),
            })
            .map(|response| response.of_kept(&kept));
        let apart = |m: &DMatrix<C64>| {
            (
                m.as_slice().iter().map(|c| c.re).collect(),
                m.as_slice().iter().map(|c| c.im).collect(),
            )
        };
        let inverse_rows = apart(&inverse.transpose());
        let kept_inverse_columns = (0..2 * n)
            .flat_map(|j| kept.iter().map(move |&(k, _)| (k, j)))
            .map(|(k, j)| inverse[(k, j)])
            .collect();
        let mode_columns = apart(&modes);
        let kept_peaks = kept_peaks(&modes, &kept);
        let joint_modes = joint_modes(&rates, &kept, &kept_sizes, omega);
        Ok(Self {
            dofs: n,
            omega,
            period,
            rates,
            modes,
            inverse,
            inverse_rows,
            kept_inverse_columns,
            mode_columns,
            plus,
            minus,
            constant,
            kept,
            kept_sizes,
            kept_peaks,
            joint_modes,
            steady,
        })
    }

    /// Per kept mode, in their order, `(Re v_ik, Im v_ik)`: entry `i` of its eigenvector, as
    /// [`Flight::state_at`] adds it into the state (`y_i = Σ_k Re v_ik Re z_k − Im v_ik Im
    /// z_k`, mode by mode from `0`).
    ///
    /// # Panics
    ///
    /// If `i ≥ 2n`.
    pub(crate) fn kept_entry(&self, i: usize) -> Vec<(f64, f64)> {
        let m = 2 * self.dofs;
        assert!(i < m, "state entry {i} of {m}");
        let (columns_re, columns_im) = &self.mode_columns;
        self.kept
            .iter()
            .map(|&(k, _)| (columns_re[k * m + i], columns_im[k * m + i]))
            .collect()
    }

    /// Per kept mode, in their order, the largest `max(|Re v_ik|, |Im v_ik|)` of its
    /// eigenvector's position entries (`i < n`) and of its velocity entries: with the
    /// modes' coordinates `z` they bound the state's entries, `|y_i| ≤ Σ_k peak_k (|Re z_k| +
    /// |Im z_k|)`, up to rounding.
    pub(crate) fn kept_peaks(&self) -> &[(f64, f64)] {
        &self.kept_peaks
    }

    /// Per kept mode `k`, `Σ_i w_i max(|Re v_ik|, |Im v_ik|)` for nonnegative weights `w` of
    /// the state's entries (length `2n`): `Σ_i w_i |y_i| ≤ Σ_k size_k (|Re z_k| + |Im z_k|)`
    /// for the state of coordinates `z`, with no cancellation between entries, so the bound
    /// holds for the entries as [`Flight::state_at`] rounds them to within a few roundings
    /// of its size.
    ///
    /// # Panics
    ///
    /// If `weights` is not of length `2n`.
    pub(crate) fn kept_entry_sizes(&self, weights: &[f64]) -> Vec<f64> {
        let m = 2 * self.dofs;
        assert_eq!(weights.len(), m, "weights of the state's entries");
        self.kept
            .iter()
            .map(|&(k, _)| {
                let column = self.modes.column(k);
                weights
                    .iter()
                    .zip(column.iter())
                    .map(|(&w, v)| w * v.re.abs().max(v.im.abs()))
                    .sum()
            })
            .collect()
    }

    /// One mode's coordinate `(V⁻¹y)_k` from its row of `V⁻¹` (real and imaginary parts
    /// apart): `re += Re v·y_i`, `im += Im v·y_i` over the entries in order from `0`.
    #[inline(always)]
    fn modal_coordinate(&self, (row_re, row_im): (&[f64], &[f64]), y: &[f64]) -> C64 {
        let (mut re, mut im) = (0.0, 0.0);
        for ((&vr, &vi), &yj) in row_re.iter().zip(row_im).zip(y) {
            re += vr * yj;
            im += vi * yj;
        }
        C64::new(re, im)
    }

    /// `y += Re(v_k z)`, `v_k` the `k`-th eigenvector: one mode's part of a state.
    #[inline]
    fn add_mode(&self, k: usize, z: C64, y: &mut [f64]) {
        let m = 2 * self.dofs;
        let (columns_re, columns_im) = &self.mode_columns;
        let column = k * m..(k + 1) * m;
        // Equal-length slices and an index loop: each entry on its own (the compiler may pack
        // them), the same operations as entry by entry.
        let (re, im) = (&columns_re[column.clone()], &columns_im[column]);
        let y = &mut y[..m];
        // A short column (a unit's four entries) gains nothing from the packed call, which
        // is kept out of line so that this loop stays inlined.
        #[cfg(target_arch = "x86_64")]
        if m >= AVX_COLUMN {
            return add_column(re, im, z, y);
        }
        for i in 0..m {
            y[i] += re[i] * z.re - im[i] * z.im;
        }
    }

    /// Degrees of freedom.
    pub fn dofs(&self) -> usize {
        self.dofs
    }

    /// The fastest free rate `max |λ_k|` of the system (rad/s).
    pub fn fastest_rate(&self) -> f64 {
        self.rates.iter().map(|l| l.norm()).fold(0.0, f64::max)
    }

    /// The homogeneous propagator `Φ(s) = ∂y(s)/∂y(0) = e^{A s} = Re(V e^{Λ s} V⁻¹)` of a
    /// flight of duration `s`: the tangent flow of the linear flight (independent of the
    /// forcing and of the start phase), from the same modal form as the flights themselves.
    pub fn propagator(&self, s: f64) -> DMatrix<f64> {
        let m = 2 * self.dofs;
        let mut out = DMatrix::zeros(m, m);
        self.propagator_into(s, &mut out);
        out
    }

    /// [`Self::propagator`] written into `out`, resized to `2n × 2n` if needed (no allocation
    /// when it already has that size).
    pub fn propagator_into(&self, s: f64, out: &mut DMatrix<f64>) {
        let m = 2 * self.dofs;
        if out.shape() != (m, m) {
            *out = DMatrix::zeros(m, m);
        } else {
            out.fill(0.0);
        }
        for &(k, weight) in &self.kept {
            let e = cexp(self.rates[k], s) * weight;
            for j in 0..m {
                let w = self.inverse[(k, j)] * e;
                for i in 0..m {
                    out[(i, j)] += (self.modes[(i, k)] * w).re;
                }
            }
        }
    }

    /// Whether flights use the steady forced response (no mode resonant with the forcing); at
    /// or near resonance they use the resonance-safe `φ` form instead.
    pub fn has_steady_response(&self) -> bool {
        self.steady.is_some()
    }

    /// The flight from state `y` (length `2n`) at forcing phase time `t0` (the forcing is
    /// evaluated at `t0 + s`).
    pub fn flight(&self, y: &DVector<f64>, t0: f64) -> Flight<'_> {
        let (sin, cos) = crate::trig::sin_cos(self.omega * t0);
        self.flight_at_phase(y, C64::new(cos, sin), Vec::new())
    }

    /// [`Self::flight`] given its forcing phase `e^{iωt0}` as `crate::trig::sin_cos(ωt0)`
    /// gives it (the event loop keeps the last one it computed: a contact's accelerations and
    /// the flight that follows start at the same time), its modal deviation written into
    /// `storage` (any contents; the event loop hands back the last flight's,
    /// [`Flight::into_storage`], so that a flight allocates nothing).
    pub(crate) fn flight_at_phase(
        &self,
        y: &DVector<f64>,
        phase: C64,
        mut storage: Vec<C64>,
    ) -> Flight<'_> {
        let m = 2 * self.dofs;
        let form = match &self.steady {
            Some(p) => {
                // The kept modes' deviations, in their order.
                if storage.len() != self.kept.len() {
                    storage.clear();
                    storage.resize(self.kept.len(), C64::default());
                }
                let mut deviation = storage;
                let y = y.as_slice();
                let (rows_re, rows_im) = &self.inverse_rows;
                // A chain's modal coordinates `V⁻¹y` with AVX, two modes to a register, but for
                // a last odd one (the same sums, so the same bits); a unit's as they were.
                #[cfg(target_arch = "x86_64")]
                if self.kept.len() >= PACKED_MODES && std::arch::is_x86_feature_detected!("avx") {
                    // SAFETY: the CPU has AVX (checked just above).
                    let done = unsafe {
                        modal_coordinates_avx(&self.kept_inverse_columns, y, &mut deviation)
                    };
                    let modes = deviation.iter_mut().zip(&self.kept).enumerate();
                    for (j, (h, &(k, _))) in modes {
                        let z = if j < done {
                            *h
                        } else {
                            let row = k * m..(k + 1) * m;
                            self.modal_coordinate((&rows_re[row.clone()], &rows_im[row]), y)
                        };
                        *h = z - (p.plus[j] * phase + p.minus[j] * phase.conj() + p.constant[j]);
                    }
                    return Flight {
                        flow: self,
                        form: Form::Steady {
                            response: p,
                            deviation,
                            phase,
                        },
                    };
                }
                for (j, (h, &(k, _))) in deviation.iter_mut().zip(&self.kept).enumerate() {
                    let row = k * m..(k + 1) * m;
                    let z = self.modal_coordinate((&rows_re[row.clone()], &rows_im[row]), y);
                    *h = z - (p.plus[j] * phase + p.minus[j] * phase.conj() + p.constant[j]);
                }
                Form::Steady {
                    response: p,
                    deviation,
                    phase,
                }
            }
            None => Form::General {
                start: &self.inverse * y.map(|v| C64::new(v, 0.0)),
                plus: self.plus.map(|g| g * phase),
                minus: self.minus.map(|g| g * phase.conj()),
            },
        };
        Flight { flow: self, form }
    }

    /// The flight at the forcing phase `e^{iωt0}` (as [`Self::flight_at_phase`] takes it) from
    /// a state whose deviation from the steady response, `h = z(0) − z_p(t0)` per mode (the
    /// kept modes', in their order), is already
    /// known, as [`Flight::deviation_at`] and [`Self::add_jump`] carry it across an event;
    /// `None` (the deviation handed back) when the flow has no steady response.
    ///
    /// It is [`Self::flight`] of that state up to rounding: the deviation is not recomputed
    /// from the state, so the last bits differ from a fresh start.
    pub(crate) fn flight_with_deviation(
        &self,
        deviation: Vec<C64>,
        phase: C64,
    ) -> Result<Flight<'_>, Vec<C64>> {
        let Some(p) = &self.steady else {
            return Err(deviation);
        };
        if deviation.len() != self.kept.len() {
            return Err(deviation);
        }
        Ok(Flight {
            flow: self,
            form: Form::Steady {
                response: p,
                deviation,
                phase,
            },
        })
    }

    /// Adds to a modal deviation (of the kept modes) the jump of the state from `before` to
    /// `after` (an impact's velocity change): `h += V⁻¹ (after − before)`, over the entries
    /// that changed only, among `changed` (rising), the only entries that can differ (an
    /// impact's: the velocities along `M⁻¹d`; comparing every entry of the state would be a
    /// third of the carry's instructions on a chain of eight cells).
    pub(crate) fn add_jump(
        &self,
        deviation: &mut [C64],
        (before, after): (&[f64], &[f64]),
        changed: impl Iterator<Item = usize>,
    ) {
        let count = self.kept.len();
        if count == 0 {
            return;
        }
        for j in changed {
            let (b, a) = (before[j], after[j]);
            if a == b {
                continue;
            }
            let delta = a - b;
            let column = &self.kept_inverse_columns[j * count..(j + 1) * count];
            #[cfg(target_arch = "x86_64")]
            if count >= PACKED_MODES && std::arch::is_x86_feature_detected!("avx") {
                // SAFETY: the CPU has AVX (checked just above).
                unsafe { add_scaled_avx(deviation, column, delta) };
                continue;
            }
            for (h, &v) in deviation.iter_mut().zip(column) {
                *h += v * delta;
            }
        }
    }

    /// The functionals, in their order, prepared for [`Flight::summarize_all`].
    pub(crate) fn joint_weights(&self, functionals: &[&Functional]) -> JointWeights {
        let count = functionals.len();
        let mut joint = JointWeights {
            count,
            ..JointWeights::default()
        };
        for block in functionals.chunks(LANES) {
            let lane = |l: usize, of: &dyn Fn(&Functional) -> C64| {
                block.get(l).map_or(C64::default(), |f| of(f))
            };
            for &(k, _) in &self.kept {
                let w: [C64; LANES] = std::array::from_fn(|l| lane(l, &|f| f.weights[k]));
                joint.blocks.push(std::array::from_fn(|i| {
                    if i < LANES {
                        w[i].re
                    } else {
                        w[i - LANES].im
                    }
                }));
            }
            let forced: [C64; LANES] = std::array::from_fn(|l| lane(l, &|f| f.forced));
            joint.blocks.push(std::array::from_fn(|i| {
                if i < LANES {
                    forced[i].re
                } else {
                    forced[i - LANES].im
                }
            }));
        }
        joint
            .constant
            .extend(functionals.iter().map(|f| f.constant));
        joint
    }

    /// Modal weights `Vᵀ c` of the functional `c · y`, with the steady response's part.
    pub fn functional(&self, c: &DVector<f64>) -> Functional {
        let weights = self.modes.transpose() * c.map(|v| C64::new(v, 0.0));
        let (mut forced, mut constant) = (C64::default(), 0.0);
        if let Some(p) = &self.steady {
            for (j, &(k, weight)) in self.kept.iter().enumerate() {
                // Re[w P⁻ e^{−iωt}] = Re[conj(w P⁻) e^{iωt}].
                forced += (weights[k] * p.plus[j] + (weights[k] * p.minus[j]).conj()) * weight;
                constant += (weights[k] * p.constant[j]).re * weight;
            }
        }
        Functional {
            weights,
            forced,
            constant,
        }
    }
}

/// The modes of [`LinearFlow::joint_modes`]: each kept mode `(k, weight)` with its rate and
/// sizes, then the forced part at `iω` as `add_decaying` adds it (weight 1 is exact), every
/// deviation zero; `None` where [`Flight::summarize_all`] gives no summaries.
fn joint_modes(
    rates: &[C64],
    kept: &[(usize, f64)],
    kept_sizes: &[(f64, f64)],
    omega: f64,
) -> Option<Vec<ModeTerm>> {
    if rates.iter().any(|r| r.re > 0.0)
        || kept.is_empty()
        || kept_sizes.iter().any(|&(rate, _)| rate == 0.0)
    {
        return None;
    }
    let mut modes: Vec<ModeTerm> = kept
        .iter()
        .zip(kept_sizes)
        .map(|(&(k, weight), &sizes)| ModeTerm::new(rates[k], weight, sizes))
        .collect();
    let forcing = C64::new(0.0, omega);
    let rate = forcing.re.abs() + forcing.im.abs();
    modes.push(ModeTerm::new(forcing, 1.0, (rate, rate * rate * rate)));
    Some(modes)
}

/// The shortest state (`2n` entries) whose modes [`LinearFlow::add_mode`] adds out of line,
/// with AVX when the CPU has it: a unit's four entries cost more instructions so (a call
/// where the inlined loop is cheaper), a chain's 32 fewer (see the performance page,
/// `docs/performance.md`).
#[cfg(target_arch = "x86_64")]
const AVX_COLUMN: usize = 8;

/// [`LinearFlow::add_mode`]'s loop for a long column (`y[i] += re[i]·z.re − im[i]·z.im` over
/// equal-length slices), with AVX when the CPU has it ([`add_column_avx`], the same bits).
#[cfg(target_arch = "x86_64")]
#[inline(never)]
fn add_column(re: &[f64], im: &[f64], z: C64, y: &mut [f64]) {
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU has AVX (checked just above), the only requirement of the
        // `target_feature` function.
        return unsafe { add_column_avx(re, im, z, y) };
    }
    for i in 0..y.len() {
        y[i] += re[i] * z.re - im[i] * z.im;
    }
}

/// [`Flight::state_at`]'s steady form with AVX: each kept mode's
/// `z_k = (h_k e^{λ_k s} + P⁺_k F + P⁻_k F̄ + P⁰_k)·weight` (`F` the forcing's phase at `s`)
/// formed two modes to a register, then the two modes' columns added four entries at once in
/// one pass ([`add_two_columns_avx`]; an odd last mode's by [`add_column_avx`]). Complex
/// products as [`Complex`]'s (the imaginary part's sum with its operands swapped, which
/// rounds the same), the sums in the same order: the same bits as [`Flight::state_at`]'s
/// loop. `y` is zero on entry.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn steady_state_avx(
    f: &LinearFlow,
    (p, deviation, forced): (&SteadyResponse, &[C64], C64),
    (s, known): (f64, Option<&[C64]>),
    y: &mut [f64],
) {
    use crate::expsum::{complex_pair, complex_pair_product};
    use std::arch::x86_64::*;
    let m = 2 * f.dofs;
    let (columns_re, columns_im) = &f.mode_columns;
    let y = &mut y[..m];
    let pack = |a: C64, b: C64| _mm256_set_pd(b.im, b.re, a.im, a.re);
    // Two neighbouring complex numbers (`C64` is `repr(C)`: `[re₀, im₀, re₁, im₁]`, as `pack`
    // lays them out).
    let load = |v: &[C64], i: usize| {
        let two = &v[i..i + 2];
        // SAFETY: `two` holds two `C64`, four `f64` in that order: one unaligned load.
        unsafe { _mm256_loadu_pd(two.as_ptr().cast()) }
    };
    // A `match`, not `Option::map_or_else`, which the compiler leaves out of line here (a
    // call per entry).
    let el = |j: usize, k: usize| match known {
        Some(e) => e[j],
        None => cexp(f.rates[k], s),
    };
    let pairs = f.kept.chunks_exact(2);
    let last = pairs.remainder();
    for (i, pair) in pairs.enumerate() {
        let ((k0, w0), (k1, w1)) = (pair[0], pair[1]);
        let h = load(deviation, 2 * i);
        let e = match known {
            Some(e) => load(e, 2 * i),
            None => pack(cexp(f.rates[k0], s), cexp(f.rates[k1], s)),
        };
        let z = pair_coordinates_avx(p, 2 * i, complex_pair_product(h, e), forced, (w0, w1));
        let (z0, z1) = complex_pair(z);
        let (c0, c1) = (k0 * m..(k0 + 1) * m, k1 * m..(k1 + 1) * m);
        add_two_columns_avx(
            (&columns_re[c0.clone()], &columns_im[c0], z0),
            (&columns_re[c1.clone()], &columns_im[c1], z1),
            y,
        );
    }
    if let &[(k, weight)] = last {
        let j = f.kept.len() - 1;
        let zk = p.coordinate(j, deviation[j] * el(j, k), forced, weight);
        let column = k * m..(k + 1) * m;
        add_column_avx(&columns_re[column.clone()], &columns_im[column], zk, y);
    }
}

/// The kept modes' coordinates `(V⁻¹y)_k` of the state `y` into `out` (as long as the kept
/// modes), from `columns` ([`LinearFlow::kept_inverse_columns`]), two modes to an AVX
/// register and four registers at a time: each coordinate's real and imaginary parts summed
/// over the state's entries in order from `0`, `re += Re v·y_i` and `im += Im v·y_i`, as
/// [`LinearFlow::flight_at_phase`] sums them entry by entry (no FMA: the same bits). Returns
/// how many modes it formed (all but a last odd one).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn modal_coordinates_avx(columns: &[C64], y: &[f64], out: &mut [C64]) -> usize {
    use std::arch::x86_64::*;
    /// Registers summed side by side: four chains of additions in flight at once.
    const BLOCK: usize = 4;
    let count = out.len();
    let columns = &columns[..count * y.len()];
    let pairs = count / 2;
    let mut p = 0;
    while p < pairs {
        let block = (pairs - p).min(BLOCK);
        let mut sums = [_mm256_setzero_pd(); BLOCK];
        for (i, &yi) in y.iter().enumerate() {
            let yi = _mm256_set1_pd(yi);
            let column = &columns[i * count + 2 * p..i * count + 2 * (p + block)];
            for (sum, two) in sums.iter_mut().zip(column.chunks_exact(2)) {
                // SAFETY: `two` holds two `C64`, four `f64`: one unaligned load.
                let v = unsafe { _mm256_loadu_pd(two.as_ptr().cast()) };
                *sum = _mm256_add_pd(*sum, _mm256_mul_pd(v, yi));
            }
        }
        for (q, sum) in sums.iter().take(block).enumerate() {
            let two = &mut out[2 * (p + q)..2 * (p + q) + 2];
            // SAFETY: `two` holds two `C64`, four `f64`: one unaligned store.
            unsafe { _mm256_storeu_pd(two.as_mut_ptr().cast(), *sum) };
        }
        p += block;
    }
    2 * pairs
}

/// [`LinearFlow::kept_peaks`] of the eigenvectors `modes` (as columns, `2n` rows).
fn kept_peaks(modes: &DMatrix<C64>, kept: &[(usize, f64)]) -> Vec<(f64, f64)> {
    let n = modes.nrows() / 2;
    let peak = |k: usize, rows: std::ops::Range<usize>| {
        rows.map(|i| modes[(i, k)])
            .fold(0.0, |m: f64, v| m.max(v.re.abs()).max(v.im.abs()))
    };
    kept.iter()
        .map(|&(k, _)| (peak(k, 0..n), peak(k, n..2 * n)))
        .collect()
}

/// [`SteadyResponse::coordinate`] of kept modes `j` and `j + 1` (their decayed deviations
/// packed in `decayed`, weights `w0`, `w1`), two to an AVX register: the same operations in
/// the same order ([`complex_pair_product`](crate::expsum::complex_pair_product): [`Complex`]'s
/// products), so the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
fn pair_coordinates_avx(
    p: &SteadyResponse,
    j: usize,
    decayed: std::arch::x86_64::__m256d,
    forced: C64,
    (w0, w1): (f64, f64),
) -> std::arch::x86_64::__m256d {
    use crate::expsum::complex_pair_product;
    use std::arch::x86_64::*;
    let pack = |a: C64, b: C64| _mm256_set_pd(b.im, b.re, a.im, a.re);
    let load = |v: &[C64]| {
        let two = &v[j..j + 2];
        // SAFETY: `two` holds two `C64`, four `f64` in that order: one unaligned load.
        unsafe { _mm256_loadu_pd(two.as_ptr().cast()) }
    };
    let (plus, minus) = (pack(forced, forced), pack(forced.conj(), forced.conj()));
    let mut z = _mm256_add_pd(decayed, complex_pair_product(load(&p.plus), plus));
    z = _mm256_add_pd(z, complex_pair_product(load(&p.minus), minus));
    z = _mm256_add_pd(z, load(&p.constant));
    _mm256_mul_pd(z, _mm256_set_pd(w1, w1, w0, w0))
}

/// [`Flight::modal_state`] with AVX and the exponentials known: [`steady_state_avx`]'s
/// coordinates (the same operations, so the same bits), written to `z` (as long as the kept
/// modes) rather than added into a state, and their first products `h_k e^{λ_k s}` to
/// `carried` (as long).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn modal_state_avx(
    f: &LinearFlow,
    (p, deviation, forced): (&SteadyResponse, &[C64], C64),
    e: &[C64],
    (z, carried): (&mut [C64], &mut [C64]),
) {
    use crate::expsum::complex_pair_product;
    use std::arch::x86_64::*;
    let load = |v: &[C64], i: usize| {
        let two = &v[i..i + 2];
        // SAFETY: `two` holds two `C64`, four `f64` in that order: one unaligned load.
        unsafe { _mm256_loadu_pd(two.as_ptr().cast()) }
    };
    let pairs = f.kept.chunks_exact(2);
    let last = pairs.remainder();
    for (i, pair) in pairs.enumerate() {
        let (w0, w1) = (pair[0].1, pair[1].1);
        let decayed = complex_pair_product(load(deviation, 2 * i), load(e, 2 * i));
        let first = &mut carried[2 * i..2 * i + 2];
        // SAFETY: `first` holds two `C64`, four `f64`: one unaligned store.
        unsafe { _mm256_storeu_pd(first.as_mut_ptr().cast(), decayed) };
        let v = pair_coordinates_avx(p, 2 * i, decayed, forced, (w0, w1));
        let out = &mut z[2 * i..2 * i + 2];
        // SAFETY: `out` holds two `C64`, four `f64`: one unaligned store.
        unsafe { _mm256_storeu_pd(out.as_mut_ptr().cast(), v) };
    }
    if let &[(_, weight)] = last {
        let j = f.kept.len() - 1;
        carried[j] = deviation[j] * e[j];
        z[j] = p.coordinate(j, carried[j], forced, weight);
    }
}

/// Kept modes from which a flight's deviation is carried across an event two modes to an AVX
/// register ([`products_avx`](crate::expsum::products_avx), [`add_scaled_avx`]): a chain's
/// 16 take fewer instructions so (see the performance page, `docs/performance.md`); a unit's
/// two stay scalar.
#[cfg(target_arch = "x86_64")]
const PACKED_MODES: usize = 8;

/// `h[j] += v[j]·delta` over `h`'s length (`v` at least as long), two entries to an AVX
/// register: `C64 · f64` is `(re·delta, im·delta)`, so the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn add_scaled_avx(h: &mut [C64], v: &[C64], delta: f64) {
    use std::arch::x86_64::*;
    let n = h.len();
    let v = &v[..n];
    let scale = _mm256_set1_pd(delta);
    let mut j = 0;
    while j + 2 <= n {
        // SAFETY: `j + 2 ≤ n`, the length of both slices: two `C64` (four `f64`) loaded from
        // each and stored back into `h`.
        unsafe {
            let old = _mm256_loadu_pd(h.as_ptr().add(j).cast());
            let step = _mm256_mul_pd(_mm256_loadu_pd(v.as_ptr().add(j).cast()), scale);
            _mm256_storeu_pd(h.as_mut_ptr().add(j).cast(), _mm256_add_pd(old, step));
        }
        j += 2;
    }
    if j < n {
        h[j] += v[j] * delta;
    }
}

/// Two modes' columns `(re, im, z)` added in one pass over `y` (each column as long as `y`):
/// each entry gets the first mode's term and then the second's, the operations of
/// [`add_column_avx`] twice (so the same bits), `y` loaded and stored once for both rather
/// than once per mode (fewer instructions and less time on a chain: see the performance
/// page, `docs/performance.md`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
fn add_two_columns_avx(
    (re0, im0, z0): (&[f64], &[f64], C64),
    (re1, im1, z1): (&[f64], &[f64], C64),
    y: &mut [f64],
) {
    use std::arch::x86_64::*;
    let m = y.len();
    let (re0, im0, re1, im1) = (&re0[..m], &im0[..m], &re1[..m], &im1[..m]);
    let (zr0, zi0) = (_mm256_set1_pd(z0.re), _mm256_set1_pd(z0.im));
    let (zr1, zi1) = (_mm256_set1_pd(z1.re), _mm256_set1_pd(z1.im));
    let whole = m - m % 4;
    for i in (0..whole).step_by(4) {
        // SAFETY: `i + 4 ≤ m`, the length of all five slices: each load and store stays
        // within its slice.
        unsafe {
            let load = |v: &[f64]| _mm256_loadu_pd(v.as_ptr().add(i));
            let first = _mm256_sub_pd(_mm256_mul_pd(load(re0), zr0), _mm256_mul_pd(load(im0), zi0));
            let second =
                _mm256_sub_pd(_mm256_mul_pd(load(re1), zr1), _mm256_mul_pd(load(im1), zi1));
            let sum = _mm256_add_pd(_mm256_add_pd(load(y), first), second);
            _mm256_storeu_pd(y.as_mut_ptr().add(i), sum);
        }
    }
    for i in whole..m {
        y[i] += re0[i] * z0.re - im0[i] * z0.im;
        y[i] += re1[i] * z1.re - im1[i] * z1.im;
    }
}

/// `y[i] += re[i]·z.re − im[i]·z.im` over equal-length slices ([`LinearFlow::add_mode`]),
/// four entries at once with AVX: each entry's operations in the same order (no FMA), so the
/// same bits as entry by entry.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
fn add_column_avx(re: &[f64], im: &[f64], z: C64, y: &mut [f64]) {
    use std::arch::x86_64::*;
    let m = y.len();
    let (re, im) = (&re[..m], &im[..m]);
    let (zr, zi) = (_mm256_set1_pd(z.re), _mm256_set1_pd(z.im));
    let whole = m - m % 4;
    for i in (0..whole).step_by(4) {
        // SAFETY: `i + 4 ≤ m`, the length of all three slices: each load and store stays
        // within its slice.
        unsafe {
            let r = _mm256_loadu_pd(re.as_ptr().add(i));
            let v = _mm256_loadu_pd(im.as_ptr().add(i));
            let old = _mm256_loadu_pd(y.as_ptr().add(i));
            let step = _mm256_sub_pd(_mm256_mul_pd(r, zr), _mm256_mul_pd(v, zi));
            _mm256_storeu_pd(y.as_mut_ptr().add(i), _mm256_add_pd(old, step));
        }
    }
    for i in whole..m {
        y[i] += re[i] * z.re - im[i] * z.im;
    }
}

impl Flight<'_> {
    /// The flight's storage for its modal deviation (empty for the resonance-safe form), for
    /// the next [`LinearFlow::flight_at_phase`].
    pub(crate) fn into_storage(self) -> Vec<C64> {
        match self.form {
            Form::Steady { deviation, .. } => deviation,
            Form::General { .. } => Vec::new(),
        }
    }

    /// The state `y(s)` at time `s` into the flight.
    pub fn state(&self, s: f64) -> DVector<f64> {
        let mut y = DVector::zeros(2 * self.flow.dofs);
        self.state_into(s, &mut y);
        y
    }

    /// [`Self::state`] written into `y` (length `2n`), without allocating.
    pub fn state_into(&self, s: f64, y: &mut DVector<f64>) {
        self.state_with(s, None, y);
    }

    /// [`Self::state_into`], given `exponentials`: `e^{μ_j s}` of the terms of any functional
    /// [`Self::expand`]ed from this flight, in their order (as a search over that functional
    /// leaves them at the contact it found). They replace the exponentials of the modes and
    /// the forcing when the flight follows the steady response; otherwise they are ignored.
    pub fn state_at(&self, s: f64, exponentials: &[C64], y: &mut DVector<f64>) {
        self.state_with(s, Some(exponentials), y);
    }

    fn state_with(&self, s: f64, exponentials: Option<&[C64]>, y: &mut DVector<f64>) {
        let f = self.flow;
        // Zeroed as a slice: nalgebra's element iterator takes some 360 instructions for a
        // chain's 32 entries.
        y.as_mut_slice().fill(0.0);
        // `expand` lists the kept modes, then the forcing.
        let known = exponentials.filter(|e| e.len() > f.kept.len());
        // Shared exponentials: e^{±iωs} once for all modes.
        let ep = match known {
            Some(e) if matches!(self.form, Form::Steady { .. }) => e[f.kept.len()],
            _ => cexp(C64::new(0.0, f.omega), s),
        };
        match &self.form {
            Form::Steady {
                response: p,
                deviation,
                phase,
            } => {
                let forced = ep * phase;
                // A chain's state with AVX when the CPU has it (the same bits).
                #[cfg(target_arch = "x86_64")]
                if 2 * f.dofs >= AVX_COLUMN && std::arch::is_x86_feature_detected!("avx") {
                    let at = (s, known);
                    // SAFETY: the CPU has AVX (checked just above).
                    unsafe { steady_state_avx(f, (p, deviation, forced), at, y.as_mut_slice()) };
                    return;
                }
                for (j, &(k, weight)) in f.kept.iter().enumerate() {
                    let el = known.map_or_else(|| cexp(f.rates[k], s), |e| e[j]);
                    let zk = p.coordinate(j, deviation[j] * el, forced, weight);
                    f.add_mode(k, zk, y.as_mut_slice());
                }
            }
            Form::General { start, plus, minus } => {
                let w = C64::new(0.0, f.omega);
                let em = ep.conj();
                let zero = C64::new(0.0, 0.0);
                for &(k, weight) in &f.kept {
                    let l = f.rates[k];
                    let el = cexp(l, s);
                    let mut zk = el * start[k]
                        + plus[k] * phi_shared(l, el, w, ep, s, f.period)
                        + minus[k] * phi_shared(l, el, -w, em, s, f.period);
                    if f.constant[k] != zero {
                        zk += f.constant[k]
                            * phi_shared(l, el, zero, C64::new(1.0, 0.0), s, f.period);
                    }
                    let zk = zk * weight;
                    f.add_mode(k, zk, y.as_mut_slice());
                }
            }
        }
    }

    /// The kept modes' coordinates `z_k` (their weights included, `y = Σ_k Re(v_k z_k)`) of
    /// the state at `s` into the flight, into `z` (the kept modes', in their order), given
    /// `exponentials` as for [`Self::state_at`], which forms the state from the same
    /// coordinates, the same bits: `(h_k e^{λ_k s} + P⁺_k F + P⁻_k F̄ + P⁰_k)·weight`, `F`
    /// the forcing's phase at `s`. With AVX and the exponentials there given, `h_k e^{λ_k
    /// s}` too, into `carried`, bit for bit [`Self::deviation_at`]'s (else `carried` is
    /// left empty). `false` (nothing written) for the general form.
    pub(crate) fn modal_state(
        &self,
        s: f64,
        exponentials: &[C64],
        (z, carried): (&mut Vec<C64>, &mut Vec<C64>),
    ) -> bool {
        let f = self.flow;
        let Form::Steady {
            response: p,
            deviation,
            phase,
        } = &self.form
        else {
            return false;
        };
        let known = (exponentials.len() > f.kept.len()).then_some(exponentials);
        let ep = match known {
            Some(e) => e[f.kept.len()],
            None => cexp(C64::new(0.0, f.omega), s),
        };
        let forced = ep * phase;
        z.clear();
        carried.clear();
        #[cfg(target_arch = "x86_64")]
        if let Some(e) = known {
            if f.kept.len() >= PACKED_MODES && std::arch::is_x86_feature_detected!("avx") {
                z.resize(f.kept.len(), C64::default());
                carried.resize(f.kept.len(), C64::default());
                // SAFETY: the CPU has AVX (checked just above).
                unsafe { modal_state_avx(f, (p, deviation, forced), e, (z, carried)) };
                return true;
            }
        }
        z.extend(f.kept.iter().enumerate().map(|(j, &(k, weight))| {
            let el = match known {
                Some(e) => e[j],
                None => cexp(f.rates[k], s),
            };
            p.coordinate(j, deviation[j] * el, forced, weight)
        }));
        true
    }

    /// The deviation from the steady response at `s` into the flight, `h e^{λs}` per kept
    /// mode, written into `out` (the kept modes', in their order), given `exponentials` as for
    /// [`Self::state_at`]: the start of the next flight without recomputing it from the
    /// state. `false` (nothing written) for the general form or without those exponentials.
    pub(crate) fn deviation_at(&self, exponentials: &[C64], out: &mut Vec<C64>) -> bool {
        let f = self.flow;
        let Form::Steady { deviation, .. } = &self.form else {
            return false;
        };
        if exponentials.len() <= f.kept.len() {
            return false;
        }
        out.clear();
        #[cfg(target_arch = "x86_64")]
        if deviation.len() >= PACKED_MODES && std::arch::is_x86_feature_detected!("avx") {
            out.resize(deviation.len(), C64::default());
            // SAFETY: the CPU has AVX (checked just above).
            unsafe { crate::expsum::products_avx(deviation, exponentials, out) };
            return true;
        }
        out.extend(deviation.iter().zip(exponentials).map(|(&h, &e)| h * e));
        true
    }

    /// The [`Summary`] of the functional's terms, as [`Self::expand`] would write them (the
    /// same coefficients — `w (d·weight)` there `(w d)·weight`, equal since a weight of 1 or 2
    /// scales exactly — in the same order), without writing them, term by term as
    /// [`Summary::add_mode`] adds them: for the steady-response form when no rate grows (then
    /// the summary holds for any cutoff); `None` otherwise.
    pub(crate) fn summarize(&self, functional: &Functional, horizon: f64) -> Option<Summary> {
        let f = self.flow;
        let Form::Steady {
            deviation, phase, ..
        } = &self.form
        else {
            return None;
        };
        if !horizon.is_finite() || f.rates.iter().any(|r| r.re > 0.0) {
            return None;
        }
        let weights = functional.weights.as_slice();
        let mut sum = Summary::default();
        let modes = f.kept.iter().zip(&f.kept_sizes).zip(deviation);
        for ((&(k, weight), &(rate, cube)), &h) in modes {
            let (c, mu) = (weights[k] * (h * weight), f.rates[k]);
            if rate == 0.0 {
                sum.add_decaying::<true>(c, mu);
            } else {
                sum.add_mode(c, mu, rate, cube);
            }
        }
        let forcing = C64::new(0.0, f.omega);
        let rate = forcing.re.abs() + forcing.im.abs();
        sum.add_mode(functional.forced * phase, forcing, rate, rate * rate * rate);
        if functional.constant != 0.0 {
            sum.add_decaying::<true>(C64::new(functional.constant, 0.0), C64::default());
        }
        Some(sum)
    }

    /// [`Self::summarize`] of every functional of `joint`, in its order, into `out`, in one
    /// pass over the modes (each mode's deviation and rate read once for all functionals);
    /// each summary is bit for bit the one [`Self::summarize`] gives. `false` (nothing
    /// written) where [`Self::summarize`] gives `None`, or a kept mode has rate zero.
    /// The terms' coefficients are left in `coefficients`, laid out as `joint`'s weights, for
    /// [`Self::expand_joint`].
    pub(crate) fn summarize_all(
        &self,
        joint: &JointWeights,
        horizon: f64,
        (deviations, coefficients): (&mut Vec<C64>, &mut Vec<[f64; 2 * LANES]>),
        out: &mut Vec<Summary>,
    ) -> bool {
        let f = self.flow;
        let Form::Steady {
            deviation, phase, ..
        } = &self.form
        else {
            return false;
        };
        let Some(template) = &f.joint_modes else {
            return false;
        };
        if !horizon.is_finite()
            || joint.blocks.len() != joint.count.div_ceil(LANES) * (f.kept.len() + 1)
        {
            return false;
        }
        let count = joint.count;
        let modes = &template[..];
        // Each kept mode's deviation times its weight, then the forced part `forced · phase`
        // at `iω` (weight 1: exact).
        deviations.clear();
        deviations.extend(modes.iter().zip(deviation).map(|(m, &h)| m.weighted(h)));
        deviations.push(modes[f.kept.len()].weighted(*phase));
        coefficients.resize(joint.blocks.len(), [0.0; 2 * LANES]);
        let per_block = modes.len();
        // Every summary is written below: storage of the right length is only kept.
        out.resize(joint.blocks.len() / per_block * LANES, Summary::default());
        for ((block, written), sums) in joint
            .blocks
            .chunks_exact(per_block)
            .zip(coefficients.chunks_exact_mut(per_block))
            .zip(out.chunks_exact_mut(LANES))
        {
            summarize_block(block, (modes, deviations), written, sums);
        }
        out.truncate(count);
        for (sum, &constant) in out.iter_mut().zip(&joint.constant) {
            if constant != 0.0 {
                sum.add_decaying::<true>(C64::new(constant, 0.0), C64::default());
            }
        }
        true
    }

    /// The linear functional `c · y(s)` as a sum of exponential terms in `s`.
    pub fn value_of(&self, c: &DVector<f64>) -> ExpSum {
        let mut out = ExpSum::default();
        self.expand(&self.flow.functional(c), &mut out);
        out
    }

    /// [`Self::expand`] of the functional in slot `slot` of the joint summaries that
    /// [`Self::summarize_all`] has just formed for this flight, into `out` that holds the
    /// expansion of that functional by an earlier flight of the same flow in the
    /// steady-response form (its rates, its zero coefficients beyond the constant ones, its
    /// constant term): only the constant coefficients that depend on the flight are written,
    /// copied from the summaries' `coefficients` (`w (d·weight)` there, `(w d)·weight` in
    /// [`Self::expand`]: equal, since a weight of 1 or 2 scales exactly), so `out` ends as
    /// [`Self::expand`] would leave it, bit for bit. Otherwise (another form, or `out` not of
    /// that length) it is [`Self::expand`]. Writing the terms out is some 5 % of a chain's
    /// time, and forming their coefficients again would be 5 % of its instructions (see the
    /// performance page, `docs/performance.md`).
    pub(crate) fn expand_joint(
        &self,
        functional: &Functional,
        (coefficients, slot): (&[[f64; 2 * LANES]], usize),
        out: &mut ExpSum,
    ) {
        let f = self.flow;
        let kept = f.kept.len();
        let count = kept + 1 + usize::from(functional.constant != 0.0);
        let (block, lane) = (slot / LANES, slot % LANES);
        let rows = coefficients.get(block * (kept + 1)..(block + 1) * (kept + 1));
        match (&self.form, rows) {
            (Form::Steady { .. }, Some(rows)) if out.terms.len() == count => {
                for (t, row) in out.terms.iter_mut().zip(rows) {
                    t.poly[0] = C64::new(row[lane], row[LANES + lane]);
                }
            }
            _ => self.expand(functional, out),
        }
    }

    /// The functional prepared by [`LinearFlow::functional`] as a sum of exponential terms in
    /// `s`, written into `out` (its previous terms are dropped, its storage reused).
    pub fn expand(&self, functional: &Functional, out: &mut ExpSum) {
        let f = self.flow;
        let zero = C64::new(0.0, 0.0);
        let w = C64::new(0.0, f.omega);
        let weights = &functional.weights;
        out.terms.clear();
        match &self.form {
            Form::Steady {
                deviation, phase, ..
            } => {
                let weights = weights.as_slice();
                out.terms
                    .extend(f.kept.iter().zip(deviation).map(|(&(k, weight), &h)| Term {
                        poly: [weights[k] * h * weight, zero, zero, zero],
                        rate: f.rates[k],
                    }));
                out.terms.push(Term {
                    poly: [functional.forced * phase, zero, zero, zero],
                    rate: w,
                });
                if functional.constant != 0.0 {
                    out.terms.push(Term {
                        poly: [C64::new(functional.constant, 0.0), zero, zero, zero],
                        rate: zero,
                    });
                }
            }
            Form::General { start, plus, minus } => {
                let mut terms = Vec::with_capacity(4 * f.rates.len());
                for (k, &l) in f.rates.iter().enumerate() {
                    let wk = weights[k];
                    terms.push(Term {
                        poly: [wk * start[k], zero, zero, zero],
                        rate: l,
                    });
                    phi_terms(l, w, f.period, wk * plus[k], &mut terms);
                    phi_terms(l, -w, f.period, wk * minus[k], &mut terms);
                    if f.constant[k] != zero {
                        phi_terms(l, zero, f.period, wk * f.constant[k], &mut terms);
                    }
                }
                out.terms = merge(terms);
            }
        }
    }
}

/// Merges terms with equal rates, and folds each term with rate `μ̄` into the one with rate `μ`
/// (`Re(B e^{μ̄s}) = Re(B̄ e^{μs})`): half the exponentials to evaluate for a real system.
fn merge(terms: Vec<Term>) -> Vec<Term> {
    let mut out: Vec<Term> = Vec::with_capacity(terms.len());
    for t in terms {
        if let Some(o) = out.iter_mut().find(|o| o.rate == t.rate) {
            for i in 0..4 {
                o.poly[i] += t.poly[i];
            }
        } else if let Some(o) = out.iter_mut().find(|o| o.rate == t.rate.conj()) {
            for i in 0..4 {
                o.poly[i] += t.poly[i].conj();
            }
        } else {
            out.push(t);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `e^{λ_k s}` of the flow's kept modes in order, then the forcing's `e^{iωs}`: the
    /// exponentials a flight's state at `s` is formed from.
    fn kept_exponentials(flow: &LinearFlow, s: f64) -> Vec<C64> {
        flow.kept
            .iter()
            .map(|&(k, _)| cexp(flow.rates[k], s))
            .chain([cexp(C64::new(0.0, flow.omega), s)])
            .collect()
    }

    /// An undamped system's rates are `±iω_k` exactly (the exact answer: `M`, `K` symmetric
    /// positive definite); the Schur form leaves rounding in their real parts, which
    /// [`conservative_rates`] removes. A damped system's real parts stay as they are.
    #[test]
    fn undamped_rates_are_purely_imaginary_and_damped_ones_keep_their_decay() {
        use crate::test_models::{paper_chain, LIGHT_DAMPING};
        for cells in [1, 3, 8] {
            for damping in [None, Some(LIGHT_DAMPING)] {
                let model = paper_chain(cells, 2.0, damping, None);
                let flow = LinearFlow::of_model(&model, 2.0).expect("the paper's chain has a flow");
                let (_, a) = first_order(&model.mass, model.damping.as_ref(), &model.stiffness)
                    .expect("the paper's chain has a mass inverse");
                let raw = eigenvalues(&a).expect("eigenvalues");
                for (r, schur) in flow.rates.iter().zip(&raw) {
                    assert_eq!(r.im, schur.im);
                    if damping.is_none() {
                        assert_eq!(r.re, 0.0, "{cells} cells: {r}");
                        // Only rounding was removed.
                        assert!(schur.re.abs() <= 1e-14 * schur.norm(), "{schur}");
                    } else {
                        assert_eq!(r.re, schur.re);
                        assert!(r.re < -1e-4, "{cells} cells: {r}");
                    }
                }
            }
        }
    }

    /// The free flow of a lightly damped chain of the paper's cell, its pairs' relative
    /// displacements, and a start state away from rest.
    fn chain_flow(cells: usize) -> (LinearFlow, Vec<Functional>, DVector<f64>) {
        use crate::test_models::{paper_chain, LIGHT_DAMPING};
        use crate::CellStops;
        let omega = 2.0;
        let model = paper_chain(
            cells,
            omega,
            Some(LIGHT_DAMPING),
            Some(CellStops::symmetric(0.5, 0.8)),
        );
        let n = 2 * cells;
        let flow = LinearFlow::of_model(&model, omega).expect("flow");
        let functionals = model
            .contacts
            .iter()
            .map(|c| {
                let mut position = DVector::zeros(2 * n);
                position.rows_mut(0, n).copy_from(&c.direction(n));
                flow.functional(&position)
            })
            .collect();
        let y = DVector::from_fn(2 * n, |i, _| 0.3 * (1.7 * i as f64 + 0.4).sin());
        (flow, functionals, y)
    }

    /// A chain's modal coordinates `V⁻¹y` with AVX, two modes to a register, are bit for bit
    /// the row-by-row sums (an even and an odd number of kept modes: 8 cells keep 16, and a
    /// flow's kept modes as long less one).
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn modal_coordinates_with_avx_are_the_row_by_row_sums() {
        if !std::arch::is_x86_feature_detected!("avx") {
            eprintln!("skipped: this CPU has no AVX");
            return;
        }
        let (flow, _, y) = chain_flow(8);
        let y = y.as_slice();
        let m = y.len();
        let (rows_re, rows_im) = &flow.inverse_rows;
        let expected: Vec<C64> = flow
            .kept
            .iter()
            .map(|&(k, _)| {
                let (mut re, mut im) = (0.0, 0.0);
                for i in 0..m {
                    re += rows_re[k * m + i] * y[i];
                    im += rows_im[k * m + i] * y[i];
                }
                C64::new(re, im)
            })
            .collect();
        let count = flow.kept.len();
        assert_eq!(count, 16);
        for modes in [count, count - 1] {
            // The first `modes` kept modes' columns, as `kept_inverse_columns` lays them out.
            let columns: Vec<C64> = (0..m)
                .flat_map(|i| flow.kept_inverse_columns[i * count..i * count + modes].to_vec())
                .collect();
            let mut out = vec![C64::default(); modes];
            // SAFETY: the CPU has AVX.
            let done = unsafe { modal_coordinates_avx(&columns, y, &mut out) };
            assert_eq!(done, modes - modes % 2);
            for (a, b) in out[..done].iter().zip(&expected) {
                assert_eq!(
                    (a.re.to_bits(), a.im.to_bits()),
                    (b.re.to_bits(), b.im.to_bits())
                );
            }
        }
    }

    /// A mode's column added to a state with AVX, four entries at once, is bit for bit the
    /// entry-by-entry sum, for every length (whole groups of four and a remainder).
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn a_column_added_with_avx_is_the_entry_by_entry_sum() {
        if !std::arch::is_x86_feature_detected!("avx") {
            eprintln!("skipped: this CPU has no AVX");
            return;
        }
        let z = C64::new(0.37, -1.91);
        for m in 0..14 {
            let value =
                |i: usize, a: f64| (a * i as f64 + 0.3).sin() * 10f64.powi(i as i32 % 5 - 2);
            let (re, im): (Vec<f64>, Vec<f64>) =
                (0..m).map(|i| (value(i, 1.3), value(i, 2.9))).unzip();
            let mut expected: Vec<f64> = (0..m).map(|i| value(i, 0.7)).collect();
            let mut y = expected.clone();
            for i in 0..m {
                expected[i] += re[i] * z.re - im[i] * z.im;
            }
            // SAFETY: the CPU has AVX.
            unsafe { add_column_avx(&re, &im, z, &mut y) };
            assert_eq!(
                y.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                expected.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                "length {m}"
            );
        }
    }

    #[test]
    fn a_functional_expanded_from_the_joint_summaries_is_its_expansion_bit_for_bit() {
        // The watch of several pairs writes only the constant coefficients of a pair's terms
        // written by an earlier flight, copied from the summaries' coefficients: the terms
        // must be those a fresh expansion writes, for every slot of odd and even counts.
        for cells in [3, 8] {
            let (flow, functionals, y) = chain_flow(cells);
            let refs: Vec<&Functional> = functionals.iter().collect();
            let joint = flow.joint_weights(&refs);
            let earlier = flow.flight(&y, 0.7);
            let later = flow.flight(&y.map(|v| 1.3 * v - 0.1), 2.9);
            let (mut modes, mut coefficients, mut sums) = (Vec::new(), Vec::new(), Vec::new());
            let scratch = (&mut modes, &mut coefficients);
            assert!(later.summarize_all(&joint, 2.5, scratch, &mut sums));
            for (slot, functional) in functionals.iter().enumerate() {
                let mut again = ExpSum::default();
                earlier.expand(functional, &mut again);
                later.expand_joint(functional, (&coefficients, slot), &mut again);
                let mut fresh = ExpSum::default();
                later.expand(functional, &mut fresh);
                assert_eq!(format!("{again:?}"), format!("{fresh:?}"), "{cells} cells");
                // Not what the earlier flight left.
                let mut first = ExpSum::default();
                earlier.expand(functional, &mut first);
                assert_ne!(format!("{first:?}"), format!("{fresh:?}"));
            }
            // A gap of another length is expanded afresh.
            let mut short = ExpSum::default();
            later.expand_joint(&functionals[0], (&coefficients, 0), &mut short);
            let mut fresh = ExpSum::default();
            later.expand(&functionals[0], &mut fresh);
            assert_eq!(format!("{short:?}"), format!("{fresh:?}"));
        }
    }

    #[test]
    fn joint_summaries_are_each_pairs_summary_bit_for_bit() {
        // Regression guard for the watch of several pairs: its one-pass summaries must be the
        // very sums the per-pair summary (and so the search) forms, for odd and even counts.
        for cells in [2, 3, 8] {
            let (flow, functionals, y) = chain_flow(cells);
            let refs: Vec<&Functional> = functionals.iter().collect();
            let joint = flow.joint_weights(&refs);
            let flight = flow.flight(&y, 0.7);
            let (mut modes, mut coefficients, mut out) = (Vec::new(), Vec::new(), Vec::new());
            let scratch = (&mut modes, &mut coefficients);
            assert!(flight.summarize_all(&joint, 2.5, scratch, &mut out));
            assert_eq!(out.len(), cells);
            for (sum, functional) in out.iter().zip(&functionals) {
                let single = flight.summarize(functional, 2.5).expect("summary");
                assert_eq!(format!("{sum:?}"), format!("{single:?}"), "{cells} cells");
            }
        }
    }

    #[test]
    fn summarised_searches_find_the_one_pair_searches_exits() {
        // The summarised search (fixed grid, cached chunk exponentials, seeded polish) against
        // the search on the horizon's grid (stepped exponentials, fresh polish) over many flights of an 8-cell chain, every
        // pair, full and cut horizons, bands from wide to grazing: the same first exit, to the
        // time tolerance, on the same side.
        use crate::expsum::SearchStack;
        let (flow, functionals, _) = chain_flow(8);
        let (tol, depth) = (1e-12 * std::f64::consts::PI, 1e-12);
        let tolerances = crate::expsum::Tolerances { time: tol, depth };
        let (mut plain, mut summarised) = (SearchStack::default(), SearchStack::default());
        let mut gap = ExpSum::default();
        let (mut exits, mut searches) = (0, 0);
        for case in 0..300 {
            let y = DVector::from_fn(32, |i, _| {
                0.4 * (1.3 * (i * 7 + case * 13) as f64 + 0.2 * case as f64).sin()
            });
            let t0 = 0.01 * case as f64 % std::f64::consts::PI;
            let flight = flow.flight(&y, t0);
            let horizon = std::f64::consts::PI - t0;
            for functional in &functionals {
                flight.expand(functional, &mut gap);
                let summary = flight.summarize(functional, horizon).expect("summary");
                let f0 = gap.eval(0.0).0;
                for width in [0.05, 0.2, 0.5, 1.0] {
                    let (lo, hi) = (f0 - width, f0 + 0.7 * width);
                    for cutoff in [horizon, 0.5 * horizon, 0.1] {
                        let expected = gap.first_exit_on_horizon_grid(
                            (lo, hi),
                            horizon,
                            cutoff,
                            tolerances,
                            &mut plain,
                        );
                        let found = if summary.excludes(lo, hi, cutoff.min(horizon), horizon) {
                            None
                        } else {
                            searches += 1;
                            gap.first_exit_summarized(
                                &summary,
                                (lo, hi),
                                horizon,
                                cutoff,
                                tolerances,
                                &mut summarised,
                            )
                        };
                        // Exits after the cutoff may or may not be reported.
                        let keep = |e: Option<(f64, i8)>| e.filter(|&(s, _)| s <= cutoff);
                        match (keep(expected), keep(found)) {
                            (None, None) => {}
                            (Some((a, sa)), Some((b, sb))) => {
                                exits += 1;
                                assert_eq!(sa, sb, "case {case}: side");
                                assert!((a - b).abs() <= 4.0 * tol, "case {case}: {a} vs {b}");
                            }
                            (a, b) => panic!("case {case}: {a:?} vs {b:?}"),
                        }
                    }
                }
            }
        }
        assert!(
            exits > 1000 && searches > 2000,
            "{exits} exits, {searches} searches"
        );
    }

    /// A chain's state at a contact (its exponentials known, and not) is bit for bit the
    /// state formed mode by mode and entry by entry, whether or not it is formed with AVX.
    #[test]
    fn a_chains_state_is_its_modes_summed_entry_by_entry() {
        for cells in [2, 3, 8] {
            let (flow, _, y) = chain_flow(cells);
            let flight = flow.flight(&y, 0.7);
            let Form::Steady {
                response: p,
                deviation,
                phase,
            } = &flight.form
            else {
                panic!("steady response");
            };
            let s = 0.45;
            let exps = kept_exponentials(&flow, s);
            let m = 2 * flow.dofs;
            let mut expected = vec![0.0; m];
            let forced = exps[flow.kept.len()] * phase;
            for (j, &(k, weight)) in flow.kept.iter().enumerate() {
                let z = (deviation[j] * exps[j]
                    + p.plus[j] * forced
                    + p.minus[j] * forced.conj()
                    + p.constant[j])
                    * weight;
                for (i, y) in expected.iter_mut().enumerate() {
                    *y += flow.mode_columns.0[k * m + i] * z.re
                        - flow.mode_columns.1[k * m + i] * z.im;
                }
            }
            let mut state = DVector::zeros(m);
            flight.state_at(s, &exps, &mut state);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(state.as_slice()), bits(&expected), "{cells} cells");
        }
    }

    /// The packed products and scaled sums of a carried deviation are the scalar ones bit for
    /// bit, for odd and even lengths.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn packed_carries_are_the_scalar_ones_bit_for_bit() {
        if !std::arch::is_x86_feature_detected!("avx") {
            return;
        }
        let mut x = 0.3_f64;
        let mut next = move || {
            x = (x * 7919.0 + 0.123).fract();
            (x - 0.5) * 10f64.powi((x * 7.0) as i32 - 3)
        };
        let bits = |v: &[C64]| {
            v.iter()
                .flat_map(|c| [c.re.to_bits(), c.im.to_bits()])
                .collect::<Vec<_>>()
        };
        for n in [0, 1, 2, 7, 16, 17] {
            let a: Vec<C64> = (0..n).map(|_| C64::new(next(), next())).collect();
            let b: Vec<C64> = (0..n).map(|_| C64::new(next(), next())).collect();
            let mut packed = vec![C64::default(); n];
            // SAFETY: the CPU has AVX.
            unsafe { crate::expsum::products_avx(&a, &b, &mut packed) };
            let scalar: Vec<C64> = a.iter().zip(&b).map(|(&x, &y)| x * y).collect();
            assert_eq!(bits(&packed), bits(&scalar), "products, {n}");
            let delta = next();
            let mut packed = a.clone();
            // SAFETY: the CPU has AVX.
            unsafe { add_scaled_avx(&mut packed, &b, delta) };
            let scalar: Vec<C64> = a.iter().zip(&b).map(|(&h, &v)| h + v * delta).collect();
            assert_eq!(bits(&packed), bits(&scalar), "scaled sums, {n}");
        }
    }

    #[test]
    fn a_carried_deviation_is_the_state_s_flight() {
        // The start carried across an event (the deviation at `s`, plus a velocity jump)
        // against the flight recomputed from the state there: the same motion to rounding.
        let (flow, _, y) = chain_flow(3);
        let n = 6;
        let flight = flow.flight(&y, 0.7);
        let s = 0.45;
        let exps = kept_exponentials(&flow, s);
        let before = flight.state(s);
        let mut after = before.clone();
        after[n + 2] += 0.25;
        after[n + 3] -= 0.125;
        let mut deviation = Vec::new();
        assert!(flight.deviation_at(&exps, &mut deviation));
        let changed = 0..before.len();
        flow.add_jump(
            &mut deviation,
            (before.as_slice(), after.as_slice()),
            changed,
        );
        let (sin, cos) = crate::trig::sin_cos(flow.omega * (0.7 + s));
        let carried = flow
            .flight_with_deviation(deviation, C64::new(cos, sin))
            .expect("steady response");
        let fresh = flow.flight(&after, 0.7 + s);
        for t in [0.0, 0.3, 1.1] {
            let (a, b) = (carried.state(t), fresh.state(t));
            let error = (&a - &b).amax();
            assert!(error <= 1e-13 * b.amax(), "t = {t}: {error:e}");
        }
    }

    #[test]
    fn eigenvalues_where_the_plain_schur_iteration_cycles() {
        // A 4×4 matrix (a monodromy met in a map) on which nalgebra's unbounded real Schur
        // iteration never converges; column by column.
        let a = DMatrix::from_column_slice(
            4,
            4,
            &[
                -0.5949065900786252,
                -0.54785366462303,
                0.09877288697600826,
                0.12768814862690236,
                -0.2736063407419963,
                -0.24558433817231848,
                -0.24127877581140877,
                -0.10566685059017007,
                -0.08898796197315695,
                -0.12830918791764725,
                -0.48568868720653724,
                -0.48981661360765977,
                0.17069267029308077,
                0.07791231009587478,
                -0.3650431717907076,
                -0.34735400366643376,
            ],
        );
        let rates = eigenvalues(&a).expect("converges");
        let sum: C64 = rates.iter().sum();
        let product: C64 = rates.iter().product();
        assert!((sum.re - a.trace()).abs() < 1e-12 && sum.im.abs() < 1e-12);
        assert!((product.re - a.clone().determinant()).abs() < 1e-12);
        let ac = a.map(|v| C64::new(v, 0.0));
        for &l in &rates {
            let shifted = &ac - DMatrix::<C64>::identity(4, 4) * l;
            assert!(shifted.determinant().norm() < 1e-10, "{l}");
        }
        let mut bad = a;
        bad[(0, 3)] = f64::INFINITY;
        assert_eq!(eigenvalues(&bad), Err(FlowError::NotFinite));
    }
}
