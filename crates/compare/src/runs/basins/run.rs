//! The runs over a grid of starts: the scene each start runs on ([`System`]), the reference
//! attractors of the coarse subgrid and the distance that attributes a start to one
//! ([`BASIN_PROXIMITY`]), where each start goes, and the basins of the whole grid or of one
//! part of it ([`plane_basins_part`]).

use super::attractor::{number, Attractor, Basins, Reached};
use super::plane::{BasinGrid, BasinPlane};
use crate::runs::parallel::{parallel_map, Grain, Progress};
use crate::runs::shard::Shard;
use crate::scene::simulator::run_watched;
use crate::scene::structure::Structure;
use crate::scene::{AnyScene, Scene};
use nalgebra::DVector;
use rattle_event_driven::{simulate_watched, Model, SimulationOptions, Start, SteadyState, Stop};

/// The scene a basins grid runs on, with what its runs need.
enum System<'a> {
    /// A single unit: the unit's attractors ([`Attractor::Periodic`]).
    Unit(&'a Scene),
    /// A chain of cells.
    Chain(&'a Scene),
    /// A structure and its simulator model at the frequency (`None`: the model was refused,
    /// every start fails).
    Structure(&'a Structure, Option<Box<Model>>),
}

impl<'a> System<'a> {
    fn of(scene: &'a AnyScene, omega: f64) -> System<'a> {
        match scene {
            AnyScene::Cells(s) if s.is_chain() => System::Chain(s),
            AnyScene::Cells(s) => System::Unit(s),
            AnyScene::Structure(form) => System::Structure(
                &form.structure,
                form.structure.event_model(omega).ok().map(Box::new),
            ),
        }
    }

    fn dofs(&self) -> usize {
        match self {
            System::Unit(s) | System::Chain(s) => 2 * s.cell_count(),
            System::Structure(s, _) => s.dofs(),
        }
    }

    /// The length the attribution distance is relative to, at least: the unit's or chain's
    /// gap, a structure's smallest stop distance, else 1.
    fn gap(&self) -> f64 {
        match self {
            System::Unit(s) | System::Chain(s) => s.gap().unwrap_or(1.0),
            System::Structure(s, _) => {
                let smallest = s
                    .stops
                    .iter()
                    .flat_map(|stop| [stop.gap_plus, stop.gap_minus])
                    .filter(|g| g.is_finite())
                    .fold(f64::INFINITY, f64::min);
                if smallest.is_finite() {
                    smallest
                } else {
                    1.0
                }
            }
        }
    }

    /// Whether `start` lies outside a structure's stop clearance (never for the unit and
    /// chain forms, whose starts run as given).
    fn outside(&self, start: &Start) -> bool {
        let System::Structure(s, _) = self else {
            return false;
        };
        let u = |end: Option<usize>| end.map_or(0.0, |j| start.state[j]);
        s.stops.iter().any(|stop| {
            let r = u(stop.plus) - u(stop.minus);
            r > stop.gap_plus || r < -stop.gap_minus
        })
    }

    /// One run from `start`, watched: the steady state and the outer (observed) amplitude,
    /// or `None` when the simulator fails; the attractor it is.
    fn run(
        &self,
        omega: f64,
        start: &Start,
        options: &SimulationOptions,
        watch: &mut dyn FnMut(u64, &DVector<f64>) -> bool,
    ) -> Option<(Attractor, f64, SteadyState)> {
        match self {
            System::Unit(scene) => {
                let sim = run_watched(scene, omega, start, options, watch).ok()?;
                Some((Attractor::of(&sim), sim.outer_amplitude, sim.steady))
            }
            System::Chain(scene) => {
                let sim = run_watched(scene, omega, start, options, watch).ok()?;
                let attractor = Attractor::motion(&sim.steady, scene.pair_count(), |_| true);
                Some((attractor, sim.outer_amplitude, sim.steady))
            }
            System::Structure(structure, model) => {
                let steady =
                    simulate_watched(model.as_deref()?, omega, start, options, watch).ok()?;
                let outer = steady
                    .amplitudes
                    .get(structure.observe)
                    .copied()
                    .unwrap_or(f64::NAN);
                // The floating groups some impact or contact of the cycle touches.
                let touched: Vec<usize> = steady
                    .cycle_impacts
                    .iter()
                    .map(|i| i.pair)
                    .chain(steady.cycle_contacts.iter().map(|c| c.pair))
                    .flat_map(|pair| {
                        let stop = structure.stops[pair];
                        [stop.plus, stop.minus]
                    })
                    .flatten()
                    .filter_map(|j| structure.floating[j])
                    .collect();
                let held = |j: usize| structure.floating[j].is_none_or(|g| touched.contains(&g));
                let attractor = Attractor::motion(&steady, structure.stops.len(), held);
                Some((attractor, outer, steady))
            }
        }
    }
}

/// The start at rest with displacements `outer`, `inner` at time 0.
pub fn start_at_rest(outer: f64, inner: f64) -> Start {
    Start {
        state: DVector::from_column_slice(&[outer, inner, 0.0, 0.0]),
        time: 0.0,
    }
}

/// A start belongs to a reference periodic attractor once its stroboscopic state (at `t = kT`)
/// lies within this distance of one of the attractor's, relative to the larger of that state's
/// norm and the gap, unless the references lie closer together than that (then a third of their
/// smallest separation).
///
/// Measured on the undamped paper unit at ω = 1.9 rad/s (`rattle basins --omega 1.9`, ±1.5 m,
/// 100 × 100 starts), where the stable `++--` orbit attracts slowly (λ₁ = −0.008 /s, 2.6 % per
/// period) and a `+-` orbit coexists: at 1e-2, 31 starts stayed `not periodic` within the
/// 400-period cap (177 periods per start on average); at 3e-2, 17 of them were attributed to
/// `++--` (137 periods per start); at 1e-1, 26 (89 periods per start), and every one of the 26,
/// run on alone for up to 20 000 periods, repeats on `++--` after 677–757 periods. No start
/// changed between the two periodic attractors at any of the three values.
pub const BASIN_PROXIMITY: f64 = 1e-1;

/// The reference grid takes every this-many-th start on each axis (both ends included): 400
/// of a 200 × 200 grid, run to the cap without references.
pub const BASIN_REFERENCE_STRIDE: usize = 10;

/// The attribution distance for `references`: [`BASIN_PROXIMITY`], or a third of the smallest
/// relative distance between the stroboscopic states of two different references if that is
/// smaller, so that no state lies within it of two attractors.
fn proximity(references: &[Reference], gap: f64) -> f64 {
    let mut closest = f64::INFINITY;
    for (k, a) in references.iter().enumerate() {
        for b in &references[k + 1..] {
            for s in &a.states {
                for t in &b.states {
                    let scale = s.norm().max(t.norm()).max(gap);
                    closest = closest.min((s - t).norm() / scale);
                }
            }
        }
    }
    BASIN_PROXIMITY.min(closest / 3.0)
}

/// A periodic attractor reached from the reference grid, with its stroboscopic states.
#[derive(Debug, Clone)]
struct Reference {
    attractor: Attractor,
    outer_amplitude: f64,
    states: Vec<DVector<f64>>,
}

/// Where `start` goes on `system` at `omega`: the attractor, `X_o`, periods run, and for a
/// periodic motion its stroboscopic states. One run up to the options' cap, watched at every
/// section `t = kT` before it is decided: a start whose state lies within `proximity` (relative,
/// see [`BASIN_PROXIMITY`]) of a reference's belongs to that attractor, and the run ends there.
/// A structure's start outside a stop's clearance is not run.
fn reach(
    system: &System<'_>,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
    references: &[Reference],
    proximity: f64,
) -> (Attractor, f64, u64, Vec<DVector<f64>>) {
    if system.outside(start) {
        return (Attractor::OutsideClearance, f64::NAN, 0, Vec::new());
    }
    let gap = system.gap();
    let mut near: Option<&Reference> = None;
    let mut watch = |_: u64, x: &DVector<f64>| {
        near = references.iter().find(|r| {
            r.states
                .iter()
                .any(|s| x.metric_distance(s) <= proximity * s.norm().max(gap))
        });
        near.is_some()
    };
    let Some((attractor, amplitude, steady)) = system.run(omega, start, options, &mut watch) else {
        return (Attractor::Failed, f64::NAN, 0, Vec::new());
    };
    let periods = steady.periods_run;
    match near {
        Some(r) if steady.stopped == Stop::Watched => {
            (r.attractor.clone(), r.outer_amplitude, periods, Vec::new())
        }
        _ => (attractor, amplitude, periods, steady.stroboscopic),
    }
}

/// Where `start` goes on `scene` at `omega`, run to the options' cap (no references): the
/// attractor, `X_o` and periods run.
pub fn destination(
    scene: &Scene,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
) -> (Attractor, f64, u64) {
    let system = if scene.is_chain() {
        System::Chain(scene)
    } else {
        System::Unit(scene)
    };
    let (attractor, amplitude, periods, _) = reach(&system, omega, start, options, &[], 0.0);
    (attractor, amplitude, periods)
}

/// Where `start` goes on a scene of any form at `omega`, run to the options' cap (no
/// references): the attractor, the outer (observed) amplitude and periods run. A structure's
/// start outside a stop's clearance is [`Attractor::OutsideClearance`], not run.
pub fn destination_of(
    scene: &AnyScene,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
) -> (Attractor, f64, u64) {
    let system = System::of(scene, omega);
    let (attractor, amplitude, periods, _) = reach(&system, omega, start, options, &[], 0.0);
    (attractor, amplitude, periods)
}

/// The starts of `grid`, the first axis slowest, the second fastest.
fn starts(grid: &BasinGrid) -> Vec<(f64, f64)> {
    let inner = grid.inner.values();
    grid.outer
        .values()
        .into_iter()
        .flat_map(|o| inner.iter().map(move |&i| (o, i)))
        .collect()
}

/// The periodic attractors of the coarse reference subgrid of `plane` (every
/// [`BASIN_REFERENCE_STRIDE`]-th start on each axis, both ends included), run without
/// references, in grid order (so they do not depend on the number of threads), and the
/// attribution distance for them ([`proximity`]). Families are no references.
fn references(
    system: &System<'_>,
    omega: f64,
    plane: &BasinPlane,
    options: &SimulationOptions,
) -> (Vec<Reference>, f64) {
    let (outer, inner) = (plane.grid.outer.values(), plane.grid.inner.values());
    let every = |n: usize| -> Vec<usize> {
        let mut k: Vec<usize> = (0..n).step_by(BASIN_REFERENCE_STRIDE).collect();
        if n > 0 && k.last() != Some(&(n - 1)) {
            k.push(n - 1);
        }
        k
    };
    let coarse: Vec<(f64, f64)> = every(outer.len())
        .into_iter()
        .flat_map(|a| every(inner.len()).into_iter().map(move |b| (a, b)))
        .map(|(a, b)| (outer[a], inner[b]))
        .collect();
    let dofs = system.dofs();
    let mut references: Vec<Reference> = Vec::new();
    for (attractor, outer_amplitude, _, states) in
        parallel_map(&coarse, Grain::Uneven, &Progress::hidden(), |&xy| {
            reach(system, omega, &plane.start(dofs, xy), options, &[], 0.0)
        })
    {
        let periodic = attractor.is_periodic() && !attractor.is_family();
        if periodic && !references.iter().any(|r| r.attractor.same(&attractor)) {
            references.push(Reference {
                attractor,
                outer_amplitude,
                states,
            });
        }
    }
    let within = proximity(&references, system.gap());
    (references, within)
}

/// Where each of `starts` goes, in parallel, in order.
fn reach_all(
    system: &System<'_>,
    omega: f64,
    plane: &BasinPlane,
    starts: &[(f64, f64)],
    (references, within): &(Vec<Reference>, f64),
    options: &SimulationOptions,
    progress: &Progress,
) -> Vec<Reached> {
    let dofs = system.dofs();
    parallel_map(starts, Grain::Uneven, progress, |&(outer, inner)| {
        let (attractor, outer_amplitude, periods_run, _) = reach(
            system,
            omega,
            &plane.start(dofs, (outer, inner)),
            options,
            references,
            *within,
        );
        Reached {
            outer,
            inner,
            attractor,
            outer_amplitude,
            periods_run,
        }
    })
}

/// The basins of the unit or chain `scene` at `omega` over `grid` (the unit's outer and inner
/// displacements), in parallel, deterministic.
pub fn basins(
    scene: &Scene,
    omega: f64,
    grid: BasinGrid,
    options: &SimulationOptions,
    progress: &Progress,
) -> Basins {
    basins_part(scene, omega, grid, options, None, progress)
}

/// The starts of one part of the unit's basins over its outer and inner displacements (all of
/// them for `None`): [`plane_basins_part`] on the default plane ([`BasinPlane::unit`]).
pub fn basins_part(
    scene: &Scene,
    omega: f64,
    grid: BasinGrid,
    options: &SimulationOptions,
    shard: Option<Shard>,
    progress: &Progress,
) -> Basins {
    let system = if scene.is_chain() {
        System::Chain(scene)
    } else {
        System::Unit(scene)
    };
    part_of(
        &system,
        omega,
        &BasinPlane::unit(grid),
        options,
        shard,
        progress,
    )
}

/// The starts of one part of the basins of `scene` (any form) over `plane` (all of them for
/// `None`): part `K` of `N` is block `K` of `N` nearly equal contiguous blocks of the starts in
/// grid order ([`Shard::range`]), each start run as in the whole grid (every part finds the
/// same references on the whole grid's coarse subgrid), so that its cells are the whole
/// grid's bit for bit. The attractors are numbered within the part; [`merge_parts`] numbers
/// them over the whole grid.
///
/// [`merge_parts`]: super::merge_parts
pub fn plane_basins_part(
    scene: &AnyScene,
    omega: f64,
    plane: &BasinPlane,
    options: &SimulationOptions,
    shard: Option<Shard>,
    progress: &Progress,
) -> Basins {
    part_of(
        &System::of(scene, omega),
        omega,
        plane,
        options,
        shard,
        progress,
    )
}

fn part_of(
    system: &System<'_>,
    omega: f64,
    plane: &BasinPlane,
    options: &SimulationOptions,
    shard: Option<Shard>,
    progress: &Progress,
) -> Basins {
    let all = starts(&plane.grid);
    let range = shard.map_or(0..all.len(), |s| s.range(all.len()));
    // A part without starts needs no references.
    let references = if range.is_empty() {
        (Vec::new(), BASIN_PROXIMITY)
    } else {
        references(system, omega, plane, options)
    };
    let reached = reach_all(
        system,
        omega,
        plane,
        &all[range],
        &references,
        options,
        progress,
    );
    let body_amplitudes = reached
        .iter()
        .map(|r| r.attractor.body_amplitudes().to_vec())
        .collect();
    let (attractors, counts, cells) = number(reached);
    Basins {
        omega,
        grid: plane.grid,
        plane: plane.clone(),
        attractors,
        counts,
        cells,
        body_amplitudes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference(states: &[[f64; 4]]) -> Reference {
        Reference {
            attractor: Attractor::NotPeriodic,
            outer_amplitude: 1.0,
            states: states
                .iter()
                .map(|s| DVector::from_column_slice(s))
                .collect(),
        }
    }

    #[test]
    fn the_proximity_keeps_the_attractors_neighbourhoods_apart() {
        let a = reference(&[[1.0, 0.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0]]);
        // One state of `b` 0.06 from one of `a`'s (relative to norms about 1): a third of it.
        let b = reference(&[[1.06, 0.0, 0.0, 0.0], [0.0, 3.0, 0.0, 0.0]]);
        let guarded = proximity(&[a.clone(), b], 0.5);
        assert!((guarded - 0.06 / 1.06 / 3.0).abs() < 1e-15, "{guarded}");
        // Far apart, or alone: the constant.
        let c = reference(&[[0.0, 0.0, 5.0, 0.0]]);
        assert_eq!(proximity(&[a.clone(), c], 0.5), BASIN_PROXIMITY);
        assert_eq!(proximity(&[a], 0.5), BASIN_PROXIMITY);
        assert_eq!(proximity(&[], 0.5), BASIN_PROXIMITY);
    }
}
