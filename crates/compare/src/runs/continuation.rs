//! Continuation in ω of every orbit of a signature (on a chain: an impact sequence) found at
//! one frequency: the branches, their bifurcation events and ends, numbered across starts.

use crate::output::finite;
use crate::output::records::{
    BranchRecord, ContinuationPointRecord, ContinuationRecord, EndRecord, EventRecord,
};
use crate::scene::analytic::chain_linear_model;
use crate::scene::analytic::orbits_of_signature;
use crate::scene::structure::StructureForm;
use crate::scene::Scene;
use crate::verdict::chain::{chain_orbits, ChainOrbitsError};
use rattle_analytic::{
    continue_orbit_after, continue_sequence_after, Branch, BranchEnd, Continuation,
    ContinuationError, ContinuationPoint, ContinuationSettings, Event,
};
use rattle_analytic::{ImpactSequence, LinearModel, SequenceOrbit, Signature, SignatureOrbit};
use std::f64::consts::PI;
use thiserror::Error;

/// A start orbit lies on a branch already followed when, interpolated to the start's
/// frequency, the branch's base phase (over π) and impact phases are this close: far above the
/// corrector's tolerance (1e-10), far below the distance of two distinct orbits of the unit
/// at one frequency (measured ≥ 1e-2 on the paper unit).
pub const SAME_BRANCH: f64 = 1e-5;

/// Every branch followed from the orbits of a signature at one frequency.
#[derive(Debug, Clone)]
pub struct Followed {
    /// The signature asked for, canonical.
    pub signature: Signature,
    /// The frequency of the start orbits, rad/s.
    pub omega_start: f64,
    /// The orbits found at `omega_start` (all of them, viable or not).
    pub start_orbits: Vec<SignatureOrbit>,
    /// Indices into `start_orbits` of the orbits followed; the others lie on a branch already
    /// followed.
    pub followed_starts: Vec<usize>,
    /// Every branch, event and end, numbered across starts.
    pub branches: Branches,
}

/// Why no continuation could be run.
#[derive(Debug, Error)]
pub enum FollowError {
    /// The scene has no stops: there is no impacting orbit to follow.
    #[error("the scene has no stops: there is no impacting orbit to follow")]
    NoStops,
    /// No orbit of the signature at the start frequency.
    #[error("no {signature} orbit over {period} period(s) at ω = {omega}: nothing to follow (try `rattle orbit --signature`)")]
    NoOrbit {
        /// The signature.
        signature: String,
        /// Its period.
        period: u32,
        /// The start frequency.
        omega: f64,
    },
    /// `--orbit K` beyond the orbits found.
    #[error(
        "--orbit = {asked} is out of range: {found} orbit(s) found at ω = {omega}, numbered from 0"
    )]
    OrbitIndex {
        /// The index asked for.
        asked: usize,
        /// How many were found.
        found: usize,
        /// The start frequency.
        omega: f64,
    },
    /// The analytic continuation refused its settings or start.
    #[error("{0}")]
    Continuation(#[from] ContinuationError),
    /// A chain's impact sequence or cells refused, or its start orbits not found.
    #[error("{0}")]
    Chain(#[from] ChainOrbitsError),
}

/// Follows every orbit of `signature` at `omega_start` (or only the `orbit`-th) within the
/// settings' frequency range, both directions, switching branches as the settings say.
///
/// # Errors
/// See [`FollowError`].
pub fn follow(
    scene: &Scene,
    signature: &Signature,
    omega_start: f64,
    orbit: Option<usize>,
    settings: &ContinuationSettings,
) -> Result<Followed, FollowError> {
    settings.validate()?;
    let stops = scene.stops_model().ok_or(FollowError::NoStops)?;
    let unit = scene.unit_model();
    let start_orbits = orbits_of_signature(scene, omega_start, signature);
    if start_orbits.is_empty() {
        return Err(FollowError::NoOrbit {
            signature: signature.to_string(),
            period: signature.period(),
            omega: omega_start,
        });
    }
    let chosen: Vec<usize> = match orbit {
        Some(k) if k >= start_orbits.len() => {
            return Err(FollowError::OrbitIndex {
                asked: k,
                found: start_orbits.len(),
                omega: omega_start,
            })
        }
        Some(k) => vec![k],
        None => (0..start_orbits.len()).collect(),
    };
    let mut out = Followed {
        signature: signature.clone(),
        omega_start,
        start_orbits: Vec::new(),
        followed_starts: Vec::new(),
        branches: Branches::default(),
    };
    let starts: Vec<SignatureOrbit> = chosen.iter().map(|&k| start_orbits[k].clone()).collect();
    let outcome = out.branches.extend_all(&unit, &stops, &starts, settings);
    for (k, followed) in chosen.into_iter().zip(outcome) {
        if followed? {
            out.followed_starts.push(k);
        }
    }
    out.start_orbits = start_orbits;
    Ok(out)
}

/// Branches, events and ends numbered across continuations from several starts.
#[derive(Debug, Clone, Default)]
pub struct Branches {
    /// Every branch (`Branch::index` is the position here).
    pub branches: Vec<Branch>,
    /// Every event; `Event::branch` indexes `branches`.
    pub events: Vec<Event>,
    /// How each branch ends (one entry per end of each branch).
    pub ends: Vec<BranchEnd>,
}

impl Branches {
    /// Follows `start` unless it lies on a branch already followed here (or on its mirror
    /// image); returns whether it was followed. Its branches end where they run onto one
    /// followed here ([`rattle_analytic::EndReason::Joins`]) and its events
    /// are listed unless listed here already.
    ///
    /// # Errors
    /// The continuation's refusal of its settings or start.
    pub fn extend(
        &mut self,
        unit: &rattle_analytic::Unit,
        stops: &rattle_analytic::Stops,
        start: &SignatureOrbit,
        settings: &ContinuationSettings,
    ) -> Result<bool, ContinuationError> {
        if self.followed(start) {
            return Ok(false);
        }
        let mut all = Continuation {
            branches: std::mem::take(&mut self.branches),
            events: std::mem::take(&mut self.events),
            ends: std::mem::take(&mut self.ends),
        };
        let outcome = continue_orbit_after(unit, stops, start, settings, &mut all);
        (self.branches, self.events, self.ends) = (all.branches, all.events, all.ends);
        outcome
    }

    /// [`Branches::extend`] for each of `starts` in turn. Returns, per start, whether it was
    /// followed (`Ok(true)`), lies on a branch already followed (`Ok(false)`) or was refused.
    /// The starts are followed one after the other, each against the branches of those
    /// before (so that no branch is followed twice): the result does not depend on the
    /// thread count.
    pub fn extend_all(
        &mut self,
        unit: &rattle_analytic::Unit,
        stops: &rattle_analytic::Stops,
        starts: &[SignatureOrbit],
        settings: &ContinuationSettings,
    ) -> Vec<Result<bool, ContinuationError>> {
        starts
            .iter()
            .map(|start| self.extend(unit, stops, start, settings))
            .collect()
    }

    /// Whether a branch already followed passes through `start`.
    fn followed(&self, start: &SignatureOrbit) -> bool {
        self.branches.iter().any(|b| passes_through(b, start))
    }
}

/// Whether `branch` passes through `orbit`: two consecutive points bracket its frequency and,
/// interpolated there, match its base phase and impact phases within [`SAME_BRANCH`].
fn passes_through(branch: &Branch, orbit: &SignatureOrbit) -> bool {
    if branch.signature != orbit.signature {
        return false;
    }
    let w = orbit.omega;
    branch.points.windows(2).any(|pair| {
        let (a, b) = (&pair[0], &pair[1]);
        let (lo, hi) = (a.omega.min(b.omega), a.omega.max(b.omega));
        if !(lo <= w && w <= hi) {
            return false;
        }
        let s = if hi > lo {
            (w - a.omega) / (b.omega - a.omega)
        } else {
            0.0
        };
        let alpha_step = crate::scene::phase::wrap(b.alpha - a.alpha);
        let alpha = a.alpha + s * alpha_step;
        let phase_close = a
            .impact_phases
            .iter()
            .zip(&b.impact_phases)
            .zip(&orbit.impact_phases)
            .all(|((pa, pb), po)| (pa + s * (pb - pa) - po).abs() < SAME_BRANCH);
        phase_close && crate::scene::phase::distance(alpha, orbit.alpha) / PI < SAME_BRANCH
    })
}

impl Followed {
    /// The record of the run on the scene named `scene`.
    pub fn record(&self, scene: &str) -> ContinuationRecord {
        let b = &self.branches;
        Parts {
            signature: &self.signature,
            period: self.signature.period(),
            cells: None,
            omega_start: self.omega_start,
            start_orbits: self.start_orbits.len(),
            followed_starts: &self.followed_starts,
            branches: &b.branches,
            events: &b.events,
            ends: &b.ends,
        }
        .record(scene, ContinuationPointRecord::new)
    }
}

/// What a continuation record is made of, for a unit's branches (`L` a [`Signature`]) or a
/// chain's ([`ImpactSequence`]).
struct Parts<'a, L> {
    signature: &'a L,
    period: u32,
    cells: Option<usize>,
    omega_start: f64,
    start_orbits: usize,
    followed_starts: &'a [usize],
    branches: &'a [Branch<L>],
    events: &'a [Event<L>],
    ends: &'a [BranchEnd],
}

impl<L: std::fmt::Display> Parts<'_, L> {
    /// The record on the scene named `scene`, each point's by `point`.
    fn record(
        &self,
        scene: &str,
        point: impl Fn(&ContinuationPoint) -> ContinuationPointRecord,
    ) -> ContinuationRecord {
        ContinuationRecord {
            scene: scene.to_owned(),
            signature: self.signature.to_string(),
            period: self.period,
            cells: self.cells,
            omega_start: finite(self.omega_start),
            start_orbits: self.start_orbits,
            followed_starts: self.followed_starts.to_vec(),
            branches: self
                .branches
                .iter()
                .map(|b| BranchRecord {
                    branch: b.index,
                    signature: b.signature.to_string(),
                    period: b.period,
                    from_event: b.from_event,
                    points: b.points.len(),
                })
                .collect(),
            points: self
                .branches
                .iter()
                .flat_map(|b| b.points.iter().map(&point))
                .collect(),
            events: self
                .events
                .iter()
                .map(|e| EventRecord {
                    branch: e.branch,
                    kind: e.kind.name(),
                    omega: finite(e.omega),
                    signature_after: e.signature_after.as_ref().map(|s| s.to_string()),
                    period_after: e.period_after,
                    outer_amplitude: finite(e.point.outer_amplitude),
                })
                .collect(),
            ends: self
                .ends
                .iter()
                .map(|e| EndRecord {
                    branch: e.branch,
                    omega: finite(e.omega),
                    reason: e.reason.name(),
                    joins: e.joins,
                })
                .collect(),
        }
    }
}

/// Every branch followed from the orbits of an impact sequence of a model (a chain, a
/// structure) at one frequency.
#[derive(Debug, Clone)]
pub struct SequenceFollowed {
    /// The impact sequence asked for, canonical.
    pub sequence: ImpactSequence,
    /// The frequency of the start orbits, rad/s.
    pub omega_start: f64,
    /// The orbits found at `omega_start` (all of them, viable or not).
    pub start_orbits: Vec<SequenceOrbit>,
    /// Indices into `start_orbits` of the orbits followed; the others lie on a branch already
    /// followed.
    pub followed_starts: Vec<usize>,
    /// Every branch, event and end, numbered across starts.
    pub continuation: Continuation<ImpactSequence>,
}

/// [`follow`] on a chain: every orbit of the impact sequence `text` over `period` forcing
/// periods (`0+ 1- 0- 1+`: pair index and side) at `omega_start` (or only the `orbit`-th),
/// each followed unless it lies on a branch already followed.
///
/// # Errors
/// [`FollowError::Chain`] for a sequence that does not parse or names a pair the chain lacks,
/// or a cell without stops; [`FollowError::NoOrbit`], [`FollowError::OrbitIndex`] and
/// [`FollowError::Continuation`] as [`follow`].
pub fn follow_chain(
    scene: &Scene,
    text: &str,
    period: u32,
    omega_start: f64,
    orbit: Option<usize>,
    settings: &ContinuationSettings,
) -> Result<SequenceFollowed, FollowError> {
    settings.validate()?;
    let record = chain_orbits(scene, omega_start, text, period)?;
    let model = chain_linear_model(scene).map_err(ChainOrbitsError::from)?;
    let sequence = ImpactSequence::parse(text, period).map_err(ChainOrbitsError::from)?;
    follow_sequence(
        &model,
        sequence,
        record.orbits,
        omega_start,
        orbit,
        settings,
    )
}

/// [`follow`] on a model: the orbits `start_orbits` of `sequence` found at `omega_start` on
/// `model` (or only the `orbit`-th), each followed unless it lies on a branch already followed.
///
/// # Errors
/// [`FollowError::NoOrbit`] when `start_orbits` is empty, [`FollowError::OrbitIndex`] and
/// [`FollowError::Continuation`] as [`follow`].
pub fn follow_sequence(
    model: &LinearModel,
    sequence: ImpactSequence,
    start_orbits: Vec<SequenceOrbit>,
    omega_start: f64,
    orbit: Option<usize>,
    settings: &ContinuationSettings,
) -> Result<SequenceFollowed, FollowError> {
    settings.validate()?;
    if start_orbits.is_empty() {
        return Err(FollowError::NoOrbit {
            signature: sequence.to_string(),
            period: sequence.period(),
            omega: omega_start,
        });
    }
    let chosen: Vec<usize> = match orbit {
        Some(k) if k >= start_orbits.len() => {
            return Err(FollowError::OrbitIndex {
                asked: k,
                found: start_orbits.len(),
                omega: omega_start,
            })
        }
        Some(k) => vec![k],
        None => (0..start_orbits.len()).collect(),
    };
    let mut continuation = Continuation::default();
    let mut followed_starts = Vec::new();
    for k in chosen {
        if continue_sequence_after(model, &start_orbits[k], settings, &mut continuation)? {
            followed_starts.push(k);
        }
    }
    Ok(SequenceFollowed {
        sequence,
        omega_start,
        start_orbits,
        followed_starts,
        continuation,
    })
}

impl SequenceFollowed {
    /// The record of the run on the chain scene `scene`: the unit's fields, with `cells` and
    /// each point's `cell_outer_amplitudes`.
    pub fn record(&self, scene: &Scene) -> ContinuationRecord {
        self.parts(Some(scene.cell_count()))
            .record(&scene.name, ContinuationPointRecord::of_chain)
    }

    /// The record of the run on the structure `form`: each point's `outer_amplitude` and
    /// `transmittance_db` those of the observed body, with every body's amplitude by name.
    pub fn structure_record(&self, form: &StructureForm) -> ContinuationRecord {
        self.parts(None).record(&form.scene.name, |p| {
            ContinuationPointRecord::of_structure(&form.structure, p)
        })
    }

    /// What the record is made of, with `cells` on a chain.
    fn parts(&self, cells: Option<usize>) -> Parts<'_, ImpactSequence> {
        let c = &self.continuation;
        Parts {
            signature: &self.sequence,
            period: self.sequence.period(),
            cells,
            omega_start: self.omega_start,
            start_orbits: self.start_orbits.len(),
            followed_starts: &self.followed_starts,
            branches: &c.branches,
            events: &c.events,
            ends: &c.ends,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seeds on the paper unit: the viable `+-` orbits at four frequencies, two of which (2.2
    /// and 2.4 rad/s) lie on one branch, so the later one is skipped.
    fn seeds(scene: &Scene) -> Vec<SignatureOrbit> {
        let sig = Signature::parse("+-", 1).expect("a valid signature");
        [0.5, 2.2, 2.4, 3.0]
            .iter()
            .flat_map(|&w| orbits_of_signature(scene, w, &sig))
            .filter(|o| o.viable)
            .collect()
    }

    fn settings() -> ContinuationSettings {
        ContinuationSettings {
            max_branches: 2,
            max_points_per_branch: 300,
            ..ContinuationSettings::new(0.5, 3.5)
        }
    }

    fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool")
            .install(f)
    }

    #[test]
    fn extend_all_gives_the_serial_result_on_any_thread_count() {
        let scene = Scene::paper();
        let (unit, stops) = (scene.unit_model(), scene.stops_model().expect("stops"));
        let starts = seeds(&scene);
        assert!(starts.len() >= 4, "{} seeds", starts.len());
        let mut serial = Branches::default();
        let serial_outcome: Vec<bool> = starts
            .iter()
            .map(|s| {
                serial
                    .extend(&unit, &stops, s, &settings())
                    .expect("followed")
            })
            .collect();
        assert!(
            serial_outcome.contains(&false),
            "a seed lies on a branch followed"
        );
        for threads in [1, 2, 3] {
            let (parallel, outcome) = in_pool(threads, || {
                let mut b = Branches::default();
                let outcome = b.extend_all(&unit, &stops, &starts, &settings());
                (b, outcome)
            });
            let outcome: Vec<bool> = outcome.into_iter().map(|r| r.expect("followed")).collect();
            assert_eq!(outcome, serial_outcome, "{threads} threads");
            assert_eq!(
                format!("{parallel:?}"),
                format!("{serial:?}"),
                "{threads} threads"
            );
        }
    }
}
