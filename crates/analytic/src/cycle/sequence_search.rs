//! Every orbit of an impact sequence on a [`LinearModel`]: a systematic multi-start over impact
//! phases, the general counterpart of the unit's [`crate::signature_orbits`].
//!
//! The cycle `pT` is cut into `N` grid intervals and every ordered tuple
//! `0 < φ₂ < … < φ_m < 1` of grid points is scanned. For fixed impact times the contact
//! residuals are affine in `(cos α, sin α)` (linear but for the stops; with rigid modes the
//! bordered residuals of [`crate::cycle_equations`] likewise; with harmonics affine in
//! `(cos kα, sin kα)` of every order), so each tuple's squared residual is scanned on
//! `ALPHA_SCAN = 64` values of `α` (`16 K` for a forcing of highest order `K > 4`) for
//! the cost of one cycle; Newton
//! ([`crate::sequence_orbit::SequenceNewton`]) starts from every minimum in `α` of every tuple
//! (up to `FULL_START_TUPLES = 5000` tuples; above, from the minima over the joint grid). Converged
//! solutions are brought to the canonical first impact and deduplicated by `(α, phases)`
//! within `DEDUP_TOLERANCE = 1e-8`. The grid and the start rules are those of the unit's search.
//!
//! **Contact phases.** Orbits of a sequence with contact phases, found from the rigid orbits they continue.
//!
//! A contact phase lasts about `π/ω_c`, far below any grid spacing of the rigid multi-start
//! once the contact is stiff, so its entry and exit are not scanned on a grid. Instead the
//! orbits of the same sequence on the rigid proxy (every compliant pair rigid with its
//! isolated restitution, [`crate::Compliance::restitution`]) are found by the rigid
//! multi-start ([`crate::sequence_orbits_on_grid`]), and each seeds Newton on the compliant
//! cycle: a contact phase enters at its rigid impact's time and leaves the isolated contact
//! duration later. As the contact stiffens at fixed restitution the compliant orbit tends to
//! the rigid one, so every compliant orbit on a branch that continues a rigid orbit is found;
//! compliant orbits without a rigid counterpart (soft contacts far from the rigid limit) are
//! not.

use crate::cycle_equations::CycleEquations;
use crate::model::LinearModel;
use crate::model_flight::eigenvalues;
use crate::orbit::wrap;
use crate::problem::forcing::PhaseRows;
use crate::sequence::{ImpactKind, ImpactSequence, PairImpact};
use crate::sequence_orbit::{SequenceNewton, SequenceOrbitError, SequenceProblem};
use crate::sequence_verdicts::{ModelVerdicts, SequenceOrbit};
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, DimMin, OMatrix};
use std::collections::HashMap;

/// Grid points per period of the fastest oscillation of the flow (`max(ω, ω_n)`) in the
/// multi-start over impact phases: each impact time of any orbit lies within `1/32` of that
/// period of a grid point. Four points per period (an eighth) missed non-viable two-impact
/// orbits of the paper unit at `ω = 0.8` whose Newton basins are narrow; sixteen found
/// every viable orbit that grids up to four times finer found (see
/// [`crate::signature_orbits`]).
pub const GRID_PER_OSCILLATION: f64 = 16.0;

/// Fewest grid intervals over the cycle, whatever the frequencies: with `n ≤ 4` impacts
/// there are then at least `C(15, 3) = 455` ordered phase tuples.
pub const MIN_GRID: usize = 16;

/// Up to this many impact-phase tuples, Newton starts from every minimum in `α` of every
/// tuple's linear residual; above it, only from the minima over the joint grid of impact
/// phases and `α`. A Newton start costs about 0.2 ms on the unit, so this bounds the full
/// search to about two seconds (`n = 4`, `p = 1`, `ω ≥ 1.2` on the paper unit stay below it).
pub(crate) const FULL_START_TUPLES: usize = 5000;

/// Cap on the impact-phase tuples of a multi-start: at low `ω` or long cycles the grid of
/// [`GRID_PER_OSCILLATION`] is coarsened until `C(N − 1, n − 1)` tuples fit, which bounds the
/// scan's memory (64 residuals per tuple, about 30 MB) and its time (about a second on the
/// unit). Not binding on the paper unit for `n ≤ 4` impacts above `ω ≈ 1.08` with `p = 2`,
/// above `ω ≈ 0.54` with `p = 1`.
pub const MAX_TUPLES: usize = 60_000;

/// Samples of `α` on which the linear contact residual is scanned for each phase tuple; its
/// square is a trigonometric polynomial of degree 2 in `α` (at most two local minima), so 64
/// samples (`π/32` apart) land within `π/64` of each minimum, and separate the two unless
/// they nearly merge (then one start serves both).
pub(crate) const ALPHA_SCAN: usize = 64;

/// Samples of the `α` scan for a forcing of highest order `K`: [`ALPHA_SCAN`] up to `K = 4`,
/// `16 K` above. The squared residual is a trigonometric polynomial of degree `2K` in `α`
/// (at most `2K` local minima); 64 samples keep at least eight per period of its fastest
/// term up to `K = 4`, and `16 K` keep eight beyond.
pub(crate) fn alpha_samples(highest_order: u32) -> usize {
    ALPHA_SCAN.max(16 * highest_order as usize)
}

/// Two converged solutions are the same orbit when their base phases (after bringing both
/// to the canonical first impact) and impact phases differ by less than this: Newton pins
/// them to about `1e-13`, and distinct orbits lie many orders further apart.
pub(crate) const DEDUP_TOLERANCE: f64 = 1e-8;

/// The grid intervals of a multi-start over a cycle of `period` forcing periods with `m`
/// impacts, `fastest` the fastest frequency of the motion (`max(ω, ω_n)`): `max(`[`MIN_GRID`]`,
/// m, ⌈`[`GRID_PER_OSCILLATION`]` · p · fastest/ω⌉)`, coarsened until the number of tuples
/// `C(N − 1, m − 1)` is at most [`MAX_TUPLES`] (never below `max(`[`MIN_GRID`]`, m)`).
pub(crate) fn grid_intervals(fastest: f64, omega: f64, period: u32, m: usize) -> usize {
    let wanted = (GRID_PER_OSCILLATION * f64::from(period) * fastest / omega).ceil();
    let fewest = MIN_GRID.max(m);
    let mut grid = (wanted.min(MAX_TUPLES as f64) as usize).max(fewest);
    while grid > fewest && tuples(grid, m) > MAX_TUPLES as f64 {
        grid -= 1;
    }
    grid
}

/// Every orbit of `sequence` on `model` at `omega` found by the multi-start, deduplicated,
/// viable or not, sorted by `α`.
///
/// The grid has `N = max(`[`MIN_GRID`]`, ⌈`[`GRID_PER_OSCILLATION`]` · p · max(Kω, ω_n)/ω⌉)`
/// intervals, `ω_n` the largest modulus of an eigenvalue of the model's system matrix and `K`
/// the forcing's highest order (1 without harmonics),
/// coarsened until the number of tuples `C(N − 1, m − 1)` is at most [`MAX_TUPLES`] (never
/// below `max(`[`MIN_GRID`]`, m)`: a sequence of many impacts gets at least one tuple).
///
/// A sequence with contact phases (`0+c`, compliant pairs) is solved from the orbits of its
/// rigid proxy, each contact seeded at its rigid impact (see the module's documentation): the
/// grid is the proxy's, of one point per contact phase.
///
/// # Errors
/// [`SequenceOrbitError::InvalidFrequency`] and [`SequenceOrbitError::Sequence`] as
/// [`SequenceProblem::new`]. A start whose Newton iteration fails is dropped silently: most
/// starts lie far from any orbit.
pub fn sequence_orbits(
    model: &LinearModel,
    omega: f64,
    sequence: &ImpactSequence,
) -> Result<Vec<SequenceOrbit>, SequenceOrbitError> {
    SequenceProblem::new(model, omega, sequence)?;
    let natural = eigenvalues(&model.system_matrix())
        .map(|l| l.iter().fold(0.0, |a: f64, z| a.max(z.norm())))
        .unwrap_or(0.0);
    let m = sequence.impacts().len();
    let fastest = f64::from(model.forcing().highest_order()) * omega;
    let grid = grid_intervals(fastest.max(natural), omega, sequence.period(), m);
    sequence_orbits_on_grid(model, omega, sequence, grid)
}

/// Number of ordered impact-phase tuples `C(grid − 1, m − 1)` of a grid, as a float (0 when
/// the grid has fewer points than impacts).
fn tuples(grid: usize, m: usize) -> f64 {
    (1..m).fold(1.0, |c, k| c * (grid as f64 - k as f64).max(0.0) / k as f64)
}

/// [`sequence_orbits`] with an explicit number of grid intervals over the cycle. The work and
/// memory grow like `C(grid − 1, m − 1)`: the caller bounds it. An empty list when `grid` is
/// below the number of impacts.
///
/// # Errors
/// As [`sequence_orbits`].
pub fn sequence_orbits_on_grid(
    model: &LinearModel,
    omega: f64,
    sequence: &ImpactSequence,
    grid: usize,
) -> Result<Vec<SequenceOrbit>, SequenceOrbitError> {
    if sequence.has_contact_phases() {
        return contact_orbits(model, omega, sequence, grid);
    }
    let problem = SequenceProblem::new(model, omega, sequence)?;
    let verdicts = ModelVerdicts::new(&problem);
    let samples = alpha_samples(model.forcing().highest_order());
    let found = multi_start(
        problem.equations(),
        grid,
        samples,
        |alpha, phases, iterations| verdicts.assemble(alpha, phases, iterations).ok(),
    );
    Ok(found)
}

/// The multi-start over a grid of `grid` intervals of the cycle on any cycle equations: every
/// ordered impact-phase tuple scanned in `α` on `samples` values ([`linear_scan`],
/// [`alpha_samples`] of the forcing's highest order), Newton ([`SequenceNewton`])
/// from the start nodes ([`start_nodes`]), each converged solution brought to its canonical
/// representation, deduplicated within `DEDUP_TOLERANCE = 1e-8` and made into an orbit by
/// `assemble(α, phases, iterations)` (`None`: dropped). The orbits sorted by `α`; an empty list
/// when `grid` is below the number of impacts.
pub(crate) fn multi_start<D, O>(
    equations: &CycleEquations<D>,
    grid: usize,
    samples: usize,
    mut assemble: impl FnMut(f64, &[f64], usize) -> Option<O>,
) -> Vec<O>
where
    D: DimMin<D, Output = D>,
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let m = equations.impacts();
    if grid < m {
        return Vec::new();
    }
    let steps: Vec<OMatrix<f64, D, D>> = (0..=grid)
        .map(|k| equations.flow(k as f64 * equations.cycle() / grid as f64))
        .collect();
    let mut scanned: HashMap<Vec<usize>, Vec<f64>> = HashMap::new();
    let mut tuple: Vec<usize> = (0..m).collect();
    loop {
        if m == 1 || tuple[m - 1] < grid {
            let scan = linear_scan(equations, &steps, &tuple, grid, samples);
            scanned.insert(tuple.clone(), scan);
        }
        if !next_tuple(&mut tuple, grid) {
            break;
        }
    }
    let starts = start_nodes(&scanned, |t| neighbours(t), samples);
    let solver = SequenceNewton::default();
    let mut found: Vec<(Vec<f64>, O)> = Vec::new();
    for (tuple, k) in starts {
        let guess = start_guess(tuple, k, grid, samples);
        let Ok(converged) = solver.solve(equations, &guess) else {
            continue;
        };
        let (alpha, phases) = equations.canonical(&converged.unknowns);
        if found.iter().any(|(key, _)| same_orbit(key, alpha, &phases)) {
            continue;
        }
        if let Some(orbit) = assemble(alpha, &phases, converged.iteration) {
            let mut key = phases;
            key[0] = alpha;
            found.push((key, orbit));
        }
    }
    found.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]));
    found.into_iter().map(|(_, o)| o).collect()
}

/// Whether a found orbit's key `(α, φ₂ …)` matches `(alpha, phases)` within
/// `DEDUP_TOLERANCE = 1e-8` (angles compared modulo 2π).
fn same_orbit(key: &[f64], alpha: f64, phases: &[f64]) -> bool {
    wrap(key[0] - alpha).abs() < DEDUP_TOLERANCE
        && key[1..]
            .iter()
            .zip(&phases[1..])
            .all(|(a, b)| (a - b).abs() < DEDUP_TOLERANCE)
}

/// Most free impact indices for which [`neighbours`] walks the full cube of `3^(m − 1) − 1`
/// neighbours (80 for five impacts); above, only the `2(m − 1)` neighbours along one index.
const FULL_NEIGHBOURHOOD: usize = 4;

/// The tuples that differ from `tuple` by at most one grid step in each impact index (the
/// first, always 0, excluded), `tuple` itself left out; for more than
/// [`FULL_NEIGHBOURHOOD`] free indices, those that differ by one step in one index only.
fn neighbours(tuple: &[usize]) -> Box<dyn Iterator<Item = Vec<usize>> + '_> {
    let free = tuple.len() - 1;
    if free > FULL_NEIGHBOURHOOD {
        return Box::new((1..tuple.len()).flat_map(move |i| {
            [1isize, -1].into_iter().filter_map(move |d| {
                let mut t = tuple.to_vec();
                t[i] = t[i].checked_add_signed(d)?;
                Some(t)
            })
        }));
    }
    Box::new(cube_neighbours(tuple))
}

/// The tuples that differ from `tuple` by at most one grid step in each impact index (the
/// first, always 0, excluded), `tuple` itself left out: the full cube of `3^(m − 1) − 1`.
pub(crate) fn cube_neighbours(tuple: &[usize]) -> impl Iterator<Item = Vec<usize>> + '_ {
    let free = tuple.len() - 1;
    (0..3usize.pow(free as u32)).filter_map(move |code| {
        let mut t = tuple.to_vec();
        let mut c = code;
        let mut moved = false;
        for v in t.iter_mut().skip(1) {
            match c % 3 {
                1 => {
                    *v += 1;
                    moved = true;
                }
                2 => {
                    *v = v.checked_sub(1)?;
                    moved = true;
                }
                _ => {}
            }
            c /= 3;
        }
        moved.then_some(t)
    })
}

/// Advances `tuple = (0, i₂, …, i_m)`, `0 < i₂ < … < i_m < grid`, in lexicographic order.
pub(crate) fn next_tuple(tuple: &mut [usize], grid: usize) -> bool {
    let m = tuple.len();
    if m == 1 {
        return false;
    }
    let mut i = m - 1;
    loop {
        if tuple[i] < grid - (m - i) {
            tuple[i] += 1;
            for j in i + 1..m {
                tuple[j] = tuple[j - 1] + 1;
            }
            return true;
        }
        if i == 1 {
            return false;
        }
        i -= 1;
    }
}

/// Sample `k` of an `α` scan of `samples` values: `−π + 2πk/samples`.
pub(crate) fn scan_angle(k: usize, samples: usize) -> f64 {
    -std::f64::consts::PI + std::f64::consts::TAU * k as f64 / samples as f64
}

/// The starts of a multi-start over `scanned` (impact-index tuple → residual on the `α`
/// scan of `samples` values): each node `(tuple, k)` that is a finite local minimum in `α`
/// and, when there are more than `FULL_START_TUPLES = 5000` tuples, also over the tuple's
/// `neighbours` in the joint grid; in sorted order.
pub(crate) fn start_nodes<'a, I>(
    scanned: &'a HashMap<Vec<usize>, Vec<f64>>,
    neighbours: impl Fn(&'a [usize]) -> I,
    samples: usize,
) -> Vec<(&'a Vec<usize>, usize)>
where
    I: Iterator<Item = Vec<usize>>,
{
    let every = scanned.len() <= FULL_START_TUPLES;
    let mut starts = Vec::new();
    for (t, values) in scanned {
        for k in 0..samples {
            let v = values[k];
            // The neighbours on the circle of samples, without a division.
            let before = if k == 0 { samples - 1 } else { k - 1 };
            let after = if k + 1 == samples { 0 } else { k + 1 };
            let around = [before, k, after];
            let alpha_min = values[around[0]] >= v && values[around[2]] > v;
            if alpha_min
                && v.is_finite()
                && (every
                    || neighbours(t).all(|nb| {
                        scanned
                            .get(&nb)
                            .is_none_or(|w| around.iter().all(|&k2| w[k2] >= v))
                    }))
            {
                starts.push((t, k));
            }
        }
    }
    starts.sort();
    starts
}

/// The Newton guess of node `(tuple, k)`: `α` the `k`-th of `samples` scan angles, the impact
/// phases the tuple's grid points over `grid`.
pub(crate) fn start_guess(tuple: &[usize], k: usize, grid: usize, samples: usize) -> Vec<f64> {
    let mut guess = vec![scan_angle(k, samples); tuple.len()];
    for i in 1..tuple.len() {
        guess[i] = tuple[i] as f64 / grid as f64;
    }
    guess
}

/// For impact times on grid points `tuple`, the squared contact residual on the `α` scan of
/// `samples` values (affine in the phase states for fixed times: one cycle's cost). Infinite
/// where the periodicity solve is singular.
fn linear_scan<D>(
    equations: &CycleEquations<D>,
    steps: &[OMatrix<f64, D, D>],
    tuple: &[usize],
    grid: usize,
    samples: usize,
) -> Vec<f64>
where
    D: DimMin<D, Output = D>,
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let m = tuple.len();
    let flights: Vec<&OMatrix<f64, D, D>> = (0..m)
        .map(|f| {
            let end = if f + 1 < m { tuple[f + 1] } else { grid };
            &steps[end - tuple[f]]
        })
        .collect();
    let pre = equations.pre_maps(&flights);
    if equations.is_bordered() || equations.phase_states() > 2 {
        // A model with rigid modes or harmonics: the residuals are affine in the phase states.
        let Some((constant, linear)) = equations.affine_residuals(&pre) else {
            return vec![f64::INFINITY; samples];
        };
        return (0..samples)
            .map(|k| {
                let p = equations.phase_at(scan_angle(k, samples));
                (0..m)
                    .map(|j| {
                        let r = linear
                            .iter()
                            .zip(&p)
                            .fold(constant[j], |sum, (l, v)| sum + l[j] * v);
                        r.powi(2)
                    })
                    .sum()
            })
            .collect();
    }
    let Some(lu) = equations.periodicity(&pre) else {
        return vec![f64::INFINITY; samples];
    };
    // The contact values for p₀ = (1, 0) and (0, 1): residual j = c_j · p − stop_j.
    let mut coefficients = vec![[0.0; 2]; m];
    for (c, p) in [[1.0, 0.0], [0.0, 1.0]].into_iter().enumerate() {
        let Some(z) = lu.solve(&equations.augmented_vector(None, PhaseRows::Given(&p))) else {
            return vec![f64::INFINITY; samples];
        };
        for (j, v) in equations.contact_values(&pre, &z).into_iter().enumerate() {
            coefficients[j][c] = v;
        }
    }
    let stops = equations.stops();
    (0..samples)
        .map(|k| {
            let (c, s) = (scan_angle(k, samples).cos(), scan_angle(k, samples).sin());
            (0..m)
                .map(|j| (coefficients[j][0] * c + coefficients[j][1] * s - stops[j]).powi(2))
                .sum()
        })
        .collect()
}

/// The orbits of `sequence` (with contact phases) on `model` at `omega` seeded from the rigid
/// proxy's orbits on a grid of `grid` intervals (see the module's documentation), deduplicated
/// within `DEDUP_TOLERANCE = 1e-8` and sorted by `α`.
///
/// # Errors
/// As [`SequenceProblem::new`] on the compliant model and [`crate::sequence_orbits_on_grid`]
/// on the proxy.
pub(crate) fn contact_orbits(
    model: &LinearModel,
    omega: f64,
    sequence: &ImpactSequence,
    grid: usize,
) -> Result<Vec<SequenceOrbit>, SequenceOrbitError> {
    let problem = SequenceProblem::new(model, omega, sequence)?;
    let proxy = model.rigid_proxy();
    let rigid_impacts: Vec<PairImpact> = sequence
        .impacts()
        .iter()
        .map(|i| PairImpact::rigid(i.pair, i.side))
        .collect();
    let rigid = ImpactSequence::from_cycle(&rigid_impacts, sequence.period())?;
    let seeds = sequence_orbits_on_grid(&proxy, omega, &rigid, grid)?;
    let verdicts = ModelVerdicts::new(&problem);
    let solver = SequenceNewton::default();
    let equations = problem.equations();
    let mut found: Vec<(Vec<f64>, SequenceOrbit)> = Vec::new();
    for seed in seeds {
        let Some(guess) = seed_guess(&problem, &seed) else {
            continue;
        };
        let Ok(converged) = solver.solve(equations, &guess) else {
            continue;
        };
        let (alpha, phases) = equations.canonical(&converged.unknowns);
        if found.iter().any(|(key, _)| same_orbit(key, alpha, &phases)) {
            continue;
        }
        if let Ok(orbit) = verdicts.assemble(alpha, &phases, converged.iteration) {
            let mut key = phases;
            key[0] = alpha;
            found.push((key, orbit));
        }
    }
    found.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]));
    Ok(found.into_iter().map(|(_, o)| o).collect())
}

/// The cycle's unknowns `(α, φ₂ …)` from a rigid orbit of the same impacts (both canonical,
/// so impact `j` of one is impact `j` of the other): a rigid impact at its time, a contact
/// phase entering at its impact's time and leaving the isolated contact duration later, a
/// sticking phase landing at its impact's time and released at the first sign change of the
/// release functional along the held flow from there ([`stick_release`]); `None` when a
/// contact would reach the next event or a held pair is not released before it.
fn seed_guess(problem: &SequenceProblem<'_>, seed: &SequenceOrbit) -> Option<Vec<f64>> {
    let model = problem.model();
    let impacts = problem.sequence().impacts();
    let cycle = problem.cycle();
    let mut guess = Vec::with_capacity(2 * impacts.len());
    for (j, impact) in impacts.iter().enumerate() {
        let at = if j == 0 {
            seed.alpha
        } else {
            seed.impact_phases[j]
        };
        guess.push(at);
        let entry = seed.impact_phases[j];
        let next = seed.impact_phases.get(j + 1).copied().unwrap_or(1.0);
        let exit = match impact.kind {
            ImpactKind::Rigid => continue,
            ImpactKind::Contact => {
                let law = model.compliance(impact.pair)?;
                entry + law.contact_duration(model.reduced_mass(impact.pair)) / cycle
            }
            ImpactKind::Stick => stick_release(problem, seed, j, guess.len() - 1)?,
        };
        if exit.partial_cmp(&next) != Some(std::cmp::Ordering::Less) {
            return None;
        }
        guess.push(exit);
    }
    Some(guess)
}

/// Samples of the release functional along a held flow in [`stick_release`]: the first sign
/// change is bracketed to `1/64` of the time to the next impact, well inside Newton's basin
/// of a release (a simple root).
const RELEASE_SAMPLES: usize = 64;

/// The release phase (fraction of the cycle) of the sticking phase of impact `j` (event
/// `landing`) seeded by the rigid orbit `seed`: from the state after its landing impact, the
/// midpoint of the first interval of [`RELEASE_SAMPLES`] over the time to the next impact on
/// which the held pair's release functional `s h` changes sign; `None` when it does not.
fn stick_release(
    problem: &SequenceProblem<'_>,
    seed: &SequenceOrbit,
    j: usize,
    landing: usize,
) -> Option<f64> {
    let (model, equations) = (problem.model(), problem.equations());
    let impact = problem.sequence().impacts()[j];
    let cycle = problem.cycle();
    let entry = seed.impact_phases[j];
    let next = seed.impact_phases.get(j + 1).copied().unwrap_or(1.0);
    let before = nalgebra::DVector::from_column_slice(&seed.states_before_impacts[j]);
    let after = model.impact_state(impact.pair, &before);
    let theta = seed.alpha + problem.omega() * entry * cycle;
    let phases = model.phase_at(theta);
    let mut z = nalgebra::DVector::zeros(equations.augmented_matrix().nrows());
    z.rows_mut(0, after.len()).copy_from(&after);
    z.rows_mut(after.len(), phases.len()).copy_from(&phases);
    z[after.len() + phases.len()] = 1.0;
    let h = equations.contact_functional(landing + 1);
    let s = f64::from(impact.side);
    let span = (next - entry) * cycle;
    (1..RELEASE_SAMPLES)
        .find(|&i| {
            let tau = span * i as f64 / RELEASE_SAMPLES as f64;
            s * h.dot(&(equations.flight_flow(landing, tau) * &z)) < 0.0
        })
        .map(|i| entry + (next - entry) * (i as f64 - 0.5) / RELEASE_SAMPLES as f64)
}
