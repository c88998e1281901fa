//! Compliant (Kelvin–Voigt) stops, each test model with its exact answer worked out here:
//! the isolated pair returns `−e` times its entry velocity after `π/ω_d`; the impact
//! oscillator's compliant orbit tends to the rigid one at the rate the contact's duration
//! sets; the Floquet multipliers are the stroboscopic map's derivative's; the forcing's work
//! over a cycle is what the dashpots dissipate; bad contact laws are refused by field.

use nalgebra::{DMatrix, DVector};
use rattle_event_driven::*;
use std::f64::consts::PI;

/// One mass `m` against a frame stop at `u = gap` (side 1; no stop on side 2), no spring, no
/// damping, no forcing.
fn isolated(m: f64, gap: f64) -> Model {
    Model::new(
        DMatrix::from_element(1, 1, m),
        DMatrix::zeros(1, 1),
        None,
        DVector::zeros(1),
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
}

/// The isolated pair's gap.
fn gap_of() -> f64 {
    1.0
}

/// The isolated pair's one contact: mass `m` starting at `u = 0` with velocity `v` towards
/// the stop at `gap`, run one period of `omega`.
fn isolated_contact(
    m: f64,
    law: Compliance,
    omega: f64,
    root_tolerance: f64,
) -> (ContactRecord, SteadyState) {
    let (gap, v) = (gap_of(), 1.0);
    let model = isolated(m, gap).with_compliance(0, law).unwrap();
    let options = SimulationOptions {
        fixed_periods: Some(1),
        max_period_multiplicity: 1,
        root_tolerance,
        ..SimulationOptions::default()
    };
    let start = Start {
        state: DVector::from_vec(vec![0.0, v]),
        time: 0.0,
    };
    let steady = simulate(&model, omega, &start, &options).unwrap();
    assert_eq!(steady.cycle_contacts.len(), 1, "one contact");
    (steady.cycle_contacts[0].clone(), steady)
}

/// The isolated pair: `ṙ⁺ = −e ṙ⁻`, `e = exp(−ζπ/√(1 − ζ²))`, after `π/ω_d`,
/// `ω_d = √(k_c/μ)√(1 − ζ²)`, for damping ratios from 0 to 0.95 and contact stiffnesses
/// from 1 to 1e8 times the reference stiffness 1 (a contact rate up to 7e3, 3.5e4 ω). The entry is at `t = 1`
/// (gap 1, speed 1), its time resolved to the root tolerance; the exit's velocity is a sum
/// of the flow's terms of the entry velocity's size, so it holds to rounding of that size
/// times the contact's condition, and the duration to the root tolerance of the period
/// (`1e-15 T` asked here), relative to the contact's duration.
#[test]
fn isolated_pair_restitution_and_duration() {
    let m = 2.0;
    // A period long enough for the softest, most damped contact (`π/ω_d ≈ 14` at ζ = 0.95).
    let omega = 0.2;
    let root_tolerance = 1e-15;
    let mut worst = (0.0f64, 0.0f64);
    for &stiffness in &[1.0, 1e4, 1e8] {
        for &zeta in &[0.0, 0.1, 0.5, 0.9, 0.95] {
            let law = Compliance {
                stiffness,
                damping: 2.0 * zeta * (stiffness * m).sqrt(),
            };
            let e = (-zeta * PI / (1.0f64 - zeta * zeta).sqrt()).exp();
            assert!((law.restitution(m) - e).abs() <= 1e-15);
            let (c, steady) = isolated_contact(m, law, omega, root_tolerance);
            assert!(steady.cycle_impacts.is_empty());
            let wd = (stiffness / m).sqrt() * (1.0 - zeta * zeta).sqrt();
            let duration = PI / wd;
            let velocity_error = (c.exit_velocity + e * c.entry_velocity).abs() / c.entry_velocity;
            let duration_error = ((c.exit_time - c.entry_time) - duration).abs() / duration;
            worst = (worst.0.max(velocity_error), worst.1.max(duration_error));
            eprintln!(
                "k_c {stiffness:e} ζ {zeta}: velocity {velocity_error:.2e}, duration \
                 {duration_error:.2e}, entry {:.3e}",
                (c.entry_time - 1.0).abs()
            );
            assert!((c.entry_velocity - 1.0).abs() <= 1e-14);
            assert!((c.entry_time - 1.0).abs() <= 1e-14);
            // The exit is where `δ = r − gap` returns to 0; `r` is a sum of size `gap`, known to
            // a few roundings `8ε gap`, and crosses at the exit speed `e v`: the exit time is
            // known to `8ε gap/(e v)` besides the time tolerance `root_tolerance T`, and the
            // duration to those and the entry's (speed `v`) and the times' own rounding.
            let eps = f64::EPSILON;
            let tolerance_time = root_tolerance * 2.0 * PI / omega;
            let exit_time_error = 8.0 * eps * gap_of() / (e * 1.0) + tolerance_time;
            let duration_tolerance =
                (exit_time_error + tolerance_time + 8.0 * eps * (gap_of() + c.exit_time))
                    / duration;
            // The exit speed moves at `|r̈| = c_c e v/μ = 2ζω_c e v` there: the exit time's
            // error times that, plus the rounding of the velocity's sum (`100ε` of `v`).
            let rate = (stiffness / m).sqrt();
            let velocity_tolerance = 100.0 * eps + 2.0 * zeta * rate * e * exit_time_error;
            assert!(
                velocity_error <= velocity_tolerance,
                "k_c {stiffness} ζ {zeta}: {velocity_error:e} > {velocity_tolerance:e}"
            );
            assert!(
                duration_error <= duration_tolerance,
                "k_c {stiffness} ζ {zeta}: {duration_error:e} > {duration_tolerance:e}"
            );
            // The largest penetration, undamped: v/ω_c.
            if zeta == 0.0 {
                let depth = 1.0 / (stiffness / m).sqrt();
                assert!((c.max_penetration - depth).abs() <= 1e-12 * depth);
            }
            let per_period = steady.contact_time_per_period;
            assert!((per_period - duration).abs() <= duration_tolerance * duration);
        }
    }
    eprintln!("worst: velocity {:.2e}, duration {:.2e}", worst.0, worst.1);
}

/// Bad contact laws are refused, each by its field.
#[test]
fn bad_compliance_is_refused_by_field() {
    let model = isolated(1.0, 1.0);
    let field = |r: Result<Model, ModelError>| match r {
        Err(ModelError::OutOfRange { field, .. }) => field,
        other => panic!("not refused: {other:?}"),
    };
    let law = |stiffness, damping| Compliance { stiffness, damping };
    assert_eq!(
        field(model.clone().with_compliance(1, law(1.0, 0.0))),
        "pair"
    );
    for k in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(
            field(model.clone().with_compliance(0, law(k, 0.0))),
            "compliance.stiffness"
        );
    }
    for c in [-1e-9, f64::NAN, f64::INFINITY] {
        assert_eq!(
            field(model.clone().with_compliance(0, law(1.0, c))),
            "compliance.damping"
        );
    }
    // The contact rate √(k_c/μ) at most 1e6 ω: k_c = 1e12 μ ω² passes, just above fails,
    // in the model's check and in every run.
    let omega = 1.0;
    let edge = model.clone().with_compliance(0, law(1e12, 0.0)).unwrap();
    assert_eq!(edge.check_compliance(omega), Ok(()));
    let stiff = model.with_compliance(0, law(1.0001e12, 0.0)).unwrap();
    let refused = stiff.check_compliance(omega).unwrap_err();
    assert!(
        matches!(&refused, ModelError::OutOfRange { field, .. } if field == "compliance[0].stiffness")
    );
    let run = simulate(
        &stiff,
        omega,
        &Start::rest(1),
        &SimulationOptions::default(),
    );
    assert_eq!(run.unwrap_err(), SimulationError::Model(refused));
    // The model reads its laws back; a rigid pair has none.
    assert_eq!(edge.compliance(0), Some(law(1e12, 0.0)));
    assert_eq!(isolated(1.0, 1.0).compliance(0), None);
}

/// The impact oscillator: mass 1 on a spring 1 and a dashpot `0.1` to the frame, forced by
/// `cos ωt`, one stop against the frame at `u = 1` of restitution `e` (rigid).
fn oscillator(e: f64) -> Model {
    Model::new(
        DMatrix::from_element(1, 1, 1.0),
        DMatrix::from_element(1, 1, 1.0),
        Some(DMatrix::from_element(1, 1, DASHPOT)),
        DVector::from_element(1, 1.0),
        DVector::zeros(1),
        vec![ContactPair {
            plus_dof: Some(0),
            minus_dof: None,
            gap_plus: 1.0,
            gap_minus: f64::INFINITY,
            restitution: e,
        }],
    )
    .unwrap()
}

/// The impact oscillator's dashpot.
const DASHPOT: f64 = 0.1;

/// The forcing frequency of the oscillator's tests: a stable period-1 orbit with one impact
/// per period (multipliers `−0.30 ± 0.54i` rigid).
const OMEGA: f64 = 1.2;

/// The oscillator's steady state from rest, its orbit polished.
fn steady(model: &Model) -> SteadyState {
    let s = simulate(model, OMEGA, &Start::rest(1), &SimulationOptions::default()).unwrap();
    assert_eq!(s.status, Status::Periodic);
    assert_eq!(s.period, Some(1));
    s
}

/// `k_c → ∞` with the isolated pair's restitution held at the rigid stop's `e`: the
/// compliant periodic orbit tends to the rigid one. Each contact lasts `π/ω_d ∝ k_c^{-1/2}`,
/// and the motion's departure from the rigid one is of the order of that duration (the pair
/// sits on the stop for it while the rigid one has already left at `−e v`), so the error
/// falls by 2 per fourfold stiffness, up to the next order, a relative `O(k_c^{-1/2})`
/// itself: the ratio's departure from 2 must shrink by about 2 per step too.
#[test]
fn stiff_limit_tends_to_the_rigid_orbit() {
    let e = 0.8;
    let rigid = steady(&oscillator(e));
    let target = rigid.orbit.as_ref().unwrap().state.clone();
    let mut errors = Vec::new();
    let stiffnesses: Vec<f64> = (0..6).map(|j| 1e4 * 4f64.powi(j)).collect();
    for &k in &stiffnesses {
        let model = oscillator(e)
            .with_compliance(0, Compliance::matching(k, e, 1.0))
            .unwrap();
        let s = steady(&model);
        assert_eq!(s.cycle_contacts.len(), 1);
        assert!(s.cycle_impacts.is_empty());
        let orbit = s.orbit.as_ref().unwrap();
        assert_eq!(orbit.contact_phases.len(), 1);
        let error = (&orbit.state - &target).norm() / target.norm();
        errors.push(error);
    }
    let ratios: Vec<f64> = errors.windows(2).map(|w| w[0] / w[1]).collect();
    eprintln!("errors {errors:?}");
    eprintln!("ratios {ratios:.4?}");
    for (j, ratio) in ratios.iter().enumerate() {
        // The next order's share, `|ratio/2 − 1|`, about `π/√k_c` times a constant of order
        // one (the contact's duration against the orbit's time scale `1/ω`).
        let duration = PI / stiffnesses[j].sqrt();
        assert!(
            (ratio / 2.0 - 1.0).abs() <= 2.0 * duration,
            "k_c {:e}: ratio {ratio}",
            stiffnesses[j]
        );
    }
    // The next order is `O(k_c^{-1/2})`: its share halves per fourfold stiffness as well
    // (measured 2.013, 2.006, 2.003, 2.002).
    let departures: Vec<f64> = ratios.iter().map(|r| (r / 2.0 - 1.0).abs()).collect();
    for w in departures.windows(2) {
        let fall = w[0] / w[1];
        assert!((1.5..=2.5).contains(&fall), "departures {departures:?}");
    }
}

/// The compliant oscillator of the Floquet and energy tests: `k_c = 1e4` (a contact rate
/// 100 times the natural one), restitution 0.8 matched.
fn compliant_oscillator() -> (Model, Compliance) {
    let law = Compliance::matching(1e4, 0.8, 1.0);
    (oscillator(0.8).with_compliance(0, law).unwrap(), law)
}

/// The Floquet multipliers of the compliant orbit (its map's Jacobian through the flows of
/// the contact phase and the saltations at entry and exit) against a central difference of
/// the simulator's own stroboscopic map. The difference's truncation is `h² |P'''|/6`, and
/// the map's values are known to the contact times' tolerance `root_tolerance T` times the
/// state's rate, `|ẏ| ≤ 4` here: divided by `h` that is the difference's noise. (A saltation
/// of the wrong sign at entry and exit leaves the Jacobian 1.3e-3 off.)
///
/// Twice: the oscillator of [`compliant_oscillator`] at `ω = 1.2`, its contact inside the
/// cycle, and a softer stop (`k_c = 100`) at `ω = 0.8`, whose contact runs through the
/// section: the map then starts and ends pressed.
#[test]
fn floquet_multipliers_match_the_map_derivative() {
    let (inside, _) = compliant_oscillator();
    let soft = Compliance::matching(1e2, 0.8, 1.0);
    let through = oscillator(0.8).with_compliance(0, soft).unwrap();
    for (model, omega, wraps) in [(inside, OMEGA, false), (through, 0.8, true)] {
        check_multipliers(&model, omega, wraps);
    }
}

/// [`floquet_multipliers_match_the_map_derivative`] for `model` at `omega`; `wraps`: its
/// contact runs through the section.
fn check_multipliers(model: &Model, omega: f64, wraps: bool) {
    let s = simulate(model, omega, &Start::rest(1), &SimulationOptions::default()).unwrap();
    assert_eq!(s.period, Some(1));
    let orbit = s.orbit.as_ref().unwrap();
    let phases = &orbit.contact_phases;
    assert_eq!(phases.len(), 1);
    assert_eq!(phases[0].exit < phases[0].entry, wraps, "{phases:?}");
    // Contact times to 1e-14 T, so that the map's noise is below the difference's signal.
    let options = SimulationOptions {
        root_tolerance: 1e-14,
        ..SimulationOptions::default()
    };
    let at = |y: &DVector<f64>| {
        let start = Start {
            state: y.clone(),
            time: orbit.time,
        };
        stroboscopic_map(model, omega, &start, 1, &options).unwrap()
    };
    let exact = at(&orbit.state);
    assert_eq!(exact.contacts.len(), if wraps { 2 } else { 1 });
    assert!(exact.impact_sides.is_empty());
    let h = 1e-5;
    let mut fd = DMatrix::zeros(2, 2);
    for i in 0..2 {
        let mut plus = orbit.state.clone();
        let mut minus = orbit.state.clone();
        plus[i] += h;
        minus[i] -= h;
        let column = (at(&plus).state - at(&minus).state) / (2.0 * h);
        fd.set_column(i, &column);
    }
    let period = 2.0 * PI / omega;
    let noise = options.root_tolerance * period * 4.0 / h;
    let tolerance = h * h + noise;
    let error = (&fd - &exact.jacobian).amax() / exact.jacobian.amax();
    eprintln!("Jacobian: central difference within {error:.2e} (tolerance {tolerance:.1e})");
    assert!(error <= tolerance, "{error:e}");
    // The multipliers against the difference's through their sum and product (the trace
    // and determinant of a 2 × 2 map: well conditioned in the entries, where the
    // eigenvalues of a near-double pair are not): `|Δ tr| ≤ 2 δ`, `|Δ det| ≤ 4 |J| δ + 2δ²`
    // for entries within `δ`.
    let delta = tolerance * exact.jacobian.amax();
    let sum = orbit.floquet_multipliers[0] + orbit.floquet_multipliers[1];
    let product = orbit.floquet_multipliers[0] * orbit.floquet_multipliers[1];
    let trace_gap = (sum - nalgebra::Complex::new(fd.trace(), 0.0)).norm();
    let det_gap = (product - nalgebra::Complex::new(fd.determinant(), 0.0)).norm();
    eprintln!(
        "multipliers {:?}: trace off by {trace_gap:.2e}, determinant by {det_gap:.2e}",
        orbit.floquet_multipliers
    );
    assert!(trace_gap <= 2.0 * delta, "{trace_gap:e}");
    assert!(
        det_gap <= 4.0 * exact.jacobian.amax() * delta + 2.0 * delta * delta,
        "{det_gap:e}"
    );
}

/// Gauss–Legendre nodes and weights on `[−1, 1]`, `n` points, by Newton on `P_n`.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut derivative = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                derivative = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / derivative;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * derivative * derivative))
        })
        .collect()
}

/// The energy balance over the compliant orbit's cycle: the forcing's work equals what the
/// dashpot and the contact's dashpot dissipate (the energy, kinetic, spring and contact
/// spring, returns to itself; the contact spring holds none at entry and exit, where the
/// penetration is zero). The cycle is integrated here, independently of the simulator, on
/// its contact times and orbit state: each phase's flow in closed form ([`LinearFlow`]),
/// the powers by Gauss–Legendre quadrature (16 points on each of 64 pieces per phase, exact
/// to rounding for these smooth integrands). The balance holds to the orbit's residual and
/// the contact times' tolerance (`root_tolerance T`) times the powers' size.
#[test]
fn forcing_work_equals_dissipation_over_a_cycle() {
    let (model, law) = compliant_oscillator();
    let s = steady(&model);
    let orbit = s.orbit.as_ref().unwrap();
    let period = 2.0 * PI / OMEGA;
    let contact = &orbit.contact_phases[0];
    let (entry, exit) = (contact.entry * period, contact.exit * period);
    assert!(entry < exit, "a contact inside the cycle");
    let one = |v: f64| DMatrix::from_element(1, 1, v);
    let zero = DVector::zeros(1);
    let force = DVector::from_element(1, 1.0);
    let free = LinearFlow::new(
        &one(1.0),
        Some(&one(DASHPOT)),
        &one(1.0),
        &force,
        &zero,
        &zero,
        OMEGA,
    )
    .unwrap();
    let pressed = LinearFlow::new(
        &one(1.0),
        Some(&one(DASHPOT + law.damping)),
        &one(1.0 + law.stiffness),
        &force,
        &zero,
        &DVector::from_element(1, law.stiffness),
        OMEGA,
    )
    .unwrap();
    let rule = gauss_legendre(16);
    let mut y = orbit.state.clone();
    let (mut work, mut dissipated) = (0.0, 0.0);
    let mut penetrations = Vec::new();
    for (flow, from, to, contact_damping) in [
        (&free, 0.0, entry, 0.0),
        (&pressed, entry, exit, law.damping),
        (&free, exit, period, 0.0),
    ] {
        let flight = flow.flight(&y, from);
        let pieces = 64;
        let width = (to - from) / pieces as f64;
        for piece in 0..pieces {
            for &(x, w) in &rule {
                let s = width * (piece as f64 + 0.5 * (x + 1.0));
                let state = flight.state(s);
                let v = state[1];
                let t = from + s;
                work += 0.5 * width * w * (OMEGA * t).cos() * v;
                dissipated += 0.5 * width * w * (DASHPOT + contact_damping) * v * v;
            }
        }
        y = flight.state(to - from);
        penetrations.push(y[0] - 1.0);
    }
    let energy = |y: &DVector<f64>| 0.5 * y[1] * y[1] + 0.5 * y[0] * y[0];
    let change = energy(&y) - energy(&orbit.state);
    let imbalance = (work - dissipated - change).abs() / work;
    eprintln!(
        "work {work:.15}, dissipated {dissipated:.15}, energy change {change:.2e}, \
         imbalance {imbalance:.2e}, penetrations at entry and exit {penetrations:?}"
    );
    let tolerance = SimulationOptions::default().root_tolerance * period * 10.0;
    // The simulator's entry and exit are on the stop, to the times' tolerance times the speed.
    assert!(penetrations[0].abs() <= tolerance && penetrations[1].abs() <= tolerance);
    assert!(imbalance <= tolerance, "{imbalance:e}");
    // Over the orbit the energy returns to itself, to the orbit's residual.
    assert!(change.abs() <= 10.0 * orbit.residual.max(1e-13) * energy(&orbit.state));
}

/// A graze of a compliant stop (`ṙ = 0` on it) is no contact: the undamped, unforced
/// oscillator `u = cos t` (mass 1, spring 1) from `u = 0`, `u̇ = 1` reaches its stop at
/// `u = 1` at rest, at `t = π/2 + 2πj`. With the stop at `1 + 1e-3` it never reaches it; at
/// `1 − 1e-3` it enters, and the contact returns it `ṙ = −√(1 − (1 − 1e-3)²)` undamped.
#[test]
fn a_graze_is_no_contact() {
    let run = |gap: f64| {
        let model = Model::new(
            DMatrix::from_element(1, 1, 1.0),
            DMatrix::from_element(1, 1, 1.0),
            None,
            DVector::zeros(1),
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
        .with_compliance(
            0,
            Compliance {
                stiffness: 1e4,
                damping: 0.0,
            },
        )
        .unwrap();
        let options = SimulationOptions {
            fixed_periods: Some(3),
            max_period_multiplicity: 3,
            ..SimulationOptions::default()
        };
        let start = Start {
            state: DVector::from_vec(vec![0.0, 1.0]),
            time: 0.0,
        };
        simulate(&model, 1.0, &start, &options).unwrap()
    };
    for gap in [1.0, 1.0 + 1e-3] {
        let s = run(gap);
        assert!(
            s.cycle_contacts.is_empty(),
            "gap {gap}: {:?}",
            s.cycle_contacts
        );
        assert!(s.impacts == 0 && s.contact_time_per_period == 0.0);
    }
    let s = run(1.0 - 1e-3);
    assert!(!s.cycle_contacts.is_empty());
    let speed = (1.0f64 - (1.0 - 1e-3f64).powi(2)).sqrt();
    for c in &s.cycle_contacts {
        assert!((c.entry_velocity - speed).abs() <= 1e-12);
        assert!((c.exit_velocity + speed).abs() <= 1e-12);
    }
}

/// The dense samples of a compliant orbit's cycle cover its contact: samples inside the
/// contact lie beyond the stop, by at most the largest penetration.
#[test]
fn trajectories_cover_contact_phases() {
    let (model, _) = compliant_oscillator();
    let s = steady(&model);
    let contact = &s.cycle_contacts[0];
    let trajectory = final_cycle_trajectory(
        &model,
        OMEGA,
        &s,
        &TrajectoryOptions {
            samples_per_period: 2000,
            ..TrajectoryOptions::default()
        },
    )
    .unwrap();
    let period = 2.0 * PI / OMEGA;
    let (entry, exit) = (contact.entry_phase, contact.exit_phase);
    let inside: Vec<f64> = trajectory
        .rows
        .iter()
        .filter(|r| {
            let phase = (r.time + trajectory.phase).rem_euclid(period);
            phase > entry && phase < exit
        })
        .map(|r| r.relative[0] - 1.0)
        .collect();
    assert!(inside.len() >= 5, "{} samples in the contact", inside.len());
    let deepest = inside.iter().fold(0.0f64, |a, &b| a.max(b));
    assert!(inside.iter().all(|&d| d > 0.0));
    assert!(deepest <= contact.max_penetration * (1.0 + 1e-12));
    assert!(deepest >= 0.9 * contact.max_penetration);
}

/// The signal response refuses a model with a compliant stop, by value.
#[test]
fn the_signal_response_refuses_compliant_stops() {
    let (model, _) = compliant_oscillator();
    let signal = Signal::tone_burst(1.0, 2.0, 3.0).unwrap();
    let excitation = Excitation::new(DVector::from_element(1, 1.0), DVector::zeros(1));
    let refused = respond(&model, &excitation, &signal, &ResponseOptions::over(10.0));
    assert_eq!(refused.unwrap_err(), ResponseError::Compliant { pair: 0 });
}

/// Two compliant pairs pressed at once, and a rigid pair beside compliant ones: a two-cell
/// chain whose cells' inner masses ride between stops. Each chain, run until periodic, has
/// its contacts recorded by pair, and each contact ends back on its stop with the pair
/// moving out.
#[test]
fn several_pairs_press_at_once_and_beside_rigid_ones() {
    let cell = CellParameters {
        outer_mass: 2.0,
        inner_mass: 1.0,
        outer_stiffness: 6.0,
        inner_stiffness: 3.0,
        outer_damping: Some(0.1),
        inner_damping: Some(0.05),
        stops: Some(CellStops::symmetric(0.05, 0.7)),
    };
    let chain = Model::chain(&[cell, cell], 0.3, 2.0).unwrap();
    let law = Compliance::matching(3e3, 0.7, 2.0 / 3.0);
    let both = chain
        .clone()
        .with_compliance(0, law)
        .unwrap()
        .with_compliance(1, law)
        .unwrap();
    let mixed = chain.with_compliance(1, law).unwrap();
    let options = SimulationOptions {
        fixed_periods: Some(60),
        max_period_multiplicity: 4,
        ..SimulationOptions::default()
    };
    let mut overlap = false;
    for (model, rigid_zero) in [(both, false), (mixed, true)] {
        let s = simulate(&model, 2.0, &Start::rest(4), &options).unwrap();
        assert!(!s.cycle_contacts.is_empty());
        for c in &s.cycle_contacts {
            assert!(c.exit_time > c.entry_time);
            assert!(c.entry_velocity * c.side as f64 > 0.0);
            assert!(c.exit_velocity * c.side as f64 <= 0.0);
            assert!(!(rigid_zero && c.pair == 0), "pair 0 is rigid");
        }
        if rigid_zero {
            assert!(s.cycle_impacts.iter().all(|i| i.pair == 0));
        } else {
            assert!(s.cycle_impacts.is_empty());
            overlap |= s.cycle_contacts.iter().any(|a| {
                s.cycle_contacts.iter().any(|b| {
                    a.pair != b.pair && a.entry_time < b.exit_time && b.entry_time < a.exit_time
                })
            });
        }
    }
    assert!(
        overlap,
        "both pairs pressed at once somewhere in the final cycle"
    );
}
