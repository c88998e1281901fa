//! Spectral analysis of uniformly sampled records: the radix-2 FFT ([`fft`]) and Welch's
//! averaged cross-spectral estimator of a transfer function ([`welch`]).
//!
//! Pure functions of their inputs, no threads: the same bits on every machine for the same
//! records.

pub mod fft;
pub mod welch;
