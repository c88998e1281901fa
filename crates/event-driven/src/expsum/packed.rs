//! Two complex numbers packed in one AVX register (`[re₀, im₀, re₁, im₁]`), shared by the
//! packed polish ([`super::polish`](mod@super::polish)), the seed points' exponentials
//! ([`super::cache`]) and the flow's packed steady state and carry (`crate::flow`): each
//! operation the scalar `C64` one, without FMA, so the same bits.

use super::C64;

/// `a·b` for the two complex numbers packed in each operand (`[re₀, im₀, re₁, im₁]`):
/// `re = a.re b.re − a.im b.im`, `im = a.re b.im + a.im b.re` (the sum's operands swapped,
/// which rounds the same), without FMA: the same bits as `C64`'s product, number by number.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
pub(crate) fn complex_pair_product(
    a: std::arch::x86_64::__m256d,
    b: std::arch::x86_64::__m256d,
) -> std::arch::x86_64::__m256d {
    use std::arch::x86_64::*;
    let straight = _mm256_mul_pd(a, _mm256_movedup_pd(b));
    let crossed = _mm256_mul_pd(
        _mm256_permute_pd::<0b0101>(a),
        _mm256_permute_pd::<0b1111>(b),
    );
    _mm256_addsub_pd(straight, crossed)
}

/// The two complex numbers packed in `v` (`[re₀, im₀, re₁, im₁]`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
pub(crate) fn complex_pair(v: std::arch::x86_64::__m256d) -> (C64, C64) {
    let mut out = [0.0; 4];
    // SAFETY: `out` holds four `f64`, the unaligned store's 32 bytes.
    unsafe { std::arch::x86_64::_mm256_storeu_pd(out.as_mut_ptr(), v) };
    (C64::new(out[0], out[1]), C64::new(out[2], out[3]))
}

/// `out[j] = a[j]·b[j]` over `out`'s length (`a` and `b` at least as long), two products to
/// an AVX register ([`complex_pair_product`]: `C64`'s, so the same bits).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
pub(crate) fn products_avx(a: &[C64], b: &[C64], out: &mut [C64]) {
    use std::arch::x86_64::*;
    let n = out.len();
    let (a, b) = (&a[..n], &b[..n]);
    let mut j = 0;
    while j + 2 <= n {
        // SAFETY: `j + 2 ≤ n`, the length of all three slices: two `C64` (`repr(C)`, four
        // `f64`) loaded from each operand and stored into `out`.
        unsafe {
            let x = _mm256_loadu_pd(a.as_ptr().add(j).cast());
            let y = _mm256_loadu_pd(b.as_ptr().add(j).cast());
            _mm256_storeu_pd(out.as_mut_ptr().add(j).cast(), complex_pair_product(x, y));
        }
        j += 2;
    }
    if j < n {
        out[j] = a[j] * b[j];
    }
}
