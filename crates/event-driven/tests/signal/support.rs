//! What the response tests share: the closed forms of linear models by the matrix
//! exponential, the comparison with the periodic simulator, and small helpers.

use nalgebra::{Complex, DMatrix, DVector};
use rattle_event_driven::*;
use rattle_event_driven::{Segment, Shape, Sinusoid};

type C64 = Complex<f64>;

/// The paper unit's base excitation: `f = (k_o s + c_o ṡ, 0)` for the base motion `s`.
pub fn base_excitation(co: f64) -> Excitation {
    Excitation::new(
        DVector::from_vec(vec![6.0, 0.0]),
        DVector::from_vec(vec![co, 0.0]),
    )
}

pub fn options(duration: f64, at: Vec<f64>) -> ResponseOptions {
    ResponseOptions {
        at,
        ..ResponseOptions::over(duration)
    }
}

/// The exact motion of the linear model `y' = A y + b(t)` from rest, `A` the first-order
/// matrix of `(M, C, K)`, by the matrix exponential: affine forcing `f₀ + f₁t` or a sinusoid
/// `Re(F e^{iνt})`, each with its particular solution from a linear solve.
pub struct Linear {
    a: DMatrix<f64>,
    minv: DMatrix<f64>,
    n: usize,
}

impl Linear {
    pub fn new(m: &DMatrix<f64>, c: &DMatrix<f64>, k: &DMatrix<f64>) -> Linear {
        let n = m.nrows();
        let minv = m.clone().try_inverse().unwrap();
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        a.view_mut((0, n), (n, n)).fill_with_identity();
        a.view_mut((n, 0), (n, n)).copy_from(&(-(&minv * k)));
        a.view_mut((n, n), (n, n)).copy_from(&(-(&minv * c)));
        Linear { a, minv, n }
    }

    fn lift(&self, f: &DVector<f64>) -> DVector<f64> {
        let mut b = DVector::zeros(2 * self.n);
        b.rows_mut(self.n, self.n).copy_from(&(&self.minv * f));
        b
    }

    /// `y(t)` under `f₀ + f₁ t` from rest.
    pub fn affine(&self, f0: &DVector<f64>, f1: &DVector<f64>, t: f64) -> DVector<f64> {
        let ainv = self.a.clone().try_inverse().unwrap();
        let (b0, b1) = (self.lift(f0), self.lift(f1));
        let p1 = -(&ainv * &b1);
        let p0 = &ainv * (&p1 - &b0);
        (&self.a * t).exp() * (-&p0) + &p0 + &p1 * t
    }

    /// `y(t)` under `Re(F e^{iνt})` from rest.
    pub fn sinusoid(&self, f: &DVector<C64>, nu: f64, t: f64) -> DVector<f64> {
        let m = 2 * self.n;
        let ac = self.a.map(|v| C64::new(v, 0.0));
        let mut b = DVector::<C64>::zeros(m);
        let minv = self.minv.map(|v| C64::new(v, 0.0));
        b.rows_mut(self.n, self.n).copy_from(&(&minv * f));
        let shifted = DMatrix::<C64>::identity(m, m) * C64::new(0.0, nu) - ac;
        let y = shifted.lu().solve(&b).unwrap();
        let at = |t: f64| (&y * C64::new(0.0, nu * t).exp()).map(|c| c.re);
        (&self.a * t).exp() * (-at(0.0)) + at(t)
    }
}

pub fn relative_error(a: &[f64], b: &[f64], scale: f64) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}

pub fn state(r: &ResponseState) -> Vec<f64> {
    r.displacements
        .iter()
        .chain(&r.velocities)
        .copied()
        .collect()
}

/// Sizes of the closed-form states over the times, for relative errors.
pub fn scale_of(states: &[DVector<f64>]) -> f64 {
    states.iter().map(|y| y.amax()).fold(0.0, f64::max)
}
/// A 1-dof and a 2-dof linear model (no stops): `(M, C, K)`.
pub fn linear_models() -> Vec<(DMatrix<f64>, DMatrix<f64>, DMatrix<f64>)> {
    vec![
        (
            DMatrix::from_element(1, 1, 2.0),
            DMatrix::from_element(1, 1, 0.3),
            DMatrix::from_element(1, 1, 5.0),
        ),
        (
            DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 1.0]),
            DMatrix::from_row_slice(2, 2, &[0.15, -0.05, -0.05, 0.05]),
            DMatrix::from_row_slice(2, 2, &[9.0, -3.0, -3.0, 3.0]),
        ),
    ]
}

pub fn linear_model(m: &DMatrix<f64>, c: Option<&DMatrix<f64>>, k: &DMatrix<f64>) -> Model {
    let n = m.nrows();
    Model::new(
        m.clone(),
        k.clone(),
        c.cloned(),
        DVector::zeros(n),
        DVector::zeros(n),
        Vec::new(),
    )
    .unwrap()
}
/// A sampled `cos ωt`, `per_period` samples a period, over `periods` periods.
pub fn sampled_cosine(omega: f64, per_period: usize, periods: usize) -> Signal {
    let h = std::f64::consts::TAU / omega / per_period as f64;
    let samples: Vec<(f64, f64)> = (0..=per_period * periods)
        .map(|j| {
            let t = j as f64 * h;
            (t, (omega * t).cos())
        })
        .collect();
    Signal::from_samples(&samples).unwrap()
}
/// The periodic simulator's run from rest of `model` at `omega` over `periods` periods,
/// against the response to the same forcing as a signal (`s = cos ωt`, `d = f_c`,
/// `v = −f_s/ω`): the same impacts (pair, side, time, `ṙ⁻`) and the same states at the
/// trajectory's uniform samples, to `tolerance`.
pub fn compare_with_periodic(
    model: &Model,
    (fc, fs): (&[f64], &[f64]),
    omega: f64,
    periods: u64,
    tolerance: f64,
) -> Response {
    let trajectory = sample_trajectory(
        model,
        omega,
        &Start::rest(model.dofs()),
        &TrajectoryOptions {
            periods,
            samples_per_period: 10,
            ..TrajectoryOptions::default()
        },
    )
    .unwrap();
    let period = std::f64::consts::TAU / omega;
    let signal = Signal::from_segments(vec![Segment {
        start: 0.0,
        end: f64::INFINITY,
        shape: Shape::Sinusoids(vec![Sinusoid {
            frequency: omega,
            cos: 1.0,
            sin: 0.0,
        }]),
    }])
    .unwrap();
    let excitation = Excitation::new(
        DVector::from_column_slice(fc),
        DVector::from_iterator(fs.len(), fs.iter().map(|v| -v / omega)),
    );
    let uniform: Vec<&TrajectoryRow> = trajectory
        .rows
        .iter()
        .filter(|r| r.kind == RowKind::Sample)
        .collect();
    let at: Vec<f64> = uniform.iter().map(|r| r.time).collect();
    let same_scale = ResponseOptions {
        time_scale: Some(period),
        ..options(periods as f64 * period, at)
    };
    let response = respond(model, &excitation, &signal, &same_scale).unwrap();
    assert!(!trajectory.impacts.is_empty());
    assert_eq!(
        response.impacts.len(),
        trajectory.impacts.len(),
        "omega {omega}"
    );
    let mut worst: (f64, f64, f64) = (0.0, 0.0, 0.0);
    for (a, b) in response.impacts.iter().zip(&trajectory.impacts) {
        assert_eq!(a.pair, b.pair);
        assert_eq!(a.side, if b.side > 0 { 1 } else { 2 });
        worst.0 = worst.0.max((a.t - b.time).abs());
        worst.1 = worst
            .1
            .max((a.relative_velocity_before - b.relative_velocity_before).abs());
    }
    for (s, r) in response.states.iter().zip(&uniform) {
        let expected: Vec<f64> = r
            .displacements
            .iter()
            .chain(&r.velocities)
            .copied()
            .collect();
        worst.2 = worst.2.max(relative_error(&state(s), &expected, 1.0));
    }
    let sticks: Vec<f64> = trajectory
        .rows
        .iter()
        .filter(|r| r.kind == RowKind::AfterStick)
        .map(|r| r.time)
        .collect();
    let held: Vec<&ResponseHold> = response.holds.iter().filter(|h| h.stick).collect();
    assert_eq!(held.len(), sticks.len(), "omega {omega}: sticks");
    for (h, &t) in held.iter().zip(&sticks) {
        worst.0 = worst.0.max((h.t - t).abs());
    }
    println!(
        "{} dof at omega {omega}: {} impacts, |Δt| {:e}, |Δṙ⁻| {:e}, |Δy| {:e}",
        model.dofs(),
        response.impacts.len(),
        worst.0,
        worst.1,
        worst.2
    );
    assert!(
        worst.0 <= tolerance && worst.1 <= tolerance && worst.2 <= tolerance,
        "omega {omega}: {worst:?}"
    );
    response
}

/// The largest error of the response's `states` at `times` against `exact(t)` (the state
/// `[u…, u̇…]`), relative to the largest entry of the exact states at those times.
pub fn worst_against<F: Fn(f64) -> E, E: AsRef<[f64]>>(
    states: &[ResponseState],
    times: &[f64],
    exact: F,
) -> f64 {
    let scale = times
        .iter()
        .flat_map(|&t| exact(t).as_ref().to_vec())
        .fold(0.0, |a: f64, v| a.max(v.abs()));
    states
        .iter()
        .zip(times)
        .map(|(s, &t)| relative_error(&state(s), exact(t).as_ref(), scale))
        .fold(0.0, f64::max)
}

/// The signal `amplitude · cos(frequency · t)` from `t = 0` on, one sinusoid segment.
pub fn cosine(frequency: f64, amplitude: f64) -> Signal {
    Signal::from_segments(vec![Segment {
        start: 0.0,
        end: f64::INFINITY,
        shape: Shape::Sinusoids(vec![Sinusoid {
            frequency,
            cos: amplitude,
            sin: 0.0,
        }]),
    }])
    .expect("a sinusoid of finite frequency is a signal")
}
