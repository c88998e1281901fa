//! The derivative coefficients of a function whose polynomials are all constants (every
//! steady-response flight's): what the polish, the chunk tests and the scans read `f`, `f'`,
//! `f''` and `f'''` from where the exponentials are known.

use super::*;

/// `(c, cμ, cμ²)` of every term when every polynomial is a constant `c` (the steady-response
/// flights), so that `f, f', f''` at a point where the exponentials are known cost three
/// real parts of products per term; empty otherwise.
#[derive(Debug, Clone, Default)]
pub(super) struct Derivatives(pub(super) Vec<[C64; 4]>);

/// `[c, cμ, cμ², cμ³]` of a term of constant polynomial `c` and rate `μ`, each product of
/// the one before and `μ` ([`Complex`]'s).
#[inline]
fn constant_derivatives(t: &Term) -> [C64; 4] {
    let c = t.poly[0];
    let c2 = c * t.rate * t.rate;
    [c, c * t.rate, c2, c2 * t.rate]
}

/// [`constant_derivatives`] of the terms in pairs, two complex numbers to an AVX register
/// ([`complex_pair_product`]: [`Complex`]'s products, so the same bits), into `out` (as long
/// as `terms`). Returns how many terms it formed (all but a last odd one).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn constant_derivatives_avx(terms: &[Term], out: &mut [[C64; 4]]) -> usize {
    use std::arch::x86_64::*;
    let pack = |a: C64, b: C64| _mm256_set_pd(b.im, b.re, a.im, a.re);
    let pairs = terms.len().min(out.len()) / 2;
    for (t, d) in terms
        .chunks_exact(2)
        .zip(out.chunks_exact_mut(2))
        .take(pairs)
    {
        let rate = pack(t[0].rate, t[1].rate);
        let c0 = pack(t[0].poly[0], t[1].poly[0]);
        let c1 = complex_pair_product(c0, rate);
        let c2 = complex_pair_product(c1, rate);
        let c3 = complex_pair_product(c2, rate);
        // The first term's four in the registers' low halves, the second's in the high.
        let rows = [
            _mm256_permute2f128_pd::<0x20>(c0, c1),
            _mm256_permute2f128_pd::<0x20>(c2, c3),
            _mm256_permute2f128_pd::<0x31>(c0, c1),
            _mm256_permute2f128_pd::<0x31>(c2, c3),
        ];
        // SAFETY: `d` holds two `[C64; 4]` (`repr(C)`: sixteen `f64`, each term's four
        // coefficients in order): four unaligned stores of four.
        unsafe {
            let at = d.as_mut_ptr().cast::<f64>();
            for (k, row) in rows.into_iter().enumerate() {
                _mm256_storeu_pd(at.add(4 * k), row);
            }
        }
    }
    2 * pairs
}

impl Derivatives {
    pub(super) fn of(&mut self, f: &ExpSum) {
        if f.terms
            .iter()
            .all(|t| t.poly[1..].iter().all(|c| *c == C64::default()))
        {
            self.of_constants(f);
        } else {
            self.0.clear();
        }
    }

    /// [`Self::of`] for `f` whose polynomials are all constants, without testing them: the
    /// fixed grid's search ([`ExpSum::fixed_search`]) is made only for such `f` (its chunk
    /// sums read the constant coefficients alone), and the test of a chain's seventeen terms,
    /// six comparisons each, once per search that reaches a chunk not excluded at once, would
    /// take some 2.7 % of a chain's time.
    pub(super) fn of_constants(&mut self, f: &ExpSum) {
        debug_assert!(f
            .terms
            .iter()
            .all(|t| t.poly[1..].iter().all(|c| *c == C64::default())));
        #[cfg(target_arch = "x86_64")]
        if f.terms.len() >= PACKED_TERMS && std::arch::is_x86_feature_detected!("avx") {
            // Every entry is written below: storage of the right length is only kept (zeroing
            // it first would be a third of the packed derivatives' instructions).
            self.0.resize(f.terms.len(), [C64::default(); 4]);
            // SAFETY: the CPU has AVX (checked just above).
            let done = unsafe { constant_derivatives_avx(&f.terms, &mut self.0) };
            for (d, t) in self.0[done..].iter_mut().zip(&f.terms[done..]) {
                *d = constant_derivatives(t);
            }
            return;
        }
        self.0.clear();
        self.0.extend(f.terms.iter().map(constant_derivatives));
    }

    /// `f` at `s`, given `exps[j] = e^{μ_j s}`.
    #[inline]
    pub(super) fn value(&self, f: &ExpSum, s: f64, exps: &[C64]) -> f64 {
        if self.0.is_empty() {
            return f
                .terms
                .iter()
                .zip(exps)
                .map(|(t, &e)| {
                    let p = t.poly;
                    ((p[0] + (p[1] + (p[2] + p[3] * s) * s) * s) * e).re
                })
                .sum();
        }
        self.0
            .iter()
            .zip(exps)
            .map(|(c, e)| c[0].re * e.re - c[0].im * e.im)
            .sum()
    }

    /// `(f, f', f'', f''')` at `s`, given `exps[j] = e^{μ_j s}`, for steady-response flights
    /// (every polynomial a constant); `f''' = NaN` otherwise.
    #[inline]
    pub(super) fn at3(&self, f: &ExpSum, s: f64, exps: &[C64]) -> (f64, f64, f64, f64) {
        if self.0.is_empty() {
            let (v, d, dd) = f.eval2_with(s, exps);
            return (v, d, dd, f64::NAN);
        }
        let re = |a: C64, b: C64| a.re * b.re - a.im * b.im;
        let (mut v, mut d, mut dd, mut d3) = (0.0, 0.0, 0.0, 0.0);
        for (c, &e) in self.0.iter().zip(exps) {
            v += re(c[0], e);
            d += re(c[1], e);
            dd += re(c[2], e);
            d3 += re(c[3], e);
        }
        (v, d, dd, d3)
    }

    /// `f'''` at the point where `exps[j] = e^{μ_j s}`, for steady-response flights; `NaN`
    /// otherwise.
    #[inline]
    pub(super) fn third(&self, exps: &[C64]) -> f64 {
        if self.0.is_empty() {
            return f64::NAN;
        }
        self.0
            .iter()
            .zip(exps)
            .map(|(c, e)| c[3].re * e.re - c[3].im * e.im)
            .sum()
    }

    /// `(f, f', f'')` at `s`, given `exps[j] = e^{μ_j s}`.
    #[inline]
    pub(super) fn at(&self, f: &ExpSum, s: f64, exps: &[C64]) -> (f64, f64, f64) {
        if self.0.is_empty() {
            return f.eval2_with(s, exps);
        }
        let re = |a: C64, b: C64| a.re * b.re - a.im * b.im;
        let (mut v, mut d, mut dd) = (0.0, 0.0, 0.0);
        for (c, &e) in self.0.iter().zip(exps) {
            v += re(c[0], e);
            d += re(c[1], e);
            dd += re(c[2], e);
        }
        (v, d, dd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The packed derivatives of constant terms are bit for bit the scalar ones, for odd and
    /// even numbers of terms of rates and coefficients over several decades.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn packed_constant_derivatives_are_the_scalar_ones() {
        if !std::arch::is_x86_feature_detected!("avx") {
            eprintln!("skipped: this CPU has no AVX");
            return;
        }
        let value = |i: usize, a: f64| (a * i as f64 + 0.3).sin() * 10f64.powi(i as i32 % 5 - 2);
        for n in [0, 1, 2, 5, 17] {
            let terms: Vec<Term> = (0..n)
                .map(|j| Term {
                    poly: [
                        C64::new(value(j, 1.7), value(j, 0.4)),
                        C64::default(),
                        C64::default(),
                        C64::default(),
                    ],
                    rate: C64::new(-value(j, 0.7).abs(), value(j, 3.1)),
                })
                .collect();
            let mut packed = vec![[C64::default(); 4]; n];
            // SAFETY: the CPU has AVX.
            let done = unsafe { constant_derivatives_avx(&terms, &mut packed) };
            assert_eq!(done, n - n % 2);
            let bits = |d: &[C64; 4]| d.map(|c| (c.re.to_bits(), c.im.to_bits()));
            for (d, t) in packed[..done].iter().zip(&terms) {
                assert_eq!(bits(d), bits(&constant_derivatives(t)), "{n} terms");
            }
        }
    }
}
