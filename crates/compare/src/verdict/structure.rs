//! How the two solvers relate at one frequency on a structure scene: the chain's seeded check
//! ([`crate::verdict::chain`]) on each solver's own model of the structure, with every body's
//! amplitude compared, and the linear steady state for a motion without impacts.

use crate::output::finite;
use crate::output::records::{multipliers, ByBody};
use crate::output::structure::{
    signatures, StructureAnalyticRecord, StructureAt, StructureCompareRecord,
    StructureSimulatedRecord,
};
use crate::scene::simulator::{run_structure, SimulateError};
use crate::scene::structure::{Structure, StructureScene};
use crate::verdict::chain::{
    judge, relative_to_largest, seeded_models, ChainCheck, ChainConfirmation, ChainReason,
    CheckModels,
};
use crate::verdict::contact::seeded_contacts;
use rattle_event_driven::SimulationOptions;

/// Both solvers on the motion `structure` settles on from rest at `omega`, classed as a
/// chain's ([`crate::verdict::chain::chain_cross_check`]): the simulator runs from rest and
/// polishes its cycle; the analytic solver solves the cycle's impact sequence of the stops,
/// seeded from the simulated impact times; every body's amplitude, the states and the phases
/// are compared. A periodic motion without impacts is compared with the linear steady state,
/// which must stay clear of every stop.
///
/// # Errors
/// A failure of the simulator.
pub fn structure_cross_check(
    structure: &Structure,
    omega: f64,
    options: &SimulationOptions,
) -> Result<ChainCheck, SimulateError> {
    let options = SimulationOptions {
        polish: true,
        ..*options
    };
    let simulated = run_structure(structure, omega, &structure.rest(), &options)?;
    let check = ChainCheck::new(1, omega, simulated);
    let analytic = structure.analytic_model();
    judge(
        check,
        |check| linear_check(structure, check),
        |check, orbit, steady| match analytic {
            Ok(analytic) => {
                let models = CheckModels {
                    event: structure.event_model(omega)?,
                    analytic,
                    compared: (0..structure.dofs()).collect(),
                    relative_to_largest: true,
                };
                if steady.cycle_contacts.is_empty() {
                    seeded_models(&models, omega, orbit, steady, &options, check)
                } else {
                    seeded_contacts(&models, omega, orbit, steady, &options, check)
                }
            }
            Err(e) => {
                check.contradiction(
                    ChainReason::NoAnalyticOrbit,
                    format!("the analytic solver refuses the structure: {e}"),
                );
                Ok(())
            }
        },
    )
}

/// Whether the linear steady `state` of `model` reaches a stop: the relative coordinate's
/// highest value beyond side 1's distance, or its lowest beyond side 2's (a forcing with
/// harmonics swings further one way than the other).
pub fn linear_reaches_stops(
    model: &rattle_analytic::LinearModel,
    state: &rattle_analytic::HarmonicState,
) -> bool {
    model.pairs().iter().any(|pair| {
        let (low, high) = state.relative_extremes(pair);
        high > pair.gap_side1 || -low > pair.gap_side2
    })
}

/// A periodic motion without impacts beside the structure's linear steady state.
///
/// A floating body's linear motion is a family (its offset is free), so the simulated motion
/// is one member of it: the floating bodies' amplitudes are not compared, and the stops are
/// reached only when no offset of the floating bodies keeps every one of them clear at once
/// (each stop that moves with an offset needs at least its peak-to-peak `2|R|` within its
/// clearance `gap_plus + gap_minus`). Without floating bodies a stop is reached as
/// [`linear_reaches_stops`] tells.
fn linear_check(structure: &Structure, check: &mut ChainCheck) {
    let linear = structure
        .analytic_model()
        .map_err(|e| e.to_string())
        .and_then(|m| {
            m.linear_steady_state(check.omega)
                .map(|state| (m, state))
                .map_err(|e| e.to_string())
        });
    let (model, state) = match linear {
        Ok(pair) => pair,
        Err(e) => {
            return check.contradiction(
                ChainReason::NotLinear,
                format!(
                    "periodic without impacts, but the linear structure has no bounded motion: {e}"
                ),
            )
        }
    };
    let reaches = if structure.has_floating() {
        // One offset of the floating bodies must keep every stop clear at once: the analytic
        // model decides it exactly (and finds such an offset), beyond each stop's own
        // peak-to-peak.
        match model.clear_family(check.omega) {
            Ok(family) => !family.exists,
            Err(e) => {
                return check.contradiction(
                    ChainReason::NotLinear,
                    format!(
                        "periodic without impacts, but the linear structure has no bounded \
                         motion: {e}"
                    ),
                )
            }
        }
    } else {
        linear_reaches_stops(&model, &state)
    };
    let held = |v: &[f64]| -> Vec<f64> {
        v.iter()
            .zip(&structure.floating)
            .filter(|(_, f)| f.is_none())
            .map(|(a, _)| *a)
            .collect()
    };
    let linear_amplitudes: Vec<f64> = state.amplitudes().iter().copied().collect();
    let d = relative_to_largest(
        &held(&check.simulated.steady.amplitudes),
        &held(&linear_amplitudes),
    );
    let words = if structure.has_floating() {
        "the linear steady state (the bodies springs hold; the floating ones may sit anywhere \
         the stops allow)"
    } else {
        "the linear steady state"
    };
    check.decide_linear(d, reaches, words);
}

/// The record of `check` on `structure` (`scene` as written): what `rattle compare --json`
/// prints for a structure.
pub fn record(
    scene: &StructureScene,
    structure: &Structure,
    check: &ChainCheck,
) -> StructureCompareRecord {
    let s = &check.simulated;
    let amplitudes = check
        .polished
        .as_ref()
        .map_or(&s.steady.amplitudes, |p| &p.amplitudes);
    StructureCompareRecord {
        at: StructureAt::new(scene, structure, check.omega),
        simulated: StructureSimulatedRecord {
            status: s.status_name(),
            period: s.steady.period,
            pair_signatures: signatures(s, structure.stops.len()),
            impacts_per_period: finite(s.steady.impacts_per_period),
            contacts_per_period: structure
                .has_compliant_stops()
                .then(|| s.contacts_per_period()),
            contact_time_per_period: structure
                .has_compliant_stops()
                .then_some(s.steady.contact_time_per_period),
            outer_amplitude: amplitudes.get(structure.observe).copied().and_then(finite),
            body_amplitudes: ByBody::new(structure, amplitudes),
            floquet_multipliers: s
                .steady
                .orbit
                .as_ref()
                .map(|o| multipliers(&o.floquet_multipliers)),
        },
        analytic: check
            .analytic
            .as_ref()
            .map(|o| StructureAnalyticRecord::new(structure, o)),
        analytic_error: check.analytic_error.clone(),
        class: check.class.name(),
        reason: check.reason.map(|r| r.name()),
        class_detail: check.class.detail().to_owned(),
        relative_difference: check.relative_difference.and_then(finite),
        multiplier_difference: check.multiplier_difference.and_then(finite),
        confirmation: check.confirmation.as_ref().map(ChainConfirmation::record),
    }
}
