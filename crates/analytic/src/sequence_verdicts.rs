//! A converged cycle of an impact sequence made into an orbit with its verdicts: amplitudes
//! from rigorous extrema, viability per pair, Floquet multipliers and the energy balance.
//!
//! [`solve_sequence`] is the entry point from a guess; [`crate::sequence_search`] finds every
//! orbit of a sequence by a multi-start.

use crate::linear::transmittance_db;
use crate::model::LinearModel;
use crate::model_flight::{eigenvalues, ModelFlight};
use crate::orbit::{STABILITY_MARGIN, VIABILITY_TOLERANCE};
use crate::sequence::ImpactSequence;
use crate::sequence_orbit::{SequenceNewton, SequenceOrbitError, SequenceProblem};
use crate::signature::Signature;
use nalgebra::{Complex, DMatrix, DVector};
use serde::{Serialize, Serializer};

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

/// The energy balance of a cycle of a [`LinearModel`], each term computed on its own:
/// `d/dt (½ u̇ᵀMu̇ + ½ uᵀKu) = u̇ᵀ f(t) − u̇ᵀCu̇` between impacts, and an impact of pair `w`
/// loses `½ (1 − e²) ṙ⁻² / (wᵀM⁻¹w)`; over a cycle the energy returns, so
/// `forcing_work = dashpot_dissipation + impact_losses`.
///
/// On a base-driven model `f` is the force of the moving base (`k_o u_g + c_o u̇_g` on the
/// first outer mass) and `C` holds the dashpot to the base as one to the ground: the terms
/// differ from the unit's [`crate::EnergyBalance`] (which measures `k_o` and `c_o` from the
/// moving base) by cycle integrals of exact derivatives (which vanish) and by
/// `∮ c_o (2u̇_o u̇_g − u̇_g²) dt`, carried by the work and the dissipation alike: both balances
/// hold.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ModelEnergy {
    /// `∮ u̇ᵀ f(t) dt`.
    pub forcing_work: f64,
    /// `∮ u̇ᵀ C u̇ dt`.
    pub dashpot_dissipation: f64,
    /// `Σ ½ (1 − e²) ṙ⁻² / (wᵀM⁻¹w)` over the impacts.
    pub impact_losses: f64,
    /// `½ ∮ (ω u̇ᵀMu̇ + fᵀM⁻¹f / ω) dt`, a closed-form bound on the gross energy the forcing
    /// exchanges, `∮ |u̇ᵀf| dt` (`|u̇ᵀf| ≤ ½(ω u̇ᵀMu̇ + fᵀM⁻¹f/ω)` pointwise). On a
    /// conservative orbit the exchanges cancel (`forcing_work = 0`) and the rounding of their
    /// sum is relative to this.
    pub exchange_bound: f64,
}

/// A periodic orbit of an impact sequence on a [`LinearModel`], and its verdicts.
///
/// Times and phases are measured from the first impact of the canonical sequence.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SequenceOrbit {
    /// The impact sequence, canonical (text form `0+ 1+ 0- 1-`).
    #[serde(serialize_with = "display")]
    pub sequence: ImpactSequence,
    /// The canonical signature of each contact pair's own impacts (`null` for a pair that
    /// does not impact).
    #[serde(serialize_with = "display_options")]
    pub pair_signatures: Vec<Option<Signature>>,
    /// Number of forcing periods in the cycle.
    pub period: u32,
    /// Angular frequency `ω` of the forcing.
    pub omega: f64,
    /// Impact times as fractions of the cycle `pT`, in sequence order, first = 0.
    pub impact_phases: Vec<f64>,
    /// Forcing phase `θ = ωt + α` at the first impact, radians in `(−π, π]`.
    pub alpha: f64,
    /// State `(u, u̇)` just after the first impact.
    pub state_after_impact: Vec<f64>,
    /// State `(u, u̇)` just before each impact, in sequence order.
    pub states_before_impacts: Vec<Vec<f64>>,
    /// `max_t |u_k(t)|` of every degree of freedom over the cycle, from rigorous extrema.
    pub amplitudes: Vec<f64>,
    /// For each contact pair (cell), the amplitude of its outer coordinate: the coordinate
    /// with the most negative entry of its direction (`r = u_i − u_o`: the cell's outer mass);
    /// `NaN` (`null`) for a direction without a negative entry.
    pub cell_outer_amplitudes: Vec<f64>,
    /// The last cell's outer amplitude (the last entry of `cell_outer_amplitudes`).
    pub outer_amplitude: f64,
    /// `20 log10(outer_amplitude / X_s)`, `X_s` the static displacement `(K⁻¹f_c)` of that
    /// coordinate: `u_g` for a base-driven model.
    pub transmittance_db: f64,
    /// True when no [`SequenceViolation`] was found.
    pub viable: bool,
    /// Every condition that fails.
    pub violations: Vec<SequenceViolation>,
    /// Eigenvalues of the monodromy matrix (flights and saltation at every impact), as
    /// `[re, im]`; `null` entries when the monodromy is not finite.
    #[serde(serialize_with = "complex_pairs")]
    pub floquet_multipliers: Vec<Complex<f64>>,
    /// Every multiplier has modulus `< 1 − 1e-9` ([`STABILITY_MARGIN`]).
    pub stable: bool,
    /// The monodromy matrix (`2n × 2n`) from just after the first impact.
    #[serde(skip)]
    pub monodromy: DMatrix<f64>,
    /// The terms of the energy balance.
    pub energy: ModelEnergy,
    /// `|forcing_work − dashpot_dissipation − impact_losses|` relative to the largest of
    /// `|forcing_work|`, `dashpot_dissipation + impact_losses`,
    /// [`ENERGY_EXCHANGE_FRACTION`]` · exchange_bound` (so that a conservative orbit's residual
    /// measures rounding against the energy it exchanges) and [`ENERGY_FLOOR`]`· f_cᵀK⁻¹f_c`.
    pub energy_residual: f64,
    /// Newton iterations taken.
    pub newton_iterations: usize,
}

fn display<S: Serializer, T: std::fmt::Display>(v: &T, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(v)
}

fn display_options<S: Serializer>(v: &[Option<Signature>], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(v.iter().map(|o| o.as_ref().map(ToString::to_string)))
}

fn complex_pairs<S: Serializer>(v: &[Complex<f64>], s: S) -> Result<S::Ok, S::Error> {
    let finite = |x: f64| x.is_finite().then_some(x);
    s.collect_seq(v.iter().map(|c| [finite(c.re), finite(c.im)]))
}

/// The orbit of `sequence` on `model` at `omega` nearest (in Newton's sense) to
/// `guess = (α, φ₂, …, φ_m)`: the forcing phase at the first canonical impact and the impact
/// times of the others as fractions of the cycle (`0 < φ₂ < … < φ_m < 1`).
///
/// # Errors
/// [`SequenceOrbitError::InvalidFrequency`], [`SequenceOrbitError::Sequence`] (a pair the
/// model lacks), [`SequenceOrbitError::InvalidGuess`], [`SequenceOrbitError::SingularCycle`],
/// [`SequenceOrbitError::NoConvergence`].
pub fn solve_sequence(
    model: &LinearModel,
    omega: f64,
    sequence: &ImpactSequence,
    guess: &[f64],
) -> Result<SequenceOrbit, SequenceOrbitError> {
    let problem = SequenceProblem::new(model, omega, sequence)?;
    let solver = SequenceNewton::default();
    let converged = solver.solve(problem.equations(), guess)?;
    let (alpha, phases) = problem.equations().canonical(&converged.unknowns);
    assemble(&problem, alpha, &phases, converged.iteration)
}

/// Builds the orbit at converged unknowns `(alpha, phases)` (phases with first 0) and derives
/// its verdicts.
///
/// # Errors
/// [`SequenceOrbitError::SingularCycle`] from the evaluation.
pub fn assemble(
    problem: &SequenceProblem,
    alpha: f64,
    phases: &[f64],
    newton_iterations: usize,
) -> Result<SequenceOrbit, SequenceOrbitError> {
    let model = problem.model();
    let sequence = problem.sequence();
    let impacts = sequence.impacts();
    let omega = problem.omega();
    let m = impacts.len();
    let n = model.dofs();
    let n2 = 2 * n;
    let mut x = phases.to_vec();
    x[0] = alpha;
    let e = problem
        .equations()
        .evaluate_with(&x, false)
        .ok_or(SequenceOrbitError::SingularCycle { omega })?;
    // Augmented state just before impact j (impact 0 closes the cycle).
    let before = e.before_impacts();
    let x_before: Vec<DVector<f64>> = before.iter().map(|z| z.rows(0, n2).into_owned()).collect();
    let p_at: Vec<DVector<f64>> = (0..m)
        .map(|j| {
            if j == 0 {
                e.z1.rows(n2, 2).into_owned()
            } else {
                before[j].rows(n2, 2).into_owned()
            }
        })
        .collect();
    let after: Vec<DVector<f64>> = (0..m)
        .map(|j| model.impact_state(impacts[j].pair, &x_before[j]))
        .collect();

    // Approach of each impact.
    let pairs = model.pairs();
    let rdot: Vec<f64> = (0..m)
        .map(|j| {
            pairs[impacts[j].pair]
                .direction
                .dot(&x_before[j].rows(n, n))
        })
        .collect();
    let wrong: Vec<bool> = (0..m)
        .map(|j| f64::from(impacts[j].side) * rdot[j] <= 0.0)
        .collect();
    let side_number = |s: i8| if s > 0 { 1u8 } else { 2u8 };
    let mut violations = Vec::new();
    for j in 0..m {
        if wrong[j] {
            violations.push(SequenceViolation::WrongApproach {
                pair: impacts[j].pair,
                side: side_number(impacts[j].side),
                relative_velocity: rdot[j],
            });
        }
    }

    // Extrema of every coordinate and every pair's coordinate along every flight.
    let flight = ModelFlight::new(model, omega);
    let mut functionals: Vec<DVector<f64>> = (0..n)
        .map(|k| {
            let mut c = DVector::zeros(n2 + 2);
            c[k] = 1.0;
            c
        })
        .collect();
    for pair in pairs {
        let mut c = DVector::zeros(n2 + 2);
        c.rows_mut(0, n).copy_from(&pair.direction);
        functionals.push(c);
    }
    let (work_q, dissipation_q, exchange_q) = energy_forms(model, omega);
    let mut amplitudes = vec![0.0f64; n];
    let mut energy = ModelEnergy {
        forcing_work: 0.0,
        dashpot_dissipation: 0.0,
        impact_losses: 0.0,
        exchange_bound: 0.0,
    };
    let cycle = problem.cycle();
    for f in 0..m {
        let end = if f + 1 < m { phases[f + 1] } else { 1.0 };
        let duration = (end - phases[f]) * cycle;
        let mut start = DVector::zeros(n2 + 2);
        start.rows_mut(0, n2).copy_from(&after[f]);
        start.rows_mut(n2, 2).copy_from(&p_at[f]);
        let ext = flight.extrema(&start, duration, &functionals);
        for k in 0..n {
            amplitudes[k] = amplitudes[k].max(ext[k].max.abs()).max(ext[k].min.abs());
        }
        let next = (f + 1) % m;
        let t0 = phases[f] * cycle;
        for (p, pair) in pairs.iter().enumerate() {
            let r = ext[n + p];
            // An excursion beyond a stop that one of this flight's own impacts on that stop
            // reaches from outside is the flight passing through the stop; any other is a
            // contact the sequence does not have.
            let attached = |s: i8| {
                [f, next]
                    .iter()
                    .any(|&j| impacts[j].pair == p && impacts[j].side == s && wrong[j])
            };
            for (s, gap, excess, time) in [
                (1i8, pair.gap_side1, r.max - pair.gap_side1, r.argmax),
                (-1i8, pair.gap_side2, -pair.gap_side2 - r.min, r.argmin),
            ] {
                if excess > VIABILITY_TOLERANCE * gap {
                    let (side, time) = (side_number(s), t0 + time);
                    violations.push(if attached(s) {
                        SequenceViolation::Penetration {
                            pair: p,
                            side,
                            time,
                            excess,
                        }
                    } else {
                        SequenceViolation::ExtraImpact {
                            pair: p,
                            side,
                            time,
                            excess,
                        }
                    });
                }
            }
        }
        let moment = flight.second_moment(&start, duration);
        let integral = |q: &DMatrix<f64>| q.component_mul(&moment).sum();
        energy.forcing_work += integral(&work_q);
        energy.exchange_bound += integral(&exchange_q);
        energy.dashpot_dissipation += integral(&dissipation_q);
    }
    let mass_cholesky = model.mass().clone().cholesky();
    energy.impact_losses = (0..m)
        .map(|j| {
            let pair = &pairs[impacts[j].pair];
            let flexibility = mass_cholesky
                .as_ref()
                .map_or(f64::NAN, |c| pair.direction.dot(&c.solve(&pair.direction)));
            0.5 * (1.0 - pair.restitution.powi(2)) * rdot[j] * rdot[j] / flexibility
        })
        .sum();
    let statics = model
        .stiffness()
        .clone()
        .lu()
        .solve(&model.forcing().cosine)
        .unwrap_or_else(|| DVector::from_element(n, f64::NAN));
    let static_energy = model.forcing().cosine.dot(&statics).abs();
    let reference = energy_reference(
        energy.forcing_work,
        energy.dashpot_dissipation.abs() + energy.impact_losses,
        energy.exchange_bound,
        static_energy,
    );
    let energy_residual =
        (energy.forcing_work - energy.dashpot_dissipation - energy.impact_losses).abs() / reference;

    // Outer coordinate of each pair, its amplitude, and the transmittance of the last.
    let outer_of = |w: &DVector<f64>| {
        let k = w.imin();
        (w[k] < 0.0).then_some(k)
    };
    let cell_outer_amplitudes: Vec<f64> = pairs
        .iter()
        .map(|p| outer_of(&p.direction).map_or(f64::NAN, |k| amplitudes[k]))
        .collect();
    let outer_amplitude = cell_outer_amplitudes.last().copied().unwrap_or(f64::NAN);
    let reference_amplitude = pairs
        .last()
        .and_then(|p| outer_of(&p.direction))
        .map_or(f64::NAN, |k| statics[k].abs());

    // Monodromy from just after impact 0: E₀, then S₁, E₁, …, E_{m−1}, S₀.
    let mut monodromy = DMatrix::<f64>::identity(n2, n2);
    for f in 0..m {
        let next = (f + 1) % m;
        let hom = e.flights[f].view((0, 0), (n2, n2));
        let s = model.saltation(omega, impacts[next].pair, &x_before[next], &p_at[next]);
        monodromy = s * (hom * monodromy);
    }
    let floquet_multipliers =
        eigenvalues(&monodromy).unwrap_or_else(|| vec![Complex::new(f64::NAN, f64::NAN); n2]);
    let stable = floquet_multipliers
        .iter()
        .all(|mu| mu.norm() < 1.0 - STABILITY_MARGIN);

    Ok(SequenceOrbit {
        sequence: sequence.clone(),
        pair_signatures: (0..pairs.len())
            .map(|p| sequence.pair_signature(p))
            .collect(),
        period: sequence.period(),
        omega,
        impact_phases: phases.to_vec(),
        alpha,
        state_after_impact: after[0].iter().copied().collect(),
        states_before_impacts: x_before
            .iter()
            .map(|x| x.iter().copied().collect())
            .collect(),
        amplitudes,
        cell_outer_amplitudes,
        outer_amplitude,
        transmittance_db: transmittance_db(outer_amplitude, reference_amplitude),
        viable: violations.is_empty(),
        violations,
        floquet_multipliers,
        stable,
        monodromy,
        energy,
        energy_residual,
        newton_iterations,
    })
}

/// Energy scale floor of the energy residual's reference, as a fraction of the static energy
/// `f_cᵀK⁻¹f_c` (`k_o u_g²` on the unit): a conservative orbit that exchanges next to no
/// energy is measured against this rather than against rounding.
pub const ENERGY_FLOOR: f64 = 1e-6;

/// The reference of the energy residual on every path (the unit's and every model's): the
/// largest of `|work|`, the losses (dashpots and impacts), [`ENERGY_EXCHANGE_FRACTION`] of the
/// bound on the gross energy exchanged, and [`ENERGY_FLOOR`] of the static energy (ignored
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

/// Fraction of [`ModelEnergy::exchange_bound`] below which the energy residual's reference
/// does not fall: `1e-3`, so that a conservative orbit (no work, no losses) is measured
/// against a thousandth of its gross exchange (a bound, above the exchange itself) rather than
/// against rounding, while a dissipative orbit whose work exceeds a thousandth of its gross
/// exchange is still measured against its work.
pub const ENERGY_EXCHANGE_FRACTION: f64 = 1e-3;

/// The quadratic forms `Q` (`rate = zᵀ Q z` on the augmented state `z = (u, u̇, p)`) of the
/// forcing's power `u̇ᵀ(f_c p₀ + (f_s + ω f_ω) p₁)`, of the dashpots' dissipation `u̇ᵀCu̇` and
/// of the exchange bound `½(ω u̇ᵀMu̇ + fᵀM⁻¹f/ω)`.
fn energy_forms(model: &LinearModel, omega: f64) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
    let n = model.dofs();
    let size = 2 * n + 2;
    let mut b = DMatrix::zeros(size, size);
    b.view_mut((n, 2 * n), (n, 1))
        .copy_from(&model.forcing().cosine);
    b.view_mut((n, 2 * n + 1), (n, 1))
        .copy_from(&model.forcing().sine_at(omega));
    let work = (&b + b.transpose()) * 0.5;
    let mut dissipation = DMatrix::zeros(size, size);
    dissipation
        .view_mut((n, n), (n, n))
        .copy_from(model.damping());
    let mut exchange = DMatrix::zeros(size, size);
    exchange
        .view_mut((n, n), (n, n))
        .copy_from(&(model.mass() * (0.5 * omega)));
    let mut force = DMatrix::zeros(n, 2);
    force.column_mut(0).copy_from(&model.forcing().cosine);
    force
        .column_mut(1)
        .copy_from(&model.forcing().sine_at(omega));
    if let Some(cholesky) = model.mass().clone().cholesky() {
        let compliance = force.transpose() * cholesky.solve(&force) * (0.5 / omega);
        exchange
            .view_mut((2 * n, 2 * n), (2, 2))
            .copy_from(&compliance);
    }
    (work, dissipation, exchange)
}
