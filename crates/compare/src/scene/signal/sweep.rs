//! Linear sine sweeps, continuous and stepped.
//!
//! **Continuous** (`sweep:from=W1,to=W2,rate=R`): the ideal chirp is `A sin φ(t)`,
//! `φ(t) = W1 t ± R t²/2` (`+` up, `−` down), whose instantaneous frequency `φ' = W1 ± Rt`
//! runs from `W1` to `W2` over `T_s = |W2 − W1|/R`; after `T_s` the base keeps oscillating at
//! `W2`, phase continuous. The engine solves sinusoids of constant frequency exactly, so the
//! sweep is solved as `n` segments of length `Δ = T_s/n`, segment `j` on `[t_j, t_{j+1}]` the
//! sinusoid `A sin(φ(t_j) + ν_j (t − t_j))` at the midpoint frequency
//! `ν_j = φ'((t_j + t_{j+1})/2)`. As `φ'` is linear, `ν_j Δ = φ(t_{j+1}) − φ(t_j)` exactly:
//! the phase is continuous at every boundary and exact there, and inside a segment it errs by
//! `|φ(t) − φ_j(t)| = (R/2)|(Δ/2)² − (t − t_mid)²| ≤ RΔ²/8`. So the solved signal differs
//! from the ideal chirp by at most `A·RΔ²/8` in displacement and `A(RΔ/2 + W_max RΔ²/8)` in
//! rate, and its instantaneous frequency steps by `RΔ` between segments. `Δ` is the largest
//! `T_s/n` with `RΔ ≤ 10⁻³ · min(W1, W2)` (a relative frequency step of at most `10⁻³`) and
//! `RΔ²/8 ≤ 10⁻³` rad.
//!
//! **Stepped** (`steps=N`, `N ≥ 2`): `N` sinusoids at the frequencies evenly spaced from `W1`
//! to `W2` (ends included), each `A sin ν_i(t − t_i)` from its step's start `t_i` (phase 0 at
//! every step; the state is carried across), each lasting `T_s/N` so that the whole sweep
//! takes `T_s` as the continuous one does; the last frequency is held until the end of the
//! run.

use super::{sinusoid, BuiltSignal, Input, Params, SignalDescription, SignalSpecError};
use super::{MAX_SEGMENTS, SIGNAL_ACCURACY};
use rattle_event_driven::{Segment, Shape, Signal};
use serde::Serialize;

/// A sweep as written.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepSpec {
    /// `W1`, rad/s.
    pub from: f64,
    /// `W2`, rad/s.
    pub to: f64,
    /// `R`, rad/s².
    pub rate: f64,
    /// `A` (default: the scene's `u_g`).
    pub amplitude: Option<f64>,
    /// The number of steps of a stepped sweep; `None`: continuous.
    pub steps: Option<u64>,
}

/// A continuous sweep as solved.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepDescription {
    /// `W1`, rad/s.
    pub from: f64,
    /// `W2`, rad/s.
    pub to: f64,
    /// `R`, rad/s².
    pub rate: f64,
    /// `A`.
    pub amplitude: f64,
    /// `T_s = |W2 − W1|/R`, s.
    pub sweep_duration: f64,
    /// The segments built (those starting before the run's end, and the hold at `W2`).
    pub segments: usize,
    /// `Δ`, s.
    pub segment_duration: f64,
    /// `RΔ`, rad/s: the instantaneous frequency's step between segments.
    pub frequency_step: f64,
    /// `RΔ/min(W1, W2)`.
    pub relative_frequency_step: f64,
    /// `RΔ²/8`, rad: the largest phase error against the ideal chirp.
    pub phase_error_bound: f64,
    /// `A·RΔ²/8`: the largest displacement (or force) error against the ideal chirp.
    pub value_error_bound: f64,
    /// `A(RΔ/2 + max(W1, W2)·RΔ²/8)`: the largest rate error against the ideal chirp.
    pub rate_error_bound: f64,
}

/// A stepped sweep as solved.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SteppedDescription {
    /// `W1`, rad/s.
    pub from: f64,
    /// `W2`, rad/s.
    pub to: f64,
    /// `R`, rad/s².
    pub rate: f64,
    /// `A`.
    pub amplitude: f64,
    /// `N`.
    pub steps: u64,
    /// The steps that start before the run's end.
    pub steps_run: usize,
    /// `|W2 − W1|/(N R)`, s (the last step is held until the end of the run).
    pub step_duration: f64,
    /// `|W2 − W1|/(N − 1)`, rad/s.
    pub frequency_step: f64,
}

impl SweepSpec {
    /// Reads the sweep's parameters.
    pub(super) fn parse(p: &mut Params<'_>) -> Result<SweepSpec, SignalSpecError> {
        let kind = p.kind;
        let from = p.required_number("from")?;
        let to = p.required_number("to")?;
        let rate = p.required_number("rate")?;
        let amplitude = p.optional_number("amplitude")?;
        let steps = p.take("steps").map(|text| {
            text.parse::<u64>()
                .ok()
                .filter(|&n| n >= 2)
                .ok_or_else(|| SignalSpecError::range(kind, "steps", text, "a whole number ≥ 2"))
        });
        let steps = steps.transpose()?;
        if from <= 0.0 {
            return Err(SignalSpecError::range(kind, "from", from, "> 0 (rad/s)"));
        }
        if to <= 0.0 || to == from {
            return Err(SignalSpecError::range(
                kind,
                "to",
                to,
                "> 0 (rad/s) and different from `from`",
            ));
        }
        if rate <= 0.0 {
            return Err(SignalSpecError::range(kind, "rate", rate, "> 0 (rad/s²)"));
        }
        Ok(SweepSpec {
            from,
            to,
            rate,
            amplitude,
            steps,
        })
    }

    /// `T_s = |W2 − W1|/R`, s.
    pub fn sweep_duration(&self) -> f64 {
        (self.to - self.from).abs() / self.rate
    }

    /// The sweep over `[0, duration]`.
    pub(super) fn build(
        &self,
        duration: f64,
        default_amplitude: f64,
    ) -> Result<BuiltSignal, SignalSpecError> {
        let amplitude = self.amplitude.unwrap_or(default_amplitude);
        match self.steps {
            Some(steps) => self.stepped(duration, amplitude, steps),
            None => self.continuous(duration, amplitude),
        }
    }

    fn stepped(
        &self,
        duration: f64,
        amplitude: f64,
        steps: u64,
    ) -> Result<BuiltSignal, SignalSpecError> {
        let step = self.sweep_duration() / steps as f64;
        let run = ((duration / step).ceil() as u64).clamp(1, steps);
        if run as usize > MAX_SEGMENTS {
            return Err(SignalSpecError::range(
                "sweep",
                "steps",
                steps,
                "at most 4194304 steps in the run",
            ));
        }
        let spacing = (self.to - self.from) / (steps - 1) as f64;
        let list: Vec<(f64, f64, f64)> = (0..run)
            .map(|i| {
                let nu = self.from + spacing * i as f64;
                let start = step * i as f64;
                let length = if i + 1 == run {
                    step.max(duration - start)
                } else {
                    step
                };
                (nu, amplitude, length)
            })
            .collect();
        let signal = Signal::stepped_sweep(&list)
            .map_err(|e| SignalSpecError::new("sweep", "steps", e.to_string()))?;
        Ok(BuiltSignal {
            signal,
            input: Input::Base,
            description: SignalDescription::SteppedSweep(SteppedDescription {
                from: self.from,
                to: self.to,
                rate: self.rate,
                amplitude,
                steps,
                steps_run: run as usize,
                step_duration: step,
                frequency_step: spacing.abs(),
            }),
        })
    }

    fn continuous(&self, duration: f64, amplitude: f64) -> Result<BuiltSignal, SignalSpecError> {
        let (w1, w2, rate) = (self.from, self.to, self.rate);
        let sign = (w2 - w1).signum();
        let sweep = self.sweep_duration();
        let longest =
            (SIGNAL_ACCURACY * w1.min(w2) / rate).min((8.0 * SIGNAL_ACCURACY / rate).sqrt());
        let total = (sweep / longest).ceil().max(1.0);
        let delta = sweep / total;
        let built = (duration / delta).ceil().min(total);
        if built > MAX_SEGMENTS as f64 {
            return Err(SignalSpecError::range(
                "sweep",
                "rate",
                rate,
                "fast enough that the run needs at most 4194304 segments: raise the rate or \
                 shorten --duration",
            ));
        }
        let (total, built) = (total as u64, built as u64);
        let time = |j: u64| {
            if j == total {
                sweep
            } else {
                sweep * j as f64 / total as f64
            }
        };
        // On [t_j, t_{j+1}]: A sin(ν_j t + ψ_j), ψ_j = φ(t_j) − ν_j t_j = ∓R t_j t_{j+1}/2.
        let piece = |start: f64, end: f64, nu: f64| {
            let psi =
                (-sign * rate * start * end.min(sweep) / 2.0).rem_euclid(std::f64::consts::TAU);
            let (sin, cos) = libm::sincos(psi);
            Segment {
                start,
                end,
                shape: Shape::Sinusoids(vec![sinusoid(nu, amplitude * sin, amplitude * cos)]),
            }
        };
        let mut segments: Vec<Segment> = (0..built)
            .map(|j| {
                let (a, b) = (time(j), time(j + 1));
                piece(a, b, w1 + sign * rate * 0.5 * (a + b))
            })
            .collect();
        if built == total && sweep < duration {
            segments.push(piece(sweep, f64::INFINITY, w2));
        }
        let count = segments.len();
        let signal = Signal::from_segments(segments)
            .map_err(|e| SignalSpecError::new("sweep", "rate", e.to_string()))?;
        let step = rate * delta;
        let phase = rate * delta * delta / 8.0;
        Ok(BuiltSignal {
            signal,
            input: Input::Base,
            description: SignalDescription::Sweep(SweepDescription {
                from: w1,
                to: w2,
                rate,
                amplitude,
                sweep_duration: sweep,
                segments: count,
                segment_duration: delta,
                frequency_step: step,
                relative_frequency_step: step / w1.min(w2),
                phase_error_bound: phase,
                value_error_bound: amplitude.abs() * phase,
                rate_error_bound: amplitude.abs() * (step / 2.0 + w1.max(w2) * phase),
            }),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The solved sweep against the ideal chirp on a fine grid: within the stated bounds, and
    /// the bounds within the stated accuracy.
    #[test]
    fn the_segments_follow_the_chirp_within_the_bound() {
        for (from, to, rate) in [(0.5, 3.0, 0.05), (4.0, 1.0, 0.2), (1.0, 1.5, 0.001)] {
            let spec = SweepSpec {
                from,
                to,
                rate,
                amplitude: Some(0.7),
                steps: None,
            };
            let sweep = spec.sweep_duration();
            let built = spec.build(sweep * 1.2, 1.0).unwrap();
            let SignalDescription::Sweep(d) = &built.description else {
                panic!()
            };
            assert!(d.relative_frequency_step <= SIGNAL_ACCURACY * (1.0 + 1e-12));
            assert!(d.phase_error_bound <= SIGNAL_ACCURACY * (1.0 + 1e-12));
            let sign = (to - from).signum();
            let mut worst: f64 = 0.0;
            let mut worst_rate: f64 = 0.0;
            for i in 0..=20_000 {
                let t = sweep * 1.2 * i as f64 / 20_000.0;
                let (phase, frequency) = if t <= sweep {
                    (from * t + sign * rate * t * t / 2.0, from + sign * rate * t)
                } else {
                    (
                        from * sweep + sign * rate * sweep * sweep / 2.0 + to * (t - sweep),
                        to,
                    )
                };
                let (s, r) = built.signal.value_and_rate(t);
                worst = worst.max((s - 0.7 * phase.sin()).abs());
                worst_rate = worst_rate.max((r - 0.7 * frequency * phase.cos()).abs());
            }
            println!(
                "{from} → {to}: {worst:e} ≤ {:e}, rate {worst_rate:e} ≤ {:e}",
                d.value_error_bound, d.rate_error_bound
            );
            // The phase's rounding at t ~ T_s adds about |φ|·1e-16.
            assert!(worst <= d.value_error_bound + 1e-11, "{worst:e}");
            assert!(worst_rate <= d.rate_error_bound + 1e-11, "{worst_rate:e}");
        }
    }

    #[test]
    fn steps_hold_their_frequencies() {
        let spec = SweepSpec {
            from: 1.0,
            to: 2.0,
            rate: 0.1,
            amplitude: None,
            steps: Some(3),
        };
        let built = spec.build(15.0, 0.5).unwrap();
        // Steps of 10/3 s at 1, 1.5, 2 rad/s, the last held to 15 s.
        let (s, _) = built.signal.value_and_rate(12.0);
        let start: f64 = 20.0 / 3.0;
        assert!((s - 0.5 * (2.0 * (12.0 - start)).sin()).abs() < 1e-12);
        assert!((built.signal.end() - 15.0).abs() < 1e-12);
    }
}
