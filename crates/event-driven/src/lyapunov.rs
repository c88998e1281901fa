//! Lyapunov exponents of the impacting flow from the simulator's exact tangent flow.
//!
//! The tangent flow is the one [`crate::newton`] uses for its Jacobian, extended to sticking:
//! each free flight's homogeneous propagator `e^{Aτ}` (the modal closed form), at each impact
//! the saltation matrix `S = Ĝ + (f⁺ − Ĝ f⁻) h_xᵀ / (h_x · f⁻)` (`det S = e²`), at each stick
//! the plastic saltation matrix onto the held pair's constrained tangent space, while a pair
//! is held the reduced flow's propagator, and at a release the identity (the contact force is
//! zero there, so the free and the constrained vector fields agree).
//!
//! Benettin's method: an orthonormal frame `Q` (`2n` vectors) is carried along the run and
//! re-orthonormalised by a QR factorisation at every section `t = kT`, `J Q = Q' R`; the
//! exponents are `λ_i = (1/t) Σ_k log |R_ii|`, in 1/s, in descending order (sorted; Benettin's
//! order is descending once the frame has aligned).
//!
//! Two exact identities make the output checkable:
//! - a periodic motion of `p` periods has `λ_i = log |μ_i| / (pT)` with `μ_i` its Floquet
//!   multipliers;
//! - while no pair sticks, `Σ λ_i = tr A + 2 log(e) × impacts per second`, since
//!   `log |det J| = tr A · t + Σ log e²`.
//!
//! A stick maps every perturbation onto the constrained tangent space of the held pair
//! (`d·δu = d·δu̇ = 0`): the two directions across it are contracted to zero in finite time,
//! exponents `−∞`. Those are not reported as numbers: [`LyapunovSpectrum::collapsed`] counts
//! them, and [`LyapunovSpectrum::exponents`] holds the `2n − collapsed` finite ones (the
//! frame's last columns carry only rounding after a stick, which is why they are dropped).
//!
//! The uncertainty covers the two ways a finite-time exponent errs:
//! - a statistical error, for a chaotic motion: the run is cut into [`BATCHES`] consecutive
//!   blocks, each gives its own exponents, and the standard error of their mean (their spread
//!   over `√B`) is the error of a time average whose correlation time is shorter than a block;
//!   [`UNCERTAINTY_FACTOR`] times it (about 95 % for a Gaussian mean);
//! - a bounded oscillation, for a periodic or quasi-periodic motion: the two members of a
//!   complex pair of multipliers (or a torus's rotating directions) share one growth rate and
//!   split it by a bounded, oscillating factor `g(t)`, so each member is off by
//!   `(g(t) − g(0))/t`. Block boundaries can alias that oscillation (a rotation close to a
//!   multiple of `2π` per block), so the batch spread misses it; the running sum's deviation
//!   from the fitted line `Σ log R_ii − λ t` (its "bridge") does not: its range over the run is
//!   at least that of `g` once the rotation has turned a few times, hence at least the final
//!   error. For a chaotic motion the bridge is a Brownian bridge, whose range is `~σ√t`, the
//!   order of the statistical error again.
//!
//! The uncertainty reported is the larger of the two, divided by the time where it is a range.

use crate::engine::{check_inputs, Engine, SimulationError, SimulationOptions, Start, SteadyState};
use crate::model::Model;
use crate::newton::shifted;
use nalgebra::DMatrix;
use thiserror::Error;

/// Default [`LyapunovOptions::periods`]. The statistical uncertainty of a chaotic motion
/// falls as `1/√N`: at 2000 periods the largest exponent of the paper's unit at a chaotic
/// point (ω = 1.25, Δ = 0.25, e = 0.8, light damping: `λ₁ = 0.384 ± 0.010`/s;
/// `tests/lyapunov.rs`) is known to 3 % of itself, enough to tell chaos (positive beyond the
/// uncertainty) from a quasi-periodic or slowly settling motion. The cost is 1.4× that of a
/// plain simulation of as many periods (benchmark `lyapunov`: 16.0 ms against 11.2 ms for
/// 1000 periods there, ~16 impacts a period), so about 35 ms at the default.
pub const DEFAULT_LYAPUNOV_PERIODS: u64 = 2000;

/// Default [`LyapunovOptions::alignment_periods`]: the frame aligns with the growth directions
/// at the rate of the gaps between distinct exponents, `e^{−(λ_i − λ_{i+1}) T}` per period; on
/// the paper's unit the gaps between a decaying pair and the next exponent are ≥ 0.1/s
/// (`T` ≈ 3.3–6.3 s), so 100 periods bring the frame's error below rounding while costing 5 %
/// of the default run. Gaps too small to align within it (two nearly equal exponents of a
/// chaotic motion) leave an error `O(1/t)`, below the statistical `O(1/√t)`.
pub const DEFAULT_ALIGNMENT_PERIODS: u64 = 100;

/// Number of consecutive blocks of the run for the batch-means uncertainty: enough blocks for
/// their spread to estimate a standard deviation (9 degrees of freedom), few enough that each
/// block is long against the motion's correlation time (200 periods each at the default).
pub const BATCHES: u64 = 10;

/// Multiple of the batch-means standard error reported as the uncertainty: two, an interval
/// of about 95 % for a Gaussian mean.
pub const UNCERTAINTY_FACTOR: f64 = 2.0;

/// The frame the run starts from: an orthonormal basis in general position, deterministic (the
/// Q of a fixed matrix of well-spread entries `frac(i·√2 + j·√3)`). Not the identity: its
/// first `n` vectors are pure displacements, and a unit whose modes are (nearly) proportionally
/// damped maps that subspace onto one direction of each mode's plane, so the frame's leading
/// plane would not see the slowest mode's second direction until rounding seeded it (measured:
/// ~200 periods of misalignment on the linear paper unit at ω = 1.3).
fn initial_frame(m: usize) -> DMatrix<f64> {
    let spread = DMatrix::from_fn(m, m, |i, j| {
        let x = (i + 1) as f64 * std::f64::consts::SQRT_2 + (j + 1) as f64 * 3f64.sqrt();
        x.fract() - 0.5
    });
    spread.qr().q()
}

/// At most this many points of the running sums are kept for the bridge (every period up to
/// it, then every `⌈periods/MAX_BRIDGE_POINTS⌉`-th): a range over 65 536 points of a run misses
/// little of the oscillation's range, and keeps the record at 2 MB for the unit.
pub const MAX_BRIDGE_POINTS: u64 = 65_536;

/// How the exponents are computed.
#[derive(Debug, Clone, PartialEq)]
pub struct LyapunovOptions {
    /// Forcing periods over which the exponents are averaged, at least [`BATCHES`].
    pub periods: u64,
    /// Periods run first with the frame re-orthonormalised but not counted, so that it aligns
    /// with the growth directions (Benettin's transient).
    pub alignment_periods: u64,
    /// The simulator's options (contact times to its `root_tolerance`; its steady-state
    /// options are used only by [`lyapunov_after_steady_state`]'s caller).
    pub simulation: SimulationOptions,
}

impl Default for LyapunovOptions {
    fn default() -> Self {
        Self {
            periods: DEFAULT_LYAPUNOV_PERIODS,
            alignment_periods: DEFAULT_ALIGNMENT_PERIODS,
            simulation: SimulationOptions::default(),
        }
    }
}

/// The Lyapunov spectrum of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct LyapunovSpectrum {
    /// The finite exponents in descending order, in 1/s: `2n − collapsed` of them.
    pub exponents: Vec<f64>,
    /// The uncertainty of each exponent (same order), in 1/s: the larger of
    /// [`UNCERTAINTY_FACTOR`] times the batch-means standard error and the range of the running
    /// sum's deviation from its fitted line over the time (module documentation).
    pub uncertainties: Vec<f64>,
    /// The uncertainty of the largest exponent, in 1/s (`∞` when every direction collapsed).
    pub uncertainty: f64,
    /// Directions contracted to zero by sticking (exponents `−∞`, not in
    /// [`Self::exponents`]): two for each contact pair that stuck during the run.
    pub collapsed: usize,
    /// Forcing periods averaged over.
    pub periods: u64,
    /// The time averaged over, `periods × T`, in s.
    pub time: f64,
    /// Impacts during the counted periods (sticks not counted).
    pub impacts: u64,
    /// Sticks (plastic holds on a stop) during the counted periods.
    pub sticks: u64,
    /// Time spent with a pair held on a stop during the counted periods, in s.
    pub time_stuck: f64,
    /// Where the run ended, at the start's forcing phase: continue from here.
    pub final_state: Start,
}

/// What a motion that does not repeat is, judged by its largest exponent `λ₁` and that
/// exponent's uncertainty `u`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Regime {
    /// `λ₁ > u`: nearby motions separate exponentially.
    Chaotic,
    /// `|λ₁| ≤ u`: neither separating nor converging (a torus).
    QuasiPeriodic,
    /// `λ₁ < −u`: the motion converges, yet did not repeat within the cap: a long transient or
    /// a period longer than searched.
    Unsettled,
}

impl Regime {
    /// The regime's name: `chaotic`, `quasi-periodic` or `unsettled`.
    pub fn name(self) -> &'static str {
        match self {
            Regime::Chaotic => "chaotic",
            Regime::QuasiPeriodic => "quasi-periodic",
            Regime::Unsettled => "unsettled",
        }
    }

    /// The regime of a largest exponent `largest` with uncertainty `uncertainty` (both 1/s).
    pub fn of(largest: f64, uncertainty: f64) -> Regime {
        if largest > uncertainty {
            Regime::Chaotic
        } else if largest >= -uncertainty {
            Regime::QuasiPeriodic
        } else {
            Regime::Unsettled
        }
    }
}

impl LyapunovSpectrum {
    /// The largest exponent, `None` when every direction collapsed.
    pub fn largest(&self) -> Option<f64> {
        self.exponents.first().copied()
    }

    /// The regime by [`Regime::of`] from the largest exponent; a spectrum whose every
    /// direction collapsed (`λ = −∞`) is [`Regime::Unsettled`].
    pub fn regime(&self) -> Regime {
        match self.largest() {
            Some(l) => Regime::of(l, self.uncertainty),
            None => Regime::Unsettled,
        }
    }

    /// The sum of the finite exponents, in 1/s.
    pub fn sum(&self) -> f64 {
        self.exponents.iter().sum()
    }
}

/// Why no exponents were computed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LyapunovError {
    /// The inputs, the flow or the run failed.
    #[error("simulation: {0}")]
    Simulation(#[from] SimulationError),
    /// Fewer periods than batches.
    #[error("periods = {0} is out of range: must be at least {BATCHES}")]
    Periods(u64),
    /// The tangent flow overflowed or became undefined within one period (at this period).
    #[error("the tangent flow is not finite in period {0}")]
    NonFinite(u64),
}

/// The Lyapunov exponents of `model` at `omega` over `options.periods` forcing periods from
/// `start` (its time fixes the forcing phase of the sections), after
/// `options.alignment_periods` periods that only align the frame.
///
/// The start should lie on the motion of interest (e.g. a steady-state run's final state,
/// [`lyapunov_after_steady_state`]): the alignment periods are not meant to settle a
/// transient of the motion itself.
///
/// # Errors
/// [`LyapunovError::Simulation`] for inputs [`crate::simulate()`] refuses or a failed run,
/// [`LyapunovError::Periods`] for fewer than [`BATCHES`] periods, and
/// [`LyapunovError::NonFinite`] when the tangent flow overflows within a period.
pub fn lyapunov_exponents(
    model: &Model,
    omega: f64,
    start: &Start,
    options: &LyapunovOptions,
) -> Result<LyapunovSpectrum, LyapunovError> {
    check_inputs(model, omega, start, &options.simulation)?;
    let periods = options.periods;
    if periods < BATCHES {
        return Err(LyapunovError::Periods(periods));
    }
    let period = std::f64::consts::TAU / omega;
    let phase = start.time.rem_euclid(period);
    let model = shifted(model, omega, phase);
    let mut engine = Engine::new(&model, omega, &options.simulation)?;
    let m = start.state.len();
    // Sums of log |R_ii| per batch, and periods per batch.
    let batches = BATCHES as usize;
    let mut sums = vec![vec![0.0; m]; batches];
    let mut lengths = vec![0u64; batches];
    // The running sums, every `stride` periods, for the bridge: (periods so far, sums).
    let stride = periods.div_ceil(MAX_BRIDGE_POINTS).max(1);
    let mut running = vec![0.0; m];
    let mut bridge: Vec<(u64, Vec<f64>)> = Vec::new();
    let alignment = options.alignment_periods;
    let mut k = 0u64;
    let mut impacts = 0u64;
    let mut at_alignment = (0u64, 0.0);
    let mut non_finite: Option<u64> = None;
    let run = alignment.saturating_add(periods);
    let (state, tangent) = engine
        .tangent_periods(&start.state, initial_frame(m), run, |t| {
            k += 1;
            if t.jacobian.iter().any(|v| !v.is_finite()) {
                non_finite.get_or_insert(k);
                return Err(SimulationError::Option("non-finite tangent".into()));
            }
            let (q, r) = t.jacobian.clone().qr().unpack();
            t.jacobian = q;
            if k <= alignment {
                t.impacts.clear();
                at_alignment = (t.sticks, t.stuck_time);
                return Ok(());
            }
            impacts += t.impacts.len() as u64;
            t.impacts.clear();
            let batch = (((k - alignment - 1) * BATCHES) / periods) as usize;
            for (i, sum) in sums[batch].iter_mut().enumerate() {
                let log = r[(i, i)].abs().ln();
                *sum += log;
                running[i] += log;
            }
            lengths[batch] += 1;
            let counted = k - alignment;
            if counted % stride == 0 || counted == periods {
                bridge.push((counted, running.clone()));
            }
            Ok(())
        })
        .map_err(|e| match non_finite {
            Some(k) => LyapunovError::NonFinite(k),
            None => LyapunovError::Simulation(e),
        })?;
    let collapsed = (2 * tangent.stuck_pairs.iter().filter(|&&s| s).count()).min(m);
    let kept = m - collapsed;
    let total = periods as f64 * period;
    // Per exponent: the run's value and the batch means' standard error.
    let mut pairs: Vec<(f64, f64)> = (0..kept)
        .map(|i| {
            let value = sums.iter().map(|s| s[i]).sum::<f64>() / total;
            let blocks: Vec<f64> = sums
                .iter()
                .zip(&lengths)
                .map(|(s, &l)| s[i] / (l as f64 * period))
                .collect();
            let mean = blocks.iter().sum::<f64>() / BATCHES as f64;
            let variance =
                blocks.iter().map(|b| (b - mean).powi(2)).sum::<f64>() / (BATCHES - 1) as f64;
            let error = UNCERTAINTY_FACTOR * (variance / BATCHES as f64).sqrt();
            // The bridge: the running sum's deviation from the line of slope `value`.
            let (low, high) = bridge.iter().fold((0.0f64, 0.0f64), |(lo, hi), (c, sums)| {
                let deviation = sums[i] - value * (*c as f64 * period);
                (lo.min(deviation), hi.max(deviation))
            });
            (value, error.max((high - low) / total))
        })
        .collect();
    if pairs.iter().any(|(v, u)| !v.is_finite() || !u.is_finite()) {
        return Err(LyapunovError::NonFinite(periods));
    }
    pairs.sort_by(|a, b| b.0.total_cmp(&a.0));
    let exponents: Vec<f64> = pairs.iter().map(|p| p.0).collect();
    let uncertainties: Vec<f64> = pairs.iter().map(|p| p.1).collect();
    Ok(LyapunovSpectrum {
        uncertainty: uncertainties.first().copied().unwrap_or(f64::INFINITY),
        exponents,
        uncertainties,
        collapsed,
        periods,
        time: total,
        impacts,
        sticks: tangent.sticks - at_alignment.0,
        time_stuck: tangent.stuck_time - at_alignment.1,
        final_state: Start { state, time: phase },
    })
}

/// The exponents over `options.periods` more periods from where a steady-state (or fixed)
/// run `steady` of `model` at `omega` ended ([`SteadyState::final_state`]): the run has
/// settled on its attractor, so every period counts.
///
/// # Errors
/// As [`lyapunov_exponents`].
pub fn lyapunov_after_steady_state(
    model: &Model,
    omega: f64,
    steady: &SteadyState,
    options: &LyapunovOptions,
) -> Result<LyapunovSpectrum, LyapunovError> {
    lyapunov_exponents(model, omega, &steady.final_state, options)
}

/// `A = [[0, I], [−M⁻¹K, −M⁻¹C]]` of `model`: its trace `−tr(M⁻¹C)` is the flow's volume
/// contraction rate in the sum rule `Σ λ_i = tr A + 2 log(e) × impacts per second`.
///
/// # Errors
/// [`SimulationError::Flow`] when the mass matrix is singular.
pub fn system_matrix(model: &Model) -> Result<DMatrix<f64>, SimulationError> {
    let n = model.dofs();
    let minv = model
        .mass()
        .clone()
        .try_inverse()
        .ok_or(crate::flow::FlowError::SingularMass)?;
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    a.view_mut((0, n), (n, n))
        .copy_from(&DMatrix::identity(n, n));
    a.view_mut((n, 0), (n, n))
        .copy_from(&(-&minv * &model.stiffness));
    if let Some(c) = &model.damping {
        a.view_mut((n, n), (n, n)).copy_from(&(-&minv * c));
    }
    Ok(a)
}
