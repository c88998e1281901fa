//! A [`LinearModel`]'s side of continuation (a chain of cells, or any model with contact
//! pairs): its cycle equations on heap matrices, the verdicts of
//! [`crate::verdicts::assemble`] at each point, and the test functions per contact
//! pair from the model's rigorous extrema.

use super::system::{flight_span, BranchModel, Cycles, Verdicts};
use super::test_functions::{torus_test, Test, Tests};
use crate::cycle_equations::{CycleEquations, CycleEvaluation};
use crate::model::LinearModel;
use crate::model_flight::ModelFlight;
use crate::sequence::{ImpactSequence, PairImpact, SequenceError};
use crate::sequence_orbit::{SequenceOrbitError, SequenceProblem};
use crate::sequence_verdicts::{ModelVerdicts, SequenceOrbit};
use nalgebra::{Complex, DMatrix, DVector, Dyn};

/// The cycle equations of one impact sequence of a model.
pub(crate) struct ModelBranch<'a> {
    model: &'a LinearModel,
    sequence: ImpactSequence,
    cycles: Cycles<Dyn>,
}

impl<'a> ModelBranch<'a> {
    /// The orbits of `sequence` on `model`.
    ///
    /// # Errors
    /// [`SequenceError::Pair`] when the sequence names a pair the model lacks;
    /// [`SequenceError::ContinuedContact`] when it has contact phases.
    pub(crate) fn new(
        model: &'a LinearModel,
        sequence: ImpactSequence,
    ) -> Result<Self, SequenceError> {
        if sequence.has_contact_phases() {
            return Err(SequenceError::ContinuedContact);
        }
        let problem = SequenceProblem::new(model, 1.0, &sequence).map_err(|e| match e {
            SequenceOrbitError::Sequence(s) => s,
            // A frequency of 1 is valid: only the sequence can be refused.
            _ => unreachable!("ω = 1 is a valid frequency"),
        })?;
        let equations: CycleEquations<Dyn> = problem.equations().clone();
        let cycles = Cycles::new(equations, model.augmented_rate(), sequence.period());
        Ok(Self {
            model,
            sequence,
            cycles,
        })
    }

    /// The orbit's verdicts at `X` from the sequence solver's own assembly; `None` when the
    /// periodicity solve is singular there.
    fn orbit(&self, x: &[f64]) -> Option<SequenceOrbit> {
        let n = x.len() - 1;
        let problem = SequenceProblem::new(self.model, x[n], &self.sequence).ok()?;
        let phases = CycleEquations::<Dyn>::phases(&x[..n]);
        ModelVerdicts::new(&problem).assemble(x[0], &phases, 0).ok()
    }

    /// Per flight and pair, the distance of the pair's coordinate to its nearer stop at its
    /// interior critical points, and the time and impact of that critical point.
    fn clearances(
        &self,
        x: &[f64],
        eval: &CycleEvaluation<Dyn>,
    ) -> (Vec<f64>, Vec<(f64, PairImpact)>) {
        let n = x.len() - 1;
        let omega = x[n];
        let dofs = self.model.dofs();
        let impacts = self.sequence.impacts();
        let pairs = self.model.pairs();
        let functionals: Vec<DVector<f64>> = pairs
            .iter()
            .map(|p| {
                let mut c = DVector::zeros(self.model.augmented_size());
                c.rows_mut(0, dofs).copy_from(&p.direction);
                c
            })
            .collect();
        let critical = vec![true; pairs.len()];
        let flight = ModelFlight::new(self.model, omega);
        let cycle = self.cycles.angle() / omega;
        let before = eval.before_impacts();
        let mut clearance = Vec::with_capacity(n * pairs.len());
        let mut graze = Vec::with_capacity(n * pairs.len());
        for f in 0..n {
            let (s, e) = flight_span(x, n, f);
            let x_before = before[f].rows(0, 2 * dofs).into_owned();
            let mut start = if f == 0 {
                eval.z1.clone()
            } else {
                before[f].clone()
            };
            start
                .rows_mut(0, 2 * dofs)
                .copy_from(&self.model.impact_state(impacts[f].pair, &x_before));
            let ext = flight.mixed_extrema(&start, (e - s) * cycle, &functionals, &critical);
            for (q, pair) in pairs.iter().enumerate() {
                let to_side1 = pair.gap_side1 - ext[q].max;
                let to_side2 = pair.gap_side2 + ext[q].min;
                if !(to_side1.is_finite() || to_side2.is_finite()) {
                    clearance.push(pair.gap_side1.min(pair.gap_side2));
                    graze.push((f64::NAN, PairImpact::rigid(q, 0)));
                } else if to_side1 <= to_side2 {
                    clearance.push(to_side1);
                    graze.push((ext[q].argmax / cycle, PairImpact::rigid(q, 1)));
                } else {
                    clearance.push(to_side2);
                    graze.push((ext[q].argmin / cycle, PairImpact::rigid(q, -1)));
                }
            }
        }
        (clearance, graze)
    }

    /// `s_j ṙ⁻_j` of each impact, `ṙ` its pair's relative velocity.
    fn approach(&self, eval: &CycleEvaluation<Dyn>) -> Vec<f64> {
        let dofs = self.model.dofs();
        let pairs = self.model.pairs();
        eval.before_impacts()
            .iter()
            .zip(self.sequence.impacts())
            .map(|(z, i)| f64::from(i.side) * pairs[i.pair].direction.dot(&z.rows(dofs, dofs)))
            .collect()
    }
}

impl BranchModel for ModelBranch<'_> {
    type Label = ImpactSequence;
    type Evaluation = CycleEvaluation<Dyn>;

    fn label(&self) -> &ImpactSequence {
        &self.sequence
    }

    fn relabel(&self, label: ImpactSequence) -> Self {
        // Switching only inserts impacts of the model's own pairs, or repeats the sequence.
        Self::new(self.model, label).unwrap_or_else(|_| unreachable!("a pair of the model"))
    }

    fn pairs(&self) -> usize {
        self.model.pairs().len()
    }

    fn mirrored(&self) -> bool {
        self.model
            .pairs()
            .iter()
            .all(|p| p.gap_side1 == p.gap_side2)
    }

    fn evaluate(&self, x: &[f64], with_jacobian: bool) -> Option<CycleEvaluation<Dyn>> {
        let omega = x[x.len() - 1];
        self.cycles
            .evaluate(x, self.model.augmented_matrix(omega), with_jacobian)
    }

    fn evaluate_state(&self, x: &[f64]) -> Option<CycleEvaluation<Dyn>> {
        let omega = x[x.len() - 1];
        self.cycles
            .evaluate_state(x, self.model.augmented_matrix(omega))
    }

    fn with_jacobian(&self, x: &[f64], e: CycleEvaluation<Dyn>) -> Option<CycleEvaluation<Dyn>> {
        let omega = x[x.len() - 1];
        self.cycles
            .with_jacobian(x, self.model.augmented_matrix(omega), e)
    }

    fn residual(e: &CycleEvaluation<Dyn>) -> &DVector<f64> {
        &e.residual
    }

    fn jacobian(e: &CycleEvaluation<Dyn>) -> &DMatrix<f64> {
        &e.jacobian
    }

    fn scale(&self, e: &CycleEvaluation<Dyn>) -> f64 {
        self.cycles.scale(e)
    }

    fn conditioning(&self, _x: &[f64], e: &CycleEvaluation<Dyn>) -> f64 {
        self.cycles.conditioning(e)
    }

    fn verdicts(&self, x: &[f64], eval: &CycleEvaluation<Dyn>) -> Verdicts {
        let (clearance, graze) = self.clearances(x, eval);
        let approach = self.approach(eval);
        let cells = self.model.pairs().len();
        let Some(orbit) = self.orbit(x) else {
            let nan = f64::NAN;
            return Verdicts {
                outer_amplitude: nan,
                cell_outer_amplitudes: vec![nan; cells],
                amplitudes: vec![nan; self.model.dofs()],
                transmittance_db: nan,
                stable: false,
                viable: false,
                floquet_multipliers: vec![Complex::new(nan, nan); 2 * self.model.dofs()],
                tests: Tests {
                    fold: nan,
                    branch: nan,
                    doubling: nan,
                    torus: nan,
                    clearance,
                    graze,
                    approach,
                },
            };
        };
        let size = orbit.monodromy.nrows();
        let identity = DMatrix::<f64>::identity(size, size);
        let tests = Tests {
            fold: f64::NAN,
            branch: (&orbit.monodromy - &identity).determinant(),
            doubling: (&orbit.monodromy + &identity).determinant(),
            torus: torus_test(&orbit.floquet_multipliers),
            clearance,
            graze,
            approach,
        };
        Verdicts {
            outer_amplitude: orbit.outer_amplitude,
            cell_outer_amplitudes: orbit.cell_outer_amplitudes,
            amplitudes: orbit.amplitudes,
            transmittance_db: orbit.transmittance_db,
            stable: orbit.stable,
            viable: orbit.viable,
            floquet_multipliers: orbit.floquet_multipliers,
            tests,
        }
    }

    fn monodromy(&self, x: &[f64], _eval: &CycleEvaluation<Dyn>) -> Option<DMatrix<f64>> {
        Some(self.orbit(x)?.monodromy)
    }

    fn test_value(&self, test: Test, x: &[f64], eval: &CycleEvaluation<Dyn>) -> Option<f64> {
        match test {
            Test::Fold => None,
            Test::Approach(j) => Some(self.approach(eval)[j]),
            Test::Clearance(c) => Some(self.clearances(x, eval).0[c]),
            Test::Branch | Test::Doubling | Test::Torus => {
                let tests = self.verdicts(x, eval).tests;
                let value = match test {
                    Test::Branch => tests.branch,
                    Test::Doubling => tests.doubling,
                    _ => tests.torus,
                };
                value.is_finite().then_some(value)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_models::{fundamental, two_masses_two_pairs, BaseHarmonic};

    /// Continuation's Jacobian in `X = (α, φ₂ … φ_m, ω)` on a model driven by a base motion
    /// with harmonics (orders 2 and 3, with phases and dashpots) against central differences
    /// of its residuals: step `1e-6`, truncation `O(1e-12)` and rounding `O(1e-10)` of the
    /// residuals' size, as the cycle equations' own check.
    #[test]
    fn the_jacobian_in_omega_with_harmonics_is_the_derivative() {
        let harmonic = |order, amplitude, phase| BaseHarmonic {
            order,
            amplitude,
            phase,
        };
        let model = two_masses_two_pairs(&[
            fundamental(0.8),
            harmonic(2, 0.3, 0.5),
            harmonic(3, 0.15, -1.2),
        ]);
        let sequence = ImpactSequence::parse("0+ 1+ 0-", 1).unwrap_or_else(|e| panic!("{e}"));
        let branch = ModelBranch::new(&model, sequence).unwrap_or_else(|e| panic!("{e}"));
        let x = [0.4, 0.3, 0.65, 1.1];
        let exact = branch
            .evaluate(&x, true)
            .unwrap_or_else(|| panic!("singular"))
            .jacobian;
        assert_eq!(exact.shape(), (3, 4));
        let step = 1e-6;
        let scale = exact.amax();
        for i in 0..4 {
            let at = |d: f64| {
                let mut y = x;
                y[i] += d;
                branch
                    .evaluate(&y, false)
                    .unwrap_or_else(|| panic!("singular"))
                    .residual
            };
            let quotient = (at(step) - at(-step)) / (2.0 * step);
            for j in 0..3 {
                assert!(
                    (quotient[j] - exact[(j, i)]).abs() <= 1e-7 * scale,
                    "∂r{j}/∂X{i}: {} vs {}",
                    quotient[j],
                    exact[(j, i)]
                );
            }
        }
    }
}
