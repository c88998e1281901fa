//! The impact oscillator's period-1 orbit in closed form: one body on a spring and a dashpot
//! to the frame, `m ẍ + c ẋ + k x = F cos(ωt + φ)`, against a rigid stop at `x = σ`
//! (`ẋ⁺ = −r ẋ⁻`), with one impact per forcing period (Shaw & Holmes; Budd & Dux).
//!
//! The flight between two impacts lasts one period `T = 2π/ω`. Write the motion as the steady
//! forced response `x_p(t) = A cos(ωt + φ − δ)`, `A = F/√((k − mω²)² + (cω)²)`,
//! `δ = atan2(cω, k − mω²)`, plus the free motion `z_h = Φ(t) z_h(0)`, `z = (x, ẋ)`.
//! Let `θ` be the phase of `x_p` at the impact, `(p, q) = (A cos θ, −Aω sin θ)` its state there,
//! and `v = ẋ⁻ > 0` the velocity just before the impact. `x_p` repeats over `T`, so periodicity
//! of the whole motion is periodicity of the free part:
//! `(σ − p, v − q) = Φ(T) (σ − p, −r v − q)`.
//! These two equations are linear in `(cos θ, sin θ, v)`; they give `cos θ` and `sin θ` as
//! affine functions of `v`, and `cos²θ + sin²θ = 1` is a quadratic in `v`: zero or two orbits.
//!
//! With `λ = c/(2m)`, `ω_n² = k/m`, `ω_d = √(ω_n² − λ²)` (underdamped), the free flow over `t`
//! is `Φ = e^{−λt} [[C + (λ/ω_d) S, S/ω_d], [−(ω_n²/ω_d) S, C − (λ/ω_d) S]]`,
//! `C = cos ω_d t`, `S = sin ω_d t`.
//!
//! An orbit is a motion (viable) when the impact is approached from inside (`v > 0`) and
//! `x(t) ≤ σ` over the flight, checked here on a fine uniform grid of the closed form (a
//! reference for orbits away from grazing, not a rigorous bound). Its stability is that of the
//! monodromy `Φ(T) S`, `S = [[−r, 0], [(a⁺ + r a⁻)/v, −r]]` the saltation matrix at the
//! impact, `a^∓` the accelerations just before and after it.

use std::f64::consts::TAU;
use thiserror::Error;

/// The impact oscillator: one body against a rigid stop on side `+` (`x = σ`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactOscillator {
    /// `m > 0`.
    pub mass: f64,
    /// `c ≥ 0`, with `c² < 4km` (underdamped).
    pub damping: f64,
    /// `k > 0`.
    pub stiffness: f64,
    /// `F`, the force's amplitude.
    pub force: f64,
    /// `φ`, the force's phase: `F cos(ωt + φ)`.
    pub phase: f64,
    /// `σ > 0`, the stop's distance.
    pub gap: f64,
    /// `r ∈ [0, 1]`.
    pub restitution: f64,
}

/// A period-1 orbit with one impact per period.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeriodOneOrbit {
    /// The force's phase `ωt + φ` at the impact, rad in `(−π, π]`.
    pub forcing_phase: f64,
    /// The impact's time within the period, `[0, T)`: the force is `F cos(ω t_i + φ)` there.
    pub impact_time: f64,
    /// `ẋ⁻`, the velocity just before the impact.
    pub velocity_before: f64,
    /// `max |x|` over the period (on the grid of the viability check).
    pub amplitude: f64,
    /// Approached from inside (`ẋ⁻ > 0`) and `x ≤ σ` over the flight.
    pub viable: bool,
    /// The two Floquet multipliers `[re, im]`.
    pub multipliers: [[f64; 2]; 2],
    /// Both multipliers inside the unit circle.
    pub stable: bool,
}

/// Why there is no closed form.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ReferenceError {
    /// The oscillator is not underdamped, or a value is out of range.
    #[error("the closed form needs m, k, σ, ω > 0, r in [0, 1] and an underdamped oscillator")]
    OutOfRange,
}

/// Samples of the flight in the viability check of [`ImpactOscillator::period_one_orbits`]:
/// the grid's spacing (`T/2¹⁶`) resolves an excursion beyond the stop of more than about
/// `1e-9` of the motion's size for flights whose fastest rate is of the order of `ω`.
pub const VIABILITY_SAMPLES: usize = 1 << 16;

impl ImpactOscillator {
    /// Every period-1 one-impact orbit at `omega` (zero or two), viable or not, its
    /// viability checked on [`VIABILITY_SAMPLES`] points of the flight.
    ///
    /// # Errors
    /// [`ReferenceError::OutOfRange`] outside the closed form's range.
    pub fn period_one_orbits(&self, omega: f64) -> Result<Vec<PeriodOneOrbit>, ReferenceError> {
        self.period_one_orbits_sampled(omega, VIABILITY_SAMPLES)
    }

    /// The fold in `[lo, hi]`: where the count of period-1 orbits changes (its two orbits
    /// meet and vanish), bisected to rounding; `None` when the count is the same at both ends.
    ///
    /// # Errors
    /// [`ReferenceError::OutOfRange`] outside the closed form's range.
    pub fn fold_between(&self, mut lo: f64, mut hi: f64) -> Result<Option<f64>, ReferenceError> {
        // The count does not depend on the viability grid: the coarsest one serves.
        let count = |omega: f64| self.period_one_orbits_sampled(omega, 16).map(|o| o.len());
        let at_lo = count(lo)?;
        if at_lo == count(hi)? {
            return Ok(None);
        }
        while hi - lo > 4.0 * f64::EPSILON * hi {
            let mid = 0.5 * (lo + hi);
            if count(mid)? == at_lo {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Ok(Some(0.5 * (lo + hi)))
    }

    /// [`Self::period_one_orbits`] with the viability (and the amplitude) checked on
    /// `samples` points of the flight: fewer for a figure, whose points near grazing may then
    /// be misjudged by an excursion below the grid's resolution.
    ///
    /// # Errors
    /// [`ReferenceError::OutOfRange`] outside the closed form's range.
    pub fn period_one_orbits_sampled(
        &self,
        omega: f64,
        samples: usize,
    ) -> Result<Vec<PeriodOneOrbit>, ReferenceError> {
        let Self {
            mass: m,
            damping: c,
            stiffness: k,
            force,
            phase,
            gap: sigma,
            restitution: r,
        } = *self;
        let lambda = c / (2.0 * m);
        let wn2 = k / m;
        let ok = m > 0.0
            && k > 0.0
            && c >= 0.0
            && sigma > 0.0
            && omega > 0.0
            && (0.0..=1.0).contains(&r)
            && lambda * lambda < wn2;
        if !ok {
            return Err(ReferenceError::OutOfRange);
        }
        let period = TAU / omega;
        let [[a, b], [d, e]] = self.free_flow(period);
        let dynamic = k - m * omega * omega;
        let amplitude = force / dynamic.hypot(c * omega);
        let delta = (c * omega).atan2(dynamic);
        // [[A(a−1), −bAω], [dA, Aω(1−e)]] (cos θ, sin θ) = ((a−1)σ − b r v, dσ − (1 + e r) v).
        let (m11, m12, m21, m22) = (
            amplitude * (a - 1.0),
            -b * amplitude * omega,
            d * amplitude,
            amplitude * omega * (1.0 - e),
        );
        let det = m11 * m22 - m12 * m21;
        // (cos θ, sin θ) = u + v w.
        let solve = |r1: f64, r2: f64| ((m22 * r1 - m12 * r2) / det, (m11 * r2 - m21 * r1) / det);
        let u = solve((a - 1.0) * sigma, d * sigma);
        let w = solve(-b * r, -(1.0 + e * r));
        let qa = w.0 * w.0 + w.1 * w.1;
        let qb = 2.0 * (u.0 * w.0 + u.1 * w.1);
        let qc = u.0 * u.0 + u.1 * u.1 - 1.0;
        let disc = qb * qb - 4.0 * qa * qc;
        if disc < 0.0 || !det.is_finite() || det == 0.0 {
            return Ok(Vec::new());
        }
        let root = -0.5 * (qb + qb.signum() * disc.sqrt());
        let mut roots = vec![root / qa, qc / root];
        roots.sort_by(f64::total_cmp);
        Ok(roots
            .into_iter()
            .map(|v| {
                let (cos, sin) = (u.0 + v * w.0, u.1 + v * w.1);
                let theta = sin.atan2(cos);
                let forcing_phase = wrap(theta + delta);
                let impact_time = (forcing_phase - phase).rem_euclid(TAU) / omega;
                let (p, q) = (amplitude * cos, -amplitude * omega * sin);
                let after = (sigma - p, -r * v - q);
                let (peak, inside) = self.flight_extent(omega, theta, after, amplitude, samples);
                let (multipliers, stable) = self.multipliers(omega, forcing_phase, v);
                PeriodOneOrbit {
                    forcing_phase,
                    impact_time,
                    velocity_before: v,
                    amplitude: peak,
                    viable: v > 0.0 && inside,
                    multipliers,
                    stable,
                }
            })
            .collect())
    }

    /// `Φ(t)`, the free flow over `t`.
    fn free_flow(&self, t: f64) -> [[f64; 2]; 2] {
        free_flow(self.mass, self.damping, self.stiffness, t)
    }

    /// `max |x|` over the flight from the impact and whether `x ≤ σ` there, on the grid:
    /// `x = A cos(θ + ωt) + (Φ(t) z_h(0))₀`.
    fn flight_extent(
        &self,
        omega: f64,
        theta: f64,
        free: (f64, f64),
        amplitude: f64,
        samples: usize,
    ) -> (f64, bool) {
        let period = TAU / omega;
        let sigma = self.gap;
        let tolerance = 1e-9 * sigma.max(amplitude);
        let mut peak = sigma;
        let mut inside = true;
        for j in 1..samples {
            let t = period * j as f64 / samples as f64;
            let [[a, b], _] = self.free_flow(t);
            let x = amplitude * (theta + omega * t).cos() + a * free.0 + b * free.1;
            peak = peak.max(x.abs());
            inside &= x <= sigma + tolerance;
        }
        (peak, inside)
    }

    /// The Floquet multipliers of the orbit with the force's phase `forcing_phase` at the
    /// impact and velocity `v` just before it, and whether both lie inside the unit circle.
    fn multipliers(&self, omega: f64, forcing_phase: f64, v: f64) -> ([[f64; 2]; 2], bool) {
        let (m, c, k, r) = (self.mass, self.damping, self.stiffness, self.restitution);
        let push = self.force * forcing_phase.cos() - k * self.gap;
        let before = (push - c * v) / m;
        let after = (push + c * r * v) / m;
        let saltation = [[-r, 0.0], [(after + r * before) / v, -r]];
        let [[a, b], [d, e]] = self.free_flow(TAU / omega);
        let mono = [
            [
                a * saltation[0][0] + b * saltation[1][0],
                a * saltation[0][1] + b * saltation[1][1],
            ],
            [
                d * saltation[0][0] + e * saltation[1][0],
                d * saltation[0][1] + e * saltation[1][1],
            ],
        ];
        let trace = mono[0][0] + mono[1][1];
        let det = mono[0][0] * mono[1][1] - mono[0][1] * mono[1][0];
        let disc = trace * trace - 4.0 * det;
        let pair = if disc >= 0.0 {
            let s = disc.sqrt();
            [[0.5 * (trace + s), 0.0], [0.5 * (trace - s), 0.0]]
        } else {
            let s = (-disc).sqrt();
            [[0.5 * trace, 0.5 * s], [0.5 * trace, -0.5 * s]]
        };
        let stable = pair.iter().all(|[re, im]| re.hypot(*im) < 1.0);
        (pair, stable)
    }
}

/// `Φ(t)`, the free flow over `t` of the underdamped `m ẍ + c ẋ + k x = 0`, as rows.
pub(crate) fn free_flow(m: f64, c: f64, k: f64, t: f64) -> [[f64; 2]; 2] {
    let lambda = c / (2.0 * m);
    let wn2 = k / m;
    let wd = (wn2 - lambda * lambda).sqrt();
    let (s, c) = (wd * t).sin_cos();
    let decay = (-lambda * t).exp();
    [
        [decay * (c + lambda / wd * s), decay * s / wd],
        [-decay * wn2 / wd * s, decay * (c - lambda / wd * s)],
    ]
}

/// `x` wrapped to `(−π, π]`.
pub(crate) fn wrap(x: f64) -> f64 {
    let y = x.rem_euclid(TAU);
    if y > std::f64::consts::PI {
        y - TAU
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed form's orbit repeats: integrating the flight from just after the impact by
    /// the closed-form free flow and the particular solution returns to `x = σ` with velocity
    /// `v` after one period (the two equations it was built from, evaluated independently).
    #[test]
    fn an_orbit_closes_on_itself() {
        let o = ImpactOscillator {
            mass: 1.3,
            damping: 0.07,
            stiffness: 0.9,
            force: 0.8,
            phase: 0.4,
            gap: 0.3,
            restitution: 0.7,
        };
        let omega = 1.1;
        let orbits = o.period_one_orbits(omega).unwrap();
        assert_eq!(orbits.len(), 2);
        for orbit in orbits {
            let period = TAU / omega;
            let dynamic = o.stiffness - o.mass * omega * omega;
            let a = o.force / dynamic.hypot(o.damping * omega);
            let delta = (o.damping * omega).atan2(dynamic);
            let xp = |t: f64| a * (omega * t + o.phase - delta).cos();
            let vp = |t: f64| -a * omega * (omega * t + o.phase - delta).sin();
            let ti = orbit.impact_time;
            let h0 = (
                o.gap - xp(ti),
                -o.restitution * orbit.velocity_before - vp(ti),
            );
            let [[p, q], [s, u]] = o.free_flow(period);
            let x = xp(ti + period) + p * h0.0 + q * h0.1;
            let v = vp(ti + period) + s * h0.0 + u * h0.1;
            assert!((x - o.gap).abs() < 1e-12, "{x}");
            assert!((v - orbit.velocity_before).abs() < 1e-12, "{v}");
            // The determinant of the monodromy is r² e^{−cT/m}.
            let [[r1, i1], [r2, i2]] = orbit.multipliers;
            let det = r1 * r2 - i1 * i2;
            let expected = o.restitution.powi(2) * (-o.damping * period / o.mass).exp();
            assert!((det - expected).abs() < 1e-12, "{det} {expected}");
        }
    }
}
