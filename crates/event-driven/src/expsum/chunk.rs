//! One chunk's test: the Taylor enclosures that exclude it, the monotone bracket that is
//! polished, the bisection of what is left; the quadratic estimates.

use super::*;

/// A recalled exit ([`Seeds::recalled`]) starts a polish, as at the root
/// ([`PolishStart::AtRoot`]), when Newton's step from it is at most this fraction of the
/// chunk's half-width `w`: the flight repeats the recalled one to a few parts in a million
/// (a periodic motion's flights repeat to rounding). A looser threshold, a quarter of the seed
/// points' spacing (`w/256`), with the recall in every run, moves the simulator's
/// Newton-polished `+-` orbit of the paper's unit at ω = 3.1496 from 3.2e-15 to 2.7e-12 of the
/// analytic one (`rattle compare`), where this one keeps 3.2e-15; the unit's steady flights
/// need no more (`unit_long` takes the same time).
pub(super) const RECALL_STEP: f64 = 4e-6;

/// A recalled exit is tried only within this fraction of the chunk's half-width `w` of the
/// quadratic model's guess (which a steady flight's exit can miss by `w/80`).
pub(super) const RECALL_REACH: f64 = 0.125;

/// Halvings of the Taylor clearance from its first trial length before giving up (clearance
/// `0` below `limit / 2¹⁶`): past that, the grid search costs less than more halvings.
pub(super) const CLEARANCE_HALVINGS: usize = 16;

/// The largest `h ≤ limit` (halving from `limit`, `0` below `limit / 2¹⁶`) such that `f`
/// cannot leave `(lo − depth, hi + depth)` on `[0, h]`, from the Taylor expansion at `0`
/// (`taylor = [f, f', f'', f''']`) and a bound `fourth` on `|f''''|`: on each side
/// `g = ±(f − edge) + depth`, `g(t) ≥ g₀ + g₁t + ½g₂t² + ⅙g₃t³ − fourth·t⁴/24`, and the
/// minimum over `[0, h]` of the cubic that bounds this from below (`t⁴ ≤ h t³` absorbed into
/// the cubic coefficient) is found in closed form. A flight that departs from a stop with
/// zero velocity (a plastic impact, a release) is cleared this way for a good part of its
/// departure, where bisection would need a level per halving.
pub(super) fn taylor_clearance(
    taylor: [f64; 4],
    fourth: f64,
    (lo, hi): (f64, f64),
    depth: f64,
    limit: f64,
) -> f64 {
    // Lower bound of g on [0, h] for g with Taylor coefficients (g0, g1, g2, g3):
    // q(t) = g0 + g1 t + ½g2 t² + (⅙g3 − fourth·h/24) t³ ≤ g(t), minimised over the ends
    // and the roots of q' in (0, h).
    let min_on = |g: [f64; 4], h: f64| -> f64 {
        let (c1, c2, c3) = (g[1], 0.5 * g[2], g[3] / 6.0 - fourth * h / 24.0);
        let q = |t: f64| g[0] + t * (c1 + t * (c2 + t * c3));
        let mut least = g[0].min(q(h));
        // q'(t) = c1 + 2c2 t + 3c3 t².
        let (a, b, c) = (3.0 * c3, 2.0 * c2, c1);
        let roots = if a == 0.0 {
            [-c / b, f64::NAN]
        } else {
            let disc = b * b - 4.0 * a * c;
            if disc < 0.0 {
                [f64::NAN, f64::NAN]
            } else {
                let q = -0.5 * (b + b.signum() * disc.sqrt());
                [q / a, c / q]
            }
        };
        for t in roots {
            if t > 0.0 && t < h {
                least = least.min(q(t));
            }
        }
        least
    };
    let [f0, f1, f2, f3] = taylor;
    let below = [f0 - lo + depth, f1, f2, f3];
    let above = [hi + depth - f0, -f1, -f2, -f3];
    if !(below[0] > 0.0 && above[0] > 0.0 && fourth.is_finite()) {
        return 0.0;
    }
    let mut h = limit;
    for _ in 0..CLEARANCE_HALVINGS {
        if min_on(below, h) > 0.0 && min_on(above, h) > 0.0 {
            return h;
        }
        h *= 0.5;
    }
    0.0
}

/// Whether a start that departs from an edge of `(lo, hi)` (or lies inside) provably makes
/// no exit on `(0, length]`, from `(f, f', f'')` at `0` and `jerk ≥ sup|f'''|`: the edge it
/// moves away from (`f'(0) > 0`: `lo`) is not reached again when `f(t) − f(0) ≥ t (f'(0) +
/// ½f''(0)t − ⅙ jerk t²) > 0` on `(0, length]` (a concave quadratic in `t`, positive at `0`,
/// so checked at `length`) and `f(0)` is no deeper than `depth` beyond it (a start on the
/// edge moving inside is no exit, [`ExpSum::first_exit`]); the other edge is not reached when
/// the quadratic model's largest excursion over `[0, length]` plus `⅙ jerk length³` stays
/// short of it. An impact's flight starts so, on the stop and moving away from it fast: its
/// first chunk is excluded without a chunk test.
#[inline]
pub(super) fn departs(
    (f, d, dd): (f64, f64, f64),
    jerk: f64,
    (lo, hi): (f64, f64),
    depth: f64,
    length: f64,
) -> bool {
    // Mirrored so that the motion is upward, away from `lower`, towards `upper`.
    let (f, d, dd, lower, upper) = if d > 0.0 {
        (f, d, dd, lo, hi)
    } else if d < 0.0 {
        (-f, -d, -dd, -hi, -lo)
    } else {
        return false;
    };
    let cubic = jerk * length * length * length / 6.0;
    let stays_clear = d + 0.5 * dd * length - jerk * length * length / 6.0 > 0.0;
    // The largest of `d t + ½dd t²` on `[0, length]`: at `length` or at the vertex.
    let mut rise = (d + 0.5 * dd * length) * length;
    if dd < 0.0 && -d / dd < length {
        rise = rise.max(-0.5 * d * d / dd);
    }
    stays_clear && f > lower - depth && f + rise.max(0.0) + cubic < upper
}

/// Whether `f` stays inside `(lo, hi)` on `[m − w, m + w]`, given `(f, f', f'')` at `m` and
/// `cubic = M₃ w³/6` (`M₃` a bound on `|f'''|`): `f(m + τ) = f + f'τ + ½f''τ² + R`,
/// `|R| ≤ cubic`, and the quadratic's extremes over `|τ| ≤ w` are at the ends or at its
/// vertex. Keeping the sign of `f''` makes a motion that turns back short of a stop (a near
/// graze) excluded at once, where `|f'|w + ½|f''|w²` would need many bisections.
#[inline]
pub(super) fn inside(
    (f, d, dd): (f64, f64, f64),
    w: f64,
    cubic: f64,
    (lo, hi): (f64, f64),
) -> bool {
    let ends = 0.5 * dd * w * w;
    let (mut upper, mut lower) = ((d * w).abs() + ends, ends - (d * w).abs());
    if dd != 0.0 && d.abs() <= dd.abs() * w {
        let vertex = -0.5 * d * d / dd;
        if dd < 0.0 {
            upper = upper.max(vertex);
        } else {
            lower = lower.min(vertex);
        }
    }
    f + upper + cubic < hi && f + lower - cubic > lo
}

/// Whether `f` stays inside `(lo, hi)` on `[m − w, m + w]`, given `(f, f', f'', f''')` at `m`
/// and `quartic = M₄ w⁴/24` (`M₄` a bound on `|f''''|`): the cubic Taylor polynomial's
/// extremes over `|τ| ≤ w` (at the ends or where its slope vanishes) ± `quartic`.
#[inline]
pub(super) fn inside_cubic(
    (f, d, dd, d3): (f64, f64, f64, f64),
    w: f64,
    quartic: f64,
    (lo, hi): (f64, f64),
) -> bool {
    let p = |t: f64| t * (d + t * (0.5 * dd + t * d3 / 6.0));
    let (mut upper, mut lower) = (p(w).max(p(-w)), p(w).min(p(-w)));
    // p'(τ) = d + dd τ + ½ d3 τ².
    for t in quadratic_roots(0.5 * d3, dd, d) {
        if t.abs() < w {
            upper = upper.max(p(t));
            lower = lower.min(p(t));
        }
    }
    f + upper + quartic < hi && f + lower - quartic > lo
}

/// Whether `f'` keeps its sign on `[m − w, m + w]`, given `(f', f'', f''')` at `m` and
/// `cubic = M₄ w³/6`: the extremes of `f' + f''τ + ½f'''τ²` over `|τ| ≤ w`, ± `cubic`.
#[inline]
pub(super) fn slope_keeps_sign((d, dd, d3): (f64, f64, f64), w: f64, cubic: f64) -> bool {
    let q = |t: f64| d + t * (dd + 0.5 * t * d3);
    let (mut upper, mut lower) = (q(w).max(q(-w)), q(w).min(q(-w)));
    if d3 != 0.0 {
        let t = -dd / d3;
        if t.abs() < w {
            upper = upper.max(q(t));
            lower = lower.min(q(t));
        }
    }
    lower > cubic || upper < -cubic
}

/// The real roots of `a t² + b t + c` (NaN where there is none), without cancellation.
#[inline]
pub(super) fn quadratic_roots(a: f64, b: f64, c: f64) -> [f64; 2] {
    if a == 0.0 {
        return [-c / b, f64::NAN];
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return [f64::NAN, f64::NAN];
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    [q / a, c / q]
}

/// The first `t > 0` at which `f0 + d0 t + ½ dd0 t²` reaches `lo` or `hi` (`∞` if never):
/// an estimate of a flight's length, not a bound.
pub(super) fn quadratic_exit(f0: f64, d0: f64, dd0: f64, lo: f64, hi: f64) -> f64 {
    // Smallest positive root of ½ dd0 t² + d0 t + c where the model moves out of the band
    // (`outward` · slope > 0): a start on an edge moving inside is no exit.
    let root = |c: f64, outward: f64| -> f64 {
        let a = 0.5 * dd0;
        let candidates = if a == 0.0 {
            [-c / d0, f64::NAN]
        } else {
            let disc = d0 * d0 - 4.0 * a * c;
            if disc < 0.0 {
                return f64::INFINITY;
            }
            // Roots without cancellation.
            let q = -0.5 * (d0 + d0.signum() * disc.sqrt());
            [q / a, c / q]
        };
        candidates
            .into_iter()
            .filter(|&t| t > 0.0 && outward * (d0 + dd0 * t) > 0.0)
            .fold(f64::INFINITY, f64::min)
    };
    // A side the model moves away from throughout (`f'` and `f''` both of the other sign, so
    // `d0 + dd0·t` keeps that sign for every `t > 0`) has no candidate: `∞` without the root's
    // division and square root.
    let upper = if d0 <= 0.0 && dd0 <= 0.0 {
        f64::INFINITY
    } else {
        root(f0 - hi, 1.0)
    };
    let lower = if d0 >= 0.0 && dd0 >= 0.0 {
        f64::INFINITY
    } else {
        root(f0 - lo, -1.0)
    };
    upper.min(lower)
}

/// Whether `f0 + d0 t + ½ dd0 t²` stays strictly inside `(lo, hi)` for every `t` in `(0,
/// until]` (a start on an edge moving inside counts as inside): then [`quadratic_exit`] is
/// later than `until`. Its largest and smallest values there are at `until` or at its vertex;
/// no square root, and a division only for a vertex within the interval. `false` for an
/// `until` that is not finite.
#[inline]
pub(super) fn quadratic_stays_inside(
    (f0, d0, dd0): (f64, f64, f64),
    (lo, hi): (f64, f64),
    until: f64,
) -> bool {
    if !until.is_finite() {
        return false;
    }
    let end = f0 + until * (d0 + 0.5 * dd0 * until);
    let (mut top, mut bottom) = (end, end);
    // The vertex `−d0/dd0` lies in `(0, until)` when the slope turns there.
    if d0 * dd0 < 0.0 && d0.abs() < dd0.abs() * until {
        let vertex = f0 - 0.5 * d0 * d0 / dd0;
        top = top.max(vertex);
        bottom = bottom.min(vertex);
    }
    f0 <= hi && f0 >= lo && top < hi && bottom > lo
}

/// What one search's chunk tests share: the band `(lo, hi)`, the bounds `jerk ≥ sup|f'''|` and
/// `fourth ≥ sup|f''''|` on `[0, horizon]` (`NaN` until a test first needs it), the
/// `(time, depth)` tolerances, and the search's scratch: the bisection's intervals, the
/// derivative coefficients, the polish's exponentials and those at one bisection point;
/// `fastest`, the largest `|Re μ| + |Im μ|` of the terms, the search's grid's
/// ([`GridSteps::fastest`](super::cache::GridSteps)), for the polish.
pub(super) struct ChunkTest<'s> {
    pub(super) band: (f64, f64),
    pub(super) fastest: f64,
    pub(super) jerk: f64,
    pub(super) fourth: f64,
    pub(super) horizon: f64,
    pub(super) tolerances: (f64, f64),
    pub(super) intervals: &'s mut Vec<(f64, f64, f64, f64)>,
    pub(super) derivatives: &'s mut Derivatives,
    pub(super) polish: &'s mut Exponentials,
    pub(super) point: &'s mut Vec<C64>,
}

impl ExpSum {
    /// The first exit from the band within one chunk `[a, b]` (values `fa`, `fb` at its ends,
    /// value and derivatives `at_m` at its midpoint), by the bounds of [`Self::first_exit`];
    /// bisects left first. With a `seed` (the chunk's midpoint exponentials), the polish starts
    /// at the seed point nearest its guess.
    pub(super) fn exit_in_chunk(
        &self,
        test: &mut ChunkTest<'_>,
        chunk: (f64, f64, f64, f64),
        at_m: (f64, f64, f64, f64),
        mut seed: Option<Seed<'_>>,
    ) -> Option<(f64, i8)> {
        let (lo, hi) = test.band;
        let (jerk, horizon, fastest) = (test.jerk, test.horizon, test.fastest);
        let (time_tolerance, depth_tolerance) = test.tolerances;
        let fourth = &mut test.fourth;
        let intervals = &mut *test.intervals;
        let derivatives: &Derivatives = test.derivatives;
        let scratch = &mut *test.polish;
        let point = &mut *test.point;
        intervals.clear();
        intervals.push(chunk);
        let mut known_m = Some(at_m);
        while let Some((a, b, fa, fb)) = intervals.pop() {
            let m = 0.5 * (a + b);
            let w = 0.5 * (b - a);
            let (fm, dm, ddm, d3m) = match known_m.take() {
                Some(at_m) => at_m,
                None => self.eval3_at_split(m, seed.as_mut(), derivatives, point),
            };
            // f(m + τ) = f(m) + f'(m)τ + ½f''(m)τ² + R, |R| ≤ ⅙ M₃ w³ on [a, b].
            if inside((fm, dm, ddm), w, jerk * w * w * w / 6.0, (lo, hi)) {
                continue;
            }
            // Monotone when f' cannot reach zero: |f'(t) − f'(m)| ≤ |f''(m)| w + ½ M₃ w².
            let mut monotone = dm.abs() > ddm.abs() * w + 0.5 * jerk * w * w;
            if !monotone && d3m.is_finite() {
                // One order more, with f'''(m) known and M₄ bounding |f''''|: the cubic model
                // ± M₄ w⁴/24, and f' = f'(m) + f''(m)τ + ½f'''(m)τ² ± M₄ w³/6. A near graze
                // is settled in fewer halvings.
                if fourth.is_nan() {
                    *fourth = self.fourth_derivative_bound(horizon);
                }
                let w3 = w * w * w;
                if inside_cubic((fm, dm, ddm, d3m), w, *fourth * w3 * w / 24.0, (lo, hi)) {
                    continue;
                }
                monotone = slope_keeps_sign((dm, ddm, d3m), w, *fourth * w3 / 6.0);
            }
            if monotone {
                // Monotone on [a, b]: it can only reach `hi` if increasing, `lo` if decreasing.
                // Quadratic model at m: a first guess for Newton.
                let guess = |target: f64| {
                    let disc = dm * dm - 2.0 * ddm * (fm - target);
                    let step = if ddm != 0.0 && disc >= 0.0 {
                        (-dm + dm.signum() * disc.sqrt()) / ddm
                    } else {
                        (target - fm) / dm
                    };
                    (m + step).clamp(a, b)
                };
                // The polish of `sign·(f − level)` from the guess: from the seed point
                // nearest it when there is one in the bracket, else from fresh exponentials.
                let mut polish_to = |sign: f64, level: f64| {
                    let guess = guess(level);
                    // A recalled exit that the flight repeats, else the seed point nearest
                    // the guess.
                    let recalled = seed.as_mut().and_then(|seed| {
                        self.recalled_start(seed, derivatives, ((a, b), guess, level), scratch)
                    });
                    let seeded = recalled
                        .map(|(s, at_s)| (s, PolishStart::AtRoot(at_s)))
                        .or_else(|| {
                            seed.as_mut()
                                .and_then(|seed| {
                                    seed.start_near(guess, (a, b), &self.terms, scratch)
                                })
                                .map(|s| (s, PolishStart::Near))
                        });
                    let crossing = Crossing {
                        fastest,
                        f: self,
                        derivatives,
                        sign,
                        level,
                        jerk,
                    };
                    match seeded {
                        Some(start) => {
                            polish_from(&crossing, (a, b), start, time_tolerance, scratch)
                        }
                        None => polish(&crossing, (a, b), guess, time_tolerance, scratch),
                    }
                };
                if dm > 0.0 {
                    if fa >= hi {
                        return Some((a, 1)); // on the upper edge at the start, moving out
                    }
                    if fb >= hi {
                        // hi − f: positive, then ≤ 0.
                        return Some((polish_to(-1.0, hi), 1));
                    }
                } else {
                    if fa <= lo {
                        return Some((a, -1));
                    }
                    if fb <= lo {
                        // f − lo: positive, then ≤ 0.
                        return Some((polish_to(1.0, lo), -1));
                    }
                }
                continue;
            }
            // A constant resting within `depth` of an edge (a free body at rest on its stop,
            // its carrier held): neither excluded nor monotone, so bisection would split down
            // to `time_tolerance` everywhere, `(b − a)/time_tolerance` evaluations, and find
            // no exit (every split point is `fm`, never `depth` beyond the edge). Same answer
            // at once. `f' = f'' = 0` at `m` is exact and rare for any other function, so the
            // terms are read only then.
            if dm == 0.0
                && ddm == 0.0
                && fm > lo - depth_tolerance
                && fm < hi + depth_tolerance
                && self.is_constant()
            {
                continue;
            }
            if w < time_tolerance {
                if fm >= hi + depth_tolerance {
                    return Some((m, 1));
                }
                if fm <= lo - depth_tolerance {
                    return Some((m, -1));
                }
                continue;
            }
            intervals.push((m, b, fm, fb));
            intervals.push((a, m, fa, fm));
        }
        None
    }

    /// A recalled exit in the bracket `[a, b]` ([`Seeds::recalled`], the most recent first)
    /// that the flight repeats: within [`RECALL_REACH`] of the `guess` and with Newton's step
    /// to `f = level` from it within [`RECALL_STEP`]; its exponentials written into `scratch`,
    /// and `(f, f', f'')` there returned with it (the polish's first iterate reads them).
    /// Counts the try ([`Seeds::recall_tried`]); `None` when the key's tries are paused
    /// ([`Seeds::recall_worth_trying`]) or none qualifies.
    fn recalled_start(
        &self,
        seed: &mut Seed<'_>,
        derivatives: &Derivatives,
        ((a, b), guess, level): ((f64, f64), f64, f64),
        scratch: &mut Exponentials,
    ) -> Option<(f64, (f64, f64, f64))> {
        if !seed.seeds.recall_worth_trying() {
            return None;
        }
        let mut start = None;
        for (s, values) in seed.recalled_within((a, b)) {
            if (s - guess).abs() > RECALL_REACH * seed.w {
                continue;
            }
            let (v, d, dd) = derivatives.at(self, s, values);
            if ((v - level) / d).abs() <= RECALL_STEP * seed.w {
                scratch.values.clear();
                scratch.values.extend_from_slice(values);
                scratch.at = s;
                start = Some((s, (v, d, dd)));
                break;
            }
        }
        seed.seeds.recall_tried(start.is_some());
        start
    }

    /// Whether `f` is a constant: every term's polynomial zero, or a constant at rate `0`.
    pub(super) fn is_constant(&self) -> bool {
        let zero = C64::default();
        self.terms.iter().all(|t| {
            t.poly[1..].iter().all(|&c| c == zero) && (t.rate == zero || t.poly[0] == zero)
        })
    }

    /// [`Self::eval3`] at a bisection's split point `s`, the exponentials there taken from the
    /// seed point at `s` when there is one ([`Seed::index_at`]: one product per term from the
    /// chunk's midpoint, with the seed's steps kept from one flight to the next), else
    /// evaluated afresh. On `cargo xtask figures`, 84 of the 142 million split points are seed
    /// points; every output of the figures is bit for bit what fresh exponentials give (maps,
    /// boundaries, agreement), and a map's search costs some 4.5 % fewer instructions so (see
    /// the performance page, `docs/performance.md`).
    #[inline]
    fn eval3_at_split(
        &self,
        s: f64,
        seed: Option<&mut Seed<'_>>,
        derivatives: &Derivatives,
        point: &mut Vec<C64>,
    ) -> (f64, f64, f64, f64) {
        match seed.and_then(|seed| Some((seed.index_at(s)?, seed))) {
            Some((k, seed)) => {
                seed.exponentials_at(k, &self.terms, point);
                derivatives.at3(self, s, point)
            }
            None => self.eval3(s, derivatives, point),
        }
    }

    /// `(f, f', f'', f''')` at `s` (`f''' = NaN` unless every polynomial is a constant), with
    /// the exponentials evaluated afresh into `point`.
    pub(super) fn eval3(
        &self,
        s: f64,
        derivatives: &Derivatives,
        point: &mut Vec<C64>,
    ) -> (f64, f64, f64, f64) {
        point.clear();
        point.extend(self.terms.iter().map(|t| cexp(t.rate, s)));
        derivatives.at3(self, s, point)
    }
}
