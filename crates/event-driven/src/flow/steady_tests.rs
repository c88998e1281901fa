//! Tests of the steady-response form with higher harmonics: its flights against the general
//! form's (the same motion to rounding), and its joint summaries, joint expansions, states,
//! modal coordinates and carries bit for bit what the one-functional and one-mode paths give,
//! as without harmonics.

use super::*;
use crate::expsum::ExpSum;

/// The free flow of a lightly damped chain of `cells` of the paper's cell forced at `ω = 2`
/// with harmonics of the orders `orders` (on the first outer and inner masses), its pairs'
/// relative displacements, and a start state away from rest.
fn harmonic_chain_flow(
    cells: usize,
    orders: &[u32],
) -> (LinearFlow, Vec<Functional>, DVector<f64>) {
    use crate::test_models::{paper_chain, LIGHT_DAMPING};
    use crate::{CellStops, Harmonic};
    let omega = 2.0;
    let n = 2 * cells;
    let harmonics = orders
        .iter()
        .map(|&order| {
            let k = f64::from(order);
            let mut cos = DVector::zeros(n);
            let mut sin = DVector::zeros(n);
            cos[0] = 0.3 / k;
            sin[0] = -0.1 * k;
            cos[1] = 0.05;
            Harmonic { order, cos, sin }
        })
        .collect();
    let model = paper_chain(
        cells,
        omega,
        Some(LIGHT_DAMPING),
        Some(CellStops::symmetric(0.5, 0.8)),
    )
    .with_harmonics(harmonics)
    .expect("valid harmonics");
    let flow = LinearFlow::of_model(&model, omega).expect("flow");
    assert!(
        flow.has_steady_response(),
        "{cells} cells, orders {orders:?}"
    );
    let functionals = model
        .contacts
        .iter()
        .map(|c| {
            let mut position = DVector::zeros(2 * n);
            position.rows_mut(0, n).copy_from(&c.direction(n));
            flow.functional(&position)
        })
        .collect();
    let y = DVector::from_fn(2 * n, |i, _| 0.3 * (1.7 * i as f64 + 0.4).sin());
    (flow, functionals, y)
}

/// `e^{μ s}` of a steady-form expansion's terms, in its order: the kept modes, the forcing,
/// each harmonic.
fn steady_exponentials(flow: &LinearFlow, s: f64) -> Vec<C64> {
    flow.kept
        .iter()
        .map(|&(k, _)| cexp(flow.rates[k], s))
        .chain([cexp(C64::new(0.0, flow.omega), s)])
        .chain(
            flow.harmonics
                .iter()
                .map(|h| cexp(C64::new(0.0, h.rate), s)),
        )
        .collect()
}

#[test]
fn steady_flights_with_harmonics_are_the_general_forms() {
    for cells in [1, 3] {
        for orders in [&[2][..], &[2, 3, 5]] {
            let (flow, _, y) = harmonic_chain_flow(cells, orders);
            let general = flow.clone().without_steady_response();
            let n = 2 * cells;
            for t0 in [0.0, 0.7, 2.3] {
                let (a, b) = (flow.flight(&y, t0), general.flight(&y, t0));
                for s in [0.0, 0.3, 1.1, 2.9] {
                    let (ya, yb) = (a.state(s), b.state(s));
                    let error = (&ya - &yb).amax();
                    assert!(
                        error <= 1e-13 * yb.amax(),
                        "{cells} cells, s = {s}: {error:e}"
                    );
                }
                for i in 0..n {
                    let mut c = DVector::zeros(2 * n);
                    c[i] = 1.0;
                    c[n + (i + 1) % n] = -0.5;
                    let (mut ea, mut eb) = (ExpSum::default(), ExpSum::default());
                    a.expand(&flow.functional(&c), &mut ea);
                    b.expand(&general.functional(&c), &mut eb);
                    // One term per kept mode, one for the forcing and one per harmonic.
                    assert_eq!(ea.terms.len(), flow.kept.len() + 1 + orders.len());
                    for s in [0.0, 0.4, 1.7] {
                        let (va, vb) = (ea.eval(s).0, eb.eval(s).0);
                        assert!((va - vb).abs() <= 1e-13 * (1.0 + vb.abs()), "{va} vs {vb}");
                    }
                }
            }
        }
    }
}

#[test]
fn joint_summaries_and_expansions_with_harmonics_are_the_single_ones_bit_for_bit() {
    for cells in [2, 3, 8] {
        let (flow, functionals, y) = harmonic_chain_flow(cells, &[2, 3]);
        let refs: Vec<&Functional> = functionals.iter().collect();
        let joint = flow.joint_weights(&refs);
        let earlier = flow.flight(&y, 0.7);
        let later = flow.flight(&y.map(|v| 1.3 * v - 0.1), 2.9);
        let (mut modes, mut coefficients, mut sums) = (Vec::new(), Vec::new(), Vec::new());
        let scratch = (&mut modes, &mut coefficients);
        assert!(later.summarize_all(&joint, 2.5, scratch, &mut sums));
        assert_eq!(sums.len(), cells);
        for (slot, functional) in functionals.iter().enumerate() {
            let single = later.summarize(functional, 2.5).expect("summary");
            assert_eq!(
                format!("{:?}", sums[slot]),
                format!("{single:?}"),
                "{cells} cells"
            );
            let mut again = ExpSum::default();
            earlier.expand(functional, &mut again);
            later.expand_joint(functional, (&coefficients, slot), &mut again);
            let mut fresh = ExpSum::default();
            later.expand(functional, &mut fresh);
            assert_eq!(format!("{again:?}"), format!("{fresh:?}"), "{cells} cells");
        }
    }
}

#[test]
fn a_state_with_harmonics_is_its_modal_coordinates_summed() {
    // The state at a contact from the search's exponentials is the state evaluated afresh
    // (the same exponentials), and the modal coordinates handed out for a contact sum,
    // mode by mode and entry by entry, to it: bit for bit.
    for cells in [1, 8] {
        let (flow, _, y) = harmonic_chain_flow(cells, &[2, 4]);
        let flight = flow.flight(&y, 0.7);
        let s = 0.45;
        let exps = steady_exponentials(&flow, s);
        let m = 2 * flow.dofs;
        let mut state = DVector::zeros(m);
        flight.state_at(s, &exps, &mut state);
        let fresh = flight.state(s);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(state.as_slice()),
            bits(fresh.as_slice()),
            "{cells} cells"
        );
        let (mut z, mut carried) = (Vec::new(), Vec::new());
        assert!(flight.modal_state(s, &exps, (&mut z, &mut carried)));
        let mut summed = vec![0.0; m];
        for (z, &(k, _)) in z.iter().zip(&flow.kept) {
            for (i, y) in summed.iter_mut().enumerate() {
                *y += flow.mode_columns.0[k * m + i] * z.re - flow.mode_columns.1[k * m + i] * z.im;
            }
        }
        assert_eq!(bits(state.as_slice()), bits(&summed), "{cells} cells");
    }
}

#[test]
fn a_carried_deviation_with_harmonics_is_the_state_s_flight() {
    let (flow, _, y) = harmonic_chain_flow(3, &[2, 3]);
    let n = 6;
    let flight = flow.flight(&y, 0.7);
    let s = 0.45;
    let exps = steady_exponentials(&flow, s);
    let before = flight.state(s);
    let mut after = before.clone();
    after[n + 2] += 0.25;
    after[n + 3] -= 0.125;
    let mut deviation = Vec::new();
    assert!(flight.deviation_at(&exps, &mut deviation));
    flow.add_jump(
        &mut deviation,
        (before.as_slice(), after.as_slice()),
        0..before.len(),
    );
    let (sin, cos) = crate::trig::sin_cos(flow.omega * (0.7 + s));
    let carried = flow
        .flight_with_deviation(deviation, C64::new(cos, sin))
        .expect("steady response");
    let fresh = flow.flight(&after, 0.7 + s);
    for t in [0.0, 0.3, 1.1, 4.0] {
        let (a, b) = (carried.state(t), fresh.state(t));
        let error = (&a - &b).amax();
        assert!(error <= 1e-13 * b.amax(), "t = {t}: {error:e}");
    }
}

#[test]
fn a_harmonic_resonant_with_an_undamped_mode_leaves_the_general_form() {
    // The undamped unit's natural frequencies are `√1.5` and `√6`: at `ω = √6/3` a harmonic
    // of order 3 meets the higher one, and the flow keeps the general form; one of order 2
    // meets neither (nor does the fundamental), and the flow has the steady form.
    use crate::test_models::paper_unit;
    use crate::Harmonic;
    let probe = LinearFlow::of_model(&paper_unit(1.0, None, None), 1.0).expect("flow");
    let highest = probe.rates.iter().map(|r| r.im).fold(0.0, f64::max);
    let omega = highest / 3.0;
    let with = |order: u32| {
        let model = paper_unit(omega, None, None)
            .with_harmonics(vec![Harmonic {
                order,
                cos: DVector::from_vec(vec![0.1, 0.0]),
                sin: DVector::zeros(2),
            }])
            .expect("valid harmonic");
        LinearFlow::of_model(&model, omega).expect("flow")
    };
    assert!(!with(3).has_steady_response());
    assert!(with(2).has_steady_response());
}
