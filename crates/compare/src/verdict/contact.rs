//! The seeded check of a cycle with contact phases of compliant stops: the simulator's
//! polished cycle read as an impact sequence whose tokens are rigid impacts and contact phases
//! (`0+c`), the analytic orbit of that sequence solved from the simulated event times (a
//! contact phase's entry and exit each an event), and the two compared event by event.
//!
//! A contact phase has no state jump, so the comparison is of what each solver reports at
//! every event: the event phases (fractions of the cycle) and the base phase at the first, the
//! entry and exit velocities and the largest penetration of every contact, and the compared
//! coordinates' amplitudes; and of the Floquet multipliers, each solver's own.

use super::chain::{
    classify, matched_distance, read_sequence, ChainCheck, ChainReason, CheckModels,
};
use crate::scene::phase;
use crate::scene::simulator::{polished_cycle, PolishedCycle, SimulateError};
use rattle_analytic::{solve_sequence, PairImpact, SequenceOrbit};
use rattle_event_driven::{PeriodicOrbit, SimulationOptions, SteadyState};

/// A polished run's contact is the polished orbit's when their exits lie within this fraction
/// of the cycle: far above the exits' rounding (`1e-15` of the cycle) and far below any two
/// exits of one pair in a cycle (each contact lasts at least `5e-7` of a period, the bound on
/// a contact's rate).
const CONTACT_MATCH: f64 = 1e-9;

/// One token of the simulated cycle: a rigid impact, or a contact phase with its exit time
/// and its record in the polished cycle's contacts.
#[derive(Debug, Clone, Copy)]
struct Token {
    /// The impact's or the entry's absolute time.
    start: f64,
    /// The pair, the side, and whether it is a contact phase.
    impact: PairImpact,
    /// The exit's absolute time and the contact's record, for a contact phase.
    contact: Option<(f64, Option<Seen>)>,
}

/// What the polished cycle's run saw of a contact phase.
#[derive(Debug, Clone, Copy)]
struct Seen {
    /// The contact's record in the polished cycle's contacts.
    record: usize,
    /// Whether the run saw the whole contact: not one through the section, which the run
    /// starts inside of (its entry velocity and its penetration before the section unseen).
    whole: bool,
}

/// The analytic orbit of the polished cycle's sequence of impacts and contact phases on
/// `models`, its differences from the simulated cycle and the class (the rest of the seeded
/// check of [`super::chain`], whose verdicts it shares). The simulator's Newton is not started
/// on the analytic orbit here: a contact cycle's events carry no state to start it from, and
/// the polished orbit already is the simulator's own fixed point.
///
/// # Errors
/// A failure of the simulator.
pub(crate) fn seeded_contacts(
    models: &CheckModels,
    omega: f64,
    orbit: &PeriodicOrbit,
    steady: &SteadyState,
    options: &SimulationOptions,
    check: &mut ChainCheck,
) -> Result<(), SimulateError> {
    let cycle = polished_cycle(&models.event, omega, orbit, options)?;
    let length = f64::from(orbit.periods) * std::f64::consts::TAU / omega;
    // The polished cycle must be the cycle the run settled on: the same impacts and contacts.
    if cycle.impacts.len() != orbit.impact_sides.len()
        || cycle.impacts.len() != steady.cycle_impacts.len()
        || cycle.contacts.len() != orbit.contact_phases.len()
        || cycle.contacts.len() != steady.cycle_contacts.len()
    {
        check.polished = Some(cycle);
        check.beyond(
            ChainReason::NotPolished,
            "the cycle run from the polished state does not repeat the polished impacts and \
             contacts"
                .into(),
        );
        return Ok(());
    }
    let tokens = cycle_tokens(&cycle, orbit, length);
    let impacts: Vec<PairImpact> = tokens.iter().map(|t| t.impact).collect();
    let Some((sequence, rotations)) = read_sequence(&impacts, orbit.periods, check) else {
        check.polished = Some(cycle);
        return Ok(());
    };
    let first = rotations[0];
    let events_from = |k: usize| events_from(&tokens, k, length);
    let ordered = |e: &[f64]| e.windows(2).all(|w| w[0] < w[1]) && e.last() < Some(&1.0);
    if !ordered(&events_from(first)) {
        check.polished = Some(cycle);
        check.beyond(
            ChainReason::OverlappingContacts,
            "an impact or a contact during another contact: a sequence's events follow one \
             another"
                .into(),
        );
        return Ok(());
    }
    let alpha_at = |k: usize| phase::wrap(omega * tokens[k].start);
    let mut guess = vec![alpha_at(first)];
    guess.extend_from_slice(&events_from(first)[1..]);
    check.sequence = Some(sequence.clone());
    let analytic = match solve_sequence(&models.analytic, omega, &sequence, &guess) {
        Ok(o) => o,
        Err(e) => {
            check.analytic_error = Some(e.to_string());
            check.polished = Some(cycle);
            check.contradiction(
                ChainReason::NoAnalyticOrbit,
                format!(
                    "the analytic solver finds no orbit of {sequence} from the simulated event \
                     times: {e}"
                ),
            );
            return Ok(());
        }
    };
    let amplitude = models.amplitude_difference(&cycle.amplitudes, &analytic.amplitudes);
    let contacts_from = |k: usize| contact_difference(&tokens, k, &cycle, &analytic);
    // The analytic orbit starts at one of the equivalent rotations: compare with the closest.
    let difference = rotations
        .iter()
        .map(|&k| {
            let events = events_from(k)
                .iter()
                .zip(&analytic.impact_phases)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            events
                .max(contacts_from(k))
                .max(phase::distance(alpha_at(k), analytic.alpha) / std::f64::consts::PI)
        })
        .fold(f64::INFINITY, f64::min)
        .max(amplitude);
    check.relative_difference = Some(difference);
    check.multiplier_difference = Some(matched_distance(
        &orbit.floquet_multipliers,
        &analytic.floquet_multipliers,
    ));
    classify(check, &sequence, &analytic, difference);
    check.polished = Some(cycle);
    check.analytic = Some(analytic);
    Ok(())
}

/// The polished cycle's tokens in time order from the section: its rigid impacts, and the
/// polished orbit's contact phases (a contact through the section has its exit below its
/// entry), each with what the run from the section saw of it, matched by its exit.
fn cycle_tokens(cycle: &PolishedCycle, orbit: &PeriodicOrbit, length: f64) -> Vec<Token> {
    let since_section = |t: f64| (t - orbit.time).rem_euclid(length);
    let seen = |pair: usize, exit: f64| {
        cycle
            .contacts
            .iter()
            .position(|c| c.pair == pair && (c.exit_time - exit).abs() <= CONTACT_MATCH * length)
            .map(|record| Seen {
                record,
                whole: cycle.contacts[record].entry_time > orbit.time,
            })
    };
    let mut tokens: Vec<Token> = cycle
        .impacts
        .iter()
        .map(|i| Token {
            start: i.time,
            impact: PairImpact::rigid(i.pair, i.side),
            contact: None,
        })
        .chain(orbit.contact_phases.iter().map(|c| {
            let entry = orbit.time + c.entry * length;
            let exit = orbit.time + c.exit * length + if c.exit < c.entry { length } else { 0.0 };
            let exit_in_run = orbit.time + c.exit * length;
            Token {
                start: entry,
                impact: PairImpact::compliant(c.pair, c.side),
                contact: Some((exit, seen(c.pair, exit_in_run))),
            }
        }))
        .collect();
    tokens.sort_by(|a, b| since_section(a.start).total_cmp(&since_section(b.start)));
    tokens
}

/// Every event's time after token `k`'s, as fractions of the cycle `length`, from token `k`
/// on: a contact's entry and exit each an event.
fn events_from(tokens: &[Token], k: usize, length: f64) -> Vec<f64> {
    let n = tokens.len();
    let origin = tokens[k].start;
    let mut out = Vec::with_capacity(2 * n);
    for j in 0..n {
        let token = &tokens[(k + j) % n];
        let start = (token.start - origin).rem_euclid(length);
        out.push(start / length);
        if let Some((exit, _)) = token.contact {
            out.push((start + (exit - token.start)) / length);
        }
    }
    out
}

/// The largest difference of the contacts from token `k` on and the `analytic` orbit's, in
/// order: each contact's entry and exit velocities relative to the fastest entry, its largest
/// penetration relative to the deepest (of a contact through the section, whose entry the
/// run did not see, the exit velocity alone); infinite for a contact the run did not see end.
fn contact_difference(
    tokens: &[Token],
    k: usize,
    cycle: &PolishedCycle,
    analytic: &SequenceOrbit,
) -> f64 {
    let n = tokens.len();
    let fastest = analytic
        .contacts
        .iter()
        .map(|c| c.entry_velocity.abs())
        .fold(f64::MIN_POSITIVE, f64::max);
    let deepest = analytic
        .contacts
        .iter()
        .map(|c| c.max_penetration.abs())
        .fold(f64::MIN_POSITIVE, f64::max);
    (0..n)
        .filter_map(|j| tokens[(k + j) % n].contact.map(|(_, seen)| seen))
        .zip(&analytic.contacts)
        .map(|(seen, a)| match seen {
            None => f64::INFINITY,
            Some(Seen { record, whole }) => {
                let s = &cycle.contacts[record];
                let exit = (s.exit_velocity - a.exit_velocity).abs() / fastest;
                if whole {
                    exit.max((s.entry_velocity - a.entry_velocity).abs() / fastest)
                        .max((s.max_penetration - a.max_penetration).abs() / deepest)
                } else {
                    exit
                }
            }
        })
        .fold(0.0, f64::max)
}
