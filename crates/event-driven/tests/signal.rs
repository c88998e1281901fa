//! The response to a non-periodic signal from rest, each against an exact answer: rest under
//! a zero signal, closed forms of linear models (affine, sinusoidal, resonant, a free body),
//! the periodic steady state reached through a finely sampled record, the periodic
//! simulator's impacts under the same sinusoid, the energy balance over a record with
//! impacts, and bad inputs refused by name.

#[path = "signal/support.rs"]
mod support;

use nalgebra::{Complex, DMatrix, DVector};
use rattle_event_driven::test_models::{paper_unit, BASE_AMPLITUDE, LIGHT_DAMPING};
use rattle_event_driven::*;
use rattle_event_driven::{Segment, Shape, Sinusoid};
use support::*;

type C64 = Complex<f64>;

#[test]
fn a_zero_signal_leaves_the_structure_at_rest() {
    let model = paper_unit(1.3, Some(LIGHT_DAMPING), Some((0.25, 0.8)));
    let signal = Signal::from_samples(&[(0.0, 0.0), (1.0, 0.0), (2.5, 0.0)]).unwrap();
    let burst = Signal::from_segments(vec![Segment {
        start: 0.0,
        end: 3.0,
        shape: Shape::Sinusoids(vec![Sinusoid {
            frequency: 2.0,
            cos: 0.0,
            sin: 0.0,
        }]),
    }])
    .unwrap();
    for signal in [signal, burst] {
        let at = vec![0.0, 0.7, 3.0, 10.0, 1.0];
        let mut samples = 0;
        let response = respond_sampled(
            &model,
            &base_excitation(0.1),
            &signal,
            &options(10.0, at.clone()),
            50,
            &mut |s| {
                samples += 1;
                assert!(s
                    .displacements
                    .iter()
                    .chain(s.velocities)
                    .all(|&v| v == 0.0));
            },
        )
        .unwrap();
        assert_eq!(samples, 51);
        assert!(response.impacts.is_empty());
        for (s, &t) in response.states.iter().zip(&at) {
            assert_eq!(s.t, t);
            assert!(state(s).iter().all(|&v| v == 0.0), "{s:?}");
        }
        let sum = &response.summary;
        assert_eq!(sum.impacts, 0);
        assert!(sum.rms.iter().chain(&sum.peak).all(|&v| v == 0.0));
        assert_eq!(
            (sum.work, sum.final_energy, sum.dissipated_by_dashpots),
            (0.0, 0.0, 0.0)
        );
    }
}

#[test]
fn linear_models_follow_their_closed_forms() {
    let times: Vec<f64> = (0..=40).map(|j| 0.37 * j as f64).collect();
    let duration = 15.0;
    for (m, c, k) in linear_models() {
        let n = m.nrows();
        let model = linear_model(&m, Some(&c), &k);
        let exact = Linear::new(&m, &c, &k);
        // d on the first coordinate, v on the last (a base through a spring and a dashpot).
        let mut d = DVector::zeros(n);
        d[0] = 1.7;
        let mut v = DVector::zeros(n);
        v[n - 1] = 0.4;
        let excitation = Excitation::new(d.clone(), v.clone());
        // Affine: s = a + b t for ever, f = d (a + b t) + v b.
        let (a, b) = (0.3, -0.8);
        let signal = Signal::from_segments(vec![Segment {
            start: 0.0,
            end: f64::INFINITY,
            shape: Shape::Affine { value: a, slope: b },
        }])
        .unwrap();
        let response = respond(
            &model,
            &excitation,
            &signal,
            &options(duration, times.clone()),
        )
        .unwrap();
        let expected: Vec<DVector<f64>> = times
            .iter()
            .map(|&t| exact.affine(&(&d * a + &v * b), &(&d * b), t))
            .collect();
        let scale = scale_of(&expected);
        let worst = response
            .states
            .iter()
            .zip(&expected)
            .map(|(s, e)| relative_error(&state(s), e.as_slice(), scale))
            .fold(0.0, f64::max);
        println!("{n} dof, affine: {worst:e}");
        assert!(worst <= 1e-10, "{n} dof, affine: {worst:e}");
        // A sinusoid s = C cos νt + S sin νt: f = Re((d + iνv)(C − iS) e^{iνt}).
        for nu in [0.9, 2.3] {
            let (cc, ss) = (0.6, -1.1);
            let signal = Signal::from_segments(vec![Segment {
                start: 0.0,
                end: f64::INFINITY,
                shape: Shape::Sinusoids(vec![Sinusoid {
                    frequency: nu,
                    cos: cc,
                    sin: ss,
                }]),
            }])
            .unwrap();
            let response = respond(
                &model,
                &excitation,
                &signal,
                &options(duration, times.clone()),
            )
            .unwrap();
            let amplitude = C64::new(cc, -ss);
            let f = DVector::from_fn(n, |i, _| {
                (C64::new(d[i], 0.0) + C64::new(0.0, nu) * v[i]) * amplitude
            });
            let expected: Vec<DVector<f64>> =
                times.iter().map(|&t| exact.sinusoid(&f, nu, t)).collect();
            let scale = scale_of(&expected);
            let worst = response
                .states
                .iter()
                .zip(&expected)
                .map(|(s, e)| relative_error(&state(s), e.as_slice(), scale))
                .fold(0.0, f64::max);
            println!("{n} dof, sinusoid at {nu}: {worst:e}");
            assert!(worst <= 1e-10, "{n} dof, sinusoid at {nu}: {worst:e}");
        }
    }
}

#[test]
fn resonance_takes_its_secular_form() {
    // Undamped m ü + k u = F cos ω_n t from rest: u = F t sin(ω_n t)/(2 m ω_n), secular.
    let (m, k, force): (f64, f64, f64) = (2.0, 8.0, 0.7);
    let wn = (k / m).sqrt();
    let model = linear_model(
        &DMatrix::from_element(1, 1, m),
        None,
        &DMatrix::from_element(1, 1, k),
    );
    let times: Vec<f64> = (0..=30).map(|j| 1.3 * j as f64).collect();
    let signal = cosine(wn, force);
    let response = respond(
        &model,
        &Excitation::force(1, 0),
        &signal,
        &options(40.0, times.clone()),
    )
    .unwrap();
    let exact = |t: f64| {
        let (s, c) = (wn * t).sin_cos();
        let g = force / (2.0 * m * wn);
        [g * t * s, g * (s + wn * t * c)]
    };
    let worst = worst_against(&response.states, &times, exact);
    println!("resonant: {worst:e}");
    assert!(worst <= 1e-10, "resonant: {worst:e}");
    // Its RMS over [0, T]: ∫ t² sin² ω_n t = T³/6 − ½[t² sin at/a + 2t cos at/a² −
    // 2 sin at/a³]₀ᵀ, a = 2ω_n; its peak: the largest |u| on a fine grid, refined by golden
    // section about it.
    let duration = 40.0;
    let g = force / (2.0 * m * wn);
    let aa = 2.0 * wn;
    let (sa, ca) = (aa * duration).sin_cos();
    let integral = duration.powi(3) / 6.0
        - 0.5
            * (duration * duration * sa / aa + 2.0 * duration * ca / (aa * aa)
                - 2.0 * sa / (aa * aa * aa));
    let rms = g * (integral / duration).sqrt();
    let u = |t: f64| (g * t * (wn * t).sin()).abs();
    let grid = 400_000;
    let best = (0..=grid)
        .map(|i| duration * i as f64 / grid as f64)
        .max_by(|a, b| u(*a).total_cmp(&u(*b)))
        .unwrap();
    let (mut lo, mut hi) = (
        (best - duration / grid as f64).max(0.0),
        (best + duration / grid as f64).min(duration),
    );
    for _ in 0..200 {
        let (x1, x2) = (hi - 0.618 * (hi - lo), lo + 0.618 * (hi - lo));
        if u(x1) < u(x2) {
            lo = x1;
        } else {
            hi = x2;
        }
    }
    let peak = u(0.5 * (lo + hi));
    let summary = &response.summary;
    let (rms_error, peak_error) = (
        (summary.rms[0] - rms).abs() / rms,
        (summary.peak[0] - peak).abs() / peak,
    );
    println!("resonant: RMS {rms_error:e}, peak {peak_error:e}");
    assert!(
        rms_error <= 1e-12 && peak_error <= 1e-12,
        "{rms_error:e} {peak_error:e}"
    );
}

#[test]
fn a_free_body_takes_its_polynomial_form() {
    let m = 2.0;
    // A free body (a rigid mode) under a ramp then a constant and a sinusoid at ν = 0 and at
    // ν: q̈ = s(t)/m, exactly a cubic, a parabola and a double integral of the sinusoid.
    let model = linear_model(
        &DMatrix::from_element(1, 1, m),
        None,
        &DMatrix::from_element(1, 1, 0.0),
    );
    let (a, b, c0, nu, amp) = (0.2, 0.5, -0.3, 1.7, 0.4);
    let signal = Signal::from_segments(vec![
        Segment {
            start: 0.0,
            end: 2.0,
            shape: Shape::Affine { value: a, slope: b },
        },
        Segment {
            start: 2.0,
            end: 5.0,
            shape: Shape::Sinusoids(vec![
                Sinusoid {
                    frequency: 0.0,
                    cos: c0,
                    sin: 9.0,
                },
                Sinusoid {
                    frequency: nu,
                    cos: amp,
                    sin: 0.0,
                },
            ]),
        },
    ])
    .unwrap();
    let times = vec![0.5, 1.0, 2.0, 3.1, 4.4, 5.0, 7.5];
    let response = respond(
        &model,
        &Excitation::force(1, 0),
        &signal,
        &options(8.0, times.clone()),
    )
    .unwrap();
    let exact = |t: f64| -> [f64; 2] {
        let ramp = |t: f64| {
            [
                (a * t * t / 2.0 + b * t * t * t / 6.0) / m,
                (a * t + b * t * t / 2.0) / m,
            ]
        };
        if t <= 2.0 {
            return ramp(t);
        }
        let [q2, p2] = ramp(2.0);
        let s = t.min(5.0) - 2.0;
        // ∫∫ amp cos ν(2 + x): q = −amp (cos ν(2+s) − cos 2ν)/ν² − amp sin 2ν s/ν.
        let (sn2, cs2) = (2.0 * nu).sin_cos();
        let (sn, cs) = (nu * (2.0 + s)).sin_cos();
        let q = q2
            + p2 * s
            + (c0 * s * s / 2.0 - amp * (cs - cs2) / (nu * nu) - amp * sn2 * s / nu) / m;
        let p = p2 + (c0 * s + amp * (sn - sn2) / nu) / m;
        if t <= 5.0 {
            [q, p]
        } else {
            [q + p * (t - 5.0), p]
        }
    };
    let worst = worst_against(&response.states, &times, exact);
    println!("free body: {worst:e}");
    assert!(worst <= 1e-10, "free body: {worst:e}");
}

/// The piecewise-linear interpolation of `cos ωt` with step `h` errs by at most
/// `h²ω²/8` (`|s − s_h| ≤ h² max|s''|/8`). The response of `m ü + c u̇ + k u = e(t)` from
/// zero is `∫ g(t − τ) e(τ) dτ`, `g(τ) = e^{−ζω_nτ} sin(ω_dτ)/(mω_d)`, so the interpolation
/// moves `u` by at most `sup|e| ∫₀^∞ |g| ≤ (h²ω²/8) / (m ω_d ζ ω_n)`, and `u̇` by at most
/// `sup|e| ∫₀^∞ |ġ| ≤ (h²ω²/8) (1 + ζω_n/ω_d)/(m ω_d)`. After 60 periods the transient from
/// rest has decayed by `e^{−ζω_n t} < 10⁻¹²`.
#[test]
fn a_sampled_cosine_reaches_the_periodic_steady_state() {
    let (m, c, k, omega): (f64, f64, f64, f64) = (1.0, 0.2, 1.0, 1.3);
    let model = Model::new(
        DMatrix::from_element(1, 1, m),
        DMatrix::from_element(1, 1, k),
        Some(DMatrix::from_element(1, 1, c)),
        DVector::from_element(1, 1.0),
        DVector::from_element(1, 0.0),
        Vec::new(),
    )
    .unwrap();
    let steady = simulate(
        &model,
        omega,
        &Start::rest(1),
        &SimulationOptions::default(),
    )
    .unwrap();
    assert_eq!(steady.status, Status::Periodic);
    let section = steady.stroboscopic[0].clone();
    let period = std::f64::consts::TAU / omega;
    let wn = (k / m).sqrt();
    let zeta = c / (2.0 * m * wn);
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let periods = 60;
    let mut errors = Vec::new();
    for per_period in [1000, 2000] {
        let h = period / per_period as f64;
        let sup_e = h * h * omega * omega / 8.0;
        let bound_u = sup_e / (m * wd * zeta * wn);
        let bound_v = sup_e * (1.0 + zeta * wn / wd) / (m * wd);
        let signal = sampled_cosine(omega, per_period, periods);
        let at: Vec<f64> = (periods - 3..=periods).map(|j| j as f64 * period).collect();
        let response = respond(
            &model,
            &Excitation::force(1, 0),
            &signal,
            &options(periods as f64 * period, at),
        )
        .unwrap();
        let mut worst: f64 = 0.0;
        for s in &response.states {
            let du = (s.displacements[0] - section[0]).abs();
            let dv = (s.velocities[0] - section[1]).abs();
            assert!(
                du <= bound_u && dv <= bound_v,
                "{per_period}: {du:e} {dv:e}"
            );
            worst = worst.max(du);
        }
        println!("{per_period} samples a period: |Δu| {worst:e} (bound {bound_u:e})");
        errors.push(worst);
    }
    // Second order: halving the step quarters the error.
    let ratio = errors[0] / errors[1];
    assert!((3.5..4.5).contains(&ratio), "ratio {ratio}");
}

/// A free ball in a clearance on a forced oscillator (a rigid mode held only by its stops,
/// its drift a polynomial between impacts) and a chain of three impacting cells (three pairs
/// watched at once), each against the periodic simulator from rest.
#[test]
fn free_bodies_and_chains_reproduce_the_periodic_simulator() {
    let damper = Model::new(
        DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 0.2]),
        DMatrix::from_row_slice(2, 2, &[4.0, 0.0, 0.0, 0.0]),
        Some(DMatrix::from_row_slice(2, 2, &[0.05, 0.0, 0.0, 0.0])),
        DVector::from_vec(vec![0.8, 0.0]),
        DVector::from_vec(vec![0.3, 0.0]),
        vec![ContactPair {
            plus_dof: Some(1),
            minus_dof: Some(0),
            gap_plus: 0.1,
            gap_minus: 0.1,
            restitution: 0.9,
        }],
    )
    .unwrap();
    // The ball's motion is sensitive: the two runs agree to rounding at first and part
    // about tenfold every 1.5 s (from 10⁻¹⁵ at t = 5 to 10⁻⁹ at t = 21), so five periods.
    compare_with_periodic(&damper, (&[0.8, 0.0], &[0.3, 0.0]), 1.7, 5, 1e-9);
    let chain = rattle_event_driven::test_models::paper_chain(
        3,
        1.4,
        Some(LIGHT_DAMPING),
        Some(CellStops::symmetric(0.3, 0.8)),
    );
    // The chain's base forcing: `k_o u_g cos ωt − c_o u_g ω sin ωt` on the first outer mass.
    let mut fc = vec![0.0; 6];
    let mut fs = vec![0.0; 6];
    fc[0] = 6.0 * BASE_AMPLITUDE;
    fs[0] = -LIGHT_DAMPING.0 * BASE_AMPLITUDE * 1.4;
    compare_with_periodic(&chain, (&fc, &fs), 1.4, 6, 1e-9);
}

/// Both runs start at rest and agree to rounding at first; the transient at `ω = 2.2`
/// amplifies rounding differences about tenfold a period (it is sensitive: the two runs'
/// contact times part from `10⁻¹⁵` to `10⁻⁹` over twelve periods), so it is compared over
/// eight.
#[test]
fn a_sinusoid_reproduces_the_periodic_simulators_impacts() {
    for (omega, periods) in [(0.8, 12), (2.2, 8)] {
        let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.25, 0.8)));
        // The base `u_g cos ωt` through `k_o` and `c_o`.
        let fc = [6.0 * BASE_AMPLITUDE, 0.0];
        let fs = [-LIGHT_DAMPING.0 * BASE_AMPLITUDE * omega, 0.0];
        compare_with_periodic(&model, (&fc, &fs), omega, periods, 1e-9);
    }
}

#[test]
fn energy_balances_over_a_record_with_impacts() {
    // The paper unit under a base record (a sampled tone burst with a ramp), and an impact
    // damper (a free ball in a clearance on a damped oscillator) under a force burst.
    let unit = paper_unit(1.0, Some(LIGHT_DAMPING), Some((0.25, 0.9)));
    let samples: Vec<(f64, f64)> = (0..=400)
        .map(|j| {
            let t = 0.05 * j as f64;
            let s = 1.2 * (1.7 * t).sin() * (-(t - 8.0) * (t - 8.0) / 20.0).exp() + 0.01 * t;
            (t, s)
        })
        .collect();
    let record = Signal::from_samples(&samples).unwrap();
    let damper = Model::new(
        DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 0.2]),
        DMatrix::from_row_slice(2, 2, &[4.0, 0.0, 0.0, 0.0]),
        Some(DMatrix::from_row_slice(2, 2, &[0.05, 0.0, 0.0, 0.0])),
        DVector::zeros(2),
        DVector::zeros(2),
        vec![ContactPair {
            plus_dof: Some(1),
            minus_dof: Some(0),
            gap_plus: 0.1,
            gap_minus: 0.1,
            restitution: 0.9,
        }],
    )
    .unwrap();
    let burst = Signal::tone_burst(1.5, 2.0, 6.0).unwrap();
    for (name, model, excitation, signal, duration) in [
        (
            "unit",
            &unit,
            base_excitation(LIGHT_DAMPING.0),
            &record,
            30.0,
        ),
        ("damper", &damper, Excitation::force(2, 0), &burst, 25.0),
    ] {
        let response = respond(model, &excitation, signal, &options(duration, Vec::new()))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let s = &response.summary;
        assert!(s.impacts >= 5, "{name}: {} impacts", s.impacts);
        let size =
            s.work.abs() + s.final_energy + s.dissipated_by_dashpots + s.dissipated_by_impacts;
        let imbalance = s.energy_imbalance().abs() / size;
        println!(
            "{name}: {} impacts, work {:.6}, final {:.6}, dashpots {:.6}, impacts {:.6}, imbalance {imbalance:e}",
            s.impacts, s.work, s.final_energy, s.dissipated_by_dashpots, s.dissipated_by_impacts
        );
        assert!(imbalance <= 1e-9, "{name}: {imbalance:e}");
        for i in &response.impacts {
            // ½μ(1 − e²)ṙ⁻², never an energy gain.
            assert!(i.energy_lost >= 0.0, "{name}: {i:?}");
        }
    }
}

fn field(result: Result<Signal, SignalError>) -> String {
    match result {
        Err(SignalError::OutOfRange { field, .. }) => field,
        Ok(_) => panic!("accepted"),
    }
}

fn response_field(result: Result<Response, ResponseError>) -> String {
    match result {
        Err(ResponseError::Input(SignalError::OutOfRange { field, .. })) => field,
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_input_is_refused_by_name() {
    let ok = [(0.0, 0.0), (1.0, 1.0), (2.0, 0.5)];
    assert!(Signal::from_samples(&ok).is_ok());
    assert_eq!(
        field(Signal::from_samples(&[(0.0, 0.0), (1.0, 1.0), (0.5, 0.5)])),
        "samples[2].time"
    );
    assert_eq!(
        field(Signal::from_samples(&[(0.0, 0.0), (1.0, 1.0), (1.0, 0.5)])),
        "samples[2].time"
    );
    assert_eq!(
        field(Signal::from_samples(&[(0.0, 0.0), (f64::NAN, 1.0)])),
        "samples[1].time"
    );
    assert_eq!(
        field(Signal::from_samples(&[(0.0, 0.0), (1.0, f64::INFINITY)])),
        "samples[1].value"
    );
    assert_eq!(
        field(Signal::from_samples(&[(0.5, 0.0)])),
        "samples[0].time"
    );
    assert_eq!(field(Signal::from_samples(&[])), "samples");
    assert_eq!(field(Signal::tone_burst(1.0, 2.0, 0.5)), "cycles");
    assert_eq!(field(Signal::tone_burst(1.0, -2.0, 3.0)), "omega");
    assert_eq!(
        field(Signal::stepped_sweep(&[(1.0, 1.0, 2.0), (2.0, 1.0, -1.0)])),
        "steps[1].duration"
    );
    assert_eq!(
        field(Signal::stepped_sweep(&[(-1.0, 1.0, 2.0)])),
        "steps[0].frequency"
    );
    assert_eq!(
        field(Signal::from_segments(vec![
            Segment {
                start: 0.0,
                end: 1.0,
                shape: Shape::Affine {
                    value: 0.0,
                    slope: 1.0
                },
            },
            Segment {
                start: 1.5,
                end: 2.0,
                shape: Shape::Affine {
                    value: 0.0,
                    slope: 1.0
                },
            },
        ])),
        "segments[1].start"
    );
    let model = paper_unit(1.0, Some(LIGHT_DAMPING), Some((0.25, 0.8)));
    let signal = Signal::from_samples(&ok).unwrap();
    let excitation = base_excitation(0.1);
    let run = |o: &ResponseOptions| respond(&model, &excitation, &signal, o);
    assert_eq!(response_field(run(&options(-1.0, Vec::new()))), "duration");
    assert_eq!(
        response_field(run(&options(f64::NAN, Vec::new()))),
        "duration"
    );
    // The cap: 10⁷ periods of the fastest oscillation (the unit's ω₂ = √6 rad/s).
    assert_eq!(response_field(run(&options(3e7, Vec::new()))), "duration");
    assert_eq!(response_field(run(&options(5.0, vec![1.0, 6.0]))), "at[1]");
    let short = Excitation::new(DVector::zeros(1), DVector::zeros(2));
    assert_eq!(
        response_field(respond(&model, &short, &signal, &options(1.0, Vec::new()))),
        "excitation.on_signal"
    );
    assert_eq!(
        response_field(respond_sampled(
            &model,
            &excitation,
            &signal,
            &options(1.0, Vec::new()),
            0,
            &mut |_| {}
        )),
        "samples"
    );
}

/// Near resonance (`ν = ω_n + δ`, undamped, from rest) the motion is the beat
/// `u = F (cos νt − cos ω_n t)/(m(ω_n² − ν²))`, written here without cancellation:
/// `cos νt − cos ω_n t = 2 sin((ω_n + ν)t/2) sin((ω_n − ν)t/2)`. Detunings on both sides of
/// the series' threshold.
#[test]
fn near_resonance_stays_exact() {
    let (m, k, force): (f64, f64, f64) = (1.0, 4.0, 0.5);
    let wn = (k / m).sqrt();
    let model = linear_model(
        &DMatrix::from_element(1, 1, m),
        None,
        &DMatrix::from_element(1, 1, k),
    );
    let times: Vec<f64> = (0..=20).map(|j| 1.9 * j as f64).collect();
    for delta in [1e-9, 1e-6, 1e-4, 1e-2] {
        let nu = wn + delta;
        let signal = cosine(nu, force);
        let response = respond(
            &model,
            &Excitation::force(1, 0),
            &signal,
            &options(40.0, times.clone()),
        )
        .unwrap();
        let exact = |t: f64| {
            let g = force / (m * (wn + nu));
            let (half_sum, half_diff) = (0.5 * (wn + nu) * t, 0.5 * (wn - nu) * t);
            // (cos νt − cos ω_n t)/(ω_n − ν) and its derivative, each without cancellation.
            let sinc = |x: f64| if x == 0.0 { 1.0 } else { x.sin() / x };
            let u = g * half_sum.sin() * t * sinc(half_diff);
            let v = g * (wn * half_sum.cos() * t * sinc(half_diff) + (nu * t).sin());
            [u, v]
        };
        let worst = worst_against(&response.states, &times, exact);
        println!("detuned by {delta:e}: {worst:e}");
        assert!(worst <= 1e-10, "detuned by {delta:e}: {worst:e}");
    }
}

#[test]
fn bursts_and_sweeps_are_their_definitions() {
    let (amplitude, omega, cycles) = (1.3, 2.5, 4.0);
    let burst = Signal::tone_burst(amplitude, omega, cycles).unwrap();
    let end = std::f64::consts::TAU * cycles / omega;
    assert_eq!(burst.end(), end);
    for j in 0..=200 {
        let t = 0.06 * j as f64;
        let expected = if t < end {
            amplitude * 0.5 * (1.0 - (omega * t / cycles).cos()) * (omega * t).sin()
        } else {
            0.0
        };
        let (s, _) = burst.value_and_rate(t);
        assert!((s - expected).abs() <= 1e-14, "t {t}: {s} vs {expected}");
    }
    let steps = [(1.0, 0.5, 2.0), (1.5, -0.7, 1.0), (3.0, 0.2, 0.5)];
    let sweep = Signal::stepped_sweep(&steps).unwrap();
    let mut start = 0.0;
    for &(nu, a, duration) in &steps {
        for j in 0..10 {
            let t = start + duration * j as f64 / 10.0;
            let (s, rate) = sweep.value_and_rate(t);
            let (sn, cs) = (nu * (t - start)).sin_cos();
            assert!((s - a * sn).abs() <= 1e-14, "t {t}");
            assert!((rate - a * nu * cs).abs() <= 1e-14, "t {t}");
        }
        start += duration;
    }
    assert_eq!(sweep.value_and_rate(start + 0.1), (0.0, 0.0));
    // The sweep drives the unit through impacts, the state carried across its steps; the
    // streamed samples are the requested states at the same times, bit for bit.
    let model = paper_unit(1.0, Some(LIGHT_DAMPING), Some((0.05, 0.9)));
    let count = 40;
    let duration = 6.0;
    let at: Vec<f64> = (0..=count)
        .rev()
        .map(|j| {
            if j == count {
                duration
            } else {
                j as f64 * duration / count as f64
            }
        })
        .collect();
    let mut streamed = Vec::new();
    let response = respond_sampled(
        &model,
        &base_excitation(LIGHT_DAMPING.0),
        &sweep,
        &options(duration, at.clone()),
        count,
        &mut |s| {
            streamed.push((
                s.t,
                s.displacements
                    .iter()
                    .chain(s.velocities)
                    .copied()
                    .collect::<Vec<f64>>(),
            ))
        },
    )
    .unwrap();
    assert!(response.summary.impacts > 0);
    assert_eq!(streamed.len(), count as usize + 1);
    for (s, (t, y)) in response.states.iter().rev().zip(&streamed) {
        assert_eq!(s.t, *t);
        assert_eq!(&state(s), y, "t {t}");
    }
    assert_eq!(response.states[0], response.final_state);
}

/// Plastic stops (`e = 0`) and chatter (`e = 0.3`, cut short into a stick as the periodic
/// engine cuts it) against the periodic simulator from rest: the same impacts, sticks and
/// states; the energy still balances with the pairs held.
#[test]
fn sticking_follows_the_periodic_simulator() {
    for (omega, restitution, periods) in [(0.8, 0.0, 10), (1.0, 0.3, 10), (2.0, 0.0, 8)] {
        let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.25, restitution)));
        let fc = [6.0 * BASE_AMPLITUDE, 0.0];
        let fs = [-LIGHT_DAMPING.0 * BASE_AMPLITUDE * omega, 0.0];
        let response = compare_with_periodic(&model, (&fc, &fs), omega, periods, 1e-9);
        let s = &response.summary;
        assert!(s.sticks > 0 && s.releases > 0, "omega {omega}: {s:?}");
        let size =
            s.work.abs() + s.final_energy + s.dissipated_by_dashpots + s.dissipated_by_impacts;
        let imbalance = s.energy_imbalance().abs() / size;
        println!(
            "  sticks {}, releases {}, imbalance {imbalance:e}",
            s.sticks, s.releases
        );
        assert!(imbalance <= 1e-9, "omega {omega}: {imbalance:e}");
    }
    // One mass against a plastic wall: held, it has no coordinate left to move in.
    let wall = Model::new(
        DMatrix::from_element(1, 1, 1.0),
        DMatrix::from_element(1, 1, 1.0),
        Some(DMatrix::from_element(1, 1, 0.1)),
        DVector::from_element(1, 1.0),
        DVector::from_element(1, 0.2),
        vec![ContactPair {
            plus_dof: Some(0),
            minus_dof: None,
            gap_plus: 0.5,
            gap_minus: f64::INFINITY,
            restitution: 0.0,
        }],
    )
    .unwrap();
    let response = compare_with_periodic(&wall, (&[1.0], &[0.2]), 0.7, 10, 1e-9);
    assert!(response.summary.sticks > 0 && response.summary.releases > 0);
}

#[test]
fn too_many_events_are_refused() {
    let omega = 0.8;
    let signal = cosine(omega, BASE_AMPLITUDE);
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.25, 0.8)));
    let capped = ResponseOptions {
        max_events: 3,
        ..options(30.0, Vec::new())
    };
    let result = respond(&model, &base_excitation(LIGHT_DAMPING.0), &signal, &capped);
    assert!(
        matches!(result, Err(ResponseError::EventCap { cap: 3, .. })),
        "{result:?}"
    );
}
