//! The gallery's impact dampers (`data/scenes/impact-damper.json`, one primary body, and
//! `impact-damper-two-mass.json`, a two-body primary): what the device buys, the primary's
//! response with the free body against the primary alone over frequency, with the one-body
//! damper's symmetric two-impact motion in closed form ([`crate::references::impact_damper`])
//! on top.

use crate::references::impact_damper::ImpactDamper;
use crate::runs::axis::Axis;
use crate::scene::structure::Structure;
use crate::study::gallery::{continued_runs, gallery_structure};
use nalgebra::{Complex, DMatrix, DVector};
use rattle_event_driven::{SimulationOptions, Status};

/// The gallery's impact damper with one primary body.
pub const IMPACT_DAMPER_SCENE: &str = include_str!("../../../../data/scenes/impact-damper.json");

/// The gallery's impact damper on the upper body of a two-body primary.
pub const IMPACT_DAMPER_TWO_MASS_SCENE: &str =
    include_str!("../../../../data/scenes/impact-damper-two-mass.json");

/// Frequencies of the sweeps, rad/s: around the one-body primary's mode (1 rad/s) and both of
/// the two-body primary's (`√0.5` and `√2` rad/s).
pub const DAMPER_RANGE: (f64, f64) = (0.4, 1.8);

/// Points of each simulated sweep, up and down (each continued from the last one's final
/// state).
pub const DAMPER_POINTS: usize = 150;

/// Points of the closed-form branch and of the primary alone.
pub const DAMPER_BRANCH_POINTS: usize = 600;

/// Samples of a half-period flight in the branch's viability check: `T/2048` resolves the
/// figure's branch away from grazing (the tests check the closed form on `T/2¹⁷`).
const BRANCH_SAMPLES: usize = 1 << 10;

/// Periods of the run at each frequency; a motion not periodic by then shows the amplitude of
/// its last cycle.
const SWEEP_MAX_PERIODS: u64 = 1500;

/// One closed-form symmetric motion on the branch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DamperBranchPoint {
    /// rad/s.
    pub omega: f64,
    /// The primary's amplitude `max |x|`, m.
    pub amplitude: f64,
    /// Stable (every multiplier inside the unit circle).
    pub stable: bool,
}

/// One impact damper's panel: the observed primary body's amplitude against frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct DamperPanel {
    /// The scene's name.
    pub scene_name: String,
    /// The observed body's name.
    pub observed: String,
    /// `(ω, amplitude)` of the primary alone (the free bodies taken out): its linear steady
    /// state.
    pub alone: Vec<(f64, f64)>,
    /// `(ω, amplitude)` simulated with the free body, sweeping up; periodic motions only.
    pub up: Vec<(f64, f64)>,
    /// The same, sweeping down.
    pub down: Vec<(f64, f64)>,
    /// `(ω, amplitude)` of motions that were not periodic within the run (their last cycle),
    /// both ways.
    pub irregular: Vec<(f64, f64)>,
    /// The viable closed-form symmetric motions (the one-body damper only).
    pub branch: Vec<DamperBranchPoint>,
}

/// The impact dampers' figure: one panel per damper.
#[derive(Debug, Clone, PartialEq)]
pub struct DamperStudy {
    /// The frequencies swept, rad/s.
    pub omega_range: (f64, f64),
    /// The one-body and the two-body damper.
    pub panels: Vec<DamperPanel>,
}

/// The bodies no spring or dashpot ties to anything: the free bodies, which only stops hold.
pub fn free_bodies(structure: &Structure) -> Vec<usize> {
    (0..structure.dofs())
        .filter(|&j| {
            structure.stiffness[(j, j)] == 0.0
                && structure.damping.as_ref().is_none_or(|c| c[(j, j)] == 0.0)
        })
        .collect()
}

/// The amplitude of body `observe` in the linear steady state of `structure` without its
/// free bodies, at `omega`: `(K − ω²M + iωC) U = f_c − i f_s` on the remaining bodies. `None`
/// where that system is singular (an undamped resonance).
pub fn primary_alone(structure: &Structure, omega: f64) -> Option<f64> {
    let free = free_bodies(structure);
    let kept: Vec<usize> = (0..structure.dofs())
        .filter(|j| !free.contains(j))
        .collect();
    let n = kept.len();
    let sin = structure.forcing_sin_at(omega);
    let system = DMatrix::from_fn(n, n, |r, c| {
        let (i, j) = (kept[r], kept[c]);
        let damping = structure.damping.as_ref().map_or(0.0, |d| d[(i, j)]);
        Complex::new(
            structure.stiffness[(i, j)] - omega * omega * structure.mass[(i, j)],
            omega * damping,
        )
    });
    let force = DVector::from_fn(n, |r, _| {
        Complex::new(structure.forcing_cos[kept[r]], -sin[kept[r]])
    });
    let response = system.lu().solve(&force)?;
    let at = kept.iter().position(|&j| j == structure.observe)?;
    Some(response[at].norm()).filter(|a| a.is_finite())
}

/// The closed form of a one-body damper: the primary body 0 on a spring and a dashpot to the
/// frame, forced, with the free body 1 between symmetric stops on it; `None` for any other
/// structure.
pub fn closed_form(structure: &Structure) -> Option<ImpactDamper> {
    let [stop] = structure.stops.as_slice() else {
        return None;
    };
    let single = structure.dofs() == 2
        && free_bodies(structure) == [1]
        && stop.minus == Some(0)
        && stop.plus == Some(1)
        && stop.gap_plus == stop.gap_minus
        && structure.forcing_cos[1] == 0.0
        && structure.forcing_sin[1] == 0.0
        && structure.forcing_sin_per_omega.iter().all(|&f| f == 0.0);
    let restitution = stop.law.restitution()?;
    single.then(|| ImpactDamper {
        mass: structure.mass[(0, 0)],
        damping: structure.damping.as_ref().map_or(0.0, |c| c[(0, 0)]),
        stiffness: structure.stiffness[(0, 0)],
        force: structure.forcing_cos[0].hypot(structure.forcing_sin[0]),
        phase: (-structure.forcing_sin[0]).atan2(structure.forcing_cos[0]),
        free_mass: structure.mass[(1, 1)],
        gap: stop.gap_plus,
        restitution,
    })
}

/// Both dampers' panels: `points` simulated frequencies, `branch_points` for the primary alone
/// and the closed form.
pub fn damper_study(points: usize, branch_points: usize) -> DamperStudy {
    let panels = [IMPACT_DAMPER_SCENE, IMPACT_DAMPER_TWO_MASS_SCENE]
        .iter()
        .map(|text| panel(text, points, branch_points))
        .collect();
    DamperStudy {
        omega_range: DAMPER_RANGE,
        panels,
    }
}

/// One damper's panel.
fn panel(text: &str, points: usize, branch_points: usize) -> DamperPanel {
    let (scene, structure) = gallery_structure(text);
    let fine = Axis::new(DAMPER_RANGE.0, DAMPER_RANGE.1, branch_points).values();
    let alone = fine
        .iter()
        .filter_map(|&omega| primary_alone(&structure, omega).map(|a| (omega, a)))
        .collect();
    let branch = closed_form(&structure).map_or_else(Vec::new, |reference| {
        fine.iter()
            .flat_map(|&omega| {
                reference
                    .symmetric_orbits_sampled(omega, BRANCH_SAMPLES)
                    .unwrap_or_default()
                    .into_iter()
                    .filter(|o| o.viable)
                    .map(move |o| DamperBranchPoint {
                        omega,
                        amplitude: o.primary_amplitude,
                        stable: o.stable,
                    })
            })
            .collect()
    });
    let grid = Axis::new(DAMPER_RANGE.0, DAMPER_RANGE.1, points).values();
    let (up, mut irregular) = sweep(&structure, grid.iter().copied());
    let (down, irregular_down) = sweep(&structure, grid.iter().rev().copied());
    irregular.extend(irregular_down);
    DamperPanel {
        scene_name: scene.name,
        observed: structure.names[structure.observe].clone(),
        alone,
        up,
        down,
        irregular,
        branch,
    }
}

/// The observed body's amplitude at each frequency of `omegas`, each run started from the
/// last one's final state (the first from rest): periodic motions, then the others.
#[allow(clippy::type_complexity)]
fn sweep(
    structure: &Structure,
    omegas: impl Iterator<Item = f64>,
) -> (Vec<(f64, f64)>, Vec<(f64, f64)>) {
    let options = SimulationOptions {
        max_periods: SWEEP_MAX_PERIODS,
        ..SimulationOptions::default()
    };
    let (mut periodic, mut irregular) = (Vec::new(), Vec::new());
    continued_runs(structure, omegas, &options, |point| {
        match point.steady.status {
            Status::Periodic => periodic.push((point.omega, point.outer_amplitude)),
            Status::NoDissipation => {}
            _ => irregular.push((point.omega, point.outer_amplitude)),
        }
    });
    (periodic, irregular)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-body damper has the closed form, the two-body one has not; the primary alone
    /// of the one-body damper is the forced oscillator's `F/√((k − mω²)² + (cω)²)`.
    #[test]
    fn the_gallery_dampers_are_what_they_say() {
        let (_, one) = gallery_structure(IMPACT_DAMPER_SCENE);
        let c = closed_form(&one).expect("a closed form");
        assert_eq!(
            (c.mass, c.free_mass, c.gap, c.restitution),
            (1.0, 0.1, 0.8, 0.6)
        );
        let (_, two) = gallery_structure(IMPACT_DAMPER_TWO_MASS_SCENE);
        assert!(closed_form(&two).is_none());
        assert_eq!(free_bodies(&two), [2]);
        for omega in [0.5f64, 1.0, 1.3] {
            let exact = 0.1 / (1.0 - omega * omega).hypot(0.05 * omega);
            let alone = primary_alone(&one, omega).unwrap();
            assert!((alone - exact).abs() < 1e-14 * exact, "{alone} {exact}");
        }
    }
}
