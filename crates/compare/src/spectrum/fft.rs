//! The discrete Fourier transform of a power-of-two length: iterative radix-2 Cooley–Tukey,
//! in place, each twiddle `e^{±2πim/n}` from `libm::sincos` (no recurrence) and no fused
//! operations, so the same input gives the same bits on every machine.
//!
//! [`inverse`] is `x_j ← Σ_k x_k e^{+2πi kj/n}` and [`forward`] `X_k ← Σ_j x_j e^{−2πi jk/n}`,
//! both unscaled: `inverse(forward(x)) = n·x`.

use std::f64::consts::TAU;

/// `x_j ← Σ_k x_k e^{+2πi kj/n}` in place, `re` and `im` the real and imaginary parts.
///
/// # Panics
/// If `re` and `im` differ in length or the length is not a power of two (or zero).
pub fn inverse(re: &mut [f64], im: &mut [f64]) {
    transform(re, im, false);
}

/// `X_k ← Σ_j x_j e^{−2πi jk/n}` in place, `re` and `im` the real and imaginary parts.
///
/// # Panics
/// If `re` and `im` differ in length or the length is not a power of two (or zero).
pub fn forward(re: &mut [f64], im: &mut [f64]) {
    transform(re, im, true);
}

/// The transform with the twiddles `e^{+2πim/n}` (`forward: false`) or their conjugates: the
/// sign of the sine is flipped, which is exact, so [`inverse`] does the same operations on
/// the same numbers whatever the direction's code path.
fn transform(re: &mut [f64], im: &mut [f64], forward: bool) {
    let n = re.len();
    assert!(
        im.len() == n && n.is_power_of_two(),
        "the FFT takes equal real and imaginary parts of a power-of-two length, not {} and {}",
        n,
        im.len()
    );
    if n <= 1 {
        return;
    }
    let bits = n.trailing_zeros();
    for i in 0..n {
        let j = i.reverse_bits() >> (usize::BITS - bits);
        if j > i {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    let twiddles: Vec<(f64, f64)> = (0..n / 2)
        .map(|m| {
            let (s, c) = libm::sincos(TAU * m as f64 / n as f64);
            (c, if forward { -s } else { s })
        })
        .collect();
    let mut len = 2;
    while len <= n {
        let stride = n / len;
        let half = len / 2;
        for start in (0..n).step_by(len) {
            for j in 0..half {
                let (wr, wi) = twiddles[j * stride];
                let (a, b) = (start + j, start + j + half);
                let vr = re[b] * wr - im[b] * wi;
                let vi = re[b] * wi + im[b] * wr;
                re[b] = re[a] - vr;
                im[b] = im[a] - vi;
                re[a] += vr;
                im[a] += vi;
            }
        }
        len *= 2;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record with no structure to hide a wrong index behind.
    fn record(n: usize) -> (Vec<f64>, Vec<f64>) {
        let re = (0..n).map(|k| ((k * 7 % 11) as f64 - 5.0) / 3.0).collect();
        let im = (0..n).map(|k| ((k * 5 % 13) as f64 - 6.0) / 4.0).collect();
        (re, im)
    }

    /// `Σ_k x_k e^{sign·2πi kj/n}` directly.
    fn direct(re: &[f64], im: &[f64], sign: f64) -> (Vec<f64>, Vec<f64>) {
        let n = re.len();
        (0..n)
            .map(|j| {
                let (mut sr, mut si) = (0.0, 0.0);
                for k in 0..n {
                    let (s, c) = (sign * TAU * (k * j) as f64 / n as f64).sin_cos();
                    sr += re[k] * c - im[k] * s;
                    si += re[k] * s + im[k] * c;
                }
                (sr, si)
            })
            .unzip()
    }

    #[test]
    fn the_fft_is_the_direct_sum() {
        for (sign, transform) in [
            (1.0, inverse as fn(&mut [f64], &mut [f64])),
            (-1.0, forward),
        ] {
            let (mut re, mut im) = record(64);
            let (sr, si) = direct(&re, &im, sign);
            transform(&mut re, &mut im);
            for j in 0..64 {
                assert!(
                    (re[j] - sr[j]).abs() < 1e-12 && (im[j] - si[j]).abs() < 1e-12,
                    "{sign} {j}"
                );
            }
        }
    }

    #[test]
    fn forward_then_inverse_is_n_times_the_record() {
        let (re0, im0) = record(256);
        let (mut re, mut im) = (re0.clone(), im0.clone());
        forward(&mut re, &mut im);
        inverse(&mut re, &mut im);
        for j in 0..256 {
            assert!((re[j] / 256.0 - re0[j]).abs() < 1e-13);
            assert!((im[j] / 256.0 - im0[j]).abs() < 1e-13);
        }
    }
}
