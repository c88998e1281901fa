//! The flows a response runs on: free flight, or a set of pairs held on their stops (the
//! constrained flow), each with its pairs' gaps, its held pairs' contact forces and its
//! contact law.
//!
//! With `D` the held pairs' directions (rows), the constraint `D u = g` (`g_p = +gap_plus` or
//! `−gap_minus`) leaves `u = T ũ + u*`, `T` an orthonormal basis of `null D` (Gram–Schmidt on
//! the unit vectors, as the periodic engine builds it), `u* = Dᵀ(DDᵀ)⁻¹g`; the reduced flow
//! is `TᵀMT ũ̈ + TᵀCT ũ̇ + TᵀKT ũ = Tᵀ(d s + v ṡ) − TᵀK u*`, the signal projected and a
//! constant force. The contact forces `λ` (`M ü = f − C u̇ − K u + Dᵀλ`) follow from
//! `D ü = 0`: `λ = −W⁻¹ D M⁻¹ (f − C u̇ − K u)`, `W = D M⁻¹ Dᵀ`; a pair on side `σ` is held
//! while its push `−σλ` is positive, and each push over a flight is a sum of terms (the
//! reduced state's and the signal's), searched for its first zero as the gaps are.

use super::modal::{Basis, Flight, FlightForcing, Functional, ModalForce};
use super::signal::Signal;
use super::ResponseError;
use crate::expsum::ExpSum;
use crate::model::Model;
use nalgebra::{DMatrix, DVector};

/// In the Gram–Schmidt of a held set's basis of `null D`, a projected unit vector shorter
/// than this is dependent on the ones kept (the periodic engine's threshold).
const BASIS_DROP: f64 = 1e-8;

/// Adds the constant `c` to the sum `out` (as [`ExpSum::shifted`], in place).
fn add_constant(out: &mut ExpSum, c: f64) {
    if c != 0.0 {
        let zero = nalgebra::Complex::new(0.0, 0.0);
        out.terms.push(crate::expsum::Term {
            poly: [nalgebra::Complex::new(c, 0.0), zero, zero, zero],
            rate: zero,
        });
    }
}

/// One held pair's push `−σλ` as `state · (ũ, ũ̇) + constant + α s + β ṡ`.
struct Push {
    state: Functional,
    constant: f64,
    on_signal: f64,
    on_rate: f64,
}

/// A flow of the response: free, or with `held` pairs on their stops.
pub(super) struct Phase {
    /// `(pair, side)` of the held pairs, in pair order; empty for free flight.
    pub(super) held: Vec<(usize, i8)>,
    basis: Basis,
    /// `u = T ũ + u*`: `(T, u*)`; `None` in free flight (`T = I`, `u* = 0`).
    reduction: Option<(DMatrix<f64>, DVector<f64>)>,
    /// The modal forces of `Tᵀd`, `Tᵀv` and the constant `−TᵀK u*`.
    forces: (ModalForce, ModalForce, Option<ModalForce>),
    /// Per pair of the model, `r = d·u` as a functional of the reduced state plus `d·u*`.
    gaps: Vec<(Functional, f64)>,
    /// Per held pair, its push.
    pushes: Vec<Push>,
    /// `(D, M⁻¹DᵀW⁻¹)`: accelerations and impulses lose `reaction · D ·` their free part.
    constraint: Option<(DMatrix<f64>, DMatrix<f64>)>,
    /// `W⁻¹ D M⁻¹`, the contact forces' map of the free force.
    force_map: Option<DMatrix<f64>>,
}

impl Phase {
    /// The free flow of `model` under `excitation`.
    ///
    /// # Errors
    /// [`ResponseError::Flow`] when the modal flow does not exist.
    pub(super) fn free(
        model: &Model,
        excitation: &super::Excitation,
    ) -> Result<Phase, ResponseError> {
        let basis = Basis::of_model(model)?;
        let n = model.dofs();
        let forces = (
            basis.force(&excitation.on_signal),
            basis.force(&excitation.on_rate),
            None,
        );
        let gaps = model
            .contacts
            .iter()
            .map(|c| {
                let mut position = DVector::zeros(2 * n);
                position.rows_mut(0, n).copy_from(&c.direction(n));
                (basis.functional(&position), 0.0)
            })
            .collect();
        Ok(Phase {
            held: Vec::new(),
            basis,
            reduction: None,
            forces,
            gaps,
            pushes: Vec::new(),
            constraint: None,
            force_map: None,
        })
    }

    /// The constrained flow of `model` under `excitation` with the pairs `held` (`(pair,
    /// side)`, in pair order, at least one) on their stops.
    ///
    /// # Errors
    /// [`ResponseError::DependentHolds`] when the held directions are dependent (at `time`),
    /// [`ResponseError::Flow`] when the reduced flow does not exist.
    pub(super) fn held(
        model: &Model,
        excitation: &super::Excitation,
        held: &[(usize, i8)],
        time: f64,
    ) -> Result<Phase, ResponseError> {
        let n = model.dofs();
        let h = held.len();
        let dependent = || ResponseError::DependentHolds {
            pairs: held.iter().map(|p| p.0).collect(),
            time,
        };
        if h == 0 || h > n {
            return Err(dependent());
        }
        let directions: Vec<DVector<f64>> = held
            .iter()
            .map(|&(pair, _)| model.contacts[pair].direction(n))
            .collect();
        let mut spanned: Vec<DVector<f64>> = Vec::with_capacity(h);
        for d in &directions {
            let mut v = d.clone();
            for b in &spanned {
                v -= b * b.dot(&v);
            }
            if v.norm() <= BASIS_DROP {
                return Err(dependent());
            }
            spanned.push(v.normalize());
        }
        let mut columns: Vec<DVector<f64>> = Vec::new();
        for i in 0..n {
            let mut v = DVector::zeros(n);
            v[i] = 1.0;
            for b in spanned.iter().chain(&columns) {
                v -= b * b.dot(&v);
            }
            if v.norm() > BASIS_DROP && columns.len() < n - h {
                columns.push(v.normalize());
            }
        }
        let m = n - h;
        let t = if columns.is_empty() {
            DMatrix::zeros(n, 0)
        } else {
            DMatrix::from_columns(&columns)
        };
        let gaps_at = DVector::from_iterator(
            h,
            held.iter().map(|&(pair, side)| {
                let c = &model.contacts[pair];
                if side > 0 {
                    c.gap_plus
                } else {
                    -c.gap_minus
                }
            }),
        );
        let constraint =
            DMatrix::from_rows(&directions.iter().map(|d| d.transpose()).collect::<Vec<_>>());
        let offset = {
            let ddt = &constraint * constraint.transpose();
            constraint.transpose() * (ddt.try_inverse().ok_or_else(dependent)? * &gaps_at)
        };
        let minv = model
            .mass
            .clone()
            .try_inverse()
            .ok_or(crate::flow::FlowError::SingularMass)?;
        let mobilities = &minv * constraint.transpose();
        let w = &constraint * &mobilities;
        let w_inverse = w.try_inverse().ok_or_else(dependent)?;
        let force_map = &w_inverse * &constraint * &minv;
        let reaction = &mobilities * &w_inverse;
        let tt = t.transpose();
        let (mass, stiffness) = (&model.mass, &model.stiffness);
        let damping = model.damping.as_ref().map(|c| &tt * c * &t);
        let basis = Basis::new(
            &(&tt * mass * &t),
            damping.as_ref(),
            &(&tt * stiffness * &t),
        )?;
        let constant = -(&tt * (stiffness * &offset));
        let forces = (
            basis.force(&(&tt * &excitation.on_signal)),
            basis.force(&(&tt * &excitation.on_rate)),
            constant
                .iter()
                .any(|&v| v != 0.0)
                .then(|| basis.force(&constant)),
        );
        let gaps = model
            .contacts
            .iter()
            .map(|c| {
                let d = c.direction(n);
                let mut weights = DVector::zeros(2 * m);
                weights.rows_mut(0, m).copy_from(&(&tt * &d));
                (basis.functional(&weights), d.dot(&offset))
            })
            .collect();
        // push = −σλ = σ W⁻¹DM⁻¹ (f − K(Tũ + u*) − C T ũ̇).
        let on_position = &force_map * stiffness * &t;
        let on_velocity = model.damping.as_ref().map(|c| &force_map * c * &t);
        let on_offset = &force_map * (stiffness * &offset);
        let on_signal = &force_map * &excitation.on_signal;
        let on_rate = &force_map * &excitation.on_rate;
        let pushes = held
            .iter()
            .enumerate()
            .map(|(row, &(_, side))| {
                let sign = side as f64;
                let mut weights = DVector::zeros(2 * m);
                for j in 0..m {
                    weights[j] = -sign * on_position[(row, j)];
                    if let Some(v) = &on_velocity {
                        weights[m + j] = -sign * v[(row, j)];
                    }
                }
                Push {
                    state: basis.functional(&weights),
                    constant: -sign * on_offset[row],
                    on_signal: sign * on_signal[row],
                    on_rate: sign * on_rate[row],
                }
            })
            .collect();
        Ok(Phase {
            held: held.to_vec(),
            basis,
            reduction: Some((t, offset)),
            forces,
            gaps,
            pushes,
            constraint: Some((constraint, reaction)),
            force_map: Some(force_map),
        })
    }

    /// Whether pair `pair` is held.
    pub(super) fn holds(&self, pair: usize) -> bool {
        self.held.iter().any(|h| h.0 == pair)
    }

    /// The fastest rate of the flow (`0` for none).
    pub(super) fn fastest_rate(&self) -> f64 {
        self.basis.fastest_rate()
    }

    /// The reduced state `(ũ, ũ̇) = (Tᵀ(u − u*), Tᵀu̇)` of the state `y`.
    fn reduce(&self, y: &DVector<f64>) -> DVector<f64> {
        let Some((t, offset)) = &self.reduction else {
            return y.clone();
        };
        let (n, m) = (t.nrows(), t.ncols());
        let mut out = DVector::zeros(2 * m);
        out.rows_mut(0, m)
            .copy_from(&(t.transpose() * (y.rows(0, n) - offset)));
        out.rows_mut(m, m)
            .copy_from(&(t.transpose() * y.rows(n, n)));
        out
    }

    /// The flight from the state `y` at `t0` in segment `segment` of `signal`, resonance-safe
    /// over the horizon `h`.
    pub(super) fn flight(
        &self,
        y: &DVector<f64>,
        (signal, segment): (&Signal, Option<usize>),
        t0: f64,
        h: f64,
    ) -> Flight {
        let mut forcing =
            Basis::flight_forcing((&self.forces.0, &self.forces.1), signal, segment, t0);
        if let Some(extra) = &self.forces.2 {
            forcing = forcing.with_constant(extra);
        }
        self.flight_with(&self.reduce(y), &forcing, h)
    }

    fn flight_with(&self, yr: &DVector<f64>, forcing: &FlightForcing, h: f64) -> Flight {
        self.basis.flight(yr, forcing, h)
    }

    /// The state `y` (length `2n`) at `s` into `flight`.
    pub(super) fn state_into(&self, flight: &Flight, s: f64, y: &mut DVector<f64>) {
        let Some((t, offset)) = &self.reduction else {
            return self.basis.state_into(flight, s, y);
        };
        let (n, m) = (t.nrows(), t.ncols());
        let mut yr = DVector::zeros(2 * m);
        self.basis.state_into(flight, s, &mut yr);
        y.rows_mut(0, n).copy_from(&(t * yr.rows(0, m) + offset));
        y.rows_mut(n, n).copy_from(&(t * yr.rows(m, m)));
    }

    /// Pair `pair`'s relative displacement over `flight` as a sum of terms, into `out`.
    pub(super) fn gap(&self, flight: &Flight, pair: usize, out: &mut ExpSum) {
        let (functional, constant) = &self.gaps[pair];
        self.basis.expand(flight, functional, out);
        add_constant(out, *constant);
    }

    /// The push of the `k`-th held pair over `flight` (from `t0` in segment `segment`) as a
    /// sum of terms, into `out`: positive while the stop holds it.
    pub(super) fn push(
        &self,
        flight: &Flight,
        k: usize,
        (signal, segment): (&Signal, Option<usize>),
        t0: f64,
        out: &mut ExpSum,
    ) {
        let push = &self.pushes[k];
        self.basis.expand(flight, &push.state, out);
        add_constant(out, push.constant);
        signal.add_terms(segment, t0, (push.on_signal, push.on_rate), &mut out.terms);
    }

    /// The acceleration `ü` at the state `y` under the force `f`, the held pairs' contact
    /// forces included.
    pub(super) fn acceleration(
        &self,
        model: &Model,
        y: &DVector<f64>,
        f: &DVector<f64>,
    ) -> DVector<f64> {
        let n = model.dofs();
        let mut net = f - &model.stiffness * y.rows(0, n);
        if let Some(c) = &model.damping {
            net -= c * y.rows(n, n);
        }
        let minv_net = model
            .mass
            .clone()
            .lu()
            .solve(&net)
            .unwrap_or_else(|| DVector::zeros(n));
        match &self.constraint {
            None => minv_net,
            Some((d, reaction)) => &minv_net - reaction * (d * &minv_net),
        }
    }

    /// The held pairs' pushes `−σλ` at the state `y` under the force `f`, in the held order.
    pub(super) fn pushes_at(&self, model: &Model, y: &DVector<f64>, f: &DVector<f64>) -> Vec<f64> {
        let Some(map) = &self.force_map else {
            return Vec::new();
        };
        let n = model.dofs();
        let mut net = f - &model.stiffness * y.rows(0, n);
        if let Some(c) = &model.damping {
            net -= c * y.rows(n, n);
        }
        let lambda = -(map * net);
        self.held
            .iter()
            .zip(lambda.iter())
            .map(|(&(_, side), &l)| -(side as f64) * l)
            .collect()
    }

    /// Newton restitution `e` of pair `pair` at the state `y`, the held pairs kept on their
    /// stops: along the constrained mobility `M⁻¹d − M⁻¹DᵀW⁻¹DM⁻¹d`, which is the free
    /// impact ([`Model::apply_impact`]) when the impact does not reach the held pairs.
    pub(super) fn restitute(&self, model: &Model, pair: usize, y: &mut DVector<f64>, e: f64) {
        let n = model.dofs();
        if let Some((d_held, reaction)) = &self.constraint {
            let (d, mobility) = &model.directions[pair];
            let coupling = d_held * mobility;
            if coupling.iter().any(|&c| c != 0.0) {
                let constrained = mobility - reaction * coupling;
                let rdot = d.dot(&y.rows(n, n));
                let scale = (1.0 + e) * rdot / d.dot(&constrained);
                for i in 0..n {
                    y[n + i] -= constrained[i] * scale;
                }
                return;
            }
        }
        model.apply_impact(pair, y, Some(e));
    }
}
