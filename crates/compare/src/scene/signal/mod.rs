//! The signals of `rattle respond`: a `--signal SPEC` read and built into the event-driven
//! engine's [`Signal`], with a description of what is solved.
//!
//! `SPEC` is one of
//!
//! - `F.csv`: a record, columns `t,u_g` (a base displacement, m) or `t,F` (a force, N, on the
//!   body `--on` names), `t` from 0 and strictly increasing; the signal is the piecewise-linear
//!   interpolation of the samples, held at the last value after the last ([`mod@file`]);
//! - `tone-burst:omega=W,cycles=N[,amplitude=A]`: the Hann-windowed burst
//!   `A·½(1 − cos(ωt/N))·sin ωt` on `[0, 2πN/ω]`, zero after, exactly three sinusoids;
//! - `sweep:from=W1,to=W2,rate=R[,amplitude=A][,steps=N]`: a linear sine sweep at `R` rad/s²,
//!   up or down, continuous or stepped ([`sweep`]);
//! - `random:band=LO-HI,rms=A,seed=S[,psd=FILE]`: a stationary random base motion, a
//!   random-phase multisine on the lines `k·2π/T` inside the band ([`random`]).
//!
//! The amplitude of a burst or a sweep defaults to the scene's base amplitude `u_g` (1 m when
//! the scene's base does not move).

pub mod file;
pub mod random;
pub mod sweep;

use rattle_event_driven::{Signal, Sinusoid};
use serde::Serialize;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Relative accuracy the built signals keep to their ideal forms: a continuous sweep's
/// instantaneous-frequency step and phase error, a random record's interpolation error.
pub const SIGNAL_ACCURACY: f64 = 1e-3;

/// At most this many segments (samples of a record, steps of a sweep) in a built signal:
/// each is a flight of the engine and about 80 bytes.
pub const MAX_SEGMENTS: usize = 1 << 22;

/// A `--signal` refused, naming the field.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("--signal {spec}: {field} {reason}")]
pub struct SignalSpecError {
    /// The signal's kind (`tone-burst`, `sweep`, `random`) or file.
    pub spec: String,
    /// The field: a parameter (`cycles`, `band`, `rms`), or a file's column (`t`, `u_g`,
    /// `columns`).
    pub field: String,
    /// What is wrong with it.
    pub reason: String,
}

impl SignalSpecError {
    /// The error of `field` in `spec`, saying `reason`.
    pub fn new(spec: &str, field: &str, reason: impl Into<String>) -> SignalSpecError {
        SignalSpecError {
            spec: spec.to_owned(),
            field: field.to_owned(),
            reason: reason.into(),
        }
    }

    /// `field = value is out of range: must be allowed`.
    fn range(spec: &str, field: &str, value: impl std::fmt::Display, allowed: &str) -> Self {
        Self::new(
            spec,
            field,
            format!("= {value} is out of range: must be {allowed}"),
        )
    }
}

/// A `--signal` as written.
#[derive(Debug, Clone, PartialEq)]
pub enum SignalSpec {
    /// A CSV record.
    File(PathBuf),
    /// A Hann-windowed tone burst.
    ToneBurst {
        /// `ω`, rad/s.
        omega: f64,
        /// `N ≥ 1` cycles.
        cycles: f64,
        /// `A` (default: the scene's `u_g`).
        amplitude: Option<f64>,
    },
    /// A linear sine sweep.
    Sweep(sweep::SweepSpec),
    /// A random base motion.
    Random(random::RandomSpec),
}

/// What drives the structure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Input {
    /// A base displacement `u_g(t)`, m, through the springs and dashpots tied to the base.
    Base,
    /// A force `F(t)`, N, on one body.
    Force,
}

impl Input {
    /// The column of the signal in the sampled tables: `u_g` or `F`.
    pub fn column(self) -> &'static str {
        match self {
            Input::Base => "u_g",
            Input::Force => "F",
        }
    }
}

/// What a built signal is, for the response's document: its kind, its parameters and the
/// numbers derived from them.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum SignalDescription {
    /// A record from a file.
    File {
        /// The file as given.
        path: String,
        /// `u_g` (a base displacement) or `F` (a force).
        column: &'static str,
        /// Its samples.
        samples: usize,
        /// Its last time, s (the value is held after it).
        last_time: f64,
        /// The shortest step between samples, s.
        shortest_step: f64,
    },
    /// A Hann-windowed tone burst: exactly three sinusoids on `[0, 2πN/ω]`, zero after.
    ToneBurst {
        /// `ω`, rad/s.
        omega: f64,
        /// `N`.
        cycles: f64,
        /// `A`.
        amplitude: f64,
        /// `2πN/ω`, s.
        burst_duration: f64,
        /// The three sinusoids' frequencies `ω, ω(1 + 1/N), ω(1 − 1/N)`, rad/s.
        frequencies: [f64; 3],
    },
    /// A continuous linear sweep, solved as phase-continuous constant-frequency segments.
    Sweep(sweep::SweepDescription),
    /// A stepped sweep.
    SteppedSweep(sweep::SteppedDescription),
    /// A random-phase multisine.
    Random(random::RandomDescription),
}

impl SignalDescription {
    /// The highest frequency the signal holds, rad/s (`0` for a record, whose content is its
    /// samples').
    pub fn fastest_frequency(&self) -> f64 {
        match self {
            SignalDescription::File { .. } => 0.0,
            SignalDescription::ToneBurst { frequencies, .. } => frequencies[1],
            SignalDescription::Sweep(s) => s.from.max(s.to),
            SignalDescription::SteppedSweep(s) => s.from.max(s.to),
            SignalDescription::Random(r) => r.band[1],
        }
    }

    /// A few words for a table: the kind and its parameters.
    pub fn words(&self) -> String {
        match self {
            SignalDescription::File {
                path,
                column,
                samples,
                ..
            } => format!("record {path} ({column}, {samples} samples)"),
            SignalDescription::ToneBurst {
                omega,
                cycles,
                amplitude,
                ..
            } => format!("tone burst ω = {omega} rad/s, {cycles} cycles, amplitude {amplitude}"),
            SignalDescription::Sweep(s) => format!(
                "sweep {} → {} rad/s at {} rad/s², amplitude {} ({} segments)",
                s.from, s.to, s.rate, s.amplitude, s.segments
            ),
            SignalDescription::SteppedSweep(s) => format!(
                "stepped sweep {} → {} rad/s in {} steps, amplitude {}",
                s.from, s.to, s.steps, s.amplitude
            ),
            SignalDescription::Random(r) => format!(
                "random band {}–{} rad/s, rms {}, seed {} ({} lines, {})",
                r.band[0], r.band[1], r.rms, r.seed, r.lines, r.solved_as
            ),
        }
    }
}

/// A built signal: the engine's [`Signal`], what it drives, and its description.
#[derive(Debug, Clone, PartialEq)]
pub struct BuiltSignal {
    /// The signal.
    pub signal: Signal,
    /// A base displacement or a force.
    pub input: Input,
    /// What it is.
    pub description: SignalDescription,
}

/// The key-value parameters of a parametric spec, each used once.
struct Params<'a> {
    kind: &'a str,
    pairs: Vec<(&'a str, &'a str, bool)>,
}

impl<'a> Params<'a> {
    fn parse(kind: &'a str, text: &'a str) -> Result<Params<'a>, SignalSpecError> {
        let mut pairs: Vec<(&str, &str, bool)> = Vec::new();
        for item in text.split(',').filter(|s| !s.trim().is_empty()) {
            let Some((key, value)) = item.split_once('=') else {
                return Err(SignalSpecError::new(
                    kind,
                    item.trim(),
                    "has no value: write KEY=VALUE",
                ));
            };
            let key = key.trim();
            if pairs.iter().any(|(k, _, _)| *k == key) {
                return Err(SignalSpecError::new(kind, key, "is given twice"));
            }
            pairs.push((key, value.trim(), false));
        }
        Ok(Params { kind, pairs })
    }

    fn take(&mut self, key: &str) -> Option<&'a str> {
        let pair = self.pairs.iter_mut().find(|(k, _, _)| *k == key)?;
        pair.2 = true;
        Some(pair.1)
    }

    fn required(&mut self, key: &str) -> Result<&'a str, SignalSpecError> {
        self.take(key)
            .ok_or_else(|| SignalSpecError::new(self.kind, key, "is missing"))
    }

    fn number(&self, key: &str, text: &str) -> Result<f64, SignalSpecError> {
        text.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| SignalSpecError::range(self.kind, key, text, "a finite number"))
    }

    fn required_number(&mut self, key: &str) -> Result<f64, SignalSpecError> {
        let text = self.required(key)?;
        self.number(key, text)
    }

    fn optional_number(&mut self, key: &str) -> Result<Option<f64>, SignalSpecError> {
        self.take(key).map(|t| self.number(key, t)).transpose()
    }

    /// Refuses a key no one took.
    fn finish(self, known: &str) -> Result<(), SignalSpecError> {
        match self.pairs.iter().find(|(_, _, used)| !used) {
            Some((key, _, _)) => Err(SignalSpecError::new(
                self.kind,
                key,
                format!(
                    "is not a parameter of {}: the parameters are {known}",
                    self.kind
                ),
            )),
            None => Ok(()),
        }
    }
}

impl SignalSpec {
    /// Reads `--signal SPEC`.
    ///
    /// # Errors
    /// [`SignalSpecError`] naming the parameter: an unknown kind, a missing, repeated or
    /// unknown key, a value that is not a finite number or out of its range (`omega > 0`,
    /// `cycles ≥ 1`, `from`, `to > 0` and different, `rate > 0`, `steps ≥ 2`, a band
    /// `0 ≤ LO < HI`, `rms > 0`).
    pub fn parse(text: &str) -> Result<SignalSpec, SignalSpecError> {
        let text = text.trim();
        let Some((kind, rest)) = text.split_once(':') else {
            return if text.ends_with(".csv") {
                Ok(SignalSpec::File(PathBuf::from(text)))
            } else {
                Err(SignalSpecError::new(
                    text,
                    "kind",
                    "is not a signal: write a .csv file, tone-burst:…, sweep:… or random:…",
                ))
            };
        };
        let mut p = Params::parse(kind, rest)?;
        let spec =
            match kind {
                "tone-burst" => {
                    let omega = p.required_number("omega")?;
                    let cycles = p.required_number("cycles")?;
                    let amplitude = p.optional_number("amplitude")?;
                    p.finish("omega, cycles, amplitude")?;
                    if omega <= 0.0 {
                        return Err(SignalSpecError::range(kind, "omega", omega, "> 0 (rad/s)"));
                    }
                    if cycles < 1.0 {
                        return Err(SignalSpecError::range(kind, "cycles", cycles, "≥ 1"));
                    }
                    SignalSpec::ToneBurst {
                        omega,
                        cycles,
                        amplitude,
                    }
                }
                "sweep" => {
                    let spec = sweep::SweepSpec::parse(&mut p)?;
                    p.finish("from, to, rate, amplitude, steps")?;
                    SignalSpec::Sweep(spec)
                }
                "random" => {
                    let spec = random::RandomSpec::parse(&mut p)?;
                    p.finish("band, rms, seed, psd")?;
                    SignalSpec::Random(spec)
                }
                _ if text.ends_with(".csv") => SignalSpec::File(PathBuf::from(text)),
                _ => return Err(SignalSpecError::new(
                    kind,
                    "kind",
                    "is not a signal: the kinds are tone-burst, sweep and random (or a .csv file)",
                )),
            };
        Ok(spec)
    }

    /// Whether the spec is a file (the only kind a force on a body may take).
    pub fn is_file(&self) -> bool {
        matches!(self, SignalSpec::File(_))
    }

    /// The signal over `[0, duration]`, a burst's or a sweep's amplitude defaulting to
    /// `default_amplitude`.
    ///
    /// # Errors
    /// [`SignalSpecError`] naming the field: a file's ([`file::read_columns`]), a sweep's or a
    /// random record's too many segments ([`MAX_SEGMENTS`]), a PSD file's.
    pub fn build(
        &self,
        duration: f64,
        default_amplitude: f64,
    ) -> Result<BuiltSignal, SignalSpecError> {
        match self {
            SignalSpec::File(path) => file::build(path),
            SignalSpec::ToneBurst {
                omega,
                cycles,
                amplitude,
            } => {
                let amplitude = amplitude.unwrap_or(default_amplitude);
                let signal = Signal::tone_burst(amplitude, *omega, *cycles)
                    .map_err(|e| SignalSpecError::new("tone-burst", "omega", e.to_string()))?;
                Ok(BuiltSignal {
                    signal,
                    input: Input::Base,
                    description: SignalDescription::ToneBurst {
                        omega: *omega,
                        cycles: *cycles,
                        amplitude,
                        burst_duration: std::f64::consts::TAU * cycles / omega,
                        frequencies: [
                            *omega,
                            omega * (1.0 + 1.0 / cycles),
                            omega * (1.0 - 1.0 / cycles),
                        ],
                    },
                })
            }
            SignalSpec::Sweep(spec) => spec.build(duration, default_amplitude),
            SignalSpec::Random(spec) => spec.build(duration),
        }
    }
}

/// `a sin νt + b cos νt` as the engine's sinusoid.
fn sinusoid(frequency: f64, cos: f64, sin: f64) -> Sinusoid {
    Sinusoid {
        frequency,
        cos,
        sin,
    }
}

/// The text of a path for a message or a document.
fn shown(path: &Path) -> String {
    path.display().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(text: &str) -> String {
        SignalSpec::parse(text).unwrap_err().field
    }

    #[test]
    fn specs_are_read_and_bad_ones_named() {
        assert_eq!(
            SignalSpec::parse("tone-burst:omega=2,cycles=5").unwrap(),
            SignalSpec::ToneBurst {
                omega: 2.0,
                cycles: 5.0,
                amplitude: None
            }
        );
        assert!(SignalSpec::parse("rec.csv").unwrap().is_file());
        assert_eq!(field("tone-burst:omega=2,cycles=0.5"), "cycles");
        assert_eq!(field("tone-burst:omega=-2,cycles=5"), "omega");
        assert_eq!(field("tone-burst:cycles=5"), "omega");
        assert_eq!(field("tone-burst:omega=2,cycles=5,colour=red"), "colour");
        assert_eq!(field("tone-burst:omega=2,omega=3,cycles=5"), "omega");
        assert_eq!(field("tone-burst:omega=nan,cycles=5"), "omega");
        assert_eq!(field("chirp:omega=2"), "kind");
        assert_eq!(field("noise"), "kind");
        assert_eq!(field("sweep:from=1,to=1,rate=0.1"), "to");
        assert_eq!(field("sweep:from=1,to=2,rate=0"), "rate");
        assert_eq!(field("sweep:from=1,to=2,rate=0.1,steps=1"), "steps");
        assert_eq!(field("random:band=3-1,rms=0.1,seed=1"), "band");
        assert_eq!(field("random:band=1-1,rms=0.1,seed=1"), "band");
        assert_eq!(field("random:band=1-3,rms=0,seed=1"), "rms");
        assert_eq!(field("random:band=1-3,rms=0.1,seed=-1"), "seed");
    }
}
