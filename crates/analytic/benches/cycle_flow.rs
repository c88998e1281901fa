//! Cost of one evaluation of the cycle equations with the exact Jacobian in `(x, ω)` (what
//! continuation's corrector and event location do at every trial point), the paper unit's
//! `++--` cycle at ω = 2.0: every flight's `exp(Â τ)` and its `ω` derivative by Padé (the
//! 6 × 6 and the 12 × 12 doubled matrix) against the unit's modal flow
//! ([`CycleEquations::with_modal_flow`]); and the residuals alone (no derivatives).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use nalgebra::{Matrix6, Vector2, Vector4};
use rattle_analytic::join;
use rattle_analytic::test_models::{paper_stops, paper_unit};
use rattle_analytic::{signature_orbits, CycleEquations, ImpactCondition, Signature};

fn cycle_flow(c: &mut Criterion) {
    let (unit, stops) = (paper_unit(), paper_stops());
    let omega = 2.0;
    let signature = Signature::parse("++--", 1).expect("a valid signature");
    let orbit = signature_orbits(&unit, &stops, omega, &signature)
        .into_iter()
        .next()
        .expect("a ++-- orbit at 2.0");
    let mut g_hat = Matrix6::identity();
    g_hat
        .fixed_view_mut::<2, 2>(2, 2)
        .copy_from(&stops.impact_map(&unit));
    // r = u_i − u_o: the pair's coordinate.
    let contact = join(&Vector4::new(-1.0, 1.0, 0.0, 0.0), &Vector2::zeros());
    let impacts = signature
        .sides()
        .iter()
        .map(|&s| ImpactCondition {
            impact_map: g_hat,
            contact,
            stop: f64::from(s) * stops.gap,
        })
        .collect();
    let pade = CycleEquations::new(
        omega,
        unit.augmented_matrix(omega),
        impacts,
        signature.symmetries(),
        std::f64::consts::TAU / omega,
    );
    let modal = pade.clone().with_modal_flow();
    let mut rate = Matrix6::zeros();
    rate[(4, 5)] = -1.0;
    rate[(5, 4)] = 1.0;
    let mut x = vec![orbit.alpha];
    x.extend_from_slice(&orbit.impact_phases[1..]);
    let mut group = c.benchmark_group("cycle equations (++--, ω = 2.0)");
    for (name, equations) in [("Padé", &pade), ("modal", &modal)] {
        group.bench_function(format!("{name}: residuals and Jacobian in (x, ω)"), |b| {
            b.iter(|| equations.evaluate_in_omega(black_box(&x), &rate))
        });
        group.bench_function(format!("{name}: residuals"), |b| {
            b.iter(|| equations.evaluate_with(black_box(&x), false))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = cycle_flow
}
criterion_main!(benches);
