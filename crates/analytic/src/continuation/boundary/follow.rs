//! The curve follower: pseudo-arclength continuation of an event's curve both ways from its
//! start (the continuation's tangent predictor, the corrector onto the curve, step control by
//! its iterations), through turning points in `p`, to a range's bound, a closed loop, a
//! strong resonance or a step too small; then the special points inserted, and the curve's
//! `ω` at given parameter values.

use super::curve::{Border, EventCurve, Node};
use super::family::Family;
use super::special::{self, BoundarySpecialPoint, SpecialKind};
use super::{Boundary, BoundaryAt, BoundaryEnd, BoundaryEndReason, BoundarySettings};
use crate::continuation::predictor::tangent;
use crate::continuation::result::EventKind;
use crate::continuation::system::BranchModel;

/// Newton iterations at or below which the next step grows.
const EASY_ITERATIONS: usize = 4;

/// Step growth after an easy correction.
const STEP_GROWTH: f64 = 1.5;

/// Step shrink after a rejected one.
const STEP_SHRINK: f64 = 0.5;

/// Two consecutive tangents must make an angle of cosine at least this (about 26°), or the
/// step is halved: a larger turn within a step may have jumped to another curve.
const MIN_TANGENT_COSINE: f64 = 0.9;

/// Shortest flight (fraction of the cycle) below which a curve ending for want of a step is
/// reported as two impacts merging.
const MERGE_WARNING: f64 = 1e-6;

/// The state of following the curve in one direction.
struct Walk {
    nodes: Vec<Node>,
    last: Node,
    step: f64,
    /// The last node is a strong resonance ending a Neimark–Sacker curve.
    resonance: Option<(SpecialKind, f64)>,
}

/// The curve followed in one direction: the points after the start, why it stops, and
/// whether its last point is a strong resonance (kind and value of its function).
struct Leg {
    nodes: Vec<Node>,
    reason: BoundaryEndReason,
    resonance: Option<(SpecialKind, f64)>,
}

/// What one step did.
enum Step {
    /// A new point, possibly past a range's bound, and the corrector's iterations.
    Accepted(Node, usize),
    /// The corrector failed or the curve turned too sharply: retry shorter.
    Rejected,
}

impl<Fam: Family> EventCurve<Fam> {
    /// The curve both ways from `(y, tangent)`, its special points, the `ω` at the values
    /// `at`, and the ends.
    pub(super) fn trace(
        &self,
        y: Vec<f64>,
        tangent: Vec<f64>,
        at: &[f64],
        settings: &BoundarySettings,
    ) -> Boundary<Fam::Label> {
        let start = Node { y, tangent };
        let mut forward = self.follow(&start, 1.0, settings, None);
        // Where the forward way stopped at its cap, a closed curve longer than that goes on
        // from there: the backward way, round it the other way, ends when it gets there.
        let meet = forward
            .nodes
            .last()
            .filter(|_| forward.reason == BoundaryEndReason::PointCap);
        let backward = if forward.reason == BoundaryEndReason::ClosedLoop {
            Leg {
                nodes: Vec::new(),
                reason: BoundaryEndReason::ClosedLoop,
                resonance: None,
            }
        } else {
            self.follow(&start, -1.0, settings, meet)
        };
        if forward.reason == BoundaryEndReason::PointCap
            && backward.reason == BoundaryEndReason::ClosedLoop
        {
            // The two ways met: the curve is followed whole, once.
            forward.reason = BoundaryEndReason::ClosedLoop;
        }
        let mut nodes = backward.nodes;
        nodes.reverse();
        nodes.push(start);
        nodes.extend(forward.nodes);
        let n = self.n();
        let end = |node: &Node, reason| BoundaryEnd {
            param_value: node.y[n + 1],
            omega: node.y[n],
            reason,
        };
        let ends = [
            end(&nodes[0], backward.reason),
            end(&nodes[nodes.len() - 1], forward.reason),
        ];
        let (nodes, specials) =
            self.with_special_points(nodes, backward.resonance, forward.resonance);
        let at = at.iter().flat_map(|&v| self.solve_at(&nodes, v)).collect();
        let special_points = specials
            .into_iter()
            .filter_map(|(node, kind, value)| {
                let point = self.describe(&node.y)?;
                Some(BoundarySpecialPoint {
                    kind,
                    param_value: point.param_value,
                    omega: point.omega,
                    value,
                    point,
                })
            })
            .collect();
        Boundary {
            signature: self.label.clone(),
            kind: self.kind,
            points: nodes
                .iter()
                .filter_map(|node| self.describe(&node.y))
                .collect(),
            at,
            special_points,
            ends,
        }
    }

    /// `nodes` with the special points between them inserted in order, and the special
    /// points (node, kind, value); `first` and `last` say that the first or last node is a
    /// resonance ending the curve.
    fn with_special_points(
        &self,
        nodes: Vec<Node>,
        first: Option<(SpecialKind, f64)>,
        last: Option<(SpecialKind, f64)>,
    ) -> (Vec<Node>, Vec<(Node, SpecialKind, f64)>) {
        let found = self.special_points(&nodes);
        let mut specials = Vec::with_capacity(found.len() + 2);
        if let Some((kind, value)) = first {
            specials.push((nodes[0].clone(), kind, value));
        }
        let mut out = Vec::with_capacity(nodes.len() + found.len());
        let mut found = found.into_iter().peekable();
        for (i, node) in nodes.into_iter().enumerate() {
            out.push(node);
            while let Some((_, special, kind, value)) = found.next_if(|f| f.0 == i) {
                out.push(special.clone());
                specials.push((special, kind, value));
            }
        }
        if let Some((kind, value)) = last {
            specials.push((out[out.len() - 1].clone(), kind, value));
        }
        (out, specials)
    }

    /// The curve's points at parameter value `value`: each crossing of `p = value` between
    /// consecutive nodes, solved with `p` fixed from the chord's point.
    fn solve_at(&self, nodes: &[Node], value: f64) -> Vec<BoundaryAt> {
        let n = self.n();
        let mut found: Vec<BoundaryAt> = Vec::new();
        for (i, pair) in nodes.windows(2).enumerate() {
            let (a, b) = (&pair[0].y, &pair[1].y);
            let (pa, pb) = (a[n + 1] - value, b[n + 1] - value);
            // A node exactly at the value is the previous pair's crossing.
            if pa * pb > 0.0 || pa == pb || (pa == 0.0 && i > 0) {
                continue;
            }
            let theta = pa / (pa - pb);
            let guess: Vec<f64> = a.iter().zip(b).map(|(u, v)| u + theta * (v - u)).collect();
            let border = Border::Fixed {
                index: n + 1,
                value,
            };
            if let Some((y, _, _)) = self.correct(&guess, &border) {
                found.push(BoundaryAt {
                    param_value: value,
                    omega: y[n],
                });
            }
        }
        found
    }

    /// Follows the curve from `start` in `direction` (`±1` along its tangent): the points
    /// after the start and why it stops.
    fn follow(
        &self,
        start: &Node,
        direction: f64,
        settings: &BoundarySettings,
        meet: Option<&Node>,
    ) -> Leg {
        let mut walk = Walk {
            nodes: Vec::new(),
            last: Node {
                y: start.y.clone(),
                tangent: start.tangent.iter().map(|v| direction * v).collect(),
            },
            step: settings.initial_step,
            resonance: None,
        };
        let reason = loop {
            match self.next_iter(&walk) {
                Step::Accepted(node, iterations) => {
                    let end = self.terminate(&mut walk, node, iterations, (start, meet), settings);
                    if let Some(reason) = end {
                        break reason;
                    }
                }
                Step::Rejected => {
                    if let Some((end, reason)) = self.beyond(&walk, settings) {
                        walk.nodes.push(end);
                        break reason;
                    }
                    walk.step *= STEP_SHRINK;
                    if walk.step < settings.min_step {
                        break self.stuck(&walk.last.y);
                    }
                }
            }
        };
        Leg {
            nodes: walk.nodes,
            reason,
            resonance: walk.resonance,
        }
    }

    /// One predictor–corrector step of `walk.step` from its last point.
    fn next_iter(&self, walk: &Walk) -> Step {
        let (y0, t0) = (&walk.last.y, &walk.last.tangent);
        let predicted: Vec<f64> = y0.iter().zip(t0).map(|(y, t)| y + walk.step * t).collect();
        let plane = Border::Plane {
            normal: t0,
            through: &predicted,
        };
        let Some((y, jacobian, iterations)) = self.correct(&predicted, &plane) else {
            return Step::Rejected;
        };
        let Some(t) = tangent(&jacobian, t0) else {
            return Step::Rejected;
        };
        let cosine: f64 = t.iter().zip(t0).map(|(a, b)| a * b).sum();
        if cosine < MIN_TANGENT_COSINE {
            return Step::Rejected;
        }
        Step::Accepted(Node { y, tangent: t }, iterations)
    }

    /// Takes the accepted `node` into `walk` and says whether the direction ends: past a
    /// range's bound (the end then solved exactly on it), back at the start, at `meet` (where
    /// the other direction stopped at its cap) travelling against it, at the point cap.
    /// Grows the step after an easy correction.
    fn terminate(
        &self,
        walk: &mut Walk,
        node: Node,
        iterations: usize,
        (start, meet): (&Node, Option<&Node>),
        settings: &BoundarySettings,
    ) -> Option<BoundaryEndReason> {
        let n = self.n();
        if let Some((index, value, reason)) = outside(&node.y, n, settings) {
            let end = self.end_at(&walk.last, &node, index, value);
            walk.nodes.extend(end);
            return Some(reason);
        }
        if self.kind == EventKind::NeimarkSacker && !self.on_circle(&node.y) {
            // The pair left the circle for the real axis at μ = 1 or −1: the last point is
            // that resonance, when located.
            if let Some((resonance, kind, value)) = self.resonance_end(&walk.last, &node) {
                walk.nodes.push(resonance);
                walk.resonance = Some((kind, value));
            }
            return Some(BoundaryEndReason::NeutralSaddle);
        }
        // Back at the start travelling the same way, or at `meet` travelling against it.
        let along = |other: &Node| -> f64 {
            node.tangent
                .iter()
                .zip(&other.tangent)
                .map(|(a, b)| a * b)
                .sum()
        };
        let near = |other: &Node| distance(&node.y, &other.y) < walk.step;
        let back = near(start) && walk.nodes.len() >= 3 && along(start) > 0.0;
        let met = meet.is_some_and(|end| near(end) && along(end) < 0.0);
        walk.last = node.clone();
        walk.nodes.push(node);
        if back || met {
            return Some(BoundaryEndReason::ClosedLoop);
        }
        if walk.nodes.len() >= settings.max_points {
            return Some(BoundaryEndReason::PointCap);
        }
        if iterations <= EASY_ITERATIONS {
            walk.step = (walk.step * STEP_GROWTH).min(settings.max_step);
        }
        None
    }

    /// After a failed step whose prediction lies beyond a range's bound (where the unit may
    /// not exist, e.g. restitution above 1): the curve's point on that bound, solved from the
    /// last point and the prediction, and the end's reason.
    fn beyond(
        &self,
        walk: &Walk,
        settings: &BoundarySettings,
    ) -> Option<(Node, BoundaryEndReason)> {
        let (y0, t0) = (&walk.last.y, &walk.last.tangent);
        let predicted: Vec<f64> = y0.iter().zip(t0).map(|(y, t)| y + walk.step * t).collect();
        let (index, value, reason) = outside(&predicted, self.n(), settings)?;
        let ahead = Node {
            y: predicted,
            tangent: t0.clone(),
        };
        Some((self.end_at(&walk.last, &ahead, index, value)?, reason))
    }

    /// The 1:1 or 1:2 resonance between the last point `a` with its complex pair on the
    /// unit circle and the next one `b`, where the pair is real: located as the zero of
    /// `c ∓ 1` ([`SpecialKind::Resonance`]), with its kind and the function's value.
    fn resonance_end(&self, a: &Node, b: &Node) -> Option<(Node, SpecialKind, f64)> {
        let n = self.n();
        let cosine = |y: &[f64]| {
            self.with_model(y[n + 1], |model| {
                let eval = model.evaluate(&y[..=n], false)?;
                special::pair_cosine(&model.monodromy(&y[..=n], &eval)?)
            })
        };
        let (ca, cb) = (cosine(&a.y)?, cosine(&b.y)?);
        let (q, target) = if cb > 1.0 { (1, 1.0) } else { (2, -1.0) };
        let kind = SpecialKind::Resonance { q };
        let (_, node, value) = self.locate(a, b, kind, ca - target, cb - target)?;
        Some((node, kind, value))
    }

    /// The point where the curve crosses `Y[index] = value` between `a` and `b`.
    fn end_at(&self, a: &Node, b: &Node, index: usize, value: f64) -> Option<Node> {
        let theta = (value - a.y[index]) / (b.y[index] - a.y[index]);
        let guess: Vec<f64> =
            a.y.iter()
                .zip(&b.y)
                .map(|(u, v)| u + theta * (v - u))
                .collect();
        let (y, _, _) = self.correct(&guess, &Border::Fixed { index, value })?;
        Some(Node {
            y,
            tangent: b.tangent.clone(),
        })
    }

    /// Why the curve cannot go on from `y`: merging impacts or a step too small.
    fn stuck(&self, y: &[f64]) -> BoundaryEndReason {
        let n = self.n();
        let mut shortest = 1.0 - y[n - 1].max(0.0);
        let mut last = 0.0;
        for &phase in &y[1..n] {
            shortest = shortest.min(phase - last);
            last = phase;
        }
        if n > 1 && shortest < MERGE_WARNING {
            BoundaryEndReason::FlightMerged
        } else {
            BoundaryEndReason::StepBelowMinimum
        }
    }
}

/// The bound `Y` lies beyond, if any: its index in `Y`, value and end reason.
fn outside(
    y: &[f64],
    n: usize,
    settings: &BoundarySettings,
) -> Option<(usize, f64, BoundaryEndReason)> {
    let (omega, p) = (y[n], y[n + 1]);
    if p < settings.param_min {
        Some((n + 1, settings.param_min, BoundaryEndReason::ParamMin))
    } else if p > settings.param_max {
        Some((n + 1, settings.param_max, BoundaryEndReason::ParamMax))
    } else if omega < settings.omega_min {
        Some((n, settings.omega_min, BoundaryEndReason::OmegaMin))
    } else if omega > settings.omega_max {
        Some((n, settings.omega_max, BoundaryEndReason::OmegaMax))
    } else {
        None
    }
}

/// Euclidean distance between two `Y`, each entry as it stands: unlike the continuation's
/// `distance` between two `X`, `α` is not taken modulo 2π (the two differ where `α` has moved
/// by more than π), so the closed-loop test compares the unknowns as the corrector moves them.
fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(u, v)| (u - v).powi(2))
        .sum::<f64>()
        .sqrt()
}
