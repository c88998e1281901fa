//! What higher harmonics of the forcing cost the event-driven simulator: the time of runs of a
//! fixed number of periods from a settled state, for the same structure forced by its
//! fundamental plus 0, 1, 2, 4 and 8 harmonics (orders 2, 3, …, 9), and by the fundamental plus
//! one harmonic of order 16 (the searches step at an eighth of the fastest harmonic's period:
//! this row parts the order's share of the cost from the count's).
//!
//! Each harmonic is a small part of the base motion, `u_g(t) = cos ωt + Σ_k a cos kωt` with
//! `a = 0.02` ([`AMPLITUDE`]), acting through the first cell's outer spring and dashpot as the
//! fundamental does: the motion keeps its kind (the unit's two impacts per period, the chain's
//! impacting steady state), checked before timing. Each forcing runs a short and a long
//! stretch (the difference of their times over the difference of their impacts is the cost per
//! impact, free of the run's fixed part); the benchmark names carry the impacts of one run, and
//! throughput is in impacts per second (`elements/s`) of the whole run.
//!
//! The structures: the lightly damped paper unit with stops `Δ = 0.5`, `e = 0.8` at `ω = 2`
//! (two impacts per period), and an 8-cell chain of the paper's cell with the same stops at
//! `ω = 2`. Runs do not polish the final cycle (no Newton solve at the end). The medians and
//! their ratios to the fundamental alone are on the performance page (`docs/performance.md`).
//!
//! Each structure's forcings with harmonics run twice: as the simulator flies them (the
//! steady-response form, each harmonic's periodic response part of the flow's steady response)
//! and with every flight in the resonance-safe general form (`Model::with_general_form`, the
//! form a flow keeps where a harmonic is resonant with an undamped mode or the structure has
//! free bodies), in groups named `harmonics, general form: …`: what the steady form saves, in
//! the same run.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use nalgebra::DVector;
use rattle_event_driven::test_models::{paper_chain, paper_unit, LIGHT_DAMPING, OUTER_STIFFNESS};
use rattle_event_driven::{simulate, CellStops, Harmonic, Model, SimulationOptions, Start};
use std::time::Duration;

/// Forcing frequency, rad/s: the unit's two-impact orbit.
const OMEGA: f64 = 2.0;

/// Base-motion amplitude of each harmonic, against the fundamental's 1.
const AMPLITUDE: f64 = 0.02;

/// Stops of the unit and of every cell of the chain: gap and restitution.
const GAP: f64 = 0.5;
const RESTITUTION: f64 = 0.8;

/// Cells of the chain (the throughput figure's chain, `benches/chain.rs`).
const CELLS: usize = 8;

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

/// The harmonics of the orders `orders` of the base motion `a cos kωt` (`a` = [`AMPLITUDE`]) on an
/// `n`-DOF structure whose base reaches DOF 0 through the paper's outer spring and dashpot:
/// `f_c,k = k_o a`, `f_s,k = −c_o kω a` on DOF 0, as the fundamental's `k_o u_g`, `−c_o ω u_g`.
fn base_harmonics(n: usize, orders: &[u32]) -> Vec<Harmonic> {
    orders
        .iter()
        .map(|&order| {
            let mut cos = DVector::zeros(n);
            let mut sin = DVector::zeros(n);
            cos[0] = OUTER_STIFFNESS * AMPLITUDE;
            sin[0] = -LIGHT_DAMPING.0 * f64::from(order) * OMEGA * AMPLITUDE;
            Harmonic { order, cos, sin }
        })
        .collect()
}

/// A run without polishing: exactly `periods` periods.
fn fixed(periods: u64) -> SimulationOptions {
    SimulationOptions {
        fixed_periods: Some(periods),
        polish: false,
        ..SimulationOptions::default()
    }
}

/// One timed run: the model, its settled start, the run's options, and the impacts and final
/// stretch of one run (the benchmark's name carries the impacts).
struct Case<'a> {
    model: &'a Model,
    start: &'a Start,
    options: SimulationOptions,
    impacts: u64,
    sticking: bool,
}

impl<'a> Case<'a> {
    /// Runs `periods` from `start` once to count the impacts of the timed run (the simulator is
    /// deterministic: every iteration has as many).
    fn new(model: &'a Model, start: &'a Start, periods: u64) -> Case<'a> {
        let options = fixed(periods);
        let probe = simulate(model, OMEGA, start, &options).expect("runs");
        assert!(probe.impacts > 0, "the motion impacts");
        Case {
            model,
            start,
            options,
            impacts: probe.impacts,
            sticking: probe.sticking,
        }
    }
}

/// Times the runs of each forcing of the structure `build` makes from a list of harmonics:
/// settled over `settle` periods from rest, then a short and a long run (`lengths`, in
/// periods), `samples` samples each. A run's time holds a part that does not grow with its
/// length (the flows' set-up and the observed final stretch), so the cost per impact of a long
/// simulation is the difference of the two medians over the difference of their impacts.
///
/// With `general`, only the forcings with harmonics, each flight in the general form.
fn compare(
    c: &mut Criterion,
    (group_name, general): (&str, bool),
    (settle, lengths, samples): (u64, [u64; 2], usize),
    build: impl Fn(&[u32]) -> Model,
    check: impl Fn(&Case),
) {
    let mut group = c.benchmark_group(group_name);
    group.sample_size(samples);
    for (label, orders) in forcings() {
        if general && orders.is_empty() {
            continue;
        }
        let model = if general {
            build(&orders).with_general_form()
        } else {
            build(&orders)
        };
        let start = simulate(&model, OMEGA, &Start::rest(model.dofs()), &fixed(settle))
            .expect("settles")
            .final_state;
        for periods in lengths {
            let case = Case::new(&model, &start, periods);
            check(&case);
            group.throughput(Throughput::Elements(case.impacts));
            group.bench_function(
                format!(
                    "{label}, {periods} periods: {} impacts{}",
                    case.impacts,
                    if case.sticking { ", sticking" } else { "" }
                ),
                |b| b.iter(|| simulate(case.model, black_box(OMEGA), case.start, &case.options)),
            );
        }
    }
    group.finish();
}

/// The paper unit: 500 and 2000 periods, two impacts in each; in the steady-response form and
/// in the general form.
fn unit(c: &mut Criterion) {
    for name in [
        ("harmonics: paper unit, ω = 2", false),
        ("harmonics, general form: paper unit, ω = 2", true),
    ] {
        compare(
            c,
            name,
            (500, [500, 2000], 20),
            |orders| {
                paper_unit(OMEGA, Some(LIGHT_DAMPING), Some((GAP, RESTITUTION)))
                    .with_harmonics(base_harmonics(2, orders))
                    .expect("valid harmonics")
            },
            // The fundamental alone settles on two impacts per period; the harmonics keep them.
            |case| {
                let periods = case.options.fixed_periods.expect("a fixed run");
                assert_eq!(case.impacts, 2 * periods, "two impacts per period");
                assert!(!case.sticking, "the unit does not stick");
            },
        );
    }
}

/// The 8-cell chain: 50 and 200 periods, some 18 impacts in each; in the steady-response form
/// and in the general form.
fn chain(c: &mut Criterion) {
    let stops = Some(CellStops::symmetric(GAP, RESTITUTION));
    for name in [
        ("harmonics: 8-cell chain, ω = 2", false),
        ("harmonics, general form: 8-cell chain, ω = 2", true),
    ] {
        compare(
            c,
            name,
            // Criterion's fewest samples: a run with 8 harmonics in the general form takes over
            // a second.
            (500, [50, 200], 10),
            |orders| {
                paper_chain(CELLS, OMEGA, Some(LIGHT_DAMPING), stops)
                    .with_harmonics(base_harmonics(2 * CELLS, orders))
                    .expect("valid harmonics")
            },
            // The chain's impacts per run differ a little between forcings: the names carry
            // each run's own count.
            |_| {},
        );
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .without_plots()
        .sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = unit, chain
}
criterion_main!(benches);
