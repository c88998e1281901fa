//! Free bodies (a singular stiffness matrix): the flow of rigid modes against closed forms and
//! an independent matrix exponential, first contacts of a drifting body, a ball bouncing
//! between stops, and an impact damper run to its periodic steady state, polished by Newton,
//! with its Lyapunov spectrum; and the neutral family of a damper whose ball never impacts.

use nalgebra::{DMatrix, DVector};
use rattle_event_driven::expsum::{ExpSum, SearchStack, Term};
use rattle_event_driven::flow::LinearFlow;
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
            assert!(error < 1e-13, "s = {s}: {y:?} against ({u}, {v}): {error:e}");
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

/// A structure with a rigid mode beside elastic ones, under a forcing on every mass: masses 0
/// and 1 (of different masses) tied to each other only (spring 2, dashpot 0.1), so that their
/// common translation is rigid and their relative motion elastic, and mass 2 on a spring and
/// a dashpot to the frame.
fn mixed_model() -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>, DVector<f64>, DVector<f64>) {
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
