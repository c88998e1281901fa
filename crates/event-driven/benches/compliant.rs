//! What a compliant stop's contact costs the event-driven simulator, against its stiffness:
//! the impact oscillator (mass 1 on a spring 1 and a dashpot 0.1 to the frame, forced by
//! `cos 1.2t`, one stop against the frame at `u = 1`) with a compliant stop whose contact law
//! gives the isolated pair the restitution 0.8 ([`Compliance::matching`]), at contact
//! stiffnesses 10 to 1e8 times the structure's spring. The motion is the period-1 orbit with
//! one contact per period, checked before timing; the rigid stop (`e = 0.8`, one impact per
//! period) is the reference row.
//!
//! Each stiffness runs a short and a long stretch from the settled orbit (100 and 400
//! periods): the difference of their medians over the difference of their contacts is the
//! cost per contact (a flight, a contact phase, the entry and the exit), free of the run's
//! fixed part (the flows' set-up, the observed final stretch). The contact phase is an exact
//! modal flow: its cost should not grow with the stiffness, however short the contact.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use nalgebra::{DMatrix, DVector};
use rattle_event_driven::{simulate, Compliance, ContactPair, Model, SimulationOptions, Start};
use std::time::Duration;

/// Forcing frequency: the period-1 orbit with one contact per period.
const OMEGA: f64 = 1.2;

/// The rigid stop's restitution, and the isolated pair's of every compliant stop.
const RESTITUTION: f64 = 0.8;

/// The timed stretches, in periods.
const LENGTHS: [u64; 2] = [100, 400];

/// The impact oscillator, its stop compliant of stiffness `ratio` times the spring's when
/// `Some`.
fn oscillator(ratio: Option<f64>) -> Model {
    let model = Model::new(
        DMatrix::from_element(1, 1, 1.0),
        DMatrix::from_element(1, 1, 1.0),
        Some(DMatrix::from_element(1, 1, 0.1)),
        DVector::from_element(1, 1.0),
        DVector::zeros(1),
        vec![ContactPair {
            plus_dof: Some(0),
            minus_dof: None,
            gap_plus: 1.0,
            gap_minus: f64::INFINITY,
            restitution: RESTITUTION,
        }],
    )
    .expect("a valid oscillator");
    match ratio {
        Some(ratio) => model
            .with_compliance(0, Compliance::matching(ratio, RESTITUTION, 1.0))
            .expect("a valid contact law"),
        None => model,
    }
}

/// A run without polishing: exactly `periods` periods.
fn fixed(periods: u64) -> SimulationOptions {
    SimulationOptions {
        fixed_periods: Some(periods),
        polish: false,
        ..SimulationOptions::default()
    }
}

fn compliant(c: &mut Criterion) {
    let mut group = c.benchmark_group("compliant stop: impact oscillator, ω = 1.2");
    group.sample_size(20);
    group.warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(3));
    let cases = [None, Some(1e1), Some(1e2), Some(1e4), Some(1e6), Some(1e8)];
    for ratio in cases {
        let model = oscillator(ratio);
        let settled = simulate(
            &model,
            OMEGA,
            &Start::rest(1),
            &SimulationOptions::default(),
        )
        .expect("settles");
        assert_eq!(settled.period, Some(1), "a period-1 orbit");
        let events = settled.cycle_contacts.len() + settled.cycle_impacts.len();
        assert_eq!(events, 1, "one contact (or impact) per period");
        let start = settled.final_state.clone();
        let (label, events) = match ratio {
            Some(ratio) => (format!("k_c = {ratio:e} k"), "contacts"),
            None => ("rigid".to_string(), "impacts"),
        };
        for periods in LENGTHS {
            let options = fixed(periods);
            group.throughput(Throughput::Elements(periods));
            group.bench_function(
                format!("{label}, {periods} periods: {periods} {events}"),
                |b| b.iter(|| simulate(&model, black_box(OMEGA), &start, &options)),
            );
        }
    }
    group.finish();
}

criterion_group!(benches, compliant);
criterion_main!(benches);
