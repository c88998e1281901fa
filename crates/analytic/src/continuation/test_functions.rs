//! The test functions along a branch, whose sign changes between consecutive points are the
//! events: fold, branch point, period doubling and Neimark–Sacker from the tangent and the
//! monodromy matrix, grazing per flight and contact pair, vanishing impact per impact.

use super::result::EventKind;
use crate::sequence::PairImpact;
use nalgebra::Complex;

/// Test functions at one point.
#[derive(Debug, Clone)]
pub(crate) struct Tests {
    pub(crate) fold: f64,
    pub(crate) branch: f64,
    pub(crate) doubling: f64,
    pub(crate) torus: f64,
    /// Per flight `f` and contact pair `q` (index `f · pairs + q`): the distance to the
    /// nearer stop of that pair's coordinate at its interior critical points over the flight
    /// (the smaller gap if it has none).
    pub(crate) clearance: Vec<f64>,
    /// Per flight and pair (as `clearance`): time (from the flight's start, in cycle
    /// fractions) of that critical point, and the impact it would be (pair and side).
    pub(crate) graze: Vec<(f64, PairImpact)>,
    /// Per impact: `s_j ṙ⁻_j`.
    pub(crate) approach: Vec<f64>,
}

impl Tests {
    /// The tests at a switch point, where they sit at zero by construction (a multiplier at
    /// ±1, a zero-velocity impact): no sign change is read from there. The graze data stay.
    pub(crate) fn unread(&self) -> Self {
        Self {
            fold: f64::NAN,
            branch: f64::NAN,
            doubling: f64::NAN,
            torus: f64::NAN,
            clearance: vec![f64::NAN; self.clearance.len()],
            graze: self.graze.clone(),
            approach: vec![f64::NAN; self.approach.len()],
        }
    }
}

/// The Neimark–Sacker test `Π_{i<j} (μ_i μ_j − 1)`: real (conjugates pair up); a conjugate
/// pair contributes `|μ|² − 1`, which vanishes when the pair crosses the unit circle.
pub(crate) fn torus_test(multipliers: &[Complex<f64>]) -> f64 {
    let mut product = Complex::new(1.0, 0.0);
    for i in 0..multipliers.len() {
        for j in i + 1..multipliers.len() {
            product *= multipliers[i] * multipliers[j] - 1.0;
        }
    }
    product.re
}

/// Which test function.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Test {
    Fold,
    Branch,
    Doubling,
    Torus,
    Clearance(usize),
    Approach(usize),
}

impl Test {
    /// The test function's value at a point. The branch-point test is `det(M − I)` over
    /// `dω/ds`: both change sign at a fold (a multiplier through 1 where the branch turns),
    /// their ratio does not (it is `det([R_X; tᵀ])` up to a factor that does not vanish), so
    /// a fold and a branch point within one step are both seen.
    pub(crate) fn value(self, t: &Tests) -> f64 {
        match self {
            Test::Fold => t.fold,
            Test::Branch => t.branch / t.fold,
            Test::Doubling => t.doubling,
            Test::Torus => t.torus,
            Test::Clearance(f) => t.clearance[f],
            Test::Approach(j) => t.approach[j],
        }
    }

    /// The kind of event at a zero of the test.
    pub(crate) fn kind(self) -> EventKind {
        match self {
            Test::Fold => EventKind::Fold,
            Test::Branch => EventKind::BranchPoint,
            Test::Doubling => EventKind::PeriodDoubling,
            Test::Torus => EventKind::NeimarkSacker,
            Test::Clearance(_) => EventKind::Grazing,
            Test::Approach(_) => EventKind::VanishingImpact,
        }
    }
}

/// Every test function of points with the tests `t`: per flight its clearances (one per
/// contact pair), then its first impact's approach.
pub(crate) fn all_tests(t: &Tests) -> Vec<Test> {
    let mut tests = vec![Test::Fold, Test::Branch, Test::Doubling, Test::Torus];
    let n = t.approach.len();
    let pairs = t.clearance.len() / n.max(1);
    for f in 0..n {
        tests.extend((f * pairs..(f + 1) * pairs).map(Test::Clearance));
        tests.push(Test::Approach(f));
    }
    tests
}

/// Every test whose function changes sign between `a` and `b`.
pub(crate) fn sign_changes(a: &Tests, b: &Tests) -> Vec<Test> {
    let mut tests = all_tests(a);
    tests.retain(|t| t.value(a) * t.value(b) < 0.0);
    tests
}
