//! Periodicity: the stroboscopic sections and their least period.

use super::*;

/// The floor of the scale of [`repeat_error`]: the gap, or the motion's own size (the largest
/// state in `ring`) when that is smaller, so that a unit that never comes near its stops is
/// judged on its own scale.
pub(super) fn scale_floor(ring: &Sections, gap: f64) -> f64 {
    gap.min(ring.norms.iter().copied().fold(0.0, f64::max))
}

/// The stroboscopic history of a run: the states at its last sections, at most `capacity`,
/// each with its norm, computed once when it is recorded (the periodicity test reads every
/// norm at every section). A full history recycles its oldest state's storage.
pub(super) struct Sections {
    pub(super) states: VecDeque<DVector<f64>>,
    pub(super) norms: VecDeque<f64>,
    pub(super) capacity: usize,
}

impl Sections {
    /// An empty history of at most `capacity` sections.
    pub(super) fn new(capacity: usize) -> Self {
        Self {
            states: VecDeque::with_capacity(capacity),
            norms: VecDeque::with_capacity(capacity),
            capacity,
        }
    }

    /// Records the state `y` at a section, dropping the oldest beyond the capacity.
    pub(super) fn push(&mut self, y: &DVector<f64>) {
        let recycled = (self.states.len() >= self.capacity)
            .then(|| {
                self.norms.pop_front();
                self.states.pop_front()
            })
            .flatten();
        match recycled {
            Some(mut v) => {
                v.copy_from(y);
                self.states.push_back(v);
            }
            None => self.states.push_back(y.clone()),
        }
        self.norms.push_back(y.norm());
    }

    /// Sections recorded.
    pub(super) fn len(&self) -> usize {
        self.states.len()
    }
}

/// Largest `|x_k − x_{k−p}|` over the last two sections (`∞` if too few), relative to
/// `max(|x_k|, floor)`.
pub(super) fn repeat_error(ring: &Sections, p: usize, floor: f64) -> f64 {
    let len = ring.len();
    if len <= p + 1 {
        return f64::INFINITY;
    }
    (0..2)
        .map(|back| {
            let a = &ring.states[len - 1 - back];
            let b = &ring.states[len - 1 - back - p];
            let diff = squared_distance(a, b).sqrt();
            diff / ring.norms[len - 1 - back].max(floor).max(SCALE_FLOOR)
        })
        .fold(0.0, f64::max)
}

/// `|a − b|²`, summed in order over the entries as slices (nalgebra's element iterators cost
/// several times the arithmetic here: the periodicity test was 8 % of a sweep's
/// steady-state runs, half of it in those iterators).
#[inline]
fn squared_distance(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    a.as_slice()
        .iter()
        .zip(b.as_slice())
        .map(|(x, y)| (x - y) * (x - y))
        .sum()
}

/// The margin of [`least_period`]'s first test (whether [`repeat_error`] certainly exceeds
/// its bound): far above the few rounding units of a sum of squares and its square root.
pub(super) const NO_REPEAT_MARGIN: f64 = 1.01;

/// The least `p` with `|x_k − x_{k−p}| ≤ tol·scale` at the last two sections, provided no
/// smaller multiplicity comes within [`AMBIGUITY`] of the tolerance (then it is too early to
/// tell, and `None` is returned).
///
/// Each `p` is first tested on whether [`repeat_error`] certainly exceeds `AMBIGUITY · tol`,
/// from the squared difference at the last section alone, without a square root or a
/// division: most multiplicities at most sections are far from repeating, and the
/// periodicity test is a sizeable share of a run with few impacts per period. The margin of
/// 1 % ([`NO_REPEAT_MARGIN`]) covers the rounding of the squares and the square root, so that
/// the test decides exactly as `repeat_error` would. Its limit (the same for every `p`) and
/// the last state are formed once and the earlier states walked back from the last (the
/// test made per `p` through the ring's indices was 2.8 % of the `steady_sweep` example's
/// instructions).
pub(super) fn least_period(ring: &Sections, p_max: usize, tol: f64, gap: f64) -> Option<u32> {
    let floor = scale_floor(ring, gap);
    let len = ring.len();
    if len <= 2 {
        return None;
    }
    let last = &ring.states[len - 1];
    let limit =
        NO_REPEAT_MARGIN * (AMBIGUITY * tol) * ring.norms[len - 1].max(floor).max(SCALE_FLOOR);
    for (p, earlier) in (1..=p_max).zip(ring.states.iter().rev().skip(1)) {
        if len <= p + 1 {
            return None;
        }
        if squared_distance(last, earlier) > limit * limit {
            continue;
        }
        let d = repeat_error(ring, p, floor);
        if d <= tol {
            return Some(p as u32);
        }
        if d <= AMBIGUITY * tol {
            return None;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`least_period`] as it was before its first test: every multiplicity's exact
    /// [`repeat_error`].
    pub(super) fn least_period_exact(
        ring: &Sections,
        p_max: usize,
        tol: f64,
        gap: f64,
    ) -> Option<u32> {
        let floor = scale_floor(ring, gap);
        for p in 1..=p_max {
            if ring.len() <= p + 1 {
                return None;
            }
            let d = repeat_error(ring, p, floor);
            if d <= tol {
                return Some(p as u32);
            }
            if d <= AMBIGUITY * tol {
                return None;
            }
        }
        None
    }

    /// Rings of states that repeat with period 1–4 up to a perturbation swept across the
    /// tolerance and the ambiguity band (random, or alternating as a transient through a
    /// multiplier −1), at scales from 1e-8 to 1e8: the shortcut decides
    /// exactly as every multiplicity's exact error does, and the sweep reaches all three
    /// outcomes (a period, too early to tell, none).
    #[test]
    pub(super) fn the_shortcut_decides_as_the_exact_errors() {
        let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut uniform = move || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let tol = 1e-9;
        let (mut periodic, mut ambiguous, mut none) = (0, 0, 0);
        for case in 0..4000 {
            let scale = 10f64.powi((case % 17) as i32 - 8);
            let period = 1 + (case / 2) % 4;
            let size = 10f64.powf(-12.0 + 10.0 * (uniform() + 0.5));
            let cycle: Vec<DVector<f64>> = (0..period)
                .map(|_| DVector::from_fn(4, |_, _| scale * uniform()))
                .collect();
            // Half the cases: a transient through a multiplier −1 (the state alternates by a
            // fixed `size` about a period-`period` cycle), ambiguous at `period` while it
            // repeats at `2 period`.
            let alternating = DVector::from_fn(4, |_, _| scale * size * uniform());
            let mut ring = Sections::new(18);
            for k in 0..18 {
                let noise = if case % 2 == 0 {
                    DVector::from_fn(4, |_, _| scale * size * uniform())
                } else if k % 2 == 0 {
                    alternating.clone()
                } else {
                    -&alternating
                };
                ring.push(&(&cycle[k % period] + noise));
            }
            let exact = least_period_exact(&ring, 16, tol, 0.5 * scale);
            assert_eq!(
                least_period(&ring, 16, tol, 0.5 * scale),
                exact,
                "case {case}"
            );
            let smallest = (1..=16)
                .map(|p| repeat_error(&ring, p, scale_floor(&ring, 0.5 * scale)))
                .fold(f64::INFINITY, f64::min);
            match exact {
                Some(_) => periodic += 1,
                None if smallest <= AMBIGUITY * tol => ambiguous += 1,
                None => none += 1,
            }
        }
        assert!(
            periodic > 100 && ambiguous > 100 && none > 100,
            "{periodic} {ambiguous} {none}"
        );
    }
}
