//! Cost of a boundary curve on the paper unit: the period-doubling curve of the asymmetric
//! `+-` orbits (from the event near ω = 2.87 on the branch of the orbit at 2.9 with its
//! side-2 impact at β ≈ 0.43) followed over the whole gap range `[0.1, 1]`, where it closes
//! on itself, special points located, on one thread. Throughput is reported in curve points
//! per second (`elements/s`); the target is a 200-point curve in at most 1 s.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rattle_analytic::test_models::{paper_stops, paper_unit};
use rattle_analytic::{
    continue_orbit, follow_boundary, signature_orbits, BoundarySettings, BoundaryStart,
    ContinuationSettings, EventKind, Signature, Stops, Unit, UnitError,
};

/// The paper unit with its stops' gap set to `gap`.
fn paper_at_gap(gap: f64) -> Result<(Unit, Stops), UnitError> {
    let stops = Stops {
        gap,
        ..paper_stops()
    };
    stops.validate()?;
    Ok((paper_unit(), stops))
}

fn boundary(c: &mut Criterion) {
    let (unit, stops) = (paper_unit(), paper_stops());
    let signature = Signature::parse("+-", 1).expect("a valid signature");
    let start = signature_orbits(&unit, &stops, 2.9, &signature)
        .into_iter()
        .find(|o| (o.impact_phases[1] - 0.43).abs() < 0.01)
        .expect("the asymmetric orbit at β ≈ 0.43");
    let continuation = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(2.8, 3.0)
    };
    let event = continue_orbit(&unit, &stops, &start, &continuation)
        .expect("continuation runs")
        .events
        .into_iter()
        .find(|e| e.kind == EventKind::PeriodDoubling)
        .expect("a period doubling near 2.87");
    let request = BoundaryStart {
        unit_at: paper_at_gap,
        signature: &start.signature,
        event: &event,
        param: stops.gap,
        at: &[],
    };
    // A step of at most 0.01 puts about 200 points on this closed curve.
    let settings = BoundarySettings {
        max_step: 0.01,
        ..BoundarySettings::new(0.1, 1.0)
    };
    let points = follow_boundary(&request, &settings)
        .expect("the curve is followed")
        .points
        .len();
    let mut group = c.benchmark_group("boundary");
    group.sample_size(20);
    group.throughput(Throughput::Elements(points as u64));
    group.bench_function(
        format!("+- period doubling over the gap, {points} points"),
        |b| b.iter(|| follow_boundary(&request, &settings)),
    );
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = boundary
}
criterion_main!(benches);
