//! The modal basis of a flow: the rates (eigenvalues of the first-order system matrix, by a
//! bounded real Schur iteration), the eigenvectors from the quadratic pencil, their inverse
//! (with the rigid modes' coordinates), the modes that carry a real motion, and what the
//! flights' summaries read of them.

use super::{rigid, FlowError, C64};
use crate::expsum::ModeTerm;
use nalgebra::{DMatrix, DVector};

/// A modal basis whose condition number (Frobenius) reaches this is defective (e.g. exactly
/// critically damped): modal coordinates would lose more than ten of the sixteen digits.
const DEFECTIVE_CONDITION: f64 = 1e10;

/// Iteration cap of each Schur decomposition tried for the eigenvalues (nalgebra's QR
/// iterations; a convergent one takes a few per eigenvalue).
const SCHUR_ITERATIONS: usize = 1000;

/// Shifts (times the matrix's largest entry) of the retries when the Schur iteration on the
/// matrix and its transpose fails: a shift moves the spectrum off a symmetric configuration
/// that stalls the iteration; 0.37 is deliberately not a simple fraction.
const SCHUR_SHIFTS: [f64; 2] = [0.5, -0.37];

/// The inverse of the elastic modes and, with rigid modes, their coordinates.
pub(super) type ModalInverse = (DMatrix<C64>, Option<Box<rigid::RigidModes>>);

/// The eigenvectors `(φ, λφ)` of the rates `rates`, as columns: each `φ` the right singular
/// vector of the smallest singular value of the pencil `λ²M + λC + K`.
///
/// # Errors
/// [`FlowError::Defective`] when a singular value decomposition fails.
pub(super) fn pencil_modes(
    mass: &DMatrix<f64>,
    damping: Option<&DMatrix<f64>>,
    stiffness: &DMatrix<f64>,
    rates: &[C64],
) -> Result<DMatrix<C64>, FlowError> {
    let n = mass.nrows();
    let mut modes = DMatrix::<C64>::zeros(2 * n, rates.len());
    let mc = mass.map(|v| C64::new(v, 0.0));
    let kc = stiffness.map(|v| C64::new(v, 0.0));
    let cc = damping.map(|c| c.map(|v| C64::new(v, 0.0)));
    for (k, &lambda) in rates.iter().enumerate() {
        let mut pencil = &mc * (lambda * lambda) + &kc;
        if let Some(c) = &cc {
            pencil += c * lambda;
        }
        let svd = pencil.svd(false, true);
        let v_t = svd.v_t.ok_or(FlowError::Defective(f64::INFINITY))?;
        let (imin, _) =
            svd.singular_values
                .iter()
                .enumerate()
                .fold(
                    (0, f64::INFINITY),
                    |acc, (i, &s)| if s < acc.1 { (i, s) } else { acc },
                );
        let shape: DVector<C64> = v_t.row(imin).adjoint();
        for i in 0..n {
            modes[(i, k)] = shape[i];
            modes[(n + i, k)] = shape[i] * lambda;
        }
    }
    Ok(modes)
}

/// `V⁻¹` of the eigenvectors `modes` (elastic rates only), and with rigid `shapes` the rigid
/// modes' own coordinates (their particular solutions from the forcing and its harmonics): `W = [V_e | (R, 0) | (0, R)]` is inverted once, the elastic
/// coordinates its first `elastic` rows, the rigid positions and velocities its last `2r`.
///
/// # Errors
/// [`FlowError::Defective`] when the basis is singular or its condition reaches
/// [`DEFECTIVE_CONDITION`].
pub(super) fn modal_inverse(
    modes: &DMatrix<C64>,
    shapes: DMatrix<f64>,
    elastic: usize,
    minv: &DMatrix<f64>,
    (forcing, harmonics): (rigid::Forcing<'_>, &[rigid::HarmonicForce<'_>]),
    omega: f64,
) -> Result<ModalInverse, FlowError> {
    let n = modes.nrows() / 2;
    if shapes.ncols() == 0 {
        let inverse = modes
            .clone()
            .try_inverse()
            .ok_or(FlowError::Defective(f64::INFINITY))?;
        let condition = modes.norm() * inverse.norm();
        if condition.is_nan() || condition >= DEFECTIVE_CONDITION {
            return Err(FlowError::Defective(condition));
        }
        Ok((inverse, None))
    } else {
        // `W = [V_e | (R, 0) | (0, R)]`: the elastic coordinates are the first rows of
        // `W⁻¹`, the rigid positions and velocities its last `2r`.
        let r = shapes.ncols();
        let mut basis = DMatrix::<C64>::zeros(2 * n, 2 * n);
        basis.view_mut((0, 0), (2 * n, elastic)).copy_from(modes);
        for j in 0..r {
            for i in 0..n {
                let v = C64::new(shapes[(i, j)], 0.0);
                basis[(i, elastic + j)] = v;
                basis[(n + i, elastic + r + j)] = v;
            }
        }
        let full = basis
            .clone()
            .try_inverse()
            .ok_or(FlowError::Defective(f64::INFINITY))?;
        let condition = basis.norm() * full.norm();
        if condition.is_nan() || condition >= DEFECTIVE_CONDITION {
            return Err(FlowError::Defective(condition));
        }
        let rows = full.rows(elastic, 2 * r).into_owned();
        let rigid = rigid::RigidModes::new(shapes, &rows, minv, (forcing, harmonics), omega);
        Ok((full.rows(0, elastic).into_owned(), Some(Box::new(rigid))))
    }
}

/// The modes that carry a real motion, with their weights: a real system has real rates and
/// exact conjugate pairs (real Schur form), each pair folded into one mode of weight 2;
/// anything else keeps every mode.
pub(super) fn kept_modes(rates: &[C64]) -> Vec<(usize, f64)> {
    let partner = |k: usize| rates.iter().position(|r| *r == rates[k].conj());
    let pairs_exact = rates
        .iter()
        .enumerate()
        .all(|(k, r)| r.im == 0.0 || partner(k).is_some());
    if pairs_exact {
        rates
            .iter()
            .enumerate()
            .filter(|(_, r)| r.im >= 0.0)
            .map(|(k, r)| (k, if r.im > 0.0 { 2.0 } else { 1.0 }))
            .collect()
    } else {
        (0..rates.len()).map(|k| (k, 1.0)).collect()
    }
}

/// The eigenvalues of the system matrix `a`, by the real Schur form with a bounded QR
/// iteration; when it does not converge, on the transpose, then on shifted copies `a + σI`
/// (nalgebra's unbounded iteration can cycle forever on some finite matrices).
pub(crate) fn eigenvalues(a: &DMatrix<f64>) -> Result<Vec<C64>, FlowError> {
    if !a.iter().all(|v| v.is_finite()) {
        return Err(FlowError::NotFinite);
    }
    let n = a.nrows();
    // A system of no coordinates (a structure held on its stops in every direction) has no
    // rates.
    if n == 0 {
        return Ok(Vec::new());
    }
    let scale = a.amax().max(f64::MIN_POSITIVE);
    let identity = DMatrix::<f64>::identity(n, n);
    for (matrix, shift) in [
        (a.clone(), 0.0),
        (a.transpose(), 0.0),
        (
            a + &identity * (SCHUR_SHIFTS[0] * scale),
            SCHUR_SHIFTS[0] * scale,
        ),
        (
            a - &identity * (-SCHUR_SHIFTS[1] * scale),
            SCHUR_SHIFTS[1] * scale,
        ),
    ] {
        if let Some(schur) =
            nalgebra::linalg::Schur::try_new(matrix, f64::EPSILON, SCHUR_ITERATIONS)
        {
            return Ok(schur
                .complex_eigenvalues()
                .iter()
                .map(|l| l - shift)
                .collect());
        }
    }
    Err(FlowError::NoConvergence)
}

/// Real parts of an undamped system's oscillating rates at most this many times `ε·|μ|` are
/// rounding (the Schur form leaves a few `1e-17` where they are zero) and are made exactly 0.
/// Far above the Schur form's rounding (a few `ε·|μ|`), far below any real damping's share
/// (a damping ratio of `1e-13`).
pub(crate) const CONSERVATIVE_ROUNDING: f64 = 1e3;

/// The rates of a system with no damping terms: its oscillating modes (`im μ ≠ 0`) conserve
/// energy, so a real part at rounding level ([`CONSERVATIVE_ROUNDING`]) is made exactly 0;
/// conjugate pairs stay exact conjugates. An undamped flight then counts as bounded and is
/// searched on the fixed grid of cached exponentials, not the horizon grid's fresh ones (the
/// `steady_sweep` example, half its runs undamped, shows the gain: see the performance page,
/// `docs/performance.md`).
pub(super) fn conservative_rates(rates: &mut [C64]) {
    for r in rates.iter_mut() {
        if r.im != 0.0 && r.re.abs() <= CONSERVATIVE_ROUNDING * f64::EPSILON * r.norm() {
            r.re = 0.0;
        }
    }
}

/// `M⁻¹` and the first-order system matrix `A = [0 I; −M⁻¹K −M⁻¹C]` (no `C` block without
/// `damping`) of `M ü + C u̇ + K u`.
///
/// # Errors
/// [`FlowError::SingularMass`] when `mass` has no inverse.
pub(super) fn first_order(
    mass: &DMatrix<f64>,
    damping: Option<&DMatrix<f64>>,
    stiffness: &DMatrix<f64>,
) -> Result<(DMatrix<f64>, DMatrix<f64>), FlowError> {
    let n = mass.nrows();
    let minv = mass.clone().try_inverse().ok_or(FlowError::SingularMass)?;
    let mut a = DMatrix::<f64>::zeros(2 * n, 2 * n);
    a.view_mut((0, n), (n, n)).fill_with_identity();
    a.view_mut((n, 0), (n, n))
        .copy_from(&(-(&minv * stiffness)));
    if let Some(c) = damping {
        a.view_mut((n, n), (n, n)).copy_from(&(-(&minv * c)));
    }
    Ok((minv, a))
}

/// The modes of [`LinearFlow::joint_modes`]: each kept mode `(k, weight)` with its rate and
/// sizes, then the forced part at `iω` as `add_decaying` adds it (weight 1 is exact), then
/// each higher harmonic's at `ikω` (`harmonics`, the rates `kω` in order) likewise, every
/// deviation zero; `None` where [`Flight::summarize_all`] gives no summaries.
pub(super) fn joint_modes(
    rates: &[C64],
    kept: &[(usize, f64)],
    kept_sizes: &[(f64, f64)],
    (omega, harmonics): (f64, &[f64]),
) -> Option<Vec<ModeTerm>> {
    if rates.iter().any(|r| r.re > 0.0)
        || kept.is_empty()
        || kept_sizes.iter().any(|&(rate, _)| rate == 0.0)
    {
        return None;
    }
    let mut modes: Vec<ModeTerm> = kept
        .iter()
        .zip(kept_sizes)
        .map(|(&(k, weight), &sizes)| ModeTerm::new(rates[k], weight, sizes))
        .collect();
    for omega in std::iter::once(omega).chain(harmonics.iter().copied()) {
        let forcing = C64::new(0.0, omega);
        let rate = forcing.re.abs() + forcing.im.abs();
        modes.push(ModeTerm::new(forcing, 1.0, (rate, rate * rate * rate)));
    }
    Some(modes)
}

/// [`LinearFlow::kept_peaks`] of the eigenvectors `modes` (as columns, `2n` rows).
pub(super) fn kept_peaks(modes: &DMatrix<C64>, kept: &[(usize, f64)]) -> Vec<(f64, f64)> {
    let n = modes.nrows() / 2;
    let peak = |k: usize, rows: std::ops::Range<usize>| {
        rows.map(|i| modes[(i, k)])
            .fold(0.0, |m: f64, v| m.max(v.re.abs()).max(v.im.abs()))
    };
    kept.iter()
        .map(|&(k, _)| (peak(k, 0..n), peak(k, n..2 * n)))
        .collect()
}
