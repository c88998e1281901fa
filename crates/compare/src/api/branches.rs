//! Branches and regime boundaries through the front door: continuation in ω (`rattle
//! continue`) and one boundary in (ω, a scene parameter) (`rattle boundary`), on any scene
//! form.

use super::orbits::structure_sequence;
use super::{argument, check_frequency, numerical, ApiError};
use crate::output::records::ContinuationRecord;
use crate::runs::boundary::{follow_any, BoundaryOptions, BoundaryRecord};
use crate::runs::continuation::{
    follow, follow_chain, follow_sequence, FollowError, Followed, SequenceFollowed,
};
use crate::scene::structure::{Structure, StructureForm};
use crate::scene::AnyScene;
use crate::verdict::chain::ChainOrbitsError;
use rattle_analytic::ContinuationSettings;
use rattle_analytic::{sequence_orbits, Signature};
use serde::{Serialize, Serializer};

/// The branches [`continuation`] followed, with the record `rattle continue --json` prints
/// (serializing a `Continuation` gives that record).
#[derive(Debug, Clone)]
pub struct Continuation {
    /// The command's record: branches, points, events and ends.
    pub record: ContinuationRecord,
    /// The branches as the continuation gives them.
    pub branches: ContinuedBranches,
}

/// The branches of a [`Continuation`], a unit's, a chain's or a structure's.
#[derive(Debug, Clone)]
pub enum ContinuedBranches {
    /// A unit's branches.
    Unit(Followed),
    /// A chain's branches, every point with every cell's outer amplitude.
    Chain(SequenceFollowed),
    /// A structure's branches, every point with every body's amplitude.
    Structure {
        /// The branches.
        followed: SequenceFollowed,
        /// The structure they belong to (its bodies' names, the observed body, the base).
        structure: Box<Structure>,
    },
}

impl Serialize for Continuation {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.record.serialize(s)
    }
}

/// Every orbit of `signature` over `period` forcing periods found at `omega` (or only the
/// `orbit`-th, numbered as [`signature_orbits`](super::signature_orbits) lists them) followed in ω by
/// pseudo-arclength continuation within `settings`' range, through folds, with its
/// bifurcations and the branches they lead onto: `rattle continue`. On a chain, `signature`
/// is an impact sequence of its pairs (e.g. `0+ 1- 0- 1+`).
///
/// # Errors
/// [`ApiError::Argument`] for a signature that does not parse, a scene without stops, an
/// `orbit` past the orbits found, or settings out of range (the message names the setting);
/// [`ApiError::Frequency`] naming `--omega`; [`ApiError::Numerical`] when no orbit exists at
/// `omega` or the continuation cannot start.
///
/// # Examples
///
/// ```
/// use rattle_analytic::ContinuationSettings;
/// use rattle_compare::api;
/// use rattle_compare::scene::{AnyScene, Scene};
///
/// let settings = ContinuationSettings {
///     max_branches: 1,
///     follow_switches: false,
///     ..ContinuationSettings::new(1.9, 2.1)
/// };
/// let paper = AnyScene::Cells(Scene::paper());
/// let followed = api::continuation(&paper, "+-", 1, 2.0, Some(0), &settings)?;
/// assert_eq!(followed.record.signature, "+-");
/// assert!(!followed.record.points.is_empty());
///
/// // A structure's orbits are of an impact sequence of its stops; `+` reads as `0+` with one.
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/impact-oscillator.json");
/// let oscillator = api::load(path)?;
/// let settings = ContinuationSettings { max_branches: 1, ..ContinuationSettings::new(1.4, 1.6) };
/// let followed = api::continuation(&oscillator, "+", 1, 1.5, Some(0), &settings)?;
/// assert_eq!(followed.record.signature, "0+");
/// let json = serde_json::to_value(&followed).unwrap();
/// assert!(json["points"][0]["body_amplitudes"]["x"].is_number());
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
pub fn continuation(
    scene: &AnyScene,
    signature: &str,
    period: u32,
    omega: f64,
    orbit: Option<usize>,
    settings: &ContinuationSettings,
) -> Result<Continuation, ApiError> {
    let omega = check_frequency(scene, "--omega", omega)?;
    let error = |e: FollowError| match e {
        FollowError::OrbitIndex { .. }
        | FollowError::NoStops
        | FollowError::Chain(ChainOrbitsError::Sequence(_) | ChainOrbitsError::MissingStops(_)) => {
            argument(e)
        }
        FollowError::Continuation(ref c) if c.to_string().contains("out of range") => argument(e),
        _ => numerical(e),
    };
    let scene = match scene {
        AnyScene::Structure(form) => {
            return structure_continuation(form, signature, period, omega, orbit, settings, error)
        }
        AnyScene::Cells(scene) => scene,
    };
    if scene.is_chain() {
        let followed =
            follow_chain(scene, signature, period, omega, orbit, settings).map_err(error)?;
        return Ok(Continuation {
            record: followed.record(scene),
            branches: ContinuedBranches::Chain(followed),
        });
    }
    let signature = Signature::parse(signature, period).map_err(argument)?;
    let followed = follow(scene, &signature, omega, orbit, settings).map_err(error)?;
    Ok(Continuation {
        record: followed.record(&scene.name),
        branches: ContinuedBranches::Unit(followed),
    })
}

/// [`continuation`] on a structure: the orbits of an impact sequence of its stops, found as
/// [`signature_orbits`] finds them, followed on the structure's analytic model.
fn structure_continuation(
    form: &StructureForm,
    signature: &str,
    period: u32,
    omega: f64,
    orbit: Option<usize>,
    settings: &ContinuationSettings,
    error: impl Fn(FollowError) -> ApiError,
) -> Result<Continuation, ApiError> {
    settings.validate().map_err(|e| error(e.into()))?;
    let (model, sequence) = structure_sequence(form, signature, period)?;
    let orbits = sequence_orbits(&model, omega, &sequence).map_err(numerical)?;
    let followed =
        follow_sequence(&model, sequence, orbits, omega, orbit, settings).map_err(error)?;
    Ok(Continuation {
        record: followed.structure_record(form),
        branches: ContinuedBranches::Structure {
            followed,
            structure: Box::new(form.structure.clone()),
        },
    })
}

/// A regime boundary: the event of `options.event`'s kind nearest `options.omega` on the
/// branches of the signature's orbits, followed in (ω, the scene parameter `options.param`)
/// through turning points: `rattle boundary`. The options are checked first
/// ([`BoundaryOptions::checked`]).
///
/// # Errors
/// [`ApiError::Argument`] for options out of range (each named, with its range), a parameter
/// the scene lacks, or a start the event does not admit; [`ApiError::Numerical`] when no
/// orbit or event is found or the curve cannot start.
pub fn boundary(scene: &AnyScene, options: &BoundaryOptions) -> Result<BoundaryRecord, ApiError> {
    let checked = options.checked().map_err(ApiError::Argument)?;
    let request = options
        .request(&checked, scene)
        .map_err(ApiError::Argument)?;
    follow_any(scene, &request, &checked.settings).map_err(|e| {
        if e.is_bad_input() {
            argument(e)
        } else {
            numerical(e)
        }
    })
}
