//! Forcing with higher harmonics, against answers known without the harmonics' code: a model
//! forced by its second harmonic alone at `ω` is the single-harmonic model at `2ω` (its orbits
//! of a sequence over one period are the period-2 orbits of that sequence, its continued branch
//! and its boundary those of the latter at twice the frequency), the linear steady state is the
//! sum of each harmonic's response at its own frequency (and the impact oscillator's closed
//! form), and a harmonic of amplitude zero changes no result.

use nalgebra::{Complex, DMatrix, DVector};
use rattle_analytic::test_models::{
    base_forcing, damped_paper_unit, fundamental, impact_oscillator, oscillator_response,
    paper_stops, two_masses_two_pairs, BaseHarmonic,
};
use rattle_analytic::*;

/// Agreement of orbits computed on two models that are the same physical system with
/// different augmented states: both Newton solves stop at `1e-13` of the motion's size, and
/// the flows' exponentials of different matrices round differently; the multipliers of a
/// non-normal monodromy amplify that about a thousandfold.
const SAME_SYSTEM: f64 = 1e-10;

/// Agreement of two continuations of the same branch, as between the continuation and the
/// orbit solver (`tests/continuation_chain.rs`): points to the corrector's fallback acceptance
/// (points near the branch point, where `R_x` is singular, are pinned no better), multipliers
/// to `1e-8` (the eigenvalues of a non-normal monodromy), events located to `1e-12` in `ω`.
const CORRECTOR_AGREEMENT: f64 = CORRECTOR_ACCEPTANCE;
const MULTIPLIER_AGREEMENT: f64 = 1e-8;
const EVENT_AGREEMENT: f64 = 1e-12;

fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// The base motion `a cos(2θ + φ)`, the second harmonic alone.
fn second(amplitude: f64, phase: f64) -> BaseHarmonic {
    BaseHarmonic {
        order: 2,
        amplitude,
        phase,
    }
}

/// Largest distance between two lists of multipliers, each matched to its nearest, relative
/// to its modulus when above 1 (near a vanishing impact a multiplier grows without bound, as
/// the saltation's `1/ṙ⁻`, and its rounding with it).
fn multiplier_distance(a: &[Complex<f64>], b: &[Complex<f64>]) -> f64 {
    a.iter()
        .map(|x| {
            b.iter()
                .map(|y| (x - y).norm())
                .fold(f64::INFINITY, f64::min)
                / x.norm().max(1.0)
        })
        .fold(0.0, f64::max)
}

/// The largest difference between two orbits of the same motion, relative to its size (the
/// largest state entry, at least 1): impact times in seconds (the cycles `cycle_a`,
/// `cycle_b`), the state after the first impact and before every impact, the amplitudes, and
/// the Floquet multipliers (absolute).
fn orbit_difference(a: &SequenceOrbit, cycle_a: f64, b: &SequenceOrbit, cycle_b: f64) -> f64 {
    let scale = a
        .states_before_impacts
        .iter()
        .flatten()
        .chain(&a.state_after_impact)
        .fold(1.0, |m: f64, v| m.max(v.abs()));
    let list = |x: &[f64], y: &[f64]| {
        assert_eq!(x.len(), y.len());
        x.iter()
            .zip(y)
            .fold(0.0, |m: f64, (p, q)| m.max((p - q).abs()))
    };
    let times = a
        .impact_phases
        .iter()
        .zip(&b.impact_phases)
        .fold(0.0, |m: f64, (p, q)| {
            m.max((p * cycle_a - q * cycle_b).abs())
        });
    let states = a
        .states_before_impacts
        .iter()
        .zip(&b.states_before_impacts)
        .fold(
            list(&a.state_after_impact, &b.state_after_impact),
            |m, (x, y)| m.max(list(x, y)),
        );
    let amplitudes = list(&a.amplitudes, &b.amplitudes);
    (times.max(states).max(amplitudes) / scale).max(multiplier_distance(
        &a.floquet_multipliers,
        &b.floquet_multipliers,
    ))
}

/// A model forced by its second harmonic alone (`a cos 2θ`, the fundamental's amplitude zero)
/// at `ω` against the single-harmonic model `a cos θ'` at `Ω = 2ω`, on the impact oscillator
/// (one stop) and on two masses with two pairs: every period-2 orbit of a sequence of the
/// latter is, twice (`α = α'/2` and `α'/2 + π`, the same motion), an orbit of that sequence
/// over one period of the former, with the same impact times in seconds, states, amplitudes
/// and multipliers; and Newton on the harmonic model from the halved `α` lands on it.
#[test]
fn the_second_harmonic_alone_is_the_single_harmonic_at_twice_the_frequency() {
    type Build = fn(&[BaseHarmonic]) -> LinearModel;
    let cases: [(&str, Build, &str, f64, f64); 3] = [
        ("impact oscillator", impact_oscillator, "0+", 0.6, 2.8),
        ("two masses", two_masses_two_pairs, "0+ 0-", 0.3, 1.6),
        ("two masses", two_masses_two_pairs, "0+ 1+", 1.0, 2.4),
    ];
    for (name, build, text, amplitude, big) in cases {
        let single = build(&[fundamental(amplitude)]);
        let harmonic = build(&[second(amplitude, 0.0)]);
        assert_eq!(harmonic.augmented_size(), single.augmented_size() + 2);
        let omega = 0.5 * big;
        let twice = ImpactSequence::parse(text, 2).unwrap();
        let once = ImpactSequence::parse(text, 1).unwrap();
        let (cycle_single, cycle_harmonic) = (
            2.0 * std::f64::consts::TAU / big,
            std::f64::consts::TAU / omega,
        );
        let reference = sequence_orbits(&single, big, &twice).unwrap();
        let found = sequence_orbits(&harmonic, omega, &once).unwrap();
        assert!(!reference.is_empty(), "{name} {text}: no orbit to compare");
        assert_eq!(
            found.len(),
            2 * reference.len(),
            "{name} {text}: each orbit twice"
        );
        let mut worst: f64 = 0.0;
        for o in &reference {
            for shift in [0.0, std::f64::consts::PI] {
                let alpha = wrap(0.5 * o.alpha + shift);
                let twin = found
                    .iter()
                    .find(|h| wrap(h.alpha - alpha).abs() < 1e-6)
                    .unwrap_or_else(|| panic!("{name} {text}: no orbit at α = {alpha}"));
                assert_eq!(twin.viable, o.viable, "{name} {text}");
                worst = worst.max(wrap(twin.alpha - alpha).abs());
                worst = worst.max(orbit_difference(o, cycle_single, twin, cycle_harmonic));
            }
            let mut guess = o.impact_phases.clone();
            guess[0] = 0.5 * o.alpha + 1e-3;
            let solved = solve_sequence(&harmonic, omega, &once, &guess).unwrap();
            worst = worst.max(orbit_difference(o, cycle_single, &solved, cycle_harmonic));
        }
        println!(
            "{name} {text} at ω = {omega}: {} orbits, largest difference {worst:.1e}",
            reference.len()
        );
        assert!(worst <= SAME_SYSTEM, "{name} {text}: {worst:e}");
    }
}

/// Continuation in `ω` of the second harmonic alone follows the single-harmonic branch at
/// twice the frequency: every point of the branch of `0+ 0-` (one period) of the harmonic
/// model at `ω` is the period-2 orbit of the single-harmonic model at `2ω` (Newton from
/// `α' = 2α`), to the corrector's agreement, and the two runs find the same events at
/// frequencies in the ratio 2 (each located to `1e-12`).
#[test]
fn continuing_the_second_harmonic_alone_follows_the_branch_at_twice_the_frequency() {
    let (amplitude, big) = (0.3, 1.6);
    let single = two_masses_two_pairs(&[fundamental(amplitude)]);
    let harmonic = two_masses_two_pairs(&[second(amplitude, 0.0)]);
    let twice = ImpactSequence::parse("0+ 0-", 2).unwrap();
    let once = ImpactSequence::parse("0+ 0-", 1).unwrap();
    let start = sequence_orbits(&single, big, &twice)
        .unwrap()
        .into_iter()
        .find(|o| o.viable)
        .expect("a viable period-2 orbit");
    let mut guess = start.impact_phases.clone();
    guess[0] = 0.5 * start.alpha;
    let half = solve_sequence(&harmonic, 0.5 * big, &once, &guess).unwrap();
    let settings = |lo: f64, hi: f64| ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(lo, hi)
    };
    let reference = continue_sequence(&single, &start, &settings(1.4, 1.8)).unwrap();
    let followed = continue_sequence(&harmonic, &half, &settings(0.7, 0.9)).unwrap();
    let points = &followed.branches[0].points;
    let (mut unknowns, mut multipliers): (f64, f64) = (0.0, 0.0);
    for p in points {
        if near_branch_point(&followed, p.omega) {
            continue;
        }
        let mut guess = p.impact_phases.clone();
        guess[0] = 2.0 * p.alpha;
        let o = solve_sequence(&single, 2.0 * p.omega, &twice, &guess).unwrap();
        let scale = o
            .state_after_impact
            .iter()
            .fold(1.0, |m: f64, v| m.max(v.abs()));
        unknowns = unknowns.max(wrap(o.alpha - 2.0 * p.alpha).abs());
        for (a, b) in o.impact_phases.iter().zip(&p.impact_phases) {
            unknowns = unknowns.max((a - b).abs());
        }
        unknowns = unknowns.max((o.outer_amplitude - p.outer_amplitude).abs() / scale);
        multipliers = multipliers.max(multiplier_distance(
            &o.floquet_multipliers,
            &p.floquet_multipliers,
        ));
    }
    let kinds = |c: &Continuation<ImpactSequence>| -> Vec<(EventKind, f64)> {
        c.events.iter().map(|e| (e.kind, e.omega)).collect()
    };
    let (a, b) = (kinds(&reference), kinds(&followed));
    assert_eq!(a.len(), b.len(), "{a:?} against {b:?}");
    let mut events: f64 = 0.0;
    for ((ka, wa), (kb, wb)) in a.iter().zip(&b) {
        assert_eq!(ka, kb);
        events = events.max((wa - 2.0 * wb).abs());
    }
    println!(
        "{} points: unknowns within {unknowns:.1e}, multipliers {multipliers:.1e}; {} events \
         within {events:.1e}",
        points.len(),
        a.len()
    );
    assert!(points.len() > 10);
    assert!(unknowns <= CORRECTOR_AGREEMENT, "{unknowns:e}");
    assert!(multipliers <= MULTIPLIER_AGREEMENT, "{multipliers:e}");
    assert!(events <= 2.0 * EVENT_AGREEMENT, "{events:e}");
}

/// `model` with pair 0's restitution set to `restitution`.
fn with_restitution(model: &LinearModel, restitution: f64) -> Result<LinearModel, ModelError> {
    let mut pairs = model.pairs().to_vec();
    pairs[0].restitution = restitution;
    LinearModel::new(
        model.mass().clone(),
        model.damping().clone(),
        model.stiffness().clone(),
        model.forcing().clone(),
        pairs,
    )
}

/// The period-doubling boundary in `(ω, e)` (`e` pair 0's restitution) of `0+ 0-` on the
/// second harmonic alone is the single-harmonic model's at twice the frequency: the curves'
/// `ω` solved at the same restitutions agree in the ratio 2 to the boundary's own agreement
/// with the solver (`1e-10`, as `tests/boundary_chain.rs`).
#[test]
fn the_second_harmonic_alones_boundary_is_at_half_the_frequency() {
    let (amplitude, big) = (0.3, 1.6);
    let single = two_masses_two_pairs(&[fundamental(amplitude)]);
    let harmonic = two_masses_two_pairs(&[second(amplitude, 0.0)]);
    let twice = ImpactSequence::parse("0+ 0-", 2).unwrap();
    let once = ImpactSequence::parse("0+ 0-", 1).unwrap();
    let start = sequence_orbits(&single, big, &twice)
        .unwrap()
        .into_iter()
        .find(|o| o.viable)
        .expect("a viable period-2 orbit");
    let mut guess = start.impact_phases.clone();
    guess[0] = 0.5 * start.alpha;
    let half = solve_sequence(&harmonic, 0.5 * big, &once, &guess).unwrap();
    let doubling = |model: &LinearModel, start: &SequenceOrbit, lo: f64, hi: f64| {
        let settings = ContinuationSettings {
            follow_switches: false,
            ..ContinuationSettings::new(lo, hi)
        };
        continue_sequence(model, start, &settings)
            .unwrap()
            .events
            .into_iter()
            .filter(|e| e.kind == EventKind::PeriodDoubling && e.branch == 0)
            .min_by(|a, b| {
                (a.omega - start.omega)
                    .abs()
                    .total_cmp(&(b.omega - start.omega).abs())
            })
            .expect("a period doubling on the branch")
    };
    let reference_event = doubling(&single, &start, 1.5, 1.65);
    let event = doubling(&harmonic, &half, 0.75, 0.825);
    assert!((reference_event.omega - 2.0 * event.omega).abs() < 1e-12);
    let restitution = harmonic.pairs()[0].restitution;
    let at = [0.66, 0.68, 0.72];
    let settings = BoundarySettings::new(0.65, 0.74);
    let reference = follow_sequence_boundary(
        &SequenceBoundaryStart {
            model_at: |e: f64| with_restitution(&single, e),
            sequence: &twice,
            event: &reference_event,
            param: restitution,
            at: &at,
        },
        &settings,
    )
    .unwrap();
    let followed = follow_sequence_boundary(
        &SequenceBoundaryStart {
            model_at: |e: f64| with_restitution(&harmonic, e),
            sequence: &once,
            event: &event,
            param: restitution,
            at: &at,
        },
        &settings,
    )
    .unwrap();
    assert_eq!(followed.at.len(), at.len(), "{:?}", followed.at);
    assert_eq!(reference.at.len(), at.len(), "{:?}", reference.at);
    let mut worst: f64 = 0.0;
    for (a, b) in reference.at.iter().zip(&followed.at) {
        assert_eq!(a.param_value, b.param_value);
        worst = worst.max((a.omega - 2.0 * b.omega).abs());
    }
    println!(
        "boundary: {} and {} points, ω at {at:?} in the ratio 2 within {worst:.1e}",
        reference.points.len(),
        followed.points.len()
    );
    assert!(worst <= 1e-10, "{worst:e}");
}

/// Whether `omega` lies within `1e-3` of a branch point or fold of `c`, where the
/// fixed-frequency Jacobian is singular and Newton at fixed `ω` pins the unknowns only to
/// about `tolerance / σ_min` (as `tests/continuation_chain.rs` treats them).
fn near_branch_point<L>(c: &Continuation<L>, omega: f64) -> bool {
    c.events.iter().any(|e| {
        matches!(e.kind, EventKind::BranchPoint | EventKind::Fold) && (e.omega - omega).abs() < 1e-3
    })
}

/// The linear steady state of two masses driven by `0.8 cos θ + 0.3 cos(2θ + 0.5)` equals, at
/// every time, the sum of the single-harmonic responses to `0.8 cos θ` at `ω` and to
/// `0.3 cos θ'` at `2ω` (with `θ' = 2θ + 0.5`), to rounding; and the impact oscillator's
/// equals its closed form ([`oscillator_response`]).
#[test]
fn the_linear_steady_state_is_the_sum_of_the_harmonics_responses() {
    let base = [fundamental(0.8), second(0.3, 0.5)];
    let both = two_masses_two_pairs(&base);
    let first = two_masses_two_pairs(&[fundamental(0.8)]);
    let other = two_masses_two_pairs(&[fundamental(0.3)]);
    let mut worst: f64 = 0.0;
    for omega in [0.4, 0.9, 1.3, 2.1] {
        let state = both.linear_steady_state(omega).unwrap();
        let a = first.linear_steady_state(omega).unwrap();
        let b = other.linear_steady_state(2.0 * omega).unwrap();
        assert_eq!(state.harmonics.len(), 1);
        let scale = a.amplitudes().amax() + b.amplitudes().amax();
        for i in 0..200 {
            let theta = std::f64::consts::TAU * f64::from(i) / 200.0;
            let sum = a.displacements(theta) + b.displacements(2.0 * theta + 0.5);
            let error = (state.displacements(theta) - sum).amax() / scale;
            worst = worst.max(error);
        }
    }
    println!("two masses: superposition within {worst:.1e} of the amplitude");
    assert!(worst <= 8.0 * f64::EPSILON, "{worst:e}");

    let base = [
        fundamental(0.9),
        second(0.3, 0.5),
        BaseHarmonic {
            order: 3,
            amplitude: 0.1,
            phase: -1.2,
        },
    ];
    let model = impact_oscillator(&base);
    let mut worst: f64 = 0.0;
    for omega in [0.3, 0.7, 1.1, 1.9] {
        let state = model.linear_steady_state(omega).unwrap();
        let scale = state.amplitudes().amax();
        for i in 0..200 {
            let t = std::f64::consts::TAU / omega * f64::from(i) / 200.0;
            let exact = oscillator_response(&base, omega, t);
            worst = worst.max((state.displacements(omega * t)[0] - exact).abs() / scale);
        }
    }
    println!("impact oscillator: closed form within {worst:.1e} of the amplitude");
    assert!(worst <= 32.0 * f64::EPSILON, "{worst:e}");
}

/// The amplitude and the extremes of the relative coordinate of a steady state with harmonics
/// against a fine scan of its displacements: the polished extremes lie within the scan's own
/// error (`h²/8 · max|r''|`) beyond it, never inside it; and `clear_family` decides each side
/// of a one-sided stop by its own extreme.
#[test]
fn extremes_of_a_steady_state_with_harmonics() {
    let base = [fundamental(0.8), second(0.3, 0.5)];
    let model = two_masses_two_pairs(&base);
    let omega = 0.9;
    let state = model.linear_steady_state(omega).unwrap();
    let fine = 200_000;
    let samples: Vec<DVector<f64>> = (0..fine)
        .map(|i| state.displacements(std::f64::consts::TAU * f64::from(i) / f64::from(fine)))
        .collect();
    for (p, pair) in model.pairs().iter().enumerate() {
        let (low, high) = state.relative_extremes(pair);
        let r: Vec<f64> = samples.iter().map(|u| pair.relative(u)).collect();
        let (l, h) = r
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                (l.min(*v), h.max(*v))
            });
        let slack = 1e-9 * (h - l);
        assert!(
            high >= h - 1e-15 && high - h <= slack,
            "pair {p}: {high} vs {h}"
        );
        assert!(
            low <= l + 1e-15 && l - low <= slack,
            "pair {p}: {low} vs {l}"
        );
        assert!(
            high + low != 0.0,
            "pair {p}: the harmonic makes it asymmetric"
        );
        assert_eq!(state.relative_amplitude(pair), high.max(-low));
    }
    let amplitudes = state.amplitudes();
    for k in 0..2 {
        let scan = samples.iter().fold(0.0, |m: f64, u| m.max(u[k].abs()));
        assert!(amplitudes[k] >= scan - 1e-15 && amplitudes[k] - scan <= 1e-9 * scan);
    }
    let family = model.clear_family(omega).unwrap();
    let clear = model.pairs().iter().all(|pair| {
        let (low, high) = state.relative_extremes(pair);
        high <= pair.gap_side1 && -low <= pair.gap_side2
    });
    assert_eq!(family.exists, clear);
}

/// The two-cell chain of damped paper cells with a harmonic of amplitude zero (order 3, phase
/// 0.7) added to its forcing: its augmented state is larger, but every orbit of the
/// multi-start, its multipliers and energy, the linear steady state and the continued branch
/// are the chain's to rounding.
#[test]
fn a_harmonic_of_amplitude_zero_changes_no_result() {
    let chain = LinearModel::chain(&damped_paper_unit(), &paper_stops(), 2).unwrap();
    let mut forcing = chain.forcing().clone();
    forcing.harmonics.push(Harmonic {
        order: 3,
        cosine: DVector::zeros(4),
        sine: DVector::zeros(4),
        sine_per_omega: DVector::zeros(4),
        phase: 0.7,
    });
    let silent = LinearModel::new(
        chain.mass().clone(),
        chain.damping().clone(),
        chain.stiffness().clone(),
        forcing,
        chain.pairs().to_vec(),
    )
    .unwrap();
    assert_eq!(silent.augmented_size(), chain.augmented_size() + 2);

    let omega = 3.3;
    let a = chain.linear_steady_state(omega).unwrap();
    let b = silent.linear_steady_state(omega).unwrap();
    assert_eq!(a.amplitudes(), b.amplitudes());
    assert_eq!(
        a.relative_amplitude(&chain.pairs()[0]),
        b.relative_amplitude(&chain.pairs()[0])
    );

    let sequence = ImpactSequence::parse("0+ 1- 0- 1+", 1).unwrap();
    let cycle = std::f64::consts::TAU / omega;
    let plain = sequence_orbits(&chain, omega, &sequence).unwrap();
    let with = sequence_orbits(&silent, omega, &sequence).unwrap();
    assert!(!plain.is_empty());
    assert_eq!(plain.len(), with.len());
    let mut worst: f64 = 0.0;
    for (o, h) in plain.iter().zip(&with) {
        worst = worst.max(wrap(o.alpha - h.alpha).abs());
        worst = worst.max(orbit_difference(o, cycle, h, cycle));
        let energy = |e: &EnergyBalance| [e.forcing_work, e.dashpot_dissipation, e.impact_losses];
        for (x, y) in energy(&o.energy).iter().zip(energy(&h.energy)) {
            worst = worst.max((x - y).abs() / x.abs().max(1e-300));
        }
        assert_eq!(o.viable, h.viable);
    }
    println!("{} orbits: largest difference {worst:.1e}", plain.len());
    assert!(worst <= SAME_SYSTEM, "{worst:e}");

    let start = plain.iter().find(|o| o.viable).expect("a viable orbit");
    let settings = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(3.1, 3.5)
    };
    let plain = continue_sequence(&chain, start, &settings).unwrap();
    let start = with
        .iter()
        .find(|h| wrap(h.alpha - start.alpha).abs() < 1e-8)
        .expect("the same start");
    let with = continue_sequence(&silent, start, &settings).unwrap();
    let (p, w) = (&plain.branches[0].points, &with.branches[0].points);
    assert_eq!(p.len(), w.len(), "the same steps");
    let (mut unknowns, mut multipliers, mut events): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for (x, y) in p.iter().zip(w) {
        let pairs = [(x.omega, y.omega), (0.0, wrap(x.alpha - y.alpha))]
            .into_iter()
            .chain(
                x.impact_phases
                    .iter()
                    .copied()
                    .zip(y.impact_phases.iter().copied()),
            );
        for (u, v) in pairs {
            unknowns = unknowns.max((u - v).abs());
        }
        let amplitude = (x.outer_amplitude - y.outer_amplitude).abs() / x.outer_amplitude;
        unknowns = unknowns.max(amplitude);
        multipliers = multipliers.max(multiplier_distance(
            &x.floquet_multipliers,
            &y.floquet_multipliers,
        ));
    }
    assert_eq!(plain.events.len(), with.events.len());
    for (x, y) in plain.events.iter().zip(&with.events) {
        assert_eq!(x.kind, y.kind);
        events = events.max((x.omega - y.omega).abs());
    }
    println!(
        "continuation: {} points, unknowns and amplitudes within {unknowns:.1e}, multipliers \
         {multipliers:.1e}, {} events {events:.1e}",
        p.len(),
        plain.events.len()
    );
    assert!(unknowns <= CORRECTOR_AGREEMENT, "{unknowns:e}");
    assert!(multipliers <= MULTIPLIER_AGREEMENT, "{multipliers:e}");
    assert!(events <= EVENT_AGREEMENT, "{events:e}");
}

/// `dÂ/dω` of a model with harmonics (phases and dashpots included) is the exact derivative
/// of `Â`: `Â` is affine in `ω`, so a central difference agrees to rounding.
#[test]
fn the_augmented_rate_is_the_derivative_of_the_augmented_matrix() {
    let base = [
        fundamental(0.8),
        second(0.3, 0.5),
        BaseHarmonic {
            order: 5,
            amplitude: 0.2,
            phase: 2.0,
        },
    ];
    let model = two_masses_two_pairs(&base);
    let (omega, step) = (1.3, 0.25);
    let quotient = (model.augmented_matrix(omega + step) - model.augmented_matrix(omega - step))
        / (2.0 * step);
    let rate = model.augmented_rate();
    assert_eq!(rate.shape(), (10, 10));
    let error = (quotient - &rate).amax() / rate.amax();
    assert!(error <= 16.0 * f64::EPSILON, "{error:e}");
    // The rotation blocks turn at kω.
    assert_eq!(model.augmented_matrix(omega)[(9, 8)], 5.0 * omega);
    assert_eq!(rate[(7, 6)], 2.0);
}

fn field_of(result: Result<LinearModel, ModelError>) -> String {
    match result {
        Err(ModelError::OutOfRange { field, .. })
        | Err(ModelError::Dimension { field, .. })
        | Err(ModelError::Structure { field, .. }) => field,
        other => panic!("expected a refused model, got {other:?}"),
    }
}

/// Harmonics of an order below 2 or above [`MAX_HARMONIC_ORDER`], a repeated order, vectors of
/// the wrong length or with a non-finite entry, and a non-finite phase are refused, the field
/// named; a good one is accepted.
#[test]
fn bad_harmonics_are_refused_with_the_field_named() {
    let one = |v: f64| DMatrix::from_element(1, 1, v);
    let good = Harmonic {
        order: 2,
        cosine: DVector::from_element(1, 0.3),
        sine: DVector::zeros(1),
        sine_per_omega: DVector::from_element(1, -0.01),
        phase: 0.5,
    };
    let build = |harmonics: Vec<Harmonic>| {
        let mut forcing = base_forcing(1, 0, 1.0, 0.05, &[fundamental(1.0)]);
        forcing.harmonics = harmonics;
        LinearModel::new(one(1.0), one(0.05), one(1.0), forcing, Vec::new())
    };
    assert!(build(vec![good.clone()]).is_ok());
    let cases: Vec<(Vec<Harmonic>, &str)> = vec![
        (
            vec![Harmonic {
                order: 1,
                ..good.clone()
            }],
            "forcing.harmonics[0].order",
        ),
        (
            vec![Harmonic {
                order: 0,
                ..good.clone()
            }],
            "forcing.harmonics[0].order",
        ),
        (
            vec![Harmonic {
                order: MAX_HARMONIC_ORDER + 1,
                ..good.clone()
            }],
            "forcing.harmonics[0].order",
        ),
        (
            vec![
                good.clone(),
                Harmonic {
                    order: 3,
                    ..good.clone()
                },
                good.clone(),
            ],
            "forcing.harmonics[2].order",
        ),
        (
            vec![Harmonic {
                cosine: DVector::zeros(2),
                ..good.clone()
            }],
            "forcing.harmonics[0].cosine",
        ),
        (
            vec![Harmonic {
                sine: DVector::from_element(1, f64::NAN),
                ..good.clone()
            }],
            "forcing.harmonics[0].sine[0]",
        ),
        (
            vec![Harmonic {
                sine_per_omega: DVector::from_element(1, f64::INFINITY),
                ..good.clone()
            }],
            "forcing.harmonics[0].sine_per_omega[0]",
        ),
        (
            vec![Harmonic {
                phase: f64::NAN,
                ..good.clone()
            }],
            "forcing.harmonics[0].phase",
        ),
    ];
    for (harmonics, name) in cases {
        let refused = build(harmonics);
        let message = refused.as_ref().map_err(ToString::to_string).err();
        assert_eq!(field_of(refused), name);
        let message = message.unwrap_or_default();
        assert!(message.contains(name), "{message}");
        if name.ends_with("order") {
            assert!(message.contains("from 2 to 16"), "{message}");
        }
    }
}

/// A harmonic at an undamped resonance (`kω = ω_n`) has no bounded steady state, reported with
/// its order; a harmonic of amplitude zero there is no obstacle.
#[test]
fn a_harmonic_at_resonance_is_unbounded() {
    let one = |v: f64| DMatrix::from_element(1, 1, v);
    let model = |amplitude: f64| {
        let base = [fundamental(1.0), second(amplitude, 0.0)];
        let forcing = base_forcing(1, 0, 1.0, 0.0, &base);
        LinearModel::new(one(1.0), one(0.0), one(1.0), forcing, Vec::new()).unwrap()
    };
    assert_eq!(
        model(0.3).linear_steady_state(0.5),
        Err(ModelError::Unbounded {
            omega: 0.5,
            order: 2
        })
    );
    assert!(model(0.0).linear_steady_state(0.5).is_ok());
}
