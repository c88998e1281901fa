//! The impact damper's symmetric two-impact motion in closed form (Masri & Caughey): a primary
//! body `m ẍ + c ẋ + k x = F cos(ωt + φ)` with a free body of mass `m_b` (no spring, no
//! dashpot) in a clearance of it, `r = y − x ∈ [−d, d]`, restitution `e` on the relative
//! velocity, momentum conserved at each impact.
//!
//! The motion has two impacts per forcing period, half a period apart, on alternate walls,
//! and repeats with a sign change after half a period: `x(t + T/2) = −x(t)`,
//! `y(t + T/2) = −y(t)`. Measure time from the impact on side `+` (`r = d`) and let the force
//! be `F cos(ωt + α)` there. The free body leaves that wall at `−V` and, the motion being
//! antisymmetric, met it at `+V`; it crosses to the other wall (`y = −x₀ − d` at `T/2`) in
//! half a period, so `V = (2ω/π)(x₀ + d)`, `x₀ = x(0)`. Restitution and momentum give the
//! primary's velocities just before and after the impact as multiples of `V`:
//! `ẋ⁻ = −γV`, `γ = (1 + 2μ − e)/(1 + e)`, and `ẋ⁺ = ẋ⁻ + 2μV`, `μ = m_b/m`.
//!
//! Between the impacts the primary moves as its steady forced response
//! `x_p = A cos(ωt + α − δ)` (`A = F/√((k − mω²)² + (cω)²)`, `δ = atan2(cω, k − mω²)`) plus a
//! free motion `z_h(t) = Φ(t) z_h(0)`, `z = (x, ẋ)`. `x_p` changes sign over half a period, so
//! the symmetry asks the free motion to do the same: `Φ(T/2) z_h(0⁺) = −z_h(T/2⁻)` with
//! `z_h(0⁺) = (x₀ − p, ẋ⁺ − q)`, `z_h(T/2⁻) = (x₀ − p, ẋ⁻ − q)` written with the half-period
//! sign, `(p, q) = (A cos θ, −Aω sin θ)` the forced state at the impact, `θ = α − δ`. These
//! two equations are linear in `(p, q, x₀)`: they give `p` and `q` as affine functions of
//! `x₀`, and `(p/A)² + (q/(Aω))² = 1` is a quadratic in `x₀`: zero or two orbits.
//!
//! An orbit is a motion (viable) when the free body leaves the wall inward (`V > 0`) and
//! stays inside the clearance over the half period, checked on a fine uniform grid of the
//! closed form (a reference for orbits away from grazing, not a rigorous bound). Its stability
//! is that of the monodromy `Φ₄(T/2) S₋ Φ₄(T/2) S₊` of the state `(x, ẋ, y, ẏ)`, with `S` the
//! saltation matrix of each impact, `S = R + (f⁺ − R f⁻) nᵀ / (nᵀ f⁻)`: `R` the impact's
//! linear map, `n` the gradient of `r ∓ d`, `f^∓` the vector field just before and after it.

use super::impact_oscillator::{free_flow, wrap, ReferenceError};
use nalgebra::{Matrix2, Matrix4, Vector4};
use std::f64::consts::{PI, TAU};

/// The impact damper: a primary body on a spring and a dashpot to the frame, forced, with a
/// free body in a clearance `±d` of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactDamper {
    /// `m > 0`, the primary's mass.
    pub mass: f64,
    /// `c ≥ 0`, with `c² < 4km` (underdamped).
    pub damping: f64,
    /// `k > 0`.
    pub stiffness: f64,
    /// `F`, the force's amplitude on the primary.
    pub force: f64,
    /// `φ`, the force's phase: `F cos(ωt + φ)`.
    pub phase: f64,
    /// `m_b > 0`, the free body's mass.
    pub free_mass: f64,
    /// `d > 0`, the clearance on each side: `r = y − x ∈ [−d, d]`.
    pub gap: f64,
    /// `e ∈ [0, 1]`.
    pub restitution: f64,
}

/// A symmetric motion with two impacts per period.
#[derive(Debug, Clone, PartialEq)]
pub struct SymmetricOrbit {
    /// The force's phase `ωt + φ` at the impact on side `+`, rad in `(−π, π]`.
    pub forcing_phase: f64,
    /// That impact's time within the period, `[0, T)`; the impact on side `−` follows half a
    /// period later.
    pub impact_time: f64,
    /// `x₀`, the primary's displacement at the impact on side `+`.
    pub primary_displacement: f64,
    /// `V`, the free body's speed between the impacts.
    pub free_speed: f64,
    /// `ẏ⁻ − ẋ⁻ = V(1 + γ)`, the relative velocity just before the impact on side `+`.
    pub relative_velocity_before: f64,
    /// `max |x|` over the period (on the grid of the viability check).
    pub primary_amplitude: f64,
    /// `max |y|` over the period.
    pub free_amplitude: f64,
    /// Leaves the wall inward (`V > 0`) and stays inside the clearance over the flight.
    pub viable: bool,
    /// The four Floquet multipliers `[re, im]`, by decreasing modulus.
    pub multipliers: Vec<[f64; 2]>,
    /// Every multiplier inside the unit circle.
    pub stable: bool,
}

/// Samples of the half-period flight in the viability check of
/// [`ImpactDamper::symmetric_orbits`]: the grid's spacing (`T/2¹⁷`, half a period in 2¹⁶
/// steps) resolves an excursion
/// beyond a wall of more than about `1e-9` of the motion's size for flights whose fastest rate
/// is of the order of `ω`.
pub const VIABILITY_SAMPLES: usize = 1 << 16;

impl ImpactDamper {
    /// Every symmetric two-impact motion at `omega` (zero or two), viable or not.
    ///
    /// # Errors
    /// [`ReferenceError::OutOfRange`] outside the closed form's range (masses, stiffness,
    /// clearance and frequency positive, `e ∈ [0, 1]`, an underdamped primary).
    pub fn symmetric_orbits(&self, omega: f64) -> Result<Vec<SymmetricOrbit>, ReferenceError> {
        self.symmetric_orbits_sampled(omega, VIABILITY_SAMPLES)
    }

    /// [`Self::symmetric_orbits`] with the viability and the amplitudes checked on `samples`
    /// points of the half-period flight.
    ///
    /// # Errors
    /// [`ReferenceError::OutOfRange`] outside the closed form's range.
    pub fn symmetric_orbits_sampled(
        &self,
        omega: f64,
        samples: usize,
    ) -> Result<Vec<SymmetricOrbit>, ReferenceError> {
        let Self {
            mass: m,
            damping: c,
            stiffness: k,
            force,
            phase,
            free_mass,
            gap: d,
            restitution: e,
        } = *self;
        let lambda = c / (2.0 * m);
        let ok = m > 0.0
            && k > 0.0
            && c >= 0.0
            && free_mass > 0.0
            && d > 0.0
            && omega > 0.0
            && force.is_finite()
            && (0.0..=1.0).contains(&e)
            && lambda * lambda < k / m;
        if !ok {
            return Err(ReferenceError::OutOfRange);
        }
        let half = PI / omega;
        let mu = free_mass / m;
        let gamma = (1.0 + 2.0 * mu - e) / (1.0 + e);
        let kappa = 2.0 * omega / PI;
        let s = 2.0 * mu - gamma;
        let phi = self.free_flow(half);
        let dynamic = k - m * omega * omega;
        let amplitude = force / dynamic.hypot(c * omega);
        let delta = (c * omega).atan2(dynamic);
        // With V = κ(x₀ + d), ẋ⁺ = sV and ẋ(T/2⁻) = −ẋ⁻ = γV, the symmetry conditions
        //   (φ₁₁ + 1)(x₀ − p) + φ₁₂ (sV − q) = 0,
        //   φ₂₁ (x₀ − p) + φ₂₂ (sV − q) − γV − q = 0
        // read `L (p, q) = a + b x₀`, with `a` and `b` the right-hand sides at `x₀ = 0` and
        // their slopes.
        let l = Matrix2::new(
            -(phi[(0, 0)] + 1.0),
            -phi[(0, 1)],
            -phi[(1, 0)],
            -(phi[(1, 1)] + 1.0),
        );
        let Some(inverse) = l.try_inverse() else {
            return Ok(Vec::new());
        };
        // Right-hand sides at x₀ = 0 and their slopes in x₀.
        let at_zero = nalgebra::Vector2::new(
            -phi[(0, 1)] * s * kappa * d,
            -phi[(1, 1)] * s * kappa * d + gamma * kappa * d,
        );
        let slope = nalgebra::Vector2::new(
            -(phi[(0, 0)] + 1.0) - phi[(0, 1)] * s * kappa,
            -phi[(1, 0)] - phi[(1, 1)] * s * kappa + gamma * kappa,
        );
        let u = inverse * at_zero;
        let w = inverse * slope;
        // (p/A, q/(Aω)) = (cos θ, −sin θ) = (u + x₀ w) scaled.
        let scale = nalgebra::Vector2::new(1.0 / amplitude, 1.0 / (amplitude * omega));
        let u = u.component_mul(&scale);
        let w = w.component_mul(&scale);
        let qa = w.norm_squared();
        let qb = 2.0 * u.dot(&w);
        let qc = u.norm_squared() - 1.0;
        let disc = qb * qb - 4.0 * qa * qc;
        if !(disc >= 0.0 && qa > 0.0) {
            return Ok(Vec::new());
        }
        let root = -0.5 * (qb + qb.signum() * disc.sqrt());
        let mut roots = vec![root / qa, qc / root];
        roots.sort_by(f64::total_cmp);
        Ok(roots
            .into_iter()
            .map(|x0| {
                let cos = u[0] + x0 * w[0];
                let sin = -(u[1] + x0 * w[1]);
                let theta = sin.atan2(cos);
                let forcing_phase = wrap(theta + delta);
                let impact_time = (forcing_phase - phase).rem_euclid(TAU) / omega;
                let v = kappa * (x0 + d);
                let after = Vector4::new(x0, s * v, x0 + d, -v);
                let flight = Flight {
                    damper: self,
                    omega,
                    theta,
                    amplitude,
                    after,
                };
                let (primary_amplitude, free_amplitude, inside) = flight.extent(samples);
                let multipliers = self.multipliers(omega, forcing_phase, &flight);
                let stable = multipliers.iter().all(|[re, im]| re.hypot(*im) < 1.0);
                SymmetricOrbit {
                    forcing_phase,
                    impact_time,
                    primary_displacement: x0,
                    free_speed: v,
                    relative_velocity_before: v * (1.0 + gamma),
                    primary_amplitude,
                    free_amplitude,
                    viable: v > 0.0 && inside,
                    multipliers,
                    stable,
                }
            })
            .collect())
    }

    /// `Φ(t)`, the primary's free flow over `t`.
    fn free_flow(&self, t: f64) -> Matrix2<f64> {
        let [[a, b], [c, d]] = free_flow(self.mass, self.damping, self.stiffness, t);
        Matrix2::new(a, b, c, d)
    }

    /// `Φ₄(t)`: the primary's free flow and the free body's uniform motion.
    fn free_flow4(&self, t: f64) -> Matrix4<f64> {
        let p = self.free_flow(t);
        let mut flow = Matrix4::zeros();
        flow.fixed_view_mut::<2, 2>(0, 0).copy_from(&p);
        flow[(2, 2)] = 1.0;
        flow[(2, 3)] = t;
        flow[(3, 3)] = 1.0;
        flow
    }

    /// The vector field of `(x, ẋ, y, ẏ)` where the force's phase is `psi`.
    fn field(&self, state: &Vector4<f64>, psi: f64) -> Vector4<f64> {
        let acceleration =
            (self.force * psi.cos() - self.damping * state[1] - self.stiffness * state[0])
                / self.mass;
        Vector4::new(state[1], acceleration, state[3], 0.0)
    }

    /// The impact's linear map: positions kept, the relative velocity `ẏ − ẋ` turned into
    /// `−e(ẏ − ẋ)` with the momentum `m ẋ + m_b ẏ` kept.
    fn impact_map(&self) -> Matrix4<f64> {
        let total = self.mass + self.free_mass;
        let (to_primary, to_free) = (
            self.free_mass / total * (1.0 + self.restitution),
            self.mass / total * (1.0 + self.restitution),
        );
        // ẋ⁺ = ẋ + a(ẏ − ẋ), ẏ⁺ = ẏ − b(ẏ − ẋ).
        Matrix4::new(
            1.0,
            0.0,
            0.0,
            0.0,
            0.0,
            1.0 - to_primary,
            0.0,
            to_primary,
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
            to_free,
            0.0,
            1.0 - to_free,
        )
    }

    /// The saltation matrix of an impact from `before` where the force's phase is `psi`, on
    /// the wall whose condition has gradient `n`.
    fn saltation(&self, before: &Vector4<f64>, psi: f64, n: &Vector4<f64>) -> Matrix4<f64> {
        let r = self.impact_map();
        let after = r * before;
        let jump = self.field(&after, psi) - r * self.field(before, psi);
        r + jump * n.transpose() / n.dot(&self.field(before, psi))
    }

    /// The four multipliers of the orbit, by decreasing modulus.
    fn multipliers(&self, omega: f64, forcing_phase: f64, flight: &Flight<'_>) -> Vec<[f64; 2]> {
        let half = PI / omega;
        let before_plus = flight.before_plus();
        let before_minus = -before_plus;
        let n = Vector4::new(-1.0, 0.0, 1.0, 0.0);
        let s_plus = self.saltation(&before_plus, forcing_phase, &n);
        let s_minus = self.saltation(&before_minus, forcing_phase + PI, &n);
        let flow = self.free_flow4(half);
        let monodromy = flow * s_minus * flow * s_plus;
        let mut out: Vec<[f64; 2]> = monodromy
            .complex_eigenvalues()
            .iter()
            .map(|z| [z.re, z.im])
            .collect();
        out.sort_by(|a, b| b[0].hypot(b[1]).total_cmp(&a[0].hypot(a[1])));
        out
    }
}

/// One half-period flight of an orbit, from just after the impact on side `+`.
struct Flight<'a> {
    damper: &'a ImpactDamper,
    omega: f64,
    /// The forced response's phase `θ = α − δ` at the impact.
    theta: f64,
    amplitude: f64,
    /// `(x₀, ẋ⁺, x₀ + d, −V)`.
    after: Vector4<f64>,
}

impl Flight<'_> {
    /// The state at `t` into the flight.
    fn state(&self, t: f64) -> Vector4<f64> {
        let (a, w, th) = (self.amplitude, self.omega, self.theta);
        let forced = |t: f64| (a * (th + w * t).cos(), -a * w * (th + w * t).sin());
        let (p, q) = forced(0.0);
        let free =
            self.damper.free_flow(t) * nalgebra::Vector2::new(self.after[0] - p, self.after[1] - q);
        let (pt, qt) = forced(t);
        Vector4::new(
            pt + free[0],
            qt + free[1],
            self.after[2] + self.after[3] * t,
            self.after[3],
        )
    }

    /// The state just before the impact on side `+`: minus the state at the end of the
    /// flight (the half-period symmetry).
    fn before_plus(&self) -> Vector4<f64> {
        -self.state(PI / self.omega)
    }

    /// `max |x|`, `max |y|` over the flight, and whether `|y − x| ≤ d` there, on the grid.
    fn extent(&self, samples: usize) -> (f64, f64, bool) {
        let half = PI / self.omega;
        let d = self.damper.gap;
        let tolerance = 1e-9 * d.max(self.amplitude);
        let (mut primary, mut free, mut inside) = (self.after[0].abs(), self.after[2].abs(), true);
        for j in 1..=samples {
            let z = self.state(half * j as f64 / samples as f64);
            primary = primary.max(z[0].abs());
            free = free.max(z[2].abs());
            inside &= (z[2] - z[0]).abs() <= d + tolerance;
        }
        (primary, free, inside)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn damper() -> ImpactDamper {
        ImpactDamper {
            mass: 1.0,
            damping: 0.05,
            stiffness: 1.0,
            force: 1.0,
            phase: 0.3,
            free_mass: 0.1,
            gap: 0.6,
            restitution: 0.6,
        }
    }

    /// The closed form's orbit closes: the state just after the impact on side `+`, carried
    /// over half a period by the flight, reaches the other wall with the velocities the
    /// symmetry asks for, and the impact there maps it to minus the state after the first.
    #[test]
    fn an_orbit_closes_on_itself() {
        let omega = 1.0;
        let orbits = damper().symmetric_orbits(omega).unwrap();
        assert_eq!(orbits.len(), 2, "{orbits:?}");
        for orbit in &orbits {
            let d = damper();
            let dynamic = d.stiffness - d.mass * omega * omega;
            let amplitude = d.force / dynamic.hypot(d.damping * omega);
            let delta = (d.damping * omega).atan2(dynamic);
            let flight = Flight {
                damper: &d,
                omega,
                theta: orbit.forcing_phase - delta,
                amplitude,
                after: Vector4::new(
                    orbit.primary_displacement,
                    orbit.free_speed * (2.0 * 0.1 - (1.0 + 0.2 - 0.6) / 1.6),
                    orbit.primary_displacement + d.gap,
                    -orbit.free_speed,
                ),
            };
            let end = flight.state(PI / omega);
            // At the other wall: r = −d.
            assert!((end[2] - end[0] + d.gap).abs() < 1e-12, "{end}");
            let after = d.impact_map() * end;
            let expected = -flight.after;
            assert!((after - expected).amax() < 1e-12, "{after} {expected}");
            // The relative velocity before the impact on side `+` is that after it over −e.
            let before = flight.before_plus();
            let relative = before[3] - before[1];
            assert!((relative - orbit.relative_velocity_before).abs() < 1e-12);
            assert!((flight.after[3] - flight.after[1] + 0.6 * relative).abs() < 1e-12);
        }
    }

    /// The monodromy's determinant is `e⁴ e^{−cT/m}`: an impact's linear map has determinant
    /// `−e`, its saltation (by the matrix determinant lemma) that times the ratio `−e` of the
    /// relative velocities across it, so `e²` per impact; the flow contracts volume by
    /// `e^{−cT/(2m)}` per half period.
    #[test]
    fn the_multipliers_multiply_to_the_volume_contraction() {
        let omega = 1.0;
        for orbit in damper().symmetric_orbits(omega).unwrap() {
            let product = orbit
                .multipliers
                .iter()
                .fold(nalgebra::Complex::new(1.0, 0.0), |acc, [re, im]| {
                    acc * nalgebra::Complex::new(*re, *im)
                });
            let expected = 0.6f64.powi(4) * (-0.05 * TAU).exp();
            assert!(
                (product.re - expected).abs() < 1e-12,
                "{product} {expected}"
            );
            assert!(product.im.abs() < 1e-12);
        }
    }
}
