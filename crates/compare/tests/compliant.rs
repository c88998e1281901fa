//! Compliant (Kelvin–Voigt) stops through both solvers: every periodic motion with contact
//! phases the simulator settles on is the analytic orbit of its sequence of contacts (`0+c`),
//! in every scene form that takes them; stiff contacts stay in agreement; what cannot be
//! resolved is refused by name.

use rattle_compare::scene::frequency::{FrequencyBounds, FrequencyError};
use rattle_compare::scene::structure::{ContactLaw, Structure};
use rattle_compare::scene::AnyScene;
use rattle_compare::verdict::chain::ChainCheck;
use rattle_compare::verdict::structure::structure_cross_check;
use rattle_event_driven::{Compliance, SimulationOptions};

/// The two solvers' event phases, contact velocities, penetrations and amplitudes agree to
/// the simulator's Newton tolerance (1e-12 relative by default, times its factor) and a few
/// hundred roundings of the events' times: far inside the verdict's own `MATCH_TOLERANCE`.
const STATES: f64 = 1e-9;

/// Each solver's own Floquet multipliers, from its own tangent flow and saltations at every
/// contact entry and exit: a few times [`STATES`], or [`multiplier_tolerance`] for a stiff
/// contact.
const MULTIPLIERS: f64 = 1e-8;

/// The multipliers' tolerance for a contact of rate `contact` (`√(k_c/μ)`, rad/s) on a
/// structure whose fastest rate is 1 rad/s: the simulator finds an event's time to its root
/// tolerance (`1e-12` of the period), and in contact its tangent flow moves on the contact's
/// rate, so the Jacobian's error grows as `root tolerance × ω_c/ω_s`; ten times that, at
/// least [`MULTIPLIERS`]. (At `k_c = 1e8` the simulator's multipliers are `2.2e-8` from the
/// analytic ones, which a central difference of the simulator's own map confirms to `5e-10`.)
fn multiplier_tolerance(contact: f64) -> f64 {
    let root = SimulationOptions::default().root_tolerance;
    MULTIPLIERS.max(10.0 * root * contact)
}

/// The impact oscillator (unit mass, spring and dashpot to the frame, a harmonic force) with a
/// compliant stop at `x = 0.5` of contact stiffness `stiffness` and damping `damping`.
fn oscillator(stiffness: f64, damping: f64) -> String {
    format!(
        r#"{{"name": "compliant-oscillator",
            "structure": {{
              "bodies":   [{{"name": "x", "mass": 1.0}}],
              "springs":  [{{"between": ["frame", "x"], "stiffness": 1.0}}],
              "dashpots": [{{"between": ["frame", "x"], "damping": 0.1}}],
              "stops":    [{{"between": ["frame", "x"], "gap_plus": 0.5,
                             "contact_stiffness": {stiffness:e}, "contact_damping": {damping:e}}}]}},
            "forcing": {{"forces": [{{"on": "x", "amplitude": 1.0, "phase": 0.0}}]}}}}"#
    )
}

fn structure(text: &str) -> Structure {
    match AnyScene::parse(text, "test").expect("the scene is valid") {
        AnyScene::Structure(form) => form.structure,
        AnyScene::Cells(_) => panic!("a scene with compliant stops is a structure"),
    }
}

/// Both solvers at each of `omegas`: every periodic motion with contacts in agreement to
/// [`STATES`] and [`MULTIPLIERS`]; returns how many had contacts.
fn agree_with_contacts(
    structure: &Structure,
    omegas: impl Iterator<Item = f64>,
    multiplier_tolerance: f64,
) -> usize {
    let options = SimulationOptions::default();
    let mut with_contacts = 0;
    for omega in omegas {
        let check: ChainCheck =
            structure_cross_check(structure, omega, &options).expect("the simulator runs");
        let steady = &check.simulated.steady;
        if steady.period.is_none() || steady.cycle_contacts.is_empty() {
            continue;
        }
        if check.class.name() == "beyond" {
            continue;
        }
        with_contacts += 1;
        assert_eq!(
            check.class.name(),
            "agreement",
            "ω = {omega}: {}",
            check.class.detail()
        );
        let difference = check.relative_difference.expect("a difference");
        let multipliers = check
            .multiplier_difference
            .expect("a multiplier difference");
        assert!(difference <= STATES, "ω = {omega}: {difference:e}");
        assert!(
            multipliers <= multiplier_tolerance,
            "ω = {omega}: {multipliers:e}"
        );
        let sequence = check.sequence.expect("a sequence").to_string();
        assert!(sequence.contains('c'), "ω = {omega}: {sequence}");
    }
    with_contacts
}

#[test]
fn the_compliant_oscillator_agrees_at_every_frequency_it_touches() {
    // e = 0.8 matched to the isolated mass at 1000 times the spring's stiffness.
    let law = Compliance::matching(1000.0, 0.8, 1.0);
    let s = structure(&oscillator(law.stiffness, law.damping));
    assert_eq!(
        s.stops[0].law,
        ContactLaw::Compliant {
            stiffness: law.stiffness,
            damping: law.damping
        }
    );
    let touched = agree_with_contacts(
        &s,
        (0..24).map(|j| 0.5 + 0.1 * f64::from(j)),
        multiplier_tolerance(1000f64.sqrt()),
    );
    assert!(touched >= 12, "{touched} motions with contacts");
}

#[test]
fn a_unit_with_compliant_stops_runs_as_a_structure_and_agrees() {
    let text = r#"{"name": "compliant-unit",
        "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
        "base": {"amplitude": 1.0},
        "stops": {"gap": 0.5, "contact_stiffness": 400.0, "contact_damping": 2.0},
        "damping": {"outer": 0.1, "inner": 0.05}}"#;
    let s = structure(text);
    assert_eq!(s.names, ["outer", "inner"]);
    // The contact's rate √(k_c/μ), μ = 2/3 the pair's reduced mass.
    let touched = agree_with_contacts(
        &s,
        [0.5, 0.9, 1.1, 2.6, 2.9, 4.4].into_iter(),
        multiplier_tolerance((400.0f64 * 1.5).sqrt()),
    );
    assert!(touched >= 4, "{touched} motions with contacts");
}

#[test]
fn a_stiff_contact_stays_in_agreement() {
    // 1e8 times the spring's stiffness: a contact rate of 1e4 rad/s, four orders above the
    // structure's and within both solvers' bounds.
    let law = Compliance::matching(1e8, 0.8, 1.0);
    let s = structure(&oscillator(law.stiffness, law.damping));
    let touched = agree_with_contacts(&s, [0.8, 1.2].into_iter(), multiplier_tolerance(1e4));
    assert_eq!(touched, 2);
}

#[test]
fn unresolvable_contacts_are_refused_by_name() {
    let e = AnyScene::parse(&oscillator(1e20, 1.0), "x.json")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(
            "x.json: structure.stops[0].contact_stiffness: 100000000000000000000 is out of range"
        ),
        "{e}"
    );
    // √(k_c/μ) = 1e5 rad/s: the simulator resolves it down to ω = 0.1 rad/s.
    let s = structure(&oscillator(1e10, 1.0));
    let bounds = FrequencyBounds::of_structure(&s);
    assert!(bounds.check("--omega", 0.1).is_ok());
    let refused = bounds.check("--omega", 0.09).unwrap_err();
    assert!(
        matches!(refused, FrequencyError::ContactTooFast { min, .. } if (min - 0.1).abs() < 1e-12),
        "{refused}"
    );
    assert!(refused
        .to_string()
        .starts_with("--omega = 9e-2 is out of range"));
}

#[test]
fn contacts_per_period_count_the_final_stretch_of_a_fixed_run() {
    // The gallery oscillator at 1.2 rad/s touches its stop once a period from the start; 20
    // periods from rest are not yet periodic, so the run's final stretch spans several
    // periods, with a contact in each.
    let s = structure(&oscillator(1000.0, 4.48));
    let fixed = SimulationOptions {
        fixed_periods: Some(20),
        ..SimulationOptions::default()
    };
    let run = rattle_compare::scene::simulator::run_structure(&s, 1.2, &s.rest(), &fixed)
        .expect("the simulator runs");
    assert!(run.steady.cycle_contacts.len() > 1);
    assert_eq!(run.contacts_per_period(), 1.0);
    let settled =
        structure_cross_check(&s, 1.2, &SimulationOptions::default()).expect("the simulator runs");
    assert_eq!(settled.simulated.contacts_per_period(), 1.0);
}
