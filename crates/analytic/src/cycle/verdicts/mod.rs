//! The verdicts on a converged cycle, written once for every model: amplitudes from rigorous
//! extrema, viability per contact pair, the energy balance and Floquet multipliers from the
//! monodromy matrix with saltation at every impact.
//!
//! [`assemble`] is generic over the augmented dimension `D` of the cycle equations and over
//! the model's own numerics ([`CycleModel`]): the unit's fixed-size flow (stack matrices,
//! [`crate::cycle`]) and a [`crate::LinearModel`]'s general one (heap matrices,
//! [`crate::sequence_verdicts`]) each supply their flights' extrema and second moments, their
//! impact maps, saltation matrices and eigenvalues; the verdicts are decided here, once.

pub mod sequence_verdicts;

use crate::cycle_equations::CycleEquations;
use crate::flow::Extrema;
use crate::orbit::{STABILITY_MARGIN, VIABILITY_TOLERANCE};
use crate::sequence::PairImpact;
use nalgebra::allocator::Allocator;
use nalgebra::{Cholesky, Complex, Const, DefaultAllocator, Dim, DimMin, OMatrix, OVector, U2};
use serde::Serialize;

/// Energy scale floor of the energy residual's reference, as a fraction of the static energy
/// `f_cᵀK⁻¹f_c` (`k_o u_g²` on the unit): a conservative orbit that exchanges next to no
/// energy is measured against this rather than against rounding.
pub(crate) const ENERGY_FLOOR: f64 = 1e-6;

/// Fraction of [`EnergyBalance::exchange_bound`] below which the energy residual's reference
/// does not fall: `1e-3`, so that a conservative orbit (no work, no losses) is measured
/// against a thousandth of its gross exchange (a bound, above the exchange itself) rather than
/// against rounding, while a dissipative orbit whose work exceeds a thousandth of its gross
/// exchange is still measured against its work.
pub const ENERGY_EXCHANGE_FRACTION: f64 = 1e-3;

/// The energy balance of a cycle, each term computed on its own:
/// `d/dt (½ u̇ᵀMu̇ + ½ uᵀKu) = u̇ᵀ f(t) − u̇ᵀCu̇` between impacts, and an impact of pair `w`
/// loses `½ (1 − e²) ṙ⁻² / (wᵀM⁻¹w)` (`½ μ (1 − e²) ṙ⁻²` on the unit, `μ` its reduced mass);
/// over a cycle the energy returns, so `forcing_work = dashpot_dissipation + impact_losses`.
///
/// On a base-driven model (the unit, a chain) `f` is the force of the moving base
/// (`k_o u_g + c_o u̇_g` on the first outer mass) and `C` holds the dashpot to the base as one
/// to the ground.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EnergyBalance {
    /// `∮ u̇ᵀ f(t) dt`.
    pub forcing_work: f64,
    /// `∮ u̇ᵀ C u̇ dt`.
    pub dashpot_dissipation: f64,
    /// `Σ ½ (1 − e²) ṙ⁻² / (wᵀM⁻¹w)` over the impacts.
    pub impact_losses: f64,
    /// `∮ c_c ṙ² dt` over the contact phases of compliant pairs: their dashpots' dissipation
    /// (their springs' work over a contact is zero). Zero, and not serialised, without
    /// contact phases.
    #[serde(skip_serializing_if = "is_zero")]
    pub contact_dissipation: f64,
    /// `½ ∮ (ω u̇ᵀMu̇ + fᵀM⁻¹f / ω) dt`, a closed-form bound on the gross energy the forcing
    /// exchanges, `∮ |u̇ᵀf| dt` (`|u̇ᵀf| ≤ ½(ω u̇ᵀMu̇ + fᵀM⁻¹f/ω)` pointwise). On a
    /// conservative orbit the exchanges cancel (`forcing_work = 0`) and the rounding of their
    /// sum is relative to this.
    pub exchange_bound: f64,
}

/// Whether `value` is zero: a term that only a cycle with contact phases has.
fn is_zero(value: &f64) -> bool {
    *value == 0.0
}

/// Why a solution of the cycle equations is not a motion, naming the contact pair.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SequenceViolation {
    /// Between impacts pair `pair`'s coordinate passes through a stop that one of the
    /// flight's own impacts (approached from outside) lies on.
    Penetration {
        /// Index of the contact pair.
        pair: usize,
        /// The stop: 1 (`r = +gap_side1`) or 2 (`r = −gap_side2`).
        side: u8,
        /// Time after the first impact at which `r` is furthest beyond the stop.
        time: f64,
        /// How far beyond the stop, `> 0`.
        excess: f64,
    },
    /// An impact of the sequence is approached from outside: `s ṙ⁻ ≤ 0`.
    WrongApproach {
        /// Index of the contact pair.
        pair: usize,
        /// The stop: 1 or 2.
        side: u8,
        /// `ṙ⁻` just before the impact.
        relative_velocity: f64,
    },
    /// Between impacts pair `pair`'s coordinate goes beyond a stop and comes back: a contact
    /// the sequence does not have.
    ExtraImpact {
        /// Index of the contact pair.
        pair: usize,
        /// The stop: 1 or 2.
        side: u8,
        /// Time after the first impact at which `r` is furthest beyond the stop.
        time: f64,
        /// How far beyond the stop, `> 0`.
        excess: f64,
    },
}

/// The quadratic forms `Q` (`rate = zᵀ Q z` on the augmented state `z = (u, u̇, p)`) of the
/// terms of the [`EnergyBalance`]: the forcing's power, the dashpots' dissipation and the
/// exchange bound.
#[derive(Debug, Clone)]
pub(crate) struct EnergyForms<D: Dim>
where
    DefaultAllocator: Allocator<D, D>,
{
    work: OMatrix<f64, D, D>,
    dissipation: OMatrix<f64, D, D>,
    exchange: OMatrix<f64, D, D>,
}

/// The model's side of the verdicts, of augmented dimension `D`: its contact pairs and the
/// numerics of its own flow (the unit's on stack matrices, a model's on heap matrices).
pub(crate) trait CycleModel<D: Dim>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    /// Dimension of the mechanical state `(u, u̇)`.
    type State: Dim;

    /// The mechanical state's dimension.
    fn state_dim(&self) -> Self::State;

    /// The `(pair, side)` of each impact, in sequence order.
    fn impacts(&self) -> &[PairImpact];

    /// Every contact pair's coordinate as a functional of the augmented state, with its two
    /// gaps `(gap_side1, gap_side2)`.
    fn pairs(&self) -> &[(OVector<f64, D>, [f64; 2])];

    /// The functionals whose amplitude `max |c · z(t)|` over the cycle is reported.
    fn amplitude_functionals(&self) -> &[OVector<f64, D>];

    /// The energy forms at the model's frequency.
    fn energy_forms(&self) -> &EnergyForms<D>;

    /// The static energy `f_cᵀK⁻¹f_c` that floors the energy residual's reference.
    fn static_energy(&self) -> f64;

    /// Rigorous extrema of `functionals` along the flight of `duration` from `start`.
    fn extrema(
        &self,
        start: &OVector<f64, D>,
        duration: f64,
        functionals: &[OVector<f64, D>],
    ) -> Vec<Extrema>;

    /// `∫₀^τ z zᵀ dt` along the flight from `start`.
    fn second_moment(&self, start: &OVector<f64, D>, tau: f64) -> OMatrix<f64, D, D>;

    /// The state after an impact of `pair` from `before`.
    fn impact_state(
        &self,
        pair: usize,
        before: &OVector<f64, Self::State>,
    ) -> OVector<f64, Self::State>
    where
        DefaultAllocator: Allocator<Self::State>;

    /// `ṙ` of `pair` in the state `x`.
    fn relative_velocity(&self, pair: usize, x: &OVector<f64, Self::State>) -> f64
    where
        DefaultAllocator: Allocator<Self::State>;

    /// The energy an impact of `pair` at relative velocity `rdot` dissipates.
    fn impact_loss(&self, pair: usize, rdot: f64) -> f64;

    /// The saltation matrix of an impact of `pair` from `before` at the phase states `phase`
    /// (the augmented state's phase rows: `(cos θ, sin θ)`, then two per harmonic).
    fn saltation(
        &self,
        pair: usize,
        before: &OVector<f64, Self::State>,
        phase: &[f64],
    ) -> OMatrix<f64, Self::State, Self::State>
    where
        DefaultAllocator: Allocator<Self::State, Self::State> + Allocator<Self::State>;

    /// The eigenvalues of a monodromy matrix; `None` when they cannot be computed.
    fn eigenvalues(
        &self,
        monodromy: &OMatrix<f64, Self::State, Self::State>,
    ) -> Option<Vec<Complex<f64>>>
    where
        DefaultAllocator: Allocator<Self::State, Self::State>;
}

/// A converged cycle made into a motion, with its verdicts, in the model's own types.
#[derive(Debug, Clone)]
pub(crate) struct CycleVerdicts<S: Dim>
where
    DefaultAllocator: Allocator<S, S> + Allocator<S>,
{
    /// State just before each impact, in sequence order.
    pub states_before: Vec<OVector<f64, S>>,
    /// State just after each impact.
    pub states_after: Vec<OVector<f64, S>>,
    /// `max |c · z(t)|` over the cycle of each of the model's amplitude functionals.
    pub amplitudes: Vec<f64>,
    /// Every condition that fails.
    pub violations: Vec<SequenceViolation>,
    /// The terms of the energy balance.
    pub energy: EnergyBalance,
    /// The balance's residual relative to [`energy_reference`].
    pub energy_residual: f64,
    /// The monodromy from just after the first impact.
    pub monodromy: OMatrix<f64, S, S>,
    /// Its eigenvalues (`NaN` when they cannot be computed).
    pub floquet_multipliers: Vec<Complex<f64>>,
    /// Every multiplier has modulus `< 1 −` [`STABILITY_MARGIN`].
    pub stable: bool,
}

/// What the flights of a cycle give: amplitudes, the violations between impacts, the energy
/// balance's integrals.
struct FlightTotals {
    amplitudes: Vec<f64>,
    violations: Vec<SequenceViolation>,
    energy: EnergyBalance,
}

/// Stop number (1 or 2) of side `s` (`+1` or `−1`).
fn side_number(s: i8) -> u8 {
    if s > 0 {
        1
    } else {
        2
    }
}

/// Builds the orbit of `equations` at the converged unknowns `(alpha, phases)` (phases with
/// first 0) on `model` and decides its verdicts. `None` when the periodicity solve is
/// singular.
pub(crate) fn assemble<D, M>(
    model: &M,
    equations: &CycleEquations<D>,
    alpha: f64,
    phases: &[f64],
) -> Option<CycleVerdicts<M::State>>
where
    D: DimMin<D, Output = D>,
    M: CycleModel<D>,
    DefaultAllocator:
        Allocator<D, D> + Allocator<D> + Allocator<M::State, M::State> + Allocator<M::State>,
{
    let impacts = model.impacts();
    let m = impacts.len();
    let s = model.state_dim();
    let states = equations.states();
    let mut x = phases.to_vec();
    x[0] = alpha;
    let e = equations.evaluate_with(&x, false)?;
    // Augmented state just before impact j (impact 0 closes the cycle), and the phase there.
    let before = e.before_impacts();
    let states_before: Vec<OVector<f64, M::State>> = before
        .iter()
        .map(|z| z.generic_view((0, 0), (s, Const::<1>)).into_owned())
        .collect();
    let p_at: Vec<Vec<f64>> = (0..m)
        .map(|j| {
            let z = if j == 0 { &e.z1 } else { &before[j] };
            z.iter().skip(states).copied().collect()
        })
        .collect();
    let states_after: Vec<OVector<f64, M::State>> = (0..m)
        .map(|j| model.impact_state(impacts[j].pair, &states_before[j]))
        .collect();

    // Approach of each impact.
    let rdot: Vec<f64> = (0..m)
        .map(|j| model.relative_velocity(impacts[j].pair, &states_before[j]))
        .collect();
    let wrong: Vec<bool> = (0..m)
        .map(|j| f64::from(impacts[j].side) * rdot[j] <= 0.0)
        .collect();
    let mut violations: Vec<SequenceViolation> = (0..m)
        .filter(|&j| wrong[j])
        .map(|j| SequenceViolation::WrongApproach {
            pair: impacts[j].pair,
            side: side_number(impacts[j].side),
            relative_velocity: rdot[j],
        })
        .collect();

    let starts: Vec<OVector<f64, D>> = (0..m)
        .map(|f| {
            let mut z = e.z1.clone();
            z.generic_view_mut((0, 0), (s, Const::<1>))
                .copy_from(&states_after[f]);
            for (i, p) in p_at[f].iter().enumerate() {
                z[states + i] = *p;
            }
            z
        })
        .collect();
    let mut flights = flights(model, equations.cycle(), phases, &starts, &wrong);
    violations.append(&mut flights.violations);
    let mut energy = flights.energy;
    energy.impact_losses = (0..m)
        .map(|j| model.impact_loss(impacts[j].pair, rdot[j]))
        .sum();
    let reference = energy_reference(
        energy.forcing_work,
        energy.dashpot_dissipation.abs() + energy.impact_losses,
        energy.exchange_bound,
        model.static_energy(),
    );
    let energy_residual =
        (energy.forcing_work - energy.dashpot_dissipation - energy.impact_losses).abs() / reference;

    // Monodromy from just after impact 0: E₀, then S₁, E₁, …, E_{m−1}, S₀.
    let mut monodromy = OMatrix::<f64, M::State, M::State>::identity_generic(s, s);
    for f in 0..m {
        let next = (f + 1) % m;
        let hom = e.flights[f].generic_view((0, 0), (s, s)).into_owned();
        let salt = model.saltation(impacts[next].pair, &states_before[next], &p_at[next]);
        monodromy = salt * hom * monodromy;
    }
    let floquet_multipliers = model
        .eigenvalues(&monodromy)
        .unwrap_or_else(|| vec![Complex::new(f64::NAN, f64::NAN); s.value()]);
    let stable = floquet_multipliers
        .iter()
        .all(|mu| mu.norm() < 1.0 - STABILITY_MARGIN);
    Some(CycleVerdicts {
        states_before,
        states_after,
        amplitudes: flights.amplitudes,
        violations,
        energy,
        energy_residual,
        monodromy,
        floquet_multipliers,
        stable,
    })
}

/// Along every flight (from `starts[f]`, the augmented state after impact `f`): the amplitudes
/// of the model's functionals, every pair's excursions beyond its stops, and the integrals of
/// the energy forms. `wrong[j]`: impact `j` is approached from outside.
fn flights<D, M>(
    model: &M,
    cycle: f64,
    phases: &[f64],
    starts: &[OVector<f64, D>],
    wrong: &[bool],
) -> FlightTotals
where
    D: Dim,
    M: CycleModel<D>,
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let impacts = model.impacts();
    let m = impacts.len();
    let pairs = model.pairs();
    let amplitude_of = model.amplitude_functionals();
    let k = amplitude_of.len();
    let mut functionals = amplitude_of.to_vec();
    functionals.extend(pairs.iter().map(|(c, _)| c.clone()));
    let forms = model.energy_forms();
    let mut totals = FlightTotals {
        amplitudes: vec![0.0; k],
        violations: Vec::new(),
        energy: EnergyBalance {
            forcing_work: 0.0,
            dashpot_dissipation: 0.0,
            impact_losses: 0.0,
            exchange_bound: 0.0,
            contact_dissipation: 0.0,
        },
    };
    for f in 0..m {
        let end = if f + 1 < m { phases[f + 1] } else { 1.0 };
        let duration = (end - phases[f]) * cycle;
        let ext = model.extrema(&starts[f], duration, &functionals);
        for (a, e) in totals.amplitudes.iter_mut().zip(&ext) {
            *a = a.max(e.max.abs()).max(e.min.abs());
        }
        let next = (f + 1) % m;
        let t0 = phases[f] * cycle;
        for (p, (_, gaps)) in pairs.iter().enumerate() {
            let r = ext[k + p];
            // An excursion beyond a stop that one of this flight's own impacts on that stop
            // reaches from outside is the flight passing through the stop; any other is a
            // contact the sequence does not have.
            let attached = |s: i8| {
                [f, next]
                    .iter()
                    .any(|&j| impacts[j].pair == p && impacts[j].side == s && wrong[j])
            };
            for (s, gap, excess, time) in [
                (1i8, gaps[0], r.max - gaps[0], r.argmax),
                (-1i8, gaps[1], -gaps[1] - r.min, r.argmin),
            ] {
                if excess > VIABILITY_TOLERANCE * gap {
                    let (pair, side, time) = (p, side_number(s), t0 + time);
                    totals.violations.push(if attached(s) {
                        SequenceViolation::Penetration {
                            pair,
                            side,
                            time,
                            excess,
                        }
                    } else {
                        SequenceViolation::ExtraImpact {
                            pair,
                            side,
                            time,
                            excess,
                        }
                    });
                }
            }
        }
        let moment = model.second_moment(&starts[f], duration);
        let integral = |q: &OMatrix<f64, D, D>| q.component_mul(&moment).sum();
        totals.energy.forcing_work += integral(&forms.work);
        totals.energy.dashpot_dissipation += integral(&forms.dissipation);
        totals.energy.exchange_bound += integral(&forms.exchange);
    }
    totals
}

/// The reference of the energy residual on every path (the unit's and every model's): the
/// largest of `|work|`, the losses (dashpots and impacts), [`ENERGY_EXCHANGE_FRACTION`] of the
/// bound on the gross energy exchanged, and `ENERGY_FLOOR = 1e-6` of the static energy (ignored
/// when not finite).
pub(crate) fn energy_reference(
    work: f64,
    losses: f64,
    exchange_bound: f64,
    static_energy: f64,
) -> f64 {
    let floor = if static_energy.is_finite() {
        ENERGY_FLOOR * static_energy
    } else {
        0.0
    };
    work.abs()
        .max(losses)
        .max(ENERGY_EXCHANGE_FRACTION * exchange_bound)
        .max(floor)
}

/// The [`EnergyForms`] of a model with mass `M`, damping `C` and harmonic force
/// `f = f_c p₀ + f_s p₁` at `omega`, on the augmented state `z = (u, u̇, p)` of dimension `d`:
/// [`energy_forms_of`] with the force's two columns.
///
/// # Panics
/// If `d` is not `2n + 2` for the `n × n` matrices.
pub(crate) fn energy_forms<D: Dim, N: Dim>(
    d: D,
    mass: &OMatrix<f64, N, N>,
    damping: &OMatrix<f64, N, N>,
    cosine: &OVector<f64, N>,
    sine: &OVector<f64, N>,
    omega: f64,
) -> EnergyForms<D>
where
    DefaultAllocator:
        Allocator<D, D> + Allocator<N, N> + Allocator<N> + Allocator<N, U2> + Allocator<U2, N>,
{
    let n = mass.shape_generic().0;
    let mut force = OMatrix::<f64, N, U2>::zeros_generic(n, U2);
    force.column_mut(0).copy_from(cosine);
    force.column_mut(1).copy_from(sine);
    energy_forms_of(d, mass, damping, &force, omega)
}

/// The [`EnergyForms`] of a model with mass `M`, damping `C` and periodic force `f = F p` on
/// the phase states `p` (the `P` columns of `force`, [`crate::HarmonicForcing::columns`]) at
/// `omega`, on the augmented state `z = (u, u̇, p)` of dimension `d = 2n + P`: the forcing's
/// power `u̇ᵀF p`, the dashpots' dissipation `u̇ᵀCu̇` and the exchange bound
/// `½(ω u̇ᵀMu̇ + fᵀM⁻¹f/ω)` (its compliance term zero when `M` is not positive definite, which a
/// validated model's never is). The pointwise bound `|u̇ᵀf| ≤ ½(ω u̇ᵀMu̇ + fᵀM⁻¹f/ω)` holds for
/// any force, harmonics included.
///
/// # Panics
/// If `d` is not `2n + P` for the `n × n` matrices and the `n × P` force.
pub(crate) fn energy_forms_of<D: Dim, N: Dim, P: Dim>(
    d: D,
    mass: &OMatrix<f64, N, N>,
    damping: &OMatrix<f64, N, N>,
    force: &OMatrix<f64, N, P>,
    omega: f64,
) -> EnergyForms<D>
where
    DefaultAllocator:
        Allocator<D, D> + Allocator<N, N> + Allocator<N, P> + Allocator<P, N> + Allocator<P, P>,
{
    let n = mass.nrows();
    let phases = force.ncols();
    assert_eq!(
        d.value(),
        2 * n + phases,
        "the augmented dimension is 2n plus the phase states"
    );
    let zeros = || OMatrix::<f64, D, D>::zeros_generic(d, d);
    let (mut work, mut dissipation, mut exchange) = (zeros(), zeros(), zeros());
    for i in 0..n {
        // ½(b + bᵀ), b carrying F p into the velocity rows.
        for k in 0..phases {
            let column = 2 * n + k;
            work[(n + i, column)] = force[(i, k)] * 0.5;
            work[(column, n + i)] = force[(i, k)] * 0.5;
        }
        for j in 0..n {
            dissipation[(n + i, n + j)] = damping[(i, j)];
            exchange[(n + i, n + j)] = mass[(i, j)] * (0.5 * omega);
        }
    }
    if let Some(compliance) = compliance(mass, force, omega) {
        for i in 0..phases {
            for j in 0..phases {
                exchange[(2 * n + i, 2 * n + j)] = compliance[(i, j)];
            }
        }
    }
    EnergyForms {
        work,
        dissipation,
        exchange,
    }
}

/// `FᵀM⁻¹F / 2ω` of the force columns `F` (`P × P`), by the Cholesky factor of `M`; `None`
/// when `M` is not positive definite.
fn compliance<N: Dim, P: Dim>(
    mass: &OMatrix<f64, N, N>,
    force: &OMatrix<f64, N, P>,
    omega: f64,
) -> Option<OMatrix<f64, P, P>>
where
    DefaultAllocator: Allocator<N, N> + Allocator<N, P> + Allocator<P, N> + Allocator<P, P>,
{
    let cholesky = Cholesky::new(mass.clone())?;
    let solved = cholesky.solve(force);
    Some(force.transpose() * solved * (0.5 / omega))
}
