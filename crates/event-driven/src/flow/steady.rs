//! The forced steady response of a flow without rigid modes, in modal coordinates: the
//! periodic particular solution `z_p(t)` of the forcing at `ω` and of each higher harmonic at
//! `kω` (the responses of a linear system add), which the steady-response form of a flight
//! writes its motion about (`z(s) = e^{λs} ∘ (z(0) − z_p(t₀)) + z_p(t₀ + s)`).
//!
//! It exists when no forcing rate meets a mode: every `|±iω − λ| T`, `|±ikω − λ| T` and, under
//! a constant force, `|λ| T` above `10⁻⁴`. Where one does not (an undamped mode resonant with
//! the fundamental or a harmonic), the flow flies in the resonance-safe general form instead.

use super::{resonant, FlowHarmonic, C64};
use nalgebra::DVector;

/// The forced steady response in modal coordinates, `z_p(t) = P⁺ e^{iωt} + P⁻ e^{−iωt} + P⁰
/// + Σ_k (P⁺_k e^{ikωt} + P⁻_k e^{−ikωt})`, `P^±_j = g^±_j/(±iω − λ_j)`, `P⁰_j = −g⁰_j/λ_j`,
/// `P^±_{k,j} = g^±_{k,j}/(±ikω − λ_j)`.
#[derive(Debug, Clone)]
pub(super) struct SteadyResponse {
    pub(super) plus: Vec<C64>,
    pub(super) minus: Vec<C64>,
    pub(super) constant: Vec<C64>,
    /// Each higher harmonic's response, in the flow's order of its harmonics; empty for a
    /// forcing at `ω` alone.
    pub(super) harmonics: Vec<SteadyHarmonic>,
}

/// One higher harmonic's part of the steady response: its rate `kω` and `P^±_k` on
/// `e^{±ikωt}`.
#[derive(Debug, Clone)]
pub(super) struct SteadyHarmonic {
    pub(super) rate: f64,
    pub(super) plus: Vec<C64>,
    pub(super) minus: Vec<C64>,
}

/// The forcing of a flow in modal coordinates: `g⁺`, `g⁻` on `e^{±iωt}`, `g⁰` on the constant,
/// and the higher harmonics'.
pub(super) type ModalForcing<'a> = (
    &'a DVector<C64>,
    &'a DVector<C64>,
    &'a DVector<C64>,
    &'a [FlowHarmonic],
);

impl SteadyResponse {
    /// The steady response of the modes of rates `rates` to `forcing` at `omega` (period
    /// `period`), over every mode; `None` where a forcing rate is resonant with a mode.
    pub(super) fn new(
        rates: &[C64],
        (plus, minus, constant, harmonics): ModalForcing<'_>,
        omega: f64,
        period: f64,
    ) -> Option<Self> {
        let w = C64::new(0.0, omega);
        let has_constant = constant.iter().any(|c| *c != C64::default());
        let fundamental = rates.iter().all(|&l| {
            let forced_at_zero = has_constant && resonant(-l, period);
            !(resonant(w - l, period) || resonant(-w - l, period) || forced_at_zero)
        });
        let harmonic = harmonics.iter().all(|h| {
            let wk = C64::new(0.0, h.rate);
            rates
                .iter()
                .all(|&l| !(resonant(wk - l, period) || resonant(-wk - l, period)))
        });
        if !(fundamental && harmonic) {
            return None;
        }
        // `g/(μ − λ)` mode by mode.
        let respond = |g: &DVector<C64>, mu: C64| -> Vec<C64> {
            rates
                .iter()
                .zip(g.iter())
                .map(|(&l, &g)| g / (mu - l))
                .collect()
        };
        Some(Self {
            plus: respond(plus, w),
            minus: respond(minus, -w),
            constant: rates
                .iter()
                .zip(constant.iter())
                .map(|(&l, &g)| if has_constant { -g / l } else { C64::default() })
                .collect(),
            harmonics: harmonics
                .iter()
                .map(|h| {
                    let wk = C64::new(0.0, h.rate);
                    SteadyHarmonic {
                        rate: h.rate,
                        plus: respond(&h.plus, wk),
                        minus: respond(&h.minus, -wk),
                    }
                })
                .collect(),
        })
    }

    /// Kept mode `j`'s coordinate `(h_j e^{λ_j s} + P⁺_j F + P⁻_j F̄ + P⁰_j)·weight` from its
    /// decayed deviation `h_j e^{λ_j s}` and the forcing's phase `F` at `s`, for a forcing
    /// without harmonics: the one form of it ([`Flight::state_at`] adds the state from these,
    /// [`Flight::modal_state`] hands them out; `packed::pair_coordinates_avx` packs the same
    /// operations two modes at a time).
    ///
    /// [`Flight::state_at`]: super::Flight::state_at
    /// [`Flight::modal_state`]: super::Flight::modal_state
    #[inline(always)]
    pub(super) fn coordinate(&self, j: usize, decayed: C64, forced: C64, weight: f64) -> C64 {
        (decayed + self.plus[j] * forced + self.minus[j] * forced.conj() + self.constant[j])
            * weight
    }

    /// [`Self::coordinate`] with the higher harmonics: `(h_j e^{λ_j s} + P⁺_j F + P⁻_j F̄ +
    /// P⁰_j + Σ_k (P⁺_{k,j} F_k + P⁻_{k,j} F̄_k))·weight`, `harmonic` each harmonic's phase
    /// `F_k` at `s`, in order.
    #[inline]
    pub(super) fn coordinate_with_harmonics(
        &self,
        j: usize,
        (decayed, forced, harmonic): (C64, C64, &[C64]),
        weight: f64,
    ) -> C64 {
        let mut z =
            decayed + self.plus[j] * forced + self.minus[j] * forced.conj() + self.constant[j];
        for (h, &f) in self.harmonics.iter().zip(harmonic) {
            z += h.plus[j] * f + h.minus[j] * f.conj();
        }
        z * weight
    }

    /// Kept mode `j`'s steady response `z_p` at the phases `phase` (`e^{iωt}`) and
    /// `harmonic_phases` (`e^{ikωt}` of each harmonic, in order): `P⁺_j F + P⁻_j F̄ + P⁰_j`,
    /// then each harmonic's terms added in order.
    #[inline(always)]
    pub(super) fn at(&self, j: usize, phase: C64, harmonic_phases: &[C64]) -> C64 {
        let mut z = self.plus[j] * phase + self.minus[j] * phase.conj() + self.constant[j];
        if self.harmonics.is_empty() {
            return z;
        }
        for (h, &f) in self.harmonics.iter().zip(harmonic_phases) {
            z += h.plus[j] * f + h.minus[j] * f.conj();
        }
        z
    }

    /// The response of the kept modes only, in the order of `kept` (contiguous, as the
    /// flights' deviations are).
    pub(super) fn of_kept(self, kept: &[(usize, f64)]) -> Self {
        let pick = |v: &[C64]| kept.iter().map(|&(k, _)| v[k]).collect();
        Self {
            plus: pick(&self.plus),
            minus: pick(&self.minus),
            constant: pick(&self.constant),
            harmonics: self
                .harmonics
                .iter()
                .map(|h| SteadyHarmonic {
                    rate: h.rate,
                    plus: pick(&h.plus),
                    minus: pick(&h.minus),
                })
                .collect(),
        }
    }

    /// The steady response's part of the functional of modal weights `weights` (`Vᵀc`): its
    /// forced part `A` with `Re(A e^{iωt})`, its constant, and each harmonic's forced part
    /// `A_k` with `Re(A_k e^{ikωt})`, summed over the kept modes (`kept`, with their
    /// weights) in order.
    pub(super) fn functional_parts(
        &self,
        weights: &DVector<C64>,
        kept: &[(usize, f64)],
    ) -> (C64, f64, Vec<C64>) {
        let (mut forced, mut constant) = (C64::default(), 0.0);
        let mut harmonic = vec![C64::default(); self.harmonics.len()];
        for (j, &(k, weight)) in kept.iter().enumerate() {
            // Re[w P⁻ e^{−iωt}] = Re[conj(w P⁻) e^{iωt}].
            forced += (weights[k] * self.plus[j] + (weights[k] * self.minus[j]).conj()) * weight;
            constant += (weights[k] * self.constant[j]).re * weight;
            for (a, h) in harmonic.iter_mut().zip(&self.harmonics) {
                *a += (weights[k] * h.plus[j] + (weights[k] * h.minus[j]).conj()) * weight;
            }
        }
        (forced, constant, harmonic)
    }
}
