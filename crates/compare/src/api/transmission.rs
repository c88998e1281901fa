//! `rattle transmission`: the Welch estimate of the transmissibility from the base to the
//! observed body under random base motion, level by level, over independent records from
//! rest, beside the exact linear response of the structure with its stops removed
//! ([`crate::runs::transmission`] for the plan, [`crate::spectrum::welch`] for the
//! estimator).

use super::respond::{prepare_spec, PreparedResponse};
use super::{ApiError, ResponseRequest};
use crate::output::transmission::TransmissionRecord;
use crate::runs::parallel::Progress;
use crate::runs::shard::Shard;
use crate::runs::transmission::{
    finish, linear_summary, merge_parts, plan, run_all, Plan, PlanInput, RunKey, RunRecords,
    PART_KIND,
};
pub use crate::runs::transmission::{TransmissionOptions, TransmissionPart};
use crate::scene::frequency::{structure_natural_frequencies, structure_slowest_decay_rate};
use crate::scene::signal::random::RandomSpec;
use crate::scene::signal::SignalSpec;
use crate::scene::AnyScene;
use rattle_event_driven::MAX_RESPONSE_SAMPLES;

/// What to estimate: `rattle transmission SCENE --signal random:… --duration T …`.
#[derive(Debug, Clone, PartialEq)]
pub struct TransmissionRequest {
    /// `--signal`: `random:band=LO-HI,rms=A,seed=S[,psd=FILE]`.
    pub signal: String,
    /// `T`, s: each record's duration from rest.
    pub duration: f64,
    /// The levels, seeds, segment, overlap, confidence and transient cut.
    pub options: TransmissionOptions,
}

impl TransmissionRequest {
    /// `signal` over `duration` with the default options ([`TransmissionOptions::default`]).
    pub fn new(signal: &str, duration: f64) -> TransmissionRequest {
        TransmissionRequest {
            signal: signal.to_owned(),
            duration,
            options: TransmissionOptions::default(),
        }
    }
}

/// A request checked and planned, ready to run: every refusal happens here, before anything
/// is computed or written.
#[derive(Debug, Clone)]
pub struct PreparedTransmission {
    scene: AnyScene,
    spec: RandomSpec,
    request: TransmissionRequest,
    plan: Plan,
    observe: String,
    reference: Vec<Option<(f64, f64)>>,
    linear: crate::output::transmission::LinearSummary,
}

/// Checks and plans `request` on `scene`: the signal must be `random:…`, every option in
/// its range, and the first run must build.
///
/// # Errors
/// [`ApiError::Argument`] naming the option: `--duration` (finite, `> 0`; at most 10⁷
/// samples at four per period of the band's top), `--signal` (not `random:…`, or a field of
/// it), `--levels`, `--seeds`, `--segment`, `--overlap`, `--confidence`, `--transient`
/// ([`crate::runs::transmission::plan`]); as [`super::prepare_response`] for the scene.
pub fn prepare_transmission(
    scene: &AnyScene,
    request: &TransmissionRequest,
) -> Result<PreparedTransmission, ApiError> {
    let duration = request.duration;
    if !(duration.is_finite() && duration > 0.0) {
        return Err(ApiError::Argument(format!(
            "--duration = {duration} is out of range: must be finite and > 0 (s)"
        )));
    }
    let spec = match SignalSpec::parse(&request.signal).map_err(super::argument)? {
        SignalSpec::Random(spec) => spec,
        _ => {
            return Err(ApiError::Argument(format!(
            "--signal {}: must be a random base motion, random:band=LO-HI,rms=A,seed=S[,psd=FILE]",
            request.signal
        )))
        }
    };
    // The first run, built: a scene or a signal the response refuses is refused here.
    let first = prepared_run(scene, &spec, request, spec.rms, spec.seed)?;
    let structure = first.structure();
    let rate = structure_slowest_decay_rate(structure);
    let input = PlanInput {
        signal: &request.signal,
        band: spec.band,
        rms: spec.rms,
        seed: spec.seed,
        psd: spec.psd.as_deref().map(|p| p.display().to_string()),
        duration,
        slowest_decay_rate: rate,
        max_samples: MAX_RESPONSE_SAMPLES,
    };
    let plan = plan(&input, &request.options).map_err(ApiError::Argument)?;
    let frequencies = plan.frequencies();
    let reference: Vec<Option<(f64, f64)>> = frequencies
        .iter()
        .map(|&w| structure.base_response(w).map(|h| (h.re, h.im)))
        .collect();
    let magnitude = |w: f64| structure.base_response(w).map_or(f64::NAN, |h| h.norm());
    let linear = linear_summary(
        structure_natural_frequencies(structure),
        rate,
        &frequencies,
        &magnitude,
    );
    Ok(PreparedTransmission {
        scene: scene.clone(),
        observe: structure.names[structure.observe].clone(),
        spec,
        request: request.clone(),
        plan,
        reference,
        linear,
    })
}

/// The response of `scene` to `spec` at level `rms` and seed `seed` over the request's `T`,
/// checked and built.
fn prepared_run(
    scene: &AnyScene,
    spec: &RandomSpec,
    request: &TransmissionRequest,
    rms: f64,
    seed: u64,
) -> Result<PreparedResponse, ApiError> {
    let run = SignalSpec::Random(RandomSpec {
        rms,
        seed,
        ..spec.clone()
    });
    prepare_spec(
        scene,
        &run,
        &ResponseRequest {
            signal: request.signal.clone(),
            duration: request.duration,
            at: Vec::new(),
            on: None,
        },
    )
}

impl PreparedTransmission {
    /// The plan: every setting the document states.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// Every run, `(level, seed)`, in the order they are combined.
    pub fn runs(&self) -> Vec<RunKey> {
        self.plan.runs()
    }

    /// The records of one run: the response from rest sampled at `t_j = jT/N`, the samples
    /// from `j₀` on of the base and of the observed body.
    fn records(&self, key: &RunKey) -> Result<RunRecords, ApiError> {
        let prepared = prepared_run(&self.scene, &self.spec, &self.request, key.rms, key.seed)?;
        let observe = 2 + prepared.structure().observe;
        let first = self.plan.first_sample();
        let kept = self.plan.settings.record_samples as usize;
        let (mut base, mut body) = (Vec::with_capacity(kept), Vec::with_capacity(kept));
        let mut j = 0u64;
        let record = prepared.run(
            Some(self.plan.settings.samples),
            &Progress::hidden(),
            &mut |row| {
                if j >= first {
                    base.push(row[1]);
                    body.push(row[observe]);
                }
                j += 1;
                Ok(())
            },
        )?;
        Ok(RunRecords {
            base,
            body,
            impacts: record.summary.impacts,
        })
    }

    /// Runs every run (in parallel, `progress` stepping once per run) and finishes the
    /// document.
    ///
    /// # Errors
    /// [`ApiError::Numerical`] when a run fails (the first in the runs' order).
    pub fn run(&self, progress: &Progress) -> Result<TransmissionRecord, ApiError> {
        let runs = run_all(&self.plan, &self.runs(), progress, |k| self.records(k))?;
        Ok(finish(
            (self.scene.name(), &self.observe),
            &self.plan.settings,
            &self.linear,
            &self.reference,
            &runs,
        ))
    }

    /// Runs part `shard` of the runs (a contiguous block, in their order) and keeps their
    /// segment sums, for [`merge_transmission`].
    ///
    /// # Errors
    /// As [`PreparedTransmission::run`].
    pub fn run_part(
        &self,
        shard: Shard,
        progress: &Progress,
    ) -> Result<TransmissionPart, ApiError> {
        let all = self.runs();
        let block = &all[shard.range(all.len())];
        let runs = run_all(&self.plan, block, progress, |k| self.records(k))?;
        Ok(TransmissionPart {
            kind: PART_KIND.to_owned(),
            shard,
            total_runs: all.len(),
            scene: self.scene.name().to_owned(),
            observe: self.observe.clone(),
            settings: self.plan.settings.clone(),
            linear: self.linear.clone(),
            reference: self.reference.clone(),
            runs,
        })
    }
}

/// The transmissibility estimate of `scene` under `request` ([`prepare_transmission`] then
/// [`PreparedTransmission::run`], no progress shown).
///
/// # Errors
/// As [`prepare_transmission`] and [`PreparedTransmission::run`].
pub fn transmission(
    scene: &AnyScene,
    request: &TransmissionRequest,
) -> Result<TransmissionRecord, ApiError> {
    prepare_transmission(scene, request)?.run(&Progress::hidden())
}

/// The whole estimate from the parts of a sharded one ([`PreparedTransmission::run_part`]),
/// in any order: the same bits as the whole run.
///
/// # Errors
/// [`ApiError::Argument`] when a part is missing, repeated or from another estimate.
pub fn merge_transmission(parts: &[TransmissionPart]) -> Result<TransmissionRecord, ApiError> {
    merge_parts(parts).map_err(ApiError::Argument)
}
