//! The cycle equations of one branch as functions of `X = (α, φ₂ … φₙ, ω)`, on any model: the
//! model's side ([`BranchModel`]: its instance of [`CycleEquations`], its verdicts and test
//! functions) and what continuation derives from it ([`System`]: admissibility, test values,
//! the points of a branch).

use super::result::ContinuationPoint;
use super::test_functions::{Test, Tests};
use crate::cycle_equations::{CycleEquations, CycleEvaluation, MIN_FLIGHT};
use crate::orbit::wrap;
use crate::sequence::{ImpactSequence, PairImpact};
use crate::signature::Signature;
use nalgebra::allocator::Allocator;
use nalgebra::{Complex, DMatrix, DVector, DefaultAllocator, Dim, DimMin, OMatrix};
use std::fmt;

/// What a branch's orbits are labelled by: the unit's [`Signature`] or a model's
/// [`ImpactSequence`], both canonical rotations of a list of `(pair, side)` impacts.
pub(crate) trait Label: Clone + PartialEq + fmt::Display {
    /// The impacts in order (pair 0 throughout for a signature).
    fn impact_list(&self) -> Vec<PairImpact>;
    /// The canonical label of the cycle `impacts` over `period` forcing periods, if within
    /// the label's limits: those of the multi-start search, which bound the labels a switch
    /// creates (a doubling, an impact gained at a grazing).
    fn from_impacts(impacts: &[PairImpact], period: u32) -> Option<Self>;
    /// The canonical label of `impacts` over `period` under the caps of a simulated cycle, as
    /// long as any label a branch is followed on: the rotations and mirror images of a
    /// followed label (`branches::representations`), which have its length and
    /// period, are labels whatever that length.
    fn from_rotated(impacts: &[PairImpact], period: u32) -> Option<Self>;
    /// Forcing periods per cycle.
    fn period(&self) -> u32;
}

impl Label for Signature {
    fn impact_list(&self) -> Vec<PairImpact> {
        self.sides()
            .iter()
            .map(|&side| PairImpact::rigid(0, side))
            .collect()
    }

    fn from_impacts(impacts: &[PairImpact], period: u32) -> Option<Self> {
        Signature::from_sides(&unit_sides(impacts)?, period).ok()
    }

    fn from_rotated(impacts: &[PairImpact], period: u32) -> Option<Self> {
        Signature::from_cycle(&unit_sides(impacts)?, period).ok()
    }

    fn period(&self) -> u32 {
        Signature::period(self)
    }
}

impl Label for ImpactSequence {
    fn impact_list(&self) -> Vec<PairImpact> {
        self.impacts().to_vec()
    }

    fn from_impacts(impacts: &[PairImpact], period: u32) -> Option<Self> {
        ImpactSequence::new(impacts, period).ok()
    }

    fn from_rotated(impacts: &[PairImpact], period: u32) -> Option<Self> {
        ImpactSequence::from_cycle(impacts, period).ok()
    }

    fn period(&self) -> u32 {
        ImpactSequence::period(self)
    }
}

/// The sides of `impacts` when they are all the unit's (pair 0).
fn unit_sides(impacts: &[PairImpact]) -> Option<Vec<i8>> {
    impacts
        .iter()
        .map(|i| (i.pair == 0).then_some(i.side))
        .collect()
}

/// The label repeated over twice the periods, if within its limits.
pub(crate) fn doubled<L: Label>(label: &L) -> Option<L> {
    let mut impacts = label.impact_list();
    impacts.extend(label.impact_list());
    L::from_impacts(&impacts, 2 * label.period())
}

/// The label with `impact` inserted after impact `flight` (during that flight), and the
/// rotation `k` of the new impact list (with the new impact at position `flight + 1`) that is
/// canonical.
pub(crate) fn grazed<L: Label>(label: &L, flight: usize, impact: PairImpact) -> Option<(L, usize)> {
    let mut impacts = label.impact_list();
    impacts.insert(flight + 1, impact);
    let canonical = L::from_impacts(&impacts, label.period())?;
    let list = canonical.impact_list();
    let m = impacts.len();
    let k = (0..m).find(|&k| (0..m).all(|j| impacts[(j + k) % m] == list[j]))?;
    Some((canonical, k))
}

/// What the model says about a converged point: its amplitudes, verdicts and test functions
/// (the fold test, which needs the tangent, left at `NaN`).
#[derive(Debug, Clone)]
pub(crate) struct Verdicts {
    /// The last cell's outer amplitude (the unit's `X_o`).
    pub(crate) outer_amplitude: f64,
    /// Each cell's outer amplitude.
    pub(crate) cell_outer_amplitudes: Vec<f64>,
    /// Every coordinate's amplitude (a model's; empty on the unit).
    pub(crate) amplitudes: Vec<f64>,
    /// `20 log10(X_o / X_s)`.
    pub(crate) transmittance_db: f64,
    /// Every multiplier inside the unit circle.
    pub(crate) stable: bool,
    /// No excursion beyond a stop, every impact from inside.
    pub(crate) viable: bool,
    /// Eigenvalues of the monodromy matrix.
    pub(crate) floquet_multipliers: Vec<Complex<f64>>,
    /// The test functions.
    pub(crate) tests: Tests,
}

/// One model's side of the cycle equations of one label: evaluation in `X`, the verdicts at
/// a converged point and the test functions there.
pub(crate) trait BranchModel: Sized {
    /// How the branches of this model are labelled.
    type Label: Label;
    /// The cycle evaluated at one `X`.
    type Evaluation;
    /// The label of the orbits.
    fn label(&self) -> &Self::Label;
    /// The same model with the orbits of another label.
    fn relabel(&self, label: Self::Label) -> Self;
    /// Number of contact pairs of the model.
    fn pairs(&self) -> usize;
    /// Whether the mirror image `−u(t + T/2)` (sides swapped) of a motion is a motion: every
    /// pair's stops symmetric.
    fn mirrored(&self) -> bool;
    /// The residuals, with the exact Jacobian in `X` when `with_jacobian`; `None` when the
    /// periodicity solve is singular.
    fn evaluate(&self, x: &[f64], with_jacobian: bool) -> Option<Self::Evaluation>;
    /// The residuals with the exact Jacobian in the state unknowns `(α, φ₂ … φₙ)` only
    /// (`n × n`: [`Self::evaluate`]'s Jacobian without the `ω` column, bit for bit, and
    /// without the cost of that column); `None` when the periodicity solve is singular.
    fn evaluate_state(&self, x: &[f64]) -> Option<Self::Evaluation>;
    /// The evaluation `e` of the residuals at `x` (by [`Self::evaluate`] without the
    /// Jacobian) with the exact Jacobian in `X` added: what [`Self::evaluate`] with the
    /// Jacobian gives at `x`, bit for bit, without recomputing the residuals. `None` when the
    /// periodicity solve is singular.
    fn with_jacobian(&self, x: &[f64], e: Self::Evaluation) -> Option<Self::Evaluation>;
    /// The contact residuals of an evaluation.
    fn residual(e: &Self::Evaluation) -> &DVector<f64>;
    /// `∂R/∂X` of an evaluation (empty without derivatives).
    fn jacobian(e: &Self::Evaluation) -> &DMatrix<f64>;
    /// Size of the motion against which residuals are measured.
    fn scale(&self, e: &Self::Evaluation) -> f64;
    /// Conditioning of the periodicity solve of an evaluation (see
    /// [`CycleEquations::conditioning`]).
    fn conditioning(&self, x: &[f64], e: &Self::Evaluation) -> f64;
    /// Amplitudes, verdicts and test functions at a converged `X`.
    fn verdicts(&self, x: &[f64], e: &Self::Evaluation) -> Verdicts;
    /// One test function other than the fold's at a converged `X`, computing only what it
    /// needs.
    fn test_value(&self, test: Test, x: &[f64], e: &Self::Evaluation) -> Option<f64>;
    /// The monodromy matrix (saltations included) at `X` from an evaluation there; `None`
    /// when it cannot be assembled.
    fn monodromy(&self, x: &[f64], e: &Self::Evaluation) -> Option<DMatrix<f64>>;
}

/// The shared part of every [`BranchModel`]: the label's cycle equations in augmented
/// dimension `D` and `dÂ/dω`, evaluated at each `X` with the model's `Â(ω)`.
#[derive(Debug, Clone)]
pub(crate) struct Cycles<D: Dim>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    equations: CycleEquations<D>,
    rate: OMatrix<f64, D, D>,
    /// `2πp`: the cycle in forcing angle.
    angle: f64,
}

impl<D: DimMin<D, Output = D>> Cycles<D>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    /// The equations `equations` (at any frequency) of a cycle of `period` forcing periods,
    /// `rate` being `dÂ/dω`.
    pub(crate) fn new(equations: CycleEquations<D>, rate: OMatrix<f64, D, D>, period: u32) -> Self {
        Self {
            equations,
            rate,
            angle: std::f64::consts::TAU * f64::from(period),
        }
    }

    /// The same, the modal flights remembered
    /// ([`CycleEquations::with_remembered_flights`]).
    pub(crate) fn with_remembered_flights(self) -> Self {
        Self {
            equations: self.equations.with_remembered_flights(),
            ..self
        }
    }

    /// The equations at `omega`, `augmented` being `Â(ω)`.
    pub(crate) fn at(&self, omega: f64, augmented: OMatrix<f64, D, D>) -> CycleEquations<D> {
        self.equations
            .at_frequency(omega, augmented, self.angle / omega)
    }

    /// The cycle at `X` (`augmented` being `Â(ω)`), with the Jacobian in `X` when
    /// `with_jacobian`.
    pub(crate) fn evaluate(
        &self,
        x: &[f64],
        augmented: OMatrix<f64, D, D>,
        with_jacobian: bool,
    ) -> Option<CycleEvaluation<D>> {
        let n = x.len() - 1;
        let equations = self.at(x[n], augmented);
        if with_jacobian {
            equations.evaluate_in_omega(&x[..n], &self.rate)
        } else {
            equations.evaluate_with(&x[..n], false)
        }
    }

    /// The evaluation `e` of the residuals at `X` (by [`Self::evaluate`] without the
    /// Jacobian, `augmented` being `Â(ω)`) with the Jacobian in `X` added: what
    /// [`Self::evaluate`] with the Jacobian gives, bit for bit, without recomputing the
    /// flights.
    pub(crate) fn with_jacobian(
        &self,
        x: &[f64],
        augmented: OMatrix<f64, D, D>,
        e: CycleEvaluation<D>,
    ) -> Option<CycleEvaluation<D>> {
        let n = x.len() - 1;
        self.at(x[n], augmented)
            .with_omega_jacobian(&x[..n], e, &self.rate)
    }

    /// The cycle at `X` (`augmented` being `Â(ω)`) with the Jacobian in the state unknowns
    /// `x` only (no `ω` column).
    pub(crate) fn evaluate_state(
        &self,
        x: &[f64],
        augmented: OMatrix<f64, D, D>,
    ) -> Option<CycleEvaluation<D>> {
        let n = x.len() - 1;
        self.at(x[n], augmented).evaluate_with(&x[..n], true)
    }

    /// [`CycleEquations::conditioning`] of an evaluation.
    pub(crate) fn conditioning(&self, e: &CycleEvaluation<D>) -> f64 {
        self.equations.conditioning(&e.pre)
    }

    /// [`CycleEquations::scale`] of an evaluation.
    pub(crate) fn scale(&self, e: &CycleEvaluation<D>) -> f64 {
        self.equations.scale(&e.z1)
    }

    /// `2πp`.
    pub(crate) fn angle(&self) -> f64 {
        self.angle
    }
}

/// Start and end of flight `f` of `X` (`n` impacts) as cycle fractions.
pub(crate) fn flight_span(x: &[f64], n: usize, f: usize) -> (f64, f64) {
    let start = if f == 0 { 0.0 } else { x[f] };
    let end = if f + 1 < n { x[f + 1] } else { 1.0 };
    (start, end)
}

/// A point on a branch with everything derived from it.
#[derive(Debug, Clone)]
pub(crate) struct Node {
    pub(crate) x: Vec<f64>,
    pub(crate) tangent: Vec<f64>,
    /// `R_X` at `x`.
    pub(crate) jacobian: DMatrix<f64>,
    pub(crate) point: ContinuationPoint,
    pub(crate) tests: Tests,
}

/// The cycle equations of one branch as functions of `X = (α, φ₂ … φₙ, ω)`.
pub(crate) struct System<M> {
    pub(crate) model: M,
}

impl<M: BranchModel> System<M> {
    /// The system of `model`.
    pub(crate) fn new(model: M) -> Self {
        Self { model }
    }

    /// The label of the branch.
    pub(crate) fn label(&self) -> &M::Label {
        self.model.label()
    }

    /// Number of impacts, also the number of residuals.
    pub(crate) fn n(&self) -> usize {
        self.model.label().impact_list().len()
    }

    /// Start and end of flight `f` as cycle fractions.
    pub(crate) fn flight_span(&self, x: &[f64], f: usize) -> (f64, f64) {
        flight_span(x, self.n(), f)
    }

    /// Shortest flight of `X`, as a fraction of the cycle.
    pub(crate) fn shortest_flight(&self, x: &[f64]) -> f64 {
        (0..self.n())
            .map(|f| {
                let (a, b) = self.flight_span(x, f);
                b - a
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether `X` is finite, ordered with flights above [`MIN_FLIGHT`] and `ω > 0`.
    pub(crate) fn admissible(&self, x: &[f64]) -> bool {
        x.iter().all(|v| v.is_finite()) && x[self.n()] > 0.0 && self.shortest_flight(x) > MIN_FLIGHT
    }

    /// Residuals and the exact Jacobian in `X`. `None` when the periodicity solve is singular.
    pub(crate) fn evaluate(&self, x: &[f64]) -> Option<M::Evaluation> {
        self.model.evaluate(x, true)
    }

    /// The residual evaluation `eval` at `x` ([`Self::evaluate_residual`]) completed with
    /// the Jacobian: [`Self::evaluate`] at `x`, bit for bit, the flights reused.
    pub(crate) fn complete(&self, x: &[f64], eval: M::Evaluation) -> Option<M::Evaluation> {
        self.model.with_jacobian(x, eval)
    }

    /// Residuals only (an empty Jacobian): one exponential per flight, no derivatives.
    pub(crate) fn evaluate_residual(&self, x: &[f64]) -> Option<M::Evaluation> {
        self.model.evaluate(x, false)
    }

    /// One test function at a converged `X` (`eval` with or without Jacobian; the fold's
    /// needs it), computing only what it needs. `None` when the fold test's tangent cannot be
    /// formed or `eval` lacks the Jacobian it needs.
    pub(crate) fn test_value(
        &self,
        test: Test,
        x: &[f64],
        eval: &M::Evaluation,
        previous: &[f64],
    ) -> Option<f64> {
        match test {
            Test::Fold => {
                let jacobian = M::jacobian(eval);
                if jacobian.nrows() != self.n() {
                    return None;
                }
                Some(self.tangent(jacobian, previous)?[self.n()])
            }
            _ => self.model.test_value(test, x, eval),
        }
    }

    /// Orbit data and test functions at a converged `X`.
    pub(crate) fn describe(
        &self,
        x: &[f64],
        eval: &M::Evaluation,
        tangent: &[f64],
        branch: usize,
    ) -> Node {
        let n = self.n();
        let mut verdicts = self.model.verdicts(x, eval);
        verdicts.tests.fold = tangent[n];
        let mut impact_phases = vec![0.0; n];
        impact_phases[1..n].copy_from_slice(&x[1..n]);
        let point = ContinuationPoint {
            branch,
            omega: x[n],
            alpha: wrap(x[0]),
            impact_phases,
            outer_amplitude: verdicts.outer_amplitude,
            cell_outer_amplitudes: verdicts.cell_outer_amplitudes,
            amplitudes: verdicts.amplitudes,
            transmittance_db: verdicts.transmittance_db,
            stable: verdicts.stable,
            viable: verdicts.viable,
            floquet_multipliers: verdicts.floquet_multipliers,
            domega_ds: tangent[n],
            residual: M::residual(eval).amax(),
        };
        Node {
            x: x.to_vec(),
            tangent: tangent.to_vec(),
            jacobian: M::jacobian(eval).clone(),
            point,
            tests: verdicts.tests,
        }
    }
}
