//! The event loop: exact flights, first contacts, restitution, chatter and sticking, and the
//! steady state seen through the stroboscopic map at `t = kT`.
//!
//! The run is split the way iterative solvers are: the *problem* (a [`Model`], `ω` and the
//! [`SimulationOptions`]), the *solver* (`Engine`: the free flow, the contact geometry and the
//! stuck flows, prepared once) and the *state* (`RunState`: everything that changes during a
//! run). The loop is `init`, then `next_iter` (one free flight or one stuck phase, ending at an
//! event or at the section `t = kT`) and, at each section, `terminate` (the stopping rules, all
//! in `stopping_rule`). The events are named points: `impact`, `stick` and `release`, and each
//! flight is one closed-form segment. A run asked for its tangent flow (`Engine::tangent_run`,
//! used by [`crate::newton`]) multiplies the Jacobian by each flight's propagator and each
//! impact's saltation matrix, at a stick by the plastic saltation onto the held pair's
//! constrained tangent space and while held by the reduced propagator (a run that sticks has
//! no invertible Jacobian, which [`crate::newton`] refuses; [`crate::lyapunov`] counts the
//! collapsed directions); ordinary runs carry no tangent and only test for its absence. A
//! traced run (`Engine::trace_run`, used by [`crate::trajectory`]) samples each segment's
//! closed form and each event's states.
//!
//! **Many contact pairs** (chains of cells, [`Model::chain`]): every pair is watched at all
//! times with the same first-contact guarantee. In free flight all pairs' gaps are searched
//! (the earliest quadratic estimate first, each search cut at the earliest contact found
//! so far; a gap is first only summarised from the flight's modal coordinates, every pair's
//! in one pass over the modes, and a pair whose evaluation-free bounds keep it inside its
//! stops up to that contact is decided exactly as its search would decide it, without the
//! search; a pair that is searched hands its summary to the search). A free flight that
//! starts where a contact left the state starts from the modal deviation carried across the
//! contact (the previous flight's, advanced by the search's exponentials, plus `V⁻¹` of the
//! impact's jump) instead of recomputing it from the state: a chain's results differ from a
//! fresh start in their last bits; one pair keeps the fresh start, bit for bit as before.
//! Any set of pairs may be held on their stops at once: the motion is then the
//! constrained flow with the held pairs' relative coordinates fixed (`Stuck`), each held pair
//! is released when its own contact force would pull, and the other pairs are searched in
//! the constrained flow. Contacts are resolved one at a time in time order, ties by pair
//! index (see `Engine::free_flight` for what that assumes).
//!
//! Free bodies (rigid modes of the free flow) fly in the flow's general form: their flights
//! are searched term by term (a polynomial drift plus oscillations, [`crate::expsum`]'s
//! general bounds), without the steady-response summaries and carries. A periodic final
//! cycle in which no impact reaches them is a family ([`SteadyState::family`]).
//!
//! The tangent flow through a stick or an impact made while other pairs are held uses the
//! free saltation matrices (exact when the event's pair shares no degree of freedom with the
//! held ones under a diagonal mass matrix, as in a chain; the constrained propagator is
//! exact in any case); [`crate::newton`] refuses sticking runs anyway.

use crate::expsum::{ExpSum, SearchStack, SharedPoints, Summary, Tolerances, LANES};
use crate::flow::{Flight, FlowError, Functional, JointWeights, LinearFlow};
use crate::model::{ContactPair, Model};
use nalgebra::{DMatrix, DVector};
use std::cell::Cell;
use std::collections::VecDeque;
use thiserror::Error;

mod contact;
mod flight;
mod options;
mod outcome;
mod periodicity;
mod pressed;
mod run;
mod state;
mod stuck;
mod tangent;
mod trace;

use flight::{Scratch, Watch, WatchedPairs};
pub use outcome::{ContactPhase, ContactRecord};
use periodicity::{least_period, repeat_error, scale_floor, Sections};
pub(crate) use pressed::TangentContact;
use pressed::{OpenContact, Pressed};
pub(crate) use state::Resume;
use state::{Contact, Decision, Mode, Observation, Plan, RunState, Window};
use stuck::Stuck;
use trace::sample;

pub(crate) use options::check_inputs;
pub use options::{
    SimulationError, SimulationOptions, Start, CONSERVATIVE_MAX_PERIODS, DEFAULT_MAX_EVENTS,
    DEFAULT_MAX_OSCILLATIONS, DEFAULT_MAX_PERIODS, DEFAULT_MAX_PERIOD_MULTIPLICITY,
    DEFAULT_PERIODICITY_TOLERANCE, DEFAULT_ROOT_TOLERANCE, EVENT_STORM, MIN_OSCILLATION_PERIODS,
    SAMPLES_PER_PERIOD,
};
pub use outcome::{ImpactRecord, PeriodicOrbit, Status, SteadyState, Stop};
pub(crate) use tangent::Tangent;
pub use trace::RowKind;
pub(crate) use trace::{Trace, TracedImpact};

/// A contact is an excursion beyond a stop deeper than this fraction of the gap scale (plus the
/// rounding of the positions, [`POSITION_ROUNDING`]): a motion that touches a stop to rounding
/// does not impact (no event storms at a graze).
pub(crate) const CONTACT_DEPTH: f64 = 1e-12;

/// Positions are known to this relative rounding of their size (`~100 ε`): an excursion beyond
/// a stop smaller than that, relative to the largest position, is no contact (introduced for
/// the base-amplitude-1e6 scene, whose positions dwarf the gap).
pub(crate) const POSITION_ROUNDING: f64 = 1e-14;

/// Velocities are known to this relative rounding of their size (`~1000 ε`, as they come out of
/// sums of exponentials of size comparable to the largest velocity): a slower approach is a
/// graze, not an impact.
pub(crate) const VELOCITY_ROUNDING: f64 = 1e-13;

/// A relative velocity below this fraction of `ω × gap` after an impact, with the stop pushing,
/// is a pair at rest on the stop: it sticks.
pub(crate) const RESTING_VELOCITY: f64 = 1e-10;

/// After a release the pair leaves the stop with zero relative velocity and acceleration;
/// rounding must not read that as a new contact, so contacts are ignored for this fraction of a
/// period (a hundred times the default root tolerance).
pub(crate) const RELEASE_GRACE: f64 = 1e-10;

/// Chatter is cut short when the remaining bounces would all fit in this fraction of a period:
/// the pair then sticks at once (the state error is of order the remaining relative velocity
/// times that time). Smaller values spend thousands of bounces per chatter on accumulations
/// whose remaining time is far below any output's resolution.
pub(crate) const CHATTER: f64 = 1e-5;

/// Undamped motion with no impact for this many periods is reported as `NoDissipation`: nothing
/// will ever dissipate its transients (unless a later beat reaches a stop; the status says so).
const QUIET: u64 = 500;

/// A period found while running is confirmed at the end with this many times the periodicity
/// tolerance: a transient through complex multipliers does not decay monotonically, so the
/// last two sections may repeat slightly less well than the two that triggered detection.
const CONFIRMATION: f64 = 10.0;

/// Differences within this factor of the tolerance at a smaller multiplicity make a period
/// ambiguous: a transient decaying through a negative or complex Floquet multiplier can repeat
/// at `2T` long before it repeats at `T`.
const AMBIGUITY: f64 = 1e3;

/// Relative accuracy of the closed-form extrema in the amplitudes (`|u_j|` maxima), relative
/// to `1 + amplitude`: a few hundred rounding units, well below any reported digit.
const AMPLITUDE_TOLERANCE: f64 = 1e-13;

/// Records (impacts, trajectory samples) within this fraction of a period before the final
/// cycle's start are kept in it: an impact at the section itself carries an absolute time that
/// rounds to either side of `kT`.
const CYCLE_START_SLACK: f64 = 1e-9;

/// In the Gram–Schmidt of a stuck pair's basis of `d⊥`, a projected unit vector shorter than
/// this is dependent on the ones kept and is dropped: the vectors are of length 1 or 0 up to
/// rounding (`d` has entries ±1), so any threshold far from both works.
const BASIS_DROP: f64 = 1e-8;

/// Smallest scale divided by: keeps a relative measure finite when the scale is zero (a run at
/// rest, a unit with no stops).
const SCALE_FLOOR: f64 = 1e-300;

/// Geometry of one contact pair.
struct Pair {
    spec: ContactPair,
    /// `d` with `r = d·u`.
    direction: DVector<f64>,
    /// `M⁻¹ d`.
    mobility: DVector<f64>,
    /// `dᵀ M⁻¹ d`.
    compliance: f64,
    /// `M⁻¹ C M⁻¹ d` (zero without damping): how the impulse along `d` changes the damping
    /// force's acceleration, for the saltation matrices.
    drag: DVector<f64>,
    /// `r` as a functional of the free flow's state.
    relative_displacement: Functional,
    /// The nonzero rows of `r̈ = (M⁻¹d) · (f(τ) − K u − C u̇)`, for
    /// [`Engine::free_relative_acceleration`]: per row `i` with `(M⁻¹d)_i ≠ 0`, that entry and
    /// the nonzero `K_ij` (index `j` into the state) and `C_ij` (index `n + j`), in the order
    /// of the dense sum.
    acceleration_rows: Vec<AccelerationRow>,
    /// The nonzero entries `(i, d_i)` of `d`, `i` rising: `ṙ = d · u̇` over them only (the
    /// terms left out are exact zeros).
    direction_entries: Vec<(usize, f64)>,
    /// The free impact ([`Model::apply_impact`], from the model's own `d` and `M⁻¹d`):
    /// the nonzero entries `(i, (M⁻¹d)_i)`, `i` rising, and `d · M⁻¹d` as it computes it.
    impact_mobility: Vec<(usize, f64)>,
    impact_compliance: f64,
    /// The state's entries a free impact of this pair reads or writes (the velocities of
    /// [`Self::direction_entries`] and [`Self::impact_mobility`], rising): all a contact
    /// with no chance of sticking needs of the state ([`Engine::before_contact`]).
    contact_entries: Vec<usize>,
    /// Per kept mode of the free flow, what a contact reads of it (`None` for more than
    /// [`CONTACT_ENTRIES`] contact entries): see [`ContactMode`].
    contact_modes: Option<Vec<ContactMode>>,
    /// Per entry of [`Self::impact_mobility`] (the velocity `u̇_i` an impact changes), its
    /// weight in a bound on `|r̈|`, `Σ_rows |(M⁻¹d)_r| |C_ri|` ([`acceleration_bound`]): the
    /// bound grows by it times `|Δu̇_i|` across the impact.
    impact_weights: Vec<f64>,
    /// A bound on the forcing's part of `r̈`, `Σ_rows |(M⁻¹d)_i| (|f_ci| + |f_si|)`
    /// ([`acceleration_bound`]), each higher harmonic's amplitudes added likewise.
    forcing_size: f64,
    /// Per higher harmonic of the forcing (none of zero amplitude), its rate `kω` and its
    /// part of `r̈`, `(M⁻¹d)·f_c,k` on `cos kωτ` and `(M⁻¹d)·f_s,k` on `sin kωτ`; empty for a
    /// forcing at `ω` alone.
    harmonic_forcing: Vec<(f64, f64, f64)>,
}

/// Contact entries ([`Pair::contact_entries`]) up to which a contact may form only them.
const CONTACT_ENTRIES: usize = 4;

/// One kept mode `k` of the free flow as a contact of a pair reads it ([`Engine::before_contact`]),
/// all of it in one pass over the modes' coordinates `z`: `sizes`, the largest position and
/// velocity entry of its eigenvector ([`LinearFlow::kept_peaks`]) and its size in `r̈`'s part
/// in the state ([`acceleration_bound`]), then `0`, each times `|Re z_k| + |Im z_k|` a bound;
/// and `re`, `im`, `Re v_ik` and `Im v_ik` of the pair's contact entries `i` in order (zeros
/// past them), each contact entry `Σ_k Re v_ik Re z_k − Im v_ik Im z_k`. Four lanes each,
/// as one AVX register holds them.
#[derive(Debug, Clone, Copy)]
struct ContactMode {
    sizes: [f64; 4],
    re: [f64; CONTACT_ENTRIES],
    im: [f64; CONTACT_ENTRIES],
}

/// One row `i` of [`Pair::acceleration_rows`]: `(M⁻¹d)_i (f_i(τ) − Σ_j (K_ij u_j + C_ij u̇_j))`
/// with only its nonzero coefficients.
struct AccelerationRow {
    mobility: f64,
    /// The forcing's amplitudes `f_i` on `cos ωt` and `sin ωt` (the model's, copied).
    forcing: (f64, f64),
    /// `(index into the state, coefficient)`, `K_ij` at `j` then `C_ij` at `n + j`, `j` rising.
    coefficients: Vec<(usize, f64)>,
}

/// The solver: everything prepared once from the problem and fixed during the run.
pub(crate) struct Engine<'m> {
    model: &'m Model,
    omega: f64,
    period: f64,
    n: usize,
    free: LinearFlow,
    /// `u_j` as functionals of the free flow's state, for the amplitudes.
    displacements: Vec<Functional>,
    pairs: Vec<Pair>,
    /// With several pairs, their relative displacements prepared for the free flight's
    /// summaries in one pass ([`Flight::summarize_all`]); `None` for one pair.
    free_joint: Option<JointWeights>,
    /// `M⁻¹`.
    inverse_mass: DMatrix<f64>,
    /// Reduced flows of sets of pairs held on their stops, built on first use.
    stuck: Vec<Stuck>,
    /// Augmented flows of sets of compliant pairs pressed into their stops, built on first
    /// use.
    pressed: Vec<Pressed>,
    /// Contact times are resolved to this (`root_tolerance × T`).
    time_tolerance: f64,
    /// The largest gap: the scale of the periodicity test and of the contact thresholds.
    pub(crate) scale: f64,
    /// [`CONTACT_DEPTH`] × scale.
    contact_depth: f64,
    /// [`RESTING_VELOCITY`] × ω × scale.
    resting_velocity: f64,
    /// [`RELEASE_GRACE`] × T.
    release_grace: f64,
    /// Storage reused by every flight.
    work: Scratch,
    /// `(τ, sin ωτ, cos ωτ)` of the last forcing phase computed ([`Self::forcing_at`]).
    forcing: Cell<(f64, f64, f64)>,
    /// Whether a free flight's search may go on past the section it reaches
    /// ([`flight::Pending`]): one contact pair, the flow has a steady response, and two
    /// periods of the fixed grid's chunks are cached ([`crate::expsum::fixed_grid_reach`]).
    carries_sections: bool,
    /// Tests only: form the state at every section, even one nothing observes
    /// ([`Engine::unobserved_section`]), and count those that are not formed.
    #[cfg(test)]
    form_every_section: bool,
    #[cfg(test)]
    unformed_sections: Cell<u64>,
    /// Tests only: form the whole state at every contact ([`Engine::before_contact`]), and
    /// count the contacts whose state is not formed whole.
    #[cfg(test)]
    form_every_contact: bool,
    #[cfg(test)]
    unformed_contacts: Cell<u64>,
}

impl<'m> Engine<'m> {
    /// The solver for `model` at `omega`.
    ///
    /// # Errors
    /// [`SimulationError::Flow`] when the modal flow does not exist.
    pub(crate) fn new(
        model: &'m Model,
        omega: f64,
        options: &SimulationOptions,
    ) -> Result<Self, SimulationError> {
        let n = model.dofs();
        let period = std::f64::consts::TAU / omega;
        let free = LinearFlow::of_model(model, omega)?;
        let minv = model
            .mass
            .clone()
            .try_inverse()
            .ok_or(FlowError::SingularMass)?;
        let pairs: Vec<Pair> = model
            .contacts
            .iter()
            .enumerate()
            .map(|(index, c)| Pair::new(model, (&free, &minv), (index, c), omega))
            .collect();
        let displacements = (0..n)
            .map(|j| {
                let mut c = DVector::zeros(2 * n);
                c[j] = 1.0;
                free.functional(&c)
            })
            .collect();
        let scale = pairs
            .iter()
            .flat_map(|p| [p.spec.gap_plus, p.spec.gap_minus])
            .filter(|gap| gap.is_finite())
            .fold(0.0, f64::max)
            .max(SCALE_FLOOR);
        let free_joint = (pairs.len() > 1).then(|| {
            let functionals: Vec<&Functional> =
                pairs.iter().map(|p| &p.relative_displacement).collect();
            free.joint_weights(&functionals)
        });
        // The searches' fastest rate as `|re| + |im|`: at most `√2 |λ|`, or the forcing's
        // fastest harmonic `kω`.
        let top_order = model.active_harmonics().map(|h| h.order).max().unwrap_or(1);
        let fastest =
            (std::f64::consts::SQRT_2 * free.fastest_rate()).max(omega * top_order as f64);
        // One pair only: with several, searching their summaries past the section cost more
        // than the flights it saved (chain8, callgrind: +3.5 %).
        let carries_sections = model.contacts.len() == 1
            && !model.has_compliance()
            && free.has_steady_response()
            && 2.0 * period <= crate::expsum::fixed_grid_reach(fastest);
        Ok(Self {
            model,
            omega,
            period,
            n,
            free,
            displacements,
            pairs,
            free_joint,
            inverse_mass: minv,
            stuck: Vec::new(),
            pressed: Vec::new(),
            time_tolerance: options.root_tolerance * period,
            scale,
            contact_depth: CONTACT_DEPTH * scale,
            resting_velocity: RESTING_VELOCITY * omega * scale,
            release_grace: RELEASE_GRACE * period,
            work: Scratch::default(),
            forcing: Cell::new((f64::NAN, 0.0, 0.0)),
            carries_sections,
            #[cfg(test)]
            form_every_section: false,
            #[cfg(test)]
            unformed_sections: Cell::new(0),
            #[cfg(test)]
            form_every_contact: false,
            #[cfg(test)]
            unformed_contacts: Cell::new(0),
        })
    }

    /// The forcing period `T`.
    pub(crate) fn period(&self) -> f64 {
        self.period
    }

    /// The free flow's rigid shapes `R` (`n × r`), if it has rigid modes.
    pub(crate) fn rigid_shapes(&self) -> Option<&DMatrix<f64>> {
        self.free.rigid_shapes()
    }

    /// What [`Engine::cannot_stick`] reads of the engine.
    fn bounce_test(&self) -> contact::BounceTest {
        contact::BounceTest {
            resting_velocity: self.resting_velocity,
            period: self.period,
        }
    }

    /// `(sin ωτ, cos ωτ)`, kept for the last `τ` asked: a contact's accelerations and the flight
    /// that follows it start at the same `τ`, and need the forcing phase there once.
    fn forcing_at(&self, tau: f64) -> (f64, f64) {
        let (at, sin, cos) = self.forcing.get();
        if at == tau {
            return (sin, cos);
        }
        let (sin, cos) = crate::trig::sin_cos(self.omega * tau);
        self.forcing.set((tau, sin, cos));
        (sin, cos)
    }
}

impl Pair {
    /// The geometry of contact pair `c` (the model's `index`-th) in the free flow `free`
    /// (`minv` = `M⁻¹`) at forcing frequency `omega`.
    fn new(
        model: &Model,
        (free, minv): (&LinearFlow, &DMatrix<f64>),
        (index, c): (usize, &ContactPair),
        omega: f64,
    ) -> Pair {
        let n = model.dofs();
        let d = c.direction(n);
        let mut position = DVector::zeros(2 * n);
        position.rows_mut(0, n).copy_from(&d);
        let mobility = minv * &d;
        let compliance = d.dot(&mobility);
        let relative_displacement = free.functional(&position);
        let drag = match &model.damping {
            Some(damping) => minv * (damping * &mobility),
            None => DVector::zeros(n),
        };
        let acceleration_rows: Vec<AccelerationRow> = (0..n)
            .filter(|&i| mobility[i] != 0.0)
            .map(|i| AccelerationRow {
                mobility: mobility[i],
                forcing: (model.forcing_cos[i], model.forcing_sin[i]),
                coefficients: (0..n)
                    .flat_map(|j| {
                        let k = (j, model.stiffness[(i, j)]);
                        let c = (n + j, model.damping.as_ref().map_or(0.0, |c| c[(i, j)]));
                        [k, c]
                    })
                    .filter(|&(_, v)| v != 0.0)
                    .collect(),
            })
            .collect();
        let (model_d, model_mobility) = &model.directions[index];
        let nonzero = |v: &DVector<f64>| -> Vec<(usize, f64)> {
            v.iter()
                .enumerate()
                .filter(|&(_, &x)| x != 0.0)
                .map(|(i, &x)| (i, x))
                .collect()
        };
        let (direction_entries, impact_mobility) = (nonzero(&d), nonzero(model_mobility));
        let mut contact_entries: Vec<usize> = direction_entries
            .iter()
            .chain(&impact_mobility)
            .map(|&(i, _)| n + i)
            .collect();
        contact_entries.sort_unstable();
        contact_entries.dedup();
        let (weights, mut forcing_size) = acceleration_bound(&acceleration_rows, 2 * n);
        let harmonic_forcing: Vec<(f64, f64, f64)> = model
            .active_harmonics()
            .map(|h| {
                let rate = h.order as f64 * omega;
                (rate, mobility.dot(&h.cos), mobility.dot(&h.sin))
            })
            .collect();
        for h in model.active_harmonics() {
            forcing_size += (0..n)
                .map(|i| mobility[i].abs() * (h.cos[i].abs() + h.sin[i].abs()))
                .sum::<f64>();
        }
        let acceleration_sizes = free.kept_entry_sizes(&weights);
        let impact_weights = impact_mobility
            .iter()
            .map(|&(i, _)| weights[n + i])
            .collect();
        let contact_modes = contact_modes(free, &contact_entries, &acceleration_sizes);
        Pair {
            direction_entries,
            impact_mobility,
            contact_entries,
            contact_modes,
            impact_weights,
            forcing_size,
            harmonic_forcing,
            impact_compliance: model_d.dot(model_mobility),
            spec: *c,
            direction: d,
            mobility,
            compliance,
            drag,
            relative_displacement,
            acceleration_rows,
        }
    }
}

/// The weights of the state's entries in a bound on a pair's `r̈` from its rows
/// ([`Pair::acceleration_rows`]), each `Σ_i |(M⁻¹d)_i| |c_ij|` over the rows' coefficients
/// (`m` entries), and `Σ_i |(M⁻¹d)_i| (|f_ci| + |f_si|)`: with no cancellation anywhere,
/// `|r̈|` as [`Engine::free_relative_acceleration`] rounds it is within a few roundings of
/// `Σ_j weight_j |y_j| + forcing`, and so of `Σ_k size_k (|Re z_k| + |Im z_k|) + forcing` with
/// the modes' sizes of those weights ([`LinearFlow::kept_entry_sizes`], [`ContactMode`]).
fn acceleration_bound(rows: &[AccelerationRow], m: usize) -> (Vec<f64>, f64) {
    let mut weights = vec![0.0; m];
    let mut forcing = 0.0;
    for row in rows {
        for &(j, c) in &row.coefficients {
            weights[j] += row.mobility.abs() * c.abs();
        }
        forcing += row.mobility.abs() * (row.forcing.0.abs() + row.forcing.1.abs());
    }
    (weights, forcing)
}

/// [`Pair::contact_modes`] of a pair's contact entries, given its modes' sizes in `r̈`.
fn contact_modes(
    free: &LinearFlow,
    contact_entries: &[usize],
    acceleration_sizes: &[f64],
) -> Option<Vec<ContactMode>> {
    if contact_entries.len() > CONTACT_ENTRIES {
        return None;
    }
    let columns: Vec<Vec<(f64, f64)>> = contact_entries
        .iter()
        .map(|&i| free.kept_entry(i))
        .collect();
    let modes = free
        .kept_peaks()
        .iter()
        .zip(acceleration_sizes)
        .enumerate()
        .map(|(k, (&(position, velocity), &acceleration))| {
            let (mut re, mut im) = ([0.0; CONTACT_ENTRIES], [0.0; CONTACT_ENTRIES]);
            for ((re, im), column) in re.iter_mut().zip(&mut im).zip(&columns) {
                (*re, *im) = column[k];
            }
            ContactMode {
                sizes: [position, velocity, acceleration, 0.0],
                re,
                im,
            }
        })
        .collect();
    Some(modes)
}
