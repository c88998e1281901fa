//! The event core's sine and cosine.
//!
//! Every `sin`/`cos` of the event-driven solver (the exponentials of its flights, the forcing
//! phase at a contact, a shifted model's forcing, a trace's base displacement) goes through
//! [`sin_cos`], so that a value computed in two places is the same double in both (a flight's
//! forcing phase and a contact's, for one).
//!
//! It is musl's `sincos` (the `libm` crate: fdlibm's argument reduction by π/2 in up to three
//! parts, and its degree-13/14 kernels), not the platform's: glibc's `sincos` switches the
//! rounding mode on every call, and was 12 % of the CPU of `cargo xtask figures` and of the
//! `steady_sweep` example, half that with this one (perf, see the commit). Its error is below
//! one unit in the last place; glibc's is correctly rounded nearly everywhere, so the two
//! differ by one unit in the last place on about 3 % of arguments (measured on 2·10⁶ of them
//! in `[−10, 3000]`; the test below checks the bound from `1e-8` to `2e9` and next to the
//! first 2000 multiples of `π/2`). The analytic solver
//! keeps the platform's: the two solvers derive their numerics independently.
//!
//! Measured and not taken (`steady_sweep`, interleaved medians of 5, same session): this
//! module 0.52 s, glibc's 0.55 s; the same algorithm copied here to be inlined, 0.55 s; and a
//! flight's terms four at a time in AVX registers (every branch computed, the lane's taken by
//! masks, bit for bit the scalar copy), 0.64 s: most arguments are below `π/4`, where the
//! scalar form does no reduction at all.

/// `(sin x, cos x)`, each within one unit in the last place; NaN for an infinite or NaN `x`.
#[inline]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place between `a` and the reference `b`.
    fn ulps(a: f64, b: f64) -> u64 {
        let (a, b) = (a.to_bits() as i64, b.to_bits() as i64);
        if (a < 0) != (b < 0) {
            // Opposite signs: only both zeros (or values next to zero) may meet here.
            return (a & i64::MAX).unsigned_abs() + (b & i64::MAX).unsigned_abs();
        }
        a.abs_diff(b)
    }

    #[test]
    fn sin_cos_is_within_one_ulp_of_the_platform_from_tiny_to_huge_arguments() {
        let mut worst = 0;
        let mut differing = 0;
        let mut count = 0;
        // Arguments over the range the flights reach (rates up to ~1e2 over times up to ~1e5)
        // and beyond, where the reduction changes method, and the doubles next to the first
        // 2000 multiples of π/2 (where the reduction cancels most), both signs.
        let mut xs: Vec<f64> = (-8..=9)
            .flat_map(|decade| {
                (0..2000).map(move |i| {
                    10f64.powi(decade) * (1.0 + (i as f64 * 0.754_877_666_246_692_7).fract())
                })
            })
            .collect();
        for k in 1..=2000 {
            let m = k as f64 * std::f64::consts::FRAC_PI_2;
            xs.extend([
                f64::from_bits(m.to_bits() - 1),
                m,
                f64::from_bits(m.to_bits() + 1),
            ]);
        }
        for x in xs.into_iter().flat_map(|x| [x, -x]) {
            let (s, c) = sin_cos(x);
            let (rs, rc) = x.sin_cos();
            for (v, r) in [(s, rs), (c, rc)] {
                let d = ulps(v, r);
                worst = worst.max(d);
                differing += usize::from(d != 0);
                count += 1;
            }
        }
        assert!(worst <= 1, "worst {worst} ulp");
        // Not the same function: some differ (else this module would be pointless to test).
        assert!(
            differing > 0 && differing < count / 10,
            "{differing} of {count}"
        );
    }

    #[test]
    fn exact_values_and_non_finite_arguments() {
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert_eq!(sin_cos(-0.0).0.to_bits(), (-0.0f64).to_bits());
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let (s, c) = sin_cos(x);
            assert!(s.is_nan() && c.is_nan(), "{x}");
        }
    }
}
