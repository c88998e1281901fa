//! The scalar signal `s(t)` of a response: contiguous segments from `t = 0`, each affine or a
//! finite sum of sinusoids, zero after the last.

use crate::expsum::Term;
use nalgebra::Complex;
use serde::Serialize;

type C64 = Complex<f64>;
use thiserror::Error;

/// A signal (or a response's input) refused, naming the field.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SignalError {
    /// A named value is not finite or out of range.
    #[error("{field} = {value} is out of range: must be {allowed}")]
    OutOfRange {
        /// Which value, e.g. `samples[3].time`.
        field: String,
        /// Its value.
        value: f64,
        /// The allowed range.
        allowed: &'static str,
    },
}

/// `Ok` when `ok` holds and `value` is finite, else [`SignalError::OutOfRange`].
pub(crate) fn check(
    field: impl FnOnce() -> String,
    value: f64,
    ok: bool,
    allowed: &'static str,
) -> Result<(), SignalError> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(SignalError::OutOfRange {
            field: field(),
            value,
            allowed,
        })
    }
}

/// One sinusoid `c cos νt + s sin νt` of absolute time `t`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Sinusoid {
    /// `ν ≥ 0`, rad/s (`0`: the constant `c`).
    pub frequency: f64,
    /// `c`, on `cos νt`.
    pub cos: f64,
    /// `s`, on `sin νt`.
    pub sin: f64,
}

/// The form of a signal on one segment.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Shape {
    /// `s(t) = value + slope (t − start)`, `ṡ = slope`.
    Affine {
        /// `s` at the segment's start.
        value: f64,
        /// `ṡ` on the segment.
        slope: f64,
    },
    /// `s(t) = Σ_j (c_j cos ν_j t + s_j sin ν_j t)`, in absolute time `t`.
    Sinusoids(Vec<Sinusoid>),
}

/// The signal on `[start, end)`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Segment {
    /// Its start, s.
    pub start: f64,
    /// Its end, s (`+∞` for a last segment that lasts for ever).
    pub end: f64,
    /// Its form.
    pub shape: Shape,
}

/// A scalar signal `s(t)`, `t ≥ 0`: contiguous [`Segment`]s from `t = 0`, `s = 0` after the
/// last one's end.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Signal {
    segments: Vec<Segment>,
}

/// At most this many sinusoids in one segment: each adds terms to every mode's flight, and
/// the event search's cost grows with the terms.
pub const MAX_SINUSOIDS: usize = 64;

impl Signal {
    /// The signal of `segments`, as given.
    ///
    /// # Errors
    /// [`SignalError::OutOfRange`] naming the field: `segments` (no segment),
    /// `segments[i].start` not `0` for the first or not the previous end, `segments[i].end`
    /// not after its start (`+∞` only for the last), `segments[i].value`, `.slope`,
    /// `.sinusoids[j].frequency` (finite, `≥ 0`), `.cos`, `.sin` not finite, and
    /// `segments[i].sinusoids` (its count) empty or beyond [`MAX_SINUSOIDS`].
    pub fn from_segments(segments: Vec<Segment>) -> Result<Signal, SignalError> {
        check(
            || "segments".into(),
            segments.len() as f64,
            !segments.is_empty(),
            "at least one segment",
        )?;
        let last = segments.len() - 1;
        for (i, seg) in segments.iter().enumerate() {
            let expected = if i == 0 { 0.0 } else { segments[i - 1].end };
            check(
                || format!("segments[{i}].start"),
                seg.start,
                seg.start == expected,
                "0 for the first segment, the previous segment's end for the others",
            )?;
            let end_ok = seg.end > seg.start && (seg.end.is_finite() || i == last);
            if !end_ok {
                return Err(SignalError::OutOfRange {
                    field: format!("segments[{i}].end"),
                    value: seg.end,
                    allowed: "after the start (+inf only for the last segment)",
                });
            }
            match &seg.shape {
                Shape::Affine { value, slope } => {
                    check(|| format!("segments[{i}].value"), *value, true, "finite")?;
                    check(|| format!("segments[{i}].slope"), *slope, true, "finite")?;
                }
                Shape::Sinusoids(list) => {
                    check(
                        || format!("segments[{i}].sinusoids"),
                        list.len() as f64,
                        !list.is_empty() && list.len() <= MAX_SINUSOIDS,
                        "between 1 and 64 sinusoids",
                    )?;
                    for (j, s) in list.iter().enumerate() {
                        check(
                            || format!("segments[{i}].sinusoids[{j}].frequency"),
                            s.frequency,
                            s.frequency >= 0.0,
                            ">= 0",
                        )?;
                        check(
                            || format!("segments[{i}].sinusoids[{j}].cos"),
                            s.cos,
                            true,
                            "finite",
                        )?;
                        check(
                            || format!("segments[{i}].sinusoids[{j}].sin"),
                            s.sin,
                            true,
                            "finite",
                        )?;
                    }
                }
            }
        }
        Ok(Signal { segments })
    }

    /// The piecewise-linear interpolation of the samples `(t_i, s_i)`, held at the last value
    /// after the last sample (`ṡ = 0` there). The first time is `0`; one sample is a constant.
    ///
    /// # Errors
    /// [`SignalError::OutOfRange`] naming the sample: `samples` (none), `samples[0].time`
    /// not `0`, `samples[i].time` not finite or not after the previous (decreasing or
    /// repeated times), `samples[i].value` not finite.
    pub fn from_samples(samples: &[(f64, f64)]) -> Result<Signal, SignalError> {
        check(
            || "samples".into(),
            samples.len() as f64,
            !samples.is_empty(),
            "at least one sample",
        )?;
        for (i, &(t, v)) in samples.iter().enumerate() {
            if i == 0 {
                check(|| "samples[0].time".into(), t, t == 0.0, "0 (the start)")?;
            } else {
                check(
                    || format!("samples[{i}].time"),
                    t,
                    t > samples[i - 1].0,
                    "finite and after the previous sample's time",
                )?;
            }
            check(|| format!("samples[{i}].value"), v, true, "finite")?;
        }
        let mut segments: Vec<Segment> = samples
            .windows(2)
            .map(|w| {
                let ((t0, v0), (t1, v1)) = (w[0], w[1]);
                Segment {
                    start: t0,
                    end: t1,
                    shape: Shape::Affine {
                        value: v0,
                        slope: (v1 - v0) / (t1 - t0),
                    },
                }
            })
            .collect();
        let &(t_last, v_last) = samples.last().expect("at least one sample");
        segments.push(Segment {
            start: t_last,
            end: f64::INFINITY,
            shape: Shape::Affine {
                value: v_last,
                slope: 0.0,
            },
        });
        Signal::from_segments(segments)
    }

    /// A Hann-windowed tone burst of `cycles` cycles, `A·½(1 − cos(ωt/N))·sin ωt` on
    /// `[0, 2πN/ω]`, zero after: exactly the three sinusoids
    /// `(A/2) sin ωt − (A/4) sin ω(1 + 1/N)t − (A/4) sin ω(1 − 1/N)t`
    /// (`cos a sin b = ½(sin(b + a) + sin(b − a))`).
    ///
    /// # Errors
    /// [`SignalError::OutOfRange`] naming `amplitude` (finite), `omega` (`> 0`) or `cycles`
    /// (`≥ 1`, so that every frequency is `≥ 0`).
    pub fn tone_burst(amplitude: f64, omega: f64, cycles: f64) -> Result<Signal, SignalError> {
        check(|| "amplitude".into(), amplitude, true, "finite")?;
        check(|| "omega".into(), omega, omega > 0.0, "> 0")?;
        check(|| "cycles".into(), cycles, cycles >= 1.0, ">= 1")?;
        let end = std::f64::consts::TAU * cycles / omega;
        check(
            || "omega".into(),
            end,
            end > 0.0,
            "with a burst of positive length",
        )?;
        let sine = |frequency: f64, sin: f64| Sinusoid {
            frequency,
            cos: 0.0,
            sin,
        };
        Signal::from_segments(vec![Segment {
            start: 0.0,
            end,
            shape: Shape::Sinusoids(vec![
                sine(omega, 0.5 * amplitude),
                sine(omega * (1.0 + 1.0 / cycles), -0.25 * amplitude),
                sine(omega * (1.0 - 1.0 / cycles), -0.25 * amplitude),
            ]),
        }])
    }

    /// A stepped sine sweep: for each step `(ν, A, duration)` in turn, `A sin ν(t − t_step)`
    /// from the step's start `t_step` (each step starts at phase 0; `s` may jump between
    /// steps, the state is carried across), zero after the last.
    ///
    /// # Errors
    /// [`SignalError::OutOfRange`] naming `steps` (none) or `steps[i].frequency` (`≥ 0`),
    /// `steps[i].amplitude` (finite), `steps[i].duration` (`> 0`, finite).
    pub fn stepped_sweep(steps: &[(f64, f64, f64)]) -> Result<Signal, SignalError> {
        check(
            || "steps".into(),
            steps.len() as f64,
            !steps.is_empty(),
            "at least one step",
        )?;
        let mut segments = Vec::with_capacity(steps.len());
        let mut start = 0.0;
        for (i, &(nu, amplitude, duration)) in steps.iter().enumerate() {
            check(|| format!("steps[{i}].frequency"), nu, nu >= 0.0, ">= 0")?;
            check(
                || format!("steps[{i}].amplitude"),
                amplitude,
                true,
                "finite",
            )?;
            check(
                || format!("steps[{i}].duration"),
                duration,
                duration > 0.0,
                "> 0",
            )?;
            let end = start + duration;
            // A sin ν(t − t₀) = A cos νt₀ sin νt − A sin νt₀ cos νt.
            let (sin0, cos0) = crate::trig::sin_cos(nu * start);
            segments.push(Segment {
                start,
                end,
                shape: Shape::Sinusoids(vec![Sinusoid {
                    frequency: nu,
                    cos: -amplitude * sin0,
                    sin: amplitude * cos0,
                }]),
            });
            start = end;
        }
        Signal::from_segments(segments)
    }

    /// The segments, in time order.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// The end of the last segment: `s = 0` from there on (`+∞` when the last lasts for
    /// ever).
    pub fn end(&self) -> f64 {
        self.segments.last().map_or(0.0, |s| s.end)
    }

    /// The index of the segment holding `t` (`t ∈ [start, end)`), `None` past the end.
    pub(crate) fn segment_at(&self, t: f64) -> Option<usize> {
        let i = self.segments.partition_point(|s| s.end <= t);
        (i < self.segments.len()).then_some(i)
    }

    /// `(s(t), ṡ(t))` (zero past the end; at a segment boundary, the later segment's).
    pub fn value_and_rate(&self, t: f64) -> (f64, f64) {
        self.value_and_rate_in(self.segment_at(t), t)
    }

    /// `(s(t), ṡ(t))` by segment `segment`'s form (`None`: past the end, zero).
    pub(crate) fn value_and_rate_in(&self, segment: Option<usize>, t: f64) -> (f64, f64) {
        match segment {
            None => (0.0, 0.0),
            Some(i) => {
                let seg = &self.segments[i];
                match &seg.shape {
                    Shape::Affine { value, slope } => (value + slope * (t - seg.start), *slope),
                    Shape::Sinusoids(list) => list.iter().fold((0.0, 0.0), |(v, r), s| {
                        let (sin, cos) = crate::trig::sin_cos(s.frequency * t);
                        (
                            v + s.cos * cos + s.sin * sin,
                            r + s.frequency * (s.sin * cos - s.cos * sin),
                        )
                    }),
                }
            }
        }
    }

    /// `α s(t₀ + σ) + β ṡ(t₀ + σ)` on segment `segment` (`None`: past the end, nothing) as
    /// terms in `σ`, added to `out`: a polynomial of degree one for an affine segment,
    /// `Re((α + iνβ) A e^{iνσ})`, `A = (c − i s) e^{iνt₀}`, per sinusoid.
    pub(crate) fn add_terms(
        &self,
        segment: Option<usize>,
        t0: f64,
        (alpha, beta): (f64, f64),
        out: &mut Vec<Term>,
    ) {
        let Some(i) = segment else { return };
        let seg = &self.segments[i];
        let zero = C64::new(0.0, 0.0);
        let real = |v: f64| C64::new(v, 0.0);
        match &seg.shape {
            Shape::Affine { value, slope } => {
                let s0 = value + slope * (t0 - seg.start);
                out.push(Term {
                    poly: [
                        real(alpha * s0 + beta * slope),
                        real(alpha * slope),
                        zero,
                        zero,
                    ],
                    rate: zero,
                });
            }
            Shape::Sinusoids(list) => {
                for x in list {
                    let nu = x.frequency;
                    let (sin, cos) = crate::trig::sin_cos(nu * t0);
                    let a = C64::new(x.cos, -x.sin) * C64::new(cos, sin);
                    let c = C64::new(alpha, nu * beta) * a;
                    let rate = C64::new(0.0, nu);
                    out.push(Term {
                        poly: [c, zero, zero, zero],
                        rate,
                    });
                }
            }
        }
    }

    /// The fastest frequency among the sinusoids (`0` for none).
    pub(crate) fn fastest_frequency(&self) -> f64 {
        self.segments
            .iter()
            .flat_map(|s| match &s.shape {
                Shape::Sinusoids(list) => list.iter().map(|x| x.frequency).collect(),
                Shape::Affine { .. } => Vec::new(),
            })
            .fold(0.0, f64::max)
    }
}
