//! The analytic solver on a scene: the linear steady state and every two-impact orbit at one
//! frequency, and the evaluation of either over time.

use crate::scene::Scene;
use nalgebra::{Complex, DVector, Vector4};
use rattle_analytic::{
    asymmetric_orbits, chain_response, linear_response, signature_orbits, symmetric_orbits, Cell,
    LinearResponse, Orbit, OrbitError, SequenceOrbit, Signature, SignatureOrbit, UnitMotion,
};

/// How many grid intervals on `β ∈ (0, 1)` bracket the asymmetric orbits: 400 resolves the
/// asymmetric pairs of the paper's unit (their `β` differ from ½ by more than 1/400 once the
/// pair exists) at about 4 ms per frequency.
pub const BETA_SAMPLES: usize = 400;

/// What the analytic solver says about a scene at one frequency.
#[derive(Debug, Clone)]
pub struct AnalyticPoint {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The linear steady state (stops ignored); of a chain, the last cell's (its
    /// `relative_amplitude` that cell's own).
    pub linear: LinearResponse,
    /// The linear steady state's `max|u_o,j|` of every cell, from the base out (one for a
    /// single unit, its `linear.outer_amplitude`; infinite where the response is unbounded).
    pub linear_cell_outer_amplitudes: Vec<f64>,
    /// Whether the linear steady state reaches the stops of some contact pair (`None`
    /// without stops).
    pub touches_stops: Option<bool>,
    /// Cells of the scene (1 for a single unit); a chain's orbits are not searched here
    /// (`orbits` is empty).
    pub cells: usize,
    /// Two-impact orbits with their branch numbers: symmetric branches 0 and 1 first, then
    /// asymmetric ones (numbered from 2) if asked for. Empty without stops.
    pub orbits: Vec<(usize, Orbit)>,
}

/// Which two-impact orbits to look for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrbitSearch {
    /// The symmetric orbits (`β = ½`) only: closed form, fast.
    Symmetric,
    /// Also the asymmetric ones, bracketed on [`BETA_SAMPLES`] intervals of `β`.
    All,
}

/// Solves the scene at `omega`.
///
/// # Errors
/// The analytic solver's, when the orbit equations cannot be set up (a singular flow).
pub fn analyse(
    scene: &Scene,
    omega: f64,
    search: OrbitSearch,
) -> Result<AnalyticPoint, OrbitError> {
    if scene.is_chain() {
        return Ok(analyse_chain(scene, omega));
    }
    let unit = scene.unit_model();
    let linear = linear_response(&unit, omega);
    let touches_stops = scene.gap().map(|g| linear.relative_amplitude > g);
    let mut orbits = Vec::new();
    if let Some(stops) = scene.stops_model() {
        let symmetric = symmetric_orbits(&unit, &stops, omega)?;
        let count = symmetric.len();
        orbits.extend(symmetric.into_iter().enumerate());
        if search == OrbitSearch::All {
            let others = asymmetric_orbits(&unit, &stops, omega, BETA_SAMPLES);
            orbits.extend(
                others
                    .into_iter()
                    .enumerate()
                    .map(|(i, o)| (count.max(2) + i, o)),
            );
        }
    }
    Ok(AnalyticPoint {
        omega,
        linear_cell_outer_amplitudes: vec![linear.outer_amplitude],
        linear,
        touches_stops,
        cells: 1,
        orbits,
    })
}

/// The linear steady state of a chain scene by the analytic crate's transfer matrices.
fn analyse_chain(scene: &Scene, omega: f64) -> AnalyticPoint {
    let cell_scenes = scene.cell_scenes();
    let cells: Vec<Cell> = cell_scenes
        .iter()
        .map(|c| Cell::of_unit(&c.unit_model()))
        .collect();
    let unbounded = || LinearResponse {
        outer: Complex::new(f64::INFINITY, 0.0),
        inner: Complex::new(f64::INFINITY, 0.0),
        outer_amplitude: f64::INFINITY,
        inner_amplitude: f64::INFINITY,
        relative_amplitude: f64::INFINITY,
        transmittance_db: f64::INFINITY,
        unbounded: true,
    };
    // The scene is valid, so the chain is; an unbounded response has infinite amplitudes.
    let response = chain_response(&cells, scene.base.amplitude, omega).ok();
    let linear = match &response {
        Some(r) if !r.unbounded => {
            let (outer, inner) = (r.outer[cells.len() - 1], r.inner[cells.len() - 1]);
            LinearResponse {
                outer,
                inner,
                outer_amplitude: outer.norm(),
                inner_amplitude: inner.norm(),
                relative_amplitude: (inner - outer).norm(),
                transmittance_db: r.transmittance_db,
                unbounded: false,
            }
        }
        _ => unbounded(),
    };
    let touches_stops = scene
        .effects()
        .contains(&crate::scene::Effect::Stops)
        .then(|| {
            cell_scenes
                .iter()
                .enumerate()
                .any(|(j, c)| match (&response, c.stops) {
                    (Some(r), Some(stops)) => {
                        r.unbounded || (r.inner[j] - r.outer[j]).norm() > stops.gap
                    }
                    _ => false,
                })
        });
    let linear_cell_outer_amplitudes = match &response {
        Some(r) if !r.unbounded => r.cell_outer_amplitudes.clone(),
        _ => vec![f64::INFINITY; cells.len()],
    };
    AnalyticPoint {
        omega,
        linear,
        linear_cell_outer_amplitudes,
        touches_stops,
        cells: cells.len(),
        orbits: Vec::new(),
    }
}

/// Every distinct orbit of `scene` at `omega` with impact signature `signature`, found by the
/// analytic crate's own multi-start over impact phases; empty without stops.
pub fn orbits_of_signature(
    scene: &Scene,
    omega: f64,
    signature: &Signature,
) -> Vec<SignatureOrbit> {
    match scene.stops_model() {
        Some(stops) => signature_orbits(&scene.unit_model(), &stops, omega, signature),
        None => Vec::new(),
    }
}

/// The state of an orbit of any signature at time `t ∈ [0, pT)` after its first canonical
/// impact (at an impact's time, the state just after it): the analytic crate's
/// [`UnitMotion::state_at`].
pub fn signature_orbit_state(scene: &Scene, orbit: &SignatureOrbit, t: f64) -> Vector4<f64> {
    UnitMotion::of_signature_orbit(&scene.unit_model(), orbit).state_at(t)
}

impl AnalyticPoint {
    /// The viable and stable orbits, with their branch numbers.
    pub fn stable_viable_orbits(&self) -> impl Iterator<Item = (usize, &Orbit)> {
        self.orbits
            .iter()
            .filter(|(_, o)| o.viable && o.stable)
            .map(|(b, o)| (*b, o))
    }
}

/// `(u_o, u_i)` of the linear steady state at time `t` (base phase `ωt`).
pub fn linear_displacements(response: &LinearResponse, omega: f64, t: f64) -> (f64, f64) {
    let turn = Complex::new(0.0, omega * t).exp();
    ((response.outer * turn).re, (response.inner * turn).re)
}

/// The state of a two-impact orbit of `scene` at time `t ∈ [0, T)` after its side-1 impact:
/// the first flight from the state after that impact up to and including `βT` (the state just
/// before the side-2 impact), then the second flight. Holds for any `β`: the analytic crate's
/// [`UnitMotion::state_before`].
pub fn orbit_state(scene: &Scene, orbit: &Orbit, t: f64) -> Vector4<f64> {
    UnitMotion::of_orbit(&scene.unit_model(), orbit).state_before(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_orbit_evaluated_over_its_period_returns_to_its_impact_state() {
        let scene = Scene::paper();
        let point = analyse(&scene, 2.0, OrbitSearch::All).unwrap();
        assert!(!point.orbits.is_empty());
        for (_, o) in &point.orbits {
            let period = std::f64::consts::TAU / o.omega;
            let end = orbit_state(&scene, o, period);
            let scale = o.state_before_impact.norm();
            assert!(
                (end - o.state_before_impact).norm() < 1e-10 * scale,
                "β = {}: {end} vs {}",
                o.beta,
                o.state_before_impact
            );
            let before2 = orbit_state(&scene, o, o.beta * period);
            assert!((before2 - o.state_before_side2).norm() < 1e-10 * scale);
        }
    }
}

/// What a row of a sampled orbit is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleKind {
    /// A uniform sample in time.
    Sample,
    /// The state just before an impact.
    BeforeImpact,
    /// The state just after it.
    AfterImpact,
}

/// A state of a sampled orbit at a time.
#[derive(Debug, Clone, PartialEq)]
pub struct OrbitSample {
    /// Time with the base at `u_g cos ωt`, s (the cycle lies in `[t₀, t₀ + pT)`, `t₀ < T`).
    pub time: f64,
    /// What the row is.
    pub kind: SampleKind,
    /// `(u, u̇)`: `(u_o, u_i, u̇_o, u̇_i)` for the unit; for a chain every cell's `u_o, u_i`
    /// from the base out, then their velocities; for a structure every body's displacement in
    /// the scene's order, then their velocities (the model's coordinates, whatever the model).
    pub state: DVector<f64>,
}

/// An impact of a sampled orbit.
#[derive(Debug, Clone, PartialEq)]
pub struct OrbitImpact {
    /// Time with the base at `u_g cos ωt`, s.
    pub time: f64,
    /// The contact pair (0 for the unit; a chain's pairs numbered from the base; a
    /// structure's stops in file order).
    pub pair: usize,
    /// `+1` side 1 (`r = +Δ`), `−1` side 2.
    pub side: i8,
    /// The state just before it (as [`OrbitSample::state`]).
    pub before: DVector<f64>,
}

/// `samples_per_period` (at least 1) uniform samples per forcing period of a cycle of `period`
/// forcing periods lasting `cycle`, from its first impact at forcing time `shift`; `state_at(t)`
/// is the state at time `t` from that impact.
fn uniform_samples(
    samples_per_period: u64,
    period: u32,
    cycle: f64,
    shift: f64,
    state_at: impl Fn(f64) -> DVector<f64>,
) -> Vec<OrbitSample> {
    let n = samples_per_period.max(1) * u64::from(period);
    (0..n)
        .map(|k| {
            let t = k as f64 * cycle / n as f64;
            OrbitSample {
                time: shift + t,
                kind: SampleKind::Sample,
                state: state_at(t),
            }
        })
        .collect()
}

/// Puts a cycle's rows in time order; at an impact's time: before, after, then a uniform
/// sample there (the state after).
fn in_time_order(rows: &mut [OrbitSample]) {
    let rank = |k: SampleKind| match k {
        SampleKind::BeforeImpact => 0,
        SampleKind::AfterImpact => 1,
        SampleKind::Sample => 2,
    };
    rows.sort_by(|a, b| {
        a.time
            .total_cmp(&b.time)
            .then(rank(a.kind).cmp(&rank(b.kind)))
    });
}

/// One cycle of `orbit` sampled from its closed form: `samples_per_period` uniform samples per
/// forcing period from its first canonical impact, and every impact as two rows (before and
/// after), in time order. Times are the forcing's own (`u_g cos ωt`), so that a simulated cycle
/// sampled the same way overlays it directly.
pub fn sample_signature_orbit(
    scene: &Scene,
    orbit: &SignatureOrbit,
    samples_per_period: u64,
) -> (Vec<OrbitSample>, Vec<OrbitImpact>) {
    let period = std::f64::consts::TAU / orbit.omega;
    let cycle = orbit.period as f64 * period;
    // The base phase α at the first impact: t = t' + α/ω, brought into [0, T).
    let shift = (orbit.alpha / orbit.omega).rem_euclid(period);
    let motion = UnitMotion::of_signature_orbit(&scene.unit_model(), orbit);
    let mut rows = uniform_samples(samples_per_period, orbit.period, cycle, shift, |t| {
        dvector(motion.state_at(t))
    });
    let mut impacts = Vec::new();
    for (j, (&phase, &side)) in orbit
        .impact_phases
        .iter()
        .zip(orbit.signature.sides())
        .enumerate()
    {
        let t = phase * cycle;
        let before = orbit.states_before_impacts[j];
        impacts.push(OrbitImpact {
            time: shift + t,
            pair: 0,
            side,
            before: dvector(before),
        });
        rows.push(OrbitSample {
            time: shift + t,
            kind: SampleKind::BeforeImpact,
            state: dvector(before),
        });
        rows.push(OrbitSample {
            time: shift + t,
            kind: SampleKind::AfterImpact,
            state: dvector(motion.state_at(t)),
        });
    }
    in_time_order(&mut rows);
    (rows, impacts)
}

/// A fixed-size state as a column.
fn dvector(x: Vector4<f64>) -> DVector<f64> {
    DVector::from_column_slice(x.as_slice())
}

/// One cycle of an `orbit` of any [`rattle_analytic::LinearModel`] (a chain's, or a
/// structure's: [`crate::scene::structure::Structure::analytic_model`]) sampled from its
/// closed form on `model`, as [`sample_signature_orbit`] samples the unit's: `samples_per_period`
/// uniform samples per forcing period from its first canonical impact, every impact as two rows
/// (before and after), in time order, times the forcing's own. Each flight is the exact forced
/// flow `exp(Â t)` ([`rattle_analytic::LinearModel::transition`]) from the state after its
/// impact; the states are in the model's coordinates ([`OrbitSample::state`]), which the
/// caller names (a chain's cells: [`crate::output::trajectory::analytic_rows`]; a structure's
/// bodies: [`crate::output::structure::structure_orbit_trajectory`]).
pub fn sample_sequence_orbit(
    model: &rattle_analytic::LinearModel,
    orbit: &SequenceOrbit,
    samples_per_period: u64,
) -> (Vec<OrbitSample>, Vec<OrbitImpact>) {
    let omega = orbit.omega;
    let period = std::f64::consts::TAU / omega;
    let cycle = f64::from(orbit.period) * period;
    let shift = (orbit.alpha / omega).rem_euclid(period);
    let impacts_in_order = orbit.sequence.impacts();
    let orders = model.forcing().orders();
    // Each impact's time from the first, the state just after it and the forcing phase there.
    let starts: Vec<(f64, DVector<f64>, DVector<f64>)> = impacts_in_order
        .iter()
        .enumerate()
        .map(|(j, impact)| {
            let t = orbit.impact_phases[j] * cycle;
            let before = DVector::from_column_slice(&orbit.states_before_impacts[j]);
            let theta = orbit.alpha + omega * t;
            (
                t,
                model.impact_state(impact.pair, &before),
                DVector::from_vec(rattle_analytic::phase_state(&orders, theta)),
            )
        })
        .collect();
    // The state at time `t` from the first impact, in the flight that holds it.
    let state_at = |t: f64| {
        let j = starts.iter().rposition(|(tj, _, _)| *tj <= t).unwrap_or(0);
        let (tj, x, p) = &starts[j];
        model.transition(omega, t - tj).apply(x, p).0
    };
    let mut rows = uniform_samples(samples_per_period, orbit.period, cycle, shift, state_at);
    let mut impacts = Vec::new();
    for (j, impact) in impacts_in_order.iter().enumerate() {
        let (t, after, _) = &starts[j];
        let before = DVector::from_column_slice(&orbit.states_before_impacts[j]);
        impacts.push(OrbitImpact {
            time: shift + t,
            pair: impact.pair,
            side: impact.side,
            before: before.clone(),
        });
        rows.push(OrbitSample {
            time: shift + t,
            kind: SampleKind::BeforeImpact,
            state: before,
        });
        rows.push(OrbitSample {
            time: shift + t,
            kind: SampleKind::AfterImpact,
            state: after.clone(),
        });
    }
    in_time_order(&mut rows);
    (rows, impacts)
}

/// The analytic crate's general model of a chain scene (or a unit): every cell with its own
/// stops, one contact pair each, numbered from the base.
///
/// # Errors
/// The index of the first cell without stops (a pair cannot be numbered without them).
pub fn chain_model(scene: &Scene) -> Result<rattle_analytic::LinearModel, usize> {
    let cells = scene
        .cell_scenes()
        .iter()
        .enumerate()
        .map(|(j, c)| {
            let stops = c.stops_model().ok_or(j)?;
            Ok((Cell::of_unit(&c.unit_model()), stops))
        })
        .collect::<Result<Vec<_>, usize>>()?;
    // The scene is valid, hence so is the chain built of its cells.
    rattle_analytic::LinearModel::graded_chain(&cells, scene.base.amplitude).map_err(|_| 0)
}

/// A chain scene with a cell without stops, whose orbits were asked for
/// ([`chain_linear_model`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "--signature: cell {cell} of scene '{scene}' has no `stops`: a chain's orbits need stops \
     in every cell"
)]
pub struct MissingStops {
    /// The scene's name.
    pub scene: String,
    /// The first cell without stops, from 0 at the base.
    pub cell: usize,
}

/// The analytic crate's model of the chain `scene`, on which
/// [`crate::verdict::chain::chain_orbits`] solves: [`chain_model`] with its error named.
///
/// # Errors
/// [`MissingStops`], naming `--signature` and the first cell without stops.
pub fn chain_linear_model(scene: &Scene) -> Result<rattle_analytic::LinearModel, MissingStops> {
    chain_model(scene).map_err(|cell| MissingStops {
        scene: scene.name.clone(),
        cell,
    })
}
