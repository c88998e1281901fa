//! What higher harmonics of the forcing cost the analytic solver: the damped paper unit with
//! its stops (`Δ = 0.5`, `e = 0.8`) as a `LinearModel`, forced by its base motion's
//! fundamental plus 0, 1, 2, 4 and 8 harmonics (orders 2, 3, …, 9), and plus one harmonic of
//! order 16 ([`rattle_analytic::MAX_HARMONIC_ORDER`]), at `ω = 2` on the symmetric `0+ 0-`
//! orbit (one impact on each side per period). Each harmonic adds two phase states to the
//! augmented state (`2n + 2` → `2n + 2 + 2h`), and the highest order sets the multi-start's grid
//! and the pieces of the flights' extremum search.
//!
//! Timed, per forcing:
//! - the cycle equations' residuals and exact Jacobian at the orbit (one Newton step's work);
//! - one orbit solve, Newton from the orbit with `α` off by `1e-3`, verdicts (viability,
//!   amplitudes, Floquet multipliers) included;
//! - the whole multi-start for the sequence (`sequence_orbits`).
//!
//! Each harmonic is a small part of the base motion, `u_g = cos θ + Σ_k a cos kθ` with
//! `a = 0.02` ([`AMPLITUDE`]), through the outer spring and dashpot as the fundamental: the
//! orbit stays viable, checked before timing. The medians and their ratios to the fundamental
//! alone are on the performance page (`docs/performance.md`).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rattle_analytic::test_models::{damped_paper_unit, paper_stops};
use rattle_analytic::{
    sequence_orbits, solve_sequence, Harmonic, ImpactSequence, LinearModel, SequenceProblem,
};
use std::time::Duration;

/// Forcing frequency, rad/s.
const OMEGA: f64 = 2.0;

/// Base-motion amplitude of each harmonic, against the fundamental's 1.
const AMPLITUDE: f64 = 0.02;

/// The forcings compared: a label and the harmonics' orders (empty: the fundamental alone).
fn forcings() -> Vec<(String, Vec<u32>)> {
    let mut cases: Vec<(String, Vec<u32>)> = [0u32, 1, 2, 4, 8]
        .into_iter()
        .map(|count| {
            let label = match count {
                0 => "fundamental alone".to_string(),
                1 => "+1 harmonic (order 2)".to_string(),
                _ => format!("+{count} harmonics (orders 2..={})", count + 1),
            };
            (label, (2..count + 2).collect())
        })
        .collect();
    cases.push(("+1 harmonic (order 16)".to_string(), vec![16]));
    cases
}

/// The paper unit's model with the base motion's harmonics of order `orders` added: each is
/// the fundamental's vectors (`f_c = k_o u_g`, `f_ω = −c_o u_g`, per unit of its own
/// frequency) times [`AMPLITUDE`], phase 0.
fn with_harmonics(unit: &LinearModel, orders: &[u32]) -> LinearModel {
    let mut forcing = unit.forcing().clone();
    forcing.harmonics = orders
        .iter()
        .map(|&order| Harmonic {
            order,
            cosine: &forcing.cosine * AMPLITUDE,
            sine: &forcing.sine * AMPLITUDE,
            sine_per_omega: &forcing.sine_per_omega * AMPLITUDE,
            phase: 0.0,
        })
        .collect();
    LinearModel::new(
        unit.mass().clone(),
        unit.damping().clone(),
        unit.stiffness().clone(),
        forcing,
        unit.pairs().to_vec(),
    )
    .expect("valid harmonics")
}

fn harmonics(c: &mut Criterion) {
    let unit = LinearModel::unit(&damped_paper_unit(), &paper_stops()).expect("a model");
    let sequence = ImpactSequence::parse("0+ 0-", 1).expect("a valid sequence");
    let cases: Vec<(String, LinearModel)> = forcings()
        .into_iter()
        .map(|(label, orders)| (label, with_harmonics(&unit, &orders)))
        .collect();
    // The orbit on each model: the multi-start's viable orbit, the one the timed solve starts
    // next to.
    let orbits: Vec<_> = cases
        .iter()
        .map(|(label, model)| {
            sequence_orbits(model, OMEGA, &sequence)
                .expect("a valid problem")
                .into_iter()
                .find(|orbit| orbit.viable)
                .unwrap_or_else(|| panic!("{label}: a viable 0+ 0- orbit at ω = {OMEGA}"))
        })
        .collect();

    let mut group = c.benchmark_group("harmonics: cycle equations, 0+ 0-, ω = 2");
    for ((label, model), orbit) in cases.iter().zip(&orbits) {
        let problem = SequenceProblem::new(model, OMEGA, &sequence).expect("a valid problem");
        let mut x = vec![orbit.alpha];
        x.extend_from_slice(&orbit.impact_phases[1..]);
        group.bench_function(format!("{label}: residuals and Jacobian"), |b| {
            b.iter(|| problem.equations().evaluate_with(black_box(&x), true))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("harmonics: orbit from a guess, 0+ 0-, ω = 2");
    for ((label, model), orbit) in cases.iter().zip(&orbits) {
        let mut guess = orbit.impact_phases.clone();
        guess[0] = orbit.alpha + 1e-3;
        group.bench_function(format!("{label}: Newton and verdicts"), |b| {
            b.iter(|| solve_sequence(model, black_box(OMEGA), &sequence, &guess))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("harmonics: multi-start, 0+ 0-, ω = 2");
    for (label, model) in &cases {
        group.bench_function(format!("{label}: every orbit"), |b| {
            b.iter(|| sequence_orbits(model, black_box(OMEGA), &sequence))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .without_plots()
        .sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = harmonics
}
criterion_main!(benches);
