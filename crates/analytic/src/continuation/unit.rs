//! The unit's side of continuation: its cycle equations on stack matrices (augmented
//! dimension 6), and its verdicts and test functions from the fixed-size forced flow.

use super::system::{flight_span, BranchModel, Cycles, Verdicts};
use super::test_functions::{torus_test, Test, Tests};
use crate::cycle_equations::{CycleEquations, CycleEvaluation, ImpactCondition};
use crate::flow::{join, Augmented, ForcedFlow};
use crate::linear::transmittance_db;
use crate::orbit::{
    eigenvalues, impact, relative_displacement, saltation, STABILITY_MARGIN, VIABILITY_TOLERANCE,
};
use crate::sequence::PairImpact;
use crate::signature::Signature;
use crate::unit::{Stops, Unit};
use nalgebra::{Complex, DMatrix, DVector, Matrix2, Matrix4, Matrix6, Vector2, Vector4, U6};

/// The cycle equations of one signature of the unit.
pub(crate) struct UnitBranch<'a> {
    unit: &'a Unit,
    stops: Stops,
    signature: Signature,
    g: Matrix2<f64>,
    gap: f64,
    cycles: Cycles<U6>,
}

impl<'a> UnitBranch<'a> {
    /// The orbits of `signature` of `unit` with `stops`.
    pub(crate) fn new(unit: &'a Unit, stops: &Stops, signature: Signature) -> Self {
        let g = stops.impact_map(unit);
        let mut g_hat = Matrix6::identity();
        g_hat.fixed_view_mut::<2, 2>(2, 2).copy_from(&g);
        let h = join(&relative_displacement(), &Vector2::zeros());
        let impacts = signature
            .sides()
            .iter()
            .map(|&s| ImpactCondition {
                impact_map: g_hat,
                contact: h,
                stop: f64::from(s) * stops.gap,
            })
            .collect();
        // `dÂ/dω`: the base's damper force `c_o u̇_g` and the phase rotation.
        let co = unit.damping.map_or(0.0, |d| d.outer);
        let mut rate = Matrix6::zeros();
        rate[(2, 5)] = -co * unit.base_amplitude / unit.outer_mass;
        rate[(4, 5)] = -1.0;
        rate[(5, 4)] = 1.0;
        let equations = CycleEquations::new(
            1.0,
            unit.augmented_matrix(1.0),
            impacts,
            signature.symmetries(),
            std::f64::consts::TAU * f64::from(signature.period()),
        )
        .with_modal_flow();
        Self {
            unit,
            stops: *stops,
            g,
            gap: stops.gap,
            cycles: Cycles::new(equations, rate, signature.period()),
            signature,
        }
    }

    /// The same, the modal flights remembered across evaluations (see
    /// [`crate::CycleEquations::with_remembered_flights`]): for a boundary curve, whose
    /// difference steps share most flights.
    pub(crate) fn with_remembered_flights(self) -> Self {
        Self {
            cycles: self.cycles.with_remembered_flights(),
            ..self
        }
    }

    /// The mechanical state just before each impact and the forcing phase there.
    fn impact_states(&self, eval: &CycleEvaluation<U6>) -> (Vec<Vector4<f64>>, Vec<Vector2<f64>>) {
        let before: Vec<Augmented> = eval.before_impacts();
        let x_before = before.iter().map(|z| z.fixed_rows::<4>(0).into()).collect();
        let p_at = (0..before.len())
            .map(|j| {
                if j == 0 {
                    eval.z1.fixed_rows::<2>(4).into()
                } else {
                    before[j].fixed_rows::<2>(4).into()
                }
            })
            .collect();
        (x_before, p_at)
    }

    /// The monodromy matrix from just after the first impact: flights and saltations.
    fn monodromy(
        &self,
        flow: &ForcedFlow,
        eval: &CycleEvaluation<U6>,
        x_before: &[Vector4<f64>],
        p_at: &[Vector2<f64>],
    ) -> Matrix4<f64> {
        let n = x_before.len();
        let mut monodromy = Matrix4::identity();
        for f in 0..n {
            let next = (f + 1) % n;
            let hom = eval.flights[f].fixed_view::<4, 4>(0, 0).into_owned();
            let s = saltation(flow, &self.g, &x_before[next], &p_at[next]);
            monodromy = s * hom * monodromy;
        }
        monodromy
    }

    /// The monodromy matrix (saltations included) of the cycle at `X` from its evaluation
    /// `eval` (with or without Jacobian).
    pub(crate) fn monodromy_at(&self, x: &[f64], eval: &CycleEvaluation<U6>) -> Matrix4<f64> {
        let flow = ForcedFlow::new(self.unit, x[x.len() - 1]);
        let (x_before, p_at) = self.impact_states(eval);
        self.monodromy(&flow, eval, &x_before, &p_at)
    }

    /// `s_j ṙ⁻_j` of each impact.
    fn approach(&self, x_before: &[Vector4<f64>]) -> Vec<f64> {
        self.signature
            .sides()
            .iter()
            .zip(x_before)
            .map(|(&s, x)| f64::from(s) * (x[3] - x[2]))
            .collect()
    }
}

impl BranchModel for UnitBranch<'_> {
    type Label = Signature;
    type Evaluation = CycleEvaluation<U6>;

    fn label(&self) -> &Signature {
        &self.signature
    }

    fn relabel(&self, label: Signature) -> Self {
        Self::new(self.unit, &self.stops, label)
    }

    fn pairs(&self) -> usize {
        1
    }

    fn mirrored(&self) -> bool {
        true
    }

    fn evaluate(&self, x: &[f64], with_jacobian: bool) -> Option<CycleEvaluation<U6>> {
        let omega = x[x.len() - 1];
        self.cycles
            .evaluate(x, self.unit.augmented_matrix(omega), with_jacobian)
    }

    fn evaluate_state(&self, x: &[f64]) -> Option<CycleEvaluation<U6>> {
        let omega = x[x.len() - 1];
        self.cycles
            .evaluate_state(x, self.unit.augmented_matrix(omega))
    }

    fn with_jacobian(&self, x: &[f64], e: CycleEvaluation<U6>) -> Option<CycleEvaluation<U6>> {
        let omega = x[x.len() - 1];
        self.cycles
            .with_jacobian(x, self.unit.augmented_matrix(omega), e)
    }

    fn residual(e: &CycleEvaluation<U6>) -> &DVector<f64> {
        &e.residual
    }

    fn jacobian(e: &CycleEvaluation<U6>) -> &DMatrix<f64> {
        &e.jacobian
    }

    fn scale(&self, e: &CycleEvaluation<U6>) -> f64 {
        self.cycles.scale(e)
    }

    fn conditioning(&self, _x: &[f64], e: &CycleEvaluation<U6>) -> f64 {
        self.cycles.conditioning(e)
    }

    fn verdicts(&self, x: &[f64], eval: &CycleEvaluation<U6>) -> Verdicts {
        let n = x.len() - 1;
        let omega = x[n];
        let flow = ForcedFlow::new(self.unit, omega);
        let (x_before, p_at) = self.impact_states(eval);
        let approach = self.approach(&x_before);
        let r_fn = join(&relative_displacement(), &Vector2::zeros());
        let uo_fn = Augmented::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let cycle = self.cycles.angle() / omega;
        let mut outer_amplitude: f64 = 0.0;
        let mut clearance = Vec::with_capacity(n);
        let mut graze = Vec::with_capacity(n);
        for f in 0..n {
            let (s, e) = flight_span(x, n, f);
            let start = join(&impact(&self.g, &x_before[f]), &p_at[f]);
            let ext = flow.mixed_extrema(&start, (e - s) * cycle, &[r_fn, uo_fn], &[true, false]);
            outer_amplitude = outer_amplitude.max(ext[1].max.abs()).max(ext[1].min.abs());
            let (high, low) = (ext[0].max, -ext[0].min);
            if high.is_finite() || low.is_finite() {
                let (value, time, side) = if high >= low {
                    (high, ext[0].argmax, 1)
                } else {
                    (low, ext[0].argmin, -1)
                };
                clearance.push(self.gap - value);
                graze.push((time / cycle, PairImpact::rigid(0, side)));
            } else {
                clearance.push(self.gap);
                graze.push((f64::NAN, PairImpact::rigid(0, 0)));
            }
        }
        let tol = VIABILITY_TOLERANCE * self.gap;
        let viable = approach.iter().all(|&v| v > 0.0) && clearance.iter().all(|&c| c >= -tol);
        let monodromy = self.monodromy(&flow, eval, &x_before, &p_at);
        let floquet_multipliers: Vec<Complex<f64>> = eigenvalues(&monodromy)
            .map(|e| e.to_vec())
            .unwrap_or_else(|| vec![Complex::new(f64::NAN, f64::NAN); 4]);
        let stable = floquet_multipliers
            .iter()
            .all(|m| m.norm() < 1.0 - STABILITY_MARGIN);
        let tests = Tests {
            fold: f64::NAN,
            branch: (monodromy - Matrix4::identity()).determinant(),
            doubling: (monodromy + Matrix4::identity()).determinant(),
            torus: torus_test(&floquet_multipliers),
            clearance,
            graze,
            approach,
        };
        Verdicts {
            outer_amplitude,
            cell_outer_amplitudes: vec![outer_amplitude],
            amplitudes: Vec::new(),
            transmittance_db: transmittance_db(outer_amplitude, self.unit.base_amplitude),
            stable,
            viable,
            floquet_multipliers,
            tests,
        }
    }

    fn monodromy(&self, x: &[f64], eval: &CycleEvaluation<U6>) -> Option<DMatrix<f64>> {
        let m = self.monodromy_at(x, eval);
        Some(DMatrix::from_column_slice(4, 4, m.as_slice()))
    }

    fn test_value(&self, test: Test, x: &[f64], eval: &CycleEvaluation<U6>) -> Option<f64> {
        let n = x.len() - 1;
        let omega = x[n];
        match test {
            Test::Fold => None,
            Test::Branch | Test::Doubling | Test::Torus => {
                let flow = ForcedFlow::new(self.unit, omega);
                let (x_before, p_at) = self.impact_states(eval);
                let m = self.monodromy(&flow, eval, &x_before, &p_at);
                Some(match test {
                    Test::Branch => (m - Matrix4::identity()).determinant(),
                    Test::Doubling => (m + Matrix4::identity()).determinant(),
                    _ => torus_test(&eigenvalues(&m)?),
                })
            }
            Test::Clearance(f) => {
                let flow = ForcedFlow::new(self.unit, omega);
                let (x_before, p_at) = self.impact_states(eval);
                let (s, e) = flight_span(x, n, f);
                let start = join(&impact(&self.g, &x_before[f]), &p_at[f]);
                let r_fn = join(&relative_displacement(), &Vector2::zeros());
                let duration = (e - s) * self.cycles.angle() / omega;
                let ext = flow.critical_extrema(&start, duration, &[r_fn])[0];
                let value = ext.max.max(-ext.min);
                Some(if value.is_finite() {
                    self.gap - value
                } else {
                    self.gap
                })
            }
            Test::Approach(j) => {
                let (x_before, _) = self.impact_states(eval);
                Some(self.approach(&x_before)[j])
            }
        }
    }
}
