//! Every orbit of an impact sequence on a [`LinearModel`]: a systematic multi-start over impact
//! phases, the general counterpart of the unit's [`crate::signature_orbits`].
//!
//! The cycle `pT` is cut into `N` grid intervals and every ordered tuple
//! `0 < φ₂ < … < φ_m < 1` of grid points is scanned. For fixed impact times the contact
//! residuals are linear in `(cos α, sin α)`, so each tuple's squared residual is scanned on
//! [`ALPHA_SCAN`] values of `α` for the cost of one cycle; Newton
//! ([`crate::sequence_orbit::SequenceNewton`]) starts from every minimum in `α` of every tuple
//! (up to [`FULL_START_TUPLES`] tuples; above, from the minima over the joint grid). Converged
//! solutions are brought to the canonical first impact and deduplicated by `(α, phases)`
//! within [`DEDUP_TOLERANCE`]. The grid and the start rules are those of the unit's search.

use crate::cycle::{
    ALPHA_SCAN, DEDUP_TOLERANCE, FULL_START_TUPLES, GRID_PER_OSCILLATION, MAX_TUPLES, MIN_GRID,
};
use crate::model::LinearModel;
use crate::model_flight::eigenvalues;
use crate::orbit::wrap;
use crate::sequence::ImpactSequence;
use crate::sequence_orbit::{SequenceNewton, SequenceOrbitError, SequenceProblem};
use crate::sequence_verdicts::{assemble, SequenceOrbit};
use nalgebra::DMatrix;
use std::collections::HashMap;

/// Every orbit of `sequence` on `model` at `omega` found by the multi-start, deduplicated,
/// viable or not, sorted by `α`.
///
/// The grid has `N = max(`[`MIN_GRID`]`, ⌈`[`GRID_PER_OSCILLATION`]` · p · max(ω, ω_n)/ω⌉)`
/// intervals, `ω_n` the largest modulus of an eigenvalue of the model's system matrix,
/// coarsened until the number of tuples `C(N − 1, m − 1)` is at most [`MAX_TUPLES`] (never
/// below `max(`[`MIN_GRID`]`, m)`: a sequence of many impacts gets at least one tuple).
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
    let fastest = omega.max(natural);
    let wanted = (GRID_PER_OSCILLATION * f64::from(sequence.period()) * fastest / omega).ceil();
    let m = sequence.impacts().len();
    let fewest = MIN_GRID.max(m);
    let mut grid = (wanted.min(MAX_TUPLES as f64) as usize).max(fewest);
    while grid > fewest && tuples(grid, m) > MAX_TUPLES as f64 {
        grid -= 1;
    }
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
    let problem = SequenceProblem::new(model, omega, sequence)?;
    let m = problem.impacts();
    if grid < m {
        return Ok(Vec::new());
    }
    let a = model.augmented_matrix(omega);
    let steps: Vec<DMatrix<f64>> = (0..=grid)
        .map(|k| (&a * (k as f64 * problem.cycle() / grid as f64)).exp())
        .collect();
    let mut scanned: HashMap<Vec<usize>, Vec<f64>> = HashMap::new();
    let mut tuple: Vec<usize> = (0..m).collect();
    loop {
        if m == 1 || tuple[m - 1] < grid {
            scanned.insert(tuple.clone(), linear_scan(&problem, &steps, &tuple, grid));
        }
        if !next_tuple(&mut tuple, grid) {
            break;
        }
    }
    let starts = start_nodes(&scanned, |t| neighbours(t));
    let solver = SequenceNewton::default();
    let mut found: Vec<SequenceOrbit> = Vec::new();
    for (tuple, k) in starts {
        let guess = start_guess(tuple, k, grid);
        let Ok(converged) = solver.solve(&problem, &guess) else {
            continue;
        };
        let (alpha, phases) = problem.canonical(&converged.unknowns);
        if found.iter().any(|o| same_orbit(o, alpha, &phases)) {
            continue;
        }
        if let Ok(orbit) = assemble(&problem, alpha, &phases, converged.iteration) {
            found.push(orbit);
        }
    }
    found.sort_by(|a, b| a.alpha.total_cmp(&b.alpha));
    Ok(found)
}

/// Whether `orbit` has `(alpha, phases)` within [`DEDUP_TOLERANCE`] (angles modulo 2π).
fn same_orbit(orbit: &SequenceOrbit, alpha: f64, phases: &[f64]) -> bool {
    wrap(orbit.alpha - alpha).abs() < DEDUP_TOLERANCE
        && orbit.impact_phases[1..]
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

/// Sample `k` of the `α` scan: `−π + 2πk/`[`ALPHA_SCAN`].
pub(crate) fn scan_angle(k: usize) -> f64 {
    -std::f64::consts::PI + std::f64::consts::TAU * k as f64 / ALPHA_SCAN as f64
}

/// The starts of a multi-start over `scanned` (impact-index tuple → residual on the `α`
/// scan): each node `(tuple, k)` that is a finite local minimum in `α` and, when there are
/// more than [`FULL_START_TUPLES`] tuples, also over the tuple's `neighbours` in the joint
/// grid; in sorted order.
pub(crate) fn start_nodes<'a, I>(
    scanned: &'a HashMap<Vec<usize>, Vec<f64>>,
    neighbours: impl Fn(&'a [usize]) -> I,
) -> Vec<(&'a Vec<usize>, usize)>
where
    I: Iterator<Item = Vec<usize>>,
{
    let every = scanned.len() <= FULL_START_TUPLES;
    let mut starts = Vec::new();
    for (t, values) in scanned {
        for k in 0..ALPHA_SCAN {
            let v = values[k];
            let around = [(k + ALPHA_SCAN - 1) % ALPHA_SCAN, k, (k + 1) % ALPHA_SCAN];
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

/// The Newton guess of node `(tuple, k)`: `α` the `k`-th scan angle, the impact phases the
/// tuple's grid points over `grid`.
pub(crate) fn start_guess(tuple: &[usize], k: usize, grid: usize) -> Vec<f64> {
    let mut guess = vec![scan_angle(k); tuple.len()];
    for i in 1..tuple.len() {
        guess[i] = tuple[i] as f64 / grid as f64;
    }
    guess
}

/// Among the rotations `symmetries` of a cycle (start at impact `k` instead of 0) that keep
/// its canonical sequence, the representation of `(α, phases)` with the smallest wrapped `α`;
/// `omega_cycle` is `ω` times the cycle's length.
pub(crate) fn smallest_rotation(
    alpha: f64,
    phases: Vec<f64>,
    symmetries: Vec<usize>,
    omega_cycle: f64,
) -> (f64, Vec<f64>) {
    let m = phases.len();
    symmetries
        .into_iter()
        .map(|k| {
            let shifted: Vec<f64> = (0..m)
                .map(|j| (phases[(j + k) % m] - phases[k]).rem_euclid(1.0))
                .collect();
            (wrap(alpha + omega_cycle * phases[k]), shifted)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap_or((wrap(alpha), phases))
}

/// For impact times on grid points `tuple`, the squared contact residual on the `α` scan
/// (linear in `(cos α, sin α)` for fixed times: one cycle's cost). Infinite where the
/// periodicity solve is singular.
fn linear_scan(
    problem: &SequenceProblem,
    steps: &[DMatrix<f64>],
    tuple: &[usize],
    grid: usize,
) -> Vec<f64> {
    let m = tuple.len();
    let n2 = 2 * problem.model().dofs();
    let g_hat = problem.impact_matrices();
    let h = problem.contact_functionals();
    let stops = problem.contact_positions();
    let flight = |f: usize| {
        let end = if f + 1 < m { tuple[f + 1] } else { grid };
        &steps[end - tuple[f]]
    };
    let mut pre: Vec<DMatrix<f64>> = Vec::with_capacity(m);
    pre.push(flight(0).clone());
    for f in 1..m {
        let next = flight(f) * (&g_hat[f] * &pre[f - 1]);
        pre.push(next);
    }
    let psi = &g_hat[0] * &pre[m - 1];
    let Some(k) = (DMatrix::<f64>::identity(n2, n2) - psi.view((0, 0), (n2, n2))).try_inverse()
    else {
        return vec![f64::INFINITY; ALPHA_SCAN];
    };
    // The augmented states after the first impact for p₀ = (1, 0) and (0, 1).
    let mut z = DMatrix::<f64>::zeros(n2 + 2, 2);
    z.view_mut((0, 0), (n2, 2))
        .copy_from(&(k * psi.view((0, n2), (n2, 2))));
    z[(n2, 0)] = 1.0;
    z[(n2 + 1, 1)] = 1.0;
    // Residual j = c_j · p − stop_j.
    let coefficients: Vec<[f64; 2]> = (0..m)
        .map(|j| {
            let row = if j == 0 {
                h[0].transpose() * &z
            } else {
                (h[j].transpose() * &pre[j - 1]) * &z
            };
            [row[0], row[1]]
        })
        .collect();
    (0..ALPHA_SCAN)
        .map(|k| {
            let (c, s) = (scan_angle(k).cos(), scan_angle(k).sin());
            (0..m)
                .map(|j| (coefficients[j][0] * c + coefficients[j][1] * s - stops[j]).powi(2))
                .sum()
        })
        .collect()
}
