//! Cost of one analytic frequency point: the linear steady state plus both symmetric branches
//! with viability and Floquet multipliers; and of one member of the β family.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rattle_analytic::test_models::{damped_paper_unit, paper_stops, paper_unit};
use rattle_analytic::{gap_for_beta, linear_response, symmetric_orbits};

fn frequency_point(c: &mut Criterion) {
    let stops = paper_stops();
    for (name, unit) in [("undamped", paper_unit()), ("damped", damped_paper_unit())] {
        c.bench_function(
            &format!("analytic frequency point ({name}, ω = 2.0)"),
            |b| {
                b.iter(|| {
                    let lin = linear_response(&unit, black_box(2.0));
                    let orbits = symmetric_orbits(&unit, &stops, black_box(2.0));
                    (lin, orbits)
                })
            },
        );
    }
    let unit = paper_unit();
    c.bench_function("analytic frequency point (undamped, ω = 0.5)", |b| {
        b.iter(|| symmetric_orbits(&unit, &stops, black_box(0.5)))
    });
    c.bench_function("family member Δ*(β = 0.3)", |b| {
        b.iter(|| gap_for_beta(&unit, 0.8, black_box(2.0), black_box(0.3)))
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = frequency_point
}
criterion_main!(benches);
