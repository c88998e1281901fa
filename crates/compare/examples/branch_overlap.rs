//! Checks that the study's continuation (`cargo xtask figures`, reading A) follows each branch
//! once: runs the study on the paper scene and prints its branches (and how many have points),
//! points and events, the points that retrace their own branch (within a tenth of a segment's
//! length of a segment at least 20 points away: a loop's closing step puts one or two there),
//! and the branches that lie on an earlier branch of the same signature for nine tenths of their
//! points or more (a branch of one point that joins at its seed counts).
//!
//! ```text
//! cargo run --release -p rattle-compare --example branch_overlap
//! ```
//!
//! A branch followed once leaves only the loops' closing steps among the retracing points, and
//! only short branches (a few points, ended at their seed or a few steps on: `joins`) on an
//! earlier one; many retracing points, or long branches on an earlier one, are a branch
//! followed twice.

use rattle_analytic::{Branch, ContinuationPoint};
use rattle_compare::scene::Scene;
use rattle_compare::study::{Study, StudySize};
use rattle_event_driven::SimulationOptions;
use std::f64::consts::{PI, TAU};

/// `X = (α, φ₂ … φₙ, ω)` of a point.
fn unknowns(p: &ContinuationPoint) -> Vec<f64> {
    [
        &[p.alpha][..],
        p.impact_phases.get(1..).unwrap_or(&[]),
        &[p.omega],
    ]
    .concat()
}

/// `b − a`, its first entry (`α`) modulo 2π in `[−π, π)`.
fn difference(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter()
        .zip(b)
        .enumerate()
        .map(|(k, (u, v))| {
            let d = v - u;
            if k == 0 {
                (d + PI).rem_euclid(TAU) - PI
            } else {
                d
            }
        })
        .collect()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(u, v)| u * v).sum()
}

/// Whether `p` lies within a tenth of the length of the segment from `a` to `b`.
fn on_segment(a: &[f64], b: &[f64], p: &[f64]) -> bool {
    let (ab, ap) = (difference(a, b), difference(a, p));
    let length2 = dot(&ab, &ab);
    if length2 == 0.0 {
        return false;
    }
    let t = (dot(&ab, &ap) / length2).clamp(0.0, 1.0);
    let off: Vec<f64> = ap.iter().zip(&ab).map(|(p, b)| p - t * b).collect();
    dot(&off, &off) < 0.01 * length2
}

/// Whether `p` lies on the polyline `xs` (on any of its segments, but those whose first
/// vertex is within `skip` of `except`).
fn on_polyline(xs: &[Vec<f64>], p: &[f64], except: Option<(usize, usize)>) -> bool {
    (0..xs.len().saturating_sub(1))
        .filter(|&j| except.is_none_or(|(i, skip)| j + skip < i || j > i + skip))
        .any(|j| on_segment(&xs[j], &xs[j + 1], p))
}

fn main() {
    let options = SimulationOptions {
        max_periods: 4000,
        ..SimulationOptions::default()
    };
    let study = Study::run(&Scene::paper(), StudySize::full(), &options, false);
    let branches: &[Branch] = &study.branches.branches;
    let xs: Vec<Vec<Vec<f64>>> = branches
        .iter()
        .map(|b| b.points.iter().map(unknowns).collect())
        .collect();
    let points: usize = xs.iter().map(Vec::len).sum();
    let retraced: Vec<usize> = xs
        .iter()
        .map(|x| {
            (0..x.len())
                .filter(|&i| on_polyline(x, &x[i], Some((i, 20))))
                .count()
        })
        .collect();
    let retracing: usize = retraced.iter().sum();
    let mostly: Vec<(usize, String, usize, usize)> = retraced
        .iter()
        .enumerate()
        .filter(|&(i, &r)| 10 * r > xs[i].len())
        .map(|(i, &r)| (i, branches[i].signature.to_string(), xs[i].len(), r))
        .collect();
    let mut on_earlier = Vec::new();
    for (i, b) in branches.iter().enumerate() {
        let earlier: Vec<&Vec<Vec<f64>>> = (0..i)
            .filter(|&j| branches[j].signature == b.signature)
            .map(|j| &xs[j])
            .collect();
        let covered = xs[i]
            .iter()
            .filter(|p| earlier.iter().any(|x| on_polyline(x, p, None)))
            .count();
        if !xs[i].is_empty() && 10 * covered >= 9 * xs[i].len() {
            on_earlier.push((i, b.signature.to_string(), xs[i].len()));
        }
    }
    println!(
        "{} branches ({} with points), {points} points, {} events",
        branches.len(),
        branches.iter().filter(|b| !b.points.is_empty()).count(),
        study.branches.events.len()
    );
    println!("{retracing} points retrace their own branch");
    println!(
        "{} branches retrace more than a tenth of their points (index, signature, points, \
         retracing): {mostly:?}",
        mostly.len()
    );
    println!(
        "{} branches lie on an earlier one (index, signature, points): {on_earlier:?}",
        on_earlier.len()
    );
}
