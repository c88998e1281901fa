//! Special points along a boundary curve: each a zero of a scalar function of the curve's
//! point that changes sign between two consecutive points, located by the Illinois variant
//! of regula falsi on the chord between them, every trial point corrected onto the curve
//! (Newton on the defining system in the hyperplane normal to the chord), until the chord
//! fraction is bracketed to [`LOCATE_TOLERANCE`] or the function vanishes.
//!
//! | special point | function |
//! |---|---|
//! | turning point | `dp/ds`, the unit tangent's parameter component |
//! | grazing | the clearance of a flight other than the event's own (per contact pair) |
//! | vanishing impact | `s_j ṙ⁻_j` of an impact other than the event's own |
//! | strong resonance `1:q` (Neimark–Sacker curves) | `c − cos(2π/q)`, `c = (μ + μ')/2` of the pair with `μ μ' = 1` |
//! | crossing | the fold (`det R_x`), period-doubling (`det(M + I)`) or Neimark–Sacker (`det(M ⊙ M − I)`) test of another event |

use super::curve::{fold_test, jacobian_of, multipliers, torus_test, Border, EventCurve, Node};
use super::family::Family;
use super::BoundaryPoint;
use crate::continuation::predictor::tangent;
use crate::continuation::result::EventKind;
use crate::continuation::system::BranchModel;
use crate::continuation::test_functions::Test;
use nalgebra::{Complex, DMatrix};

/// Chord fraction to which a special point is bracketed.
const LOCATE_TOLERANCE: f64 = 1e-13;

/// Cap on the trials of one location.
const LOCATE_ITERATIONS: usize = 80;

/// A located zero must be below this fraction of the function's larger value at the two
/// points around it: a function that jumps through zero (a clearance whose critical point
/// leaves the flight) is no special point.
const JUMP_FRACTION: f64 = 1e-6;

/// What is special about a point of a boundary curve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SpecialKind {
    /// The curve turns back in the parameter (`dp/ds = 0`): on a fold curve, a cusp.
    TurningPoint,
    /// Another flight of the event's orbit grazes a stop (or the event's flight grazes with
    /// another pair): viability is lost or gained there.
    Grazing {
        /// The flight (from impact `flight` to the next).
        flight: usize,
        /// The contact pair (0 on the unit).
        pair: usize,
    },
    /// Another impact of the event's orbit arrives with zero relative velocity.
    VanishingImpact {
        /// The impact's index in the signature.
        impact: usize,
    },
    /// A strong resonance of a Neimark–Sacker curve: the complex pair at `e^{±2πi/q}`,
    /// `q = 1, 2, 3, 4` (angle 0, π, 2π/3, π/2).
    Resonance {
        /// The resonance's order.
        q: u32,
    },
    /// Another event's curve of the same orbit crosses: its test function vanishes too.
    Crossing {
        /// The other event (fold, period doubling or Neimark–Sacker).
        other: EventKind,
    },
}

impl SpecialKind {
    /// `turning-point`, `grazing`, `vanishing-impact`, `resonance-1:q` or `crossing`.
    pub fn name(self) -> &'static str {
        match self {
            SpecialKind::TurningPoint => "turning-point",
            SpecialKind::Grazing { .. } => "grazing",
            SpecialKind::VanishingImpact { .. } => "vanishing-impact",
            SpecialKind::Resonance { q: 1 } => "resonance-1:1",
            SpecialKind::Resonance { q: 2 } => "resonance-1:2",
            SpecialKind::Resonance { q: 3 } => "resonance-1:3",
            SpecialKind::Resonance { .. } => "resonance-1:4",
            SpecialKind::Crossing { .. } => "crossing",
        }
    }
}

/// A special point of a boundary curve, located on the curve to rounding.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundarySpecialPoint {
    /// What is special there.
    pub kind: SpecialKind,
    /// The parameter's value.
    pub param_value: f64,
    /// The forcing frequency (rad/s).
    pub omega: f64,
    /// The value of the function located at its zero (see [`SpecialKind`]): `dp/ds` of the
    /// unit tangent at a turning point, the clearance at a grazing, `cos θ − cos(2π/q)` at a
    /// resonance, the other event's test at a crossing.
    pub value: f64,
    /// The curve's orbit there (also one of [`super::Boundary::points`]).
    pub point: BoundaryPoint,
}

/// The cosine `c = (μ + μ')/2` of the pair of multipliers whose product is nearest 1 (on a
/// Neimark–Sacker curve the complex pair `e^{±iθ}`, `c = cos θ`; past a 1:1 or 1:2
/// resonance the real pair `μ, 1/μ`, `|c| > 1`); the pair's sum is smooth where its members
/// are not.
pub(super) fn pair_cosine(m: &DMatrix<f64>) -> Option<f64> {
    let mu = multipliers(m)?;
    let mut best: Option<(f64, Complex<f64>)> = None;
    for i in 0..mu.len() {
        for j in i + 1..mu.len() {
            let d = (mu[i] * mu[j] - 1.0).norm();
            if best.is_none_or(|(b, _)| d < b) {
                best = Some((d, mu[i] + mu[j]));
            }
        }
    }
    best.map(|(_, sum)| 0.5 * sum.re)
}

impl<Fam: Family> EventCurve<Fam> {
    /// The special points looked for on this curve.
    pub(super) fn special_kinds(&self) -> Vec<SpecialKind> {
        let n = self.n();
        let mut kinds = vec![SpecialKind::TurningPoint];
        let pairs = self.pairs;
        kinds.extend(
            (0..n * pairs)
                .filter(|&c| !matches!(self.test, Test::Clearance(own) if own == c))
                .map(|c| SpecialKind::Grazing {
                    flight: c / pairs,
                    pair: c % pairs,
                }),
        );
        kinds.extend(
            (0..n)
                .filter(|&j| !matches!(self.test, Test::Approach(a) if a == j))
                .map(|impact| SpecialKind::VanishingImpact { impact }),
        );
        if self.kind == EventKind::NeimarkSacker {
            // 1:1 and 1:2 end the curve (where the pair leaves the circle), located there.
            kinds.extend([3, 4].map(|q| SpecialKind::Resonance { q }));
        }
        kinds.extend(
            [
                EventKind::Fold,
                EventKind::PeriodDoubling,
                EventKind::NeimarkSacker,
            ]
            .into_iter()
            // On a branch-point curve `R_x` is singular throughout: no fold test there.
            .filter(|&other| {
                other != self.kind
                    && !(self.kind == EventKind::BranchPoint && other == EventKind::Fold)
            })
            .map(|other| SpecialKind::Crossing { other }),
        );
        kinds
    }

    /// The functions of `kinds` at the curve's point `y` with unit tangent `t`.
    pub(super) fn special_values(
        &self,
        kinds: &[SpecialKind],
        y: &[f64],
        t: &[f64],
    ) -> Option<Vec<f64>> {
        let n = self.n();
        // Only the fold's test needs a Jacobian, and only in the state unknowns.
        let fold = kinds.contains(&SpecialKind::Crossing {
            other: EventKind::Fold,
        });
        self.with_model(y[n + 1], |model| {
            let x = &y[..=n];
            let eval = if fold {
                model.evaluate_state(x)?
            } else {
                model.evaluate(x, false)?
            };
            let m = model.monodromy(x, &eval)?;
            let size = m.nrows();
            kinds
                .iter()
                .map(|kind| match *kind {
                    SpecialKind::TurningPoint => Some(t[n + 1]),
                    SpecialKind::Grazing { flight, pair } => {
                        model.test_value(Test::Clearance(flight * self.pairs + pair), x, &eval)
                    }
                    SpecialKind::VanishingImpact { impact } => {
                        model.test_value(Test::Approach(impact), x, &eval)
                    }
                    SpecialKind::Resonance { q } => {
                        let angle = std::f64::consts::TAU / f64::from(q);
                        Some(pair_cosine(&m)? - angle.cos())
                    }
                    SpecialKind::Crossing { other } => Some(match other {
                        EventKind::Fold => fold_test(jacobian_of(model, &eval)),
                        EventKind::PeriodDoubling => {
                            (&m + DMatrix::identity(size, size)).determinant()
                        }
                        _ => torus_test(&m),
                    }),
                })
                .collect()
        })
    }

    /// Every special point between consecutive `nodes`, in order along the curve, with the
    /// node of each (to be inserted into the curve).
    pub(super) fn special_points(&self, nodes: &[Node]) -> Vec<(usize, Node, SpecialKind, f64)> {
        let kinds = self.special_kinds();
        let tangents = oriented_tangents(nodes);
        let values: Vec<Option<Vec<f64>>> = nodes
            .iter()
            .zip(&tangents)
            .map(|(node, t)| self.special_values(&kinds, &node.y, t))
            .collect();
        let mut found = Vec::new();
        for i in 0..nodes.len().saturating_sub(1) {
            let (Some(va), Some(vb)) = (&values[i], &values[i + 1]) else {
                continue;
            };
            let a = Node {
                y: nodes[i].y.clone(),
                tangent: tangents[i].clone(),
            };
            let mut here: Vec<(f64, Node, SpecialKind, f64)> = Vec::new();
            for (k, &kind) in kinds.iter().enumerate() {
                if va[k] * vb[k] >= 0.0 {
                    continue;
                }
                if let Some((theta, node, value)) =
                    self.locate(&a, &nodes[i + 1], kind, va[k], vb[k])
                {
                    here.push((theta, node, kind, value));
                }
            }
            here.sort_by(|a, b| a.0.total_cmp(&b.0));
            found.extend(
                here.into_iter()
                    .map(|(_, node, kind, value)| (i, node, kind, value)),
            );
        }
        found
    }

    /// The zero of the function of `kind` between `a` and `b` (values `ga`, `gb` of opposite
    /// signs): its chord fraction, the curve's point there with its tangent (oriented from
    /// `a` to `b`) and the function's value. `None` when a trial does not converge onto the
    /// curve, when the function jumps through zero rather than vanishing, or when a crossing
    /// of the Neimark–Sacker test is a neutral saddle (real multipliers).
    pub(super) fn locate(
        &self,
        a: &Node,
        b: &Node,
        kind: SpecialKind,
        ga: f64,
        gb: f64,
    ) -> Option<(f64, Node, f64)> {
        let chord: Vec<f64> = b.y.iter().zip(&a.y).map(|(u, v)| u - v).collect();
        let length = chord.iter().map(|v| v * v).sum::<f64>().sqrt();
        let normal: Vec<f64> = chord.iter().map(|v| v / length).collect();
        let (mut lo, mut hi, mut g_lo, mut g_hi) = (0.0, 1.0, ga, gb);
        let mut side = 0;
        let mut best = None;
        for _ in 0..LOCATE_ITERATIONS {
            let theta = ((lo * g_hi - hi * g_lo) / (g_hi - g_lo)).clamp(lo, hi);
            let through: Vec<f64> = a.y.iter().zip(&chord).map(|(y, c)| y + theta * c).collect();
            let border = Border::Plane {
                normal: &normal,
                through: &through,
            };
            let (y, jacobian, _) = self.correct(&through, &border)?;
            let t = tangent(&jacobian, &normal)?;
            let g = self.special_values(&[kind], &y, &t)?[0];
            best = Some((theta, Node { y, tangent: t }, g));
            if g == 0.0 || hi - lo <= LOCATE_TOLERANCE {
                break;
            }
            if g * g_lo < 0.0 {
                (hi, g_hi) = (theta, g);
                if side == -1 {
                    g_lo *= 0.5;
                }
                side = -1;
            } else {
                (lo, g_lo) = (theta, g);
                if side == 1 {
                    g_hi *= 0.5;
                }
                side = 1;
            }
        }
        let (theta, node, g) = best?;
        let vanishes = g.abs() <= JUMP_FRACTION * ga.abs().max(gb.abs());
        let genuine = match kind {
            SpecialKind::Crossing {
                other: EventKind::NeimarkSacker,
            } => self.on_circle(&node.y),
            _ => true,
        };
        (vanishes && genuine).then_some((theta, node, g))
    }
}

/// Each node's unit tangent oriented along the order of `nodes` (the walk backward from the
/// start carries tangents pointing backward).
fn oriented_tangents(nodes: &[Node]) -> Vec<Vec<f64>> {
    let last = nodes.len().saturating_sub(1);
    nodes
        .iter()
        .enumerate()
        .map(|(i, node)| {
            let (before, after) = (&nodes[i.saturating_sub(1)].y, &nodes[(i + 1).min(last)].y);
            let along: f64 = node
                .tangent
                .iter()
                .zip(after.iter().zip(before))
                .map(|(t, (u, v))| t * (u - v))
                .sum();
            let sign = if along < 0.0 { -1.0 } else { 1.0 };
            node.tangent.iter().map(|t| sign * t).collect()
        })
        .collect()
}
