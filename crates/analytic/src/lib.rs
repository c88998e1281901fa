//! Closed-form steady states of the impacting mass-in-mass unit.
//!
//! An inner mass `m_i` rattles between two stops at relative displacement `r = u_i − u_o = ±Δ`
//! inside an outer mass `m_o`, which a moving base drives through a spring `k_o`
//! (`u_g cos ωt`). This crate gives, without any time stepping:
//!
//! - [`linear`]: the modes and the steady state of the unit without stops;
//! - [`symmetric`]: the symmetric two-impact orbits (`β = ½`) of Nigm and Shabana, by the
//!   half-period symmetry, both branches;
//! - [`family`]: orbits whose side-2 impact comes `βT` after the side-1 impact, for any `β`:
//!   the gap `Δ*(β)` that admits them, and the asymmetric orbits of a given gap;
//! - [`signature`] and [`cycle`]: orbits of any impact signature (`+-`, `++--`, … over `p`
//!   forcing periods) by the Nigm–Shabana method with Newton on exact derivatives, found by
//!   a systematic multi-start ([`signature_orbits`]) or from a guess ([`solve_signature`]),
//!   with viability, Floquet multipliers and the cycle's energy balance;
//! - [`model`]: a general linear model with contact pairs ([`LinearModel`]): the unit and
//!   chains of `N` cells in series, their impact maps, forced flow matrix and linear steady
//!   state (the model the sequence solver below runs on);
//! - [`forcing`]: a model's periodic forcing ([`HarmonicForcing`]), the fundamental and any
//!   higher harmonics of integer order ([`Harmonic`]), each carried by two phase states of the
//!   augmented state, turning at its own `kω`;
//! - [`rigid`]: free bodies (a singular stiffness matrix): a model's rigid modes
//!   ([`LinearModel::rigid_modes`]), the family of its linear motions and whether one stays
//!   clear of the stops ([`LinearModel::clear_family`]); the cycle equations of such a model
//!   border their periodicity solve with contact conditions ([`cycle_equations`]);
//! - [`chain`]: chains of cells in series, graded or not ([`Cell`], at most [`MAX_CELLS`]),
//!   and the linear chain's steady state by transfer matrices ([`chain_response`]), finite at
//!   every local resonance and unbounded only at the chain's own undamped resonances;
//! - [`lattice`]: the infinite lattice of identical cells: Bloch waves, attenuation per cell
//!   ([`bloch_wave`]), band edges and stop bands of the undamped lattice in closed form
//!   ([`band_edges`], [`stop_bands`]);
//! - [`sequence`]: impact sequences of several pairs, the time-ordered `(pair, side)` impacts
//!   over a cycle ([`ImpactSequence`]; one pair's is a [`Signature`]);
//! - [`cycle_equations`]: the cycle equations of an impact sequence (residuals, exact Jacobian
//!   in the unknowns and in `ω`), written once and generic over the augmented dimension: the
//!   unit's signature solver runs them on stack matrices, a model's on heap matrices, with one
//!   Newton ([`SequenceNewton`]) and one multi-start;
//! - [`sequence_orbit`], [`sequence_verdicts`] and [`sequence_search`]: orbits of any impact
//!   sequence on any [`LinearModel`] (the signature solver generalised: problem, Newton solver
//!   and state; amplitudes, viability per pair, Floquet multipliers and energy balance; the
//!   multi-start [`sequence_orbits`]), with [`model_flight`]'s rigorous extrema and integrals;
//!   the verdicts (viability per pair, multipliers with saltation, the [`EnergyBalance`]) are
//!   assembled once for every model, the unit's signature orbits included;
//! - [`continuation`]: pseudo-arclength continuation in `ω` of orbits of any signature of the
//!   unit ([`continue_orbit`]) and of any impact sequence of a [`LinearModel`] such as a chain
//!   ([`continue_sequence`]) through folds, with exact derivatives in `ω`, the bifurcation events
//!   on the branch (fold, branch point, period doubling, Neimark–Sacker, grazing, vanishing
//!   impact) located to `1e-8` in `ω` (branch points to rounding, by a regular defining system), and the branches that leave at them, each followed
//!   once (a branch onto one followed, or onto its mirror image, ends there);
//! - for every orbit ([`orbit::Orbit`]): the outer amplitude from rigorous extrema, viability
//!   (no penetration between impacts, impacts approached from inside) and Floquet multipliers
//!   from the monodromy matrix with saltation matrices.
//!
//! An orbit's motion at any time of its cycle is [`UnitMotion`]'s (a unit's orbits).
//!
//! The flow between impacts is the exponential of the system augmented with the forcing's
//! phase states (two on the unit, [`flow::ForcedFlow`]; two per harmonic on a model): exact,
//! and finite at exact resonance.
//!
//! The source is in folders by job: [`problem`] (what is solved), [`linear`] (without
//! stops), [`flow`] (between impacts), [`cycle`] (the cycle equations of any impact sequence,
//! their Newton and search, the unit's signature orbits and the verdicts), [`closed_form`]
//! (the two-impact closed forms) and [`continuation`]; each module is also at the crate's root
//! (`rattle_analytic::unit`, `rattle_analytic::cycle_equations`, …).
#![deny(missing_docs)]

pub mod closed_form;
pub mod continuation;
pub mod cycle;
pub mod flow;
pub mod linear;
pub mod problem;
#[cfg(any(test, feature = "fixtures"))]
pub mod test_models;

pub use closed_form::{family, orbit, symmetric};
use cycle::verdicts;
pub use cycle::{cycle_equations, motion, sequence_orbit, sequence_search};
pub use flow::model_flight;
pub use linear::lattice;
pub use problem::{chain, forcing, model, rigid, sequence, signature, unit};
pub use verdicts::sequence_verdicts;

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
    ContactPair, Harmonic, HarmonicForcing, HarmonicResponse, HarmonicState, LinearModel,
    ModelError, ModelTransition, MAX_HARMONIC_ORDER,
};
pub use motion::UnitMotion;
pub use orbit::{Orbit, Side, Violation};
pub use rigid::{ClearFamily, PairClearance};
pub use sequence::{ImpactSequence, PairImpact, SequenceError};
pub use sequence_orbit::{
    NewtonState, SequenceNewton, SequenceOrbitError, SequenceProblem, Termination,
};
pub use sequence_search::{sequence_orbits, sequence_orbits_on_grid};
pub use sequence_verdicts::{solve_sequence, SequenceOrbit};
pub use signature::{Signature, SignatureError};
pub use symmetric::{symmetric_orbits, OrbitError};
pub use unit::{Damping, Stops, Unit, UnitError};
pub use verdicts::{EnergyBalance, SequenceViolation, ENERGY_EXCHANGE_FRACTION};
