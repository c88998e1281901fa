//! The contact phases of a cycle: flights under their own augmented matrix.
//!
//! A contact phase of a compliant pair is two events of the cycle equations, its entry and
//! its exit, each with the identity as impact map (the state is continuous) and the pair's
//! contact condition `h_jᵀ z(t_j⁻) = c_j` (the coordinate at the stop: the penetration is
//! zero). The flight between them is the exact flow of the contact system, `exp(Â_c τ)`,
//! `Â_c = Â + Δ`, `Δ` the contact's spring, dashpot and constant force
//! ([`crate::LinearModel`]'s contact increment), which does not depend on `ω`. Everything the
//! cycle equations derive from the flights holds flight by flight with `Â_f` in place of `Â`:
//! `∂Φ_f/∂τ_f = Â_f Φ_f`, and the `ω`-derivative through `B_f = Â_f/ω` with the free flight's
//! rate `Â'`.
//!
//! A sticking phase is a flight of the same kind: between its landing impact and its release
//! the pair is held on its stop, `Â_s = Â + Δ_s` with the accelerations projected onto
//! `wᵀü = 0`. Its `Δ_s` depends on `ω` (through the forcing's columns), so equations with a
//! sticking phase are built at each frequency, not moved by [`CycleEquations::at_frequency`]
//! (continuation refuses sequences with contact or sticking phases), and their `ω`-derivative
//! leaves out `∂Δ_s/∂ω`.
//!
//! A stiff contact has a fast mode `ω_c = √(k_c wᵀM⁻¹w)`: its matrix holds `1` in the position
//! rows and `ω_c²` in the velocity rows, so its norm over a contact (`τ ≈ π/ω_c`) is about
//! `ω_c` while its eigenvalues are of modulus about `π`. The exponential is taken of the
//! balanced `S⁻¹Â_cS τ`, `S = diag(I_n, σI_n, I_P)`, `σ` the power of two nearest the contact
//! system's fastest rate: the velocities measured in units of `σ` put both blocks at about
//! `ω_c τ`, scaling and squaring then squares about once instead of `log₂ ω_c` times, and the
//! scaling by powers of two is exact. The flow is `S exp(S⁻¹Â_cS τ) S⁻¹`.

use super::CycleEquations;
use crate::model::fastest_rate;
use nalgebra::allocator::Allocator;
use nalgebra::{DMatrix, DefaultAllocator, Dim, DimMin, OMatrix};
use std::sync::Arc;

/// The flight of a contact phase, in augmented dimension `D`.
#[derive(Debug, Clone)]
pub(crate) struct ContactFlight<D: Dim>
where
    DefaultAllocator: Allocator<D, D>,
{
    /// `Δ`: what the contact adds to the free flight's `Â` (independent of `ω`).
    increment: OMatrix<f64, D, D>,
    /// `Â_c = Â + Δ` at the equations' frequency.
    matrix: OMatrix<f64, D, D>,
    /// `σ`: the velocity scale of the balanced exponential, a power of two.
    balance: f64,
}

/// The power of two nearest the fastest rate of the flow of the augmented `matrix` of `dofs`
/// degrees of freedom ([`fastest_rate`] of its mechanical rows), 1 for a flow without rate.
pub(crate) fn velocity_balance<D: Dim>(matrix: &OMatrix<f64, D, D>, dofs: usize) -> f64
where
    DefaultAllocator: Allocator<D, D>,
{
    let system = DMatrix::from_fn(2 * dofs, 2 * dofs, |i, j| matrix[(i, j)]);
    let rate = fastest_rate(&system, dofs);
    if rate > 0.0 && rate.is_finite() {
        2f64.powi(rate.log2().round() as i32)
    } else {
        1.0
    }
}

/// `exp(A τ)` by the balanced exponential `S exp(S⁻¹AS τ) S⁻¹`, `S = diag(I_n, σI_n, I_P)`
/// (see the module's documentation); `dofs` is `n`.
pub(crate) fn balanced_exp<D: DimMin<D, Output = D>>(
    a: &OMatrix<f64, D, D>,
    dofs: usize,
    balance: f64,
    tau: f64,
) -> OMatrix<f64, D, D>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let (d, _) = a.shape_generic();
    let scale = |i: usize| {
        if (dofs..2 * dofs).contains(&i) {
            balance
        } else {
            1.0
        }
    };
    let b =
        OMatrix::<f64, D, D>::from_fn_generic(d, d, |i, j| a[(i, j)] * (scale(j) / scale(i)) * tau);
    let e = b.exp();
    OMatrix::<f64, D, D>::from_fn_generic(d, d, |i, j| e[(i, j)] * (scale(i) / scale(j)))
}

impl<D: DimMin<D, Output = D>> CycleEquations<D>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    /// The same equations with contact phases: `increments[f]` is `Some(Δ)` when flight `f`
    /// (from event `f` to event `f + 1`) is a contact phase, whose augmented matrix is then
    /// `Â + Δ`; `None` for a free flight. The modal flow of [`Self::with_modal_flow`] is
    /// dropped (it knows only the free flight's modes).
    ///
    /// # Panics
    /// If `increments` does not have one entry per event.
    pub(crate) fn with_contact_flights(self, increments: Vec<Option<OMatrix<f64, D, D>>>) -> Self {
        assert_eq!(increments.len(), self.impacts(), "one entry per flight");
        let dofs = self.states() / 2;
        let flights: Vec<Option<ContactFlight<D>>> = increments
            .into_iter()
            .map(|increment| {
                increment.map(|increment| {
                    let matrix = &self.augmented + &increment;
                    let balance = velocity_balance(&matrix, dofs);
                    ContactFlight {
                        increment,
                        matrix,
                        balance,
                    }
                })
            })
            .collect();
        Self {
            contact_flights: Some(flights.into()),
            modes: None,
            ..self
        }
    }

    /// The contact flights at the equations' frequency (after [`Self::at_frequency`]): `Â_c`
    /// recomputed from the new `Â` and each `Δ`.
    pub(crate) fn contact_flights_at_frequency(&self) -> Option<Arc<[Option<ContactFlight<D>>]>> {
        let flights = self.contact_flights.as_ref()?;
        let dofs = self.states() / 2;
        let moved: Vec<Option<ContactFlight<D>>> = flights
            .iter()
            .map(|flight| {
                flight.as_ref().map(|c| {
                    let matrix = &self.augmented + &c.increment;
                    let balance = velocity_balance(&matrix, dofs);
                    ContactFlight {
                        increment: c.increment.clone(),
                        matrix,
                        balance,
                    }
                })
            })
            .collect();
        Some(moved.into())
    }

    /// Whether the cycle has contact phases.
    pub fn has_contact_phases(&self) -> bool {
        self.contact_flights.is_some()
    }

    /// `Â_f` of flight `f` when it is a contact phase; `None` for a free flight (whose matrix
    /// is [`Self::augmented_matrix`]).
    pub(crate) fn contact_matrix(&self, f: usize) -> Option<&OMatrix<f64, D, D>> {
        self.contact_flights
            .as_ref()
            .and_then(|flights| flights[f].as_ref())
            .map(|c| &c.matrix)
    }

    /// `Â_f` of flight `f`: its contact matrix, or the free flight's `Â`.
    pub(crate) fn flight_matrix(&self, f: usize) -> &OMatrix<f64, D, D> {
        self.contact_matrix(f).unwrap_or(&self.augmented)
    }

    /// The flow of flight `f` over `tau`: the balanced exponential of a contact phase, or
    /// [`Self::flow`].
    pub(crate) fn flight_flow(&self, f: usize, tau: f64) -> OMatrix<f64, D, D> {
        let contact = self
            .contact_flights
            .as_ref()
            .and_then(|flights| flights[f].as_ref());
        match contact {
            Some(c) => balanced_exp(&c.matrix, self.states() / 2, c.balance, tau),
            None => self.flow(tau),
        }
    }
}
