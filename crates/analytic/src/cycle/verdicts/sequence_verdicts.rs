//! A converged cycle of an impact sequence made into an orbit with its verdicts: amplitudes
//! from rigorous extrema, viability per pair, Floquet multipliers and the energy balance.
//!
//! [`solve_sequence`] is the entry point from a guess; [`crate::sequence_search`] finds every
//! orbit of a sequence by a multi-start. A cycle with contact phases (compliant pairs) has its
//! verdicts from `contact`.

mod contact;

use crate::flow::Extrema;
use crate::linear::transmittance_db;
use crate::model::LinearModel;
use crate::model_flight::{eigenvalues, ModelFlight};
use crate::sequence::{ImpactKind, ImpactSequence, PairImpact};
use crate::sequence_orbit::{SequenceNewton, SequenceOrbitError, SequenceProblem};
use crate::signature::Signature;
use crate::verdicts::{energy_forms, energy_forms_of, CycleModel, EnergyForms};
use crate::verdicts::{EnergyBalance, SequenceViolation};
use nalgebra::{Complex, DMatrix, DVector, Dyn};
use serde::{Serialize, Serializer};

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
    /// coordinate under the fundamental's cosine part `f_c` (the forcing's harmonics leave it
    /// as it is): `u_g` for a base-driven model.
    pub transmittance_db: f64,
    /// True when no [`SequenceViolation`] and no [`ContactViolation`] was found.
    pub viable: bool,
    /// Every condition that fails.
    pub violations: Vec<SequenceViolation>,
    /// Every condition of a contact phase that fails (empty, and not serialised, without
    /// contact phases).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub contact_violations: Vec<ContactViolation>,
    /// The contact phases of compliant pairs and the sticking phases, in sequence order
    /// (empty, and not serialised, without). `impact_phases` and `states_before_impacts` then
    /// list every event: a contact phase's entry and its exit, a sticking phase's landing and
    /// its release.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub contacts: Vec<ContactPhase>,
    /// Eigenvalues of the monodromy matrix (flights and saltation at every impact), as
    /// `[re, im]`; `null` entries when the monodromy is not finite.
    #[serde(serialize_with = "complex_pairs")]
    pub floquet_multipliers: Vec<Complex<f64>>,
    /// Every multiplier has modulus `< 1 − 1e-9` ([`crate::orbit::STABILITY_MARGIN`]).
    pub stable: bool,
    /// The monodromy matrix (`2n × 2n`) from just after the first impact.
    #[serde(skip)]
    pub monodromy: DMatrix<f64>,
    /// The terms of the energy balance.
    pub energy: EnergyBalance,
    /// `|forcing_work − dashpot_dissipation − impact_losses|` relative to the largest of
    /// `|forcing_work|`, `dashpot_dissipation + impact_losses`,
    /// [`crate::ENERGY_EXCHANGE_FRACTION`]` · exchange_bound` (so that a conservative orbit's residual
    /// measures rounding against the energy it exchanges) and `ENERGY_FLOOR = 1e-6``· f_cᵀK⁻¹f_c`.
    pub energy_residual: f64,
    /// Newton iterations taken.
    pub newton_iterations: usize,
}

/// One contact phase of a compliant pair on an orbit, from entry (penetration 0, `ṙ` into the
/// stop) to exit (penetration 0 again), or one sticking phase of a rigid pair of restitution 0,
/// from its landing impact to its release.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ContactPhase {
    /// Index of the contact pair.
    pub pair: usize,
    /// `+1` on side 1, `−1` on side 2.
    pub side: i8,
    /// [`ImpactKind::Contact`] or [`ImpactKind::Stick`].
    #[serde(serialize_with = "kind_name")]
    pub kind: ImpactKind,
    /// Time of the entry (the landing) as a fraction of the cycle (an entry of
    /// [`SequenceOrbit::impact_phases`]).
    pub entry_phase: f64,
    /// Time from entry to exit (from landing to release).
    pub duration: f64,
    /// `ṙ` at the entry (just before the landing impact).
    pub entry_velocity: f64,
    /// `ṙ` at the exit: `−e` times the entry's for a pair on which nothing else acts during
    /// the contact ([`crate::Compliance::restitution`]); 0 at a release.
    pub exit_velocity: f64,
    /// The largest penetration `s r − gap_s` during the contact (0 while held on the stop).
    pub max_penetration: f64,
}

/// Why a contact phase of a solution of the cycle equations is not a contact of the motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ContactViolation {
    /// The penetration returns below zero before the contact's exit: the pair leaves its stop
    /// earlier (and comes back), a contact the sequence does not have.
    EarlyExit {
        /// Index of the contact pair.
        pair: usize,
        /// The stop: 1 or 2.
        side: u8,
        /// Time after the first event at which the penetration is most negative.
        time: f64,
        /// How far below zero, `> 0`.
        excess: f64,
    },
    /// At the exit the pair still moves into its stop (`s ṙ ≥ 0`): the penetration does not
    /// return to zero there.
    WrongExit {
        /// Index of the contact pair.
        pair: usize,
        /// The stop: 1 or 2.
        side: u8,
        /// `ṙ` at the exit.
        relative_velocity: f64,
    },
    /// While held on its stop the pair's free acceleration turns away from the stop (the
    /// stop would pull) before the sequence's release.
    EarlyRelease {
        /// Index of the contact pair.
        pair: usize,
        /// The stop: 1 or 2.
        side: u8,
        /// Time after the first event at which the stop would pull hardest.
        time: f64,
        /// How far the release functional (free acceleration over `ω²`) goes below zero.
        excess: f64,
    },
    /// At the release the held pair's free acceleration turns towards the stop, not away: the
    /// stop's force touches zero without changing sign.
    WrongRelease {
        /// Index of the contact pair.
        pair: usize,
        /// The stop: 1 or 2.
        side: u8,
        /// `s ḣ` at the release, `h` the release functional: `≥ 0`.
        rate: f64,
    },
}

fn kind_name<S: Serializer>(kind: &ImpactKind, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(match kind {
        ImpactKind::Rigid => "rigid",
        ImpactKind::Contact => "contact",
        ImpactKind::Stick => "stick",
    })
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
/// times of the others as fractions of the cycle (`0 < φ₂ < … < φ_m < 1`). A contact phase
/// (`0+c`) counts two events, its entry and its exit, and a sticking phase (`0+s`) two, its
/// landing and its release: each has its own entry in the guess.
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
    ModelVerdicts::new(&problem).assemble(alpha, &phases, converged.iteration)
}

/// What the verdicts need of a [`LinearModel`] at one frequency, computed once for every
/// orbit of a [`SequenceProblem`]: the model's general (heap) numerics.
pub(crate) struct ModelVerdicts<'p, 'a> {
    problem: &'p SequenceProblem<'a>,
    flight: ModelFlight,
    /// Every pair's coordinate as an augmented functional, and its gaps.
    pairs: Vec<(DVector<f64>, [f64; 2])>,
    /// Every coordinate `u_k` as an augmented functional.
    coordinates: Vec<DVector<f64>>,
    forms: EnergyForms<Dyn>,
    /// `K⁻¹f_c`, the static displacement.
    statics: DVector<f64>,
    /// `wᵀM⁻¹w` of every pair (`NaN` for a mass that is not positive definite).
    flexibility: Vec<f64>,
    /// The flows of the contact phases' flights (`Some` for a contact flight; empty without
    /// contact phases).
    contact_flows: Vec<Option<contact::ContactFlow>>,
}

impl<'p, 'a> ModelVerdicts<'p, 'a> {
    /// The verdicts' view of `problem`'s model at its frequency.
    pub(crate) fn new(problem: &'p SequenceProblem<'a>) -> Self {
        let model = problem.model();
        let omega = problem.omega();
        let n = model.dofs();
        let size = problem.equations().augmented_matrix().nrows();
        let contact = problem.equations().has_contact_phases();
        let coordinates = (0..n)
            .map(|k| {
                let mut c = DVector::zeros(size);
                c[k] = 1.0;
                c
            })
            .collect();
        let pairs = model
            .pairs()
            .iter()
            .map(|pair| {
                let mut c = DVector::zeros(size);
                c.rows_mut(0, n).copy_from(&pair.direction);
                (c, [pair.gap_side1, pair.gap_side2])
            })
            .collect();
        let forcing = model.forcing();
        let forms = if contact {
            // The constant phase pair of a cycle with contact phases forces nothing.
            let columns = forcing.columns(omega);
            let mut padded = DMatrix::zeros(n, columns.ncols() + 2);
            padded.columns_mut(0, columns.ncols()).copy_from(&columns);
            energy_forms_of(Dyn(size), model.mass(), model.damping(), &padded, omega)
        } else if forcing.harmonics.is_empty() {
            energy_forms(
                Dyn(size),
                model.mass(),
                model.damping(),
                &forcing.cosine,
                &forcing.sine_at(omega),
                omega,
            )
        } else {
            energy_forms_of(
                Dyn(size),
                model.mass(),
                model.damping(),
                &forcing.columns(omega),
                omega,
            )
        };
        let statics = if model.has_rigid_modes() {
            rigid_statics(model)
        } else {
            model
                .stiffness()
                .clone()
                .lu()
                .solve(&model.forcing().cosine)
                .unwrap_or_else(|| DVector::from_element(n, f64::NAN))
        };
        let mass_cholesky = model.mass().clone().cholesky();
        let flexibility = model
            .pairs()
            .iter()
            .map(|pair| {
                mass_cholesky
                    .as_ref()
                    .map_or(f64::NAN, |c| pair.direction.dot(&c.solve(&pair.direction)))
            })
            .collect();
        let mut flight = ModelFlight::new(model, omega);
        if contact {
            let matrix = problem.equations().augmented_matrix().clone();
            flight = ModelFlight::from_matrix(matrix, flight.rate());
        }
        let mut verdicts = Self {
            problem,
            flight,
            pairs,
            coordinates,
            forms,
            statics,
            flexibility,
            contact_flows: Vec::new(),
        };
        if contact {
            verdicts.contact_flows = contact::contact_flows(&verdicts);
        }
        verdicts
    }

    /// The orbit at converged unknowns `(alpha, phases)` (phases with first 0) with its
    /// verdicts ([`crate::verdicts::assemble`]).
    ///
    /// # Errors
    /// [`SequenceOrbitError::SingularCycle`] from the evaluation.
    pub(crate) fn assemble(
        &self,
        alpha: f64,
        phases: &[f64],
        newton_iterations: usize,
    ) -> Result<SequenceOrbit, SequenceOrbitError> {
        let problem = self.problem;
        let (model, sequence, omega) = (problem.model(), problem.sequence(), problem.omega());
        let pairs = model.pairs();
        let singular = SequenceOrbitError::SingularCycle { omega };
        let (verdicts, contact_violations, contacts) = if problem.equations().has_contact_phases() {
            contact::assemble(self, alpha, phases).ok_or(singular)?
        } else {
            let verdicts = crate::verdicts::assemble(self, problem.equations(), alpha, phases)
                .ok_or(singular)?;
            (verdicts, Vec::new(), Vec::new())
        };
        let amplitudes = verdicts.amplitudes;
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
            .map_or(f64::NAN, |k| self.statics[k].abs());
        Ok(SequenceOrbit {
            sequence: sequence.clone(),
            pair_signatures: (0..pairs.len())
                .map(|p| sequence.pair_signature(p))
                .collect(),
            period: sequence.period(),
            omega,
            impact_phases: phases.to_vec(),
            alpha,
            state_after_impact: verdicts.states_after[0].iter().copied().collect(),
            states_before_impacts: verdicts
                .states_before
                .iter()
                .map(|x| x.iter().copied().collect())
                .collect(),
            amplitudes,
            cell_outer_amplitudes,
            outer_amplitude,
            transmittance_db: transmittance_db(outer_amplitude, reference_amplitude),
            viable: verdicts.violations.is_empty() && contact_violations.is_empty(),
            violations: verdicts.violations,
            contact_violations,
            contacts,
            floquet_multipliers: verdicts.floquet_multipliers,
            stable: verdicts.stable,
            monodromy: verdicts.monodromy,
            energy: verdicts.energy,
            energy_residual: verdicts.energy_residual,
            newton_iterations,
        })
    }
}

/// The static displacement of a model with rigid modes `Φ`: the solution of `K s = f_c`
/// without a rigid component (`Φᵀs = 0`), from the regular `(K + κΦΦᵀ) s = f_c`
/// (`κ = max |K_ij|`, or 1 when `K = 0`), which projected on `Φ` gives `κΦᵀs = Φᵀf_c`; `NaN`
/// entries when `f_c` pushes a rigid mode (`|Φᵀf_c| > `[`crate::model::RIGID_COUPLING`]`|f_c|`:
/// no static displacement).
fn rigid_statics(model: &LinearModel) -> DVector<f64> {
    let n = model.dofs();
    let rigid = model.rigid_modes();
    let force = &model.forcing().cosine;
    let nan = DVector::from_element(n, f64::NAN);
    if crate::model::couples(&(rigid.transpose() * force), force) {
        return nan;
    }
    let kappa = match model.stiffness().amax() {
        k if k > 0.0 => k,
        _ => 1.0,
    };
    let regular = model.stiffness() + rigid * rigid.transpose() * kappa;
    regular.lu().solve(force).unwrap_or(nan)
}

/// A model's general numerics for the verdicts: heap flights and monodromy.
impl CycleModel<Dyn> for ModelVerdicts<'_, '_> {
    type State = Dyn;

    fn state_dim(&self) -> Dyn {
        Dyn(2 * self.problem.model().dofs())
    }

    fn impacts(&self) -> &[PairImpact] {
        self.problem.sequence().impacts()
    }

    fn pairs(&self) -> &[(DVector<f64>, [f64; 2])] {
        &self.pairs
    }

    fn amplitude_functionals(&self) -> &[DVector<f64>] {
        &self.coordinates
    }

    fn energy_forms(&self) -> &EnergyForms<Dyn> {
        &self.forms
    }

    fn static_energy(&self) -> f64 {
        self.problem
            .model()
            .forcing()
            .cosine
            .dot(&self.statics)
            .abs()
    }

    fn extrema(
        &self,
        start: &DVector<f64>,
        duration: f64,
        functionals: &[DVector<f64>],
    ) -> Vec<Extrema> {
        self.flight.extrema(start, duration, functionals)
    }

    fn second_moment(&self, start: &DVector<f64>, tau: f64) -> DMatrix<f64> {
        self.flight.second_moment(start, tau)
    }

    fn impact_state(&self, pair: usize, before: &DVector<f64>) -> DVector<f64> {
        self.problem.model().impact_state(pair, before)
    }

    fn relative_velocity(&self, pair: usize, x: &DVector<f64>) -> f64 {
        let model = self.problem.model();
        let n = model.dofs();
        model.pairs()[pair].direction.dot(&x.rows(n, n))
    }

    fn impact_loss(&self, pair: usize, rdot: f64) -> f64 {
        let restitution = self.problem.model().pairs()[pair].restitution;
        0.5 * (1.0 - restitution.powi(2)) * rdot * rdot / self.flexibility[pair]
    }

    fn saltation(&self, pair: usize, before: &DVector<f64>, phase: &[f64]) -> DMatrix<f64> {
        let p = DVector::from_column_slice(phase);
        self.problem
            .model()
            .saltation(self.problem.omega(), pair, before, &p)
    }

    fn eigenvalues(&self, monodromy: &DMatrix<f64>) -> Option<Vec<Complex<f64>>> {
        eigenvalues(monodromy)
    }
}
