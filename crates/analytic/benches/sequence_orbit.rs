//! Cost of one orbit on the paper unit by the fixed-size signature solver and by the general
//! sequence solver on the unit's `LinearModel` (the same orbit, Newton from the same guess,
//! verdicts included), and of the whole multi-start for `+-` by each path. Throughput is in
//! orbits per second (`elements/s`).

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use rattle_analytic::test_models::{damped_paper_unit, paper_stops};
use rattle_analytic::{
    sequence_orbits, signature_orbits, solve_sequence, solve_signature, ImpactSequence,
    LinearModel, Signature,
};

fn sequence_orbit(c: &mut Criterion) {
    let (unit, stops) = (damped_paper_unit(), paper_stops());
    let model = LinearModel::unit(&unit, &stops).expect("the paper unit is a model");
    let mut group = c.benchmark_group("orbit from a guess");
    group.throughput(Throughput::Elements(1));
    for (text, omega) in [("+-", 2.6), ("++--", 1.5)] {
        let signature = Signature::parse(text, 1).expect("a valid signature");
        let sequence = ImpactSequence::from_signature(&signature);
        let orbit = signature_orbits(&unit, &stops, omega, &signature)
            .into_iter()
            .next()
            .expect("an orbit");
        let mut guess = orbit.impact_phases.clone();
        guess[0] = orbit.alpha + 1e-3;
        group.bench_function(format!("{text} fixed-size, ω = {omega}"), |b| {
            b.iter(|| solve_signature(&unit, &stops, black_box(omega), &signature, &guess))
        });
        group.bench_function(format!("{text} general, ω = {omega}"), |b| {
            b.iter(|| solve_sequence(&model, black_box(omega), &sequence, &guess))
        });
    }
    group.finish();
    let mut group = c.benchmark_group("multi-start +-");
    let signature = Signature::parse("+-", 1).expect("a valid signature");
    let sequence = ImpactSequence::from_signature(&signature);
    group.bench_function("fixed-size, ω = 2.6", |b| {
        b.iter(|| signature_orbits(&unit, &stops, black_box(2.6), &signature))
    });
    group.bench_function("general, ω = 2.6", |b| {
        b.iter(|| sequence_orbits(&model, black_box(2.6), &sequence))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots().sample_size(20);
    targets = sequence_orbit
}
criterion_main!(benches);
