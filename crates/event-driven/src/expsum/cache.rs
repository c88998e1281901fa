//! The exponentials a search keeps: the scratch stack, the grids' steps and cached chunks, the
//! polish's seed points and the exponentials of one iterate (the derivative coefficients
//! beside them are [`Derivatives`]).

use super::*;

/// Reusable storage for the interval stack of [`ExpSum::first_exit`]: passing the same one to
/// every search of a run avoids an allocation per search.
#[derive(Debug, Clone, Default)]
pub struct SearchStack {
    pub(super) intervals: Vec<(f64, f64, f64, f64)>,
    /// `e^{μ_j s}` of every term at the current grid point.
    pub(super) exps: Vec<C64>,
    /// The steps of the last grid of a horizon (the searches of functions whose polynomials
    /// are not all constants, or whose rates grow).
    pub(super) grid: GridSteps,
    /// The steps of the fixed grids of the summarised searches, most recently used first (at
    /// most [`FIXED_GRIDS`]: the free flow's, and those of the sets of pairs held on their
    /// stops that the run goes through).
    pub(super) fixed: Vec<GridSteps>,
    /// See [`Derivatives`].
    pub(super) derivatives: Derivatives,
    /// The exponentials of the polishing iterate; after a search, at the exit it found (when
    /// polished).
    pub(super) polish: Exponentials,
    /// The exponentials at one bisection point.
    pub(super) point: Vec<C64>,
    /// The exponentials at the midpoint of the chunk being searched, on the fixed grid of a
    /// summarised search (see [`Seeds`]).
    pub(super) mid: Vec<C64>,
    /// Which function the next search is of, for the exits a grid recalls ([`Seeds::recalled`]):
    /// the caller's (an engine's pair index); `0` by default.
    pub(crate) recall_key: usize,
    /// Whether the searches recall their polished exits as starts for later polishes
    /// ([`Seeds::recalled`]); off by default (the caller's choice: an engine's fixed runs).
    pub(crate) recall: bool,
}

/// Fixed grids kept by a [`SearchStack`] (see [`SearchStack::fixed`]).
pub(super) const FIXED_GRIDS: usize = 4;

/// A grid's exponential steps for one set of rates and one half-width `w`.
#[derive(Debug, Clone, Default)]
pub(super) struct GridSteps {
    /// The rates the steps were computed for.
    pub(super) rates: Vec<C64>,
    /// The half-width `w` (`0` before the first search: no grid has it).
    pub(super) w: f64,
    /// The largest `|Re μ| + |Im μ|` of the rates, for the polish's local polynomial
    /// ([`Local`](super::polish::Local)): formed once per grid rather than at every polish,
    /// where its running maximum is a chain of dependent instructions.
    pub(super) fastest: f64,
    /// `e^{μ_j w}`: one grid step.
    pub(super) steps: Vec<C64>,
    /// `e^{2μ_j w}`: the first chunk's end.
    pub(super) doubled: Vec<C64>,
    /// The polish starts' exponential steps (fixed grids only).
    pub(super) seeds: Seeds,
    /// Per chunk `i < CACHED_CHUNKS` of a fixed grid, `CHUNK_ROWS` rows of one entry per term:
    /// at the chunk's midpoint `m_i = 2wi + w`, `e^{μm}`, `μe^{μm}`, `μ²e^{μm}`, `μ³e^{μm}`, and
    /// at its end `e^{2μw(i+1)}`, each exponential evaluated afresh; then the same values
    /// but the third derivative's ([`PACKED_ROWS`]) term by term, `[e^{μm}, μe^{μm}, μ²e^{μm},
    /// e^{2μw(i+1)}]` for each term in turn, for the packed chunk test
    /// ([`chunk_values_avx`](super::scan)); valid where `chunk_filled`.
    pub(super) chunk_exps: Vec<C64>,
    /// Per chunk, whether its rows in `chunk_exps` are computed.
    pub(super) chunk_filled: Vec<bool>,
}

/// Chunks of a fixed grid whose exponentials a [`GridSteps`] keeps (see
/// [`ExpSum::fixed_search`]); a search over more uses the grid's recurrence.
pub(super) const CACHED_CHUNKS: usize = 256;

/// Rows per chunk in [`GridSteps::chunk_exps`]: five by kind, then [`PACKED_ROWS`] by term.
pub(super) const CHUNK_ROWS: usize = 5 + PACKED_ROWS;

/// The rows of a chunk laid out term by term (four entries per term) after its first five.
pub(super) const PACKED_ROWS: usize = 4;

/// Whether `terms` have the rates `rates`, in order (each compared by `==`), without stopping
/// at the first difference: a search of a fixed grid checks its terms against the grid's at
/// every search, and a comparison that branches on each rate takes a quarter of
/// `fixed_search`'s own time on a chain (a search mostly has the grid's rates).
#[inline]
fn same_rates(rates: &[C64], terms: &[Term]) -> bool {
    rates.len() == terms.len()
        && rates.iter().zip(terms).fold(true, |same, (r, t)| {
            same & (r.re == t.rate.re) & (r.im == t.rate.im)
        })
}

/// The fixed grid of `terms`' rates and half-width `w` among `grids` (most recently used first,
/// at most [`FIXED_GRIDS`]), moved to the front, or made there in place of the least recently
/// used.
pub(super) fn fixed_grid<'g>(
    grids: &'g mut Vec<GridSteps>,
    terms: &[Term],
    w: f64,
) -> &'g mut GridSteps {
    // The most recent grid first, without the rotation (a free flight after a free flight).
    if grids.first().is_some_and(|g| g.matches(terms, w)) {
        return &mut grids[0];
    }
    match grids.iter().position(|g| g.matches(terms, w)) {
        Some(i) => grids[..=i].rotate_right(1),
        None => {
            if grids.len() < FIXED_GRIDS {
                grids.push(GridSteps::default());
            }
            grids.rotate_right(1);
            grids[0].refresh(terms, w);
        }
    }
    &mut grids[0]
}

/// Chunk `i`'s rows of a fixed grid (see [`GridSteps::chunk_exps`]), computed on first use.
/// Inlined: a scan asks for some five chunks a flight, all but the run's first few already
/// filled, so the lookup is one flag test (the filling is out of line, [`fill_chunk_rows`]).
#[inline]
pub(super) fn chunk_rows<'c>(
    exps: &'c mut Vec<C64>,
    filled: &mut Vec<bool>,
    i: usize,
    w: f64,
    terms: &[Term],
) -> &'c [C64] {
    let rows = CHUNK_ROWS * terms.len();
    if !filled.get(i).copied().unwrap_or(false) {
        fill_chunk_rows(exps, filled, i, w, terms);
    }
    &exps[i * rows..(i + 1) * rows]
}

/// Fills chunk `i`'s rows (see [`chunk_rows`]), growing the cache to hold them.
#[cold]
#[inline(never)]
fn fill_chunk_rows(exps: &mut Vec<C64>, filled: &mut Vec<bool>, i: usize, w: f64, terms: &[Term]) {
    let n = terms.len();
    let rows = CHUNK_ROWS * n;
    if filled.len() <= i {
        filled.resize(i + 1, false);
        exps.resize((i + 1) * rows, C64::default());
    }
    let slot = &mut exps[i * rows..(i + 1) * rows];
    let m = 2.0 * w * i as f64 + w;
    let end = 2.0 * w * (i + 1) as f64;
    for (j, t) in terms.iter().enumerate() {
        let e = cexp(t.rate, m);
        let e1 = e * t.rate;
        let e2 = e1 * t.rate;
        slot[j] = e;
        slot[n + j] = e1;
        slot[2 * n + j] = e2;
        slot[3 * n + j] = e2 * t.rate;
        let e_end = cexp(t.rate, end);
        slot[4 * n + j] = e_end;
        slot[5 * n + PACKED_ROWS * j..5 * n + PACKED_ROWS * (j + 1)]
            .copy_from_slice(&[e, e1, e2, e_end]);
    }
    filled[i] = true;
}

/// `Σ_j Re(c_j x_j)`, the terms' constant coefficients `c_j` against `x`.
#[inline]
pub(super) fn real_dot(terms: &[Term], x: &[C64]) -> f64 {
    terms
        .iter()
        .zip(x)
        .map(|(t, x)| t.poly[0].re * x.re - t.poly[0].im * x.im)
        .sum()
}

impl GridSteps {
    /// Whether these are the steps of `terms`' rates and half-width `w`.
    pub(super) fn matches(&self, terms: &[Term], w: f64) -> bool {
        self.w == w && same_rates(&self.rates, terms)
    }

    /// Whether these are the steps of `terms`' rates, whatever the half-width. Every fixed
    /// grid's half-width is its rates' `π/(8 max|μ|)` ([`fixed_grid`]'s callers form it so),
    /// so for a fixed grid this is [`Self::matches`] with that half-width.
    pub(super) fn matches_rates(&self, terms: &[Term]) -> bool {
        self.w > 0.0 && same_rates(&self.rates, terms)
    }

    /// The steps of `terms`' rates and half-width `w`, computed afresh.
    pub(super) fn refresh(&mut self, terms: &[Term], w: f64) {
        self.fastest = terms.iter().fold(0.0, |m, t| larger(m, l1(t.rate)));
        self.steps.clear();
        self.steps.extend(terms.iter().map(|t| cexp(t.rate, w)));
        self.doubled.clear();
        self.seeds.reset();
        self.rates.clear();
        self.rates.extend(terms.iter().map(|t| t.rate));
        self.w = w;
        self.chunk_exps.clear();
        self.chunk_filled.clear();
    }
}

/// Points within a chunk of the fixed grid where a summarised search's polish may start,
/// `m + k w/SEED_DIVISIONS` (`m` the chunk's midpoint, `|k| ≤ SEED_DIVISIONS`): their
/// exponentials follow from those at `m` by one complex product each,
/// `e^{μ(m + kh)} = e^{μm} e^{μkh}`, with `e^{μkh}` computed once per `k` and kept with the
/// grid's steps (the grid's half-width `w` is then the same from one flight to the next). The
/// polish so starts within `h/2` of the quadratic model's guess without evaluating an
/// exponential afresh.
#[derive(Debug, Clone, Default)]
pub(super) struct Seeds {
    /// `e^{μ_j k h}` at `(k + SEED_DIVISIONS)·terms + j`, valid where `filled`.
    pub(super) values: Vec<C64>,
    /// Per `k + SEED_DIVISIONS`, whether its exponentials are computed.
    pub(super) filled: Vec<bool>,
    /// Per recall key ([`SearchStack::recall_key`]: a pair of stops), the exits of its last
    /// [`RECALLED`] polished searches on this grid, most recent first, with the exponentials
    /// there: starts for the polish (see [`ExpSum::exit_in_chunk`]).
    pub(super) recalled: Vec<Vec<(f64, Vec<C64>)>>,
    /// The recall key of the search under way.
    pub(super) key: usize,
    /// Whether the search under way recalls ([`SearchStack::recall`]).
    pub(super) enabled: bool,
    /// Per recall key, the polishes since a recalled exit last started one (see
    /// [`Self::recall_worth_trying`]).
    pub(super) misses: Vec<u32>,
}

/// Polishes of a recall key that try its recalled exits after the last that one started
/// ([`Seeds::recall_worth_trying`]); then one in [`RECALL_RETRY`].
pub(super) const RECALL_TRIES: u32 = 4;

/// See [`RECALL_TRIES`].
pub(super) const RECALL_RETRY: u32 = 32;

/// Whether a polish of a key that has gone `misses` polishes without a recalled exit
/// starting one tries them ([`Seeds::recall_worth_trying`]).
fn tries(misses: u32) -> bool {
    misses < RECALL_TRIES || misses % RECALL_RETRY == 0
}

/// Exits a grid's [`Seeds`] recall per key: two, the flights to either stop.
pub(super) const RECALLED: usize = 2;

impl Seeds {
    /// Whether the polish under way tries the recalled exits of its key: while they start
    /// polishes (a periodic motion, each flight much like one a period earlier), and else one
    /// polish in [`RECALL_RETRY`] after [`RECALL_TRIES`] that found none (a motion that does
    /// not repeat, where each try costs an evaluation of `f` for nothing).
    pub(super) fn recall_worth_trying(&mut self) -> bool {
        if !self.enabled {
            return false;
        }
        if self.misses.len() <= self.key {
            self.misses.resize(self.key + 1, 0);
        }
        let misses = self.misses[self.key];
        let worth = tries(misses);
        if !worth {
            self.misses[self.key] += 1;
        }
        worth
    }

    /// Whether the exit of the search under way is worth recalling: whether one of its key's
    /// next [`RECALLED`] polishes tries the recalled exits ([`Self::recall_worth_trying`]).
    /// A motion that does not repeat so recalls nothing but before a retry.
    fn worth_recalling(&self) -> bool {
        let misses = self.misses.get(self.key).copied().unwrap_or(0);
        (0..RECALLED as u32).any(|k| tries(misses.saturating_add(k)))
    }

    /// Counts a try of the recalled exits ([`Self::recall_worth_trying`]): whether one started
    /// the polish.
    pub(super) fn recall_tried(&mut self, started: bool) {
        if let Some(misses) = self.misses.get_mut(self.key) {
            *misses = if started { 0 } else { misses.saturating_add(1) };
        }
    }

    /// Recalls the exit `s` of the search under way with the exponentials there (dropping its
    /// key's oldest beyond [`RECALLED`]).
    pub(super) fn recall(&mut self, s: f64, values: &[C64]) {
        if !self.enabled || !self.worth_recalling() {
            return;
        }
        if self.recalled.len() <= self.key {
            self.recalled.resize_with(self.key + 1, Vec::new);
        }
        let kept = &mut self.recalled[self.key];
        if kept.len() < RECALLED {
            kept.push((s, Vec::new()));
        }
        kept.rotate_right(1);
        let first = &mut kept[0];
        first.0 = s;
        first.1.clear();
        first.1.extend_from_slice(values);
    }

    /// Forgets every step (the grid's rates or half-width changed).
    pub(super) fn reset(&mut self) {
        self.recalled.clear();
        self.misses.clear();
        self.values.clear();
        self.filled.clear();
        self.filled.resize(2 * SEED_DIVISIONS + 1, false);
    }
}

/// Seed points per half-chunk on either side of a chunk's midpoint (see [`Seeds`]): a start
/// within `w/128` of the guess, `|μ|w/128 ≤ π/1024` for the fastest term, so the polish's
/// first step needs a Taylor series of low degree.
pub(super) const SEED_DIVISIONS: usize = 64;

/// How many units in the last place a bisection's split point and the seed point taken for
/// it may differ ([`Seed::index_at`]): `f` and its derivatives there then differ by
/// `|f'| · 4 ulp(s)` at most, below the rounding of their sums over the terms.
pub(super) const SPLIT_ULPS: f64 = 4.0;

/// A chunk's midpoint and its exponentials, for [`Seeds`].
pub(super) struct Seed<'s> {
    pub(super) m: f64,
    pub(super) w: f64,
    pub(super) mid: &'s [C64],
    pub(super) seeds: &'s mut Seeds,
}

impl Seed<'_> {
    /// The seed point nearest `guess` within `[a, b]`, with its exponentials written into
    /// `exps`; `None` when no seed point lies in `[a, b]` (a bracket narrower than `h`).
    pub(super) fn start_near(
        &mut self,
        guess: f64,
        (a, b): (f64, f64),
        terms: &[Term],
        exps: &mut Exponentials,
    ) -> Option<f64> {
        let divisions = SEED_DIVISIONS as f64;
        let h = self.w / divisions;
        let mut k = ((guess - self.m) / h).round();
        if self.m + k * h < a {
            k += 1.0;
        } else if self.m + k * h > b {
            k -= 1.0;
        }
        let start = self.m + k * h;
        if !(start >= a && start <= b && k.abs() <= divisions) {
            return None;
        }
        self.exponentials_at(k as i64, terms, &mut exps.values);
        exps.at = start;
        Some(start)
    }

    /// The seed point `m + kh` (`|k| ≤ SEED_DIVISIONS`) at `s`, to within [`SPLIT_ULPS`]
    /// units in the last place of `s`: a bisection of the chunk splits its intervals at seed
    /// points for its first `log₂ SEED_DIVISIONS` levels (up to the roundings of `½(a + b)`
    /// and of `m + kh`), and so does that of a head chunk on the seed points in part.
    #[inline]
    pub(super) fn index_at(&self, s: f64) -> Option<i64> {
        let divisions = SEED_DIVISIONS as f64;
        let k = ((s - self.m) / (self.w / divisions)).round();
        let near = (self.point(k as i64) - s).abs() <= SPLIT_ULPS * f64::EPSILON * s.abs();
        (k.abs() <= divisions && near).then_some(k as i64)
    }

    /// The exits recalled for the search under way ([`Seeds::recalled`]) within `[a, b]`,
    /// most recent first, with the exponentials there.
    pub(super) fn recalled_within(
        &self,
        (a, b): (f64, f64),
    ) -> impl Iterator<Item = (f64, &[C64])> {
        self.seeds
            .recalled
            .get(self.seeds.key)
            .into_iter()
            .flatten()
            .filter(move |(s, _)| *s >= a && *s <= b)
            .map(|(s, values)| (*s, &values[..]))
    }

    /// The seed point `m + kh` (`|k| ≤ SEED_DIVISIONS`).
    pub(super) fn point(&self, k: i64) -> f64 {
        self.m + k as f64 * (self.w / SEED_DIVISIONS as f64)
    }

    /// The exponentials at the seed point `m + kh` (`|k| ≤ SEED_DIVISIONS`) into `out`.
    pub(super) fn exponentials_at(&mut self, k: i64, terms: &[Term], out: &mut Vec<C64>) {
        let divisions = SEED_DIVISIONS as i64;
        debug_assert!(k.abs() <= divisions);
        let index = (k + divisions) as usize;
        let n = terms.len();
        if self.seeds.values.len() != (2 * SEED_DIVISIONS + 1) * n {
            self.seeds.values.clear();
            self.seeds
                .values
                .resize((2 * SEED_DIVISIONS + 1) * n, C64::default());
        }
        let steps = &mut self.seeds.values[index * n..(index + 1) * n];
        if !self.seeds.filled[index] {
            let h = self.w / SEED_DIVISIONS as f64;
            for (e, t) in steps.iter_mut().zip(terms) {
                *e = cexp(t.rate, k as f64 * h);
            }
            self.seeds.filled[index] = true;
        }
        out.clear();
        #[cfg(target_arch = "x86_64")]
        if n >= PACKED_TERMS && packed_chunks() {
            out.resize(self.mid.len().min(n), C64::default());
            // SAFETY: the CPU has AVX (`packed_chunks`), the only requirement of the
            // `target_feature` function.
            unsafe { products_avx(self.mid, steps, out) };
            return;
        }
        out.extend(self.mid.iter().zip(steps.iter()).map(|(x, y)| x * y));
    }
}

/// The exponentials at the end of the first chunk, `first_end`: when it is a whole chunk
/// (`chunks > 1`: `first_end = 2w`), from the cache kept with the grid's steps, filled on
/// first use.
pub(super) fn set_exponentials(
    exps: &mut [C64],
    terms: &[Term],
    first_end: f64,
    chunks: usize,
    doubled: &mut Vec<C64>,
) {
    if chunks > 1 && doubled.len() == terms.len() {
        exps.copy_from_slice(doubled);
        return;
    }
    for (e, t) in exps.iter_mut().zip(terms) {
        *e = cexp(t.rate, first_end);
    }
    if chunks > 1 {
        doubled.clear();
        doubled.extend_from_slice(exps);
    }
}

impl SearchStack {
    /// `e^{μ_j s}` of every term of the function last searched, when `s` is the exit that
    /// search returned and was polished (`None` otherwise): what the flow needs for the state
    /// at the exit, without evaluating the exponentials again.
    pub fn exponentials_at(&self, s: f64) -> Option<&[C64]> {
        (self.polish.at == s).then_some(&self.polish.values[..])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bisection of a chunk of the fixed grid (from its ends, halving as
    /// [`ExpSum::exit_in_chunk`] does) splits at seed points for its first
    /// `log₂ SEED_DIVISIONS` levels, and there the seed's exponentials are the library's to
    /// the rounding of the phase; below that level, and between seed points, there is no
    /// seed point.
    #[test]
    fn a_chunks_bisection_splits_at_its_seed_points() {
        let terms: Vec<Term> = [
            C64::new(-0.05, 2.4),
            C64::new(-0.02, 1.2),
            C64::new(0.0, 2.0),
        ]
        .into_iter()
        .map(|rate| Term {
            poly: [
                C64::new(1.0, 0.0),
                C64::default(),
                C64::default(),
                C64::default(),
            ],
            rate,
        })
        .collect();
        let w = std::f64::consts::PI / (8.0 * 2.4);
        let mut seeds = Seeds::default();
        seeds.reset();
        let (mut hits, mut out) = (0, Vec::new());
        for chunk in [0usize, 1, 7, 200] {
            let (a, b) = (2.0 * w * chunk as f64, 2.0 * w * (chunk + 1) as f64);
            let m = a + w;
            let mid: Vec<C64> = terms.iter().map(|t| cexp(t.rate, m)).collect();
            let mut seed = Seed {
                m,
                w,
                mid: &mid,
                seeds: &mut seeds,
            };
            let mut level = vec![(a, b)];
            for depth in 1..=8 {
                let mut next = Vec::new();
                for (lo, hi) in level {
                    let s = 0.5 * (lo + hi);
                    next.extend([(lo, s), (s, hi)]);
                    if depth == 1 {
                        continue; // the chunk's own midpoint: known to the scan
                    }
                    match seed.index_at(s) {
                        Some(k) => {
                            assert!(depth <= 7, "a seed point at depth {depth}");
                            hits += 1;
                            seed.exponentials_at(k, &terms, &mut out);
                            for (x, t) in out.iter().zip(&terms) {
                                // Both round the phase `μs` (and the product its factors).
                                let fresh = cexp(t.rate, s);
                                let rounding = 8.0 * f64::EPSILON * (1.0 + t.rate.norm() * s);
                                assert!((x - fresh).norm() <= rounding, "{x} against {fresh}");
                            }
                        }
                        None => assert!(depth > 7, "no seed point at depth {depth}, s = {s}"),
                    }
                }
                level = next;
            }
            let between = m + 0.3 * w / SEED_DIVISIONS as f64;
            assert_eq!(seed.index_at(between), None);
        }
        // Levels 2 to 7 of the halving: 2 + 4 + … + 64 split points a chunk.
        assert_eq!(hits, 4 * 126);
    }
}
