//! Which bodies springs and dashpots hold to the ground, and which groups of the others the
//! stops hold both ways: a structure with a group that nothing holds has no bounded motion.

use super::model::Stop;
use super::End;

/// Which bodies springs and dashpots hold to the ground (frame or base): union–find over the
/// elements, each group grounded when one of its bodies is tied to the frame or the base.
pub(super) struct Grounding {
    parent: Vec<usize>,
    grounded: Vec<bool>,
}

impl Grounding {
    pub(super) fn new(n: usize) -> Self {
        Self {
            parent: (0..n).collect(),
            grounded: vec![false; n],
        }
    }

    fn root(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    pub(super) fn tie(&mut self, a: End, b: End) {
        match (a, b) {
            (End::Body(i), End::Body(j)) => {
                let (ri, rj) = (self.root(i), self.root(j));
                if ri != rj {
                    self.parent[ri] = rj;
                    self.grounded[rj] |= self.grounded[ri];
                }
            }
            (End::Body(i), _) | (_, End::Body(i)) => {
                let r = self.root(i);
                self.grounded[r] = true;
            }
            _ => {}
        }
    }

    /// Per body, its group's id when the group is not grounded.
    pub(super) fn floating(&mut self) -> Vec<Option<usize>> {
        (0..self.parent.len())
            .map(|i| {
                let r = self.root(i);
                (!self.grounded[r]).then_some(r)
            })
            .collect()
    }

    /// The first group whose translation nothing bounds, with the direction it is free in
    /// (`+1`: growing `u`, `−1`: shrinking), if any.
    ///
    /// A group no spring or dashpot ties to the ground translates freely (a rigid mode). It is
    /// held when stops bound its translation both ways against ends that are held themselves
    /// (the frame, a grounded group, or a group held so): a stop `[a, b]` on group `b` bounds
    /// growth by `gap_plus` and shrinking by `gap_minus`, on group `a` the other way round.
    /// Held groups are found by repeating that rule until nothing changes.
    pub(super) fn unbounded(&mut self, stops: &[Stop]) -> Option<(Vec<usize>, f64)> {
        let n = self.parent.len();
        let roots: Vec<usize> = (0..n).map(|i| self.root(i)).collect();
        let mut held: Vec<bool> = (0..n).map(|i| self.grounded[roots[i]]).collect();
        let end_held = |held: &[bool], end: Option<usize>| end.is_none_or(|j| held[roots[j]]);
        loop {
            let mut changed = false;
            for g in 0..n {
                if roots[g] != g || held[g] {
                    continue;
                }
                let (mut up, mut down) = (false, false);
                for stop in stops {
                    let (at_plus, at_minus) = (
                        stop.plus.is_some_and(|j| roots[j] == g),
                        stop.minus.is_some_and(|j| roots[j] == g),
                    );
                    if at_plus && !at_minus && end_held(&held, stop.minus) {
                        up |= stop.gap_plus.is_finite();
                        down |= stop.gap_minus.is_finite();
                    } else if at_minus && !at_plus && end_held(&held, stop.plus) {
                        up |= stop.gap_minus.is_finite();
                        down |= stop.gap_plus.is_finite();
                    }
                }
                if up && down {
                    held[g] = true;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        let first = (0..n).find(|&i| !held[roots[i]])?;
        let group: Vec<usize> = (0..n).filter(|&i| roots[i] == roots[first]).collect();
        // Name the direction the group is free in: the first the stops leave open.
        let g = roots[first];
        let up = stops.iter().any(|stop| {
            let at_plus = stop.plus.is_some_and(|j| roots[j] == g);
            let at_minus = stop.minus.is_some_and(|j| roots[j] == g);
            (at_plus && !at_minus && end_held(&held, stop.minus) && stop.gap_plus.is_finite())
                || (at_minus
                    && !at_plus
                    && end_held(&held, stop.plus)
                    && stop.gap_minus.is_finite())
        });
        Some((group, if up { -1.0 } else { 1.0 }))
    }
}
