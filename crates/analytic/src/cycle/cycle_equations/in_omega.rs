//! The cycle equations' Jacobian in `(x, ω)`: the residuals' derivative in the forcing
//! frequency at fixed impact phases, beside the one in the unknowns (continuation's).

use super::{CycleEquations, CycleEvaluation};
use crate::cycle::unit_flights::{dynamic_exp, product, to_unit, unit_exp, UNIT_SIZE};
use crate::cycle::unit_modes::UnitModes;
use crate::problem::forcing::PhaseRows;
use nalgebra::allocator::Allocator;
use nalgebra::{DMatrix, DefaultAllocator, DimMin, OMatrix, SMatrix};

impl<D: DimMin<D, Output = D>> CycleEquations<D>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    /// The cycle at `x = (α, φ₂ … φ_m)` with the exact Jacobian in `(x, ω)`, `m × (m + 1)`:
    /// the last column is `∂ residual / ∂ω` at fixed `x` (impact phases as fractions of the
    /// cycle), `augmented_rate` being `dÂ/dω`. In the forcing angle `σ = ωt` a flight over the
    /// phase fraction `Δφ` is `Φ = exp(B σ)`, `σ = 2πp Δφ`, `B = Â/ω`, so `ω` enters only through
    /// `B`: `∂Φ/∂ω` is the Fréchet derivative of the exponential in the direction `B'σ`,
    /// `B' = Â'/ω − Â/ω²`, the top-right block of `exp([[Bσ, B'σ], [0, Bσ]])`. `None` when the
    /// periodicity solve is singular.
    ///
    /// # Panics
    /// If `x` does not have one entry per impact or `augmented_rate` is not the size of `Â`.
    pub fn evaluate_in_omega(
        &self,
        x: &[f64],
        augmented_rate: &OMatrix<f64, D, D>,
    ) -> Option<CycleEvaluation<D>> {
        let e = self.evaluate_with(x, false)?;
        self.with_omega_jacobian(x, e, augmented_rate)
    }

    /// [`Self::evaluate_in_omega`] from the evaluation `e` of the residuals at the same `x`
    /// ([`Self::evaluate_with`] without derivatives, on these equations): the exact Jacobian
    /// in `(x, ω)` added to it, the flights and maps reused (the result is the one
    /// [`Self::evaluate_in_omega`] gives, bit for bit). `None` when the periodicity solve is
    /// singular.
    ///
    /// # Panics
    /// If `x` does not have one entry per impact or `augmented_rate` is not the size of `Â`.
    pub fn with_omega_jacobian(
        &self,
        x: &[f64],
        mut e: CycleEvaluation<D>,
        augmented_rate: &OMatrix<f64, D, D>,
    ) -> Option<CycleEvaluation<D>> {
        let factors = self.periodic_factors(&e.pre)?;
        let solver = factors.view();
        let in_x = self.jacobian_in(&e, &solver, x[0])?;
        let m = self.impacts();
        let size = self.augmented.nrows();
        let d = D::from_usize(size);
        let omega = self.omega;
        let b = &self.augmented / omega;
        let b_rate = augmented_rate / omega - &self.augmented / (omega * omega);
        let angle = self.cycle * omega;
        let phases = Self::phases(x);
        let modal = self.modes.as_ref().and_then(|(modes, forcing)| {
            let rate = to_unit(augmented_rate);
            UnitModes::fits_rate(&rate).then(|| (modes, forcing, modes.forcing(&rate)))
        });
        let rates: Vec<OMatrix<f64, D, D>> = (0..m)
            .map(|f| {
                let end = if f + 1 < m { phases[f + 1] } else { 1.0 };
                if let Some((modes, forcing, forcing_rate)) = &modal {
                    let tau = (end - phases[f]) * self.cycle;
                    let fast = modes.flow_rate(forcing, forcing_rate, tau);
                    return OMatrix::<f64, D, D>::from_fn_generic(d, d, |i, j| fast[(i, j)]);
                }
                let sigma = (end - phases[f]) * angle;
                // A contact phase's flight has its own `Â` (the rate `Â'` is the free one's:
                // the contact adds nothing that depends on `ω`).
                let own = self.contact_matrix(f).map(|a| {
                    let b = a / omega;
                    let rate = augmented_rate / omega - a / (omega * omega);
                    (b, rate)
                });
                let (b, b_rate) = own.as_ref().map_or((&b, &b_rate), |(b, r)| (b, r));
                let block = |i: usize, j: usize| match (i < size, j < size) {
                    (true, true) => b[(i, j)] * sigma,
                    (false, false) => b[(i - size, j - size)] * sigma,
                    (true, false) => b_rate[(i, j - size)] * sigma,
                    (false, true) => 0.0,
                };
                if size == UNIT_SIZE {
                    // The unit's 12×12 exponential on the stack (no heap matrices per flight).
                    let ex = unit_exp(&SMatrix::from_fn(block));
                    OMatrix::<f64, D, D>::from_fn_generic(d, d, |i, j| ex[(i, size + j)])
                } else {
                    let ex = dynamic_exp(&DMatrix::from_fn(2 * size, 2 * size, block));
                    OMatrix::<f64, D, D>::from_fn_generic(d, d, |i, j| ex[(i, size + j)])
                }
            })
            .collect();
        let own = |f: usize| {
            Some(if f == 0 {
                rates[0].clone()
            } else {
                product(&rates[f], &product(&self.g_hats[f], &e.pre[f - 1]))
            })
        };
        let in_omega = self.column_in(&e, &solver, own, PhaseRows::Still)?;
        let mut jacobian = DMatrix::zeros(m, m + 1);
        jacobian.view_mut((0, 0), (m, m)).copy_from(&in_x);
        jacobian.set_column(m, &in_omega);
        e.jacobian = jacobian;
        Some(e)
    }
}
