//! The flow's AVX kernels: a flight's steady state and modal coordinates two modes to a
//! register, a state's modal coordinates, a deviation carried across a jump, and modes' columns
//! added into a state four entries at once. Each performs the scalar code's operations in the
//! same order, without FMA, so every result is the same bits.

use super::{cexp, LinearFlow, SteadyResponse, C64};

/// The shortest state (`2n` entries) whose modes [`LinearFlow::add_mode`] adds out of line,
/// with AVX when the CPU has it: a unit's four entries cost more instructions so (a call
/// where the inlined loop is cheaper), a chain's 32 fewer (see the performance page,
/// `docs/performance.md`).
#[cfg(target_arch = "x86_64")]
pub(super) const AVX_COLUMN: usize = 8;

/// [`LinearFlow::add_mode`]'s loop for a long column (`y[i] += re[i]·z.re − im[i]·z.im` over
/// equal-length slices), with AVX when the CPU has it ([`add_column_avx`], the same bits).
#[cfg(target_arch = "x86_64")]
#[inline(never)]
pub(super) fn add_column(re: &[f64], im: &[f64], z: C64, y: &mut [f64]) {
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU has AVX (checked just above), the only requirement of the
        // `target_feature` function.
        return unsafe { add_column_avx(re, im, z, y) };
    }
    for i in 0..y.len() {
        y[i] += re[i] * z.re - im[i] * z.im;
    }
}

/// [`Flight::state_at`]'s steady form with AVX: each kept mode's
/// `z_k = (h_k e^{λ_k s} + P⁺_k F + P⁻_k F̄ + P⁰_k)·weight` (`F` the forcing's phase at `s`)
/// formed two modes to a register, then the two modes' columns added four entries at once in
/// one pass ([`add_two_columns_avx`]; an odd last mode's by [`add_column_avx`]). Complex
/// products as [`Complex`]'s (the imaginary part's sum with its operands swapped, which
/// rounds the same), the sums in the same order: the same bits as [`Flight::state_at`]'s
/// loop. `y` is zero on entry.
///
/// [`Flight::state_at`]: super::Flight::state_at
/// [`Complex`]: nalgebra::Complex
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
pub(super) fn steady_state_avx(
    f: &LinearFlow,
    (p, deviation, forced): (&SteadyResponse, &[C64], C64),
    (s, known): (f64, Option<&[C64]>),
    y: &mut [f64],
) {
    use crate::expsum::{complex_pair, complex_pair_product};
    use std::arch::x86_64::*;
    let m = 2 * f.dofs;
    let (columns_re, columns_im) = &f.mode_columns;
    let y = &mut y[..m];
    let pack = |a: C64, b: C64| _mm256_set_pd(b.im, b.re, a.im, a.re);
    // Two neighbouring complex numbers (`C64` is `repr(C)`: `[re₀, im₀, re₁, im₁]`, as `pack`
    // lays them out).
    let load = |v: &[C64], i: usize| {
        let two = &v[i..i + 2];
        // SAFETY: `two` holds two `C64`, four `f64` in that order: one unaligned load.
        unsafe { _mm256_loadu_pd(two.as_ptr().cast()) }
    };
    // A `match`, not `Option::map_or_else`, which the compiler leaves out of line here (a
    // call per entry).
    let el = |j: usize, k: usize| match known {
        Some(e) => e[j],
        None => cexp(f.rates[k], s),
    };
    let pairs = f.kept.chunks_exact(2);
    let last = pairs.remainder();
    for (i, pair) in pairs.enumerate() {
        let ((k0, w0), (k1, w1)) = (pair[0], pair[1]);
        let h = load(deviation, 2 * i);
        let e = match known {
            Some(e) => load(e, 2 * i),
            None => pack(cexp(f.rates[k0], s), cexp(f.rates[k1], s)),
        };
        let z = pair_coordinates_avx(p, 2 * i, complex_pair_product(h, e), forced, (w0, w1));
        let (z0, z1) = complex_pair(z);
        let (c0, c1) = (k0 * m..(k0 + 1) * m, k1 * m..(k1 + 1) * m);
        add_two_columns_avx(
            (&columns_re[c0.clone()], &columns_im[c0], z0),
            (&columns_re[c1.clone()], &columns_im[c1], z1),
            y,
        );
    }
    if let &[(k, weight)] = last {
        let j = f.kept.len() - 1;
        let zk = p.coordinate(j, deviation[j] * el(j, k), forced, weight);
        let column = k * m..(k + 1) * m;
        add_column_avx(&columns_re[column.clone()], &columns_im[column], zk, y);
    }
}

/// The kept modes' coordinates `(V⁻¹y)_k` of the state `y` into `out` (as long as the kept
/// modes), from `columns` ([`LinearFlow::kept_inverse_columns`]), two modes to an AVX
/// register and four registers at a time: each coordinate's real and imaginary parts summed
/// over the state's entries in order from `0`, `re += Re v·y_i` and `im += Im v·y_i`, as
/// [`LinearFlow::flight_at_phase`] sums them entry by entry (no FMA: the same bits). Returns
/// how many modes it formed (all but a last odd one).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
pub(super) fn modal_coordinates_avx(columns: &[C64], y: &[f64], out: &mut [C64]) -> usize {
    use std::arch::x86_64::*;
    /// Registers summed side by side: four chains of additions in flight at once.
    const BLOCK: usize = 4;
    let count = out.len();
    let columns = &columns[..count * y.len()];
    let pairs = count / 2;
    let mut p = 0;
    while p < pairs {
        let block = (pairs - p).min(BLOCK);
        let mut sums = [_mm256_setzero_pd(); BLOCK];
        for (i, &yi) in y.iter().enumerate() {
            let yi = _mm256_set1_pd(yi);
            let column = &columns[i * count + 2 * p..i * count + 2 * (p + block)];
            for (sum, two) in sums.iter_mut().zip(column.chunks_exact(2)) {
                // SAFETY: `two` holds two `C64`, four `f64`: one unaligned load.
                let v = unsafe { _mm256_loadu_pd(two.as_ptr().cast()) };
                *sum = _mm256_add_pd(*sum, _mm256_mul_pd(v, yi));
            }
        }
        for (q, sum) in sums.iter().take(block).enumerate() {
            let two = &mut out[2 * (p + q)..2 * (p + q) + 2];
            // SAFETY: `two` holds two `C64`, four `f64`: one unaligned store.
            unsafe { _mm256_storeu_pd(two.as_mut_ptr().cast(), *sum) };
        }
        p += block;
    }
    2 * pairs
}

/// [`SteadyResponse::coordinate`] of kept modes `j` and `j + 1` (their decayed deviations
/// packed in `decayed`, weights `w0`, `w1`), two to an AVX register: the same operations in
/// the same order ([`complex_pair_product`](crate::expsum::complex_pair_product): [`Complex`]'s
/// products), so the same bits.
///
/// [`Complex`]: nalgebra::Complex
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
fn pair_coordinates_avx(
    p: &SteadyResponse,
    j: usize,
    decayed: std::arch::x86_64::__m256d,
    forced: C64,
    (w0, w1): (f64, f64),
) -> std::arch::x86_64::__m256d {
    use crate::expsum::complex_pair_product;
    use std::arch::x86_64::*;
    let pack = |a: C64, b: C64| _mm256_set_pd(b.im, b.re, a.im, a.re);
    let load = |v: &[C64]| {
        let two = &v[j..j + 2];
        // SAFETY: `two` holds two `C64`, four `f64` in that order: one unaligned load.
        unsafe { _mm256_loadu_pd(two.as_ptr().cast()) }
    };
    let (plus, minus) = (pack(forced, forced), pack(forced.conj(), forced.conj()));
    let mut z = _mm256_add_pd(decayed, complex_pair_product(load(&p.plus), plus));
    z = _mm256_add_pd(z, complex_pair_product(load(&p.minus), minus));
    z = _mm256_add_pd(z, load(&p.constant));
    _mm256_mul_pd(z, _mm256_set_pd(w1, w1, w0, w0))
}

/// [`Flight::modal_state`] with AVX and the exponentials known: [`steady_state_avx`]'s
/// coordinates (the same operations, so the same bits), written to `z` (as long as the kept
/// modes) rather than added into a state, and their first products `h_k e^{λ_k s}` to
/// `carried` (as long).
///
/// [`Flight::modal_state`]: super::Flight::modal_state
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
pub(super) fn modal_state_avx(
    f: &LinearFlow,
    (p, deviation, forced): (&SteadyResponse, &[C64], C64),
    e: &[C64],
    (z, carried): (&mut [C64], &mut [C64]),
) {
    use crate::expsum::complex_pair_product;
    use std::arch::x86_64::*;
    let load = |v: &[C64], i: usize| {
        let two = &v[i..i + 2];
        // SAFETY: `two` holds two `C64`, four `f64` in that order: one unaligned load.
        unsafe { _mm256_loadu_pd(two.as_ptr().cast()) }
    };
    let pairs = f.kept.chunks_exact(2);
    let last = pairs.remainder();
    for (i, pair) in pairs.enumerate() {
        let (w0, w1) = (pair[0].1, pair[1].1);
        let decayed = complex_pair_product(load(deviation, 2 * i), load(e, 2 * i));
        let first = &mut carried[2 * i..2 * i + 2];
        // SAFETY: `first` holds two `C64`, four `f64`: one unaligned store.
        unsafe { _mm256_storeu_pd(first.as_mut_ptr().cast(), decayed) };
        let v = pair_coordinates_avx(p, 2 * i, decayed, forced, (w0, w1));
        let out = &mut z[2 * i..2 * i + 2];
        // SAFETY: `out` holds two `C64`, four `f64`: one unaligned store.
        unsafe { _mm256_storeu_pd(out.as_mut_ptr().cast(), v) };
    }
    if let &[(_, weight)] = last {
        let j = f.kept.len() - 1;
        carried[j] = deviation[j] * e[j];
        z[j] = p.coordinate(j, carried[j], forced, weight);
    }
}

/// Kept modes from which a flight's deviation is carried across an event two modes to an AVX
/// register ([`products_avx`](crate::expsum::products_avx), [`add_scaled_avx`]): a chain's
/// 16 take fewer instructions so (see the performance page, `docs/performance.md`); a unit's
/// two stay scalar.
#[cfg(target_arch = "x86_64")]
pub(super) const PACKED_MODES: usize = 8;

/// `h[j] += v[j]·delta` over `h`'s length (`v` at least as long), two entries to an AVX
/// register: `C64 · f64` is `(re·delta, im·delta)`, so the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
pub(super) fn add_scaled_avx(h: &mut [C64], v: &[C64], delta: f64) {
    use std::arch::x86_64::*;
    let n = h.len();
    let v = &v[..n];
    let scale = _mm256_set1_pd(delta);
    let mut j = 0;
    while j + 2 <= n {
        // SAFETY: `j + 2 ≤ n`, the length of both slices: two `C64` (four `f64`) loaded from
        // each and stored back into `h`.
        unsafe {
            let old = _mm256_loadu_pd(h.as_ptr().add(j).cast());
            let step = _mm256_mul_pd(_mm256_loadu_pd(v.as_ptr().add(j).cast()), scale);
            _mm256_storeu_pd(h.as_mut_ptr().add(j).cast(), _mm256_add_pd(old, step));
        }
        j += 2;
    }
    if j < n {
        h[j] += v[j] * delta;
    }
}

/// Two modes' columns `(re, im, z)` added in one pass over `y` (each column as long as `y`):
/// each entry gets the first mode's term and then the second's, the operations of
/// [`add_column_avx`] twice (so the same bits), `y` loaded and stored once for both rather
/// than once per mode (fewer instructions and less time on a chain: see the performance
/// page, `docs/performance.md`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
fn add_two_columns_avx(
    (re0, im0, z0): (&[f64], &[f64], C64),
    (re1, im1, z1): (&[f64], &[f64], C64),
    y: &mut [f64],
) {
    use std::arch::x86_64::*;
    let m = y.len();
    let (re0, im0, re1, im1) = (&re0[..m], &im0[..m], &re1[..m], &im1[..m]);
    let (zr0, zi0) = (_mm256_set1_pd(z0.re), _mm256_set1_pd(z0.im));
    let (zr1, zi1) = (_mm256_set1_pd(z1.re), _mm256_set1_pd(z1.im));
    let whole = m - m % 4;
    for i in (0..whole).step_by(4) {
        // SAFETY: `i + 4 ≤ m`, the length of all five slices: each load and store stays
        // within its slice.
        unsafe {
            let load = |v: &[f64]| _mm256_loadu_pd(v.as_ptr().add(i));
            let first = _mm256_sub_pd(_mm256_mul_pd(load(re0), zr0), _mm256_mul_pd(load(im0), zi0));
            let second =
                _mm256_sub_pd(_mm256_mul_pd(load(re1), zr1), _mm256_mul_pd(load(im1), zi1));
            let sum = _mm256_add_pd(_mm256_add_pd(load(y), first), second);
            _mm256_storeu_pd(y.as_mut_ptr().add(i), sum);
        }
    }
    for i in whole..m {
        y[i] += re0[i] * z0.re - im0[i] * z0.im;
        y[i] += re1[i] * z1.re - im1[i] * z1.im;
    }
}

/// `y[i] += re[i]·z.re − im[i]·z.im` over equal-length slices ([`LinearFlow::add_mode`]),
/// four entries at once with AVX: each entry's operations in the same order (no FMA), so the
/// same bits as entry by entry.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
pub(super) fn add_column_avx(re: &[f64], im: &[f64], z: C64, y: &mut [f64]) {
    use std::arch::x86_64::*;
    let m = y.len();
    let (re, im) = (&re[..m], &im[..m]);
    let (zr, zi) = (_mm256_set1_pd(z.re), _mm256_set1_pd(z.im));
    let whole = m - m % 4;
    for i in (0..whole).step_by(4) {
        // SAFETY: `i + 4 ≤ m`, the length of all three slices: each load and store stays
        // within its slice.
        unsafe {
            let r = _mm256_loadu_pd(re.as_ptr().add(i));
            let v = _mm256_loadu_pd(im.as_ptr().add(i));
            let old = _mm256_loadu_pd(y.as_ptr().add(i));
            let step = _mm256_sub_pd(_mm256_mul_pd(r, zr), _mm256_mul_pd(v, zi));
            _mm256_storeu_pd(y.as_mut_ptr().add(i), _mm256_add_pd(old, step));
        }
    }
    for i in whole..m {
        y[i] += re[i] * z.re - im[i] * z.im;
    }
}
