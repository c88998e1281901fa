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
//!
//! A structure with free bodies (a common null space `R` of `K` and `C`: rigid modes) has a
//! defective `A` (a Jordan block at 0 per rigid mode), so its flow splits off the rigid
//! subspace (`rigid`): the elastic modes are those of the reduced system on `R`'s
//! `M`-orthogonal complement, the rigid coordinates fly as free bodies, `q(s) = h_q + h_p s +
//! g₀s²/2 + Re(P e^{iω(t₀+s)})`, and a functional of the state gains a polynomial term of
//! rate 0 and a term of rate `iω`. Such a flow flies in the general (resonance-safe) form,
//! which carries polynomial terms; the steady-response form, its summaries and its packed
//! kernels serve the flows without rigid modes, unchanged. Its propagator adds the rigid
//! block `(1, s; 0, 1)`. A body held by a dashpot alone (`K r = 0`, `C r ≠ 0`) is no rigid
//! mode: its zero rate is simple, with the eigenvector `(r, 0)`, and the modal flow holds it.
//!
//! Higher harmonics of the forcing (`Re(F_k e^{ikωt})`, integer `k ≥ 2`) enter as the
//! fundamental does, each with its own modal forcing `g^±_k` on `e^{±ikωt}`: in the general
//! form a mode gains `Σ_k g^±_k φ(λ, ±ikω, s)`, resonance-safe per order (the `s e^{λs}` form
//! where `|ikω − λ| T` is below `10⁻⁴`), and a rigid mode the particular solution
//! `−F_k/(kω)²` (its rate 0 meets no `kω`). Where no harmonic is resonant either, the steady
//! response holds each harmonic's part, `P^±_k = g^±_k/(±ikω − λ)` (`steady`), and a flight in
//! the steady-response form gains one exponential per harmonic, of rate `ikω`, after the
//! forcing's: its summaries, joint summaries, carries across contacts and sections work as
//! without harmonics. The AVX kernels of a flight's state and modal coordinates serve the
//! forcing at `ω` alone; with harmonics those are formed mode by mode. A functional's term of
//! rate `ikω` the event search bounds as any other term (its derivatives scale with `kω`), so
//! the first contact keeps its guarantee.
//!
//! This module builds the flow (eigen-decomposition, modal forcing); its steady response is in
//! `steady`, a flight from a state and its evaluation (states, modal coordinates, exponential
//! sums and their summaries) in `flight`, and the AVX kernels of both in `packed`.

mod flight;
mod modes;
#[cfg(target_arch = "x86_64")]
mod packed;
mod rigid;
mod steady;
#[cfg(test)]
mod steady_tests;
#[cfg(test)]
mod tests;

use crate::expsum::{ModeTerm, LANES};
pub use flight::Flight;
use flight::{Form, GeneralStart, HarmonicStart};
pub(crate) use modes::eigenvalues;
use modes::{
    conservative_rates, first_order, joint_modes, kept_modes, kept_peaks, modal_inverse,
    pencil_modes,
};
use nalgebra::{Complex, DMatrix, DVector};
#[cfg(target_arch = "x86_64")]
use packed::{add_column, add_scaled_avx, modal_coordinates_avx, AVX_COLUMN, PACKED_MODES};
use steady::SteadyResponse;
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
    /// The common null space of the stiffness and damping matrices (this many rigid modes) is
    /// not also their left null space (`Rᵀ K ≠ 0` or `Rᵀ C ≠ 0`, only possible for
    /// non-symmetric matrices): the rigid motion does not separate from the elastic one.
    #[error("the {0} rigid mode(s) are not a left null space of the stiffness and damping")]
    UnbalancedRigidModes(usize),
    /// A constant force acts on rigid mode `j` (counted among the flow's rigid modes): it
    /// accelerates without bound and there is no steady state.
    #[error("a constant force drives rigid mode {0}: it drifts without bound, no steady state")]
    RigidDrift(usize),
    /// A mode is resonant with the forcing (`|μ − λ| T ≤ 10⁻⁴`): the response grows without
    /// bound and there is no linear steady state.
    #[error("a mode is resonant with the forcing: no linear steady state")]
    Resonant,
}

/// Below this `|μ − λ|·T` a forcing rate counts as resonant with a mode.
const RESONANCE: f64 = 1e-4;

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
    /// The higher harmonics of the forcing (orders `k ≥ 2`, none of zero amplitude), each with
    /// its modal forcing on `e^{±ikωt}`; empty for a forcing at `ω` alone.
    harmonics: Vec<FlowHarmonic>,
    /// The forced steady response (of the fundamental and of every higher harmonic), when no
    /// mode is resonant with the forcing or any of its harmonics and there is no rigid mode.
    steady: Option<SteadyResponse>,
    /// The rigid modes ([`rigid`]), if any: the modes above are then the elastic ones only
    /// (`2(n − r)` of them), `V⁻¹` their rows of `W⁻¹`.
    rigid: Option<Box<rigid::RigidModes>>,
}

/// The modal basis of a flow ([`LinearFlow::basis`]).
pub(crate) struct ModalBasis<'a> {
    /// The elastic rates `λ_k`.
    pub(crate) rates: &'a [C64],
    /// Their eigenvectors `V` as columns (`2n × m`).
    pub(crate) modes: &'a DMatrix<C64>,
    /// `V⁻¹`'s rows for the elastic coordinates (`m × 2n`).
    pub(crate) inverse: &'a DMatrix<C64>,
    /// With rigid modes: `R` (`n × r`), `X_q` and `X_p` (`r × 2n` each).
    pub(crate) rigid: Option<(&'a DMatrix<f64>, &'a DMatrix<f64>, &'a DMatrix<f64>)>,
}

/// One higher harmonic of a flow's forcing, `f_c,k cos kωt + f_s,k sin kωt`: its rate `kω`
/// and its modal forcing `g⁺_k`, `g⁻_k` on `e^{ikωt}` and `e^{−ikωt}`, as the fundamental's.
#[derive(Debug, Clone)]
struct FlowHarmonic {
    order: u32,
    rate: f64,
    plus: DVector<C64>,
    minus: DVector<C64>,
}

/// A linear functional `c · y` of the state, prepared for fast flights: its modal weights
/// `Vᵀc` and, when the flow has a steady response, that response's contribution
/// `Re(forced e^{iωt}) + constant + Σ_k Re(harmonic_k e^{ikωt})`.
#[derive(Debug, Clone)]
pub struct Functional {
    /// `Vᵀc` over the modes, then, with rigid modes, each one's weights `a_j + i b_j` on its
    /// position and velocity ([`rigid::RigidModes::weights`]).
    weights: DVector<C64>,
    forced: C64,
    constant: f64,
    /// Each higher harmonic's forced part, in the flow's order of its harmonics (empty
    /// without a steady response or without harmonics).
    harmonic: Vec<C64>,
}

/// Several functionals prepared for [`Flight::summarize_all`]: in blocks of [`LANES`]
/// functionals, per kept mode, their modal weights `[Re w₀, …, Re w₃, Im w₀, …, Im w₃]`, then
/// their forced parts likewise, then each higher harmonic's forced parts likewise (a last
/// block filled up with zeros), and each functional's constant.
#[derive(Debug, Clone, Default)]
pub(crate) struct JointWeights {
    count: usize,
    blocks: Vec<[f64; 2 * LANES]>,
    constant: Vec<f64>,
}

/// Whether a forcing rate `μ = λ + δ` counts as resonant with the mode of rate `λ`.
fn resonant(delta: C64, period: f64) -> bool {
    (delta.re.abs() + delta.im.abs()) * period <= RESONANCE
}

/// `e^{μ s}`, skipping the real exponential for purely oscillatory rates.
#[inline]
fn cexp(mu: C64, s: f64) -> C64 {
    let (sin, cos) = crate::trig::sin_cos(mu.im * s);
    let r = if mu.re == 0.0 { 1.0 } else { (mu.re * s).exp() };
    C64::new(r * cos, r * sin)
}

impl LinearFlow {
    /// The free flow of `model` (its masses, dampings, stiffnesses and forcing, no constant
    /// force) at forcing frequency `omega`: the flight between its events.
    ///
    /// # Errors
    /// As [`LinearFlow::new`].
    pub(crate) fn of_model(model: &crate::Model, omega: f64) -> Result<Self, FlowError> {
        let harmonics: Vec<crate::Harmonic> = model.active_harmonics().cloned().collect();
        let flow = LinearFlow::with_harmonics(
            (&model.mass, model.damping.as_ref(), &model.stiffness),
            (
                &model.forcing_cos,
                &model.forcing_sin,
                &DVector::zeros(model.mass.nrows()),
            ),
            &harmonics,
            omega,
        )?;
        Ok(if model.general_form {
            flow.without_steady_response()
        } else {
            flow
        })
    }

    /// The flow of `M ü + C u̇ + K u = f_c cos ωt + f_s sin ωt + f₀` (`damping` `None`: no
    /// damping terms at all).
    ///
    /// # Errors
    /// As [`LinearFlow::with_harmonics`].
    pub fn new(
        mass: &DMatrix<f64>,
        damping: Option<&DMatrix<f64>>,
        stiffness: &DMatrix<f64>,
        forcing_cos: &DVector<f64>,
        forcing_sin: &DVector<f64>,
        forcing_constant: &DVector<f64>,
        omega: f64,
    ) -> Result<Self, FlowError> {
        LinearFlow::with_harmonics(
            (mass, damping, stiffness),
            (forcing_cos, forcing_sin, forcing_constant),
            &[],
            omega,
        )
    }

    /// The flow of `M ü + C u̇ + K u = f_c cos ωt + f_s sin ωt + Σ_k (f_c,k cos kωt +
    /// f_s,k sin kωt) + f₀`, the matrices `(M, C, K)` (`C` `None`: no damping terms at all),
    /// the forcing `(f_c, f_s, f₀)` and the higher `harmonics` (orders `k ≥ 2`, each vector of
    /// `n` entries; a harmonic of zero amplitude is left out). Without harmonics it is the
    /// flow of [`LinearFlow::new`], bit for bit. With them, where no mode is resonant with the
    /// forcing or a harmonic and there is no rigid mode, the steady response holds each
    /// harmonic's periodic response at `kω` and flights are in the steady-response form, one
    /// exponential per harmonic added. Otherwise flights are in the resonance-safe general
    /// form: each harmonic adds to mode `λ` the particular terms `g^±_k φ(λ, ±ikω, s)`,
    /// finite (secular) where `kω` meets an undamped natural frequency, and to each rigid
    /// mode the particular solution `−F_k/(kω)²`.
    ///
    /// # Errors
    /// [`FlowError::SingularMass`], [`FlowError::Defective`], [`FlowError::NotFinite`],
    /// [`FlowError::NoConvergence`] and [`FlowError::UnbalancedRigidModes`] when the modal
    /// flow does not exist.
    ///
    /// # Panics
    /// If a harmonic's vectors are not of `n` entries ([`crate::Model::with_harmonics`]
    /// checks them).
    pub fn with_harmonics(
        (mass, damping, stiffness): (&DMatrix<f64>, Option<&DMatrix<f64>>, &DMatrix<f64>),
        (forcing_cos, forcing_sin, forcing_constant): (&DVector<f64>, &DVector<f64>, &DVector<f64>),
        harmonics: &[crate::Harmonic],
        omega: f64,
    ) -> Result<Self, FlowError> {
        let n = mass.nrows();
        let harmonics: Vec<&crate::Harmonic> = harmonics.iter().filter(|h| !h.is_zero()).collect();
        let (minv, a) = first_order(mass, damping, stiffness)?;
        // The rigid modes apart (`rigid`): the elastic rates are the reduced system's.
        let shapes = rigid::shapes(stiffness, damping)?;
        let mut rates = if shapes.ncols() == 0 {
            eigenvalues(&a)?
        } else {
            eigenvalues(&rigid::reduced_system(
                mass, &minv, stiffness, damping, &shapes,
            ))?
        };
        if damping.is_none() {
            conservative_rates(&mut rates);
        }
        let modes = pencil_modes(mass, damping, stiffness, &rates)?;
        let forcing = (forcing_cos, forcing_sin, forcing_constant);
        let rigid_harmonics: Vec<rigid::HarmonicForce<'_>> = harmonics
            .iter()
            .map(|h| (h.order as f64 * omega, &h.cos, &h.sin))
            .collect();
        let (inverse, rigid) = modal_inverse(
            &modes,
            shapes,
            rates.len(),
            &minv,
            (forcing, &rigid_harmonics),
            omega,
        )?;
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
        // Each harmonic as the fundamental: `F_k = (f_c,k − i f_s,k)/2` on `e^{ikωt}`.
        let harmonics: Vec<FlowHarmonic> = harmonics
            .iter()
            .map(|h| {
                let f = DVector::from_fn(n, |i, _| C64::new(h.cos[i], -h.sin[i]) * 0.5);
                FlowHarmonic {
                    order: h.order,
                    rate: h.order as f64 * omega,
                    plus: lift(f.clone()),
                    minus: lift(f.map(|c| c.conj())),
                }
            })
            .collect();
        let period = std::f64::consts::TAU / omega;
        let kept = kept_modes(&rates);
        let kept_sizes: Vec<(f64, f64)> = kept
            .iter()
            .map(|&(k, _)| {
                let rate = rates[k].re.abs() + rates[k].im.abs();
                (rate, rate * rate * rate)
            })
            .collect();
        // A flow with rigid modes flies in the general form, which carries them.
        let steady = rigid
            .is_none()
            .then(|| {
                SteadyResponse::new(
                    &rates,
                    (&plus, &minus, &constant, &harmonics),
                    omega,
                    period,
                )
            })
            .flatten()
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
        let harmonic_rates: Vec<f64> = harmonics.iter().map(|h| h.rate).collect();
        let joint_modes = joint_modes(&rates, &kept, &kept_sizes, (omega, &harmonic_rates))
            .filter(|_| rigid.is_none());
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
            harmonics,
            steady,
            rigid,
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

    /// The modal basis as built: the elastic rates `λ_k`, their eigenvectors `V` (columns,
    /// `2n` rows), the rows of `V⁻¹` giving a state's elastic coordinates, and with rigid
    /// modes their shapes `R` and the rows `X_q`, `X_p` giving their positions and velocities
    /// (`y = Re Σ_k V_k z_k + (R q, R p)`): what a flow under another forcing
    /// ([`crate::respond`]) is built on.
    pub(crate) fn basis(&self) -> ModalBasis<'_> {
        ModalBasis {
            rates: &self.rates,
            modes: &self.modes,
            inverse: &self.inverse,
            rigid: self
                .rigid
                .as_deref()
                .map(|r| (&r.shapes, &r.position_rows, &r.velocity_rows)),
        }
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
        if let Some(rigid) = &self.rigid {
            rigid.add_propagator(s, out);
        }
    }

    /// Rigid modes `r`: the dimension of the common null space of `K` and `C` (a free body
    /// contributes one per direction it moves in unheld). The elastic modes number
    /// `2(n − r)`.
    pub fn rigid_modes(&self) -> usize {
        self.rigid.as_ref().map_or(0, |r| r.count())
    }

    /// The rigid shapes `R` (`n × r`, orthonormal columns), if the flow has rigid modes.
    pub fn rigid_shapes(&self) -> Option<&DMatrix<f64>> {
        self.rigid.as_ref().map(|r| &r.shapes)
    }

    /// The linear steady state `y(t)` (length `2n`) at time `t`, the motion with every free
    /// transient decayed: each elastic mode's forced response
    /// `Re Σ_k v_k (g⁺_k e^{iωt}/(iω − λ_k) + g⁻_k e^{−iωt}/(−iω − λ_k) − g⁰_k/λ_k)`, plus
    /// the same at `kω` for each higher harmonic (the responses of a linear system add). With
    /// rigid modes the steady state is a family (a rigid mode keeps any constant position):
    /// this is its zero-mean member, each rigid mode on the particular solution
    /// `q = −Re(F e^{iωt})/ω² − Σ_k Re(F_k e^{ikωt})/(kω)²` alone.
    ///
    /// # Errors
    /// [`FlowError::Resonant`] when a mode is resonant with the forcing or one of its
    /// harmonics (or, under a constant force, a mode has rate 0), [`FlowError::RigidDrift`]
    /// when a constant force acts on a rigid mode.
    pub fn linear_steady_state(&self, t: f64) -> Result<DVector<f64>, FlowError> {
        let m = 2 * self.dofs;
        let w = C64::new(0.0, self.omega);
        let (sin, cos) = crate::trig::sin_cos(self.omega * t);
        let phase = C64::new(cos, sin);
        let harmonic_phases: Vec<C64> = self
            .harmonics
            .iter()
            .map(|h| {
                let (sin, cos) = crate::trig::sin_cos(h.rate * t);
                C64::new(cos, sin)
            })
            .collect();
        let has_constant = self.constant.iter().any(|c| *c != C64::default());
        let mut y = DVector::zeros(m);
        for (k, &l) in self.rates.iter().enumerate() {
            let forced_at_zero = has_constant && resonant(-l, self.period);
            if resonant(w - l, self.period) || resonant(-w - l, self.period) || forced_at_zero {
                return Err(FlowError::Resonant);
            }
            let mut z = self.plus[k] / (w - l) * phase + self.minus[k] / (-w - l) * phase.conj();
            if has_constant {
                z -= self.constant[k] / l;
            }
            for (h, &phase) in self.harmonics.iter().zip(&harmonic_phases) {
                let wk = C64::new(0.0, h.rate);
                if resonant(wk - l, self.period) || resonant(-wk - l, self.period) {
                    return Err(FlowError::Resonant);
                }
                z += h.plus[k] / (wk - l) * phase + h.minus[k] / (-wk - l) * phase.conj();
            }
            for i in 0..m {
                y[i] += (self.modes[(i, k)] * z).re;
            }
        }
        if let Some(rigid) = &self.rigid {
            rigid.add_steady_state((phase, &harmonic_phases), self.omega, y.as_mut_slice())?;
        }
        Ok(y)
    }

    /// The orders `k ≥ 2` of the flow's higher harmonics, in their order (none of zero
    /// amplitude); empty for a forcing at `ω` alone.
    pub fn harmonic_orders(&self) -> Vec<u32> {
        self.harmonics.iter().map(|h| h.order).collect()
    }

    /// `e^{ikωt₀}` of each higher harmonic, from the fundamental's phase `e^{iωt₀}`: its
    /// `k`-th power (by squaring, a few roundings per doubling of `k`).
    fn harmonic_phases(&self, phase: C64) -> Vec<C64> {
        if self.harmonics.is_empty() {
            return Vec::new();
        }
        self.harmonics.iter().map(|h| phase.powu(h.order)).collect()
    }

    /// Whether flights use the steady forced response (no mode resonant with the forcing or
    /// any of its harmonics, no rigid mode); at or near resonance they use the resonance-safe
    /// `φ` form instead.
    pub fn has_steady_response(&self) -> bool {
        self.steady.is_some()
    }

    /// The higher harmonics the steady response carries (each one's term in a steady-form
    /// expansion, after the forcing's): the flow's harmonics with a steady response, none
    /// without.
    fn steady_harmonics(&self) -> usize {
        self.steady.as_ref().map_or(0, |p| p.harmonics.len())
    }

    /// The flow with every flight in the general form, whether or not the steady response
    /// exists: the reference the steady-response form is checked against
    /// ([`crate::Model::with_general_form`]).
    pub(crate) fn without_steady_response(mut self) -> Self {
        self.steady = None;
        self.joint_modes = None;
        self
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
                // Each harmonic's phase `e^{ikωt₀}` (none without harmonics: no allocation).
                let harmonic_phases = self.harmonic_phases(phase);
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
                        *h = z - p.at(j, phase, &harmonic_phases);
                    }
                    return Flight {
                        flow: self,
                        form: Form::Steady {
                            response: p,
                            deviation,
                            phase,
                            harmonic_phases,
                        },
                    };
                }
                for (j, (h, &(k, _))) in deviation.iter_mut().zip(&self.kept).enumerate() {
                    let row = k * m..(k + 1) * m;
                    let z = self.modal_coordinate((&rows_re[row.clone()], &rows_im[row]), y);
                    *h = z - p.at(j, phase, &harmonic_phases);
                }
                Form::Steady {
                    response: p,
                    deviation,
                    phase,
                    harmonic_phases,
                }
            }
            None => {
                let harmonic_phases = self.harmonic_phases(phase);
                Form::General(Box::new(GeneralStart {
                    start: match &self.rigid {
                        None => &self.inverse * y.map(|v| C64::new(v, 0.0)),
                        Some(rigid) => rigid.start(
                            &self.inverse * y.map(|v| C64::new(v, 0.0)),
                            y,
                            (phase, &harmonic_phases),
                            self.omega,
                        ),
                    },
                    plus: self.plus.map(|g| g * phase),
                    minus: self.minus.map(|g| g * phase.conj()),
                    harmonics: self
                        .harmonics
                        .iter()
                        .zip(&harmonic_phases)
                        .map(|(h, &phase)| HarmonicStart {
                            rate: C64::new(0.0, h.rate),
                            plus: h.plus.map(|g| g * phase),
                            minus: h.minus.map(|g| g * phase.conj()),
                        })
                        .collect(),
                }))
            }
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
                harmonic_phases: self.harmonic_phases(phase),
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
            for h in 0..self.steady_harmonics() {
                let forced: [C64; LANES] = std::array::from_fn(|l| {
                    lane(l, &|f| f.harmonic.get(h).copied().unwrap_or_default())
                });
                joint.blocks.push(std::array::from_fn(|i| {
                    if i < LANES {
                        forced[i].re
                    } else {
                        forced[i - LANES].im
                    }
                }));
            }
        }
        joint
            .constant
            .extend(functionals.iter().map(|f| f.constant));
        joint
    }

    /// Modal weights `Vᵀ c` of the functional `c · y`, with the steady response's part.
    pub fn functional(&self, c: &DVector<f64>) -> Functional {
        let mut weights = self.modes.transpose() * c.map(|v| C64::new(v, 0.0));
        if let Some(rigid) = &self.rigid {
            weights = rigid.weights(weights, c);
        }
        let (forced, constant, harmonic) = match &self.steady {
            Some(p) => p.functional_parts(&weights, &self.kept),
            None => (C64::default(), 0.0, Vec::new()),
        };
        Functional {
            weights,
            forced,
            constant,
            harmonic,
        }
    }
}
