//! Free bodies (a singular stiffness matrix): the flow of rigid modes against closed forms and
//! an independent matrix exponential, first contacts of a drifting body, a ball bouncing
//! between stops, and an impact damper run to its periodic steady state, polished by Newton,
//! with its Lyapunov spectrum; and the neutral family of a damper whose ball never impacts.

use nalgebra::{DMatrix, DVector};
use rattle_event_driven::LinearFlow;
use rattle_event_driven::SearchStack;
use rattle_event_driven::*;
use std::f64::consts::{PI, TAU};

type C64 = nalgebra::Complex<f64>;

/// The exact state of a free mass `m` under `f_c cos ωt + f_s sin ωt` a time `s` after
/// `(u₀, v₀)` at `t₀`, by integrating `ü = (f_c cos θ + f_s sin θ)/m`, `θ = ω(t₀ + s)`,
/// twice: `v = v₀ + (f_c (sin θ − sin θ₀) − f_s (cos θ − cos θ₀))/(mω)` and
/// `u = u₀ + v₀ s − (f_c (cos θ − cos θ₀ + ωs sin θ₀) + f_s (sin θ − sin θ₀ − ωs cos θ₀))/(mω²)`.
fn free_mass_state(
    (m, omega): (f64, f64),
    (fc, fs): (f64, f64),
    (u0, v0, t0): (f64, f64, f64),
    s: f64,
) -> (f64, f64) {
    let (th0, th) = (omega * t0, omega * (t0 + s));
    let v = v0 + (fc * (th.sin() - th0.sin()) - fs * (th.cos() - th0.cos())) / (m * omega);
    let u = u0 + v0 * s
        - (fc * (th.cos() - th0.cos() + omega * s * th0.sin())
            + fs * (th.sin() - th0.sin() - omega * s * th0.cos()))
            / (m * omega * omega);
    (u, v)
}

#[test]
fn a_free_mass_flies_as_the_closed_form() {
    let (m, omega) = (0.7, 1.3);
    let (fc, fs) = (0.9, -0.4);
    let flow = LinearFlow::new(
        &DMatrix::from_element(1, 1, m),
        None,
        &DMatrix::zeros(1, 1),
        &DVector::from_element(1, fc),
        &DVector::from_element(1, fs),
        &DVector::zeros(1),
        omega,
    )
    .expect("a free mass has a flow");
    assert_eq!(flow.rigid_modes(), 1);
    let mut worst: f64 = 0.0;
    for &(u0, v0, t0) in &[(0.2, -0.3, 0.0), (-1.0, 0.05, 1.1), (0.0, 0.0, 4.0)] {
        let flight = flow.flight(&DVector::from_vec(vec![u0, v0]), t0);
        for s in [0.0, 0.01, 0.9, 3.3, 12.5] {
            let y = flight.state(s);
            let (u, v) = free_mass_state((m, omega), (fc, fs), (u0, v0, t0), s);
            let scale = u.abs().max(v.abs()).max(1.0);
            let error = (y[0] - u).abs().max((y[1] - v).abs()) / scale;
            worst = worst.max(error);
            assert!(
                error < 1e-13,
                "s = {s}: {y:?} against ({u}, {v}): {error:e}"
            );
        }
        // The position as an exponential sum is the same function.
        let c = DVector::from_vec(vec![1.0, 0.0]);
        let sum = flight.value_of(&c);
        for s in [0.3, 7.0] {
            let (u, _) = free_mass_state((m, omega), (fc, fs), (u0, v0, t0), s);
            assert!((sum.eval(s).0 - u).abs() < 1e-13 * u.abs().max(1.0));
        }
    }
    eprintln!("free mass: worst relative error {worst:e}");
}

/// `e^{B s}` by a Taylor series of degree 30 on `B s / 2^j` (`‖Bs‖/2^j ≤ 1/2`), squared `j`
/// times: independent of the flow's modal form.
fn expm(b: &DMatrix<f64>, s: f64) -> DMatrix<f64> {
    let scaled = b * s;
    let norm = scaled.amax() * scaled.nrows() as f64;
    let mut squarings = 0;
    while norm / 2f64.powi(squarings) > 0.5 {
        squarings += 1;
    }
    let x = scaled / 2f64.powi(squarings);
    let n = b.nrows();
    let mut sum = DMatrix::identity(n, n);
    let mut term = DMatrix::identity(n, n);
    for k in 1..=30 {
        term = &term * &x / k as f64;
        sum += &term;
    }
    for _ in 0..squarings {
        sum = &sum * &sum;
    }
    sum
}

/// `M`, `K`, `C`, `f_c`, `f_s` of a structure.
type Structure = (
    DMatrix<f64>,
    DMatrix<f64>,
    DMatrix<f64>,
    DVector<f64>,
    DVector<f64>,
);

/// A structure with a rigid mode beside elastic ones, under a forcing on every mass: masses 0
/// and 1 (of different masses) tied to each other only (spring 2, dashpot 0.1), so that their
/// common translation is rigid and their relative motion elastic, and mass 2 on a spring and
/// a dashpot to the frame.
fn mixed_model() -> Structure {
    let mass = DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 0.5, 2.0]));
    let spring = |k: &mut DMatrix<f64>, i: usize, j: Option<usize>, v: f64| {
        k[(i, i)] += v;
        if let Some(j) = j {
            k[(j, j)] += v;
            k[(i, j)] -= v;
            k[(j, i)] -= v;
        }
    };
    let mut k = DMatrix::zeros(3, 3);
    spring(&mut k, 0, Some(1), 2.0);
    spring(&mut k, 2, None, 3.0);
    let mut c = DMatrix::zeros(3, 3);
    spring(&mut c, 0, Some(1), 0.1);
    spring(&mut c, 2, None, 0.05);
    let fc = DVector::from_vec(vec![0.5, 0.0, 1.0]);
    let fs = DVector::from_vec(vec![0.0, -0.3, 0.2]);
    (mass, k, c, fc, fs)
}

#[test]
fn a_mixed_structure_flies_as_the_augmented_exponential() {
    let omega = 1.1;
    let (mass, k, c, fc, fs) = mixed_model();
    let flow = LinearFlow::new(&mass, Some(&c), &k, &fc, &fs, &DVector::zeros(3), omega)
        .expect("the mixed structure has a flow");
    assert_eq!(flow.rigid_modes(), 1);
    // The augmented system: z = (u, v, cos ωt, sin ωt), ż = B z.
    let n = 3;
    let minv = mass.clone().try_inverse().unwrap();
    let mut b = DMatrix::zeros(2 * n + 2, 2 * n + 2);
    b.view_mut((0, n), (n, n)).fill_with_identity();
    b.view_mut((n, 0), (n, n)).copy_from(&(-(&minv * &k)));
    b.view_mut((n, n), (n, n)).copy_from(&(-(&minv * &c)));
    b.view_mut((n, 2 * n), (n, 1)).copy_from(&(&minv * &fc));
    b.view_mut((n, 2 * n + 1), (n, 1)).copy_from(&(&minv * &fs));
    b[(2 * n, 2 * n + 1)] = -omega;
    b[(2 * n + 1, 2 * n)] = omega;
    let y0 = DVector::from_vec(vec![0.3, -0.2, 0.1, 0.05, 0.4, -0.6]);
    let mut worst: f64 = 0.0;
    for t0 in [0.0, 0.8] {
        let flight = flow.flight(&y0, t0);
        let mut z0 = DVector::zeros(2 * n + 2);
        z0.rows_mut(0, 2 * n).copy_from(&y0);
        z0[2 * n] = (omega * t0).cos();
        z0[2 * n + 1] = (omega * t0).sin();
        for s in [0.0, 0.4, 2.5, 9.0] {
            let exact = expm(&b, s) * &z0;
            let y = flight.state(s);
            let scale = exact.rows(0, 2 * n).amax().max(1.0);
            let error = (y - exact.rows(0, 2 * n)).amax() / scale;
            worst = worst.max(error);
            assert!(error < 1e-12, "t0 = {t0}, s = {s}: {error:e}");
        }
    }
    // The propagator is `e^{As}` (the augmented exponential's first block).
    for s in [0.3, 4.0] {
        let exact = expm(&b, s).view((0, 0), (2 * n, 2 * n)).into_owned();
        let error = (flow.propagator(s) - &exact).amax() / exact.amax().max(1.0);
        worst = worst.max(error);
        assert!(error < 1e-12, "propagator at s = {s}: {error:e}");
    }
    eprintln!("mixed structure: worst relative error {worst:e}");
}

/// A unit free mass under `cos 2t` from `(u₀, v₀)` at `t = 0`: `u(s) = u₀ + v₀ s +
/// (1 − cos 2s)/4` (the closed form above with `m = 1`, `ω = 2`, `f_c = 1`).
fn drifting_mass(forcing: f64) -> LinearFlow {
    LinearFlow::new(
        &DMatrix::from_element(1, 1, 1.0),
        None,
        &DMatrix::zeros(1, 1),
        &DVector::from_element(1, forcing),
        &DVector::zeros(1),
        &DVector::zeros(1),
        2.0,
    )
    .expect("a free mass has a flow")
}

/// The first exit of the position from `(−∞, gap)` over a flight from `(u₀, v₀)`.
fn first_contact(flow: &LinearFlow, (u0, v0): (f64, f64), gap: f64, horizon: f64) -> Option<f64> {
    let sum = flow
        .flight(&DVector::from_vec(vec![u0, v0]), 0.0)
        .value_of(&DVector::from_vec(vec![1.0, 0.0]));
    let mut stack = SearchStack::default();
    sum.first_exit(
        f64::NEG_INFINITY,
        gap,
        horizon,
        1e-13,
        1e-12 * gap,
        &mut stack,
    )
    .map(|(s, side)| {
        assert_eq!(side, 1);
        s
    })
}

/// `u(s) = u₀ + v₀ s + (1 − cos 2s)/4`, the drifting mass's position.
fn drifting_position((u0, v0): (f64, f64), s: f64) -> f64 {
    u0 + v0 * s + 0.25 * (1.0 - (2.0 * s).cos())
}

#[test]
fn a_mass_at_constant_velocity_reaches_the_stop_at_gap_over_speed() {
    let flow = drifting_mass(0.0);
    for (gap, v) in [(0.75, 0.3), (1e-3, 2.0), (4.0, 1e-2)] {
        let s = first_contact(&flow, (0.0, v), gap, 1000.0).expect("a contact");
        let exact = gap / v;
        assert!((s - exact).abs() <= 1e-12 * exact, "{s} against {exact}");
    }
    // Moving away: no contact.
    assert_eq!(first_contact(&flow, (0.0, -0.3), 0.75, 1000.0), None);
}

#[test]
fn a_drifting_oscillation_finds_its_first_crossing_and_no_graze() {
    let flow = drifting_mass(1.0);
    let (v0, gap) = (-0.1, 0.5);
    // u' = v₀ + sin(2s)/2 vanishes at sin 2s = 0.2: the first maximum at s* = (π − asin 0.2)/2.
    let peak = 0.5 * (PI - (0.2f64).asin());
    let bump = |u0: f64| drifting_position((u0, v0), peak) - u0;
    // Crosses up at s₁ = 1.2 (rising there), back down after the peak, and stays below the
    // stop up to the horizon: the first crossing is s₁.
    let s1 = 1.2;
    let u0 = gap - (drifting_position((0.0, v0), s1));
    let s = first_contact(&flow, (u0, v0), gap, 3.0).expect("a crossing");
    assert!((s - s1).abs() < 1e-12, "{s} against {s1}");
    // The peak a part in 10⁹ of the gap below the stop: a tangency without crossing.
    let below = gap * (1.0 - 1e-9) - bump(0.0);
    assert_eq!(first_contact(&flow, (below, v0), gap, 3.0), None);
    // ... and as far above: two crossings 6.4e-5 apart, the first found.
    let above = gap * (1.0 + 1e-9) - bump(0.0);
    let s = first_contact(&flow, (above, v0), gap, 3.0).expect("a crossing near the peak");
    // The exact first root, by bisection on the rising side [s₁, s*].
    let (mut a, mut b) = (s1, peak);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if drifting_position((above, v0), m) < gap {
            a = m;
        } else {
            b = m;
        }
    }
    assert!(peak - a > 1e-5, "two distinct crossings");
    assert!((s - a).abs() < 1e-11, "{s} against {a}");
}

/// A unit ball between frame stops at `±1`, elastic (`e = 1`), unforced.
fn bouncing_ball() -> Model {
    Model::new(
        DMatrix::from_element(1, 1, 1.0),
        DMatrix::zeros(1, 1),
        None,
        DVector::zeros(1),
        DVector::zeros(1),
        vec![ContactPair {
            plus_dof: Some(0),
            minus_dof: None,
            gap_plus: 1.0,
            gap_minus: 1.0,
            restitution: 1.0,
        }],
    )
    .expect("the ball's model")
}

#[test]
fn a_ball_bounces_between_stops_at_the_exact_times() {
    let model = bouncing_ball();
    let (omega, v) = (1.0, 0.3);
    let start = Start {
        state: DVector::from_vec(vec![0.0, v]),
        time: 0.0,
    };
    let periods = 5;
    let map = stroboscopic_map(
        &model,
        omega,
        &start,
        periods,
        &SimulationOptions::default(),
    )
    .expect("the ball's map");
    // From the middle at speed v: the first stop after 1/v, then one every 2/v.
    let end = periods as f64 * TAU;
    let exact: Vec<f64> = (0..)
        .map(|k| (1.0 + 2.0 * k as f64) / v)
        .take_while(|&t| t < end)
        .collect();
    assert_eq!(map.impact_times.len(), exact.len());
    // Each contact time to the root tolerance `1e-12 T`.
    let tolerance = 1e-12 * TAU;
    let mut worst: f64 = 0.0;
    for (t, e) in map.impact_times.iter().zip(&exact) {
        worst = worst.max((t - e).abs());
        assert!((t - e).abs() <= tolerance, "{t} against {e}");
    }
    eprintln!("ball: worst impact time error {worst:e}");
    let sides: Vec<i8> = (0..exact.len())
        .map(|k| if k % 2 == 0 { 1 } else { -1 })
        .collect();
    assert_eq!(map.impact_sides, sides);
    // The state at the end: moving at ±v from the last stop.
    let last = *exact.last().unwrap();
    let sign = if exact.len() % 2 == 0 { 1.0 } else { -1.0 };
    let position = -sign + sign * v * (end - last);
    assert!(
        (map.state[0] - position).abs() < 1e-11,
        "{} against {position}",
        map.state[0]
    );
    assert!((map.state[1] - sign * v).abs() < 1e-14);
}

/// The impact damper: a primary mass `m₁ = 1` on a spring `k = 1` and a dashpot `c = 0.05`
/// to the frame, forced by `cos ωt`, and a free mass `m₂ = 0.1` in a clearance `±clearance`
/// of the primary (`r = u₂ − u₁`), restitution `e = 0.6`.
fn impact_damper(clearance: f64) -> Model {
    Model::new(
        DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 0.1])),
        DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 0.0]),
        Some(DMatrix::from_row_slice(2, 2, &[0.05, 0.0, 0.0, 0.0])),
        DVector::from_vec(vec![1.0, 0.0]),
        DVector::zeros(2),
        vec![ContactPair {
            plus_dof: Some(1),
            minus_dof: Some(0),
            gap_plus: clearance,
            gap_minus: clearance,
            restitution: 0.6,
        }],
    )
    .expect("the damper's model")
}

/// The damper's steady cycle: clearance 5 at ω = 1.1, period one with two impacts (one on
/// each side), from rest.
const DAMPER: (f64, f64) = (5.0, 1.1);

#[test]
fn the_impact_damper_settles_polishes_and_has_its_floquet_exponents() {
    let (clearance, omega) = DAMPER;
    let model = impact_damper(clearance);
    assert_eq!(model.rigid_modes(), Ok(1));
    let options = SimulationOptions::default();
    let steady = simulate(&model, omega, &Start::rest(2), &options).expect("the damper runs");
    assert_eq!(steady.status, Status::Periodic);
    assert_eq!(steady.period, Some(1));
    assert!(!steady.family && !steady.sticking);
    assert_eq!(steady.impacts_per_period, 2.0);
    let sides: Vec<i8> = steady.cycle_impacts.iter().map(|i| i.side).collect();
    assert!(sides.contains(&1) && sides.contains(&-1), "{sides:?}");
    let orbit = steady.orbit.as_deref().expect("Newton polishes the cycle");
    // The residual at rounding: well below the root tolerance it is asked for.
    assert!(orbit.residual < 1e-14, "residual {:e}", orbit.residual);
    eprintln!(
        "damper: residual {:e} after {} steps",
        orbit.residual, orbit.iterations
    );
    // The map through the orbit and its Jacobian against central differences.
    let start = Start {
        state: orbit.state.clone(),
        time: orbit.time,
    };
    let map = stroboscopic_map(&model, omega, &start, 1, &options).expect("the map");
    assert!((&map.state - &orbit.state).amax() < 1e-12 * orbit.state.amax());
    let h = 1e-6;
    let mut worst: f64 = 0.0;
    for j in 0..4 {
        let at = |sign: f64| {
            let mut state = orbit.state.clone();
            state[j] += sign * h;
            let moved = Start {
                state,
                time: orbit.time,
            };
            let image = stroboscopic_map(&model, omega, &moved, 1, &options).expect("the map");
            assert_eq!(image.impact_sides, map.impact_sides);
            image.state
        };
        let column = (at(1.0) - at(-1.0)) / (2.0 * h);
        let error = (column - map.jacobian.column(j)).amax();
        worst = worst.max(error);
    }
    // Central differences: truncation `h² |P'''|/6` (some 1e-12 here) and the map's own
    // error (contact times to `1e-12 T`, states to about 1e-15) over `h`: 1e-9 or so.
    let scale = map.jacobian.amax();
    eprintln!("damper: Jacobian against differences {worst:e} of {scale}");
    assert!(worst < 1e-7 * scale, "{worst:e} of {scale}");
    // det DP = e⁴ e^{tr A T} (two impacts, tr A = −c/m₁).
    let period = TAU / omega;
    let det: f64 = map.jacobian.determinant();
    let exact = 0.6f64.powi(4) * (-0.05 * period).exp();
    eprintln!("damper: det DP {det} against {exact}");
    assert!((det - exact).abs() < 1e-12 * exact, "{det} against {exact}");
    // The Lyapunov exponents from the orbit are log|μ|/T.
    let spectrum = lyapunov_exponents(&model, omega, &start, &LyapunovOptions::default())
        .expect("the damper's spectrum");
    assert_eq!(spectrum.collapsed, 0);
    assert!(
        spectrum.exponents.iter().all(|&x| x < 0.0),
        "{:?}",
        spectrum.exponents
    );
    let mut rates: Vec<(f64, f64)> = orbit
        .floquet_multipliers
        .iter()
        .map(|m| (m.norm().ln() / period, m.im))
        .collect();
    rates.sort_by(|a, b| b.0.total_cmp(&a.0));
    eprintln!(
        "damper: exponents {:?} against {rates:?}",
        spectrum.exponents
    );
    check_against(&spectrum, &rates, 1e-6);
}

/// Compares `exponents` (descending) with exact `rates` `(Re, Im)` (descending by `Re`): a real
/// rate individually to `tol` relative, a complex-conjugate pair by its sum (the two members of
/// a pair share one growth rate and split it by a bounded oscillation, an `O(1/t)` error that
/// only their sum is free of) to `tol`, and each member within its stated uncertainty.
fn check_against(spectrum: &LyapunovSpectrum, rates: &[(f64, f64)], tol: f64) {
    let x = &spectrum.exponents;
    assert_eq!(x.len(), rates.len());
    let mut i = 0;
    while i < rates.len() {
        let (re, im) = rates[i];
        if im != 0.0 && i + 1 < rates.len() {
            let sum = x[i] + x[i + 1];
            let exact = re + rates[i + 1].0;
            assert!(
                (sum - exact).abs() <= tol * exact.abs(),
                "pair {i}: {sum} vs {exact}"
            );
            for j in [i, i + 1] {
                let error = (x[j] - rates[j].0).abs();
                assert!(error <= spectrum.uncertainties[j], "member {j}: {error:e}");
            }
            i += 2;
        } else {
            assert!(
                (x[i] - re).abs() <= tol * re.abs(),
                "exponent {i}: {} vs {re}",
                x[i]
            );
            i += 1;
        }
    }
}

#[test]
fn a_damper_whose_ball_never_impacts_is_a_family() {
    // The primary's linear amplitude at ω = 1.1, |1/(k − mω² + icω)| ≈ 4.7, stays far inside
    // a clearance of 100: the ball, at rest, is never reached.
    let omega = 1.1;
    let model = impact_damper(100.0);
    let steady = simulate(
        &model,
        omega,
        &Start::rest(2),
        &SimulationOptions::default(),
    )
    .expect("the damper runs");
    assert_eq!(steady.status, Status::Periodic);
    assert_eq!(steady.impacts, 0);
    assert!(steady.family);
    assert!(steady.orbit.is_none());
    let reason = steady.orbit_error.as_deref().unwrap_or_default();
    assert!(reason.contains("family"), "{reason}");
    // Newton from the final state names the family rather than failing to solve.
    let error = periodic_orbit(
        &model,
        omega,
        &steady.final_state,
        1,
        &SimulationOptions::default(),
    )
    .expect_err("no isolated orbit");
    assert_eq!(error, NewtonError::Family { neutral: 1 });
    // The ball stays where it started, the primary on its linear steady state
    // `u₁ = Re(U e^{iωt})`, `U = 1/(1 − ω² + 0.05 iω)`, at the section `t = kT` (phase 0).
    let u = C64::new(1.0 - omega * omega, 0.05 * omega).inv();
    let y = &steady.final_state.state;
    let tolerance = 1e-8 * u.norm();
    assert!((y[0] - u.re).abs() < tolerance, "{} against {}", y[0], u.re);
    assert!((y[2] - (u * C64::new(0.0, omega)).re).abs() < tolerance);
    assert_eq!((y[1], y[3]), (0.0, 0.0));
}

#[test]
fn a_body_held_by_a_dashpot_alone_has_a_simple_zero_rate() {
    // Mass 2 tied to the frame by a dashpot only: K is singular, C is not on its null vector,
    // so the zero rate is simple (an eigenvector (e₂, 0)) and the modal flow exists; the
    // body's velocity relaxes as v(s) = v₀ e^{−cs/m} (no force on it), its position as
    // u₀ + (m v₀/c)(1 − e^{−cs/m}).
    let (m, c) = (0.5, 0.2);
    let flow = LinearFlow::new(
        &DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, m])),
        Some(&DMatrix::from_row_slice(2, 2, &[0.05, 0.0, 0.0, c])),
        &DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 0.0]),
        &DVector::from_vec(vec![1.0, 0.0]),
        &DVector::zeros(2),
        &DVector::zeros(2),
        1.1,
    )
    .expect("a dashpot-held body has a modal flow");
    assert_eq!(flow.rigid_modes(), 0);
    let (u0, v0) = (0.3, -0.7);
    let flight = flow.flight(&DVector::from_vec(vec![0.0, u0, 0.0, v0]), 0.4);
    for s in [0.5, 3.0, 20.0] {
        let y = flight.state(s);
        let decay = (-c * s / m).exp();
        let (u, v) = (u0 + m * v0 / c * (1.0 - decay), v0 * decay);
        assert!(
            (y[1] - u).abs() < 1e-13 && (y[3] - v).abs() < 1e-13,
            "s = {s}: {y:?}"
        );
    }
}

#[test]
fn the_linear_steady_start_of_a_damper_is_the_zero_mean_member() {
    // The primary on `u₁ = Re(U e^{iωt})`, `U = 1/(1 − ω² + 0.05 iω)`; the ball, unforced,
    // at rest at zero (its family's zero-mean member).
    let omega = 1.1;
    let start = Start::linear_steady_state(&impact_damper(100.0), omega).expect("a start");
    let u = C64::new(1.0 - omega * omega, 0.05 * omega).inv();
    let y = &start.state;
    assert!(
        (y[0] - u.re).abs() < 1e-14 * u.norm(),
        "{} against {}",
        y[0],
        u.re
    );
    assert!((y[2] - (u * C64::new(0.0, omega)).re).abs() < 1e-14 * u.norm());
    assert_eq!((y[1], y[3]), (0.0, 0.0));
    // A forced free mass: `u = −Re(F e^{iωt})/(mω²)` at t = 0, `u̇ = −Re(iωF)/(mω²)`,
    // `F = f_c − i f_s`.
    let (m, fc, fs) = (2.0, 0.6, 0.8);
    let forced = Model::new(
        DMatrix::from_element(1, 1, m),
        DMatrix::zeros(1, 1),
        None,
        DVector::from_element(1, fc),
        DVector::from_element(1, fs),
        vec![],
    )
    .expect("a free mass");
    let start = Start::linear_steady_state(&forced, omega).expect("a start");
    let (u, v) = (-fc / (m * omega * omega), -fs / (m * omega));
    assert!((start.state[0] - u).abs() < 1e-15 && (start.state[1] - v).abs() < 1e-15);
    // Starting there, the mass stays on it: the state one period later is the same.
    let map = stroboscopic_map(&forced, omega, &start, 1, &SimulationOptions::default())
        .expect("the map");
    assert!(
        (&map.state - &start.state).amax() < 1e-14,
        "{:?}",
        map.state
    );
}

#[test]
fn a_ball_between_two_one_sided_stops_bounces_at_the_same_times() {
    // The same ball with each stop its own contact pair (several pairs watched at once).
    let stop = |gap_plus: f64, gap_minus: f64| ContactPair {
        plus_dof: Some(0),
        minus_dof: None,
        gap_plus,
        gap_minus,
        restitution: 1.0,
    };
    let model = Model::new(
        DMatrix::from_element(1, 1, 1.0),
        DMatrix::zeros(1, 1),
        None,
        DVector::zeros(1),
        DVector::zeros(1),
        vec![stop(1.0, f64::INFINITY), stop(f64::INFINITY, 1.0)],
    )
    .expect("the ball's model");
    let v = 0.3;
    let start = Start {
        state: DVector::from_vec(vec![0.0, v]),
        time: 0.0,
    };
    let map = stroboscopic_map(&model, 1.0, &start, 5, &SimulationOptions::default())
        .expect("the ball's map");
    let end = 5.0 * TAU;
    let exact: Vec<f64> = (0..)
        .map(|k| (1.0 + 2.0 * k as f64) / v)
        .take_while(|&t| t < end)
        .collect();
    assert_eq!(map.impact_times.len(), exact.len());
    for (k, (t, e)) in map.impact_times.iter().zip(&exact).enumerate() {
        assert!((t - e).abs() <= 1e-12 * TAU, "{t} against {e}");
        assert_eq!(map.impact_pairs[k], k % 2);
    }
}

#[test]
fn a_constant_force_on_a_free_mass_has_no_steady_state_but_flies_exactly() {
    // ü = g₀ = 0.5/2: u(s) = u₀ + v₀ s + g₀ s²/2.
    let flow = LinearFlow::new(
        &DMatrix::from_element(1, 1, 2.0),
        None,
        &DMatrix::zeros(1, 1),
        &DVector::zeros(1),
        &DVector::zeros(1),
        &DVector::from_element(1, 0.5),
        1.0,
    )
    .expect("a free mass has a flow");
    assert_eq!(
        flow.linear_steady_state(0.0),
        Err(rattle_event_driven::FlowError::RigidDrift(0))
    );
    let y = flow
        .flight(&DVector::from_vec(vec![0.1, -0.2]), 0.3)
        .state(3.0);
    let (u, v) = (0.1 - 0.2 * 3.0 + 0.125 * 9.0, -0.2 + 0.25 * 3.0);
    assert!(
        (y[0] - u).abs() < 1e-15 && (y[1] - v).abs() < 1e-15,
        "{y:?}"
    );
}

/// Runs `f` on its own thread and returns its value, failing when it takes more than a
/// minute: a search that never ends fails the test instead of hanging it.
fn ends_within_a_minute<T: Send + 'static>(
    what: &str,
    f: impl FnOnce() -> T + Send + 'static,
) -> T {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = send.send(f());
    });
    receive
        .recv_timeout(std::time::Duration::from_secs(60))
        .unwrap_or_else(|_| panic!("{what} never ends"))
}

/// A gap that rests on an edge of its band (a free body at rest on its stop, its carrier
/// held) has no exit, and the search says so at once: the enclosure of a constant touches
/// the edge on every chunk, so that bisection alone would split each chunk down to the time
/// tolerance. Written as a stuck phase's flight writes it: the constant at rate 0 (with a
/// `−0` coefficient) and a forcing term of zero amplitude.
#[test]
fn a_gap_resting_on_its_edge_has_no_exit() {
    let zero = C64::default();
    let (lo, hi) = (0.342_693_660_141_455_36, 0.854_836_860_293_133_7);
    for (edge, level) in [(-1.0, lo), (1.0, hi)] {
        let rest = ExpSum {
            terms: vec![
                Term {
                    poly: [C64::new(level, 0.0), zero, C64::new(-0.0, 0.0), zero],
                    rate: zero,
                },
                Term {
                    poly: [zero; 4],
                    rate: C64::new(0.0, 0.7),
                },
            ],
        };
        let found = ends_within_a_minute("the search of a gap at rest on its edge", move || {
            let mut stack = SearchStack::default();
            rest.first_exit(lo, hi, 40.0, 1e-11, 2e-12, &mut stack)
        });
        assert_eq!(found, None, "at rest on the edge {edge}");
    }
}

/// A body `b0` on a spring to the frame, forced, with a near-plastic stop against the frame
/// (it chatters and sticks there) and a two-sided one, and a free body in a clearance of `b0`
/// (`r = u_free − u_b0 ∈ [−0.175, 0.337]`); no damping. From rest the free body chatters on
/// its lower stop and sticks, `b0` then sticks on the frame with it, and the free body is left
/// at rest on its stop while `b0` is held: a gap that is a constant on its edge.
fn chattering_carrier() -> (Model, f64) {
    let (m0, m1, k) = (
        0.898_058_417_286_830_9,
        0.871_583_877_874_093_5,
        2.032_357_200_040_634,
    );
    let (force, phase) = (2.743_311_271_880_616_f64, 0.050_503_683_530_197_296_f64);
    let frame = |gap_plus: f64, gap_minus: f64, restitution: f64| ContactPair {
        plus_dof: Some(0),
        minus_dof: None,
        gap_plus,
        gap_minus,
        restitution,
    };
    let model = Model::new(
        DMatrix::from_diagonal(&DVector::from_vec(vec![m0, m1])),
        DMatrix::from_row_slice(2, 2, &[k, 0.0, 0.0, 0.0]),
        None,
        DVector::from_vec(vec![force * phase.cos(), 0.0]),
        DVector::from_vec(vec![-force * phase.sin(), 0.0]),
        vec![
            frame(
                0.517_415_546_937_098_3,
                f64::INFINITY,
                0.025_986_520_618_920_04,
            ),
            frame(
                1.995_788_802_997_988_7,
                1.450_239_467_405_160_6,
                0.400_667_819_385_819_5,
            ),
            ContactPair {
                plus_dof: Some(1),
                minus_dof: Some(0),
                gap_plus: 0.337_421_313_356_035_3,
                gap_minus: 0.174_721_886_795_643,
                restitution: 0.639_736_552_433_510_1,
            },
        ],
    )
    .expect("the chattering carrier's model");
    (model, 0.696_349_122_663_189)
}

#[test]
fn a_free_body_at_rest_on_its_stop_beside_a_held_carrier_lets_the_run_end() {
    let (model, omega) = chattering_carrier();
    assert_eq!(model.rigid_modes(), Ok(1));
    let contacts = model.contacts().to_vec();
    let options = TrajectoryOptions {
        periods: 4,
        samples_per_period: 40,
        ..TrajectoryOptions::default()
    };
    let sampled = model.clone();
    let trajectory = ends_within_a_minute("four periods of the chattering carrier", move || {
        sample_trajectory(&sampled, omega, &Start::rest(2), &options)
    })
    .expect("the carrier's trajectory");
    let rows = &trajectory.rows;
    // The stops hold at every row.
    for row in rows {
        for (pair, (c, &r)) in contacts.iter().zip(&row.relative).enumerate() {
            assert!(
                r <= c.gap_plus + 1e-12 && r >= -c.gap_minus - 1e-12,
                "pair {pair} at t = {}: r = {r}",
                row.time
            );
        }
    }
    // While `b0` is held on its frame stop (`u_b0 = gap_plus`, at rest), the free body flies
    // uniformly across its clearance: from each impact on one of its stops, the next on the
    // other follows after distance / speed.
    let held = |row: &TrajectoryRow| {
        row.velocities[0] == 0.0 && (row.displacements[0] - contacts[0].gap_plus).abs() < 1e-12
    };
    let mut flights = 0;
    for (i, after) in rows.iter().enumerate() {
        if after.kind != RowKind::AfterImpact || !held(after) {
            continue;
        }
        let Some(j) = (i + 1..rows.len()).find(|&j| rows[j].kind != RowKind::Sample) else {
            continue;
        };
        let before = &rows[j];
        if before.kind != RowKind::BeforeImpact || !held(before) || !rows[i + 1..j].iter().all(held)
        {
            continue;
        }
        let speed = after.velocities[1] - after.velocities[0];
        let r = after.relative[2];
        let edge = if speed > 0.0 {
            contacts[2].gap_plus
        } else {
            -contacts[2].gap_minus
        };
        let exact = after.time + (edge - r) / speed;
        assert!(
            (before.time - exact).abs() < 1e-10,
            "flight from t = {}: impact at {} against {exact}",
            after.time,
            before.time
        );
        assert!((before.relative[2] - edge).abs() < 1e-12);
        flights += 1;
    }
    assert!(flights >= 2, "{flights} uniform flights while b0 is held");
    // Run to its steady state: the sticking cycle is reached, and the run ends.
    let steady = ends_within_a_minute("the chattering carrier's run", move || {
        simulate(
            &model,
            omega,
            &Start::rest(2),
            &SimulationOptions::default(),
        )
    })
    .expect("the carrier runs");
    assert!(steady.sticking, "{:?}", steady.status);
    assert!(
        steady.periods_run < DEFAULT_MAX_PERIODS,
        "{}",
        steady.periods_run
    );
}
