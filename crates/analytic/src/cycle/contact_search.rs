//! Orbits of a sequence with contact phases, found from the rigid orbits they continue.
//!
//! A contact phase lasts about `π/ω_c`, far below any grid spacing of the rigid multi-start
//! once the contact is stiff, so its entry and exit are not scanned on a grid. Instead the
//! orbits of the same sequence on the rigid proxy (every compliant pair rigid with its
//! isolated restitution, [`crate::Compliance::restitution`]) are found by the rigid
//! multi-start ([`crate::sequence_orbits_on_grid`]), and each seeds Newton on the compliant
//! cycle: a contact phase enters at its rigid impact's time and leaves the isolated contact
//! duration later. As the contact stiffens at fixed restitution the compliant orbit tends to
//! the rigid one, so every compliant orbit on a branch that continues a rigid orbit is found;
//! compliant orbits without a rigid counterpart (soft contacts far from the rigid limit) are
//! not.

use crate::model::LinearModel;
use crate::sequence::{ImpactSequence, PairImpact};
use crate::sequence_orbit::{SequenceNewton, SequenceOrbitError, SequenceProblem};
use crate::sequence_search::sequence_orbits_on_grid;
use crate::sequence_verdicts::{ModelVerdicts, SequenceOrbit};

/// Two converged solutions are the same orbit when their base phases and event phases differ
/// by less than this: as the rigid multi-start's deduplication (`DEDUP_TOLERANCE`).
const SAME_ORBIT: f64 = 1e-8;

/// The orbits of `sequence` (with contact phases) on `model` at `omega` seeded from the rigid
/// proxy's orbits on a grid of `grid` intervals, sorted by `α`.
///
/// # Errors
/// As [`SequenceProblem::new`] on the compliant model and [`crate::sequence_orbits_on_grid`]
/// on the proxy.
pub(crate) fn contact_orbits(
    model: &LinearModel,
    omega: f64,
    sequence: &ImpactSequence,
    grid: usize,
) -> Result<Vec<SequenceOrbit>, SequenceOrbitError> {
    let problem = SequenceProblem::new(model, omega, sequence)?;
    let proxy = model.rigid_proxy();
    let rigid_impacts: Vec<PairImpact> = sequence
        .impacts()
        .iter()
        .map(|i| PairImpact::rigid(i.pair, i.side))
        .collect();
    let rigid = ImpactSequence::from_cycle(&rigid_impacts, sequence.period())?;
    let seeds = sequence_orbits_on_grid(&proxy, omega, &rigid, grid)?;
    let verdicts = ModelVerdicts::new(&problem);
    let solver = SequenceNewton::default();
    let equations = problem.equations();
    let mut found: Vec<(Vec<f64>, SequenceOrbit)> = Vec::new();
    for seed in seeds {
        let Some(guess) = seed_guess(model, sequence, &seed, equations.cycle()) else {
            continue;
        };
        let Ok(converged) = solver.solve(equations, &guess) else {
            continue;
        };
        let (alpha, phases) = equations.canonical(&converged.unknowns);
        let same = |key: &Vec<f64>| {
            crate::orbit::wrap(key[0] - alpha).abs() < SAME_ORBIT
                && key[1..]
                    .iter()
                    .zip(&phases[1..])
                    .all(|(a, b)| (a - b).abs() < SAME_ORBIT)
        };
        if found.iter().any(|(key, _)| same(key)) {
            continue;
        }
        if let Ok(orbit) = verdicts.assemble(alpha, &phases, converged.iteration) {
            let mut key = phases;
            key[0] = alpha;
            found.push((key, orbit));
        }
    }
    found.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]));
    Ok(found.into_iter().map(|(_, o)| o).collect())
}

/// The compliant cycle's unknowns `(α, φ₂ …)` from a rigid orbit of the same impacts (both
/// canonical, so impact `j` of one is impact `j` of the other): a rigid impact at its time, a
/// contact phase entering at its impact's time and leaving the isolated contact duration
/// later; `None` when a contact would then reach the next event.
fn seed_guess(
    model: &LinearModel,
    sequence: &ImpactSequence,
    seed: &SequenceOrbit,
    cycle: f64,
) -> Option<Vec<f64>> {
    let impacts = sequence.impacts();
    let mut guess = Vec::with_capacity(2 * impacts.len());
    for (j, impact) in impacts.iter().enumerate() {
        let at = if j == 0 {
            seed.alpha
        } else {
            seed.impact_phases[j]
        };
        guess.push(at);
        if impact.contact {
            let law = model.compliance(impact.pair)?;
            let duration = law.contact_duration(model.reduced_mass(impact.pair));
            let entry = seed.impact_phases[j];
            let next = seed.impact_phases.get(j + 1).copied().unwrap_or(1.0);
            let exit = entry + duration / cycle;
            if !(exit < next) {
                return None;
            }
            guess.push(exit);
        }
    }
    Some(guess)
}
