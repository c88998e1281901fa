//! Orbits through the front door: the unit's symmetric orbits (`rattle orbit`), every orbit of
//! one signature or impact sequence on any scene form (`rattle orbit --signature`), and one of
//! them sampled over its cycle (`--trajectory`).

use super::{
    argument, cells, check_cells_frequency, check_frequency, numerical, ApiError, TrajectoryTables,
};
use crate::output::finite;
use crate::output::records::{
    At, ChainOrbitsRecord, LinearRecord, OrbitRecord, OrbitsRecord, SignatureOrbitRecord,
    SignatureOrbitsRecord,
};
use crate::output::structure::{
    structure_orbit_trajectory, StructureAnalyticRecord, StructureAt, StructureOrbitRecord,
    StructureOrbitsRecord,
};
use crate::output::trajectory::analytic_rows;
use crate::scene::analytic::{
    analyse, chain_linear_model, orbits_of_signature, sample_sequence_orbit,
    sample_signature_orbit, AnalyticPoint, OrbitSearch,
};
use crate::scene::structure::StructureForm;
use crate::scene::AnyScene;
use crate::verdict::chain::{chain_orbits, ChainOrbitsError};
use rattle_analytic::{
    sequence_orbits, ImpactSequence, LinearModel, SequenceOrbit, Signature, SignatureOrbit,
};
use serde::{Serialize, Serializer};

/// The analytic picture of a unit at one frequency ([`orbits`]): the solver's answer and the
/// record `rattle orbit --json` prints (serializing `Orbits` gives that record).
#[derive(Debug, Clone)]
pub struct Orbits {
    /// The solver's answer: the linear response and the orbits, unrounded.
    pub point: AnalyticPoint,
    /// The command's record.
    pub record: OrbitsRecord,
}

impl Serialize for Orbits {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.record.serialize(s)
    }
}

/// The analytic picture of a single unit at `omega`: its linear steady state and every
/// two-impact orbit of `search` (symmetric, or asymmetric β too), with viability and
/// stability: `rattle orbit`.
///
/// # Errors
/// [`ApiError::Argument`] for a chain or a structure (their orbits are those of an impact
/// sequence: [`signature_orbits`]); [`ApiError::Frequency`] naming `--omega`;
/// [`ApiError::Numerical`] when the analytic solver fails.
///
/// # Examples
///
/// ```
/// use rattle_compare::api;
/// use rattle_compare::scene::analytic::OrbitSearch;
/// use rattle_compare::scene::{AnyScene, Scene};
///
/// let scene = AnyScene::Cells(Scene::paper());
/// let found = api::orbits(&scene, 2.0, OrbitSearch::Symmetric)?;
/// assert!(found.record.orbits.iter().all(|o| o.beta == Some(0.5)));
/// assert_eq!(found.record.linear.unbounded, found.point.linear.unbounded);
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
pub fn orbits(scene: &AnyScene, omega: f64, search: OrbitSearch) -> Result<Orbits, ApiError> {
    let scene = cells(scene, "orbits")?;
    scene
        .refuse_chain("rattle_compare::api::orbits")
        .map_err(argument)?;
    let omega = check_cells_frequency(scene, "--omega", omega)?;
    let point = analyse(scene, omega, search).map_err(numerical)?;
    let record = OrbitsRecord {
        at: At::new(scene, omega),
        linear: LinearRecord::new(&point.linear, scene.gap()),
        orbits: point
            .orbits
            .iter()
            .map(|(b, o)| OrbitRecord::new(o, *b))
            .collect(),
    };
    Ok(Orbits { point, record })
}

/// Every orbit of one impact signature found by [`signature_orbits`], with the solver's
/// orbits beside the record (to sample one: [`orbit_trajectory`]); serializing it gives the
/// record `rattle orbit --signature --json` prints.
#[derive(Debug, Clone)]
pub enum SignatureOrbits {
    /// A single unit's orbits of a signature.
    Unit {
        /// The solver's orbits.
        orbits: Vec<SignatureOrbit>,
        /// The command's record.
        record: SignatureOrbitsRecord,
    },
    /// A chain's orbits of an impact sequence of its pairs (the record holds the orbits).
    Chain {
        /// The command's record.
        record: ChainOrbitsRecord,
    },
    /// A structure's orbits of an impact sequence of its stops.
    Structure {
        /// The solver's orbits.
        orbits: Vec<SequenceOrbit>,
        /// The command's record.
        record: StructureOrbitsRecord,
    },
}

impl SignatureOrbits {
    /// How many orbits were found.
    pub fn len(&self) -> usize {
        match self {
            SignatureOrbits::Unit { orbits, .. } => orbits.len(),
            SignatureOrbits::Chain { record } => record.orbits.len(),
            SignatureOrbits::Structure { orbits, .. } => orbits.len(),
        }
    }

    /// No orbit was found.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The signature or impact sequence, canonical, as the record writes it.
    pub fn signature(&self) -> &str {
        match self {
            SignatureOrbits::Unit { record, .. } => &record.signature,
            SignatureOrbits::Chain { record } => &record.sequence,
            SignatureOrbits::Structure { record, .. } => &record.sequence,
        }
    }
}

impl Serialize for SignatureOrbits {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            SignatureOrbits::Unit { record, .. } => record.serialize(s),
            SignatureOrbits::Chain { record } => record.serialize(s),
            SignatureOrbits::Structure { record, .. } => record.serialize(s),
        }
    }
}

/// Every orbit with the impact signature `signature` over `period` forcing periods at
/// `omega`: `rattle orbit --signature`. On a unit, `signature` lists the stops hit over one
/// cycle, `+` side 1 and `-` side 2 (e.g. `+-`); on a chain, `<pair><side>` tokens (e.g.
/// `0+ 1- 0- 1+`); on a structure, `<stop><side>` tokens (with one stop, the sides alone).
///
/// # Errors
/// [`ApiError::Argument`] for a signature that does not parse (or names a stop or pair the
/// scene lacks), a `period` outside `[1, 8]`, or a scene without stops;
/// [`ApiError::Frequency`] naming `--omega`; [`ApiError::Numerical`] when the solver fails.
///
/// # Examples
///
/// ```
/// use rattle_compare::api;
/// use rattle_compare::scene::{AnyScene, Scene};
///
/// let scene = AnyScene::Cells(Scene::paper());
/// let found = api::signature_orbits(&scene, 2.0, "+-", 1)?;
/// assert_eq!(found.signature(), "+-");
/// let json = serde_json::to_value(&found).unwrap();
/// assert_eq!(json["orbits"].as_array().unwrap().len(), found.len());
///
/// let refused = api::signature_orbits(&scene, 2.0, "+x", 1).unwrap_err();
/// assert!(matches!(refused, api::ApiError::Argument(_)));
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
pub fn signature_orbits(
    scene: &AnyScene,
    omega: f64,
    signature: &str,
    period: u32,
) -> Result<SignatureOrbits, ApiError> {
    let omega = check_frequency(scene, "--omega", omega)?;
    match scene {
        AnyScene::Structure(form) => structure_orbits(form, omega, signature, period),
        AnyScene::Cells(scene) if scene.is_chain() => {
            let record = chain_orbits(scene, omega, signature, period).map_err(|e| match e {
                ChainOrbitsError::Numerical(_) => numerical(e),
                _ => argument(e),
            })?;
            Ok(SignatureOrbits::Chain { record })
        }
        AnyScene::Cells(scene) => {
            let signature = Signature::parse(signature, period).map_err(argument)?;
            if scene.stops.is_none() {
                return Err(ApiError::Argument(
                    "--signature: the scene has no `stops`, so no impact signature".into(),
                ));
            }
            let orbits = orbits_of_signature(scene, omega, &signature);
            let record = SignatureOrbitsRecord {
                at: At::new(scene, omega),
                signature: signature.to_string(),
                period: signature.period(),
                orbits: orbits.iter().map(SignatureOrbitRecord::new).collect(),
            };
            Ok(SignatureOrbits::Unit { orbits, record })
        }
    }
}

/// A structure's analytic model with the impact sequence `text` of its stops over `period`
/// forcing periods, checked against it.
pub(super) fn structure_sequence(
    form: &StructureForm,
    text: &str,
    period: u32,
) -> Result<(LinearModel, ImpactSequence), ApiError> {
    let structure = &form.structure;
    if structure.stops.is_empty() {
        return Err(ApiError::Argument(format!(
            "--signature: structure '{}' has no stops: it has no impacting orbits",
            form.scene.name
        )));
    }
    let sequence = structure.sequence(text, period).map_err(argument)?;
    let model = structure.analytic_model().map_err(argument)?;
    sequence.check(&model).map_err(argument)?;
    Ok((model, sequence))
}

/// [`signature_orbits`] on a structure: every orbit of one impact sequence of its stops.
fn structure_orbits(
    form: &StructureForm,
    omega: f64,
    text: &str,
    period: u32,
) -> Result<SignatureOrbits, ApiError> {
    let structure = &form.structure;
    let (model, sequence) = structure_sequence(form, text, period)?;
    let found = sequence_orbits(&model, omega, &sequence).map_err(numerical)?;
    let n = structure.dofs();
    let record = StructureOrbitsRecord {
        at: StructureAt::new(&form.scene, structure, omega),
        sequence: sequence.to_string(),
        period: sequence.period(),
        orbits: found
            .iter()
            .map(|o| StructureOrbitRecord {
                alpha: finite(o.alpha),
                impact_phases: o.impact_phases.iter().map(|&p| finite(p)).collect(),
                relative_velocities_before: o
                    .sequence
                    .impacts()
                    .iter()
                    .zip(&o.states_before_impacts)
                    .map(|(i, x)| {
                        let w = &model.pairs()[i.pair].direction;
                        finite((0..n).map(|k| w[k] * x[n + k]).sum())
                    })
                    .collect(),
                orbit: StructureAnalyticRecord::new(structure, o),
            })
            .collect(),
    };
    Ok(SignatureOrbits::Structure {
        orbits: found,
        record,
    })
}

/// The `orbit`-th of `found` (numbered from 0, as listed) sampled from the closed form,
/// `samples_per_period` uniform samples per forcing period plus every impact:
/// `rattle orbit --signature … --orbit K --trajectory F --impacts I`. The tables have the
/// columns [`simulation_trajectory`](super::simulation_trajectory) gives the same scene, so that the two solvers' cycles
/// overlay: a unit's or a chain's one row per cell at each time, a structure's a column per
/// body and per stop.
///
/// # Errors
/// [`ApiError::Argument`] naming `--orbit` when it is not below `found.len()`, naming
/// `--samples-per-period` outside `[1, MAX_SAMPLES_PER_PERIOD]`, or when `found` is not of
/// `scene`'s form (orbits found on another scene).
///
/// # Examples
///
/// ```
/// use rattle_compare::api::{self, TrajectoryTables};
/// use rattle_compare::scene::{AnyScene, Scene};
///
/// let scene = AnyScene::Cells(Scene::paper());
/// let found = api::signature_orbits(&scene, 2.0, "+-", 1)?;
/// if !found.is_empty() {
///     let TrajectoryTables::Cells { rows, impacts } = api::orbit_trajectory(&scene, &found, 0, 16)?
///     else { unreachable!("a unit's tables") };
///     assert!(rows.len() >= 16);
///     assert_eq!(impacts.len(), 2);
/// }
/// let past = api::orbit_trajectory(&scene, &found, found.len(), 16).unwrap_err();
/// assert!(past.to_string().starts_with("--orbit = "));
///
/// // A structure's orbit: a column per body and per stop, as `simulate --trajectory` writes.
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/impact-oscillator.json");
/// let oscillator = api::load(path)?;
/// let found = api::signature_orbits(&oscillator, 1.8, "+", 1)?;
/// let TrajectoryTables::Structure { states, impacts } =
///     api::orbit_trajectory(&oscillator, &found, 0, 16)?
/// else { unreachable!("a structure's tables") };
/// assert_eq!(states.columns, ["t", "kind", "base", "u_x", "v_x", "r_0"]);
/// assert_eq!(impacts.rows.len(), 1);
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
pub fn orbit_trajectory(
    scene: &AnyScene,
    found: &SignatureOrbits,
    orbit: usize,
    samples_per_period: u64,
) -> Result<TrajectoryTables, ApiError> {
    crate::output::trajectory::check_samples_per_period(samples_per_period.into())
        .map_err(ApiError::Argument)?;
    if orbit >= found.len() {
        let omega = match found {
            SignatureOrbits::Unit { record, .. } => record.at.omega,
            SignatureOrbits::Chain { record } => record.at.omega,
            SignatureOrbits::Structure { record, .. } => record.at.omega,
        }
        .unwrap_or(f64::NAN);
        return Err(ApiError::Argument(format!(
            "--orbit = {orbit} is out of range: {} orbit(s) of {} at ω = {omega}, numbered from 0",
            found.len(),
            found.signature()
        )));
    }
    let other_form = || {
        ApiError::Argument(format!(
            "orbit_trajectory: the orbits of {} were not found on scene '{}' (another form)",
            found.signature(),
            scene.name()
        ))
    };
    let (scene, omega, (samples, impacts)) = match (scene, found) {
        (AnyScene::Structure(form), SignatureOrbits::Structure { orbits, .. }) => {
            let structure = &form.structure;
            let model = structure.analytic_model().map_err(argument)?;
            let o = &orbits[orbit];
            if !o.contacts.is_empty() {
                return Err(ApiError::Argument(format!(
                    "--trajectory: the orbits of {} have contact phases, whose flow the \
                     analytic sampler does not step through; `rattle simulate --trajectory` \
                     samples the simulated cycle, contact phases included",
                    found.signature()
                )));
            }
            let (samples, impacts) = sample_sequence_orbit(&model, o, samples_per_period);
            let (states, impacts) =
                structure_orbit_trajectory(structure, &samples, &impacts, o.omega);
            return Ok(TrajectoryTables::Structure { states, impacts });
        }
        (AnyScene::Cells(scene), SignatureOrbits::Unit { orbits, .. }) => {
            let o = &orbits[orbit];
            (
                scene,
                o.omega,
                sample_signature_orbit(scene, o, samples_per_period),
            )
        }
        (AnyScene::Cells(scene), SignatureOrbits::Chain { record }) => {
            let model = chain_linear_model(scene).map_err(argument)?;
            let o = &record.orbits[orbit];
            (
                scene,
                o.omega,
                sample_sequence_orbit(&model, o, samples_per_period),
            )
        }
        _ => return Err(other_form()),
    };
    let (rows, impacts) = analytic_rows(
        &samples,
        &impacts,
        omega,
        scene.base.amplitude,
        &scene.cell_pairs(),
    );
    Ok(TrajectoryTables::Cells { rows, impacts })
}
