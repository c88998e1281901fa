//! [`ExpSum::max_abs`] for several functions of one flight: the coordinates a run records
//! share their rates, and the bisection of `[0, horizon]` visits the same points for each of
//! them down to the depth where their refinements part, so the exponentials there are
//! evaluated once for all of them.

use super::*;

/// Bisection nodes of [`ExpSum::max_abs`] whose exponentials are kept: the heap-numbered
/// nodes `1..NODES` (the root interval `[0, horizon]` is `1`, the halves of node `i` are
/// `2i` and `2i + 1`), eight levels, and two more slots for `s = 0` and `s = horizon`.
/// The bisections of a flight's coordinates part early, so deeper points are each one
/// coordinate's: on a chain (16 coordinates of 17 terms) 256 nodes keep nearly all that
/// sharing saves, and more save little (see the performance page, `docs/performance.md`).
const NODES: usize = 256;

/// The exponentials `e^{μ_j s}` of one flight's rates at the points [`ExpSum::max_abs`]
/// evaluates, shared by the functions of that flight ([`ExpSum::max_abs_shared`]): every
/// value is the one the crate's `cexp` (`e^{μ s}`) gives for the same rate and time (rates
/// compared bit for bit, times too), so a shared search returns what [`ExpSum::max_abs`]
/// returns, bit for bit.
/// Functions of other rates than the last call's start the kept values afresh.
#[derive(Debug, Clone, Default)]
pub struct SharedPoints {
    /// The rates the kept exponentials are of (the last function's).
    rates: Vec<C64>,
    /// `(NODES + 2) × rates.len()` exponentials, node by node.
    values: Vec<C64>,
    /// Each node's time, or NaN when its exponentials are not kept (yet).
    times: Vec<f64>,
    /// The bisection's pending intervals `(a, b, node)`, kept to spare an allocation a call.
    stack: Vec<(f64, f64, usize)>,
}

impl SharedPoints {
    /// Keeps the exponentials of `f`'s rates from now on, unless they are already those
    /// (a value kept is a function of the rate and the time alone, both compared bit for
    /// bit, so what is kept stays valid from flight to flight).
    fn adopt(&mut self, f: &ExpSum) {
        let same =
            |a: &C64, b: &C64| a.re.to_bits() == b.re.to_bits() && a.im.to_bits() == b.im.to_bits();
        if f.terms.len() == self.rates.len()
            && f.terms
                .iter()
                .zip(&self.rates)
                .all(|(t, r)| same(&t.rate, r))
        {
            return;
        }
        self.rates.clear();
        self.rates.extend(f.terms.iter().map(|t| t.rate));
        self.values.clear();
        self.values
            .resize((NODES + 2) * self.rates.len(), C64::default());
        self.times.clear();
        self.times.resize(NODES + 2, f64::NAN);
    }

    /// The exponentials at `s`, the point of `node` (`NODES` for `0`, `NODES + 1` for the
    /// horizon), evaluated the first time they are asked for.
    fn at(&mut self, node: usize, s: f64) -> Option<&[C64]> {
        if node >= NODES + 2 {
            return None;
        }
        let n = self.rates.len();
        let values = &mut self.values[node * n..(node + 1) * n];
        if self.times[node].to_bits() != s.to_bits() {
            for (e, &mu) in values.iter_mut().zip(&self.rates) {
                *e = cexp(mu, s);
            }
            self.times[node] = s;
        }
        Some(values)
    }
}

impl ExpSum {
    /// Value and first derivative at `s` given `exps[j] = e^{μ_j s}`: [`Self::eval`]'s sums.
    #[inline]
    fn eval_with(&self, s: f64, exps: &[C64]) -> (f64, f64) {
        let (mut v, mut d) = (0.0, 0.0);
        for (t, &e) in self.terms.iter().zip(exps) {
            let (tv, td) = t.value_at(s, e);
            v += tv;
            d += td;
        }
        (v, d)
    }

    /// [`Self::max_abs`] with the exponentials at its bisection's first points shared with
    /// the other functions of the same flight and `horizon` (`points`, [`SharedPoints`], kept
    /// from call to call):
    /// the same evaluations in the same order, so the same value bit for bit.
    pub fn max_abs_shared(
        &self,
        horizon: f64,
        (floor, tolerance): (f64, f64),
        points: &mut SharedPoints,
    ) -> f64 {
        if self.bounded_by(floor, horizon) {
            return floor;
        }
        let curvature = self.curvature_bound(horizon);
        points.adopt(self);
        let shared = |s: f64, node: usize, points: &mut SharedPoints| match points.at(node, s) {
            Some(exps) => self.eval_with(s, exps),
            None => self.eval(s),
        };
        let mut best = floor
            .max(shared(0.0, NODES, points).0.abs())
            .max(shared(horizon, NODES + 1, points).0.abs());
        let mut stack = std::mem::take(&mut points.stack);
        stack.clear();
        stack.push((0.0, horizon, 1));
        while let Some((a, b, node)) = stack.pop() {
            let m = 0.5 * (a + b);
            let w = 0.5 * (b - a);
            let (fm, dm) = if node < NODES {
                shared(m, node, points)
            } else {
                self.eval(m)
            };
            best = best.max(fm.abs());
            if fm.abs() + dm.abs() * w + 0.5 * curvature * w * w <= best + tolerance
                || w < MAX_ABS_RESOLUTION * horizon
            {
                continue;
            }
            // Children past the kept nodes are numbered `NODES` and above (not kept).
            let (left, right) = if node < NODES {
                (2 * node, 2 * node + 1)
            } else {
                (NODES + 2, NODES + 2)
            };
            stack.push((a, m, left));
            stack.push((m, b, right));
        }
        points.stack = stack;
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Functions of the same rates, as one flight's coordinates are.
    fn coordinates() -> Vec<ExpSum> {
        let rates = [
            C64::new(-0.05, 1.3),
            C64::new(-0.02, 2.9),
            C64::new(-0.11, 0.7),
            C64::new(0.0, 2.0),
        ];
        (0..6)
            .map(|k| {
                let k = k as f64;
                ExpSum {
                    terms: rates
                        .iter()
                        .enumerate()
                        .map(|(j, &rate)| Term {
                            poly: [
                                C64::new((k + 1.0) * (0.3 + j as f64), 0.2 * k - 0.1 * j as f64),
                                C64::default(),
                                C64::default(),
                                C64::default(),
                            ],
                            rate,
                        })
                        .collect(),
                }
            })
            .collect()
    }

    #[test]
    fn shared_amplitudes_are_max_abs_bit_for_bit() {
        let mut points = SharedPoints::default();
        for horizon in [0.3, 2.0, 7.5] {
            for (floor, tolerance) in [(0.0, 1e-9), (1.0, 1e-6), (3.0, 1e-12)] {
                for f in coordinates() {
                    let alone = f.max_abs(horizon, floor, tolerance);
                    let shared = f.max_abs_shared(horizon, (floor, tolerance), &mut points);
                    assert_eq!(alone.to_bits(), shared.to_bits(), "{horizon} {floor}");
                }
            }
        }
        // Other rates start the kept values afresh.
        let mut other = coordinates().remove(0);
        other.terms[1].rate = C64::new(-0.3, 4.0);
        let alone = other.max_abs(2.0, 0.0, 1e-9);
        let shared = other.max_abs_shared(2.0, (0.0, 1e-9), &mut points);
        assert_eq!(alone.to_bits(), shared.to_bits());
    }
}
