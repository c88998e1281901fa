//! Closed-form steady states of the impacting mass-in-mass unit.
//!
//! An inner mass `m_i` rattles between two stops at relative displacement `r = u_i − u_o = ±Δ`
//! inside an outer mass `m_o`, which a moving base drives through a spring `k_o`
//! (`u_g cos ωt`). This crate gives, without any time stepping:
//!
//! - the modes and the steady state of the unit without stops ([`modes`],
//!   [`linear_response`]);
//! - the symmetric two-impact orbits (`β = ½`) of Nigm and Shabana, by the half-period
//!   symmetry, both branches ([`symmetric_orbits`]);
//! - orbits whose side-2 impact comes `βT` after the side-1 impact, for any `β`: the gap
//!   `Δ*(β)` that admits them ([`gap_for_beta`]) and the asymmetric orbits of a given gap
//!   ([`asymmetric_orbits`]);
//! - orbits of any impact [`Signature`] (`+-`, `++--`, … over `p` forcing periods) by the
//!   Nigm–Shabana method with Newton on exact derivatives, found by a systematic multi-start
//!   ([`signature_orbits`]) or from a guess ([`solve_signature`]), with viability, Floquet
//!   multipliers and the cycle's energy balance ([`SignatureOrbit`]);
//! - a general linear model with contact pairs ([`LinearModel`]): the unit and chains of `N`
//!   cells in series, their impact maps, forced flow matrix and linear steady state (the model
//!   the sequence solver below runs on);
//! - a model's periodic forcing ([`HarmonicForcing`]), the fundamental and any higher harmonics
//!   of integer order ([`Harmonic`]), each carried by two phase states of the augmented state
//!   ([`phase_state`]), turning at its own `kω`;
//! - free bodies (a singular stiffness matrix): a model's rigid modes
//!   ([`LinearModel::rigid_modes`]), the family of its linear motions and whether one stays
//!   clear of the stops ([`LinearModel::clear_family`], [`ClearFamily`]); the cycle equations
//!   of such a model border their periodicity solve with contact conditions
//!   ([`ImpactCondition`]);
//! - chains of cells in series, graded or not ([`Cell`], at most [`MAX_CELLS`]), and the linear
//!   chain's steady state by transfer matrices ([`chain_response`]), finite at every local
//!   resonance and unbounded only at the chain's own undamped resonances;
//! - the infinite lattice of identical cells: Bloch waves, attenuation per cell
//!   ([`bloch_wave`]), band edges and stop bands of the undamped lattice in closed form
//!   ([`band_edges`], [`stop_bands`]);
//! - impact sequences of several pairs, the time-ordered `(pair, side)` impacts over a cycle
//!   ([`ImpactSequence`]; one pair's is a [`Signature`]);
//! - the cycle equations of an impact sequence (residuals, exact Jacobian in the unknowns and
//!   in `ω`; [`CycleEquations`]), written once and generic over the augmented dimension: the
//!   unit's signature solver runs them on stack matrices, a model's on heap matrices, with one
//!   Newton ([`SequenceNewton`] on a [`SequenceProblem`]) and one multi-start;
//! - orbits of any impact sequence on any [`LinearModel`] (the signature solver generalised:
//!   amplitudes, viability per pair, Floquet multipliers and energy balance; the multi-start
//!   [`sequence_orbits`], from a guess [`solve_sequence`]), with [`ModelFlight`]'s rigorous
//!   extrema and integrals; the verdicts (viability per pair, multipliers with saltation, the
//!   [`EnergyBalance`]) are assembled once for every model, the unit's signature orbits
//!   included;
//! - compliant contact pairs ([`Compliance`], [`LinearModel::with_compliance`]): a
//!   Kelvin–Voigt spring and dashpot act while the pair penetrates its stop; an impact of such
//!   a pair is a contact phase (`0+c`), two events (entry, exit) whose flight between is the
//!   exact flow of the contact system, with the saltation at entry and exit, the penetration
//!   and duration of every contact ([`ContactPhase`]), its viability ([`ContactViolation`]) and
//!   the contact dashpots' dissipation in the [`EnergyBalance`]; and sticking phases (`0+s`) of
//!   rigid pairs of restitution 0: the landing impact, the flow held on the stop and the
//!   release where the stop's force vanishes;
//! - pseudo-arclength continuation in `ω` of orbits of any signature of the unit
//!   ([`continue_orbit`]) and of any impact sequence of a [`LinearModel`] such as a chain
//!   ([`continue_sequence`]) through folds, with exact derivatives in `ω`, the bifurcation
//!   events on the branch (fold, branch point, period doubling, Neimark–Sacker, grazing,
//!   vanishing impact; [`Event`]) located to `1e-8` in `ω` (branch points to rounding, by a
//!   regular defining system), and the branches that leave at them, each followed once (a
//!   branch onto one followed, or onto its mirror image, ends there); and the exact
//!   two-parameter curves where such an event occurs ([`follow_boundary`],
//!   [`follow_sequence_boundary`]);
//! - for every orbit ([`Orbit`]): the outer amplitude from rigorous extrema, viability (no
//!   penetration between impacts, impacts approached from inside) and Floquet multipliers from
//!   the monodromy matrix with saltation matrices.
//!
//! An orbit's motion at any time of its cycle is [`UnitMotion`]'s (a unit's orbits).
//!
//! The flow between impacts is the exponential of the system augmented with the forcing's
//! phase states (two on the unit, [`ForcedFlow`]; two per harmonic on a model): exact, and
//! finite at exact resonance.
//!
//! Every public item has one path, at the crate's root (`rattle_analytic::Unit`,
//! `rattle_analytic::continue_orbit`, …). The source is in private folders by job: `problem`
//! (what is solved), `linear` (without stops), `flow` (between impacts), `cycle` (the cycle
//! equations of any impact sequence, their Newton and search, the unit's signature orbits and
//! the verdicts), `closed_form` (the two-impact closed forms) and `continuation`.
#![deny(missing_docs)]

mod closed_form;
mod continuation;
mod cycle;
mod flow;
mod linear;
mod problem;
#[cfg(any(test, feature = "fixtures"))]
pub mod test_models;

use closed_form::{family, orbit, symmetric};
use cycle::verdicts;
use cycle::{cycle_equations, motion, sequence_orbit, sequence_search};
use flow::model_flight;
use linear::lattice;
use problem::{chain, forcing, model, rigid, sequence, signature, unit};
use verdicts::sequence_verdicts;

pub use chain::{chain_response, Cell, ChainResponse, MAX_CELLS};
pub use continuation::{
    continue_orbit, continue_orbit_after, continue_sequence, continue_sequence_after,
    follow_boundary, follow_sequence_boundary, Boundary, BoundaryAt, BoundaryEnd,
    BoundaryEndReason, BoundaryError, BoundaryPoint, BoundarySettings, BoundarySpecialPoint,
    BoundaryStart, Branch, BranchEnd, Continuation, ContinuationError, ContinuationPoint,
    ContinuationSettings, EndReason, Event, EventKind, SequenceBoundaryStart, SpecialKind,
};
pub use cycle::{signature_orbits, signature_orbits_on_grid, solve_signature, SignatureOrbit};
pub use cycle_equations::{CycleEquations, CycleEvaluation, ImpactCondition};
pub use family::{asymmetric_orbits, gap_for_beta, FamilyPoint};
pub use lattice::{
    band_edges, bloch_wave, effective_mass, stop_bands, BandEdges, BlochWave, StopBand,
    StopBandKind,
};
pub use linear::{linear_response, modes, LinearResponse, Modes};
pub use model::{
    Compliance, ContactPair, Harmonic, HarmonicForcing, HarmonicResponse, HarmonicState,
    LinearModel, ModelError, ModelTransition, MAX_HARMONIC_ORDER,
};
pub use motion::UnitMotion;
pub use orbit::{Orbit, Side, Violation};
pub use rigid::{ClearFamily, PairClearance};
pub use sequence::{ImpactKind, ImpactSequence, PairImpact, SequenceError};
pub use sequence_orbit::{
    NewtonState, SequenceNewton, SequenceOrbitError, SequenceProblem, Termination,
};
pub use sequence_search::{sequence_orbits, sequence_orbits_on_grid};
pub use sequence_verdicts::{solve_sequence, ContactPhase, ContactViolation, SequenceOrbit};
pub use signature::{Signature, SignatureError};
pub use symmetric::{symmetric_orbits, OrbitError};
pub use unit::{Damping, Stops, Unit, UnitError};
pub use verdicts::{EnergyBalance, SequenceViolation, ENERGY_EXCHANGE_FRACTION};

pub use continuation::{CORRECTOR_ACCEPTANCE, DEFAULT_MAX_DEPTH};
pub use family::{FamilyError, GAP_ACCEPTANCE, NEAR_HALF};
pub use flow::{join, Augmented, Extrema, ForcedFlow, Transition};
pub use forcing::phase_state;
pub use linear::transmittance_db;
pub use model::{MAX_CONTACT_FREQUENCY_RATIO, RIGID_COUPLING, RIGID_EIGENVALUE};
pub use model_flight::{eigenvalues, ModelFlight};
pub use orbit::{STABILITY_MARGIN, VIABILITY_TOLERANCE};
pub use sequence::MAX_SEQUENCE_IMPACTS;
pub use sequence_orbit::{NEWTON_ACCEPTANCE, NEWTON_ITERATIONS};
pub use sequence_search::{GRID_PER_OSCILLATION, MAX_TUPLES, MIN_GRID};
pub use signature::{MAX_CYCLE_IMPACTS, MAX_CYCLE_PERIOD, MAX_IMPACTS, MAX_PERIOD};
