//! Tests of the flow: its rates, and its flights' states, carries, expansions and summaries,
//! packed and scalar alike bit for bit.

#[cfg(target_arch = "x86_64")]
use super::packed::add_column_avx;
use super::*;
use crate::expsum::ExpSum;

/// `e^{λ_k s}` of the flow's kept modes in order, then the forcing's `e^{iωs}`: the
/// exponentials a flight's state at `s` is formed from.
fn kept_exponentials(flow: &LinearFlow, s: f64) -> Vec<C64> {
    flow.kept
        .iter()
        .map(|&(k, _)| cexp(flow.rates[k], s))
        .chain([cexp(C64::new(0.0, flow.omega), s)])
        .collect()
}

/// An undamped system's rates are `±iω_k` exactly (the exact answer: `M`, `K` symmetric
/// positive definite); the Schur form leaves rounding in their real parts, which
/// [`conservative_rates`] removes. A damped system's real parts stay as they are.
#[test]
fn undamped_rates_are_purely_imaginary_and_damped_ones_keep_their_decay() {
    use crate::test_models::{paper_chain, LIGHT_DAMPING};
    for cells in [1, 3, 8] {
        for damping in [None, Some(LIGHT_DAMPING)] {
            let model = paper_chain(cells, 2.0, damping, None);
            let flow = LinearFlow::of_model(&model, 2.0).expect("the paper's chain has a flow");
            let (_, a) = first_order(&model.mass, model.damping.as_ref(), &model.stiffness)
                .expect("the paper's chain has a mass inverse");
            let raw = eigenvalues(&a).expect("eigenvalues");
            for (r, schur) in flow.rates.iter().zip(&raw) {
                assert_eq!(r.im, schur.im);
                if damping.is_none() {
                    assert_eq!(r.re, 0.0, "{cells} cells: {r}");
                    // Only rounding was removed.
                    assert!(schur.re.abs() <= 1e-14 * schur.norm(), "{schur}");
                } else {
                    assert_eq!(r.re, schur.re);
                    assert!(r.re < -1e-4, "{cells} cells: {r}");
                }
            }
        }
    }
}

/// The free flow of a lightly damped chain of the paper's cell, its pairs' relative
/// displacements, and a start state away from rest.
fn chain_flow(cells: usize) -> (LinearFlow, Vec<Functional>, DVector<f64>) {
    use crate::test_models::{paper_chain, LIGHT_DAMPING};
    use crate::CellStops;
    let omega = 2.0;
    let model = paper_chain(
        cells,
        omega,
        Some(LIGHT_DAMPING),
        Some(CellStops::symmetric(0.5, 0.8)),
    );
    let n = 2 * cells;
    let flow = LinearFlow::of_model(&model, omega).expect("flow");
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

/// A chain's modal coordinates `V⁻¹y` with AVX, two modes to a register, are bit for bit
/// the row-by-row sums (an even and an odd number of kept modes: 8 cells keep 16, and a
/// flow's kept modes as long less one).
#[cfg(target_arch = "x86_64")]
#[test]
fn modal_coordinates_with_avx_are_the_row_by_row_sums() {
    if !std::arch::is_x86_feature_detected!("avx") {
        eprintln!("skipped: this CPU has no AVX");
        return;
    }
    let (flow, _, y) = chain_flow(8);
    let y = y.as_slice();
    let m = y.len();
    let (rows_re, rows_im) = &flow.inverse_rows;
    let expected: Vec<C64> = flow
        .kept
        .iter()
        .map(|&(k, _)| {
            let (mut re, mut im) = (0.0, 0.0);
            for i in 0..m {
                re += rows_re[k * m + i] * y[i];
                im += rows_im[k * m + i] * y[i];
            }
            C64::new(re, im)
        })
        .collect();
    let count = flow.kept.len();
    assert_eq!(count, 16);
    for modes in [count, count - 1] {
        // The first `modes` kept modes' columns, as `kept_inverse_columns` lays them out.
        let columns: Vec<C64> = (0..m)
            .flat_map(|i| flow.kept_inverse_columns[i * count..i * count + modes].to_vec())
            .collect();
        let mut out = vec![C64::default(); modes];
        // SAFETY: the CPU has AVX.
        let done = unsafe { modal_coordinates_avx(&columns, y, &mut out) };
        assert_eq!(done, modes - modes % 2);
        for (a, b) in out[..done].iter().zip(&expected) {
            assert_eq!(
                (a.re.to_bits(), a.im.to_bits()),
                (b.re.to_bits(), b.im.to_bits())
            );
        }
    }
}

/// A mode's column added to a state with AVX, four entries at once, is bit for bit the
/// entry-by-entry sum, for every length (whole groups of four and a remainder).
#[cfg(target_arch = "x86_64")]
#[test]
fn a_column_added_with_avx_is_the_entry_by_entry_sum() {
    if !std::arch::is_x86_feature_detected!("avx") {
        eprintln!("skipped: this CPU has no AVX");
        return;
    }
    let z = C64::new(0.37, -1.91);
    for m in 0..14 {
        let value = |i: usize, a: f64| (a * i as f64 + 0.3).sin() * 10f64.powi(i as i32 % 5 - 2);
        let (re, im): (Vec<f64>, Vec<f64>) = (0..m).map(|i| (value(i, 1.3), value(i, 2.9))).unzip();
        let mut expected: Vec<f64> = (0..m).map(|i| value(i, 0.7)).collect();
        let mut y = expected.clone();
        for i in 0..m {
            expected[i] += re[i] * z.re - im[i] * z.im;
        }
        // SAFETY: the CPU has AVX.
        unsafe { add_column_avx(&re, &im, z, &mut y) };
        assert_eq!(
            y.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            expected.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            "length {m}"
        );
    }
}

#[test]
fn a_functional_expanded_from_the_joint_summaries_is_its_expansion_bit_for_bit() {
    // The watch of several pairs writes only the constant coefficients of a pair's terms
    // written by an earlier flight, copied from the summaries' coefficients: the terms
    // must be those a fresh expansion writes, for every slot of odd and even counts.
    for cells in [3, 8] {
        let (flow, functionals, y) = chain_flow(cells);
        let refs: Vec<&Functional> = functionals.iter().collect();
        let joint = flow.joint_weights(&refs);
        let earlier = flow.flight(&y, 0.7);
        let later = flow.flight(&y.map(|v| 1.3 * v - 0.1), 2.9);
        let (mut modes, mut coefficients, mut sums) = (Vec::new(), Vec::new(), Vec::new());
        let scratch = (&mut modes, &mut coefficients);
        assert!(later.summarize_all(&joint, 2.5, scratch, &mut sums));
        for (slot, functional) in functionals.iter().enumerate() {
            let mut again = ExpSum::default();
            earlier.expand(functional, &mut again);
            later.expand_joint(functional, (&coefficients, slot), &mut again);
            let mut fresh = ExpSum::default();
            later.expand(functional, &mut fresh);
            assert_eq!(format!("{again:?}"), format!("{fresh:?}"), "{cells} cells");
            // Not what the earlier flight left.
            let mut first = ExpSum::default();
            earlier.expand(functional, &mut first);
            assert_ne!(format!("{first:?}"), format!("{fresh:?}"));
        }
        // A gap of another length is expanded afresh.
        let mut short = ExpSum::default();
        later.expand_joint(&functionals[0], (&coefficients, 0), &mut short);
        let mut fresh = ExpSum::default();
        later.expand(&functionals[0], &mut fresh);
        assert_eq!(format!("{short:?}"), format!("{fresh:?}"));
    }
}

#[test]
fn joint_summaries_are_each_pairs_summary_bit_for_bit() {
    // Regression guard for the watch of several pairs: its one-pass summaries must be the
    // very sums the per-pair summary (and so the search) forms, for odd and even counts.
    for cells in [2, 3, 8] {
        let (flow, functionals, y) = chain_flow(cells);
        let refs: Vec<&Functional> = functionals.iter().collect();
        let joint = flow.joint_weights(&refs);
        let flight = flow.flight(&y, 0.7);
        let (mut modes, mut coefficients, mut out) = (Vec::new(), Vec::new(), Vec::new());
        let scratch = (&mut modes, &mut coefficients);
        assert!(flight.summarize_all(&joint, 2.5, scratch, &mut out));
        assert_eq!(out.len(), cells);
        for (sum, functional) in out.iter().zip(&functionals) {
            let single = flight.summarize(functional, 2.5).expect("summary");
            assert_eq!(format!("{sum:?}"), format!("{single:?}"), "{cells} cells");
        }
    }
}

#[test]
fn summarised_searches_find_the_one_pair_searches_exits() {
    // The summarised search (fixed grid, cached chunk exponentials, seeded polish) against
    // the search on the horizon's grid (stepped exponentials, fresh polish) over many flights of an 8-cell chain, every
    // pair, full and cut horizons, bands from wide to grazing: the same first exit, to the
    // time tolerance, on the same side.
    use crate::expsum::SearchStack;
    let (flow, functionals, _) = chain_flow(8);
    let (tol, depth) = (1e-12 * std::f64::consts::PI, 1e-12);
    let tolerances = crate::expsum::Tolerances { time: tol, depth };
    let (mut plain, mut summarised) = (SearchStack::default(), SearchStack::default());
    let mut gap = ExpSum::default();
    let (mut exits, mut searches) = (0, 0);
    for case in 0..300 {
        let y = DVector::from_fn(32, |i, _| {
            0.4 * (1.3 * (i * 7 + case * 13) as f64 + 0.2 * case as f64).sin()
        });
        let t0 = 0.01 * case as f64 % std::f64::consts::PI;
        let flight = flow.flight(&y, t0);
        let horizon = std::f64::consts::PI - t0;
        for functional in &functionals {
            flight.expand(functional, &mut gap);
            let summary = flight.summarize(functional, horizon).expect("summary");
            let f0 = gap.eval(0.0).0;
            for width in [0.05, 0.2, 0.5, 1.0] {
                let (lo, hi) = (f0 - width, f0 + 0.7 * width);
                for cutoff in [horizon, 0.5 * horizon, 0.1] {
                    let expected = gap.first_exit_on_horizon_grid(
                        (lo, hi),
                        horizon,
                        cutoff,
                        tolerances,
                        &mut plain,
                    );
                    let found = if summary.excludes(lo, hi, cutoff.min(horizon), horizon) {
                        None
                    } else {
                        searches += 1;
                        gap.first_exit_summarized(
                            &summary,
                            (lo, hi),
                            horizon,
                            cutoff,
                            tolerances,
                            &mut summarised,
                        )
                    };
                    // Exits after the cutoff may or may not be reported.
                    let keep = |e: Option<(f64, i8)>| e.filter(|&(s, _)| s <= cutoff);
                    match (keep(expected), keep(found)) {
                        (None, None) => {}
                        (Some((a, sa)), Some((b, sb))) => {
                            exits += 1;
                            assert_eq!(sa, sb, "case {case}: side");
                            assert!((a - b).abs() <= 4.0 * tol, "case {case}: {a} vs {b}");
                        }
                        (a, b) => panic!("case {case}: {a:?} vs {b:?}"),
                    }
                }
            }
        }
    }
    assert!(
        exits > 1000 && searches > 2000,
        "{exits} exits, {searches} searches"
    );
}

/// A chain's state at a contact (its exponentials known, and not) is bit for bit the
/// state formed mode by mode and entry by entry, whether or not it is formed with AVX.
#[test]
fn a_chains_state_is_its_modes_summed_entry_by_entry() {
    for cells in [2, 3, 8] {
        let (flow, _, y) = chain_flow(cells);
        let flight = flow.flight(&y, 0.7);
        let Form::Steady {
            response: p,
            deviation,
            phase,
            ..
        } = &flight.form
        else {
            panic!("steady response");
        };
        let s = 0.45;
        let exps = kept_exponentials(&flow, s);
        let m = 2 * flow.dofs;
        let mut expected = vec![0.0; m];
        let forced = exps[flow.kept.len()] * phase;
        for (j, &(k, weight)) in flow.kept.iter().enumerate() {
            let z = (deviation[j] * exps[j]
                + p.plus[j] * forced
                + p.minus[j] * forced.conj()
                + p.constant[j])
                * weight;
            for (i, y) in expected.iter_mut().enumerate() {
                *y += flow.mode_columns.0[k * m + i] * z.re - flow.mode_columns.1[k * m + i] * z.im;
            }
        }
        let mut state = DVector::zeros(m);
        flight.state_at(s, &exps, &mut state);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(state.as_slice()), bits(&expected), "{cells} cells");
    }
}

/// The packed products and scaled sums of a carried deviation are the scalar ones bit for
/// bit, for odd and even lengths.
#[cfg(target_arch = "x86_64")]
#[test]
fn packed_carries_are_the_scalar_ones_bit_for_bit() {
    if !std::arch::is_x86_feature_detected!("avx") {
        return;
    }
    let mut x = 0.3_f64;
    let mut next = move || {
        x = (x * 7919.0 + 0.123).fract();
        (x - 0.5) * 10f64.powi((x * 7.0) as i32 - 3)
    };
    let bits = |v: &[C64]| {
        v.iter()
            .flat_map(|c| [c.re.to_bits(), c.im.to_bits()])
            .collect::<Vec<_>>()
    };
    for n in [0, 1, 2, 7, 16, 17] {
        let a: Vec<C64> = (0..n).map(|_| C64::new(next(), next())).collect();
        let b: Vec<C64> = (0..n).map(|_| C64::new(next(), next())).collect();
        let mut packed = vec![C64::default(); n];
        // SAFETY: the CPU has AVX.
        unsafe { crate::expsum::products_avx(&a, &b, &mut packed) };
        let scalar: Vec<C64> = a.iter().zip(&b).map(|(&x, &y)| x * y).collect();
        assert_eq!(bits(&packed), bits(&scalar), "products, {n}");
        let delta = next();
        let mut packed = a.clone();
        // SAFETY: the CPU has AVX.
        unsafe { add_scaled_avx(&mut packed, &b, delta) };
        let scalar: Vec<C64> = a.iter().zip(&b).map(|(&h, &v)| h + v * delta).collect();
        assert_eq!(bits(&packed), bits(&scalar), "scaled sums, {n}");
    }
}

#[test]
fn a_carried_deviation_is_the_state_s_flight() {
    // The start carried across an event (the deviation at `s`, plus a velocity jump)
    // against the flight recomputed from the state there: the same motion to rounding.
    let (flow, _, y) = chain_flow(3);
    let n = 6;
    let flight = flow.flight(&y, 0.7);
    let s = 0.45;
    let exps = kept_exponentials(&flow, s);
    let before = flight.state(s);
    let mut after = before.clone();
    after[n + 2] += 0.25;
    after[n + 3] -= 0.125;
    let mut deviation = Vec::new();
    assert!(flight.deviation_at(&exps, &mut deviation));
    let changed = 0..before.len();
    flow.add_jump(
        &mut deviation,
        (before.as_slice(), after.as_slice()),
        changed,
    );
    let (sin, cos) = crate::trig::sin_cos(flow.omega * (0.7 + s));
    let carried = flow
        .flight_with_deviation(deviation, C64::new(cos, sin))
        .expect("steady response");
    let fresh = flow.flight(&after, 0.7 + s);
    for t in [0.0, 0.3, 1.1] {
        let (a, b) = (carried.state(t), fresh.state(t));
        let error = (&a - &b).amax();
        assert!(error <= 1e-13 * b.amax(), "t = {t}: {error:e}");
    }
}

#[test]
fn eigenvalues_where_the_plain_schur_iteration_cycles() {
    // A 4×4 matrix (a monodromy met in a map) on which nalgebra's unbounded real Schur
    // iteration never converges; column by column.
    let a = DMatrix::from_column_slice(
        4,
        4,
        &[
            -0.5949065900786252,
            -0.54785366462303,
            0.09877288697600826,
            0.12768814862690236,
            -0.2736063407419963,
            -0.24558433817231848,
            -0.24127877581140877,
            -0.10566685059017007,
            -0.08898796197315695,
            -0.12830918791764725,
            -0.48568868720653724,
            -0.48981661360765977,
            0.17069267029308077,
            0.07791231009587478,
            -0.3650431717907076,
            -0.34735400366643376,
        ],
    );
    let rates = eigenvalues(&a).expect("converges");
    let sum: C64 = rates.iter().sum();
    let product: C64 = rates.iter().product();
    assert!((sum.re - a.trace()).abs() < 1e-12 && sum.im.abs() < 1e-12);
    assert!((product.re - a.clone().determinant()).abs() < 1e-12);
    let ac = a.map(|v| C64::new(v, 0.0));
    for &l in &rates {
        let shifted = &ac - DMatrix::<C64>::identity(4, 4) * l;
        assert!(shifted.determinant().norm() < 1e-10, "{l}");
    }
    let mut bad = a;
    bad[(0, 3)] = f64::INFINITY;
    assert_eq!(eigenvalues(&bad), Err(FlowError::NotFinite));
}
