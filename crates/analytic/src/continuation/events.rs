//! Events: every test function that changed sign over a step is located on its own, by the
//! Illinois variant of regula falsi on the chord between the two points (each trial point
//! corrected onto the branch), and accepted or not as an event of its kind.

use super::branches::distance;
use super::corrector::Constraint;
use super::result::Event;
use super::system::{doubled, grazed, BranchModel, Label, Node, System};
use super::test_functions::{all_tests, sign_changes, Test, Tests};
use nalgebra::DMatrix;

/// An event is located when the chord fraction `θ ∈ [0, 1]` between two points is bracketed
/// to this width: steps are at most `max_step` long in `(x, ω)`, so the event's `ω` is pinned
/// to well under `1e-12` for any `max_step ≤ 1`, four orders inside the required `1e-8`.
pub(crate) const LOCATION_FRACTION: f64 = 1e-13;

/// Cap on the Illinois iterations of one event location: Illinois converges superlinearly,
/// so a location that needs more is stalling on a discontinuity.
pub(crate) const LOCATION_ITERATIONS: usize = 100;

/// A sign change of a test function is an event only if its value at the located point is
/// below this fraction of the larger of its values at the two points around it. A continuous
/// test function is zero there to rounding; one that jumped (a critical point of `r` born
/// away from the stops, a multiplier test through a pole as `ṙ⁻ → 0`) is not.
pub(crate) const EVENT_ACCEPTANCE: f64 = 1e-3;

/// A sign change of a test function over a step is a pole, not a zero, once the test at both
/// ends of a bracket `w` wide (as a chord fraction, `w ≥` [`POLE_WIDTH`]) exceeds
/// `POLE_GROWTH · w` times its larger size at the step's two points: near a zero of a smooth
/// test the values at the bracket's ends are of the order of `w` times that size, at a pole
/// they grow as `1/w`. The location stops there without an event. Such sign changes are the
/// multiplier tests through their pole as an impact's velocity `ṙ⁻` vanishes (the saltation
/// matrix grows as `1/ṙ⁻`). On the study's continuation of the paper unit (114 seeds, 2288
/// locations) 296 locations are poles, each past this bound at a width of `4e-5`–`7e-4`, and
/// stop here after 19–30 iterations instead of 60–100 (14 % of the instructions of the
/// continuation from the three `+-` seeds, whose branches are the same either way). Run on,
/// 11 of them would end on a trial point where the monodromy matrix, dominated by the
/// saltation's `1/ṙ⁻` term, has lost rank in floating point (the test exactly 0), and be
/// listed as period doublings or a branch point at the `ω` of a vanishing impact (to
/// `1e-14`); no event of any other kind depends on this bound.
pub(crate) const POLE_GROWTH: f64 = 1e6;

/// The narrowest bracket on which [`POLE_GROWTH`] is tested: far above the width (about
/// `1e-9`) at which a smooth test reaches the noise of its trial points (a fold's `dω/ds`
/// scatters by about `1e-6` of its size there), so that noise is never read as a pole.
pub(crate) const POLE_WIDTH: f64 = 1e-6;

/// A located zero of the branch-point test is a branch point when the smallest singular value
/// of `R_X` there is below this fraction of its largest (it vanishes at a branch point, where
/// `R_X` loses rank; at a regular point it is of the order of the largest). Measured on the
/// paper unit: 1.7e-10 at the pitchfork at 2.1925686 rad/s located on the asymmetric pair,
/// 0.026 at a sign change of the test through its pole at a vanishing impact (2.19307 rad/s).
pub(crate) const BRANCH_RANK_DEFICIENCY: f64 = 1e-5;

/// The unit vector from `a` to `b` (`None` when they coincide).
fn unit_chord(a: &Node, b: &Node) -> Option<Vec<f64>> {
    let chord: Vec<f64> = a.x.iter().zip(&b.x).map(|(p, q)| q - p).collect();
    let norm = chord.iter().map(|v| v * v).sum::<f64>().sqrt();
    (norm > 0.0 && norm.is_finite()).then(|| chord.iter().map(|v| v / norm).collect())
}

/// `σ_min / σ_max` of `R_X` (`n × (n + 1)`); 1 when it cannot be formed.
fn rank_deficiency(jacobian: &DMatrix<f64>) -> f64 {
    let sv = jacobian.singular_values();
    let max = sv.iter().copied().fold(0.0, f64::max);
    let min = sv.iter().copied().fold(f64::INFINITY, f64::min);
    if max > 0.0 && min.is_finite() {
        min / max
    } else {
        1.0
    }
}

/// A complex pair of multipliers is on the unit circle at a Neimark–Sacker event when its
/// modulus is within this of 1; a located zero of the pair-product test without such a pair
/// is a neutral saddle (real `μ, 1/μ`), not an event. The multipliers come from a 4×4 Schur
/// form carrying about `1e-13` of rounding; located to `1e-13` in the chord fraction, the
/// modulus is pinned far tighter than this.
pub(crate) const TORUS_TOLERANCE: f64 = 1e-6;

/// Imaginary part below which a multiplier counts as real.
const REAL_MULTIPLIER: f64 = 1e-9;

/// A graze is interior when its critical point lies at least this far (as a fraction of the
/// cycle) from both ends of its flight. As an impact's velocity `ṙ⁻` passes through zero, a
/// critical point of `r` leaves the flight through that end with `r` at the stop: the
/// clearance crosses zero at the vanishing impact too, within the location tolerance of it.
/// Those crossings are the vanishing impact, not a graze. Far above the location error of an
/// event's time, far below the flights of the orbits followed.
pub(crate) const GRAZE_INTERIOR: f64 = 1e-6;

impl<M: BranchModel> System<M> {
    /// The point of the branch at chord fraction `theta` between its points `a` and `b`
    /// (corrected within the hyperplane normal to the chord), described as a point of the
    /// branch of `a` with its tangent oriented as `a`'s.
    pub(crate) fn node_at(&self, a: &Node, b: &Node, theta: f64) -> Option<Node> {
        let n = self.n();
        let chord: Vec<f64> = (0..=n).map(|k| b.x[k] - a.x[k]).collect();
        let through: Vec<f64> = (0..=n).map(|k| a.x[k] + theta * chord[k]).collect();
        let plane = Constraint::Plane {
            normal: &chord,
            through: &through,
        };
        let (x, eval, _) = self.converge(&through, &plane, &a.jacobian)?;
        let tangent = self.tangent(M::jacobian(&eval), &a.tangent)?;
        Some(self.describe(&x, &eval, &tangent, a.point.branch))
    }
}

/// A located event with the branch point it sits at.
pub(crate) struct Found<L> {
    pub(crate) event: Event<L>,
    pub(crate) node: Node,
}

/// A pair of zeros of one test function within the step from `a` to `b`, which the signs at
/// `a` and `b` do not show: the quadratic in arclength through the function's values at
/// `before`, `a` and `b` has its extremum inside the step, of the other sign. Returns the
/// chord fraction of that extremum (for the first test where it happens).
fn hidden_pair(before: &Node, a: &Node, b: &Node) -> Option<f64> {
    let s0 = -distance(&before.x, &a.x);
    let s2 = distance(&a.x, &b.x);
    if !(s0 < 0.0 && s2 > 0.0) {
        return None;
    }
    all_tests(&a.tests).into_iter().find_map(|test| {
        let v0 = test.value(&before.tests);
        let v1 = test.value(&a.tests);
        let v2 = test.value(&b.tests);
        if !(v0.is_finite() && v1.is_finite() && v2.is_finite()) || v1 * v2 <= 0.0 {
            return None;
        }
        // Newton's form: q(s) = v0 + d01 (s − s0) + c2 (s − s0) s.
        let d01 = (v1 - v0) / -s0;
        let d12 = (v2 - v1) / s2;
        let c2 = (d12 - d01) / (s2 - s0);
        if c2 == 0.0 || !c2.is_finite() {
            return None;
        }
        let vertex = 0.5 * (s0 - d01 / c2);
        let q = v0 + d01 * (vertex - s0) + c2 * (vertex - s0) * vertex;
        (vertex > 0.0 && vertex < s2 && q * v1 < 0.0).then_some(vertex / s2)
    })
}

/// The events between two consecutive points `a`, `b` (`before`: the point before `a`): the
/// zero of every test function that changed sign over the step, each located on its own, in
/// their order along the step. Where a test function may have two zeros within the step
/// ([`hidden_pair`]), the step is split at the point between them and each half searched.
pub(crate) fn detect<M: BranchModel>(
    system: &System<M>,
    a: &Node,
    b: &Node,
    before: Option<&Node>,
) -> Vec<Found<M::Label>> {
    let split = before
        .and_then(|p| hidden_pair(p, a, b))
        .and_then(|theta| system.node_at(a, b, theta));
    match split {
        Some(middle) => {
            let mut found = detect_step(system, a, &middle);
            found.extend(detect_step(system, &middle, b));
            found
        }
        None => detect_step(system, a, b),
    }
}

/// [`detect`] over one step, without splitting it.
fn detect_step<M: BranchModel>(system: &System<M>, a: &Node, b: &Node) -> Vec<Found<M::Label>> {
    let mut found: Vec<(f64, Found<M::Label>)> = sign_changes(&a.tests, &b.tests)
        .into_iter()
        .filter_map(|test| {
            let (theta, node) = match test {
                Test::Branch => locate_branch_point(system, a, b)?,
                _ => locate(system, a, b, test)?,
            };
            Some((theta, event_at(system, a, b, test, node)?))
        })
        .collect();
    found.sort_by(|p, q| p.0.total_cmp(&q.0));
    found.into_iter().map(|(_, f)| f).collect()
}

/// The event of `test` at its located zero `node` between `a` and `b`, unless the zero is
/// not an event (a jump of the test function, a neutral saddle, a graze at a flight's end).
fn event_at<M: BranchModel>(
    system: &System<M>,
    a: &Node,
    b: &Node,
    test: Test,
    mut node: Node,
) -> Option<Found<M::Label>> {
    let n = system.n();
    if let Test::Branch = test {
        // At a branch point R_X has a two-dimensional null space and the bordered tangent
        // solve picks an arbitrary member of it: the branch's own direction there is the
        // chord between the two regular points around it.
        node.tangent = unit_chord(a, b)?;
        node.point.domega_ds = node.tangent[n];
    }
    // The branch test is accepted on its determinant `det(M − I)`, zero at a branch point
    // (the tangent there, hence `dω/ds`, is arbitrary: on the asymmetric pair through a
    // pitchfork `dω/ds` vanishes too).
    let value = |t: &Tests| match test {
        Test::Branch => t.branch.abs(),
        _ => test.value(t).abs(),
    };
    let (va, vb, located) = (value(&a.tests), value(&b.tests), value(&node.tests));
    let accepted = match test {
        // A branch point is accepted where `R_X` has lost rank (located by the regular
        // defining system, or, where that does not converge, pinned by the bracket to about
        // `√ε`), which a jump of the test (a pole as an impact's velocity vanishes) does not
        // show.
        Test::Branch => rank_deficiency(&node.jacobian) < BRANCH_RANK_DEFICIENCY,
        _ => located <= EVENT_ACCEPTANCE * va.max(vb),
    };
    if located.is_nan() || !accepted {
        return None;
    }
    let mut phase = None;
    let mut pair = None;
    let mut signature_after = None;
    match test {
        Test::Torus => {
            let on_circle =
                node.point.floquet_multipliers.iter().any(|m| {
                    m.im.abs() > REAL_MULTIPLIER && (m.norm() - 1.0).abs() < TORUS_TOLERANCE
                });
            if !on_circle {
                return None;
            }
        }
        Test::Branch => signature_after = Some(system.label().clone()),
        Test::Doubling => signature_after = doubled(system.label()),
        Test::Clearance(c) => {
            let (time, impact) = node.tests.graze[c];
            let f = c / system.model.pairs();
            let (s, e) = system.flight_span(&node.x, f);
            // A critical point of r at a flight's end is the shadow of a vanishing impact
            // there (r̈ turns r back at the stop), not a graze between impacts.
            if !(time > GRAZE_INTERIOR && e - s - time > GRAZE_INTERIOR) {
                return None;
            }
            phase = Some(s + time);
            pair = Some(impact.pair);
            signature_after = grazed(system.label(), f, impact).map(|(sig, _)| sig);
        }
        Test::Approach(j) => {
            phase = Some(if j == 0 { 0.0 } else { node.x[j] });
            pair = Some(system.label().impact_list()[j].pair);
        }
        Test::Fold => {}
    }
    let period_after = signature_after.as_ref().map(|s| s.period());
    Some(Found {
        event: Event {
            branch: node.point.branch,
            kind: test.kind(),
            omega: node.x[n],
            signature_after,
            period_after,
            phase,
            pair,
            point: node.point.clone(),
        },
        node,
    })
}

/// The branch point between `a` and `b` whose test function `det(M − I) / (dω/ds)` changed
/// sign: the zero of that test by [`locate`] (each trial point polished onto the branch),
/// which pins it to about `√ε` (the corrected points near a branch point carry errors of that
/// size), then solved to rounding by the regular defining system of
/// [`super::branch_point`]; accepted by [`event_at`] where `R_X` has lost rank.
fn locate_branch_point<M: BranchModel>(
    system: &System<M>,
    a: &Node,
    b: &Node,
) -> Option<(f64, Node)> {
    let (theta, node) = locate(system, a, b, Test::Branch)?;
    let Some(x) = system.branch_point_near(&node.x) else {
        return Some((theta, node));
    };
    let eval = system.evaluate(&x)?;
    // Solved to rounding, `R_X` there may have lost rank so far that the bordered tangent
    // solve breaks down (the modal flow's rounding meets it on the paper's `+-` branch point
    // near 2.1925686 rad/s); the tangent at a branch point is arbitrary anyway, and
    // [`event_at`] replaces it by the chord from `a` to `b`, so that chord serves here too.
    let tangent = system
        .tangent(M::jacobian(&eval), &a.tangent)
        .or_else(|| unit_chord(a, b))?;
    Some((theta, system.describe(&x, &eval, &tangent, a.point.branch)))
}

/// The zero of `test` between `a` and `b`, by Illinois on the chord fraction `θ`: each trial
/// point `a + θ (b − a)` is corrected onto the branch within the hyperplane normal to the
/// chord. Returns `θ` at the zero and the point there.
fn locate<M: BranchModel>(
    system: &System<M>,
    a: &Node,
    b: &Node,
    test: Test,
) -> Option<(f64, Node)> {
    let n = system.n();
    let chord: Vec<f64> = (0..=n).map(|k| b.x[k] - a.x[k]).collect();
    // A trial point on the branch at chord fraction θ, and the test function there: only
    // what the test needs is computed (the full point is built once, at the end).
    let at = |theta: f64| -> Option<(Vec<f64>, M::Evaluation, f64)> {
        let through: Vec<f64> = (0..=n).map(|k| a.x[k] + theta * chord[k]).collect();
        let plane = Constraint::Plane {
            normal: &chord,
            through: &through,
        };
        let (x, eval) = match test {
            // Near a branch point Newton converges only linearly along the singular
            // direction: full Newton, then polish.
            Test::Branch => {
                let (x, eval, _) = system.correct(&through, &plane)?;
                system.polish(x, eval, &plane)
            }
            _ => match system.correct_chord(&through, &plane, &a.jacobian) {
                // The fold's test needs the Jacobian: added to the chord's residuals.
                Some((x, residual, _)) if matches!(test, Test::Fold) => {
                    let eval = system.complete(&x, residual)?;
                    (x, eval)
                }
                Some((x, residual, _)) => (x, residual),
                None => {
                    let (x, eval, _) = system.correct(&through, &plane)?;
                    (x, eval)
                }
            },
        };
        let mut value = system.test_value(test, &x, &eval, &a.tangent)?;
        if let Test::Branch = test {
            value /= system.tangent(M::jacobian(&eval), &a.tangent)?[n];
        }
        Some((x, eval, value))
    };
    // The point at the zero, from its trial evaluation (the Jacobian added where it has
    // none).
    let finish = |x: &[f64], eval: M::Evaluation| -> Option<Node> {
        let eval = if M::jacobian(&eval).nrows() == n {
            eval
        } else {
            system.complete(x, eval)?
        };
        let tangent = system.tangent(M::jacobian(&eval), &a.tangent)?;
        Some(system.describe(x, &eval, &tangent, a.point.branch))
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut f_lo = test.value(&a.tests);
    let mut f_hi = test.value(&b.tests);
    if f_lo.is_nan() || f_hi.is_nan() || f_lo * f_hi >= 0.0 {
        return None;
    }
    // The test's larger size at the two points, and its size at the bracket's ends (the
    // values Illinois works with are halved, these are not).
    let ends = f_lo.abs().max(f_hi.abs());
    let (mut size_lo, mut size_hi) = (f_lo.abs(), f_hi.abs());
    let mut best: Option<(f64, Vec<f64>, M::Evaluation)> = None;
    let mut side = 0i8;
    for _ in 0..LOCATION_ITERATIONS {
        if hi - lo <= LOCATION_FRACTION {
            break;
        }
        let mut theta = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        if !(theta > lo && theta < hi) {
            theta = 0.5 * (lo + hi);
        }
        let (x, eval, f) = at(theta)?;
        if !f.is_finite() {
            return None;
        }
        let done = f == 0.0;
        if f.signum() == f_hi.signum() {
            hi = theta;
            f_hi = f;
            size_hi = f.abs();
            if side == -1 {
                f_lo *= 0.5;
            }
            side = -1;
        } else {
            lo = theta;
            f_lo = f;
            size_lo = f.abs();
            if side == 1 {
                f_hi *= 0.5;
            }
            side = 1;
        }
        best = Some((theta, x, eval));
        if done {
            break;
        }
        let width = hi - lo;
        if width >= POLE_WIDTH && size_lo.min(size_hi) > POLE_GROWTH * width * ends {
            return None;
        }
    }
    let (theta, x, eval) = best?;
    Some((theta, finish(&x, eval)?))
}
