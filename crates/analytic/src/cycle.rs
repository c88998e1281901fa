//! Periodic orbits of any impact signature, by the Nigm–Shabana method with Newton.
//!
//! A cycle of `p` forcing periods (`pT`) has `n` impacts at `0 = t₁ < t₂ < … < tₙ < pT` on
//! sides `s_j` (`+1` at `r = +Δ`, `−1` at `r = −Δ`), in the canonical order of its
//! [`Signature`]. The base moves as `u_g cos(ωt + α)`. For fixed `x = (α, t₂ … tₙ)`
//! everything else is linear: with the augmented flow `Φ_j = exp(Â τ_j)` of flight `j`
//! (`τ_j = t_{j+1} − t_j`, `t_{n+1} = pT`) and the augmented impact map `Ĝ = diag(I₂, G, I₂)`,
//! the cycle map `Ψ = Ĝ Φₙ Ĝ Φₙ₋₁ ⋯ Ĝ Φ₁` carries `(y₁, p₀)`, the state just after the first
//! impact and the forcing phase `p₀ = (cos α, sin α)`, round the cycle. Periodicity
//! `(I − Ψ_xx) y₁ = Ψ_xp p₀` fixes `y₁` (a 4×4 solve), and the `n` contact conditions
//! `r(t_j⁻) = s_j Δ` are the residuals: `n` equations in `n` unknowns.
//!
//! Newton uses exact derivatives from the same closed form: `∂Φ_j/∂τ_j = Â Φ_j`,
//! `∂p₀/∂α = (−sin α, cos α)`, and the periodicity solve is differentiated implicitly,
//! `dy₁ = (I − Ψ_xx)⁻¹ (dΨ_xx y₁ + dΨ_xp p₀ + Ψ_xp dp₀)`.

use crate::flow::{join, Augmented, ForcedFlow};
use crate::linear::{modes, transmittance_db};
use crate::orbit::{
    eigenvalues, impact, relative_displacement, saltation, wrap, Side, Violation, STABILITY_MARGIN,
    VIABILITY_TOLERANCE,
};
use crate::signature::Signature;
use crate::symmetric::OrbitError;
use crate::unit::{Stops, Unit};
use nalgebra::{Complex, DMatrix, DVector, Matrix2, Matrix4, Matrix6, SMatrix, Vector2, Vector4};
use std::collections::HashMap;

type Matrix12 = SMatrix<f64, 12, 12>;

/// Cap on Newton iterations. From a start inside the basin Newton converges quadratically in
/// well under ten steps; the cap bounds starts that wander (most multi-start points do not
/// lie near an orbit) and is the only bound on the work of one [`solve_signature`].
pub const NEWTON_ITERATIONS: usize = 40;

/// Newton has converged when the largest contact residual `|r(t_j⁻) − s_j Δ|` is below this
/// fraction of the motion's size `max(Δ, |u_o(0)|, |u_i(0)|)`: about 450 `ε`, the rounding
/// left by a chain of a few 6×6 exponentials and a 4×4 solve.
pub const NEWTON_TOLERANCE: f64 = 1e-13;

/// Fallback acceptance: when the Newton step has shrunk to rounding ([`STEP_ROUNDING`]) the
/// residual cannot be reduced further; it is then accepted if below this fraction of the
/// motion's size (two orders looser than [`NEWTON_TOLERANCE`], for ill-conditioned cycles).
pub const NEWTON_ACCEPTANCE: f64 = 1e-11;

/// A Newton step below this (in radians of `α` and in fractions of the cycle) no longer moves
/// the unknowns beyond a few ulps of numbers of order one.
pub const STEP_ROUNDING: f64 = 1e-15;

/// Halvings of the Newton step when it would reorder the impacts or raise the residual's
/// 2-norm: `2⁻¹⁰ ≈ 1e-3` of a step; beyond that the direction is useless and the start is
/// abandoned. (30 halvings cost the multi-start 2–3 times more and found the same viable
/// orbits on the paper unit; see [`signature_orbits`].)
pub(crate) const LINE_SEARCH_HALVINGS: usize = 10;

/// A flight shorter than this fraction of the cycle is two impacts merging: a grazing limit,
/// not an orbit of the signature. Far below any grid spacing, far above rounding of the times.
pub const MIN_FLIGHT: f64 = 1e-9;

/// Grid points per period of the fastest oscillation of the flow (`max(ω, ω_n)`) in the
/// multi-start over impact phases: each impact time of any orbit lies within `1/32` of that
/// period of a grid point. Four points per period (an eighth) missed non-viable two-impact
/// orbits of the paper unit at `ω = 0.8` whose Newton basins are narrow; sixteen found
/// every viable orbit that grids up to four times finer found (see [`signature_orbits`]).
pub const GRID_PER_OSCILLATION: f64 = 16.0;

/// Fewest grid intervals over the cycle, whatever the frequencies: with `n ≤ 4` impacts
/// there are then at least `C(15, 3) = 455` ordered phase tuples.
pub const MIN_GRID: usize = 16;

/// Up to this many impact-phase tuples, Newton starts from every minimum in `α` of every
/// tuple's linear residual; above it, only from the minima over the joint grid of impact
/// phases and `α`. A Newton start costs about 0.2 ms, so this bounds the full search to
/// about two seconds (`n = 4`, `p = 1`, `ω ≥ 1.2` on the paper unit stay below it).
pub const FULL_START_TUPLES: usize = 5000;

/// Cap on the impact-phase tuples of [`signature_orbits`]: at low `ω` or long cycles the
/// grid of [`GRID_PER_OSCILLATION`] is coarsened until `C(N − 1, n − 1)` tuples fit, which
/// bounds the scan's memory (64 residuals per tuple, about 30 MB) and its time (about a
/// second). Not binding on the paper unit for `n ≤ 4` impacts above `ω ≈ 1.08` with `p = 2`,
/// above `ω ≈ 0.54` with `p = 1`.
pub const MAX_TUPLES: usize = 60_000;

/// Samples of `α` on which the linear contact residual is scanned for each phase tuple; its
/// square is a trigonometric polynomial of degree 2 in `α` (at most two local minima), so 64
/// samples (`π/32` apart) land within `π/64` of each minimum, and separate the two unless
/// they nearly merge (then one start serves both).
pub const ALPHA_SCAN: usize = 64;

/// Two converged solutions are the same orbit when their base phases (after bringing both
/// to the canonical first impact) and impact phases differ by less than this: Newton pins
/// them to about `1e-13`, and distinct orbits of the unit lie many orders further apart.
pub const DEDUP_TOLERANCE: f64 = 1e-8;

/// Energy scale floor for [`SignatureOrbit::energy_residual`], as a fraction of `k_o u_g²`:
/// a conservative orbit (no dashpots, `e = 1`) exchanges no energy, and its residual is then
/// measured against this fraction of the unit's energy scale rather than against rounding.
pub const ENERGY_FLOOR: f64 = 1e-6;

/// The energy balance of a cycle, each term computed on its own.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyBalance {
    /// Work done by the base over the cycle, `∫ −(k_o (u_o − u_g) + c_o (u̇_o − u̇_g)) u̇_g dt`.
    pub base_work: f64,
    /// Dissipation of both dashpots, `∫ c_o (u̇_o − u̇_g)² + c_i ṙ² dt`.
    pub dashpot_dissipation: f64,
    /// Impact losses `Σ ½ μ (1 − e²) ṙ⁻²`.
    pub impact_losses: f64,
}

/// A periodic orbit of an impact signature and its verdicts.
///
/// Times and phases are measured from the first impact of the canonical signature.
#[derive(Debug, Clone, PartialEq)]
pub struct SignatureOrbit {
    /// The signature, canonical.
    pub signature: Signature,
    /// Number of forcing periods in the cycle.
    pub period: u32,
    /// Angular frequency `ω` of the forcing.
    pub omega: f64,
    /// Impact times as fractions of the cycle `pT`, in canonical order, first = 0.
    pub impact_phases: Vec<f64>,
    /// Base-motion phase at the first canonical impact, radians in `(−π, π]`.
    pub alpha: f64,
    /// State `(u_o, u_i, u̇_o, u̇_i)` just after the first canonical impact.
    pub state_after_impact: Vector4<f64>,
    /// State just before each impact, in canonical order.
    pub states_before_impacts: Vec<Vector4<f64>>,
    /// `X_o = max |u_o(t)|` over the cycle, from the rigorous extrema of every flight.
    pub outer_amplitude: f64,
    /// `20 log10(X_o / u_g)`.
    pub transmittance_db: f64,
    /// True when no [`Violation`] was found.
    pub viable: bool,
    /// Every condition that fails; times from the first canonical impact.
    pub violations: Vec<Violation>,
    /// Eigenvalues of the monodromy matrix (flight propagators and saltation matrices).
    pub floquet_multipliers: Vec<Complex<f64>>,
    /// Every multiplier has modulus `< 1 −` [`STABILITY_MARGIN`].
    pub stable: bool,
    /// The monodromy matrix over the cycle, from just after the first canonical impact.
    pub monodromy: Matrix4<f64>,
    /// The energy balance over the cycle.
    pub energy: EnergyBalance,
    /// `|work − dissipation − impact losses| / max(|work|, dissipation + losses,`
    /// [`ENERGY_FLOOR`]` k_o u_g²)`.
    pub energy_residual: f64,
    /// Newton iterations taken to converge.
    pub newton_iterations: usize,
}

/// The cycle's problem: flow, impact map and signature.
struct Problem<'a> {
    flow: ForcedFlow,
    g: Matrix2<f64>,
    g_hat: Matrix6<f64>,
    gap: f64,
    sides: &'a [i8],
    cycle: f64,
}

/// The cycle evaluated at one `(α, t₂ … tₙ)`.
struct Evaluation {
    /// `Φ_j` of each flight.
    flights: Vec<Matrix6<f64>>,
    /// `Pre_j`: from `(y₁, p₀)` to the augmented state just before impact `j + 1`
    /// (impact `n + 1` being the first impact of the next cycle).
    pre: Vec<Matrix6<f64>>,
    /// State just after the first impact.
    y1: Vector4<f64>,
    /// `p₀`.
    p0: Vector2<f64>,
    /// Contact residuals.
    residual: DVector<f64>,
    /// `∂ residual / ∂ (α, φ₂ … φₙ)`, `φ` the impact times as fractions of the cycle.
    jacobian: DMatrix<f64>,
}

impl<'a> Problem<'a> {
    fn new(unit: &Unit, stops: &Stops, omega: f64, signature: &'a Signature) -> Self {
        let flow = ForcedFlow::new(unit, omega);
        let g = stops.impact_map(unit);
        let mut g_hat = Matrix6::identity();
        g_hat.fixed_view_mut::<2, 2>(2, 2).copy_from(&g);
        let cycle = flow.period() * signature.period() as f64;
        Self {
            flow,
            g,
            g_hat,
            gap: stops.gap,
            sides: signature.sides(),
            cycle,
        }
    }

    /// Residuals and their exact Jacobian at `α` and impact fractions `phases` (first 0).
    fn evaluate(&self, alpha: f64, phases: &[f64]) -> Result<Evaluation, OrbitError> {
        let n = self.sides.len();
        let a = self.flow.augmented_matrix();
        let h = join(&relative_displacement(), &Vector2::zeros());
        let flights: Vec<Matrix6<f64>> = (0..n)
            .map(|f| {
                let end = if f + 1 < n { phases[f + 1] } else { 1.0 };
                (a * ((end - phases[f]) * self.cycle)).exp()
            })
            .collect();
        let mut pre = Vec::with_capacity(n);
        pre.push(flights[0]);
        for f in 1..n {
            pre.push(flights[f] * self.g_hat * pre[f - 1]);
        }
        let psi = self.g_hat * pre[n - 1];
        let k = Matrix4::identity() - psi.fixed_view::<4, 4>(0, 0);
        let lu = k.lu();
        let omega = self.flow.omega();
        if !lu.is_invertible() {
            return Err(OrbitError::SingularCycle { omega });
        }
        let solve = |b: Vector4<f64>| lu.solve(&b).ok_or(OrbitError::SingularCycle { omega });
        let psi_xp = psi.fixed_view::<4, 2>(0, 4).into_owned();
        let p0 = Vector2::new(alpha.cos(), alpha.sin());
        let y1 = solve(psi_xp * p0)?;
        let z1 = join(&y1, &p0);
        let contact = |z: &Augmented, j: usize| h.dot(z) - self.sides[j] as f64 * self.gap;
        let mut residual = DVector::zeros(n);
        residual[0] = contact(&z1, 0);
        for f in 0..n - 1 {
            residual[f + 1] = contact(&(pre[f] * z1), f + 1);
        }

        let mut jacobian = DMatrix::zeros(n, n);
        // α: only p₀ moves.
        let dp0 = Vector2::new(-alpha.sin(), alpha.cos());
        let dy1 = solve(psi_xp * dp0)?;
        let dz1 = join(&dy1, &dp0);
        jacobian[(0, 0)] = h.dot(&dz1);
        for f in 0..n - 1 {
            jacobian[(f + 1, 0)] = h.dot(&(pre[f] * dz1));
        }
        // t_i (impact i, 0-based i ≥ 1): τ_{i−1} grows, τ_i shrinks.
        for i in 1..n {
            let c = |f: usize| (f + 1 == i) as i32 as f64 - (f == i) as i32 as f64;
            let mut dpre = Vec::with_capacity(n);
            dpre.push(a * flights[0] * c(0));
            for f in 1..n {
                let mut d = flights[f] * self.g_hat * dpre[f - 1];
                let cf = c(f);
                if cf != 0.0 {
                    d += a * flights[f] * self.g_hat * pre[f - 1] * cf;
                }
                dpre.push(d);
            }
            let dpsi = self.g_hat * dpre[n - 1];
            let dy1 =
                solve(dpsi.fixed_view::<4, 4>(0, 0) * y1 + dpsi.fixed_view::<4, 2>(0, 4) * p0)?;
            let dz1 = join(&dy1, &Vector2::zeros());
            jacobian[(0, i)] = h.dot(&dz1) * self.cycle;
            for f in 0..n - 1 {
                jacobian[(f + 1, i)] = h.dot(&(dpre[f] * z1 + pre[f] * dz1)) * self.cycle;
            }
        }
        Ok(Evaluation {
            flights,
            pre,
            y1,
            p0,
            residual,
            jacobian,
        })
    }

    /// Size of the motion against which residuals are measured.
    fn scale(&self, y1: &Vector4<f64>) -> f64 {
        self.gap.max(y1[0].abs()).max(y1[1].abs())
    }

    /// Newton from `(α, phases)`; returns the converged unknowns and the iteration count.
    fn newton(&self, guess: &[f64]) -> Result<(Vec<f64>, usize), OrbitError> {
        let n = self.sides.len();
        let omega = self.flow.omega();
        let mut x = guess.to_vec();
        let ordered = |x: &[f64]| {
            (1..n).all(|i| {
                let prev = if i == 1 { 0.0 } else { x[i - 1] };
                x[i] - prev > MIN_FLIGHT
            }) && (n == 1 || 1.0 - x[n - 1] > MIN_FLIGHT)
        };
        let phases = |x: &[f64]| {
            let mut p = vec![0.0; n];
            p[1..n].copy_from_slice(&x[1..n]);
            p
        };
        let mut eval = self.evaluate(x[0], &phases(&x))?;
        let mut norm = eval.residual.amax();
        let mut merit = eval.residual.norm();
        for iteration in 0..=NEWTON_ITERATIONS {
            let scale = self.scale(&eval.y1);
            if !norm.is_finite() {
                break;
            }
            if norm <= NEWTON_TOLERANCE * scale {
                // One more full step polishes the quadratic convergence down to rounding;
                // kept only if it lowers the residual.
                let polished = eval.jacobian.clone().lu().solve(&(-&eval.residual));
                if let Some(step) = polished {
                    let trial: Vec<f64> = x.iter().zip(step.iter()).map(|(a, d)| a + d).collect();
                    if ordered(&trial) {
                        if let Ok(e) = self.evaluate(trial[0], &phases(&trial)) {
                            if e.residual.norm() < merit {
                                return Ok((trial, iteration + 1));
                            }
                        }
                    }
                }
                return Ok((x, iteration));
            }
            if iteration == NEWTON_ITERATIONS {
                break;
            }
            let step = eval
                .jacobian
                .clone()
                .lu()
                .solve(&(-&eval.residual))
                .ok_or(OrbitError::SingularCycle { omega })?;
            if step.amax() <= STEP_ROUNDING {
                if norm <= NEWTON_ACCEPTANCE * scale {
                    return Ok((x, iteration));
                }
                break;
            }
            let mut lambda = 1.0;
            let mut accepted = false;
            for _ in 0..LINE_SEARCH_HALVINGS {
                let trial: Vec<f64> = x
                    .iter()
                    .zip(step.iter())
                    .map(|(a, d)| a + lambda * d)
                    .collect();
                if ordered(&trial) {
                    if let Ok(e) = self.evaluate(trial[0], &phases(&trial)) {
                        let m = e.residual.norm();
                        if m < merit {
                            x = trial;
                            norm = e.residual.amax();
                            eval = e;
                            merit = m;
                            accepted = true;
                            break;
                        }
                    }
                }
                lambda *= 0.5;
            }
            if !accepted {
                if norm <= NEWTON_ACCEPTANCE * scale {
                    return Ok((x, iteration));
                }
                break;
            }
        }
        Err(OrbitError::NoConvergence {
            omega,
            residual: norm,
        })
    }
}

/// The orbit of `signature` nearest (in Newton's sense) to `guess = (α, φ₂, …, φₙ)`: the base
/// phase at the first canonical impact and the impact times of the others as fractions of the
/// cycle (`0 < φ₂ < … < φₙ < 1`). The unit and stops are not validated here.
///
/// # Errors
/// [`OrbitError::InvalidFrequency`] unless `omega` is finite and positive;
/// [`OrbitError::InvalidGuess`] when `guess` does not have `n` finite entries with ordered
/// phases in `(0, 1)`; [`OrbitError::SingularCycle`] when the periodicity solve or the Newton
/// Jacobian is singular; [`OrbitError::NoConvergence`] when Newton does not reach
/// [`NEWTON_TOLERANCE`] within [`NEWTON_ITERATIONS`].
pub fn solve_signature(
    unit: &Unit,
    stops: &Stops,
    omega: f64,
    signature: &Signature,
    guess: &[f64],
) -> Result<SignatureOrbit, OrbitError> {
    if !(omega.is_finite() && omega > 0.0) {
        return Err(OrbitError::InvalidFrequency { omega });
    }
    let n = signature.impacts();
    if !is_ordered_guess(guess, n) {
        return Err(OrbitError::InvalidGuess {
            impacts: n,
            len: guess.len(),
        });
    }
    let problem = Problem::new(unit, stops, omega, signature);
    let (x, iterations) = problem.newton(guess)?;
    let (alpha, phases) = canonical_shift(&problem, signature, &x);
    assemble(unit, stops, &problem, signature, alpha, &phases, iterations)
}

/// Among the rotations of the cycle that keep the canonical signature, the representation with
/// the smallest wrapped `α`.
/// Whether `guess = (α, φ₂, …, φ_n)` is a usable start for `n` impacts: `n` finite entries
/// with the impact phases ordered in `(0, 1)` (`α` is free).
pub(crate) fn is_ordered_guess(guess: &[f64], n: usize) -> bool {
    guess.len() == n
        && guess.iter().all(|v| v.is_finite())
        && (1..n).all(|i| guess[i] > if i == 1 { 0.0 } else { guess[i - 1] })
        && (n == 1 || guess[n - 1] < 1.0)
}

fn canonical_shift(problem: &Problem, signature: &Signature, x: &[f64]) -> (f64, Vec<f64>) {
    let n = signature.impacts();
    let mut phases = vec![0.0; n];
    phases[1..n].copy_from_slice(&x[1..n]);
    crate::sequence_search::smallest_rotation(
        x[0],
        phases,
        signature.symmetries(),
        problem.flow.omega() * problem.cycle,
    )
}

/// Builds the orbit at converged unknowns and derives its verdicts.
fn assemble(
    unit: &Unit,
    stops: &Stops,
    problem: &Problem,
    signature: &Signature,
    alpha: f64,
    phases: &[f64],
    newton_iterations: usize,
) -> Result<SignatureOrbit, OrbitError> {
    let n = signature.impacts();
    let sides = signature.sides();
    let flow = &problem.flow;
    let e = problem.evaluate(alpha, phases)?;
    let z1 = join(&e.y1, &e.p0);
    // Augmented state just before impact j (impact 0 closes the cycle).
    let before: Vec<Augmented> = (0..n)
        .map(|j| e.pre[if j == 0 { n - 1 } else { j - 1 }] * z1)
        .collect();
    let x_before: Vec<Vector4<f64>> = before.iter().map(|z| z.fixed_rows::<4>(0).into()).collect();
    let p_at: Vec<Vector2<f64>> = (0..n)
        .map(|j| {
            if j == 0 {
                e.p0
            } else {
                before[j].fixed_rows::<2>(4).into()
            }
        })
        .collect();
    let after: Vec<Vector4<f64>> = x_before.iter().map(|x| impact(&problem.g, x)).collect();

    let gap = problem.gap;
    let r_fn = join(&relative_displacement(), &Vector2::zeros());
    let uo_fn = Augmented::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let mut violations = Vec::new();
    let rdot: Vec<f64> = x_before.iter().map(|x| x[3] - x[2]).collect();
    let side_of = |s: i8| if s > 0 { Side::One } else { Side::Two };
    let wrong: Vec<bool> = (0..n).map(|j| sides[j] as f64 * rdot[j] <= 0.0).collect();
    for j in 0..n {
        if wrong[j] {
            violations.push(Violation::WrongApproach {
                side: side_of(sides[j]),
                relative_velocity: rdot[j],
            });
        }
    }
    let tol = VIABILITY_TOLERANCE * gap;
    let mut outer_amplitude: f64 = 0.0;
    let mut energy = EnergyBalance {
        base_work: 0.0,
        dashpot_dissipation: 0.0,
        impact_losses: 0.0,
    };
    let (work_q, dissipation_q) = energy_forms(unit, flow.omega());
    for f in 0..n {
        let end = if f + 1 < n { phases[f + 1] } else { 1.0 };
        let duration = (end - phases[f]) * problem.cycle;
        let start = join(&after[f], &p_at[f]);
        let ext = flow.extrema(&start, duration, &[r_fn, uo_fn]);
        outer_amplitude = outer_amplitude.max(ext[1].max.abs()).max(ext[1].min.abs());
        let t0 = phases[f] * problem.cycle;
        let next = (f + 1) % n;
        // An excursion beyond a stop that one of this flight's own impacts on that stop reaches
        // from outside is the flight passing through the stop; any other is a contact the
        // signature does not have.
        let attached = |s: i8| (sides[f] == s && wrong[f]) || (sides[next] == s && wrong[next]);
        for (s, excess, time) in [
            (1i8, ext[0].max - gap, ext[0].argmax),
            (-1i8, -gap - ext[0].min, ext[0].argmin),
        ] {
            if excess > tol {
                let (side, time) = (side_of(s), t0 + time);
                violations.push(if attached(s) {
                    Violation::Penetration { side, time, excess }
                } else {
                    Violation::ExtraImpact { side, time, excess }
                });
            }
        }
        energy.base_work += quadratic_integral(flow, &work_q, &start, duration);
        energy.dashpot_dissipation += quadratic_integral(flow, &dissipation_q, &start, duration);
    }
    let e2 = stops.restitution * stops.restitution;
    energy.impact_losses = rdot
        .iter()
        .map(|v| 0.5 * unit.reduced_mass() * (1.0 - e2) * v * v)
        .sum();
    let reference = energy
        .base_work
        .abs()
        .max(energy.dashpot_dissipation.abs() + energy.impact_losses)
        .max(ENERGY_FLOOR * unit.outer_stiffness * unit.base_amplitude.powi(2));
    let energy_residual =
        (energy.base_work - energy.dashpot_dissipation - energy.impact_losses).abs() / reference;

    // Monodromy from just after impact 0: E₀, then S₁, E₁, …, Eₙ₋₁, S₀.
    let mut monodromy = Matrix4::identity();
    for f in 0..n {
        let next = (f + 1) % n;
        let hom = e.flights[f].fixed_view::<4, 4>(0, 0).into_owned();
        let s = saltation(flow, &problem.g, &x_before[next], &p_at[next]);
        monodromy = s * hom * monodromy;
    }
    let floquet_multipliers: Vec<Complex<f64>> = eigenvalues(&monodromy)
        .map(|e| e.to_vec())
        .unwrap_or_else(|| vec![Complex::new(f64::NAN, f64::NAN); 4]);
    let stable = floquet_multipliers
        .iter()
        .all(|m| m.norm() < 1.0 - STABILITY_MARGIN);

    Ok(SignatureOrbit {
        signature: signature.clone(),
        period: signature.period(),
        omega: flow.omega(),
        impact_phases: phases.to_vec(),
        alpha,
        state_after_impact: after[0],
        states_before_impacts: x_before,
        outer_amplitude,
        transmittance_db: transmittance_db(outer_amplitude, unit.base_amplitude),
        viable: violations.is_empty(),
        violations,
        floquet_multipliers,
        stable,
        monodromy,
        energy,
        energy_residual,
        newton_iterations,
    })
}

/// The quadratic forms `Q` (`rate = zᵀ Q z` on the augmented state) of the base's power and
/// of the dashpots' dissipation. With `u_g(t) = u_g p₀`, `u̇_g = −u_g ω p₁`:
/// power `−(k_o (u_o − u_g) + c_o (u̇_o − u̇_g)) u̇_g`, dissipation
/// `c_o (u̇_o − u̇_g)² + c_i (u̇_i − u̇_o)²`.
fn energy_forms(unit: &Unit, omega: f64) -> (Matrix6<f64>, Matrix6<f64>) {
    let (co, ci) = unit.damping.map_or((0.0, 0.0), |d| (d.outer, d.inner));
    let (ko, ug) = (unit.outer_stiffness, unit.base_amplitude);
    // Force on the base side of the spring-dashpot, k_o(u_o − u_g) + c_o(u̇_o − u̇_g), as w·z.
    let w = Augmented::new(ko, 0.0, co, 0.0, -ko * ug, co * ug * omega);
    // −u̇_g = u_g ω p₁.
    let v = Augmented::new(0.0, 0.0, 0.0, 0.0, 0.0, ug * omega);
    let work = 0.5 * (v * w.transpose() + w * v.transpose());
    let a = Augmented::new(0.0, 0.0, 1.0, 0.0, 0.0, ug * omega);
    let b = Augmented::new(0.0, 0.0, -1.0, 1.0, 0.0, 0.0);
    let dissipation = a * a.transpose() * co + b * b.transpose() * ci;
    (work, dissipation)
}

/// `∫₀^τ z(t)ᵀ Q z(t) dt` along the exact flow from `start`, in closed form by Van Loan's
/// block exponential: `exp([[−Âᵀ, Q], [0, Â]] τ) = [[·, G], [0, e^{Âτ}]]` and
/// `∫₀^τ e^{Âᵀs} Q e^{Âs} ds = e^{Âτ}ᵀ G`.
fn quadratic_integral(flow: &ForcedFlow, q: &Matrix6<f64>, start: &Augmented, tau: f64) -> f64 {
    let a = flow.augmented_matrix();
    let mut c = Matrix12::zeros();
    c.fixed_view_mut::<6, 6>(0, 0).copy_from(&(-a.transpose()));
    c.fixed_view_mut::<6, 6>(0, 6).copy_from(q);
    c.fixed_view_mut::<6, 6>(6, 6).copy_from(a);
    let ex = (c * tau).exp();
    let gram = ex.fixed_view::<6, 6>(6, 6).transpose() * ex.fixed_view::<6, 6>(0, 6);
    start.dot(&(gram * start))
}

/// Every orbit of `signature` found by a systematic multi-start over impact phases,
/// deduplicated, viable or not, sorted by `α`.
///
/// The cycle `pT` is cut into `N = max(`[`MIN_GRID`]`, ⌈`[`GRID_PER_OSCILLATION`]` · p ·
/// max(ω, ω_n)/ω⌉)` intervals: [`GRID_PER_OSCILLATION`] points per period of the fastest
/// oscillation of the motion (the forcing or the highest natural frequency `ω_n`). Every
/// ordered tuple `0 < φ₂ < … < φₙ < 1` of grid points is scanned. The phase `α` is not a
/// Newton guess from a coarse grid: for fixed impact times the contact residuals are
/// *linear* in `(cos α, sin α)`, so each tuple's squared residual is scanned on
/// [`ALPHA_SCAN`] values of `α` for the cost of one cycle. Newton starts from every minimum
/// in `α` of every tuple when there are at most [`FULL_START_TUPLES`] tuples, and otherwise
/// from the nodes that are minima over the joint grid of impact phases and `α`.
///
/// Why this grid: each impact time of any orbit lies within `1/32` of the fastest period of
/// the motion from a grid tuple, where `r(t)` near an impact is close to its linearisation,
/// and `α` is then the best one for those times. For `n ≤ 4` impacts and `p ≤ 2` on the
/// paper unit (undamped and damped, `ω` from 0.8 to 3) no refinement of the grid (up to
/// 4 times finer for two impacts, 2 to 3 times for four) found a viable orbit this grid
/// missed; refinement does find a few more *non-viable* solutions, whose basins are smaller
/// than a grid cell (near folds). This is a measured and reasoned claim, not a proof.
///
/// Orbits of a repeated signature (e.g. `+-+-` over 2 periods) include those of its root
/// (`+-` over 1 period) traversed twice: they are solutions too. A start whose Newton
/// iteration fails is dropped silently: most starts lie far from any orbit. The unit and
/// stops are not validated here.
pub fn signature_orbits(
    unit: &Unit,
    stops: &Stops,
    omega: f64,
    signature: &Signature,
) -> Vec<SignatureOrbit> {
    if !(omega.is_finite() && omega > 0.0) {
        return Vec::new();
    }
    let nat = modes(unit)
        .natural_frequencies_squared
        .iter()
        .fold(omega, |m, w2| m.max(w2.sqrt()));
    let wanted = (GRID_PER_OSCILLATION * signature.period() as f64 * nat / omega).ceil();
    let mut grid = (wanted.min(MAX_TUPLES as f64) as usize).max(MIN_GRID);
    while grid > MIN_GRID && tuples(grid, signature.impacts()) > MAX_TUPLES as f64 {
        grid -= 1;
    }
    signature_orbits_on_grid(unit, stops, omega, signature, grid)
}

/// Number of ordered impact-phase tuples `C(grid − 1, n − 1)` of a grid, as a float.
fn tuples(grid: usize, n: usize) -> f64 {
    (1..n).fold(1.0, |c, k| c * (grid - k) as f64 / k as f64)
}

/// [`signature_orbits`] with an explicit number of grid intervals over the cycle. The work
/// and memory grow like the number of tuples, `C(grid − 1, n − 1)`: the caller bounds it.
/// An empty list when `grid` is below the number of impacts or `omega` is not finite and
/// positive.
pub fn signature_orbits_on_grid(
    unit: &Unit,
    stops: &Stops,
    omega: f64,
    signature: &Signature,
    grid: usize,
) -> Vec<SignatureOrbit> {
    let n = signature.impacts();
    if grid < n || !(omega.is_finite() && omega > 0.0) {
        return Vec::new();
    }
    let problem = Problem::new(unit, stops, omega, signature);
    let a = problem.flow.augmented_matrix();
    let h = join(&relative_displacement(), &Vector2::zeros());
    let steps: Vec<Matrix6<f64>> = (0..=grid)
        .map(|m| (a * (m as f64 * problem.cycle / grid as f64)).exp())
        .collect();
    // Pass 1: for every grid tuple, the squared linear contact residual on the α scan.
    let mut scanned: HashMap<Vec<usize>, Vec<f64>> = HashMap::new();
    let mut tuple: Vec<usize> = (0..n).collect();
    loop {
        if n == 1 || tuple[n - 1] < grid {
            scanned.insert(
                tuple.clone(),
                linear_scan(&problem, &steps, &tuple, grid, &h),
            );
        }
        if !crate::sequence_search::next_tuple(&mut tuple, grid) {
            break;
        }
    }
    // Pass 2: Newton from the nodes (tuple, α sample) that are local minima of the residual
    // in α, and (when there are more than FULL_START_TUPLES tuples) also over their
    // neighbours in the joint grid (±1 in any impact index and in α).
    let starts = crate::sequence_search::start_nodes(&scanned, |t| {
        crate::sequence_search::cube_neighbours(t)
    });
    let mut found: Vec<(Vec<f64>, SignatureOrbit)> = Vec::new();
    for (tuple, k) in starts {
        let guess = crate::sequence_search::start_guess(tuple, k, grid);
        {
            let Ok((x, iterations)) = problem.newton(&guess) else {
                continue;
            };
            let (alpha, phases) = canonical_shift(&problem, signature, &x);
            if found.iter().any(|(k, _)| same_orbit(k, alpha, &phases)) {
                continue;
            }
            if let Ok(orbit) =
                assemble(unit, stops, &problem, signature, alpha, &phases, iterations)
            {
                let mut key = vec![alpha];
                key.extend_from_slice(&phases[1..]);
                found.push((key, orbit));
            }
        }
    }
    let mut orbits: Vec<SignatureOrbit> = found.into_iter().map(|(_, o)| o).collect();
    orbits.sort_by(|a, b| a.alpha.total_cmp(&b.alpha));
    orbits
}

/// Whether a found orbit's key `(α, φ₂ …)` matches `(alpha, phases)` within
/// [`DEDUP_TOLERANCE`] (angles compared modulo 2π).
fn same_orbit(key: &[f64], alpha: f64, phases: &[f64]) -> bool {
    wrap(key[0] - alpha).abs() < DEDUP_TOLERANCE
        && key[1..]
            .iter()
            .zip(&phases[1..])
            .all(|(a, b)| (a - b).abs() < DEDUP_TOLERANCE)
}

/// For impact times on grid points `tuple`, the squared contact residual on the `α` scan:
/// for fixed times the residuals are linear in `(cos α, sin α)`, so this costs one cycle.
/// Infinite where the periodicity solve is singular.
fn linear_scan(
    problem: &Problem,
    steps: &[Matrix6<f64>],
    tuple: &[usize],
    grid: usize,
    h: &Augmented,
) -> Vec<f64> {
    let n = tuple.len();
    let flights: Vec<&Matrix6<f64>> = (0..n)
        .map(|f| {
            let end = if f + 1 < n { tuple[f + 1] } else { grid };
            &steps[end - tuple[f]]
        })
        .collect();
    let mut pre = Vec::with_capacity(n);
    pre.push(*flights[0]);
    for f in 1..n {
        pre.push(flights[f] * problem.g_hat * pre[f - 1]);
    }
    let psi = problem.g_hat * pre[n - 1];
    let Some(k) = (Matrix4::identity() - psi.fixed_view::<4, 4>(0, 0)).try_inverse() else {
        return vec![f64::INFINITY; ALPHA_SCAN];
    };
    let y = k * psi.fixed_view::<4, 2>(0, 4);
    // Residual j = a_j · p − s_j Δ.
    let coefficients: Vec<Vector2<f64>> = (0..n)
        .map(|j| {
            let mut c = Vector2::zeros();
            for col in 0..2 {
                let mut p = Vector2::zeros();
                p[col] = 1.0;
                let z = join(&(y * p), &p);
                c[col] = if j == 0 {
                    h.dot(&z)
                } else {
                    h.dot(&(pre[j - 1] * z))
                };
            }
            c
        })
        .collect();
    let cost = |alpha: f64| {
        let p = Vector2::new(alpha.cos(), alpha.sin());
        (0..n)
            .map(|j| (coefficients[j].dot(&p) - problem.sides[j] as f64 * problem.gap).powi(2))
            .sum::<f64>()
    };
    (0..ALPHA_SCAN)
        .map(|k| cost(crate::sequence_search::scan_angle(k)))
        .collect()
}
