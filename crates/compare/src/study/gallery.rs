//! The gallery's impact oscillator (`data/scenes/impact-oscillator.json`): a frequency sweep
//! of the simulator beside the closed-form period-1 branch
//! ([`crate::references::impact_oscillator`]), for its bifurcation diagram.

use crate::references::impact_oscillator::ImpactOscillator;
use crate::runs::axis::Axis;
use crate::scene::simulator::{run_structure, SimulatedPoint};
use crate::scene::structure::{Structure, StructureScene};
use rattle_event_driven::{SimulationOptions, Start, Status};

/// The gallery's impact oscillator scene.
pub const IMPACT_OSCILLATOR_SCENE: &str =
    include_str!("../../../../data/scenes/impact-oscillator.json");

/// Frequencies of the sweep, rad/s: from well below the natural frequency (1 rad/s) to
/// three times it, where the period-1 branch leaves the stop.
pub const OSCILLATOR_RANGE: (f64, f64) = (0.4, 3.0);

/// Points of the simulated sweep (each continued from the last one's final state).
pub const OSCILLATOR_POINTS: usize = 400;

/// Points of the closed-form branch.
pub const BRANCH_POINTS: usize = 1000;

/// Samples of a flight in the branch's viability check: `T/1024` resolves the figure's
/// branch away from grazing (the tests check the closed form on `T/2¹⁶`).
const BRANCH_SAMPLES: usize = 1 << 10;

/// Periods of the run at each frequency: the sweep records the impacts of the last
/// [`RECORDED_PERIODS`] of a fixed run when the motion is not periodic by then.
const SWEEP_MAX_PERIODS: u64 = 1500;

/// Periods whose impacts a non-periodic point records.
const RECORDED_PERIODS: u32 = 16;

/// One closed-form orbit on the branch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BranchPoint {
    /// rad/s.
    pub omega: f64,
    /// `ẋ⁻`, m/s.
    pub velocity_before: f64,
    /// Stable (both multipliers inside the unit circle).
    pub stable: bool,
}

/// The impact oscillator's bifurcation diagram: impact velocities against frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct OscillatorStudy {
    /// The scene's name.
    pub scene_name: String,
    /// The frequencies swept, rad/s.
    pub omega_range: (f64, f64),
    /// Simulated `(ω, ẋ⁻)` of every impact of the final cycle, sweeping up.
    pub up: Vec<(f64, f64)>,
    /// The same, sweeping down.
    pub down: Vec<(f64, f64)>,
    /// The viable closed-form period-1 orbits.
    pub branch: Vec<BranchPoint>,
}

/// The gallery's impact oscillator, checked.
///
/// # Panics
/// Never: the scene is a fixed, valid text (tested).
pub fn impact_oscillator() -> (StructureScene, Structure) {
    gallery_structure(IMPACT_OSCILLATOR_SCENE)
}

/// A gallery scene's text, parsed and checked.
///
/// # Panics
/// Never on the gallery's texts (fixed and valid, tested).
pub fn gallery_structure(text: &str) -> (StructureScene, Structure) {
    let scene: StructureScene = serde_json::from_str(text).expect("the gallery's scene parses");
    let structure = scene.structure().expect("the gallery's scene is valid");
    (scene, structure)
}

/// Runs `structure` at each frequency of `omegas` in turn, each run started from the last
/// one's final state (the first, and any after a failed run, from rest), and hands every
/// point to `each`: the gallery's sweeps up and down.
pub fn continued_runs(
    structure: &Structure,
    omegas: impl Iterator<Item = f64>,
    options: &SimulationOptions,
    mut each: impl FnMut(&SimulatedPoint),
) {
    let mut start = structure.rest();
    for omega in omegas {
        let Ok(point) = run_structure(structure, omega, &start, options) else {
            start = structure.rest();
            continue;
        };
        each(&point);
        start = Start {
            state: point.steady.final_state.state.clone(),
            time: point.steady.final_state.time,
        };
    }
}

/// The closed form of the gallery's oscillator (one body, a force, a rigid stop on side 1);
/// `None` when its stop is compliant.
pub fn closed_form(structure: &Structure) -> Option<ImpactOscillator> {
    Some(ImpactOscillator {
        mass: structure.mass[(0, 0)],
        damping: structure.damping.as_ref().map_or(0.0, |c| c[(0, 0)]),
        stiffness: structure.stiffness[(0, 0)],
        force: structure.forcing_cos[0].hypot(structure.forcing_sin[0]),
        phase: (-structure.forcing_sin[0]).atan2(structure.forcing_cos[0]),
        gap: structure.stops[0].gap_plus,
        restitution: structure.stops[0].law.restitution()?,
    })
}

/// The sweeps up and down (`points` frequencies each, sequential) and the closed-form branch.
pub fn oscillator_study(points: usize, branch_points: usize) -> OscillatorStudy {
    let (scene, structure) = impact_oscillator();
    let grid = Axis::new(OSCILLATOR_RANGE.0, OSCILLATOR_RANGE.1, points).values();
    let up = sweep(&structure, grid.iter().copied());
    let down = sweep(&structure, grid.iter().rev().copied());
    let reference = closed_form(&structure);
    let branch = Axis::new(OSCILLATOR_RANGE.0, OSCILLATOR_RANGE.1, branch_points)
        .values()
        .into_iter()
        .flat_map(|omega| {
            reference
                .as_ref()
                .and_then(|r| r.period_one_orbits_sampled(omega, BRANCH_SAMPLES).ok())
                .unwrap_or_default()
                .into_iter()
                .filter(|o| o.viable)
                .map(move |o| BranchPoint {
                    omega,
                    velocity_before: o.velocity_before,
                    stable: o.stable,
                })
        })
        .collect();
    OscillatorStudy {
        scene_name: scene.name,
        omega_range: OSCILLATOR_RANGE,
        up,
        down,
        branch,
    }
}

/// The impact velocities of the final cycle at each frequency of `omegas`, each run started
/// from the last one's final state (the first from rest).
fn sweep(structure: &Structure, omegas: impl Iterator<Item = f64>) -> Vec<(f64, f64)> {
    let options = SimulationOptions {
        max_periods: SWEEP_MAX_PERIODS,
        max_period_multiplicity: RECORDED_PERIODS,
        ..SimulationOptions::default()
    };
    let mut out = Vec::new();
    continued_runs(structure, omegas, &options, |point| {
        let steady = &point.steady;
        if steady.status != Status::NoDissipation {
            out.extend(
                steady
                    .cycle_impacts
                    .iter()
                    .map(|i| (point.omega, i.state_before[1])),
            );
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gallery's oscillator is the closed form's: one body, one stop on side 1.
    #[test]
    fn the_gallery_oscillator_has_a_closed_form() {
        let (_, s) = impact_oscillator();
        let c = closed_form(&s).expect("a rigid stop");
        assert_eq!(
            (c.mass, c.damping, c.stiffness, c.force, c.phase),
            (1.0, 0.1, 1.0, 1.0, 0.0)
        );
        assert_eq!((c.gap, c.restitution), (0.5, 0.8));
        let study = oscillator_study(6, 50);
        assert!(study.branch.iter().any(|p| p.stable));
        assert!(!study.up.is_empty() && !study.down.is_empty());
    }
}
