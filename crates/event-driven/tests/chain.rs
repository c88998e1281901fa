//! Chains of impacting cells (the event-driven solver), each test against an exact answer:
//! the linear chain's steady state from an independent complex solve written here, today's
//! unit bit for bit, the impact law (momentum, `ṙ⁺ = −e ṙ⁻`, energy loss `½μ(1 − e²)ṙ⁻²`) at
//! every impact, no penetration of any pair, two pairs reaching their stops `1e-12 T` apart at
//! times known in closed form (an independent matrix exponential written here), and one pair
//! held while another flies.

use nalgebra::{Complex, DMatrix, DVector};
use rattle_event_driven::test_models::{
    paper_cell, paper_chain, paper_unit, BASE_AMPLITUDE, LIGHT_DAMPING,
};
use rattle_event_driven::*;

/// Unit roundoff.
const EPS: f64 = f64::EPSILON;

/// `M`, `C`, `K` and the forcing `(f_c, f_s)` of a chain, written out here from the physics
/// (outer mass `j` tied to outer mass `j − 1` by `k_o, c_o`, the first to the base moving as
/// `u_g cos ωt`; `u = (u_o1, u_i1, …)`), independently of [`Model::chain`].
struct ChainMatrices {
    mass: DMatrix<f64>,
    damping: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    forcing_cos: DVector<f64>,
    forcing_sin: DVector<f64>,
}

fn chain_matrices(cells: &[CellParameters], base: f64, omega: f64) -> ChainMatrices {
    let n = 2 * cells.len();
    let mut m = ChainMatrices {
        mass: DMatrix::zeros(n, n),
        damping: DMatrix::zeros(n, n),
        stiffness: DMatrix::zeros(n, n),
        forcing_cos: DVector::zeros(n),
        forcing_sin: DVector::zeros(n),
    };
    // A spring (or dashpot) of value `v` between DOFs `a` and `b` (`None`: the base).
    let link = |matrix: &mut DMatrix<f64>, a: Option<usize>, b: usize, v: f64| {
        matrix[(b, b)] += v;
        if let Some(a) = a {
            matrix[(a, a)] += v;
            matrix[(a, b)] -= v;
            matrix[(b, a)] -= v;
        }
    };
    for (j, c) in cells.iter().enumerate() {
        let (o, i) = (2 * j, 2 * j + 1);
        let previous = (j > 0).then(|| o - 2);
        m.mass[(o, o)] = c.outer_mass;
        m.mass[(i, i)] = c.inner_mass;
        link(&mut m.stiffness, previous, o, c.outer_stiffness);
        link(&mut m.stiffness, Some(o), i, c.inner_stiffness);
        link(&mut m.damping, previous, o, c.outer_damping.unwrap_or(0.0));
        link(&mut m.damping, Some(o), i, c.inner_damping.unwrap_or(0.0));
    }
    // The base's spring and dashpot: k_o u_g cos ωt + c_o u̇_g = k_o u_g cos ωt − c_o u_g ω sin ωt.
    m.forcing_cos[0] = cells[0].outer_stiffness * base;
    m.forcing_sin[0] = -cells[0].outer_damping.unwrap_or(0.0) * base * omega;
    m
}

/// The linear steady state `u(t) = Re{U e^{iωt}}`: `(K − ω²M + iωC) U = F`, `F = f_c − i f_s`,
/// by complex LU.
fn linear_chain_response(m: &ChainMatrices, omega: f64) -> DVector<Complex<f64>> {
    let c = |x: &DMatrix<f64>| x.map(|v| Complex::new(v, 0.0));
    let dynamic = c(&m.stiffness) - c(&m.mass) * Complex::new(omega * omega, 0.0)
        + c(&m.damping) * Complex::new(0.0, omega);
    let f = DVector::from_iterator(
        m.forcing_cos.len(),
        m.forcing_cos
            .iter()
            .zip(m.forcing_sin.iter())
            .map(|(&fc, &fs)| Complex::new(fc, -fs)),
    );
    dynamic.lu().solve(&f).expect("the damped chain is regular")
}

/// `exp(A s)` by scaling and squaring of a Taylor series (40 terms after scaling to
/// `‖A s‖ < ½`: the remainder is below `2⁻⁴⁰/40!`).
fn expm(a: &DMatrix<f64>, s: f64) -> DMatrix<f64> {
    let mut x = a * s;
    let norm = x.norm();
    let squarings = if norm > 0.5 {
        (norm / 0.5).log2().ceil() as u32
    } else {
        0
    };
    x /= 2f64.powi(squarings as i32);
    let n = a.nrows();
    let mut result = DMatrix::identity(n, n);
    let mut term = DMatrix::identity(n, n);
    for k in 1..=40 {
        term = &term * &x / k as f64;
        result += &term;
    }
    for _ in 0..squarings {
        result = &result * &result;
    }
    result
}

/// The augmented state `(u, u̇, cos ωt, sin ωt)` evolves by `ż = A z`, forcing included.
fn augmented_system(m: &ChainMatrices, omega: f64) -> DMatrix<f64> {
    let n = m.mass.nrows();
    let minv = m.mass.clone().try_inverse().unwrap();
    let mut a = DMatrix::zeros(2 * n + 2, 2 * n + 2);
    a.view_mut((0, n), (n, n)).fill_with_identity();
    a.view_mut((n, 0), (n, n))
        .copy_from(&(-(&minv * &m.stiffness)));
    a.view_mut((n, n), (n, n))
        .copy_from(&(-(&minv * &m.damping)));
    a.view_mut((n, 2 * n), (n, 1))
        .copy_from(&(&minv * &m.forcing_cos));
    a.view_mut((n, 2 * n + 1), (n, 1))
        .copy_from(&(&minv * &m.forcing_sin));
    a[(2 * n, 2 * n + 1)] = -omega;
    a[(2 * n + 1, 2 * n)] = omega;
    a
}

/// Cell `j`'s `(m_o, m_i, e)`.
fn cell_law(cells: &[CellParameters], j: usize) -> (f64, f64, f64) {
    let c = &cells[j];
    (
        c.outer_mass,
        c.inner_mass,
        c.stops.map_or(1.0, |s| s.restitution),
    )
}

/// Every event of a trajectory obeys the impact law: each row after an impact or a stick
/// differs from the row before it (same time) only in one cell's two velocities; that cell's
/// momentum is kept, its relative velocity maps as `ṙ⁺ = −e ṙ⁻` (`e = 0` for a stick) and its
/// kinetic energy drops by `½ μ (1 − e²) ṙ⁻²`, `μ = m_o m_i/(m_o + m_i)`. Tolerances: a few
/// rounding units of the terms summed (`8ε` of the momenta and relative speeds, `16ε` of the
/// kinetic energy). Returns the number of impacts and sticks checked.
fn check_impact_law(trajectory: &Trajectory, cells: &[CellParameters]) -> (usize, usize) {
    let (mut impacts, mut sticks) = (0, 0);
    for w in trajectory.rows.windows(2) {
        let (before, after) = (&w[0], &w[1]);
        let e_of = |j: usize| match after.kind {
            RowKind::AfterImpact => Some(cell_law(cells, j).2),
            RowKind::AfterStick => Some(0.0),
            _ => None,
        };
        if e_of(0).is_none() {
            continue;
        }
        assert_eq!(before.time, after.time);
        assert_eq!(before.displacements, after.displacements);
        let changed: Vec<usize> = (0..before.velocities.len())
            .filter(|&k| before.velocities[k] != after.velocities[k])
            .collect();
        if changed.is_empty() {
            // A stick right after a plastic impact of the same pair changes nothing: that
            // pair is already at rest on its stop.
            assert_eq!(after.kind, RowKind::AfterStick, "t = {}", after.time);
            let at_rest = (0..cells.len()).any(|j| {
                let (vo, vi) = (after.velocities[2 * j], after.velocities[2 * j + 1]);
                (vi - vo).abs() <= 8.0 * EPS * (vo.abs() + vi.abs())
            });
            assert!(at_rest, "t = {}: a stick with no pair at rest", after.time);
            sticks += 1;
            continue;
        }
        let j = changed[0] / 2;
        assert!(
            changed.iter().all(|k| k / 2 == j),
            "t = {}: velocities of more than one cell changed: {changed:?}",
            after.time
        );
        let (mo, mi, _) = cell_law(cells, j);
        let e = e_of(j).unwrap();
        let (vo, vi) = (before.velocities[2 * j], before.velocities[2 * j + 1]);
        let (wo, wi) = (after.velocities[2 * j], after.velocities[2 * j + 1]);
        let momentum_scale = mo * vo.abs() + mi * vi.abs() + mo * wo.abs() + mi * wi.abs();
        assert!(
            (mo * vo + mi * vi - mo * wo - mi * wi).abs() <= 8.0 * EPS * momentum_scale,
            "t = {}: momentum of cell {j} not kept",
            after.time
        );
        let (rdot_before, rdot_after) = (vi - vo, wi - wo);
        let speed_scale = vo.abs() + vi.abs() + wo.abs() + wi.abs();
        assert!(
            (rdot_after + e * rdot_before).abs() <= 8.0 * EPS * speed_scale,
            "t = {}: ṙ⁺ = {rdot_after}, −e ṙ⁻ = {} (cell {j}, {:?} → {:?}, {:?} → {:?})",
            after.time,
            -e * rdot_before,
            before.kind,
            after.kind,
            before.velocities,
            after.velocities
        );
        let energy = |a: f64, b: f64| 0.5 * (mo * a * a + mi * b * b);
        let mu = mo * mi / (mo + mi);
        let loss = energy(vo, vi) - energy(wo, wi);
        let expected = 0.5 * mu * (1.0 - e * e) * rdot_before * rdot_before;
        assert!(
            (loss - expected).abs() <= 16.0 * EPS * energy(vo, vi),
            "t = {}: energy lost {loss}, expected {expected}",
            after.time
        );
        match after.kind {
            RowKind::AfterImpact => impacts += 1,
            _ => sticks += 1,
        }
    }
    (impacts, sticks)
}

/// `−gap_minus − tol ≤ r ≤ gap_plus + tol` for every pair at every row, with the tolerance the
/// simulator guarantees: contacts resolved in time to `root_tolerance × T` (so `|ṙ|` times
/// that), plus the contact depth `1e-12` of the largest gap and the position rounding `1e-14`
/// of the largest displacement (as in `tests/trajectory.rs`).
fn check_within_stops(trajectory: &Trajectory, model: &Model) {
    let pairs = model.contacts();
    let max_u = trajectory
        .rows
        .iter()
        .flat_map(|r| r.displacements.iter())
        .fold(0.0f64, |m, u| m.max(u.abs()));
    let max_rdot = trajectory
        .rows
        .iter()
        .flat_map(|r| {
            pairs
                .iter()
                .map(|p| p.relative(r.velocities.as_slice()).abs())
        })
        .fold(0.0, f64::max);
    let scale = pairs
        .iter()
        .map(|p| p.gap_plus.max(p.gap_minus))
        .fold(0.0, f64::max);
    let root = SimulationOptions::default().root_tolerance;
    let tol = max_rdot * root * trajectory.period + 1e-12 * scale + 1e-14 * max_u;
    for row in &trajectory.rows {
        for (j, p) in pairs.iter().enumerate() {
            let r = row.relative[j];
            assert!(
                r <= p.gap_plus + tol && r >= -p.gap_minus - tol,
                "t = {}: pair {j}: r = {r} outside [−{}, {}] by more than {tol:e}",
                row.time,
                p.gap_minus,
                p.gap_plus
            );
        }
    }
}

fn trajectory_options(periods: u64, samples: u64) -> TrajectoryOptions {
    TrajectoryOptions {
        periods,
        samples_per_period: samples,
        base_amplitude: BASE_AMPLITUDE,
        ..TrajectoryOptions::default()
    }
}

#[test]
fn one_cell_is_the_unit_bit_for_bit() {
    // The two-impact orbit (ω = 2), the chaotic point (ω = 1.25, capped) and a plastic stop
    // that sticks (e = 0 at ω = 1.5), undamped and damped.
    let cases = [
        (2.0, Some(LIGHT_DAMPING), (0.5, 0.8)),
        (1.25, Some(LIGHT_DAMPING), (0.25, 0.8)),
        (1.5, Some(LIGHT_DAMPING), (0.25, 0.0)),
        (2.0, None, (0.5, 1.0)),
    ];
    for (omega, damping, (gap, e)) in cases {
        let unit = paper_unit(omega, damping, Some((gap, e)));
        let chain = paper_chain(1, omega, damping, Some(CellStops::symmetric(gap, e)));
        assert_eq!(unit, chain, "ω = {omega}: the models differ");
        let options = SimulationOptions {
            max_periods: 400,
            ..SimulationOptions::default()
        };
        let a = simulate(&unit, omega, &Start::rest(2), &options).unwrap();
        let b = simulate(&chain, omega, &Start::rest(2), &options).unwrap();
        assert_eq!(a, b, "ω = {omega}: the steady states differ");
    }
}

#[test]
fn chain_with_huge_gaps_is_the_linear_chain() {
    // A graded three-cell chain, damped; gaps of 1e6 are never reached. Started on the linear
    // steady state (solved here), it must stay there: each DOF's amplitude is |U_j| and the
    // sections repeat, to the solver's periodicity tolerance.
    let omega = 1.7;
    let cells = [
        CellParameters {
            outer_mass: 2.0,
            inner_mass: 1.0,
            outer_stiffness: 6.0,
            inner_stiffness: 3.0,
            outer_damping: Some(0.1),
            inner_damping: Some(0.05),
            stops: Some(CellStops::symmetric(1e6, 0.8)),
        },
        CellParameters {
            outer_mass: 1.5,
            inner_mass: 0.7,
            outer_stiffness: 5.0,
            inner_stiffness: 2.0,
            outer_damping: Some(0.2),
            inner_damping: None,
            stops: Some(CellStops {
                gap_plus: 1e6,
                gap_minus: 2e6,
                restitution: 0.5,
            }),
        },
        CellParameters {
            outer_mass: 1.0,
            inner_mass: 0.5,
            outer_stiffness: 4.0,
            inner_stiffness: 1.0,
            outer_damping: None,
            inner_damping: Some(0.03),
            stops: Some(CellStops::symmetric(1e6, 0.0)),
        },
    ];
    let base = 0.8;
    let model = Model::chain(&cells, base, omega).unwrap();
    let matrices = chain_matrices(&cells, base, omega);
    assert_eq!(model.mass(), &matrices.mass);
    let u = linear_chain_response(&matrices, omega);
    let n = model.dofs();
    let mut state = DVector::zeros(2 * n);
    for j in 0..n {
        state[j] = u[j].re;
        state[n + j] = -omega * u[j].im;
    }
    let options = SimulationOptions {
        fixed_periods: Some(3),
        ..SimulationOptions::default()
    };
    let start = Start {
        state: state.clone(),
        time: 0.0,
    };
    let steady = simulate(&model, omega, &start, &options).unwrap();
    let tol = SimulationOptions::default().periodicity_tolerance;
    assert_eq!(steady.impacts, 0);
    for j in 0..n {
        let exact = u[j].norm();
        assert!(
            (steady.amplitudes[j] - exact).abs() <= tol * exact,
            "DOF {j}: amplitude {} against |U| = {exact}",
            steady.amplitudes[j]
        );
    }
    let end = &steady.final_state.state;
    assert!(
        (end - &state).norm() <= tol * state.norm(),
        "the section after 3 periods left the linear steady state by {:e}",
        (end - &state).norm()
    );
    assert_eq!(steady.status, Status::Periodic);
    assert_eq!(steady.period, Some(1));
}

#[test]
fn every_impact_of_a_chain_keeps_momentum_and_loses_the_stated_energy() {
    // Five paper cells, mixed restitutions (a plastic cell sticks, the others bounce).
    let omega = 1.5;
    let restitutions = [0.8, 0.0, 0.5, 0.95, 0.8];
    let cells: Vec<CellParameters> = restitutions
        .iter()
        .map(|&e| paper_cell(Some(LIGHT_DAMPING), Some(CellStops::symmetric(0.25, e))))
        .collect();
    let model = Model::chain(&cells, BASE_AMPLITUDE, omega).unwrap();
    let trajectory = sample_trajectory(
        &model,
        omega,
        &Start::rest(model.dofs()),
        &trajectory_options(100, 50),
    )
    .unwrap();
    let (impacts, sticks) = check_impact_law(&trajectory, &cells);
    assert!(impacts > 100, "only {impacts} impacts");
    assert!(sticks > 0, "the plastic cell never stuck");
    let pairs_seen: std::collections::BTreeSet<usize> =
        trajectory.impacts.iter().map(|i| i.pair).collect();
    assert_eq!(pairs_seen.len(), 5, "pairs that impacted: {pairs_seen:?}");
}

#[test]
fn no_pair_of_a_five_cell_chain_penetrates_over_a_long_run() {
    // 1000 periods of five paper cells (gap 0.25), sticking (e = 0) and bouncing pairs
    // together, after a settling run from rest.
    let omega = 1.5;
    let restitutions = [0.8, 0.0, 0.8, 0.0, 0.3];
    let cells: Vec<CellParameters> = restitutions
        .iter()
        .map(|&e| paper_cell(Some(LIGHT_DAMPING), Some(CellStops::symmetric(0.25, e))))
        .collect();
    let model = Model::chain(&cells, BASE_AMPLITUDE, omega).unwrap();
    let trajectory = sample_trajectory(
        &model,
        omega,
        &Start::rest(model.dofs()),
        &trajectory_options(1000, 40),
    )
    .unwrap();
    check_within_stops(&trajectory, &model);
    check_impact_law(&trajectory, &cells);
    assert!(trajectory.impacts.len() > 1000);
    // Several pairs held at once, with others flying: rows where two pairs rest on a stop
    // (r = ±Δ and ṙ = 0 to rounding) and the run goes on.
    let resting = |r: &TrajectoryRow, j: usize| {
        let (vo, vi) = (r.velocities[2 * j], r.velocities[2 * j + 1]);
        (r.relative[j].abs() - 0.25).abs() <= 1e-12 && (vi - vo).abs() <= 1e-12
    };
    let doubly_held = trajectory
        .rows
        .iter()
        .filter(|r| r.kind == RowKind::Sample && (0..5).filter(|&j| resting(r, j)).count() >= 2)
        .count();
    assert!(doubly_held > 0, "never two pairs held at once");
}

#[test]
fn two_pairs_reaching_their_stops_1e_12_periods_apart() {
    // Two paper cells, lightly damped. From y0 at t = 0 the free flow is exp(A s) (the
    // augmented system, written here). Pair 0 is sent up, pair 1 down; the stops are placed
    // where the pairs are at s₁ = 0.1 T (pair 0, side 1) and s₂ = s₁ + 1e-12 T (pair 1,
    // side 2), both approached monotonically: the first contacts are exactly there.
    let omega = 2.0;
    let period = std::f64::consts::TAU / omega;
    let (s1, s2) = (0.1 * period, 0.1 * period + 1e-12 * period);
    let base_cells = vec![paper_cell(Some(LIGHT_DAMPING), None); 2];
    let matrices = chain_matrices(&base_cells, BASE_AMPLITUDE, omega);
    let a = augmented_system(&matrices, omega);
    let y0 = [0.0, 0.0, 0.1, -0.1, 0.0, 2.0, 0.0, -1.5];
    let mut z0 = DVector::zeros(10);
    z0.rows_mut(0, 8).copy_from_slice(&y0);
    z0[8] = 1.0; // cos 0
    let at = |s: f64| expm(&a, s) * &z0;
    // r₀ = u_i1 − u_o1 rises and r₁ = u_i2 − u_o2 falls all the way (the construction's check).
    for k in 0..=1000 {
        let z = at(s2 * k as f64 / 1000.0);
        assert!(z[5] - z[4] > 0.0 && z[7] - z[6] < 0.0);
    }
    let (z1, z2) = (at(s1), at(s2));
    let gap0 = z1[1] - z1[0];
    let gap1 = -(z2[3] - z2[2]);
    let cells = vec![
        CellParameters {
            stops: Some(CellStops {
                gap_plus: gap0,
                gap_minus: 1.0,
                restitution: 0.8,
            }),
            ..base_cells[0]
        },
        CellParameters {
            stops: Some(CellStops {
                gap_plus: 1.0,
                gap_minus: gap1,
                restitution: 0.6,
            }),
            ..base_cells[1]
        },
    ];
    let model = Model::chain(&cells, BASE_AMPLITUDE, omega).unwrap();
    let start = Start {
        state: DVector::from_column_slice(&y0),
        time: 0.0,
    };
    let trajectory = sample_trajectory(&model, omega, &start, &trajectory_options(1, 200)).unwrap();
    let first: Vec<&TrajectoryImpact> = trajectory.impacts.iter().take(2).collect();
    assert_eq!(first.len(), 2);
    let root = SimulationOptions::default().root_tolerance * period;
    // In time order, ties by pair index: pair 0 at s₁, then pair 1 at s₂, each to the root
    // tolerance (plus rounding of the time).
    assert_eq!((first[0].pair, first[0].side), (0, 1));
    assert_eq!((first[1].pair, first[1].side), (1, -1));
    assert!(first[0].time <= first[1].time);
    for (impact, exact) in first.iter().zip([s1, s2]) {
        assert!(
            (impact.time - exact).abs() <= root + 4.0 * EPS * exact,
            "pair {}: impact at {} against {exact} (|Δ| = {:e})",
            impact.pair,
            impact.time,
            (impact.time - exact).abs()
        );
    }
    // Each impact's velocities against the exact pre-impact velocities of the flow.
    let z_exact = [&z1, &z2];
    for (impact, z) in first.iter().zip(z_exact) {
        let j = impact.pair;
        let exact_rdot = z[4 + 2 * j + 1] - z[4 + 2 * j];
        assert!(
            (impact.relative_velocity_before - exact_rdot).abs()
                <= 1e-10 * exact_rdot.abs() + 4.0 * root * a.norm() * z.norm(),
            "pair {j}: ṙ⁻ = {} against {exact_rdot}",
            impact.relative_velocity_before
        );
    }
    check_within_stops(&trajectory, &model);
    let (impacts, _) = check_impact_law(&trajectory, &cells);
    assert!(impacts >= 2);
}

#[test]
fn one_pair_held_while_another_flies_and_both_are_watched() {
    // Cell 1 plastic (e = 0) is sent onto its side-1 stop while its outer mass is far out
    // (u_o1 = 3: the springs pull the outer mass back hard, pressing the inner mass onto the
    // stop); cell 2 (e = 0.8) rattles fast between its stops. Cell 2 must impact while cell 1
    // is held, and never pass its stops; cell 1 stays on its stop (r = Δ, ṙ = 0) while held.
    let omega = 1.0;
    let gap = 0.25;
    let cells = vec![
        paper_cell(Some(LIGHT_DAMPING), Some(CellStops::symmetric(gap, 0.0))),
        paper_cell(Some(LIGHT_DAMPING), Some(CellStops::symmetric(gap, 0.8))),
    ];
    let model = Model::chain(&cells, BASE_AMPLITUDE, omega).unwrap();
    let y0 = [3.0, 3.2, 0.0, 0.0, 0.0, 1.0, 0.0, 4.0];
    let start = Start {
        state: DVector::from_column_slice(&y0),
        time: 0.0,
    };
    let trajectory =
        sample_trajectory(&model, omega, &start, &trajectory_options(3, 2000)).unwrap();
    check_within_stops(&trajectory, &model);
    check_impact_law(&trajectory, &cells);
    // The hold: from pair 0's first stick to the first row where it has left the stop.
    let stick = trajectory
        .rows
        .iter()
        .position(|r| r.kind == RowKind::AfterStick && (r.relative[0] - gap).abs() < 1e-9)
        .expect("pair 0 sticks");
    let stuck_at = trajectory.rows[stick].time;
    // While held: r₀ = Δ and ṙ₀ = 0 to rounding of the state (16ε of the motion's scale).
    let scale = 16.0 * EPS * 10.0;
    let held_until = trajectory.rows[stick..]
        .iter()
        .find(|r| (r.relative[0] - gap).abs() > scale)
        .map_or(f64::INFINITY, |r| r.time);
    assert!(held_until > stuck_at);
    let held_rows = trajectory.rows[stick..]
        .iter()
        .filter(|r| r.time < held_until)
        .count();
    assert!(held_rows > 10, "held for only {held_rows} rows");
    for r in trajectory.rows[stick..]
        .iter()
        .filter(|r| r.time < held_until)
    {
        assert!((r.velocities[1] - r.velocities[0]).abs() <= scale);
    }
    let during: Vec<&TrajectoryImpact> = trajectory
        .impacts
        .iter()
        .filter(|i| i.pair == 1 && i.time > stuck_at && i.time < held_until)
        .collect();
    assert!(
        during.len() >= 2,
        "pair 1 impacted {} times while pair 0 was held",
        during.len()
    );
}

#[test]
fn chain_validation_names_the_cell_and_the_field() {
    let good = paper_cell(None, Some(CellStops::symmetric(0.5, 0.8)));
    let mut bad = good;
    bad.inner_stiffness = -1.0;
    let err = Model::chain(&[good, bad], 1.0, 1.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("cells[1].inner_stiffness"), "{err}");
    let mut bad = good;
    bad.stops = Some(CellStops {
        gap_plus: 0.5,
        gap_minus: 0.5,
        restitution: 1.5,
    });
    let err = Model::chain(&[bad], 1.0, 1.0).unwrap_err().to_string();
    assert!(err.contains("cells[0].stops.restitution"), "{err}");
    let mut bad = good;
    bad.stops = Some(CellStops {
        gap_plus: 0.5,
        gap_minus: 0.0,
        restitution: 0.5,
    });
    let err = Model::chain(&[good, good, bad], 1.0, 1.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("cells[2].stops.gap_minus"), "{err}");
    let err = Model::chain(&[], 1.0, 1.0).unwrap_err().to_string();
    assert!(err.contains("cells"), "{err}");
    assert!(Model::chain(&vec![good; MAX_CELLS + 1], 1.0, 1.0).is_err());
    assert!(Model::chain(&vec![good; MAX_CELLS], 1.0, 1.0).is_ok());
    let err = Model::chain(&[good], 1.0, f64::NAN)
        .unwrap_err()
        .to_string();
    assert!(err.contains("omega"), "{err}");
}

#[test]
fn tangent_tools_run_on_chains() {
    // Newton, Lyapunov and trajectories on a three-cell chain: they must return (Newton may
    // refuse a sticking run, as for the unit), never panic; a bouncing chain's exponents sum
    // to tr A + 2 ln(e) × impacts per second when nothing sticks (tests/lyapunov.rs).
    let omega = 2.0;
    for e in [0.8, 0.0] {
        let model = paper_chain(
            3,
            omega,
            Some(LIGHT_DAMPING),
            Some(CellStops::symmetric(0.5, e)),
        );
        let options = SimulationOptions {
            max_periods: 300,
            ..SimulationOptions::default()
        };
        let steady = simulate(&model, omega, &Start::rest(6), &options).unwrap();
        let _ = periodic_orbit(&model, omega, &steady.final_state, 1, &options);
        let lyapunov = LyapunovOptions {
            periods: 64,
            alignment_periods: 8,
            simulation: options.clone(),
        };
        let spectrum = lyapunov_exponents(&model, omega, &steady.final_state, &lyapunov);
        if let Ok(s) = spectrum {
            assert_eq!(s.exponents.len() + s.collapsed, 12);
        }
        let trajectory = sample_trajectory(
            &model,
            omega,
            &steady.final_state,
            &trajectory_options(2, 50),
        )
        .unwrap();
        check_within_stops(&trajectory, &model);
    }
}
