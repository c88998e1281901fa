//! The driver: follows a branch both ways from its seed (predictor, corrector, step control,
//! events on each step, the ends), then the branches that leave at its events, each once.

use super::branches::{cosine, distance, listed, passes, same_switch, Atlas, Curve, SwitchKey};
use super::branches::{LOOP_MIN_POINTS, LOOP_TANGENT_COSINE};
use super::corrector::{Constraint, HARD_ITERATIONS};
use super::events::{detect, Found};
use super::predictor::seed_tangent;
use super::result::{Branch, BranchEnd, Continuation, EndReason, EventKind};
use super::settings::ContinuationSettings;
use super::switching::{switch_seed, Seed, SWITCH_STEP};
use super::system::{BranchModel, Label, Node, System};
use std::collections::VecDeque;

/// Step growth when the corrector converged in at most [`EASY_ITERATIONS`] iterations.
const STEP_GROWTH: f64 = 1.5;

/// Chord iterations at or below which the step is grown. The chord iteration contracts by
/// about `hκ` per iteration from a predictor error of about `κh²`, so its count grows with
/// the step: measured on the paper unit (`+-` over `ω ∈ [2.5, 3.5]`, `++--` over
/// `[1.8, 2.2]`), growing at ≤ 3 gave 957 and 383 points in 34 ms per branch, ≤ 4 gave 392
/// and 183 points in 17 and 22 ms, ≤ 5 gave 253 and 138 points in 13 and 19 ms: ≤ 4 keeps
/// the curves resolved for plotting at half the cost of ≤ 3.
const EASY_ITERATIONS: usize = 4;

/// Shrink factor after a hard step, and after a rejected one (halved then).
const STEP_SHRINK: f64 = 0.7;

/// Two consecutive tangents must make an angle whose cosine is at least this, or the step is
/// halved: about 26°. A larger turn within one step means the corrector may have jumped to
/// another branch, or the step skipped over a sharp feature (a fold of short extent).
pub(crate) const MIN_TANGENT_COSINE: f64 = 0.9;

/// Shortest flight (fraction of the cycle) below which a failed step is reported as two
/// impacts merging rather than as a step below the minimum.
const MERGE_WARNING: f64 = 1e-6;

/// The state of a continuation from one start: the result so far, the branches followed
/// (an [`Atlas`]), the switch points taken and the seeds still to follow.
pub(crate) struct Run<'a, M: BranchModel> {
    /// The model, with the start's label (each branch relabels it).
    pub(crate) model: &'a M,
    pub(crate) settings: &'a ContinuationSettings,
    pub(crate) out: &'a mut Continuation<M::Label>,
    pub(crate) atlas: Atlas<M::Label>,
    pub(crate) switched: Vec<SwitchKey<M::Label>>,
    pub(crate) queue: VecDeque<Seed<M::Label>>,
    /// Branches followed from this start.
    pub(crate) followed: usize,
}

impl<M: BranchModel> Run<'_, M> {
    /// Follows the seeds queued, up to `max_branches`; the seeds left then are recorded as
    /// branches without points, both ends [`EndReason::BranchCap`] at their seed.
    pub(crate) fn run(&mut self) {
        while let Some(seed) = self.queue.pop_front() {
            if self.followed >= self.settings.max_branches {
                let omega = seed.x[seed.x.len() - 1];
                self.unfollowed(
                    &seed.signature,
                    seed.from_event,
                    omega,
                    EndReason::BranchCap,
                );
                continue;
            }
            self.follow(seed);
        }
    }

    /// Follows the branch of `seed`, records it, its ends and events, and queues its switches.
    fn follow(&mut self, seed: Seed<M::Label>) {
        self.followed += 1;
        let index = self.out.branches.len();
        let system = System::new(self.model.relabel(seed.signature.clone()));
        let follow = Follow {
            system: &system,
            settings: self.settings,
            origin: &seed,
            branch: index,
            atlas: &self.atlas,
        };
        let Some(followed) = follow.branch() else {
            // The seed itself could not be evaluated: record the attempt as a branch without
            // points ending where it started.
            let omega = seed.x[seed.x.len() - 1];
            self.unfollowed(
                &seed.signature,
                seed.from_event,
                omega,
                EndReason::NewtonFailed,
            );
            return;
        };
        self.out.branches.push(Branch {
            index,
            signature: seed.signature.clone(),
            period: seed.signature.period(),
            points: followed.nodes.iter().map(|n| n.point.clone()).collect(),
            from_event: seed.from_event,
        });
        self.out.ends.extend(followed.ends);
        self.atlas.curves.push(followed.curve);
        for found in followed.events {
            self.event(&system, &seed, index, found);
        }
        // The seed of this branch is a switch point too (so the way back is not taken).
        self.switched.push((seed.signature.clone(), seed.x.clone()));
    }

    /// Records a branch that is not followed: no points, both ends `reason` at `omega`.
    fn unfollowed(
        &mut self,
        signature: &M::Label,
        from_event: Option<usize>,
        omega: f64,
        reason: EndReason,
    ) {
        let index = self.out.branches.len();
        self.out.branches.push(Branch {
            index,
            signature: signature.clone(),
            period: signature.period(),
            points: Vec::new(),
            from_event,
        });
        for _ in 0..2 {
            self.out.ends.push(BranchEnd {
                branch: index,
                omega,
                reason,
                joins: None,
            });
        }
    }

    /// Lists an event found on branch `index` (unless it is listed already: a branch point
    /// seen from both branches through it, or the image of one listed) and queues the branch
    /// that leaves there, or records the depth cut.
    fn event(
        &mut self,
        system: &System<M>,
        seed: &Seed<M::Label>,
        index: usize,
        found: Found<M::Label>,
    ) {
        let mut event = found.event;
        event.branch = index;
        event.point.branch = index;
        let mirrored = system.model.mirrored();
        if listed(
            self.out,
            system.label(),
            event.kind,
            &found.node.x,
            mirrored,
        ) {
            return;
        }
        let event_index = self.out.events.len();
        let switches = matches!(
            event.kind,
            EventKind::BranchPoint | EventKind::PeriodDoubling | EventKind::Grazing
        ) && event.signature_after.is_some();
        if self.settings.follow_switches && switches {
            if seed.depth >= self.settings.max_depth {
                if let Some(signature) = event.signature_after.clone() {
                    let omega = event.omega;
                    self.out.events.push(event);
                    self.unfollowed(&signature, Some(event_index), omega, EndReason::MaxDepth);
                    return;
                }
            }
            let step = (SWITCH_STEP * self.settings.initial_step).max(self.settings.min_step);
            if let Some(mut next) = switch_seed(system, &found.node, &event, event_index, step) {
                let key = (next.signature.clone(), next.x.clone());
                if !self.switched.iter().any(|k| same_switch(k, &key)) {
                    next.depth = seed.depth + 1;
                    self.switched.push(key);
                    self.queue.push_back(next);
                }
            }
        }
        self.out.events.push(event);
    }
}

/// The result of following one branch both ways.
struct Followed<L> {
    nodes: Vec<Node>,
    /// In their order along the branch.
    events: Vec<Found<L>>,
    ends: Vec<BranchEnd>,
    /// The branch as followed.
    curve: Curve<L>,
}

/// Following one branch: the problem (its equations, the settings, its seed, the branches
/// already followed).
struct Follow<'a, M: BranchModel> {
    system: &'a System<M>,
    settings: &'a ContinuationSettings,
    origin: &'a Seed<M::Label>,
    branch: usize,
    atlas: &'a Atlas<M::Label>,
}

impl<M: BranchModel> Follow<'_, M> {
    fn end(&self, reason: EndReason, omega: f64) -> BranchEnd {
        BranchEnd {
            branch: self.branch,
            omega,
            reason,
            joins: None,
        }
    }

    /// Follows the branch of the seed both ways; a switched seed that lies on a branch
    /// already followed is not followed (both ends [`EndReason::Joins`]).
    fn branch(&self) -> Option<Followed<M::Label>> {
        let (system, seed, branch) = (self.system, self.origin, self.branch);
        let eval = system.evaluate(&seed.x)?;
        let tangent = seed_tangent(system, seed.tangent.as_deref(), &eval)?;
        let mut seed_node = system.describe(&seed.x, &eval, &tangent, branch);
        let mut curve = Curve::new(branch, system.label().clone());
        curve.push(&seed.x, &tangent);
        if seed.from_event.is_some() {
            if let Some(other) = self.atlas.joins(system.label(), &seed.x, &tangent, None) {
                let end = BranchEnd {
                    joins: Some(other),
                    ..self.end(EndReason::Joins, seed.x[system.n()])
                };
                return Some(Followed {
                    nodes: vec![seed_node],
                    events: Vec::new(),
                    ends: vec![end, end],
                    curve,
                });
            }
            // At a switch point the test functions sit at zero by construction (a
            // multiplier at ±1, a zero-velocity impact): no sign change is read from the
            // seed.
            seed_node.tests = seed_node.tests.unread();
        }
        let cap = self.settings.max_points_per_branch;
        let (forward, events_forward, mut end_forward) =
            self.direction(&seed_node, 1.0, cap / 2, None, &mut curve);
        let second_cap = cap.saturating_sub(1 + forward.len());
        // Where the forward way stopped at its share of the points, a loop longer than that
        // share goes on from there: the backward way, round the loop the other way, ends
        // when it reaches that point.
        let meet = forward
            .last()
            .filter(|_| end_forward.reason == EndReason::PointCap)
            .map(|node| (node.x.as_slice(), node.tangent.as_slice()));
        let (backward, mut events, end_backward) = if end_forward.reason == EndReason::ClosedLoop {
            // The whole loop is followed already.
            (Vec::new(), Vec::new(), end_forward)
        } else {
            self.direction(&seed_node, -1.0, second_cap, meet, &mut curve)
        };
        if end_forward.reason == EndReason::PointCap && end_backward.reason == EndReason::ClosedLoop
        {
            // The two ways met: the loop is followed whole, once.
            end_forward.reason = EndReason::ClosedLoop;
        }
        // In the branch's order: backward reversed, seed, forward.
        events.reverse();
        events.extend(events_forward);
        // The backward points were found along −t: orient their tangents along that order.
        let mut nodes: Vec<Node> = backward
            .into_iter()
            .rev()
            .map(|mut node| {
                node.tangent.iter_mut().for_each(|v| *v = -*v);
                node.point.domega_ds = -node.point.domega_ds;
                node
            })
            .collect();
        nodes.push(seed_node);
        nodes.extend(forward);
        Some(Followed {
            nodes,
            events,
            ends: vec![end_forward, end_backward],
            curve,
        })
    }

    /// The point on the band's edge `edge` between `prev` and `x` (just beyond it).
    fn edge_node(&self, prev: &Node, x: &[f64], edge: f64) -> Option<Node> {
        let system = self.system;
        let n = system.n();
        let w = (edge - prev.x[n]) / (x[n] - prev.x[n]);
        let guess: Vec<f64> = (0..=n)
            .map(|k| prev.x[k] + w * (x[k] - prev.x[k]))
            .collect();
        let (xe, ee, _) = system.correct(&guess, &Constraint::Omega(edge))?;
        let te = system.tangent(M::jacobian(&ee), &prev.tangent)?;
        Some(system.describe(&xe, &ee, &te, self.branch))
    }

    /// Follows one direction from `seed` (its tangent times `direction`), adding the points
    /// to `curve` (whose vertex 0 is the seed). With `meet` (the point where the other
    /// direction stopped at its cap, and its tangent along that direction), the branch is a
    /// closed loop when a step passes that point travelling against it.
    fn direction(
        &self,
        seed: &Node,
        direction: f64,
        cap: usize,
        meet: Option<(&[f64], &[f64])>,
        curve: &mut Curve<M::Label>,
    ) -> (Vec<Node>, Vec<Found<M::Label>>, BranchEnd) {
        let (system, settings) = (self.system, self.settings);
        let n = system.n();
        let mut prev = seed.clone();
        prev.tangent.iter_mut().for_each(|v| *v *= direction);
        prev.point.domega_ds = prev.tangent[n];
        if prev.tests.fold.is_finite() {
            prev.tests.fold = prev.tangent[n];
        }
        let switched = self.origin.from_event.is_some();
        let mut h = if switched {
            (SWITCH_STEP * settings.initial_step).max(settings.min_step)
        } else {
            settings.initial_step
        };
        let mut nodes: Vec<Node> = Vec::new();
        let mut events = Vec::new();
        let mut vertex = 0;
        let mut before: Option<Node> = None;
        loop {
            if nodes.len() >= cap {
                return (nodes, events, self.end(EndReason::PointCap, prev.x[n]));
            }
            if h < settings.min_step {
                let reason = if system.shortest_flight(&prev.x) < MERGE_WARNING {
                    EndReason::FlightMerged
                } else {
                    EndReason::StepBelowMinimum
                };
                return (nodes, events, self.end(reason, prev.x[n]));
            }
            let pred: Vec<f64> = (0..=n).map(|k| prev.x[k] + h * prev.tangent[k]).collect();
            let plane = Constraint::Plane {
                normal: &prev.tangent,
                through: &pred,
            };
            let Some((x, eval, iterations)) = system.converge(&pred, &plane, &prev.jacobian) else {
                if switched && nodes.is_empty() && h <= settings.min_step * 2.0 {
                    return (nodes, events, self.end(EndReason::NewtonFailed, prev.x[n]));
                }
                h *= 0.5;
                continue;
            };
            let Some(tangent) = system.tangent(M::jacobian(&eval), &prev.tangent) else {
                h *= 0.5;
                continue;
            };
            let turn: f64 = tangent.iter().zip(&prev.tangent).map(|(a, b)| a * b).sum();
            if turn < MIN_TANGENT_COSINE {
                h *= 0.5;
                continue;
            }
            let mut node = system.describe(&x, &eval, &tangent, self.branch);
            // Leaving the band: the last point lies on its edge.
            let bound = if x[n] > settings.omega_max {
                Some((settings.omega_max, EndReason::OmegaMax))
            } else if x[n] < settings.omega_min {
                Some((settings.omega_min, EndReason::OmegaMin))
            } else {
                None
            };
            if let Some((edge, reason)) = bound {
                let Some(edge_node) = self.edge_node(&prev, &x, edge) else {
                    h *= 0.5;
                    continue;
                };
                events.extend(detect(system, &prev, &edge_node, before.as_ref()));
                let k = curve.push(&edge_node.x, &edge_node.tangent);
                curve.link(vertex, k);
                nodes.push(edge_node);
                return (nodes, events, self.end(reason, edge));
            }
            // A branch born at a grazing that leaves on the side where the new impact is
            // approached from outside is not a motion.
            if let Some(j) = self.origin.grazing_impact {
                if nodes.is_empty() && node.tests.approach[j] <= 0.0 {
                    return (
                        nodes,
                        events,
                        self.end(EndReason::VanishingImpact, prev.x[n]),
                    );
                }
            }
            events.extend(detect(system, &prev, &node, before.as_ref()));
            node.point.domega_ds = node.tangent[n];
            let k = curve.push(&node.x, &node.tangent);
            curve.link(vertex, k);
            vertex = k;
            if let Some(other) = self.atlas.joins(
                system.label(),
                &node.x,
                &node.tangent,
                Some((curve, distance(&prev.x, &node.x))),
            ) {
                nodes.push(node);
                let end = BranchEnd {
                    joins: Some(other),
                    ..self.end(EndReason::Joins, x[n])
                };
                return (nodes, events, end);
            }
            // Closed loop: the step from `prev` to `node` passes the seed.
            let along = cosine(&node.tangent, &seed.tangent) * direction;
            if nodes.len() >= LOOP_MIN_POINTS
                && along > LOOP_TANGENT_COSINE
                && passes(&prev.x, &node.x, &seed.x, h)
            {
                nodes.push(node);
                return (nodes, events, self.end(EndReason::ClosedLoop, x[n]));
            }
            // Closed loop from both ways: the step passes where the other way stopped,
            // travelling against it (`passes` and the cosine as for the seed).
            if let Some((end, end_tangent)) = meet {
                if cosine(&node.tangent, end_tangent) < -LOOP_TANGENT_COSINE
                    && passes(&prev.x, &node.x, end, h)
                {
                    nodes.push(node);
                    return (nodes, events, self.end(EndReason::ClosedLoop, x[n]));
                }
            }
            nodes.push(node.clone());
            before = Some(std::mem::replace(&mut prev, node));
            h = if iterations <= EASY_ITERATIONS {
                h * STEP_GROWTH
            } else if iterations > HARD_ITERATIONS {
                h * STEP_SHRINK
            } else {
                h
            }
            .min(settings.max_step);
        }
    }
}
