//! The conventional way to integrate impacts, kept as a test and benchmark peer (not a product
//! solver): an adaptive Dormand–Prince 5(4) Runge–Kutta integrator with its standard
//! continuous extension (Hairer, Nørsett & Wanner, *Solving ODEs I*, `DOPRI5`), and, on top,
//! event location as MATLAB's `ode45` or scipy's `solve_ivp` do it: after each accepted step the
//! gap functions `r ∓ Δ` are checked for a sign change at the step's ends, the crossing is
//! bracketed on the dense output and root-found, the restitution map `ṙ⁺ = −e ṙ⁻` (momentum
//! conserved) is applied, and the integration restarts from the impact.
//!
//! Why our own integrator: `ode_solvers` (crates.io) has `Dopri5`/`Dop853` with dense output,
//! but only on a fixed output grid `dx`; its continuous extension cannot be evaluated at an
//! arbitrary time, which event location needs. The integrator here is the textbook one, about
//! a hundred lines, and tested against closed forms.
//!
//! Accuracy is whatever the step-size control gives: a crossing that starts and ends inside
//! one step (a graze) is missed, as it is by every sampling event locator.

use crate::scene::Scene;
use thiserror::Error;

/// A state `(u_o, u_i, u̇_o, u̇_i)`.
pub type State = [f64; 4];

/// A failure of the baseline integrator.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BaselineError {
    /// The step size fell below the floating-point resolution of time.
    #[error("step size underflow at t = {time}")]
    StepUnderflow {
        /// Where it happened.
        time: f64,
    },
    /// More steps than the cap were needed.
    #[error("more than {0} steps")]
    StepCap(u64),
    /// The scene has no stops or is not a valid unit.
    #[error("scene: {0}")]
    Scene(String),
}

/// Tolerances of the step-size control (the same meaning as in `ode45`/`solve_ivp`: the local
/// error of each component is kept below `atol + rtol |y|`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
}

/// `atol / rtol` of [`Tolerances::relative`]: the unit's motions are of order a metre, so an
/// absolute tolerance a thousand times below the relative one only matters near zero
/// crossings.
pub const ABSOLUTE_OVER_RELATIVE: f64 = 1e-3;

impl Tolerances {
    /// `rtol` with `atol = rtol ×` [`ABSOLUTE_OVER_RELATIVE`].
    pub fn relative(rtol: f64) -> Self {
        Self {
            rtol,
            atol: rtol * ABSOLUTE_OVER_RELATIVE,
        }
    }
}

/// The longest step, in forcing periods: a quarter period keeps the forcing's phase resolved
/// in the dense output where contacts are looked for.
const MAX_STEP_PER_PERIOD: f64 = 0.25;

/// The step-size controller of Hairer, Nørsett & Wanner (*Solving ODEs I*, II.4, the
/// `DOPRI5` code): safety factor, and the bounds on the step's change per step.
const SAFETY: f64 = 0.9;
/// A step shrinks at most to this fraction of itself.
const SHRINK_LIMIT: f64 = 0.1;
/// A step grows at most by this factor.
const GROWTH_LIMIT: f64 = 5.0;
/// After an accepted step the next grows at most by `1 / ACCEPTED_FACTOR_FLOOR`.
const ACCEPTED_FACTOR_FLOOR: f64 = 0.2;
/// The initial-step heuristic's constants (Hairer's `HINIT`): below `HINIT_SMALL` the norms
/// are treated as zero and the trial step is `HINIT_FLOOR`; the trial step is `HINIT_FRACTION`
/// of the state's own scale.
const HINIT_SMALL: f64 = 1e-5;
const HINIT_FLOOR: f64 = 1e-6;
const HINIT_FRACTION: f64 = 0.01;
/// Below this the derivatives' norms count as zero in `HINIT`.
const HINIT_ZERO: f64 = 1e-15;

// Dormand–Prince 5(4) coefficients.
const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A2: [f64; 1] = [0.2];
const A3: [f64; 2] = [3.0 / 40.0, 9.0 / 40.0];
const A4: [f64; 3] = [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0];
const A5: [f64; 4] = [
    19372.0 / 6561.0,
    -25360.0 / 2187.0,
    64448.0 / 6561.0,
    -212.0 / 729.0,
];
const A6: [f64; 5] = [
    9017.0 / 3168.0,
    -355.0 / 33.0,
    46732.0 / 5247.0,
    49.0 / 176.0,
    -5103.0 / 18656.0,
];
// The fifth-order weights (also the seventh stage's row: FSAL).
const B: [f64; 6] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
];
// Fifth minus fourth order weights: the error estimate.
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
// Dense output (Shampine's continuous extension as coded in DOPRI5).
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

fn axpy(y: &State, h: f64, terms: &[(f64, &State)]) -> State {
    let mut out = *y;
    for (c, k) in terms {
        for i in 0..4 {
            out[i] += h * c * k[i];
        }
    }
    out
}

/// The continuous extension of one accepted step `[t0, t0 + h]`.
#[derive(Debug, Clone, Copy)]
pub struct DenseStep {
    /// Start of the step.
    pub t0: f64,
    /// Its length.
    pub h: f64,
    coefficients: [State; 5],
}

impl DenseStep {
    /// The state at `t ∈ [t0, t0 + h]` (fourth order, exact at both ends).
    pub fn state(&self, t: f64) -> State {
        let s = (t - self.t0) / self.h;
        let s1 = 1.0 - s;
        let r = &self.coefficients;
        let mut y = [0.0; 4];
        for i in 0..4 {
            y[i] = r[0][i] + s * (r[1][i] + s1 * (r[2][i] + s * (r[3][i] + s1 * r[4][i])));
        }
        y
    }
}

/// An adaptive Dormand–Prince 5(4) integrator of `ẏ = f(t, y)` on four states.
pub struct Dopri5<F: Fn(f64, &State) -> State> {
    field: F,
    tolerances: Tolerances,
    /// Current time.
    pub time: f64,
    /// Current state.
    pub state: State,
    derivative: State,
    step: f64,
    /// Right-hand-side evaluations so far.
    pub evaluations: u64,
    /// Accepted steps so far.
    pub steps: u64,
}

impl<F: Fn(f64, &State) -> State> Dopri5<F> {
    /// Starts at `(time, state)`; the first step is chosen as in `DOPRI5`'s `HINIT`, capped by
    /// `max_step`.
    pub fn new(field: F, tolerances: Tolerances, time: f64, state: State, max_step: f64) -> Self {
        let derivative = field(time, &state);
        let mut integrator = Self {
            field,
            tolerances,
            time,
            state,
            derivative,
            step: max_step,
            evaluations: 1,
            steps: 0,
        };
        integrator.restart(time, state, max_step);
        integrator
    }

    /// Restarts from `(time, state)` (after an impact), choosing a fresh first step.
    pub fn restart(&mut self, time: f64, state: State, max_step: f64) {
        self.time = time;
        self.state = state;
        self.derivative = (self.field)(time, &state);
        self.evaluations += 1;
        let scale = |y: &State, i: usize| self.tolerances.atol + self.tolerances.rtol * y[i].abs();
        let norm = |v: &State| {
            ((0..4)
                .map(|i| (v[i] / scale(&state, i)).powi(2))
                .sum::<f64>()
                / 4.0)
                .sqrt()
        };
        let d0 = norm(&state);
        let d1 = norm(&self.derivative);
        let h0 = if d0 < HINIT_SMALL || d1 < HINIT_SMALL {
            HINIT_FLOOR
        } else {
            HINIT_FRACTION * d0 / d1
        }
        .min(max_step);
        let y1 = axpy(&state, h0, &[(1.0, &self.derivative)]);
        let f1 = (self.field)(time + h0, &y1);
        self.evaluations += 1;
        let diff: State = std::array::from_fn(|i| f1[i] - self.derivative[i]);
        let d2 = norm(&diff) / h0;
        let h1 = if d1.max(d2) <= HINIT_ZERO {
            (h0 * 1e-3).max(HINIT_FLOOR)
        } else {
            (HINIT_FRACTION / d1.max(d2)).powf(0.2)
        };
        self.step = (100.0 * h0).min(h1).min(max_step);
    }

    /// Takes one accepted step (retrying rejected ones), not beyond `max_step`; returns its
    /// continuous extension.
    pub fn step(&mut self, max_step: f64) -> Result<DenseStep, BaselineError> {
        let f = &self.field;
        let (t, y, k1) = (self.time, self.state, self.derivative);
        let mut h = self.step.min(max_step);
        loop {
            if h < 1e-14 * t.abs().max(1.0) {
                return Err(BaselineError::StepUnderflow { time: t });
            }
            let k2 = f(t + C[1] * h, &axpy(&y, h, &[(A2[0], &k1)]));
            let k3 = f(t + C[2] * h, &axpy(&y, h, &[(A3[0], &k1), (A3[1], &k2)]));
            let k4 = f(
                t + C[3] * h,
                &axpy(&y, h, &[(A4[0], &k1), (A4[1], &k2), (A4[2], &k3)]),
            );
            let k5 = f(
                t + C[4] * h,
                &axpy(
                    &y,
                    h,
                    &[(A5[0], &k1), (A5[1], &k2), (A5[2], &k3), (A5[3], &k4)],
                ),
            );
            let k6 = f(
                t + C[5] * h,
                &axpy(
                    &y,
                    h,
                    &[
                        (A6[0], &k1),
                        (A6[1], &k2),
                        (A6[2], &k3),
                        (A6[3], &k4),
                        (A6[4], &k5),
                    ],
                ),
            );
            let y1 = axpy(
                &y,
                h,
                &[
                    (B[0], &k1),
                    (B[2], &k3),
                    (B[3], &k4),
                    (B[4], &k5),
                    (B[5], &k6),
                ],
            );
            let k7 = f(t + h, &y1);
            self.evaluations += 6;
            let ks = [&k1, &k2, &k3, &k4, &k5, &k6, &k7];
            let mut err = 0.0;
            for i in 0..4 {
                let e: f64 = (0..7).map(|j| E[j] * ks[j][i]).sum::<f64>() * h;
                let sk = self.tolerances.atol + self.tolerances.rtol * y[i].abs().max(y1[i].abs());
                err += (e / sk).powi(2);
            }
            let err = (err / 4.0).sqrt();
            let factor = (err.powf(0.2) / SAFETY).clamp(1.0 / GROWTH_LIMIT, 1.0 / SHRINK_LIMIT);
            if err <= 1.0 {
                let mut coefficients = [[0.0; 4]; 5];
                for i in 0..4 {
                    let ydiff = y1[i] - y[i];
                    let bspl = h * k1[i] - ydiff;
                    coefficients[0][i] = y[i];
                    coefficients[1][i] = ydiff;
                    coefficients[2][i] = bspl;
                    coefficients[3][i] = ydiff - h * k7[i] - bspl;
                    coefficients[4][i] = h * (0..7).map(|j| D[j] * ks[j][i]).sum::<f64>();
                }
                self.time = t + h;
                self.state = y1;
                self.derivative = k7;
                self.step = h / factor.max(ACCEPTED_FACTOR_FLOOR);
                self.steps += 1;
                return Ok(DenseStep {
                    t0: t,
                    h,
                    coefficients,
                });
            }
            h /= factor.max(1.0);
        }
    }
}

/// One impact found by the baseline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    /// Time of the impact.
    pub time: f64,
    /// `+1` at side 1 (`r = +Δ`), `−1` at side 2.
    pub side: i8,
    /// State just before.
    pub state_before: State,
}

/// A run of the baseline: the impacts and the outer amplitude over the last period.
#[derive(Debug, Clone, PartialEq)]
pub struct BaselineRun {
    /// Impacts in the last forcing period.
    pub last_period_impacts: Vec<Impact>,
    /// `X_o = max|u_o|` over the last period, from the dense output (extrema of `u_o` located
    /// where `u̇_o` changes sign within a step, plus step ends and impacts).
    pub outer_amplitude: f64,
    /// Impacts over the whole run.
    pub impacts: u64,
    /// Accepted steps over the whole run.
    pub steps: u64,
    /// Right-hand-side evaluations over the whole run.
    pub evaluations: u64,
    /// State at the end.
    pub final_state: State,
}

/// Root of `g` on `[a, b]` with `g(a) g(b) ≤ 0`, by the Illinois variant of regula falsi, to
/// a time resolution of a few ulps.
fn root(g: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let (mut ga, mut gb) = (g(a), g(b));
    let mut side = 0;
    for _ in 0..200 {
        if (b - a).abs() <= 4.0 * f64::EPSILON * b.abs().max(1.0) {
            break;
        }
        let c = if ga != gb {
            (a * gb - b * ga) / (gb - ga)
        } else {
            0.5 * (a + b)
        };
        let c = if c > a.min(b) && c < a.max(b) {
            c
        } else {
            0.5 * (a + b)
        };
        let gc = g(c);
        if gc == 0.0 {
            return c;
        }
        if (gc > 0.0) == (gb > 0.0) {
            b = c;
            gb = gc;
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        } else {
            a = c;
            ga = gc;
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        }
    }
    // The end on the contact side (the impact has happened there).
    b
}

/// The equations of motion of `scene` at `omega`, `ẏ = f(t, y)`, free flight between stops.
pub fn vector_field(scene: &Scene, omega: f64) -> impl Fn(f64, &State) -> State {
    let unit = scene.unit_model();
    let (mo, mi, ko, ki) = (
        unit.outer_mass,
        unit.inner_mass,
        unit.outer_stiffness,
        unit.inner_stiffness,
    );
    let (co, ci) = unit.damping.map_or((0.0, 0.0), |d| (d.outer, d.inner));
    let ug = unit.base_amplitude;
    move |t: f64, y: &State| {
        let (s, c) = (omega * t).sin_cos();
        let base = ko * ug * c - co * ug * omega * s;
        let spring = ki * (y[1] - y[0]) + ci * (y[3] - y[2]);
        let outer = (base - ko * y[0] - co * y[2] + spring) / mo;
        let inner = -spring / mi;
        [y[2], y[3], outer, inner]
    }
}

/// Runs the baseline on `scene` at `omega` from `start` at `start_time` (base phase
/// `ω·start_time`) for `periods` forcing periods, with impacts located on the dense output; at
/// most `max_steps` steps.
pub fn run(
    scene: &Scene,
    omega: f64,
    start_time: f64,
    start: State,
    periods: u64,
    tolerances: Tolerances,
    max_steps: u64,
) -> Result<BaselineRun, BaselineError> {
    let stops = scene
        .stops_model()
        .ok_or_else(|| BaselineError::Scene("the scene has no stops".into()))?;
    let (gap, e) = (stops.gap, stops.restitution);
    let unit = scene.unit_model();
    let (mo, mi) = (unit.outer_mass, unit.inner_mass);
    let period = std::f64::consts::TAU / omega;
    let end = start_time + period * periods as f64;
    let last_start = end - period;
    let max_step = MAX_STEP_PER_PERIOD * period;
    let mut integrator = Dopri5::new(
        vector_field(scene, omega),
        tolerances,
        start_time,
        start,
        max_step,
    );
    let mut impacts = 0u64;
    let mut last = Vec::new();
    let mut amplitude: f64 = 0.0;
    let gap_side = |y: &State| y[1] - y[0];
    while integrator.time < end {
        if integrator.steps >= max_steps {
            return Err(BaselineError::StepCap(max_steps));
        }
        let remaining = end - integrator.time;
        let dense = integrator.step(max_step.min(remaining))?;
        let (t0, t1) = (dense.t0, dense.t0 + dense.h);
        let y0 = dense.state(t0);
        let y1 = integrator.state;
        // A crossing of a stop, detected at the step's ends (as ode45 / solve_ivp do).
        let r0 = gap_side(&y0);
        let r1 = gap_side(&y1);
        let side = if r0 < gap && r1 >= gap {
            1
        } else if r0 > -gap && r1 <= -gap {
            -1
        } else {
            0
        };
        let (t_end, y_end) = if side != 0 {
            let stop = f64::from(side) * gap;
            let ti = root(
                |t| f64::from(side) * (gap_side(&dense.state(t)) - stop),
                t0,
                t1,
            );
            let before = dense.state(ti);
            // Newton restitution along r, momentum conserved: ṙ⁺ = −e ṙ⁻.
            let rdot = before[3] - before[2];
            let jump = (1.0 + e) * rdot * (mo * mi / (mo + mi));
            let mut after = before;
            after[2] += jump / mo;
            after[3] -= jump / mi;
            impacts += 1;
            if ti >= last_start {
                last.push(Impact {
                    time: ti,
                    side,
                    state_before: before,
                });
                amplitude = amplitude.max(before[0].abs());
            }
            integrator.restart(ti, after, max_step);
            (ti, before)
        } else {
            (t1, y1)
        };
        // Extrema of u_o within the part of the step that was kept.
        if t_end >= last_start {
            amplitude = amplitude.max(y_end[0].abs());
            let a = t0.max(last_start);
            let ya = dense.state(a);
            amplitude = amplitude.max(ya[0].abs());
            if ya[2] * y_end[2] < 0.0 {
                let tm = root(|t| -dense.state(t)[2] * ya[2].signum(), a, t_end);
                amplitude = amplitude.max(dense.state(tm)[0].abs());
            }
        }
    }
    Ok(BaselineRun {
        last_period_impacts: last,
        outer_amplitude: amplitude,
        impacts,
        steps: integrator.steps,
        evaluations: integrator.evaluations,
        final_state: integrator.state,
    })
}
