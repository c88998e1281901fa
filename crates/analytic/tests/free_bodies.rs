//! Models with free bodies (a singular stiffness matrix): the flow of a free mass against its
//! closed form, Masri and Caughey's symmetric two-impact motion of the impact damper against a
//! closed form derived here, its multipliers against finite differences of the cycle map, a
//! free mass resting against a one-sided stop and one between one-sided stops on the primary
//! and the frame, the family of linear motions clear of the stops, continuation in `ω` of the
//! damper's orbit, and the refusals.

use nalgebra::{Complex, DMatrix, DVector};
use rattle_analytic::*;
use std::f64::consts::PI;

fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// The impact damper: a primary mass `m1` on a spring `k` and a dashpot `c` to the frame,
/// driven by `F cos θ`, and a free mass `m2` in a clearance of the primary with a gap `d` on
/// each side (total clearance `2d`): coordinates `(x, y)`, the pair's relative coordinate
/// `r = y − x` (direction `e2 − e1`), side 1 at `r = +d`, side 2 at `r = −d`, restitution `e`.
#[derive(Debug, Clone, Copy)]
struct Damper {
    m1: f64,
    k: f64,
    c: f64,
    m2: f64,
    force: f64,
    gap: f64,
    restitution: f64,
}

impl Damper {
    fn model(&self) -> LinearModel {
        LinearModel::new(
            DMatrix::from_row_slice(2, 2, &[self.m1, 0.0, 0.0, self.m2]),
            DMatrix::from_row_slice(2, 2, &[self.c, 0.0, 0.0, 0.0]),
            DMatrix::from_row_slice(2, 2, &[self.k, 0.0, 0.0, 0.0]),
            HarmonicForcing {
                cosine: DVector::from_vec(vec![self.force, 0.0]),
                sine: DVector::zeros(2),
                sine_per_omega: DVector::zeros(2),
                harmonics: Vec::new(),
            },
            vec![ContactPair {
                direction: DVector::from_vec(vec![-1.0, 1.0]),
                gap_side1: self.gap,
                gap_side2: self.gap,
                restitution: self.restitution,
            }],
        )
        .unwrap_or_else(|e| panic!("{e}"))
    }
}

/// Masri and Caughey's symmetric two-impact motion, derived by hand (independent of the
/// solver): impacts at `t = 0` on side 1 (`r = +d`) and at `t = T/2` on side 2, the motion
/// antisymmetric under the half-period shift, `(x, y)(t + T/2) = −(x, y)(t)`.
#[derive(Debug, Clone, Copy)]
struct MasriCaughey {
    /// Forcing phase `θ = ωt + α` at the side-1 impact.
    alpha: f64,
    /// The free mass's velocity after the side-1 impact (`V < 0`: towards side 2).
    v_free: f64,
    /// The primary's displacement at the side-1 impact.
    x0: f64,
    /// The primary's velocity just after the side-1 impact.
    v_after: f64,
    /// The primary's velocity just before it.
    v_before: f64,
    /// `max_t |x(t)|`.
    amplitude: f64,
}

/// The closed form. Between impacts the primary's motion is the linear forced response
/// `p(t) = Re[H F e^{i(ωt + α)}]`, `H = 1/(k − m1ω² + icω)`, plus a free decay `h(t)` with the
/// transition `Φ(τ)` of `m1ẍ + cẋ + kx = 0`; the free mass moves at the constant velocity `V`.
///
/// - Crossing: `y(0) = x0 + d`, `y(T/2) = x(T/2) − d = −x0 − d`, so `V T/2 = −2(x0 + d)`:
///   `x0 = −d − πV/(2ω)`.
/// - Impact at `t = 0` (side 1): before it the free mass moves at `−V` (antisymmetry) and the
///   primary at `u`; after it at `V` and `v0`. Momentum `m1u − m2V = m1v0 + m2V` and
///   restitution `V − v0 = e(V + u)` (`ṙ⁺ = −eṙ⁻`) give, with `μ = m2/m1`,
///   `u = a_u V`, `a_u = (1 + 2μ − e)/(1 + e)`, and `v0 = a_v V`, `a_v = (1 − e − 2μe)/(1 + e)`.
/// - Closing by symmetry: `h(T/2) = −h(0)` and `ḣ(T/2⁻) = −u + ṗ(0)` (because
///   `p(t + T/2) = −p(t)`), with `h(0) = x0 − p(0)`, `ḣ(0) = v0 − ṗ(0)` and
///   `(h, ḣ)(T/2) = Φ(π/ω)(h, ḣ)(0)`. With `p(0) = X cos ψ`, `ṗ(0) = −ωX sin ψ`,
///   `X = |H|F`, `ψ = α − δ`, `δ = −arg H`, these are two equations linear in `V`,
///   `cos ψ`, `sin ψ`:
///   `a₁V + X(b₁c cos ψ + b₁s sin ψ) = (Φ₁₁ + 1)d`, `a₂V + X(b₂c cos ψ + b₂s sin ψ) = Φ₂₁d`,
///   `a₁ = −(Φ₁₁ + 1)π/(2ω) + Φ₁₂a_v`, `b₁c = −(Φ₁₁ + 1)`, `b₁s = ωΦ₁₂`,
///   `a₂ = −Φ₂₁π/(2ω) + Φ₂₂a_v + a_u`, `b₂c = −Φ₂₁`, `b₂s = ω(Φ₂₂ + 1)`.
/// - Eliminating `V`: `X(C_c cos ψ + C_s sin ψ) = d K₀`, `C_c = a₂b₁c − a₁b₂c`,
///   `C_s = a₂b₁s − a₁b₂s`, `K₀ = a₂(Φ₁₁ + 1) − a₁Φ₂₁`: `ψ = β ± arccos(dK₀/(XR))`,
///   `R = |(C_c, C_s)|`, `β = atan2(C_s, C_c)` (two branches; none when `|dK₀| > XR`), then
///   `V` from the first equation.
fn masri_caughey(p: &Damper, omega: f64) -> Vec<MasriCaughey> {
    let wn = (p.k / p.m1).sqrt();
    let zeta = p.c / (2.0 * (p.k * p.m1).sqrt());
    let sigma = zeta * wn;
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let tau = PI / omega;
    let decay = (-sigma * tau).exp();
    let (s, c) = (wd * tau).sin_cos();
    let f11 = decay * (c + sigma / wd * s);
    let f12 = decay * s / wd;
    let f21 = -decay * wn * wn / wd * s;
    let f22 = decay * (c - sigma / wd * s);
    let (re, im) = (p.k - p.m1 * omega * omega, p.c * omega);
    let x_amp = p.force / re.hypot(im);
    let delta = im.atan2(re);
    let mu = p.m2 / p.m1;
    let e = p.restitution;
    let a_u = (1.0 + 2.0 * mu - e) / (1.0 + e);
    let a_v = (1.0 - e - 2.0 * mu * e) / (1.0 + e);
    let a1 = -(f11 + 1.0) * PI / (2.0 * omega) + f12 * a_v;
    let (b1c, b1s) = (-(f11 + 1.0), omega * f12);
    let a2 = -f21 * PI / (2.0 * omega) + f22 * a_v + a_u;
    let (b2c, b2s) = (-f21, omega * (f22 + 1.0));
    let cc = a2 * b1c - a1 * b2c;
    let cs = a2 * b1s - a1 * b2s;
    let k0 = a2 * (f11 + 1.0) - a1 * f21;
    let q = p.gap * k0 / (x_amp * cc.hypot(cs));
    if q.abs() > 1.0 {
        return Vec::new();
    }
    let beta = cs.atan2(cc);
    [1.0, -1.0]
        .iter()
        .map(|sign| {
            let psi = beta + sign * q.acos();
            let v_free = ((f11 + 1.0) * p.gap - x_amp * (b1c * psi.cos() + b1s * psi.sin())) / a1;
            let x0 = -p.gap - PI * v_free / (2.0 * omega);
            let v_after = a_v * v_free;
            // x(t) on the first half period, and its largest modulus: by antisymmetry the
            // second half is −x, so the amplitude is the largest |x| on [0, T/2], found by
            // bisection on ẋ between samples where it changes sign, and the ends.
            let h0 = x0 - x_amp * psi.cos();
            let hd0 = v_after + omega * x_amp * psi.sin();
            let motion = |t: f64| -> (f64, f64) {
                let d = (-sigma * t).exp();
                let (s, c) = (wd * t).sin_cos();
                let a = hd0 + sigma * h0;
                let h = d * (h0 * c + a / wd * s);
                let hd = d * (-sigma * (h0 * c + a / wd * s) + (-h0 * wd * s + a * c));
                let th = omega * t + psi;
                (x_amp * th.cos() + h, -omega * x_amp * th.sin() + hd)
            };
            let mut amplitude = x0.abs().max(motion(tau).0.abs());
            let samples = 4000;
            for i in 0..samples {
                let (mut lo, mut hi) = (
                    tau * i as f64 / samples as f64,
                    tau * (i + 1) as f64 / samples as f64,
                );
                let (vlo, vhi) = (motion(lo).1, motion(hi).1);
                if vlo.signum() == vhi.signum() {
                    continue;
                }
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if motion(mid).1.signum() == vlo.signum() {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                amplitude = amplitude.max(motion(0.5 * (lo + hi)).0.abs());
            }
            MasriCaughey {
                alpha: wrap(psi + delta),
                v_free,
                x0,
                v_after,
                v_before: a_u * v_free,
                amplitude,
            }
        })
        .collect()
}

fn damper() -> Damper {
    Damper {
        m1: 1.0,
        k: 1.0,
        c: 0.05,
        m2: 0.1,
        force: 1.0,
        gap: 1.0,
        restitution: 0.8,
    }
}

/// Relative agreement asked of the solver against a closed form (both exact: rounding only).
const AGREEMENT: f64 = 1e-12;

/// The model of one free mass `m` (no spring) with a dashpot `c` (0: none) to the frame,
/// driven by `F cos θ`, with a one-sided stop at `x = +gap`.
fn free_mass(m: f64, c: f64, force: f64) -> LinearModel {
    LinearModel::new(
        DMatrix::from_element(1, 1, m),
        DMatrix::from_element(1, 1, c),
        DMatrix::zeros(1, 1),
        HarmonicForcing {
            cosine: DVector::from_element(1, force),
            sine: DVector::zeros(1),
            sine_per_omega: DVector::zeros(1),
            harmonics: Vec::new(),
        },
        vec![ContactPair {
            direction: DVector::from_element(1, 1.0),
            gap_side1: 1.0,
            gap_side2: f64::INFINITY,
            restitution: 0.5,
        }],
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// The flow of a free mass under `F cos(ωt + α)` from `(x₀, v₀)`: `mẍ = F cos(ωt + α)` gives
/// `v(t) = v₀ + F/(mω) (sin(ωt + α) − sin α)` and
/// `x(t) = x₀ + (v₀ − F sin α/(mω)) t + F/(mω²) (cos α − cos(ωt + α))`. With a dashpot
/// (`mẍ + cẋ = F cos(ωt + α)`, `λ = c/m`): the particular velocity
/// `v_p(t) = Re[F e^{i(ωt + α)} / (m(λ + iω))]`, `v(t) = v_p(t) + (v₀ − v_p(0)) e^{−λt}`,
/// `x(t) = x₀ + ∫₀ᵗ v`, `∫₀ᵗ v_p = Re[F (e^{i(ωt + α)} − e^{iα}) / (m iω(λ + iω))]`.
#[test]
fn free_mass_flow_is_its_closed_form() {
    let (m, force, omega, alpha): (f64, f64, f64, f64) = (0.7, 1.3, 1.9, 0.4);
    let (x0, v0) = (0.25, -0.6);
    for c in [0.0, 0.35] {
        let model = free_mass(m, c, force);
        assert!(model.has_rigid_modes());
        assert_eq!(model.rigid_modes().ncols(), 1);
        for t in [0.1, 1.7, 6.0, 23.0] {
            let flow = model.transition(omega, t);
            let (x, p) = flow.apply(
                &DVector::from_vec(vec![x0, v0]),
                &DVector::from_vec(vec![alpha.cos(), alpha.sin()]),
            );
            let th = omega * t + alpha;
            let (x_exact, v_exact) = if c == 0.0 {
                (
                    x0 + (v0 - force * alpha.sin() / (m * omega)) * t
                        + force / (m * omega * omega) * (alpha.cos() - th.cos()),
                    v0 + force / (m * omega) * (th.sin() - alpha.sin()),
                )
            } else {
                let lambda = c / m;
                let z = |a: f64| Complex::new(0.0, a).exp();
                let denominator = Complex::new(lambda, omega) * m;
                let vp = |a: f64| (z(a) * force / denominator).re;
                let decay = (-lambda * t).exp();
                let v = vp(th) + (v0 - vp(alpha)) * decay;
                let integral = ((z(th) - z(alpha)) * force
                    / (denominator * Complex::new(0.0, omega)))
                .re + (v0 - vp(alpha)) * (1.0 - decay) / lambda;
                (x0 + integral, v)
            };
            let scale = x_exact.abs().max(v_exact.abs()).max(1.0);
            assert!(
                (x[0] - x_exact).abs() <= AGREEMENT * scale,
                "c = {c}, t = {t}: x {} vs {x_exact}",
                x[0]
            );
            assert!(
                (x[1] - v_exact).abs() <= AGREEMENT * scale,
                "c = {c}, t = {t}: v {} vs {v_exact}",
                x[1]
            );
            assert!((p[0] - th.cos()).abs() <= AGREEMENT && (p[1] - th.sin()).abs() <= AGREEMENT);
        }
    }
}

/// The parameter sets of the Masri–Caughey checks: the damper with `e = 0.8`, `c = 0.05`,
/// `μ = 0.1` at `ω = 1.2` (a viable, unstable orbit) and `ω = 1.62` (viable and stable), and
/// with `e = 0.6`, `c = 0.2`, `μ = 0.3` at `ω = 1.5` (viable and stable).
fn masri_caughey_cases() -> Vec<(Damper, f64, bool)> {
    let heavy = Damper {
        restitution: 0.6,
        c: 0.2,
        m2: 0.3,
        ..damper()
    };
    vec![
        (damper(), 1.2, false),
        (damper(), 1.62, true),
        (heavy, 1.5, true),
    ]
}

/// The closed-form orbit of a case that is viable (approached from inside, `V < 0`) and has
/// the expected stability: the branch the solver must reproduce.
fn solve_case(p: &Damper, omega: f64) -> Vec<(MasriCaughey, SequenceOrbit)> {
    let model = p.model();
    let sequence = ImpactSequence::parse("0+ 0-", 1).unwrap_or_else(|e| panic!("{e}"));
    masri_caughey(p, omega)
        .into_iter()
        .filter(|mc| mc.v_free < 0.0 && -mc.v_free - mc.v_before > 0.0)
        .map(|mc| {
            let guess = [mc.alpha + 1e-3, 0.5 - 1e-3];
            let orbit = solve_sequence(&model, omega, &sequence, &guess)
                .unwrap_or_else(|e| panic!("ω = {omega}: {e}"));
            (mc, orbit)
        })
        .collect()
}

/// The solver's `0+ 0-` orbit of the impact damper is Masri and Caughey's symmetric motion:
/// impact phase, forcing phase, the state at the impact (pre- and post-impact velocities of
/// both masses) and the primary's amplitude, to rounding; and the verdicts (viable, stable or
/// not, the energy balance) are those expected of the case.
#[test]
fn damper_two_impact_orbit_is_masri_and_caugheys() {
    let mut stable_seen = [false, false];
    for (p, omega, stable) in masri_caughey_cases() {
        let solved = solve_case(&p, omega);
        assert!(!solved.is_empty(), "ω = {omega}: a physical branch");
        for (mc, o) in solved {
            let scale = mc.x0.abs().max(p.gap).max(mc.v_free.abs());
            let close = |a: f64, b: f64, what: &str| {
                assert!(
                    (a - b).abs() <= AGREEMENT * scale,
                    "ω = {omega}, {what}: solver {a} vs closed form {b}"
                );
            };
            assert!(
                wrap(o.alpha - mc.alpha).abs() <= AGREEMENT,
                "ω = {omega}: α"
            );
            assert!(
                (o.impact_phases[1] - 0.5).abs() <= AGREEMENT,
                "ω = {omega}: phase"
            );
            let before = &o.states_before_impacts[0];
            close(before[0], mc.x0, "x at the side-1 impact");
            close(before[1], mc.x0 + p.gap, "y at the side-1 impact");
            close(before[2], mc.v_before, "primary velocity before");
            close(before[3], -mc.v_free, "free mass velocity before");
            close(
                o.state_after_impact[2],
                mc.v_after,
                "primary velocity after",
            );
            close(
                o.state_after_impact[3],
                mc.v_free,
                "free mass velocity after",
            );
            let half = &o.states_before_impacts[1];
            close(half[0], -mc.x0, "x at the side-2 impact");
            close(half[2], -mc.v_before, "primary velocity before side 2");
            close(half[3], mc.v_free, "free mass velocity before side 2");
            close(o.amplitudes[0], mc.amplitude, "primary amplitude");
            assert!(o.viable, "ω = {omega}: {:?}", o.violations);
            // The cycle's energy balance (forcing work = dashpot and impact losses), as the
            // other models' orbits are held to.
            assert!(
                o.energy_residual <= 1e-10,
                "ω = {omega}: {}",
                o.energy_residual
            );
            if o.stable == stable {
                stable_seen[usize::from(stable)] = true;
            }
        }
    }
    assert!(
        stable_seen[0] && stable_seen[1],
        "a stable and an unstable orbit"
    );
}

/// The multi-start finds Masri and Caughey's orbit among the `0+ 0-` orbits of the damper.
#[test]
fn multi_start_finds_masri_and_caugheys_orbit() {
    let p = damper();
    let omega = 1.2;
    let sequence = ImpactSequence::parse("0+ 0-", 1).unwrap_or_else(|e| panic!("{e}"));
    let found = sequence_orbits(&p.model(), omega, &sequence).unwrap_or_else(|e| panic!("{e}"));
    for (mc, _) in solve_case(&p, omega) {
        assert!(
            found
                .iter()
                .any(|o| wrap(o.alpha - mc.alpha).abs() <= AGREEMENT
                    && (o.impact_phases[1] - 0.5).abs() <= AGREEMENT),
            "α = {} among {:?}",
            mc.alpha,
            found.iter().map(|o| o.alpha).collect::<Vec<_>>()
        );
    }
}

/// The state at time `duration` from the state `x` at forcing phase `p`, stepped with the
/// model's exact flow and impact map, each crossing of a stop located by bisection on the
/// exact flow (a cycle map written independently of the solver's equations).
fn step_with_impacts(
    model: &LinearModel,
    omega: f64,
    mut x: DVector<f64>,
    mut p: DVector<f64>,
    duration: f64,
) -> DVector<f64> {
    let n = model.dofs();
    let steps = 400;
    let h = duration / steps as f64;
    let outside = |x: &DVector<f64>| {
        model.pairs().iter().position(|pair| {
            let r = pair.relative(&x.rows(0, n).into_owned());
            r > pair.gap_side1 || r < -pair.gap_side2
        })
    };
    let mut left = duration;
    for _ in 0..10 * steps {
        if left <= 0.0 {
            return x;
        }
        let dt = h.min(left);
        let (xn, pn) = model.transition(omega, dt).apply(&x, &p);
        if let Some(pair) = outside(&xn) {
            let (mut lo, mut hi) = (0.0, dt);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                let (xm, _) = model.transition(omega, mid).apply(&x, &p);
                if outside(&xm).is_some() {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let (xc, pc) = model.transition(omega, hi).apply(&x, &p);
            x = model.impact_state(pair, &xc);
            p = pc;
            left -= hi;
        } else {
            x = xn;
            p = pn;
            left -= dt;
        }
    }
    panic!("the stepping does not reach the end of the cycle (a contact that never ends)");
}

/// The multipliers of the crate's monodromy (flights and saltation matrices) against finite
/// differences of the cycle map: the map over one period from a quarter period after the
/// side-1 impact (mid-flight), stepped with the exact flow and bisected impacts, is
/// differenced centrally with steps `δ = 1e-5` and `δ/2`, extrapolated (Richardson:
/// `(4D(δ/2) − D(δ))/3`, truncation `O(δ⁴)`; the plain quotient's `O(δ²)` term is large on
/// these non-normal cycles, `|M|` up to 250); its Jacobian is the monodromy carried to that
/// section, `E(T/4) M E(T/4)⁻¹`. Truncation and rounding (`O(ε/δ · |M|)`) stay below
/// `1e-7 |M|`; the multipliers' moduli then agree to `1e-6` (relative above 1).
#[test]
fn damper_multipliers_are_the_cycle_maps() {
    for (p, omega, _) in masri_caughey_cases() {
        let model = p.model();
        for (_, o) in solve_case(&p, omega) {
            let period = std::f64::consts::TAU / omega;
            let quarter = model.transition(omega, period / 4.0);
            let after = DVector::from_vec(o.state_after_impact.clone());
            let p0 = DVector::from_vec(vec![o.alpha.cos(), o.alpha.sin()]);
            let (start, phase) = quarter.apply(&after, &p0);
            let e = &quarter.homogeneous;
            let carried = e * &o.monodromy * e.clone().try_inverse().unwrap_or_else(|| panic!());
            let quotient = |step: f64| {
                let mut fd = DMatrix::zeros(4, 4);
                for k in 0..4 {
                    let moved = |d: f64| {
                        let mut x = start.clone();
                        x[k] += d;
                        step_with_impacts(&model, omega, x, phase.clone(), period)
                    };
                    fd.set_column(k, &((moved(step) - moved(-step)) / (2.0 * step)));
                }
                fd
            };
            let step = 1e-5;
            let fd = (quotient(0.5 * step) * 4.0 - quotient(step)) / 3.0;
            let diff = (&fd - &carried).amax();
            assert!(
                diff <= 1e-7 * carried.amax(),
                "ω = {omega}: |FD − M| = {diff:e}, |M| = {}",
                carried.amax()
            );
            let moduli = |m: &DMatrix<f64>| {
                let mut v: Vec<f64> = m.complex_eigenvalues().iter().map(|c| c.norm()).collect();
                v.sort_by(f64::total_cmp);
                v
            };
            let (a, b) = (moduli(&fd), o.floquet_multipliers.iter().map(|c| c.norm()));
            let mut b: Vec<f64> = b.collect();
            b.sort_by(f64::total_cmp);
            for (x, y) in a.iter().zip(&b) {
                assert!(
                    (x - y).abs() <= 1e-6 * y.max(1.0),
                    "ω = {omega}: {a:?} vs {b:?}"
                );
            }
        }
    }
}

/// A free mass against a one-sided stop on a forced primary (`r = y − x ≤ d`, no stop on the
/// other side), with no force on the free mass: its impulses all push it the same way, so a
/// periodic motion has none; the one periodic contact is the free mass at rest touching the
/// primary where `r` is largest, i.e. where the primary's linear response
/// `x = X cos(ωt + α − δ)` is at its minimum: `α = π + δ`, `x = −X`, `y = d − X`, both at rest,
/// `ṙ⁻ = 0`. The solver finds exactly that: a grazing contact, not an impacting orbit. A
/// bouncing ball needs a constant force (gravity) to come back,
/// which the harmonic forcing cannot express.
#[test]
fn free_mass_rests_against_a_one_sided_stop() {
    let p = damper();
    let base = p.model();
    let model = LinearModel::new(
        base.mass().clone(),
        base.damping().clone(),
        base.stiffness().clone(),
        base.forcing().clone(),
        vec![ContactPair {
            direction: DVector::from_vec(vec![-1.0, 1.0]),
            gap_side1: p.gap,
            gap_side2: f64::INFINITY,
            restitution: p.restitution,
        }],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let one = ImpactSequence::parse("0+", 1).unwrap_or_else(|e| panic!("{e}"));
    let omega = 1.3;
    let (re, im) = (p.k - p.m1 * omega * omega, p.c * omega);
    let (delta, x_amp) = (im.atan2(re), p.force / re.hypot(im));
    let o = solve_sequence(&model, omega, &one, &[wrap(PI + delta + 0.3)])
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(wrap(o.alpha - (PI + delta)).abs() <= AGREEMENT);
    let x = &o.state_after_impact;
    let scale = x_amp.max(p.gap);
    assert!((x[0] + x_amp).abs() <= AGREEMENT * scale, "x = {}", x[0]);
    assert!(
        (x[1] - (p.gap - x_amp)).abs() <= AGREEMENT * scale,
        "y = {}",
        x[1]
    );
    assert!(x[2].abs() <= AGREEMENT * scale && x[3].abs() <= AGREEMENT * scale);
    // The contact is a grazing: the approach velocity is zero to rounding, so whether the
    // verdict calls it an impact approached from outside (`ṙ⁻ ≤ 0`) is rounding's choice.
    let before = &o.states_before_impacts[0];
    assert!((before[3] - before[2]).abs() <= AGREEMENT * scale);
    assert!(o.violations.iter().all(|v| matches!(
        v,
        SequenceViolation::WrongApproach { relative_velocity, .. }
            if relative_velocity.abs() <= AGREEMENT * scale
    )));
}

/// The family of linear motions of the damper: the free mass's harmonic part vanishes, so
/// `r = y − x` has the primary's amplitude `X = F/|k − m1ω² + icω|`; some offset of the free
/// mass keeps it inside `[−d, d]` exactly when `2X ≤ 2d`. The member without offset touches
/// neither question: the offset found is one that works (`|a|` plus `X` within `d`).
#[test]
fn damper_clear_family_is_the_peak_to_peak_condition() {
    let omega = 1.3;
    let p = damper();
    let (re, im) = (p.k - p.m1 * omega * omega, p.c * omega);
    let x_amp = p.force / re.hypot(im);
    for (gap, exists) in [(x_amp * (1.0 + 1e-9), true), (x_amp * (1.0 - 1e-9), false)] {
        let model = Damper { gap, ..p }.model();
        let family = model.clear_family(omega).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(family.exists, exists, "gap {gap}");
        assert_eq!(family.pairs.len(), 1);
        assert!(family.pairs[0].involves_rigid);
        assert!((family.pairs[0].amplitude - x_amp).abs() <= AGREEMENT * x_amp);
        assert!(
            family.state.cosine[1].abs() <= AGREEMENT && family.state.sine[1].abs() <= AGREEMENT
        );
        if let Some(a) = &family.offset {
            let shift = (family.rigid_modes.transpose() * &model.pairs()[0].direction).dot(a);
            assert!(shift.abs() + x_amp <= gap * (1.0 + 1e-15));
        }
    }
    // A model without rigid modes: the family is the one motion, clear when its relative
    // amplitude is within the smaller gap.
    let unit = rattle_analytic::test_models::damped_paper_unit();
    let stops = rattle_analytic::test_models::paper_stops();
    let model = LinearModel::unit(&unit, &stops).unwrap_or_else(|e| panic!("{e}"));
    assert!(!model.has_rigid_modes());
    let family = model.clear_family(1.3).unwrap_or_else(|e| panic!("{e}"));
    let amplitude = family.state.relative_amplitude(&model.pairs()[0]);
    assert_eq!(family.exists, amplitude <= stops.gap);
    assert!(!family.pairs[0].involves_rigid);
}

/// Two free masses in one primary (pairs 0 and 1), a sequence that hits only the first: the
/// second's offset is fixed by no contact, and the problem is refused naming it. A free mass
/// that neither a pair nor a dashpot restrains drifts, and an indefinite stiffness or damping
/// has no bounded motion: such models are refused naming the reason.
#[test]
fn unrestrained_and_unbounded_models_are_refused() {
    let two = LinearModel::new(
        DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 0.1, 0.1])),
        DMatrix::from_diagonal(&DVector::from_vec(vec![0.05, 0.0, 0.0])),
        DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 0.0, 0.0])),
        HarmonicForcing {
            cosine: DVector::from_vec(vec![1.0, 0.0, 0.0]),
            sine: DVector::zeros(3),
            sine_per_omega: DVector::zeros(3),
            harmonics: Vec::new(),
        },
        vec![
            ContactPair {
                direction: DVector::from_vec(vec![-1.0, 1.0, 0.0]),
                gap_side1: 1.0,
                gap_side2: 1.0,
                restitution: 0.8,
            },
            ContactPair {
                direction: DVector::from_vec(vec![-1.0, 0.0, 1.0]),
                gap_side1: 1.0,
                gap_side2: 1.0,
                restitution: 0.8,
            },
        ],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(two.rigid_modes().ncols(), 2);
    let only_first = ImpactSequence::parse("0+ 0-", 1).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        SequenceProblem::new(&two, 1.2, &only_first).err(),
        Some(SequenceOrbitError::UnrestrainedRigidMode {
            restrained: 1,
            modes: 2
        })
    );
    let both = ImpactSequence::parse("0+ 1+ 0- 1-", 1).unwrap_or_else(|e| panic!("{e}"));
    assert!(SequenceProblem::new(&two, 1.2, &both).is_ok());
    // A third free mass that no pair reaches: undamped it drifts (refused), damped its offset
    // is merely arbitrary (accepted; the cycle equations then ask a sequence that sees it).
    let third = |c: f64| {
        LinearModel::new(
            DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 0.1, 0.2])),
            DMatrix::from_diagonal(&DVector::from_vec(vec![0.05, 0.0, c])),
            DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 0.0, 0.0])),
            HarmonicForcing {
                cosine: DVector::from_vec(vec![1.0, 0.0, 0.0]),
                sine: DVector::zeros(3),
                sine_per_omega: DVector::zeros(3),
                harmonics: Vec::new(),
            },
            vec![ContactPair {
                direction: DVector::from_vec(vec![-1.0, 1.0, 0.0]),
                gap_side1: 1.0,
                gap_side2: 1.0,
                restitution: 0.8,
            }],
        )
    };
    assert_eq!(
        third(0.0).err(),
        Some(ModelError::Drift { modes: 2, free: 1 })
    );
    let damped = third(0.3).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        SequenceProblem::new(&damped, 1.2, &only_first).err(),
        Some(SequenceOrbitError::UnrestrainedRigidMode {
            restrained: 1,
            modes: 2
        })
    );
    let p = damper();
    let base = p.model();
    for (name, damping, stiffness) in [
        (
            "model.stiffness",
            base.damping().clone(),
            DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, -0.1]),
        ),
        (
            "model.damping",
            DMatrix::from_row_slice(2, 2, &[0.05, 0.0, 0.0, -0.01]),
            base.stiffness().clone(),
        ),
    ] {
        let refused = LinearModel::new(
            base.mass().clone(),
            damping,
            stiffness,
            base.forcing().clone(),
            base.pairs().to_vec(),
        );
        assert!(
            matches!(&refused, Err(ModelError::Structure { field, .. }) if field == name),
            "{refused:?}"
        );
    }
}

/// Continuation in `ω` of the damper's symmetric orbit (the bordered equations at every
/// frequency): every point of the branch is Masri and Caughey's orbit at its own frequency.
#[test]
fn continued_damper_orbit_stays_masri_and_caugheys() {
    let p = damper();
    let model = p.model();
    let (_, start) = solve_case(&p, 1.62)
        .into_iter()
        .find(|(_, o)| o.stable)
        .unwrap_or_else(|| panic!("the stable orbit"));
    let settings = ContinuationSettings {
        omega_min: 1.45,
        omega_max: 1.75,
        follow_switches: false,
        max_branches: 1,
        ..ContinuationSettings::default()
    };
    let result = continue_sequence(&model, &start, &settings).unwrap_or_else(|e| panic!("{e}"));
    let points = &result.branches[0].points;
    assert!(points.len() > 10, "{} points", points.len());
    let mut worst: f64 = 0.0;
    for point in points {
        let closed: Vec<MasriCaughey> = masri_caughey(&p, point.omega);
        let nearest = closed
            .iter()
            .map(|mc| wrap(point.alpha - mc.alpha).abs())
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(nearest);
        assert!((point.impact_phases[1] - 0.5).abs() <= AGREEMENT);
    }
    assert!(worst <= AGREEMENT, "worst α difference {worst:e}");
}

/// A free mass `y` between two undamped primaries `x₁`, `x₂` (springs `k = 1`, masses 1,
/// forces `F₁ cos θ`, `F₂ cos θ`), pairs `r_i = y − x_i`: the free mass's harmonic part
/// vanishes, so `r_i` has the amplitude `A_i = |F_i/(k − ω²)|` and the offset `a` of the free
/// mass must lie in `[A_i − gap_side2_i, gap_side1_i − A_i]` for both pairs. At `ω = 1/2`,
/// `F_i = 0.45`: `A_i = 0.6`. With gaps `(2, 0.5)` and `(0.5, 2)` each pair alone is clear
/// (`2A = 1.2 ≤ 2.5`) but the intervals `[0.1, 1.4]` and `[−1.4, −0.1]` are disjoint: no
/// member of the family is clear. With gaps `(2, 0.5)` twice they are the same interval, and
/// the offset found lies in it.
#[test]
fn clear_family_needs_one_offset_for_every_pair() {
    let omega = 0.5;
    let model = |second: [f64; 2]| {
        let pair = |k: usize, gaps: [f64; 2]| {
            let mut w = DVector::zeros(3);
            w[k] = -1.0;
            w[2] = 1.0;
            ContactPair {
                direction: w,
                gap_side1: gaps[0],
                gap_side2: gaps[1],
                restitution: 0.8,
            }
        };
        LinearModel::new(
            DMatrix::identity(3, 3),
            DMatrix::zeros(3, 3),
            DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 1.0, 0.0])),
            HarmonicForcing {
                cosine: DVector::from_vec(vec![0.45, 0.45, 0.0]),
                sine: DVector::zeros(3),
                sine_per_omega: DVector::zeros(3),
                harmonics: Vec::new(),
            },
            vec![pair(0, [2.0, 0.5]), pair(1, second)],
        )
        .unwrap_or_else(|e| panic!("{e}"))
    };
    let apart = model([0.5, 2.0])
        .clear_family(omega)
        .unwrap_or_else(|e| panic!("{e}"));
    for pair in &apart.pairs {
        assert!((pair.amplitude - 0.6).abs() <= AGREEMENT);
        assert!(pair.involves_rigid && pair.clear);
    }
    assert!(!apart.exists && apart.offset.is_none());
    let together = model([2.0, 0.5])
        .clear_family(omega)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(together.exists);
    let a = together.offset.unwrap_or_else(|| panic!("an offset"));
    // The free mass's displacement is Φa (Φ = ±e₃).
    let y = (&together.rigid_modes * a)[2];
    assert!((0.1..=1.4).contains(&y), "y offset {y}");
}

/// A free mass between two one-sided stops: one on the forced primary (`r₀ = y − x ≤ d`) and
/// one on the frame (`y ≥ −g`, restitution `e_f`), sequence `0+ 1-`. Between the impacts it
/// moves at `V₁` (after the primary's impact) and `−e_f V₁` (after the frame's, which changes
/// nothing else), so coming back to where it was, `V₁t₂ − e_f V₁(T − t₂) = 0` with `V₁ ≠ 0`,
/// puts the frame impact at the phase `t₂/T = e_f/(1 + e_f)` exactly, whatever the primary
/// does. Every viable orbit the multi-start finds has that phase, and is periodic when stepped
/// over a cycle with the model's flow and impact maps (independently of the cycle equations).
#[test]
fn free_mass_between_one_sided_stops() {
    let p = damper();
    let base = p.model();
    let frame_restitution = 0.6;
    let model = LinearModel::new(
        base.mass().clone(),
        base.damping().clone(),
        base.stiffness().clone(),
        base.forcing().clone(),
        vec![
            ContactPair {
                direction: DVector::from_vec(vec![-1.0, 1.0]),
                gap_side1: 1.0,
                gap_side2: f64::INFINITY,
                restitution: p.restitution,
            },
            ContactPair {
                direction: DVector::from_vec(vec![0.0, 1.0]),
                gap_side1: f64::INFINITY,
                gap_side2: 1.5,
                restitution: frame_restitution,
            },
        ],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let sequence = ImpactSequence::parse("0+ 1-", 1).unwrap_or_else(|e| panic!("{e}"));
    let phase = frame_restitution / (1.0 + frame_restitution);
    let mut viable = 0;
    for omega in [0.6, 1.5, 2.0] {
        let found = sequence_orbits(&model, omega, &sequence).unwrap_or_else(|e| panic!("{e}"));
        for o in found.iter().filter(|o| o.viable) {
            viable += 1;
            assert!(
                (o.impact_phases[1] - phase).abs() <= AGREEMENT,
                "ω = {omega}: {}",
                o.impact_phases[1]
            );
            let after = DVector::from_vec(o.state_after_impact.clone());
            let p0 = DVector::from_vec(vec![o.alpha.cos(), o.alpha.sin()]);
            let period = std::f64::consts::TAU / omega;
            let (start, at) = model
                .transition(omega, 0.5 * phase * period)
                .apply(&after, &p0);
            let back = step_with_impacts(&model, omega, start.clone(), at, period);
            let scale = start.amax().max(1.0);
            // Bisected impact times (to rounding of the time) and 400 flights of rounding.
            assert!((back - &start).amax() <= 1e-10 * scale, "ω = {omega}");
            assert!(
                o.energy_residual <= 1e-10,
                "ω = {omega}: {}",
                o.energy_residual
            );
        }
    }
    assert!(viable > 0, "a viable orbit");
}
