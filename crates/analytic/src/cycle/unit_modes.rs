//! The unit's flight flow `exp(Â τ)` and its frequency derivative in the modal basis of its
//! system matrix: the fast path of the cycle equations at augmented dimension 6.
//!
//! `Â = [[A, B], [0, W]]` with `W = ω J`, `J = [[0, −1], [1, 0]]`. The system matrix `A` does
//! not depend on `ω` (nor on the stops), so its eigen-decomposition `A = V Λ V⁻¹` is computed
//! once per unit and reused at every frequency and flight time. With `J = U M U⁻¹`,
//! `U = [[1, 1], [−i, i]]`, `M = diag(i, −i)`:
//!
//! `exp(Â τ) = [[V e^{Λτ} V⁻¹, V X̃ U⁻¹], [0, R(ωτ)]]`, `X̃_kl = B̃_kl d(λ_k, μ_l, τ)`,
//! `B̃ = V⁻¹ B U`, `μ_l = ±iω`, and `d(λ, μ, τ) = ∫₀^τ e^{λ(τ−s)} e^{μs} ds =
//! τ e^{μτ} φ₁((λ − μ)τ)` with `φ₁(z) = (e^z − 1)/z`: the divided difference, evaluated
//! stably through its confluent limit, so exact resonance (`λ_k = μ_l`, the undamped unit
//! forced at a natural frequency) needs nothing special. Only `V`'s conditioning matters:
//! where `A` is (nearly) defective the decomposition is refused and the caller keeps Padé.
//!
//! The `ω` column of continuation differentiates `Φ = exp(Â(ω) σ/ω)` at fixed forcing angle
//! `σ = ωτ`: `R(σ)` does not move, `dE/dω = −(τ/ω) A E`, and with `e^{μτ}` fixed,
//! `∂d/∂ω = −(τ/ω) e^{μτ} (φ₁(z) + λτ φ₁'(z))`, `z = (λ − μ)τ`, `φ₁' = φ₁ − φ₂`,
//! `φ₂(z) = (e^z − 1 − z)/z²`; `B̃` moves with `dB/dω`.

use crate::orbit::{SCHUR_EPSILON, SCHUR_ITERATIONS};
use nalgebra::{Complex, Matrix4, Matrix4x2, Matrix6, SMatrix};

type C = Complex<f64>;
type CMatrix4 = SMatrix<C, 4, 4>;
type CVector4 = SMatrix<C, 4, 1>;

/// The modal forcing of one frequency: what every flight at that `ω` shares.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ModalForcing {
    omega: f64,
    /// `B̃₀` of `Â(ω)`'s forcing `B`.
    forcing: CVector4,
}

impl ModalForcing {
    /// Whether `other` is this forcing bit for bit (a flow from one is the flow from the
    /// other).
    pub(crate) fn same_bits(&self, other: &Self) -> bool {
        self.omega.to_bits() == other.omega.to_bits()
            && self
                .forcing
                .iter()
                .zip(other.forcing.iter())
                .all(|(a, b)| a.re.to_bits() == b.re.to_bits() && a.im.to_bits() == b.im.to_bits())
    }
}

/// Largest accepted `‖V‖₁ ‖V⁻¹‖₁` of the eigenvector matrix (columns of unit 1-norm). The
/// modal flow's rounding grows with it; the paper's unit has 6.8 (damped or not), where the
/// flow came within 9.1e-16 of its size of a 40-digit reference (Padé: 9.3e-16), and 100
/// keeps it within about 1e-14. Beyond it (nearly coinciding modes, critical damping) the
/// decomposition is refused and the flights keep Padé.
const MAX_CONDITION: f64 = 100.0;

/// Largest accepted eigen-residual `‖A v − λ v‖₁`, relative to `‖A‖₁` (`v` of unit 1-norm):
/// a few hundred ulps. Inverse iteration from Schur's eigenvalues reaches a few ulps; a larger
/// residual means the eigenvalue was not simple.
const MAX_RESIDUAL: f64 = 1e-13;

/// Inverse-iteration steps per eigenvector: from a random-free start `(1, 1, 1, 1)` against
/// the shifted matrix at the computed eigenvalue, the first step already lies along the
/// eigenvector to rounding; the second removes what the start's other components left.
const INVERSE_ITERATIONS: usize = 2;

/// Below this `|z|`, `φ₁` and `φ₂` by their Taylor series (the closed forms lose
/// `log₁₀(1/|z|)` digits to cancellation): at `|z| < 1` the series' 20th term is below
/// `1/20! ≈ 4e-19`, under rounding.
const SERIES_RADIUS: f64 = 1.0;

/// Terms of the Taylor series of `φ₁`, `φ₂` inside [`SERIES_RADIUS`] (see there).
const SERIES_TERMS: usize = 20;

/// The eigen-decomposition `A = V Λ V⁻¹` of a unit's system matrix.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct UnitModes {
    system: Matrix4<f64>,
    values: [C; 4],
    vectors: CMatrix4,
    inverse: CMatrix4,
}

/// `B̃₀ = V⁻¹ (b₀ − i b₁)`: the forcing's `e^{iωt}` column in the modal basis (`B U`'s first
/// column, `b₀, b₁` the columns of `B`); the `e^{−iωt}` column is its conjugate's mirror and
/// is never needed (see [`UnitModes::forced`]).
fn modal_forcing(inverse: &CMatrix4, b: &Matrix4x2<f64>) -> CVector4 {
    let column = CVector4::from_fn(|r, _| C::new(b[(r, 0)], -b[(r, 1)]));
    inverse * column
}

/// One step of [`series`]'s lockstep recurrence, `p = p z / d + 1` in complex arithmetic
/// (as `num_complex` does it) on each of the `L` lanes `(re, im)`.
#[inline(always)]
fn series_step<const L: usize>(
    (pr, pi): (&mut [f64; L], &mut [f64; L]),
    (zr, zi): (&[f64; L], &[f64; L]),
    d: f64,
) {
    for l in 0..L {
        let re = pr[l] * zr[l] - pi[l] * zi[l];
        let im = pr[l] * zi[l] + pi[l] * zr[l];
        pr[l] = re / d + 1.0;
        pi[l] = im / d + 0.0;
    }
}

/// `φ₁(z_l)` and, with `RATE`, `φ₂(z_l)` of the `L` values `z_l` (the four modes of one
/// flight, or of two flights together) by their Taylor series, `φ₁ = Σ z^k/(k+1)!`,
/// `φ₂ = Σ z^k/(k+2)!`, Horner from the last term: the lanes in lockstep (independent chains
/// of divisions the processor overlaps, instead of one long chain per mode), each lane the
/// same operations in the same order as one series at a time, so bit for bit its scalar
/// value. Without `RATE`, `φ₂` is left at 1.
#[inline(always)]
fn series<const RATE: bool, const L: usize>(z: &[C; L]) -> ([C; L], [C; L]) {
    let (zr, zi) = (z.map(|v| v.re), z.map(|v| v.im));
    let (mut p1r, mut p1i) = ([1.0f64; L], [0.0f64; L]);
    let (mut p2r, mut p2i) = ([1.0f64; L], [0.0f64; L]);
    for k in (0..SERIES_TERMS - 1).rev() {
        // `p = p z / (k + c) + 1` in complex arithmetic (as `num_complex` does it).
        if RATE {
            series_step((&mut p2r, &mut p2i), (&zr, &zi), k as f64 + 3.0);
        }
        series_step((&mut p1r, &mut p1i), (&zr, &zi), k as f64 + 2.0);
    }
    (
        std::array::from_fn(|l| C::new(p1r[l], p1i[l])),
        std::array::from_fn(|l| C::new(p2r[l], p2i[l]) * 0.5),
    )
}

/// The arguments `z_l = (λ_l − μ) τ` of `φ₁`, `φ₂` of the four modes, and which of them lie
/// within [`SERIES_RADIUS`] (taken by the series).
#[inline(always)]
fn series_arguments(lambda: &[C; 4], mu: C, tau: f64) -> ([C; 4], [bool; 4]) {
    let z: [C; 4] = std::array::from_fn(|l| (lambda[l] - mu) * tau);
    let near = z.map(|z| z.norm_sqr() < SERIES_RADIUS * SERIES_RADIUS);
    (z, near)
}

/// `d(λ_l, μ, τ) = ∫₀^τ e^{λ_l(τ−s)} e^{μs} ds` of the four modes from `e^{λ_l τ}` and
/// `e^{μτ}`, and, with `RATE`, `∂d/∂ω` at fixed `σ = ωτ` (see the module's notes; without
/// `RATE` it is not computed and returned as zero): the closed form
/// `(e^{λτ} − e^{μτ})/(λ − μ)` where `|λ − μ|τ ≥ 1`, the series of `φ₁`, `φ₂` below
/// ([`series`], run once for the modes that need it).
#[inline(always)]
fn divided<const RATE: bool>(
    lambda: &[C; 4],
    mu: C,
    tau: f64,
    e_lambda: &[C; 4],
    e_mu: C,
) -> ([C; 4], [C; 4]) {
    let (z, near) = series_arguments(lambda, mu, tau);
    let by_series = near.iter().any(|&n| n).then(|| series::<RATE, 4>(&z));
    divided_from::<RATE>(lambda, tau, e_lambda, e_mu, (&z, &near), by_series.as_ref())
}

/// [`divided`] from the arguments `z` of the series and which are `near` (see
/// [`series_arguments`]) and the series' values `by_series` (`Some` wherever one is near).
#[inline(always)]
fn divided_from<const RATE: bool>(
    lambda: &[C; 4],
    tau: f64,
    e_lambda: &[C; 4],
    e_mu: C,
    (z, near): (&[C; 4], &[bool; 4]),
    by_series: Option<&([C; 4], [C; 4])>,
) -> ([C; 4], [C; 4]) {
    let mut d = [C::new(0.0, 0.0); 4];
    let mut rate = [C::new(0.0, 0.0); 4];
    for l in 0..4 {
        let (p1, p2) = match &by_series {
            Some((p1, p2)) if near[l] => (p1[l], p2[l]),
            _ => {
                // e^z − 1 = (e^{λτ} − e^{μτ}) e^{−μτ}, |e^{μτ}| = 1.
                let em1 = (e_lambda[l] - e_mu) * e_mu.conj();
                let p1 = em1 / z[l];
                (p1, (em1 - z[l]) / (z[l] * z[l]))
            }
        };
        d[l] = e_mu * p1 * tau;
        if RATE {
            rate[l] = e_mu * (p1 + lambda[l] * tau * (p1 - p2));
        }
    }
    (d, rate)
}

/// Entries of the factors of [`real_product`] below this size (real and imaginary parts)
/// cannot overflow in the imaginary parts it skips: four products of two of them sum to at
/// most `4e200`.
const REAL_PRODUCT_BOUND: f64 = 1e100;

/// The real part of nalgebra's complex product `a b` (bit for bit `(a * b).map(|c| c.re)`),
/// at half its cost: nalgebra forms entry `(i, j)` as `y = (1 a_i0) b_0j`, then
/// `y = (1 a_ik) b_kj + 1 y` for `k = 1 … 3`, in complex arithmetic. Its real part takes the
/// real value of every imaginary part it reads only through products with an exact `0`
/// (`1 a` is `(1 a.re − 0 a.im, …)`), so for finite factors (no overflow: entries below
/// [`REAL_PRODUCT_BOUND`]) every real part along the way has the same value as the sums of
/// real parts alone, `Re(a_ik b_kj) + y.re`, formed here, and rounds alike: the results agree
/// bit for bit wherever they are not zero (a zero's sign may depend on the imaginary parts).
/// Where a result is zero, or a factor is not below the bound, nalgebra's product is taken.
/// `UnitModes::modal` spent 8.8 % of the paper unit's continuation in nalgebra's product.
fn real_product(a: &CMatrix4, b: &CMatrix4) -> Matrix4<f64> {
    let bounded = |m: &CMatrix4| {
        m.iter()
            .all(|c| c.re.abs() < REAL_PRODUCT_BOUND && c.im.abs() < REAL_PRODUCT_BOUND)
    };
    if bounded(a) && bounded(b) {
        let out = Matrix4::from_fn(|i, j| {
            let term = |k: usize| {
                let (x, y) = (a[(i, k)], b[(k, j)]);
                x.re * y.re - x.im * y.im
            };
            let mut sum = term(0);
            for k in 1..4 {
                sum += term(k);
            }
            sum
        });
        if out.iter().all(|&v| v != 0.0) {
            return out;
        }
    }
    (a * b).map(|c| c.re)
}

/// What a flight of duration `tau` at frequency `ω` shares between its flow's parts.
struct Flight {
    tau: f64,
    /// `e^{μτ} = e^{iωτ}`.
    e_mu: C,
    /// `e^{λ_l τ}` of each mode.
    e_lambda: [C; 4],
    /// The arguments of the series ([`series_arguments`]) and which of them it takes.
    z: [C; 4],
    near: [bool; 4],
}

impl Flight {
    #[inline(always)]
    fn new(modes: &UnitModes, omega: f64, tau: f64) -> Self {
        let (s, c) = (omega * tau).sin_cos();
        let (z, near) = series_arguments(&modes.values, C::new(0.0, omega), tau);
        Self {
            tau,
            e_mu: C::new(c, s),
            e_lambda: modes.values.map(|l| (l * tau).exp()),
            z,
            near,
        }
    }
}

impl UnitModes {
    /// The decomposition of `system`, or `None` when it is not finite, Schur's iteration fails,
    /// or the eigenvectors are ill-conditioned ([`MAX_CONDITION`]) or inaccurate
    /// ([`MAX_RESIDUAL`]): then the caller keeps the Padé exponential.
    pub(crate) fn new(system: &Matrix4<f64>) -> Option<Self> {
        if !system.iter().all(|v| v.is_finite()) {
            return None;
        }
        let schur = nalgebra::linalg::Schur::try_new(*system, SCHUR_EPSILON, SCHUR_ITERATIONS)?;
        let found = schur.complex_eigenvalues();
        let values = [found[0], found[1], found[2], found[3]];
        let a = system.map(|v| C::new(v, 0.0));
        let norm = system
            .column_iter()
            .map(|c| c.lp_norm(1))
            .fold(0.0, f64::max);
        let tiny = f64::EPSILON * norm.max(f64::MIN_POSITIVE);
        let mut vectors = CMatrix4::zeros();
        for (k, &lambda) in values.iter().enumerate() {
            let mut shifted = a;
            for d in 0..4 {
                shifted[(d, d)] -= lambda;
            }
            let lu = shifted.lu();
            let mut v = nalgebra::Vector4::from_element(C::new(1.0, 0.0));
            for _ in 0..INVERSE_ITERATIONS {
                v = match lu.solve(&v) {
                    Some(w) if w.iter().all(|c| c.re.is_finite() && c.im.is_finite()) => w,
                    // Exactly singular: perturb the shift by rounding of ‖A‖ and retry.
                    _ => {
                        let mut nudged = shifted;
                        for d in 0..4 {
                            nudged[(d, d)] -= tiny;
                        }
                        nudged.lu().solve(&v)?
                    }
                };
                let size: f64 = v.iter().map(|c| c.norm()).sum();
                if !(size.is_finite() && size > 0.0) {
                    return None;
                }
                v /= C::new(size, 0.0);
            }
            let residual: f64 = (a * v - v * lambda).iter().map(|c| c.norm()).sum();
            if residual > MAX_RESIDUAL * norm {
                return None;
            }
            vectors.set_column(k, &v);
        }
        let mut inverse = vectors.lu().try_inverse()?;
        // One step of iterative refinement of the inverse, then the two-sided Rayleigh
        // quotients `w_k A v_k / (w_k v_k)` (`w_k` row k of `V⁻¹`): eigenvalues to a few ulps.
        let defect = CMatrix4::identity() - vectors * inverse;
        inverse += inverse * defect;
        let av = a * vectors;
        let mut values = values;
        for (k, value) in values.iter_mut().enumerate() {
            let w = inverse.row(k);
            let num = (w * av.column(k))[(0, 0)];
            let den = (w * vectors.column(k))[(0, 0)];
            *value = num / den;
        }
        let norm1 = |m: &CMatrix4| {
            m.column_iter()
                .map(|c| c.iter().map(|v| v.norm()).sum::<f64>())
                .fold(0.0, f64::max)
        };
        let condition = norm1(&vectors) * norm1(&inverse);
        (condition.is_finite() && condition <= MAX_CONDITION).then_some(Self {
            system: *system,
            values,
            vectors,
            inverse,
        })
    }

    /// Whether `augmented` is `[[A, B], [0, ωJ]]` with this decomposition's `A` (bit for bit),
    /// the structure [`Self::flow`] assumes.
    pub(crate) fn fits(&self, augmented: &Matrix6<f64>) -> bool {
        augmented.fixed_view::<4, 4>(0, 0) == self.system
            && augmented.fixed_view::<2, 4>(4, 0).iter().all(|&v| v == 0.0)
            && augmented[(4, 4)] == 0.0
            && augmented[(5, 5)] == 0.0
            && augmented[(4, 5)] == -augmented[(5, 4)]
    }

    /// Whether `rate` is `dÂ/dω` of the structure [`Self::flow_rate`] assumes: `A` and the
    /// bottom-left block fixed, the phase block's rate `J`.
    pub(crate) fn fits_rate(rate: &Matrix6<f64>) -> bool {
        rate.fixed_view::<6, 4>(0, 0).iter().all(|&v| v == 0.0)
            && rate[(4, 4)] == 0.0
            && rate[(5, 5)] == 0.0
            && rate[(4, 5)] == -1.0
            && rate[(5, 4)] == 1.0
    }

    /// `V diag(f_k) V⁻¹`, real part: [`real_product`] of `V diag(f_k)` and `V⁻¹`.
    fn modal(&self, f: &[C; 4]) -> Matrix4<f64> {
        let scaled = CMatrix4::from_fn(|r, k| self.vectors[(r, k)] * f[k]);
        real_product(&scaled, &self.inverse)
    }

    /// The forcing of `augmented` (`[[A, B], [0, ωJ]]`, see [`Self::fits`]) in the modal basis.
    pub(crate) fn forcing(&self, augmented: &Matrix6<f64>) -> ModalForcing {
        let b: Matrix4x2<f64> = augmented.fixed_view::<4, 2>(0, 4).into_owned();
        ModalForcing {
            omega: augmented[(5, 4)],
            forcing: modal_forcing(&self.inverse, &b),
        }
    }

    /// `X(τ) = V X̃ U⁻¹` from its first column's modal sum `y₀ = Σ_k v_k c_k` (`c_k` the
    /// coefficient of mode `k` against `e^{iωt}`): for real `A` and `B` the second column of
    /// `V X̃` is `y₀`'s conjugate, so `X = (Re y₀, −Im y₀)`.
    fn forced(&self, coefficients: &CVector4) -> Matrix4x2<f64> {
        let y = self.vectors * coefficients;
        Matrix4x2::<f64>::from_fn(|r, c| if c == 0 { y[r].re } else { -y[r].im })
    }

    /// `exp(Â τ)` of `Â = [[A, B], [0, ωJ]]`, `forcing` being `B` and `ω` in the modal basis.
    pub(crate) fn flow(&self, forcing: &ModalForcing, tau: f64) -> Matrix6<f64> {
        let flight = Flight::new(self, forcing.omega, tau);
        let by_series = flight
            .near
            .iter()
            .any(|&n| n)
            .then(|| series::<false, 4>(&flight.z));
        self.flow_of(forcing, &flight, by_series.as_ref())
    }

    /// [`Self::flow`] of two flights at once, bit for bit the two flows: where both take
    /// series ([`series`]), the two run in lockstep on eight lanes, whose chains of divisions
    /// the processor overlaps (one flight's four lanes leave it waiting on their latency).
    pub(crate) fn flow_pair(&self, forcing: &ModalForcing, taus: [f64; 2]) -> [Matrix6<f64>; 2] {
        // Built one by one (not by `array::map`, whose moves of the results cost more here
        // than the series they pair).
        let first = Flight::new(self, forcing.omega, taus[0]);
        let second = Flight::new(self, forcing.omega, taus[1]);
        let needs = |f: &Flight| f.near.iter().any(|&n| n);
        let (by_first, by_second) = if needs(&first) && needs(&second) {
            let z: [C; 8] =
                std::array::from_fn(|l| if l < 4 { first.z[l] } else { second.z[l - 4] });
            let (p1, p2) = series::<false, 8>(&z);
            let half = |p: &[C; 8], at: usize| [p[at], p[at + 1], p[at + 2], p[at + 3]];
            (
                Some((half(&p1, 0), half(&p2, 0))),
                Some((half(&p1, 4), half(&p2, 4))),
            )
        } else {
            (
                needs(&first).then(|| series::<false, 4>(&first.z)),
                needs(&second).then(|| series::<false, 4>(&second.z)),
            )
        };
        [
            self.flow_of(forcing, &first, by_first.as_ref()),
            self.flow_of(forcing, &second, by_second.as_ref()),
        ]
    }

    /// [`Self::flow`] of `flight`, the series' values `by_series` computed for it.
    #[inline(always)]
    fn flow_of(
        &self,
        forcing: &ModalForcing,
        flight: &Flight,
        by_series: Option<&([C; 4], [C; 4])>,
    ) -> Matrix6<f64> {
        let (d, _) = divided_from::<false>(
            &self.values,
            flight.tau,
            &flight.e_lambda,
            flight.e_mu,
            (&flight.z, &flight.near),
            by_series,
        );
        let coefficients = CVector4::from_fn(|k, _| forcing.forcing[k] * d[k]);
        let mut out = Matrix6::zeros();
        out.fixed_view_mut::<4, 4>(0, 0)
            .copy_from(&self.modal(&flight.e_lambda));
        out.fixed_view_mut::<4, 2>(0, 4)
            .copy_from(&self.forced(&coefficients));
        let (s, c) = (flight.e_mu.im, flight.e_mu.re);
        out[(4, 4)] = c;
        out[(4, 5)] = -s;
        out[(5, 4)] = s;
        out[(5, 5)] = c;
        out
    }

    /// `d/dω exp(Â(ω) σ/ω)` at fixed `σ = ω τ`, `forcing` being `Â(ω)`'s and `forcing_rate`
    /// that of `dB/dω` (`A` does not depend on `ω`; the phase block's rate is `J`).
    pub(crate) fn flow_rate(
        &self,
        forcing: &ModalForcing,
        forcing_rate: &ModalForcing,
        tau: f64,
    ) -> Matrix6<f64> {
        let omega = forcing.omega;
        let mu = C::new(0.0, omega);
        let (s, c) = (omega * tau).sin_cos();
        let e_mu = C::new(c, s);
        let e_lambda = self.values.map(|l| (l * tau).exp());
        let dtau = -tau / omega;
        let (d, d_rate) = divided::<true>(&self.values, mu, tau, &e_lambda, e_mu);
        let coefficients = CVector4::from_fn(|k, _| {
            forcing_rate.forcing[k] * d[k] + forcing.forcing[k] * d_rate[k] * dtau
        });
        let mut out = Matrix6::zeros();
        let rates: [C; 4] = std::array::from_fn(|k| self.values[k] * e_lambda[k] * dtau);
        out.fixed_view_mut::<4, 4>(0, 0)
            .copy_from(&self.modal(&rates));
        out.fixed_view_mut::<4, 2>(0, 4)
            .copy_from(&self.forced(&coefficients));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_models::{damped_paper_unit, paper_unit};

    /// [`real_product`] equals the real part of nalgebra's complex product bit for bit, on
    /// matrices with entries of every sign and scale, exact zeros (of both signs) among them,
    /// and on factors beyond [`REAL_PRODUCT_BOUND`].
    #[test]
    fn real_product_is_nalgebras_bit_for_bit() {
        let mut entry = crate::cycle::awkward_entries(0x2545_F491_4F6C_DD1D);
        let mut count = 0u32;
        let mut next = || {
            count += 1;
            // One entry in 101 beyond the bound: about half the pairs of factors hold one.
            if count % 101 == 0 {
                entry() * 1e120
            } else {
                entry()
            }
        };
        for _ in 0..20_000 {
            let a = CMatrix4::from_fn(|_, _| C::new(next(), next()));
            let b = CMatrix4::from_fn(|_, _| C::new(next(), next()));
            let fast = real_product(&a, &b);
            let slow = (a * b).map(|c| c.re);
            for (x, y) in fast.iter().zip(slow.iter()) {
                assert_eq!(x.to_bits(), y.to_bits(), "{a} {b}");
            }
        }
    }

    /// [`UnitModes::flow_pair`] gives the two flows of [`UnitModes::flow`] bit for bit, both
    /// flights by the series (short flights), one of them, or neither.
    #[test]
    fn flow_pair_is_two_flows_bit_for_bit() {
        for unit in [paper_unit(), damped_paper_unit()] {
            let modes = UnitModes::new(&unit.system_matrix()).expect("well-conditioned modes");
            for omega in [0.3, 1.3, 1.5f64.sqrt(), 3.7] {
                let forcing = modes.forcing(&unit.augmented_matrix(omega));
                let taus = [1e-6, 0.05, 0.3, 0.7, 2.0, 9.0];
                for &a in &taus {
                    for &b in &taus {
                        let pair = modes.flow_pair(&forcing, [a, b]);
                        for (fast, tau) in pair.iter().zip([a, b]) {
                            let one = modes.flow(&forcing, tau);
                            for (x, y) in fast.iter().zip(one.iter()) {
                                assert_eq!(x.to_bits(), y.to_bits(), "{omega} {a} {b}");
                            }
                        }
                    }
                }
            }
        }
    }

    /// `d/dω exp(Â(ω) σ/ω)` by the block exponential the Padé path uses: the Fréchet
    /// derivative in the direction `(Â'/ω − Â/ω²) σ`.
    fn block_rate(a: &Matrix6<f64>, rate: &Matrix6<f64>, tau: f64) -> Matrix6<f64> {
        let omega = a[(5, 4)];
        let sigma = omega * tau;
        let b = a / omega;
        let b_rate = rate / omega - a / (omega * omega);
        let big = SMatrix::<f64, 12, 12>::from_fn(|i, j| match (i < 6, j < 6) {
            (true, true) => b[(i, j)] * sigma,
            (false, false) => b[(i - 6, j - 6)] * sigma,
            (true, false) => b_rate[(i, j - 6)] * sigma,
            (false, true) => 0.0,
        })
        .exp();
        Matrix6::from_fn(|i, j| big[(i, 6 + j)])
    }

    /// The modal flow equals Padé's exponential to rounding, damped and undamped, at exact
    /// resonance (`ω` a natural frequency) and away from it; its `ω` derivative matches the
    /// block exponential the Padé path takes it from ([`block_rate`]).
    #[test]
    fn modal_flow_equals_pade() {
        for unit in [paper_unit(), damped_paper_unit()] {
            let modes = UnitModes::new(&unit.system_matrix()).expect("well-conditioned modes");
            let resonance = (1.5f64).sqrt();
            for omega in [0.3, 1.3, resonance, 6f64.sqrt(), 3.7] {
                let a = unit.augmented_matrix(omega);
                let mut rate = unit.augmented_matrix(omega + 1.0) - a;
                rate.fixed_view_mut::<4, 4>(0, 0).fill(0.0);
                for tau in [1e-6, 0.3, 2.0, 9.0] {
                    let exact = (a * tau).exp();
                    let fast = modes.flow(&modes.forcing(&a), tau);
                    let scale = exact.amax().max(1.0);
                    assert!((fast - exact).amax() < 1e-13 * scale, "{omega} {tau}");
                    let d = modes.flow_rate(&modes.forcing(&a), &modes.forcing(&rate), tau);
                    let fd = block_rate(&a, &rate, tau);
                    let err = (d - fd).amax() / fd.amax().max(1.0);
                    assert!(err < 1e-12, "{omega} {tau} {err:e}");
                }
            }
        }
    }
}
