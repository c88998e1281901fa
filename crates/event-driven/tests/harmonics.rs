//! Forcing with higher harmonics (`f(t) = Σ_k f_c,k cos kωt + f_s,k sin kωt`), each test model
//! with its exact answer worked out here: a model forced only by its second harmonic at `ω`
//! is the one-harmonic model at `2ω`; a damped linear model settles on the sum of the
//! harmonics' exact steady responses; an undamped model driven at resonance by its second
//! harmonic follows the secular solution; a harmonic of zero amplitude changes nothing; the
//! tangent flow is the stroboscopic map's derivative; bad harmonics are refused.

use nalgebra::{Complex, DMatrix, DVector};
use rattle_event_driven::LinearFlow;
use rattle_event_driven::*;

type C64 = Complex<f64>;

/// The paper's unit's matrices (`m_o = 2`, `m_i = 1`, `k_o = 6`, `k_i = 3`) with dashpots
/// `(c_o, c_i)` (`None`: no damping terms).
fn unit_matrices(
    damping: Option<(f64, f64)>,
) -> (DMatrix<f64>, DMatrix<f64>, Option<DMatrix<f64>>) {
    let mass = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 1.0]);
    let stiffness = DMatrix::from_row_slice(2, 2, &[9.0, -3.0, -3.0, 3.0]);
    let damping = damping.map(|(co, ci)| DMatrix::from_row_slice(2, 2, &[co + ci, -ci, -ci, ci]));
    (mass, stiffness, damping)
}

/// The unit's stops: `r = u_i − u_o ∈ [−gap, gap]`, restitution `e`.
fn unit_stops(gap: f64, e: f64) -> Vec<ContactPair> {
    vec![ContactPair {
        plus_dof: Some(1),
        minus_dof: Some(0),
        gap_plus: gap,
        gap_minus: gap,
        restitution: e,
    }]
}

/// A physical system forced at rate `rate` by `(f_c, f_s)`, built two ways: with that forcing
/// as its fundamental at `ω = rate`, and with it as the second harmonic of a model at
/// `ω = rate/2` whose fundamental is zero.
struct Twin {
    /// The one-harmonic model, simulated at `rate`.
    single: Model,
    /// The second-harmonic model, simulated at `rate/2`.
    second: Model,
    rate: f64,
}

impl Twin {
    fn new(
        (mass, stiffness, damping): (DMatrix<f64>, DMatrix<f64>, Option<DMatrix<f64>>),
        (cos, sin): (DVector<f64>, DVector<f64>),
        contacts: Vec<ContactPair>,
        rate: f64,
    ) -> Twin {
        let n = mass.nrows();
        let single = Model::new(
            mass.clone(),
            stiffness.clone(),
            damping.clone(),
            cos.clone(),
            sin.clone(),
            contacts.clone(),
        )
        .unwrap();
        let second = Model::new(
            mass,
            stiffness,
            damping,
            DVector::zeros(n),
            DVector::zeros(n),
            contacts,
        )
        .unwrap()
        .with_harmonics(vec![Harmonic { order: 2, cos, sin }])
        .unwrap();
        Twin {
            single,
            second,
            rate,
        }
    }

    /// The paper's unit (base motion `cos(rate·t)` through `k_o`, `c_o`) with stops.
    fn unit(rate: f64, damping: (f64, f64), gap: f64, e: f64) -> Twin {
        let cos = DVector::from_vec(vec![6.0, 0.0]);
        let sin = DVector::from_vec(vec![-damping.0 * rate, 0.0]);
        Twin::new(
            unit_matrices(Some(damping)),
            (cos, sin),
            unit_stops(gap, e),
            rate,
        )
    }

    /// A free body (a ball of mass 1, held by nothing: a rigid mode) in a clearance `±gap` of
    /// a damped oscillator (`m = 2`, `k = 6`, `c = 0.1`), both forced.
    fn free_body(rate: f64, gap: f64, e: f64) -> Twin {
        let mass = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 1.0]);
        let stiffness = DMatrix::from_row_slice(2, 2, &[6.0, 0.0, 0.0, 0.0]);
        let damping = DMatrix::from_row_slice(2, 2, &[0.1, 0.0, 0.0, 0.0]);
        let cos = DVector::from_vec(vec![6.0, 0.2]);
        let sin = DVector::from_vec(vec![-0.1 * rate, 0.06]);
        Twin::new(
            (mass, stiffness, Some(damping)),
            (cos, sin),
            unit_stops(gap, e),
            rate,
        )
    }
}

fn fixed(periods: u64) -> SimulationOptions {
    SimulationOptions {
        fixed_periods: Some(periods),
        polish: false,
        ..SimulationOptions::default()
    }
}

fn trajectory(model: &Model, omega: f64, periods: u64, start: &Start) -> Trajectory {
    let options = TrajectoryOptions {
        periods,
        samples_per_period: 8,
        base_amplitude: 0.0,
        simulation: SimulationOptions::default(),
    };
    sample_trajectory(model, omega, start, &options).unwrap()
}

/// Largest `|a_i − b_i|`.
fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .fold(0.0, |m: f64, (x, y)| m.max((x - y).abs()))
}

/// The same seconds of motion from rest: the second-harmonic model over `periods` periods of
/// `rate/2`, the one-harmonic model over twice as many of `rate`. Returns the impacts compared
/// and the sticks, and the largest time and state differences (the state relative to its
/// largest entry).
fn compare_runs(twin: &Twin, periods: u64) -> (usize, usize, f64, f64) {
    let n = twin.single.dofs();
    let start = Start::rest(n);
    let a = trajectory(&twin.second, twin.rate / 2.0, periods, &start);
    let b = trajectory(&twin.single, twin.rate, 2 * periods, &start);
    assert_eq!(a.impacts.len(), b.impacts.len(), "impact counts");
    assert!(!a.impacts.is_empty(), "the runs impact");
    let (mut dt, mut dy, mut size) = (0.0f64, 0.0f64, 0.0f64);
    for (x, y) in a.impacts.iter().zip(&b.impacts) {
        assert_eq!((x.pair, x.side), (y.pair, y.side));
        dt = dt.max((x.time - y.time).abs());
        dy = dy
            .max(max_difference(&x.displacements, &y.displacements))
            .max(max_difference(&x.velocities_before, &y.velocities_before));
        size = x
            .displacements
            .iter()
            .chain(&x.velocities_before)
            .fold(size, |m, v| m.max(v.abs()));
    }
    // The end states, at the same absolute time.
    let (end_a, end_b) = (a.rows.last().unwrap(), b.rows.last().unwrap());
    assert!((end_a.time - end_b.time).abs() <= 1e-9 * end_a.time);
    dy = dy
        .max(max_difference(&end_a.displacements, &end_b.displacements))
        .max(max_difference(&end_a.velocities, &end_b.velocities));
    let sticks = |t: &Trajectory| {
        t.rows
            .iter()
            .filter(|r| r.kind == RowKind::AfterStick)
            .count()
    };
    assert_eq!(sticks(&a), sticks(&b), "sticks");
    (a.impacts.len(), sticks(&a), dt, dy / size.max(1.0))
}

#[test]
fn a_second_harmonic_at_omega_is_the_fundamental_at_twice_omega() {
    let tolerance = DEFAULT_ROOT_TOLERANCE;
    for (name, twin, periods) in [
        ("unit, e = 0.8", Twin::unit(2.0, (0.1, 0.05), 0.5, 0.8), 20),
        (
            "unit, e = 0 (sticks)",
            Twin::unit(2.0, (0.1, 0.05), 0.5, 0.0),
            20,
        ),
        // Chaotic: rounding grows tenfold every few impacts, so a short stretch only.
        ("free body", Twin::free_body(2.0, 0.5, 0.8), 3),
    ] {
        let (impacts, sticks, dt, dy) = compare_runs(&twin, periods);
        let period = std::f64::consts::TAU / (twin.rate / 2.0);
        println!(
            "{name}: {impacts} impacts, {sticks} sticks, |Δt| ≤ {dt:.2e} s, |Δy| ≤ {dy:.2e} \
             (relative)"
        );
        assert_eq!(
            sticks > 0,
            name.contains("sticks"),
            "{name}: {sticks} sticks"
        );
        assert!(dt <= tolerance * period, "{name}: times differ by {dt:e}");
        assert!(dy <= tolerance, "{name}: states differ by {dy:e}");
    }
}

/// Eigenvalues sorted by real then imaginary part.
fn sorted(mut values: Vec<C64>) -> Vec<C64> {
    values.sort_by(|a, b| a.re.total_cmp(&b.re).then(a.im.total_cmp(&b.im)));
    values
}

#[test]
fn a_period_one_orbit_of_the_second_harmonic_is_the_period_two_orbit_at_twice_omega() {
    let twin = Twin::unit(2.0, (0.1, 0.05), 0.5, 0.8);
    for section in [0.3, 1.1] {
        let options = SimulationOptions::default();
        // Sections off `t = 0`: the second-harmonic model's forcing is shifted by `2ω·t₀`.
        let rest = Start {
            time: section,
            ..Start::rest(2)
        };
        let steady = simulate(&twin.single, twin.rate, &rest, &options).unwrap();
        assert_eq!(
            steady.status,
            Status::Periodic,
            "the one-harmonic run settles"
        );
        let guess = steady.final_state.clone();
        let b = periodic_orbit(&twin.single, twin.rate, &guess, 2, &options).unwrap();
        let a = periodic_orbit(&twin.second, twin.rate / 2.0, &guess, 1, &options).unwrap();
        let scale = b.state.amax();
        let dy = (&a.state - &b.state).amax() / scale;
        let (ma, mb) = (
            sorted(a.floquet_multipliers.clone()),
            sorted(b.floquet_multipliers.clone()),
        );
        let dm = ma
            .iter()
            .zip(&mb)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).norm()));
        println!(
            "orbit: |Δy| = {dy:.2e} relative, |Δμ| = {dm:.2e}, multipliers {mb:?}, impacts {:?}",
            a.impact_sides
        );
        assert_eq!(a.impact_sides, b.impact_sides);
        assert!(
            dy <= 10.0 * options.root_tolerance,
            "orbits differ by {dy:e}"
        );
        assert!(dm <= 1e-9, "multipliers differ by {dm:e}");
    }
}

/// `u(t) = Σ_k Re(X_k e^{ikωt})` and `u̇(t)`, `X_k = (K − (kω)²M + ikωC)⁻¹ (f_c,k − i f_s,k)`:
/// the exact steady response of a damped linear model to its harmonics `(k, f_c,k, f_s,k)`.
fn exact_steady_state(
    (mass, stiffness, damping): (&DMatrix<f64>, &DMatrix<f64>, &DMatrix<f64>),
    harmonics: &[(u32, DVector<f64>, DVector<f64>)],
    omega: f64,
    t: f64,
) -> DVector<f64> {
    let n = mass.nrows();
    let mut y = DVector::zeros(2 * n);
    for (k, cos, sin) in harmonics {
        let w = *k as f64 * omega;
        let z = DMatrix::from_fn(n, n, |i, j| {
            C64::new(
                stiffness[(i, j)] - w * w * mass[(i, j)],
                w * damping[(i, j)],
            )
        });
        let f = DVector::from_fn(n, |i, _| C64::new(cos[i], -sin[i]));
        let x = z.lu().solve(&f).unwrap();
        let phase = C64::new((w * t).cos(), (w * t).sin());
        for i in 0..n {
            y[i] += (x[i] * phase).re;
            y[n + i] += (x[i] * phase * C64::new(0.0, w)).re;
        }
    }
    y
}

#[test]
fn a_damped_linear_model_settles_on_the_sum_of_the_exact_harmonic_responses() {
    let omega = 1.3;
    let (mass, stiffness, damping) = unit_matrices(Some((0.8, 0.3)));
    let damping = damping.unwrap();
    let harmonics = [
        (
            1,
            DVector::from_vec(vec![6.0, 0.0]),
            DVector::from_vec(vec![-1.04, 0.0]),
        ),
        (
            3,
            DVector::from_vec(vec![0.5, 0.2]),
            DVector::from_vec(vec![0.0, -0.3]),
        ),
        (
            2,
            DVector::from_vec(vec![0.0, 0.7]),
            DVector::from_vec(vec![0.25, 0.0]),
        ),
    ];
    let model = Model::new(
        mass.clone(),
        stiffness.clone(),
        Some(damping.clone()),
        harmonics[0].1.clone(),
        harmonics[0].2.clone(),
        Vec::new(),
    )
    .unwrap()
    .with_harmonics(
        harmonics[1..]
            .iter()
            .map(|(k, c, s)| Harmonic {
                order: *k,
                cos: c.clone(),
                sin: s.clone(),
            })
            .collect(),
    )
    .unwrap();
    // From rest, long enough for the transients (slowest decay ≈ 0.09/s) to fall below
    // rounding.
    let settled = simulate(&model, omega, &Start::rest(2), &fixed(200)).unwrap();
    let matrices = (&mass, &stiffness, &damping);
    let start = settled.final_state;
    let run = trajectory(&model, omega, 1, &start);
    let mut worst = 0.0f64;
    let mut size = 0.0f64;
    for row in &run.rows {
        let exact = exact_steady_state(matrices, &harmonics, omega, start.time + row.time);
        let got: Vec<f64> = row
            .displacements
            .iter()
            .chain(&row.velocities)
            .copied()
            .collect();
        worst = worst.max(max_difference(&got, exact.as_slice()));
        size = size.max(exact.amax());
    }
    println!(
        "linear steady state: {} samples, relative error {:.2e}",
        run.rows.len(),
        worst / size
    );
    assert!(worst <= 1e-12 * size, "relative error {:e}", worst / size);
    // The flow's own linear steady state is the same sum.
    let flow_start = Start::linear_steady_state(&model, omega).unwrap();
    let exact = exact_steady_state(matrices, &harmonics, omega, 0.0);
    let error = (&flow_start.state - &exact).amax() / exact.amax();
    println!("Start::linear_steady_state: relative error {error:.2e}");
    assert!(error <= 1e-13);
}

/// `x(t)` and `ẋ(t)` of `ẍ + w² x = G cos t + F_c cos wt + F_s sin wt` from rest (`ω = 1`, the
/// second harmonic at `2ω = w`):
/// `x = F_c t sin wt/(2w) − F_s t cos wt/(2w) + F_s sin wt/(2w²) + G (cos t − cos wt)/(w² − 1)`.
fn secular(t: f64, w: f64, (g, fc, fs): (f64, f64, f64)) -> (f64, f64) {
    let (s, c) = (w * t).sin_cos();
    let x = fc * t * s / (2.0 * w) - fs * t * c / (2.0 * w)
        + fs * s / (2.0 * w * w)
        + g * (t.cos() - c) / (w * w - 1.0);
    let v =
        fc * (s + w * t * c) / (2.0 * w) + fs * t * s / 2.0 + g * (w * s - t.sin()) / (w * w - 1.0);
    (x, v)
}

/// The undamped oscillator `m = 1`, `k = 4` (`w = 2`) forced by `G cos t` and, at `2ω = w`,
/// by `F_c cos 2t + F_s sin 2t`, with a one-sided stop at `x = gap`.
fn resonant_oscillator((g, fc, fs): (f64, f64, f64), gap: f64) -> Model {
    Model::new(
        DMatrix::from_element(1, 1, 1.0),
        DMatrix::from_element(1, 1, 4.0),
        None,
        DVector::from_element(1, g),
        DVector::zeros(1),
        vec![ContactPair {
            plus_dof: Some(0),
            minus_dof: None,
            gap_plus: gap,
            gap_minus: f64::INFINITY,
            restitution: 1.0,
        }],
    )
    .unwrap()
    .with_harmonics(vec![Harmonic {
        order: 2,
        cos: DVector::from_element(1, fc),
        sin: DVector::from_element(1, fs),
    }])
    .unwrap()
}

#[test]
fn an_undamped_model_at_resonance_with_its_second_harmonic_grows_secularly() {
    let forcing = (0.7, 0.5, -0.3);
    let w = 2.0;
    // The flow: in the resonance-safe form, exact at any time into one flight.
    let model = resonant_oscillator(forcing, 1e6);
    let flow = LinearFlow::with_harmonics(
        (
            &DMatrix::from_element(1, 1, 1.0),
            None,
            &DMatrix::from_element(1, 1, 4.0),
        ),
        (
            &DVector::from_element(1, forcing.0),
            &DVector::zeros(1),
            &DVector::zeros(1),
        ),
        model.harmonics(),
        1.0,
    )
    .unwrap();
    assert!(!flow.has_steady_response());
    assert!(matches!(
        flow.linear_steady_state(0.0),
        Err(FlowError::Resonant)
    ));
    let flight = flow.flight(&DVector::zeros(2), 0.0);
    let x = flight.value_of(&DVector::from_vec(vec![1.0, 0.0]));
    let mut worst = 0.0f64;
    for s in [0.3, 1.0, 7.5, 40.0, 200.0] {
        let (xe, ve) = secular(s, w, forcing);
        let y = flight.state(s);
        let size = xe.abs().max(ve.abs()).max(1.0);
        let error = (y[0] - xe)
            .abs()
            .max((y[1] - ve).abs())
            .max((x.eval(s).0 - xe).abs())
            / size;
        worst = worst.max(error);
    }
    println!("secular flight: relative error {worst:.2e}");
    assert!(worst <= 1e-13, "relative error {worst:e}");
    // The simulator, period after period, with a stop too far to reach.
    let run = trajectory(&model, 1.0, 30, &Start::rest(1));
    let mut worst = 0.0f64;
    for row in &run.rows {
        let (xe, ve) = secular(row.time, w, forcing);
        let size = xe.abs().max(ve.abs()).max(1.0);
        worst = worst.max(
            (row.displacements[0] - xe)
                .abs()
                .max((row.velocities[0] - ve).abs())
                / size,
        );
    }
    println!("secular run over 30 periods: relative error {worst:.2e}");
    assert!(worst <= 1e-12, "relative error {worst:e}");
    // The stop at `gap`: the first contact is the first crossing of the exact solution.
    let gap = 5.0;
    let model = resonant_oscillator(forcing, gap);
    let run = trajectory(&model, 1.0, 30, &Start::rest(1));
    let hit = &run.impacts[0];
    let (mut lo, mut step) = (0.0, 1e-3);
    while secular(lo + step, w, forcing).0 < gap {
        lo += step;
    }
    let mut hi = lo + step;
    while hi - lo > 1e-15 * hi {
        let mid = 0.5 * (lo + hi);
        if secular(mid, w, forcing).0 < gap {
            lo = mid;
        } else {
            hi = mid;
        }
        step = hi - lo;
    }
    let _ = step;
    let dt = (hit.time - lo).abs();
    println!(
        "first contact at {:.15} s, exact {lo:.15} s: |Δt| = {dt:.2e}",
        hit.time
    );
    assert!(
        dt <= DEFAULT_ROOT_TOLERANCE * std::f64::consts::TAU,
        "|Δt| = {dt:e}"
    );
}

#[test]
fn a_harmonic_of_zero_amplitude_changes_nothing() {
    let base = Twin::unit(2.0, (0.1, 0.05), 0.5, 0.8);
    let zero = |order| Harmonic {
        order,
        cos: DVector::zeros(2),
        sin: DVector::zeros(2),
    };
    for (model, with_zero) in [
        (
            base.single.clone(),
            base.single.clone().with_harmonics(vec![zero(3)]).unwrap(),
        ),
        (
            base.second.clone(),
            base.second
                .clone()
                .with_harmonics(vec![base.second.harmonics()[0].clone(), zero(5)])
                .unwrap(),
        ),
    ] {
        let omega = if model.harmonics().is_empty() {
            2.0
        } else {
            1.0
        };
        let options = SimulationOptions::default();
        let a = simulate(&model, omega, &Start::rest(2), &options).unwrap();
        let b = simulate(&with_zero, omega, &Start::rest(2), &options).unwrap();
        assert_eq!(a.final_state.state, b.final_state.state);
        assert_eq!(a.impacts, b.impacts);
        assert_eq!(a.orbit, b.orbit);
        let ta = trajectory(&model, omega, 3, &Start::rest(2));
        let tb = trajectory(&with_zero, omega, 3, &Start::rest(2));
        assert_eq!(ta.impacts, tb.impacts);
    }
}

/// The stroboscopic map's Jacobian by central differences, step `h` times each entry's scale.
fn finite_difference_jacobian(
    model: &Model,
    omega: f64,
    start: &Start,
    periods: u32,
) -> DMatrix<f64> {
    let m = start.state.len();
    let options = SimulationOptions::default();
    let mut jacobian = DMatrix::zeros(m, m);
    for j in 0..m {
        let h = 1e-6 * start.state[j].abs().max(1.0);
        let at = |sign: f64| {
            let mut s = start.clone();
            s.state[j] += sign * h;
            stroboscopic_map(model, omega, &s, periods, &options).unwrap()
        };
        let (plus, minus) = (at(1.0), at(-1.0));
        jacobian.set_column(j, &((plus.state - minus.state) / (2.0 * h)));
    }
    jacobian
}

#[test]
fn the_tangent_flow_with_harmonics_is_the_derivative_of_the_stroboscopic_map() {
    let omega = 2.0;
    let (mass, stiffness, damping) = unit_matrices(Some((0.1, 0.05)));
    let model = Model::new(
        mass,
        stiffness,
        damping,
        DVector::from_vec(vec![6.0, 0.0]),
        DVector::from_vec(vec![-0.2, 0.0]),
        unit_stops(0.5, 0.8),
    )
    .unwrap()
    .with_harmonics(vec![
        Harmonic {
            order: 2,
            cos: DVector::from_vec(vec![1.5, 0.3]),
            sin: DVector::from_vec(vec![0.4, 0.0]),
        },
        Harmonic {
            order: 3,
            cos: DVector::from_vec(vec![0.0, 0.2]),
            sin: DVector::from_vec(vec![-0.5, 0.1]),
        },
    ])
    .unwrap();
    let options = SimulationOptions::default();
    let steady = simulate(&model, omega, &Start::rest(2), &options).unwrap();
    let orbit = steady.orbit.as_ref().expect("a polished periodic orbit");
    let start = Start {
        state: orbit.state.clone(),
        time: orbit.time,
    };
    let map = stroboscopic_map(&model, omega, &start, orbit.periods, &options).unwrap();
    assert!(!map.impact_sides.is_empty(), "the cycle impacts");
    let fd = finite_difference_jacobian(&model, omega, &start, orbit.periods);
    let error = (&map.jacobian - &fd).amax() / map.jacobian.amax();
    let multipliers = sorted(fd.complex_eigenvalues().iter().copied().collect());
    let exact = sorted(orbit.floquet_multipliers.clone());
    let dm = multipliers
        .iter()
        .zip(&exact)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).norm()));
    println!(
        "tangent flow: {} impacts per cycle of {} period(s), Jacobian error {error:.2e}, \
         multipliers {exact:?} (finite differences within {dm:.2e})",
        map.impact_sides.len(),
        orbit.periods
    );
    assert!(error <= 1e-6, "Jacobian error {error:e}");
    assert!(dm <= 1e-6, "multipliers differ by {dm:e}");
}

#[test]
fn the_lyapunov_spectrum_of_the_second_harmonic_is_the_fundamentals_at_twice_omega() {
    let twin = Twin::unit(2.0, (0.1, 0.05), 0.5, 0.8);
    let options = |periods: u64, alignment: u64| LyapunovOptions {
        periods,
        alignment_periods: alignment,
        ..LyapunovOptions::default()
    };
    let start = Start::rest(2);
    let a = lyapunov_exponents(&twin.second, 1.0, &start, &options(100, 20)).unwrap();
    let b = lyapunov_exponents(&twin.single, 2.0, &start, &options(200, 40)).unwrap();
    let error = max_difference(&a.exponents, &b.exponents);
    println!(
        "Lyapunov exponents {:?}: differ by {error:.2e}",
        b.exponents
    );
    assert_eq!(a.collapsed, b.collapsed);
    assert!(error <= 1e-9, "exponents differ by {error:e}");
}

#[test]
fn bad_harmonics_are_refused_naming_the_field() {
    let base = || Twin::unit(2.0, (0.1, 0.05), 0.5, 0.8).single;
    let good = |order| Harmonic {
        order,
        cos: DVector::from_vec(vec![1.0, 0.0]),
        sin: DVector::zeros(2),
    };
    let field_of = |harmonics: Vec<Harmonic>| match base().with_harmonics(harmonics) {
        Err(ModelError::OutOfRange { field, allowed, .. }) => (field, allowed),
        other => panic!("not refused: {other:?}"),
    };
    let (field, allowed) = field_of(vec![good(1)]);
    assert_eq!(field, "harmonics[0].order");
    assert!(allowed.contains("2..="), "{allowed}");
    assert_eq!(field_of(vec![good(0)]).0, "harmonics[0].order");
    assert_eq!(
        field_of(vec![good(MAX_HARMONIC_ORDER + 1)]).0,
        "harmonics[0].order"
    );
    let (field, allowed) = field_of(vec![good(2), good(3), good(2)]);
    assert_eq!(field, "harmonics[2].order");
    assert!(allowed.contains("distinct"), "{allowed}");
    let mut short = good(2);
    short.cos = DVector::zeros(3);
    assert_eq!(field_of(vec![short]).0, "harmonics[0].cos");
    let mut short = good(4);
    short.sin = DVector::zeros(1);
    assert_eq!(field_of(vec![good(2), short]).0, "harmonics[1].sin");
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut h = good(2);
        h.sin[1] = bad;
        let (field, allowed) = field_of(vec![h]);
        assert_eq!(field, "harmonics[0].sin[1]");
        assert_eq!(allowed, "finite");
    }
    // Accepted: any order of the orders, an empty list (the model as built).
    assert!(base().with_harmonics(vec![good(5), good(2)]).is_ok());
    assert_eq!(base().with_harmonics(Vec::new()).unwrap(), base());
}
