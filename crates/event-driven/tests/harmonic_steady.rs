//! The steady-response form with higher harmonics against the general form: each model runs
//! twice, once as built (its flights written about the periodic particular solution of the
//! fundamental and every harmonic) and once with every flight in the resonance-safe general
//! form ([`Model::with_general_form`]), and the two runs' impacts (times, states), sampled rows
//! and final states agree to the solver's rounding over hundreds of impacts: on the paper unit,
//! a 3-cell chain, a free ball in a clearance and a unit that sticks. A model with a harmonic
//! resonant with an undamped mode has no steady form and flies as the general one, bit for bit.

use nalgebra::{DMatrix, DVector};
use rattle_event_driven::test_models::{paper_chain, paper_unit, LIGHT_DAMPING, OUTER_STIFFNESS};
use rattle_event_driven::LinearFlow;
use rattle_event_driven::*;

/// Largest relative difference allowed between the two forms' impact times (over the period)
/// and states (over the largest entry).
const AGREEMENT: f64 = 1e-10;

/// The harmonics `(order, amplitude)` of a base motion acting on DOF 0 through the paper's
/// outer spring and dashpot, as the fundamental does (`f_c,k = k_o a`, `f_s,k = −c_o kω a`), on
/// an `n`-DOF structure forced at `omega`.
fn base_harmonics(n: usize, orders: &[(u32, f64)], omega: f64) -> Vec<Harmonic> {
    orders
        .iter()
        .map(|&(order, amplitude)| {
            let mut cos = DVector::zeros(n);
            let mut sin = DVector::zeros(n);
            cos[0] = OUTER_STIFFNESS * amplitude;
            sin[0] = -LIGHT_DAMPING.0 * f64::from(order) * omega * amplitude;
            Harmonic { order, cos, sin }
        })
        .collect()
}

/// A free ball (mass 1, held by nothing: a rigid mode) in a clearance `±0.5` of a damped
/// oscillator (`m = 2`, `k = 6`, `c = 0.1`), both forced, with harmonics of orders 2 and 3.
fn free_ball(omega: f64) -> Model {
    let mass = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 1.0]);
    let stiffness = DMatrix::from_row_slice(2, 2, &[6.0, 0.0, 0.0, 0.0]);
    let damping = DMatrix::from_row_slice(2, 2, &[0.1, 0.0, 0.0, 0.0]);
    Model::new(
        mass,
        stiffness,
        Some(damping),
        DVector::from_vec(vec![6.0, 0.2]),
        DVector::from_vec(vec![-0.1 * omega, 0.06]),
        vec![ContactPair {
            plus_dof: Some(1),
            minus_dof: Some(0),
            gap_plus: 0.5,
            gap_minus: 0.5,
            restitution: 0.8,
        }],
    )
    .unwrap()
    .with_harmonics(vec![
        Harmonic {
            order: 2,
            cos: DVector::from_vec(vec![0.3, 0.05]),
            sin: DVector::from_vec(vec![0.0, -0.02]),
        },
        Harmonic {
            order: 3,
            cos: DVector::from_vec(vec![0.0, 0.04]),
            sin: DVector::from_vec(vec![0.1, 0.0]),
        },
    ])
    .unwrap()
}

/// Whether the free flow of `model`, of stiffness `stiffness` and damping `damping`, has the
/// steady-response form at `omega`: the flow of its matrices and harmonics under any
/// fundamental has the same rates, so the same resonances.
fn has_steady_form(
    model: &Model,
    (stiffness, damping): (&DMatrix<f64>, &DMatrix<f64>),
    omega: f64,
) -> bool {
    let zero = DVector::zeros(model.dofs());
    LinearFlow::with_harmonics(
        (model.mass(), Some(damping), stiffness),
        (&zero, &zero, &zero),
        model.harmonics(),
        omega,
    )
    .unwrap()
    .has_steady_response()
}

/// Samples `periods` periods of `model` from `start`.
fn trajectory(model: &Model, omega: f64, periods: u64, start: &Start) -> Trajectory {
    let options = TrajectoryOptions {
        periods,
        samples_per_period: 4,
        base_amplitude: 0.0,
        simulation: SimulationOptions::default(),
    };
    sample_trajectory(model, omega, start, &options).unwrap()
}

/// A run of exactly `periods` periods, not polished.
fn fixed(periods: u64) -> SimulationOptions {
    SimulationOptions {
        fixed_periods: Some(periods),
        polish: false,
        ..SimulationOptions::default()
    }
}

/// Largest `|a_i − b_i|` and largest `|a_i|`.
fn difference(a: &[f64], b: &[f64]) -> (f64, f64) {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).fold((0.0f64, 0.0f64), |(d, s), (x, y)| {
        (d.max((x - y).abs()), s.max(x.abs()))
    })
}

/// What [`compare_forms`] measured.
#[derive(Debug)]
struct Agreement {
    impacts: usize,
    sticks: usize,
    /// Largest impact-time difference over the period.
    time: f64,
    /// Largest state difference (impacts, rows, the unrecorded run's final state) over the
    /// largest entry.
    state: f64,
}

/// Runs `model` from `start` over `periods` periods in the steady-response form and in the
/// general form, recorded (a trajectory) and not (a simulation, which forms fewer states and
/// carries flights across contacts and sections), and measures how far they part.
fn compare_forms(model: &Model, omega: f64, periods: u64, start: &Start) -> Agreement {
    let general = model.clone().with_general_form();
    let period = std::f64::consts::TAU / omega;
    let a = trajectory(model, omega, periods, start);
    let b = trajectory(&general, omega, periods, start);
    assert_eq!(a.impacts.len(), b.impacts.len(), "impact counts");
    assert_eq!(a.rows.len(), b.rows.len(), "row counts");
    let (mut time, mut state, mut size) = (0.0f64, 0.0f64, 0.0f64);
    for (x, y) in a.impacts.iter().zip(&b.impacts) {
        assert_eq!((x.pair, x.side), (y.pair, y.side), "impact at {}", x.time);
        time = time.max((x.time - y.time).abs() / period);
        for (u, v) in [
            (&x.displacements, &y.displacements),
            (&x.velocities_before, &y.velocities_before),
        ] {
            let (d, s) = difference(u, v);
            state = state.max(d);
            size = size.max(s);
        }
    }
    for (x, y) in a.rows.iter().zip(&b.rows) {
        assert_eq!(x.kind, y.kind, "row kinds at {}", x.time);
        time = time.max((x.time - y.time).abs() / period);
        for (u, v) in [
            (&x.displacements, &y.displacements),
            (&x.velocities, &y.velocities),
        ] {
            let (d, s) = difference(u, v);
            state = state.max(d);
            size = size.max(s);
        }
    }
    let (p, q) = (
        simulate(model, omega, start, &fixed(periods)).unwrap(),
        simulate(&general, omega, start, &fixed(periods)).unwrap(),
    );
    assert_eq!(p.impacts, q.impacts, "simulated impacts");
    assert_eq!(
        p.impacts as usize,
        a.impacts.len(),
        "simulated and sampled impacts"
    );
    let (d, s) = difference(
        p.final_state.state.as_slice(),
        q.final_state.state.as_slice(),
    );
    state = state.max(d);
    size = size.max(s);
    let sticks = a
        .rows
        .iter()
        .filter(|r| r.kind == RowKind::AfterStick)
        .count();
    Agreement {
        impacts: a.impacts.len(),
        sticks,
        time,
        state: state / size.max(1e-300),
    }
}

/// Checks the two forms agree on `model` of stiffness and damping `matrices` (with the
/// steady form where `steady`: the runs then differ in their last bits, else not at all).
fn check(
    name: &str,
    (model, matrices): (&Model, (&DMatrix<f64>, &DMatrix<f64>)),
    omega: f64,
    steady: bool,
) -> Agreement {
    assert_eq!(
        has_steady_form(model, matrices, omega),
        steady,
        "{name}: steady form"
    );
    let agreement = compare_forms(model, omega, 200, &Start::rest(model.dofs()));
    println!("{name}: {agreement:?}");
    assert_eq!(
        agreement.time > 0.0 || agreement.state > 0.0,
        steady,
        "{name}: the forms part only where they differ"
    );
    assert!(
        agreement.impacts >= 200,
        "{name}: {} impacts",
        agreement.impacts
    );
    assert!(
        agreement.time <= AGREEMENT,
        "{name}: times part by {:e}",
        agreement.time
    );
    assert!(
        agreement.state <= AGREEMENT,
        "{name}: states part by {:e}",
        agreement.state
    );
    agreement
}

/// The unit's matrices: `m_o = 2`, `m_i = 1`, `k_o = 6`, `k_i = 3`, dashpots `(c_o, c_i)`.
fn unit_matrices((co, ci): (f64, f64)) -> (DMatrix<f64>, DMatrix<f64>) {
    (
        DMatrix::from_row_slice(2, 2, &[9.0, -3.0, -3.0, 3.0]),
        DMatrix::from_row_slice(2, 2, &[co + ci, -ci, -ci, ci]),
    )
}

#[test]
fn the_paper_unit_with_harmonics_flies_the_same_in_both_forms() {
    let omega = 2.0;
    let (k, c) = unit_matrices(LIGHT_DAMPING);
    for orders in [vec![(2, 0.02)], vec![(2, 0.05), (3, 0.03), (5, 0.02)]] {
        let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.5, 0.8)))
            .with_harmonics(base_harmonics(2, &orders, omega))
            .unwrap();
        let name = format!("unit, orders {orders:?}");
        check(&name, (&model, (&k, &c)), omega, true);
    }
}

#[test]
fn a_sticking_unit_with_harmonics_flies_the_same_in_both_forms() {
    let omega = 2.0;
    let (k, c) = unit_matrices(LIGHT_DAMPING);
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.5, 0.0)))
        .with_harmonics(base_harmonics(2, &[(2, 0.04), (3, 0.02)], omega))
        .unwrap();
    let agreement = check("unit, e = 0", (&model, (&k, &c)), omega, true);
    assert!(agreement.sticks > 0, "the unit sticks");
}

#[test]
fn a_three_cell_chain_with_harmonics_flies_the_same_in_both_forms() {
    let omega = 2.0;
    let stops = Some(CellStops::symmetric(0.5, 0.8));
    let model = paper_chain(3, omega, Some(LIGHT_DAMPING), stops)
        .with_harmonics(base_harmonics(6, &[(2, 0.02), (3, 0.02)], omega))
        .unwrap();
    let (co, ci) = LIGHT_DAMPING;
    // The chain's tridiagonal stiffness and damping, cell by cell.
    let band = |outer: f64, inner: f64| {
        let mut m = DMatrix::zeros(6, 6);
        for cell in 0..3 {
            let (o, i) = (2 * cell, 2 * cell + 1);
            m[(o, o)] += outer + inner;
            m[(i, i)] += inner;
            m[(o, i)] -= inner;
            m[(i, o)] -= inner;
            if cell > 0 {
                let p = o - 2;
                m[(p, p)] += outer;
                m[(p, o)] -= outer;
                m[(o, p)] -= outer;
            }
        }
        m
    };
    let matrices = (&band(6.0, 3.0), &band(co, ci));
    check("chain of 3", (&model, matrices), omega, true);
}

#[test]
fn a_free_ball_with_harmonics_flies_the_same_in_both_forms() {
    let omega = 2.0;
    let stiffness = DMatrix::from_row_slice(2, 2, &[6.0, 0.0, 0.0, 0.0]);
    let damping = DMatrix::from_row_slice(2, 2, &[0.1, 0.0, 0.0, 0.0]);
    // A free body: rigid modes, in the general form either way.
    check(
        "free ball",
        (&free_ball(omega), (&stiffness, &damping)),
        omega,
        false,
    );
}
