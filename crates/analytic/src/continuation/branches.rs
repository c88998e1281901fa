//! Branch bookkeeping: each branch followed once. A branch is kept as a polyline in `X`
//! ([`Curve`]); the branches followed form an [`Atlas`], against which a new point is tested
//! in each of its representations (the same motion timed from another impact, and its mirror
//! image where the stops are symmetric), and events already listed are recognised.

use super::result::{Branch, Continuation, ContinuationPoint, EventKind};
use super::system::Label;
use crate::orbit::wrap;
use crate::sequence::PairImpact;
use std::collections::HashMap;

/// Two switch points are the same (a branch point seen from both branches, a doubling seen
/// from the doubled branch) when `ω` and every unknown agree to this: the located events sit
/// at about `1e-12` of each other, and distinct bifurcations of the unit lie far apart.
pub(crate) const SWITCH_DEDUP: f64 = 1e-6;

/// A branch whose last step passes within this fraction of the step of its seed, after at
/// least [`LOOP_MIN_POINTS`] points, has closed on itself (an isola). The chord of a step `h`
/// departs from the curve by about `κh²/8`, far below `0.1 h` for the steps the tangent-turn
/// test ([`MIN_TANGENT_COSINE`]) allows; a distinct branch passing that close to the seed is
/// not told apart from a loop.
pub(crate) const LOOP_CLOSURE: f64 = 0.1;

/// A loop closes only where the branch comes back through its seed travelling the same way:
/// the tangents agree to this cosine (a branch crossing the seed at a branch point, or
/// passing near it, does not).
pub(crate) const LOOP_TANGENT_COSINE: f64 = 0.99;

/// Fewest points before closure of a loop is tested.
pub(crate) const LOOP_MIN_POINTS: usize = 8;

/// A switch already taken: label, `X`.
pub(crate) type SwitchKey<L> = (L, Vec<f64>);

/// Whether an event of `kind` at `x` on a branch of `label` is in `out` already, as itself
/// or as one of its other representations ([`representations`], mirror images with
/// `mirrored`).
pub(crate) fn listed<L: Label>(
    out: &Continuation<L>,
    label: &L,
    kind: EventKind,
    x: &[f64],
    mirrored: bool,
) -> bool {
    let tangent = vec![0.0; x.len()];
    let reps = representations(label, x, &tangent, mirrored);
    out.events.iter().filter(|e| e.kind == kind).any(|e| {
        let Some(branch) = out.branches.get(e.branch) else {
            return false;
        };
        let y = point_unknowns(&e.point);
        reps.iter()
            .any(|r| r.signature == branch.signature && same_point(&r.x, &y))
    })
}

/// `X = (α, φ₂ … φₙ, ω)` of a point.
fn point_unknowns(p: &ContinuationPoint) -> Vec<f64> {
    let phases = p.impact_phases.get(1..).unwrap_or(&[]);
    let mut x = Vec::with_capacity(phases.len() + 2);
    x.push(p.alpha);
    x.extend_from_slice(phases);
    x.push(p.omega);
    x
}

/// Whether two `X` agree to [`SWITCH_DEDUP`] (`α` modulo 2π).
fn same_point(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len()
        && wrap(a[0] - b[0]).abs() < SWITCH_DEDUP
        && a[1..]
            .iter()
            .zip(&b[1..])
            .all(|(p, q)| (p - q).abs() < SWITCH_DEDUP)
}

/// Whether two switch keys are the same point of the same signature ([`SWITCH_DEDUP`]).
pub(crate) fn same_switch<L: Label>(a: &SwitchKey<L>, b: &SwitchKey<L>) -> bool {
    a.0 == b.0 && same_point(&a.1, &b.1)
}

/// One representation of an orbit: its signature, `X` and tangent.
struct Representation<L> {
    signature: L,
    x: Vec<f64>,
    tangent: Vec<f64>,
    /// The orbit as given (no rotation, no mirror).
    identity: bool,
}

/// Every representation of the orbit `x` of `label` (tangent `tangent`) in canonical form.
/// The same motion timed from another impact whose rotation of the impacts is canonical
/// (`k`: `α + 2πp φ_k`, phases `φ_{j+k} − φ_k`), and, with `mirrored`, its image under the
/// model's symmetry: with symmetric stops and the forcing odd over half a period,
/// `−u(t + T/2)` is a motion too, with the sides mirrored (`s → −s`) and, timed from impact
/// `k`, `α + 2πp φ_k − π`.
fn representations<L: Label>(
    label: &L,
    x: &[f64],
    tangent: &[f64],
    mirrored: bool,
) -> Vec<Representation<L>> {
    let impacts = label.impact_list();
    let n = impacts.len();
    let period = label.period();
    let angle = std::f64::consts::TAU * period as f64;
    let phase = |v: &[f64], k: usize| if k == 0 { 0.0 } else { v[k] };
    let mut out = Vec::new();
    let mirrors: &[bool] = if mirrored { &[false, true] } else { &[false] };
    for &mirror in mirrors {
        let sign = if mirror { -1 } else { 1 };
        for k in 0..n {
            let rotated: Vec<PairImpact> = (0..n)
                .map(|j| {
                    let i = impacts[(j + k) % n];
                    PairImpact {
                        side: sign * i.side,
                        ..i
                    }
                })
                .collect();
            // The label's own length and period: under the caps of a simulated cycle, not
            // those of the search (a branch of more than 16 impacts, seeded from a simulated
            // cycle, would otherwise have no representation at all, and so never be
            // recognised: neither its events listed already nor the branches running onto it).
            let Some(canonical) = L::from_rotated(&rotated, period) else {
                continue;
            };
            if canonical.impact_list() != rotated {
                continue;
            }
            let shift = if mirror { std::f64::consts::PI } else { 0.0 };
            let mut xr = vec![wrap(x[0] + angle * phase(x, k) - shift)];
            let mut tr = vec![tangent[0] + angle * phase(tangent, k)];
            for j in 1..n {
                let i = (j + k) % n;
                xr.push((phase(x, i) - phase(x, k)).rem_euclid(1.0));
                tr.push(phase(tangent, i) - phase(tangent, k));
            }
            xr.push(x[n]);
            tr.push(tangent[n]);
            out.push(Representation {
                signature: canonical,
                x: xr,
                tangent: tr,
                identity: !mirror && k == 0,
            });
        }
    }
    out
}

/// Width in `ω` (rad/s) of the buckets in which a [`Curve`] files its segments.
const CURVE_BUCKET: f64 = 0.01;

/// A branch as a polyline in `X`, with the unit tangent at each vertex, its segments filed
/// by `ω` for the test of whether a point lies on it.
pub(crate) struct Curve<L> {
    branch: usize,
    signature: L,
    x: Vec<Vec<f64>>,
    tangent: Vec<Vec<f64>>,
    segments: Vec<(usize, usize)>,
    buckets: HashMap<i64, Vec<usize>>,
}

impl<L: Label> Curve<L> {
    /// A curve without vertices of branch `branch`, of orbits of `signature`.
    pub(crate) fn new(branch: usize, signature: L) -> Self {
        Self {
            branch,
            signature,
            x: Vec::new(),
            tangent: Vec::new(),
            segments: Vec::new(),
            buckets: HashMap::new(),
        }
    }

    /// A branch recorded in a [`Continuation`]: its points in order, the tangent at each
    /// from the chord between its neighbours.
    fn of(branch: &Branch<L>) -> Self {
        let mut curve = Self::new(branch.index, branch.signature.clone());
        let xs: Vec<Vec<f64>> = branch.points.iter().map(point_unknowns).collect();
        let tangents: Vec<Vec<f64>> = (0..xs.len())
            .map(|i| {
                let (a, b) = (&xs[i.saturating_sub(1)], &xs[(i + 1).min(xs.len() - 1)]);
                let mut t: Vec<f64> = (0..a.len())
                    .map(|k| {
                        if k == 0 {
                            wrap(b[0] - a[0])
                        } else {
                            b[k] - a[k]
                        }
                    })
                    .collect();
                let norm = t.iter().map(|v| v * v).sum::<f64>().sqrt();
                t.iter_mut().for_each(|v| *v /= norm);
                t
            })
            .collect();
        // The vertices moved in (not copied by `push`, as this runs for every branch of
        // every start), then each segment linked in order.
        curve.x = xs;
        curve.tangent = tangents;
        for k in 1..curve.x.len() {
            curve.link(k - 1, k);
        }
        curve
    }

    /// Adds a vertex; its index.
    pub(crate) fn push(&mut self, x: &[f64], tangent: &[f64]) -> usize {
        self.x.push(x.to_vec());
        self.tangent.push(tangent.to_vec());
        self.x.len() - 1
    }

    /// Adds the segment between vertices `i` and `j`, filed in every bucket that a point
    /// projecting onto it within [`LOOP_CLOSURE`] of its length can fall in.
    pub(crate) fn link(&mut self, i: usize, j: usize) {
        let (a, b) = (&self.x[i], &self.x[j]);
        let n = a.len() - 1;
        let length = distance(a, b);
        let margin = 2.0 * LOOP_CLOSURE * length;
        let lo = ((a[n].min(b[n]) - margin) / CURVE_BUCKET).floor();
        let hi = ((a[n].max(b[n]) + margin) / CURVE_BUCKET).floor();
        if !(lo.is_finite() && hi.is_finite()) {
            return;
        }
        let s = self.segments.len();
        self.segments.push((i, j));
        for bucket in lo as i64..=hi as i64 {
            self.buckets.entry(bucket).or_default().push(s);
        }
    }

    /// Whether the point `x` with unit tangent `tangent` lies on the curve: a segment passes
    /// within [`LOOP_CLOSURE`] of its length of `x` (the chord of a step departs from the
    /// branch by far less) and the tangent interpolated there is parallel to `tangent` to
    /// [`LOOP_TANGENT_COSINE`] (a branch crossing this one at a branch point is not on it).
    fn holds(&self, x: &[f64], tangent: &[f64]) -> bool {
        let n = x.len() - 1;
        let bucket = (x[n] / CURVE_BUCKET).floor();
        if !bucket.is_finite() {
            return false;
        }
        let Some(segments) = self.buckets.get(&(bucket as i64)) else {
            return false;
        };
        segments.iter().any(|&s| {
            let (i, j) = self.segments[s];
            let (a, b) = (&self.x[i], &self.x[j]);
            let Some((theta, gap)) = projection(a, b, x) else {
                return false;
            };
            if gap >= LOOP_CLOSURE * distance(a, b) {
                return false;
            }
            let w = theta.clamp(0.0, 1.0);
            let t: Vec<f64> = (0..=n)
                .map(|k| (1.0 - w) * self.tangent[i][k] + w * self.tangent[j][k])
                .collect();
            cosine(&t, tangent).abs() > LOOP_TANGENT_COSINE
        })
    }
}

/// The branches followed, as curves.
pub(crate) struct Atlas<L> {
    pub(crate) curves: Vec<Curve<L>>,
    /// Whether mirror images are representations of an orbit.
    mirrored: bool,
}

impl<L: Label> Atlas<L> {
    /// The branches of a [`Continuation`]; `mirrored`: whether the model's mirror images
    /// are motions.
    pub(crate) fn of(branches: &[Branch<L>], mirrored: bool) -> Self {
        Self {
            curves: branches.iter().map(Curve::of).collect(),
            mirrored,
        }
    }

    /// The branch that the orbit `x` of `signature` (tangent `tangent`), or another of its
    /// representations, lies on; with `live` (the branch being followed, its last step
    /// `step` long) also that one, against the representations other than `x` itself that
    /// lie more than a step from `x` (near a point that is its own image, such as a branch
    /// point of the asymmetric pair on a symmetric orbit, the image of a point is the point
    /// a little further on: the branch ends only once it has passed there).
    pub(crate) fn joins(
        &self,
        signature: &L,
        x: &[f64],
        tangent: &[f64],
        live: Option<(&Curve<L>, f64)>,
    ) -> Option<usize> {
        let reps = representations(signature, x, tangent, self.mirrored);
        for rep in &reps {
            if let Some(c) = self
                .curves
                .iter()
                .find(|c| c.signature == rep.signature && c.holds(&rep.x, &rep.tangent))
            {
                return Some(c.branch);
            }
            if let Some((live, step)) = live {
                if !rep.identity
                    && live.signature == rep.signature
                    && distance(&rep.x, x) > step
                    && live.holds(&rep.x, &rep.tangent)
                {
                    return Some(live.branch);
                }
            }
        }
        None
    }
}

/// Euclidean distance between two `X` (`α` modulo 2π).
pub(crate) fn distance(a: &[f64], b: &[f64]) -> f64 {
    (0..a.len())
        .map(|k| {
            let d = if k == 0 {
                wrap(b[0] - a[0])
            } else {
                b[k] - a[k]
            };
            d * d
        })
        .sum::<f64>()
        .sqrt()
}

/// Cosine of the angle between two vectors.
pub(crate) fn cosine(a: &[f64], b: &[f64]) -> f64 {
    let dot: f64 = a.iter().zip(b).map(|(u, v)| u * v).sum();
    let na = a.iter().map(|v| v * v).sum::<f64>().sqrt();
    let nb = b.iter().map(|v| v * v).sum::<f64>().sqrt();
    dot / (na * nb)
}

/// The parameter `θ` of the projection of `p` on the line through `a` and `b` (`a + θ (b −
/// a)`) and the distance of `p` from that projection (`α` modulo 2π); `None` for `a = b`.
fn projection(a: &[f64], b: &[f64], p: &[f64]) -> Option<(f64, f64)> {
    let d = |u: &[f64], v: &[f64], k: usize| {
        if k == 0 {
            wrap(u[0] - v[0])
        } else {
            u[k] - v[k]
        }
    };
    let m = a.len();
    let ab: Vec<f64> = (0..m).map(|k| d(b, a, k)).collect();
    let ap: Vec<f64> = (0..m).map(|k| d(p, a, k)).collect();
    let len2: f64 = ab.iter().map(|v| v * v).sum();
    if len2 == 0.0 {
        return None;
    }
    let t = ab.iter().zip(&ap).map(|(u, v)| u * v).sum::<f64>() / len2;
    if !(-LOOP_CLOSURE..=1.0 + LOOP_CLOSURE).contains(&t) {
        return None;
    }
    let dist2: f64 = (0..m).map(|k| (ap[k] - t * ab[k]).powi(2)).sum();
    Some((t, dist2.sqrt()))
}

/// Whether the segment from `a` to `b` passes within [`LOOP_CLOSURE`]` · h` of `p` (angles
/// `α` compared modulo 2π), `p` projecting inside the segment.
pub(crate) fn passes(a: &[f64], b: &[f64], p: &[f64], h: f64) -> bool {
    projection(a, b, p).is_some_and(|(_, gap)| gap < LOOP_CLOSURE * h)
}
