//! One-document results: the linear steady state, a two-impact orbit with its violations, a
//! simulation; what `rattle orbit`, `family` and `simulate` print with `--json`.

use super::finite;
use crate::scene::simulator::SimulatedPoint;
use crate::scene::structure::Structure;
use crate::scene::Scene;
use nalgebra::{Complex, Vector4};
use rattle_analytic::{LinearResponse, Orbit, SequenceOrbit, SignatureOrbit, Violation};
use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;

/// A state `(u_o, u_i, u̇_o, u̇_i)`.
pub type StateRecord = [Option<f64>; 4];

/// A state as written.
pub fn state(x: &Vector4<f64>) -> StateRecord {
    [finite(x[0]), finite(x[1]), finite(x[2]), finite(x[3])]
}

/// Floquet multipliers as `[re, im]` pairs.
pub fn multipliers(m: &[Complex<f64>]) -> Vec<[Option<f64>; 2]> {
    m.iter().map(|m| [finite(m.re), finite(m.im)]).collect()
}

/// Where a one-frequency result was computed: the fields every such record starts with.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct At {
    /// Scene name.
    pub scene: String,
    /// Angular frequency, rad/s.
    pub omega: Option<f64>,
    /// The scene's active effects.
    pub effects: Vec<&'static str>,
}

impl At {
    /// `scene` at `omega`.
    pub fn new(scene: &Scene, omega: f64) -> Self {
        Self {
            scene: scene.name.clone(),
            omega: finite(omega),
            effects: scene.effect_names(),
        }
    }
}

/// The linear steady state (stops ignored).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinearRecord {
    /// `X_o`, m; `null` at an undamped resonance.
    pub outer_amplitude: Option<f64>,
    /// `X_i`, m.
    pub inner_amplitude: Option<f64>,
    /// `max|u_i − u_o|`, m.
    pub relative_amplitude: Option<f64>,
    /// `20 log10(X_o/u_g)`.
    pub transmittance_db: Option<f64>,
    /// Whether the amplitudes are unbounded (undamped exact resonance).
    pub unbounded: bool,
    /// Whether the linear motion reaches the stops; `null` without stops.
    pub touches_stops: Option<bool>,
}

impl LinearRecord {
    /// The record of `response`; `gap` the scene's gap, if it has stops.
    pub fn new(response: &LinearResponse, gap: Option<f64>) -> Self {
        Self {
            outer_amplitude: finite(response.outer_amplitude),
            inner_amplitude: finite(response.inner_amplitude),
            relative_amplitude: finite(response.relative_amplitude),
            transmittance_db: finite(response.transmittance_db),
            unbounded: response.unbounded,
            touches_stops: gap.map(|g| response.relative_amplitude > g),
        }
    }
}

/// Why an orbit is not a motion.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ViolationRecord {
    /// The inner mass passes a stop between impacts.
    Penetration {
        /// 1 or 2.
        side: u8,
        /// Time of the deepest excursion since the side-1 impact, s.
        time: Option<f64>,
        /// How far beyond the stop, m.
        excess: Option<f64>,
    },
    /// An excursion beyond a stop between impacts that is not one of the signature's impacts.
    ExtraImpact {
        /// 1 or 2.
        side: u8,
        /// Time of the deepest excursion since the first impact, s.
        time: Option<f64>,
        /// How far beyond the stop, m.
        excess: Option<f64>,
    },
    /// An impact approached from outside.
    WrongApproach {
        /// 1 or 2.
        side: u8,
        /// `ṙ⁻`, m/s.
        relative_velocity: Option<f64>,
    },
}

impl ViolationRecord {
    /// The record of `v`.
    pub fn new(v: &Violation) -> Self {
        match *v {
            Violation::Penetration { side, time, excess } => ViolationRecord::Penetration {
                side: side.number(),
                time: finite(time),
                excess: finite(excess),
            },
            Violation::ExtraImpact { side, time, excess } => ViolationRecord::ExtraImpact {
                side: side.number(),
                time: finite(time),
                excess: finite(excess),
            },
            Violation::WrongApproach {
                side,
                relative_velocity,
            } => ViolationRecord::WrongApproach {
                side: side.number(),
                relative_velocity: finite(relative_velocity),
            },
        }
    }

    /// In words, for tables: `penetrates side 2 by 1.2e-3`.
    pub fn words(&self) -> String {
        match self {
            ViolationRecord::Penetration { side, excess, .. } => {
                format!(
                    "penetrates side {side} by {:.3e}",
                    excess.unwrap_or(f64::NAN)
                )
            }
            ViolationRecord::ExtraImpact { side, excess, .. } => {
                format!(
                    "reaches side {side} between impacts by {:.3e}",
                    excess.unwrap_or(f64::NAN)
                )
            }
            ViolationRecord::WrongApproach { side, .. } => {
                format!("approaches side {side} from outside")
            }
        }
    }
}

/// One two-impact orbit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrbitRecord {
    /// Branch number (symmetric 0 and 1, asymmetric from 2).
    pub branch: usize,
    /// Fraction of the period from the side-1 to the side-2 impact.
    pub beta: Option<f64>,
    /// The gap `Δ` the orbit is for, m.
    pub gap: Option<f64>,
    /// Base phase at the side-1 impact, rad.
    pub alpha: Option<f64>,
    /// State just before the side-1 impact.
    pub state_before_impact: StateRecord,
    /// State just after the side-1 impact.
    pub state_after_impact: StateRecord,
    /// State just before the side-2 impact.
    pub state_before_side2: StateRecord,
    /// `X_o = max|u_o|`, m.
    pub outer_amplitude: Option<f64>,
    /// `20 log10(X_o/u_g)`.
    pub transmittance_db: Option<f64>,
    /// No violation.
    pub viable: bool,
    /// The violations.
    pub violations: Vec<ViolationRecord>,
    /// Floquet multipliers `[re, im]`.
    pub floquet_multipliers: Vec<[Option<f64>; 2]>,
    /// Every multiplier inside the unit circle.
    pub stable: bool,
}

impl OrbitRecord {
    /// The record of `o` as branch `branch`.
    pub fn new(o: &Orbit, branch: usize) -> Self {
        Self {
            branch,
            beta: finite(o.beta),
            gap: finite(o.gap),
            alpha: finite(o.alpha),
            state_before_impact: state(&o.state_before_impact),
            state_after_impact: state(&o.state_after_impact),
            state_before_side2: state(&o.state_before_side2),
            outer_amplitude: finite(o.outer_amplitude),
            transmittance_db: finite(o.transmittance_db),
            viable: o.viable,
            violations: o.violations.iter().map(ViolationRecord::new).collect(),
            floquet_multipliers: multipliers(&o.floquet_multipliers),
            stable: o.stable,
        }
    }

    /// The largest multiplier modulus.
    pub fn largest_multiplier(&self) -> f64 {
        largest(&self.floquet_multipliers)
    }
}

/// What `rattle orbit --json` prints.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrbitsRecord {
    /// The scene and the frequency.
    #[serde(flatten)]
    pub at: At,
    /// The linear steady state.
    pub linear: LinearRecord,
    /// Every two-impact orbit.
    pub orbits: Vec<OrbitRecord>,
}

/// What `rattle family --json` prints: the member of the family at `β`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FamilyRecord {
    /// The scene and the frequency.
    #[serde(flatten)]
    pub at: At,
    /// `Δ*(β)/u_g`.
    pub gap_over_base_amplitude: Option<f64>,
    /// The orbit at the gap `Δ*(β)`: its fields (`beta`, `gap`, `alpha`, …) at the top level.
    #[serde(flatten)]
    pub orbit: OrbitRecord,
}

/// What `rattle simulate --json` prints.
///
/// # Examples
///
/// ```
/// use rattle_compare::api::{self, Simulation};
/// use rattle_compare::scene::{AnyScene, Scene};
/// use rattle_event_driven::SimulationOptions;
///
/// let scene = AnyScene::Cells(Scene::paper());
/// let Simulation::Cells { record, .. } =
///     api::simulate(&scene, 2.0, &SimulationOptions::default())?
/// else {
///     unreachable!("a scene of the unit form")
/// };
/// assert_eq!(record.status, "periodic");
/// assert_eq!(record.period, Some(1));
/// assert_eq!(record.cell_outer_amplitudes.len(), 1);
/// // Undefined values are `None`, written `null`: never NaN in the JSON.
/// let json = serde_json::to_value(&record).unwrap();
/// assert_eq!(json["scene"], "paper");
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimulationRecord {
    /// The scene and the frequency.
    #[serde(flatten)]
    pub at: At,
    /// `periodic`, `non-periodic` or `no-dissipation`, `, sticking` appended when the final
    /// cycle sticks.
    pub status: String,
    /// The regime's name.
    pub regime: &'static str,
    /// Least period in forcing periods, when periodic.
    pub period: Option<u32>,
    /// Impacts per forcing period over the final cycle.
    pub impacts_per_period: Option<f64>,
    /// `X_o = max|u_o|` over the final cycle, m: of the last cell's outer mass in a chain.
    pub outer_amplitude: Option<f64>,
    /// `20 log10(X_o/u_g)`; `null` without a steady state.
    pub transmittance_db: Option<f64>,
    /// `max|u_o,j|` of every cell's outer mass over the final cycle, m, from the base out (one
    /// entry for a single unit).
    pub cell_outer_amplitudes: Vec<Option<f64>>,
    /// Impacts per forcing period of each contact pair (each cell with stops, from the base
    /// out) over the final cycle; they sum to `impacts_per_period`.
    pub pair_impacts_per_period: Vec<Option<f64>>,
    /// Each contact pair's canonical impact signature over the final cycle when it repeats,
    /// from the simulated impacts: `""` for a pair that does not impact, `null` for one with
    /// more impacts than a signature holds; the whole list `null` when not periodic or
    /// sticking.
    pub pair_signatures: Option<Vec<Option<String>>>,
    /// Whether the final cycle sticks.
    pub sticking: bool,
    /// Why the run ended.
    pub stopped_by: &'static str,
    /// Forcing periods simulated.
    pub periods_run: u64,
    /// Impacts over the run.
    pub impacts: u64,
    /// The canonical impact signature of the periodic cycle (`+` side 1, `-` side 2), from the
    /// simulator's own Newton on its stroboscopic map; `null` when not periodic, sticking, or
    /// when Newton failed (then `orbit_error` says why).
    pub signature: Option<String>,
    /// The simulator's own Floquet multipliers `[re, im]` of that cycle.
    pub floquet_multipliers: Option<Vec<[Option<f64>; 2]>>,
    /// Why the cycle could not be polished, when it could not.
    pub orbit_error: Option<String>,
}

impl SimulationRecord {
    /// The record of `sim` on `scene`.
    pub fn new(scene: &Scene, sim: &SimulatedPoint) -> Self {
        let s = &sim.steady;
        Self {
            at: At::new(scene, sim.omega),
            status: sim.status_name(),
            regime: sim.regime.name(),
            period: s.period,
            impacts_per_period: finite(s.impacts_per_period),
            outer_amplitude: finite(sim.outer_amplitude),
            transmittance_db: sim.transmittance_db.and_then(finite),
            cell_outer_amplitudes: sim
                .cell_outer_amplitudes()
                .into_iter()
                .map(finite)
                .collect(),
            pair_impacts_per_period: sim
                .pair_impacts_per_period(scene.pair_count())
                .into_iter()
                .map(finite)
                .collect(),
            pair_signatures: sim.pair_signatures(scene.pair_count()).map(|sigs| {
                sigs.into_iter()
                    .map(|s| s.ok().map(|s| s.map(|s| s.to_string()).unwrap_or_default()))
                    .collect()
            }),
            sticking: s.sticking,
            stopped_by: sim.stopped_by(),
            periods_run: s.periods_run,
            impacts: s.impacts,
            signature: sim.signature().map(|sig| sig.to_string()),
            floquet_multipliers: s
                .orbit
                .as_ref()
                .map(|o| multipliers(&o.floquet_multipliers)),
            orbit_error: s.orbit_error.clone(),
        }
    }
}

/// An orbit of any impact signature.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SignatureOrbitRecord {
    /// The canonical signature.
    pub signature: String,
    /// Forcing periods per cycle.
    pub period: u32,
    /// Impact times as fractions of the cycle, first = 0, in canonical order.
    pub impact_phases: Vec<Option<f64>>,
    /// Base phase at the first canonical impact, rad.
    pub alpha: Option<f64>,
    /// State just after that impact.
    pub state_after_impact: StateRecord,
    /// `X_o = max|u_o|` over the cycle, m.
    pub outer_amplitude: Option<f64>,
    /// `20 log10(X_o/u_g)`.
    pub transmittance_db: Option<f64>,
    /// No violation.
    pub viable: bool,
    /// The violations.
    pub violations: Vec<ViolationRecord>,
    /// Floquet multipliers `[re, im]`.
    pub floquet_multipliers: Vec<[Option<f64>; 2]>,
    /// Every multiplier inside the unit circle.
    pub stable: bool,
    /// `|base work − (dashpot + impact losses)| / |base work|` over the cycle.
    pub energy_residual: Option<f64>,
}

impl SignatureOrbitRecord {
    /// The record of `o`.
    pub fn new(o: &SignatureOrbit) -> Self {
        Self {
            signature: o.signature.to_string(),
            period: o.period,
            impact_phases: o.impact_phases.iter().map(|&p| finite(p)).collect(),
            alpha: finite(o.alpha),
            state_after_impact: state(&o.state_after_impact),
            outer_amplitude: finite(o.outer_amplitude),
            transmittance_db: finite(o.transmittance_db),
            viable: o.viable,
            violations: o.violations.iter().map(ViolationRecord::new).collect(),
            floquet_multipliers: multipliers(&o.floquet_multipliers),
            stable: o.stable,
            energy_residual: finite(o.energy_residual),
        }
    }

    /// The largest multiplier modulus.
    pub fn largest_multiplier(&self) -> f64 {
        largest(&self.floquet_multipliers)
    }
}

/// What `rattle orbit --signature SIG --json` prints.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SignatureOrbitsRecord {
    /// The scene and the frequency.
    #[serde(flatten)]
    pub at: At,
    /// The canonical signature asked for.
    pub signature: String,
    /// Forcing periods per cycle.
    pub period: u32,
    /// Every distinct orbit found.
    pub orbits: Vec<SignatureOrbitRecord>,
}

/// The largest modulus of multipliers written as `[re, im]`.
fn largest(m: &[[Option<f64>; 2]]) -> f64 {
    m.iter()
        .map(|[re, im]| re.unwrap_or(f64::NAN).hypot(im.unwrap_or(f64::NAN)))
        .fold(0.0, f64::max)
}

/// The simulated side of `rattle compare`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimulatedCycleRecord {
    /// As `rattle simulate`'s `status`.
    pub status: String,
    /// Least period, forcing periods.
    pub period: Option<u32>,
    /// Canonical signature of the polished cycle.
    pub signature: Option<String>,
    /// Impacts per forcing period.
    pub impacts_per_period: Option<f64>,
    /// `X_o`, m.
    pub outer_amplitude: Option<f64>,
    /// The simulator's own Floquet multipliers `[re, im]`.
    pub floquet_multipliers: Option<Vec<[Option<f64>; 2]>>,
}

/// The analytic side of `rattle compare`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnalyticCycleRecord {
    /// Canonical signature.
    pub signature: String,
    /// Forcing periods per cycle.
    pub period: u32,
    /// `X_o`, m.
    pub outer_amplitude: Option<f64>,
    /// No violation.
    pub viable: bool,
    /// Every multiplier inside the unit circle.
    pub stable: bool,
    /// Floquet multipliers `[re, im]`.
    pub floquet_multipliers: Vec<[Option<f64>; 2]>,
    /// Relative energy-balance residual over the cycle.
    pub energy_residual: Option<f64>,
}

/// What `rattle compare --json` prints.
///
/// # Examples
///
/// ```
/// use rattle_compare::api::{self, Comparison};
/// use rattle_compare::scene::{AnyScene, Scene};
/// use rattle_event_driven::SimulationOptions;
///
/// let scene = AnyScene::Cells(Scene::paper());
/// let Comparison::Unit(r) = api::compare(&scene, 2.0, &SimulationOptions::default())? else {
///     unreachable!("a single unit")
/// };
/// assert_eq!(r.class, "agreement");
/// assert_eq!(r.simulated.signature.as_deref(), Some("+-"));
/// assert!(r.relative_difference.unwrap() < 1e-6);
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CrossCheckRecord {
    /// Scene name.
    pub scene: String,
    /// Angular frequency, rad/s.
    pub omega: Option<f64>,
    /// The simulator from rest.
    pub simulated: SimulatedCycleRecord,
    /// The analytic orbit of the simulated signature, or `null`.
    pub analytic: Option<AnalyticCycleRecord>,
    /// Why there is no analytic orbit, when one was looked for.
    pub analytic_error: Option<String>,
    /// `agreement`, `beyond` or `contradiction`.
    pub class: &'static str,
    /// The class in words.
    pub class_detail: String,
    /// See `verdict::CrossCheck::relative_difference`.
    pub relative_difference: Option<f64>,
    /// The two solvers' multipliers matched one to one: the largest distance of a matched pair.
    pub multiplier_difference: Option<f64>,
    /// Every viable analytic orbit of the simulated signature, confirmed or not by the
    /// simulator's own Newton started on it.
    pub confirmed_orbits: Vec<ConfirmationRecord>,
}

/// A viable analytic orbit and the simulator's Newton started on it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConfirmationRecord {
    /// Base phase at the first canonical impact, rad.
    pub alpha: Option<f64>,
    /// Impact phases, fractions of the cycle.
    pub impact_phases: Vec<Option<f64>>,
    /// The analytic verdict.
    pub stable: bool,
    /// The analytic `X_o`, m.
    pub outer_amplitude: Option<f64>,
    /// Whether the simulator's Newton converged to it.
    pub confirmed: bool,
    /// State difference, relative.
    pub state_difference: Option<f64>,
    /// The two solvers' multipliers matched one to one: the largest distance of a matched pair.
    pub multiplier_difference: Option<f64>,
    /// Why Newton failed, if it did.
    pub error: Option<String>,
}

/// One point of a continued branch (`rattle continue --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContinuationPointRecord {
    /// Index of its branch in `branches`.
    pub branch: usize,
    /// Angular frequency, rad/s.
    pub omega: Option<f64>,
    /// Base phase at the first canonical impact, rad.
    pub alpha: Option<f64>,
    /// Impact times as fractions of the cycle.
    pub impact_phases: Vec<Option<f64>>,
    /// `X_o`, m.
    pub outer_amplitude: Option<f64>,
    /// `T`, dB.
    pub transmittance_db: Option<f64>,
    /// Every Floquet multiplier inside the unit circle.
    pub stable: bool,
    /// No penetration, every impact from inside, no extra impact.
    pub viable: bool,
    /// Floquet multipliers `[re, im]`.
    pub floquet_multipliers: Vec<[Option<f64>; 2]>,
    /// On a chain: `max|u_o,j|` of every cell, from the base out, m (`outer_amplitude` is the
    /// last); absent on a single unit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cell_outer_amplitudes: Option<Vec<Option<f64>>>,
    /// On a structure: every body's amplitude by name, m (`outer_amplitude` is the observed
    /// body's); absent on a unit or a chain.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub body_amplitudes: Option<ByBody>,
}

impl ContinuationPointRecord {
    /// The record of a unit's point `p` (without `cell_outer_amplitudes`).
    pub fn new(p: &rattle_analytic::ContinuationPoint) -> Self {
        Self {
            branch: p.branch,
            omega: finite(p.omega),
            alpha: finite(p.alpha),
            impact_phases: p.impact_phases.iter().map(|&x| finite(x)).collect(),
            outer_amplitude: finite(p.outer_amplitude),
            transmittance_db: finite(p.transmittance_db),
            stable: p.stable,
            viable: p.viable,
            floquet_multipliers: multipliers(&p.floquet_multipliers),
            cell_outer_amplitudes: None,
            body_amplitudes: None,
        }
    }

    /// The record of a chain's point `p`, with every cell's outer amplitude.
    pub fn of_chain(p: &rattle_analytic::ContinuationPoint) -> Self {
        Self {
            cell_outer_amplitudes: Some(
                p.cell_outer_amplitudes.iter().map(|&a| finite(a)).collect(),
            ),
            ..Self::new(p)
        }
    }

    /// The record of a structure's point `p`: the observed body's amplitude and transmittance,
    /// with every body's amplitude.
    pub fn of_structure(structure: &Structure, p: &rattle_analytic::ContinuationPoint) -> Self {
        let observed = p.amplitudes.get(structure.observe).copied();
        Self {
            outer_amplitude: observed.and_then(finite),
            transmittance_db: observed.and_then(|x| structure.transmittance_db(x)),
            body_amplitudes: Some(ByBody::new(structure, &p.amplitudes)),
            ..Self::new(p)
        }
    }
}

/// A branch of a continuation: its signature and where it came from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BranchRecord {
    /// Its index.
    pub branch: usize,
    /// Its canonical signature.
    pub signature: String,
    /// Forcing periods per cycle.
    pub period: u32,
    /// The event it was switched onto at, if any (index into `events`).
    pub from_event: Option<usize>,
    /// Its number of points.
    pub points: usize,
}

/// A bifurcation or signature change on a branch.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EventRecord {
    /// The branch it lies on.
    pub branch: usize,
    /// `fold`, `branch-point`, `period-doubling`, `neimark-sacker`, `grazing` or
    /// `vanishing-impact`.
    pub kind: &'static str,
    /// Angular frequency, rad/s (located to 1e-8).
    pub omega: Option<f64>,
    /// The signature of the branch switched onto, where there is one.
    pub signature_after: Option<String>,
    /// Its period.
    pub period_after: Option<u32>,
    /// `X_o` at the event, m.
    pub outer_amplitude: Option<f64>,
}

/// How a branch ends.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EndRecord {
    /// The branch.
    pub branch: usize,
    /// Angular frequency of its last point, rad/s.
    pub omega: Option<f64>,
    /// Why it ends (`omega-min`, `omega-max`, `step-below-minimum`, `point-cap`,
    /// `flight-merged`, `vanishing-impact`, `newton-failed`, `closed-loop`, `joins`,
    /// `max-depth`).
    pub reason: &'static str,
    /// For `joins`: the branch it runs onto (itself for a branch that is its own mirror
    /// image); else `null`.
    pub joins: Option<usize>,
}

/// Each body's value by its name, in the scene's order (a JSON object).
#[derive(Debug, Clone, PartialEq)]
pub struct ByBody(pub Vec<(String, Option<f64>)>);

impl ByBody {
    /// `values[k]` for every body `k` of `structure` (non-finite values `null`).
    pub fn new(structure: &Structure, values: &[f64]) -> Self {
        Self(
            structure
                .names
                .iter()
                .enumerate()
                .map(|(k, name)| (name.clone(), values.get(k).copied().and_then(finite)))
                .collect(),
        )
    }
}

impl Serialize for ByBody {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (name, value) in &self.0 {
            map.serialize_entry(name, value)?;
        }
        map.end()
    }
}

/// `rattle continue --json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContinuationRecord {
    /// Scene name.
    pub scene: String,
    /// The signature asked for, canonical (on a chain: the impact sequence, `0+ 1- 0- 1+`).
    pub signature: String,
    /// Its period.
    pub period: u32,
    /// On a chain: its number of cells (the length of each point's
    /// `cell_outer_amplitudes`); absent on a single unit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cells: Option<usize>,
    /// The start frequency, rad/s.
    pub omega_start: Option<f64>,
    /// Orbits of the signature found at the start frequency.
    pub start_orbits: usize,
    /// Which of them were followed (the others lie on a branch already followed).
    pub followed_starts: Vec<usize>,
    /// Every branch followed, including those switched onto.
    pub branches: Vec<BranchRecord>,
    /// Every point of every branch, branch by branch, in the order followed.
    pub points: Vec<ContinuationPointRecord>,
    /// Every event.
    pub events: Vec<EventRecord>,
    /// Every end.
    pub ends: Vec<EndRecord>,
}
/// The Lyapunov exponents of a simulated motion (`rattle simulate --lyapunov`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LyapunovRecord {
    /// The finite exponents in descending order, 1/s (`null` for a non-finite one).
    pub lyapunov_exponents: Vec<Option<f64>>,
    /// The uncertainty of the largest exponent, 1/s (`null` when every direction collapsed).
    pub lyapunov_uncertainty: Option<f64>,
    /// The uncertainty of each exponent, 1/s, same order.
    pub lyapunov_uncertainties: Vec<Option<f64>>,
    /// Directions contracted to zero by sticking (exponents `−∞`, not listed).
    pub lyapunov_collapsed: usize,
    /// Forcing periods averaged over.
    pub lyapunov_periods: u64,
    /// For a motion that did not repeat: `chaotic`, `quasi-periodic` or `unsettled`; `null`
    /// for a periodic one.
    pub lyapunov_regime: Option<&'static str>,
}

impl LyapunovRecord {
    /// The record of `spectrum`, computed on the motion `sim`.
    pub fn new(sim: &SimulatedPoint, spectrum: &rattle_event_driven::LyapunovSpectrum) -> Self {
        Self {
            lyapunov_exponents: spectrum.exponents.iter().map(|&v| finite(v)).collect(),
            lyapunov_uncertainty: finite(spectrum.uncertainty),
            lyapunov_uncertainties: spectrum.uncertainties.iter().map(|&v| finite(v)).collect(),
            lyapunov_collapsed: spectrum.collapsed,
            lyapunov_periods: spectrum.periods,
            lyapunov_regime: crate::scene::lyapunov::non_periodic_regime(sim, spectrum),
        }
    }
}

/// What `rattle compare --json` prints for a chain scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainCompareRecord {
    /// Scene name.
    pub scene: String,
    /// Angular frequency, rad/s.
    pub omega: Option<f64>,
    /// Cells of the chain.
    pub cells: usize,
    /// The simulator from rest.
    pub simulated: ChainSimulatedRecord,
    /// The analytic orbit of the simulated impact sequence, seeded from the simulated impact
    /// times; `null` when there is none to look for (no impacts, not periodic, …) or the
    /// analytic solver finds none (`analytic_error`).
    pub analytic: Option<ChainAnalyticRecord>,
    /// Why the analytic solver found no orbit of the simulated sequence.
    pub analytic_error: Option<String>,
    /// `agreement`, `contradiction` or `beyond`, as for a single unit.
    pub class: &'static str,
    /// Why the class is not `agreement`, one word: `non-periodic`, `no-dissipation`,
    /// `sticking`, `not-polished`, `too-many-impacts`, `period-too-long`,
    /// `cell-without-stops`, `neutral` (beyond); `no-analytic-orbit`, `not-viable`, `unstable`, `differ`,
    /// `not-linear` (contradiction); `null` for an agreement.
    pub reason: Option<&'static str>,
    /// The reason in words (empty for an agreement).
    pub class_detail: String,
    /// The largest relative difference of the two solvers' orbits: the state just before the
    /// first impact of the sequence, every cell's outer amplitude, the impact phases and the
    /// base phase at the first impact over π (without impacts: every cell's outer amplitude
    /// against the linear chain's).
    pub relative_difference: Option<f64>,
    /// The largest distance between the two solvers' Floquet multipliers, matched one to one.
    pub multiplier_difference: Option<f64>,
    /// The viable analytic orbit confirmed by the simulator's Newton started on it, mid-way
    /// through its first flight; `null` without a viable analytic orbit.
    pub confirmation: Option<ChainConfirmationRecord>,
}

/// The simulator's Newton started on the analytic orbit of a chain.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainConfirmationRecord {
    /// Whether Newton converged to a cycle with the same impacts and a state within 1e-6 of
    /// the analytic one (relative).
    pub confirmed: bool,
    /// The difference of Newton's state from the analytic one at the start, relative (0 when
    /// the analytic state is already within Newton's tolerance).
    pub state_difference: Option<f64>,
    /// Newton's final residual `|P(y) − y|` of the simulator's stroboscopic map, relative to
    /// `max(|y|, gap)`: at the analytic state itself when Newton took no step.
    pub map_residual: Option<f64>,
    /// Newton steps taken from the analytic state.
    pub newton_iterations: Option<u32>,
    /// The largest distance between Newton's multipliers and the analytic ones, matched one
    /// to one.
    pub multiplier_difference: Option<f64>,
    /// Why Newton failed, if it did.
    pub error: Option<String>,
}

/// The simulated side of a chain's comparison.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainSimulatedRecord {
    /// `periodic`, `non-periodic` or `no-dissipation`, with `, sticking` when the final cycle
    /// sticks.
    pub status: String,
    /// Forcing periods per cycle, when periodic.
    pub period: Option<u32>,
    /// Each contact pair's canonical signature over the final cycle (`""` for a pair without
    /// impacts, `null` for one beyond what a signature holds); `null` when not periodic or
    /// sticking.
    pub pair_signatures: Option<Vec<Option<String>>>,
    /// Impacts of all pairs per forcing period over the final cycle.
    pub impacts_per_period: Option<f64>,
    /// Impacts per forcing period of each pair, from the base out.
    pub pair_impacts_per_period: Vec<f64>,
    /// `max|u_o,N|` of the last cell's outer mass over the final cycle, m.
    pub outer_amplitude: Option<f64>,
    /// `max|u_o,j|` of every cell, from the base out, m.
    pub cell_outer_amplitudes: Vec<Option<f64>>,
    /// The simulator's own Floquet multipliers of its Newton-polished cycle, `[re, im]`.
    pub floquet_multipliers: Option<Vec<[Option<f64>; 2]>>,
}

/// The analytic side of a chain's comparison.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainAnalyticRecord {
    /// The impact sequence, canonical (`0+ 1- 0- 1+`).
    pub sequence: String,
    /// Forcing periods per cycle.
    pub period: u32,
    /// The last cell's outer amplitude, m.
    pub outer_amplitude: Option<f64>,
    /// Every cell's outer amplitude, from the base out, m.
    pub cell_outer_amplitudes: Vec<Option<f64>>,
    /// Whether every contact condition holds.
    pub viable: bool,
    /// Whether every Floquet multiplier lies inside the unit circle.
    pub stable: bool,
    /// The analytic Floquet multipliers (monodromy with saltation matrices), `[re, im]`.
    pub floquet_multipliers: Vec<[Option<f64>; 2]>,
    /// The energy balance's residual, relative.
    pub energy_residual: Option<f64>,
}

/// What `rattle orbit --signature --json` prints for a chain.
#[derive(Debug, Clone, Serialize)]
pub struct ChainOrbitsRecord {
    /// The scene and the frequency.
    #[serde(flatten)]
    pub at: At,
    /// Cells of the chain.
    pub cells: usize,
    /// The impact sequence asked for, canonical (`0+ 1- 0- 1+`).
    pub sequence: String,
    /// Forcing periods per cycle.
    pub period: u32,
    /// Every distinct orbit found by the analytic crate's multi-start.
    pub orbits: Vec<SequenceOrbit>,
}

/// The document `rattle simulate --json` prints (also the Python package's): the simulation
/// record with the exponents, when asked for, flattened into one.
#[derive(Serialize)]
pub struct WithLyapunov<'a, R: Serialize = SimulationRecord> {
    /// The simulation (a [`SimulationRecord`], or a structure's
    /// [`StructureSimulationRecord`](crate::output::structure::StructureSimulationRecord)).
    #[serde(flatten)]
    pub record: &'a R,
    /// The exponents, with `--lyapunov`.
    #[serde(flatten)]
    pub lyapunov: Option<&'a LyapunovRecord>,
}
