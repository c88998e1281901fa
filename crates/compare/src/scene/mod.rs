//! Scenes: the JSON description of one unit, and its translation into each solver's problem.
//!
//! ```json
//! {
//!   "name": "paper",
//!   "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
//!   "base": {"amplitude": 1.0},
//!   "stops": {"gap": 0.5, "restitution": 0.8},
//!   "damping": {"outer": 0.0, "inner": 0.0}
//! }
//! ```
//! `unit` and `base` are required; `stops` and `damping` are optional effects. Unknown fields
//! are refused. Frequencies are not part of a scene. A base motion may carry higher harmonics
//! (`"harmonics": [{"order": 2, "amplitude": 0.3, "phase": 0.5}]`, [`HarmonicSpec`]); such a
//! scene runs in the structure form ([`AnyScene::of_cells`], [`Scene::structure_scene`]).
//!
//! This module holds the format and its validation; [`analytic`] and [`simulator`] adapt a
//! scene to each solver and name what the solver finds ([`analytic::AnalyticPoint`],
//! [`simulator::SimulatedPoint`]); [`phase`] the conventions of the base phase; [`frequency`]
//! the forcing frequencies a scene can be run at in bounded time; [`parameter`] a number of a
//! scene named by its JSON path, read and set.

pub mod analytic;
pub mod frequency;
pub mod lyapunov;
pub mod parameter;
pub mod phase;
pub mod signal;
pub mod simulator;
mod stops;
pub mod structure;
pub mod structure_parameter;

pub use stops::StopsSpec;

use rattle_analytic::{Damping, Stops, Unit, UnitError};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The built-in default scene: the paper's §2.2 unit with `Δ = 0.5`, `e = 0.8`.
pub const PAPER_SCENE: &str = include_str!("../../../../data/scenes/paper.json");

/// The commands that take a chain of cells so far.
pub const CHAIN_COMMANDS: &str =
    "`rattle simulate`, `rattle sweep` (`--solver analytic`: the linear chain; `event`; `both`: the verdict of `rattle compare` at every frequency), `rattle map`, `rattle orbit --signature` (a sequence of the pairs' impacts), `rattle continue --signature` (the same, continued in ω) and `rattle compare` (the simulated cycle beside the analytic orbit of its impact sequence)";

/// The commands that take a scene in the structure form so far.
pub const STRUCTURE_COMMANDS: &str =
    "`rattle simulate`, `rattle orbit --signature`, `rattle compare`, `rattle sweep`, `rattle continue`, `rattle boundary`, `rattle boundaries`, `rattle basins` and `rattle map --x PATH --y PATH`";

/// A scene of any form: the unit and chain forms ([`Scene`]), or the structure form
/// ([`structure::StructureScene`]) with its checked [`structure::Structure`].
#[derive(Debug, Clone, PartialEq)]
pub enum AnyScene {
    /// The unit form, with `cells` or `chain` for a chain.
    Cells(Scene),
    /// The structure form.
    Structure(Box<structure::StructureForm>),
}

impl AnyScene {
    /// Parses and validates a scene of either form (the structure form when the document
    /// has a `structure` field); `origin` names it in error messages.
    ///
    /// # Errors
    /// As [`Scene::parse`]; [`SceneError::Structure`] naming the field of a structure scene
    /// that does not exist or has no bounded motion.
    pub fn parse(text: &str, origin: &str) -> Result<AnyScene, SceneError> {
        if !is_structure(text) {
            return AnyScene::of_cells(deserialize(text, origin)?, origin);
        }
        let scene: structure::StructureScene = deserialize(text, origin)?;
        AnyScene::of_structure(scene, origin)
    }

    /// A scene in the unit or chain form, checked: as itself when its base motion is the
    /// fundamental alone, else written as a structure ([`Scene::structure_scene`]), the road
    /// that solves harmonic forcing.
    ///
    /// # Errors
    /// As [`Scene::validated`] for the scene without its harmonics; [`SceneError::Harmonic`]
    /// naming a harmonic out of range (`base.harmonics[i]`).
    pub fn of_cells(mut scene: Scene, origin: &str) -> Result<AnyScene, SceneError> {
        let harmonics = std::mem::take(&mut scene.base.harmonics);
        let scene = scene.validated(origin)?;
        if harmonics.is_empty() && !scene.has_compliant_stops() {
            return Ok(AnyScene::Cells(scene));
        }
        check_harmonics("base.harmonics", &harmonics).map_err(|(field, reason)| {
            SceneError::Harmonic {
                origin: origin.to_owned(),
                field,
                reason,
            }
        })?;
        let base = BaseSpec {
            amplitude: scene.base.amplitude,
            harmonics,
        };
        AnyScene::of_structure(scene.structure_scene(base), origin)
    }

    /// A scene in the structure form with its checked structure.
    ///
    /// # Errors
    /// [`SceneError::Structure`] naming the field that does not exist or has no bounded
    /// motion.
    pub fn of_structure(
        scene: structure::StructureScene,
        origin: &str,
    ) -> Result<AnyScene, SceneError> {
        let structure = scene.structure().map_err(|source| SceneError::Structure {
            origin: origin.to_owned(),
            source,
        })?;
        Ok(AnyScene::Structure(Box::new(structure::StructureForm {
            scene,
            structure,
        })))
    }

    /// Reads, parses and validates the scene file at `path`.
    ///
    /// # Errors
    /// [`SceneError::Read`] when the file cannot be read, else as [`AnyScene::parse`].
    pub fn load(path: &Path) -> Result<AnyScene, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
            path: path.to_owned(),
            source,
        })?;
        AnyScene::parse(&text, &path.display().to_string())
    }

    /// The scene's name.
    pub fn name(&self) -> &str {
        match self {
            AnyScene::Cells(scene) => &scene.name,
            AnyScene::Structure(form) => &form.scene.name,
        }
    }
}

/// Whether a scene's text is in the structure form: a JSON object with a `structure` field.
fn is_structure(text: &str) -> bool {
    #[derive(Deserialize)]
    struct Probe {
        #[serde(default)]
        structure: Option<serde::de::IgnoredAny>,
    }
    serde_json::from_str::<Probe>(text).is_ok_and(|p| p.structure.is_some())
}

/// `T` from `text`, or the error naming the field's path, line and column.
fn deserialize<T: serde::de::DeserializeOwned>(text: &str, origin: &str) -> Result<T, SceneError> {
    let de = &mut serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(de).map_err(|e| {
        // `?` is serde_path_to_error's stand-in for a key the parser had not read when the
        // text stopped being JSON: the path ends at the last field it had read.
        let path = e.path().to_string();
        let path = path.trim_end_matches('?').trim_end_matches('.');
        let inner = e.into_inner();
        let syntax = matches!(
            inner.classify(),
            serde_json::error::Category::Syntax | serde_json::error::Category::Eof
        );
        let message = strip_position(&inner.to_string());
        SceneError::Format {
            origin: origin.to_owned(),
            path_in_scene: if path.is_empty() { "." } else { path }.to_owned(),
            message: if syntax {
                format!("not valid JSON: {message}")
            } else {
                message
            },
            line: inner.line(),
            column: inner.column(),
        }
    })
}

/// A chain scene given to a command that works on a single unit only
/// ([`Scene::refuse_chain`]).
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error(
    "scene '{scene}' is a chain of {cells} cells (`{field}`): `{command}` works on a single unit \
     (one cell); chains are taken by {commands}",
    commands = CHAIN_COMMANDS
)]
pub struct ChainRefused {
    /// The scene's name.
    pub scene: String,
    /// Its number of cells.
    pub cells: usize,
    /// The field that makes it a chain: `chain` or `cells`.
    pub field: &'static str,
    /// The command (or function) that refused it.
    pub command: String,
}

/// Why a scene could not be used. Every message names the file or the field.
#[derive(Debug, Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("cannot read scene file {path}: {source}")]
    Read {
        /// The path as given.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The file is not valid JSON, or does not have the scene's shape.
    #[error("{origin}: {path_in_scene}: {message} (line {line}, column {column})")]
    Format {
        /// The file, or `built-in`.
        origin: String,
        /// Path of the offending field, e.g. `stops.gapp`, or `.` for the document.
        path_in_scene: String,
        /// What is wrong.
        message: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
    },
    /// A value is out of its physical range.
    #[error("{origin}: {source}")]
    Value {
        /// The file, or `built-in`.
        origin: String,
        /// The field, the value and the allowed range.
        source: UnitError,
    },
    /// A value of one cell of a `chain` is out of its physical range.
    #[error("{origin}: chain[{cell}].{source}")]
    CellValue {
        /// The file, or `built-in`.
        origin: String,
        /// The cell, from 0.
        cell: usize,
        /// The field within the cell, the value and the allowed range.
        source: UnitError,
    },
    /// A structure scene's field names what does not exist, or what has no bounded motion.
    #[error("{origin}: {source}")]
    Structure {
        /// The file, or `built-in`.
        origin: String,
        /// The field's JSON path and the reason.
        source: structure::StructureError,
    },
    /// A harmonic of a base motion out of its range.
    #[error("{origin}: {field}: {reason}")]
    Harmonic {
        /// The file, or `built-in`.
        origin: String,
        /// The JSON path, e.g. `base.harmonics[0].order`.
        field: String,
        /// What is wrong, with the allowed range.
        reason: String,
    },
    /// A contact law of a unit's or a cell's stops refused: both laws, neither, or a value out
    /// of its range.
    #[error("{origin}: {field}: {reason}")]
    Stops {
        /// The file, or `built-in`.
        origin: String,
        /// The JSON path, e.g. `chain[1].stops.contact_damping`.
        field: String,
        /// What is wrong, with the allowed range.
        reason: String,
    },
    /// A unit or chain scene with compliant stops, given where the unit's own road (rigid
    /// stops) is taken.
    #[error(
        "{origin}: stops.contact_stiffness: this command solves the unit and chain forms with \
         rigid stops; a scene with compliant stops runs in the structure form (bodies \
         `outer`, `inner`; in a chain `outer0`, `inner0`, …), taken by {commands}",
        commands = STRUCTURE_COMMANDS
    )]
    CellsCompliant {
        /// The file, or `built-in`.
        origin: String,
    },
    /// A unit or chain scene whose base has harmonics, given where the unit's own road (the
    /// single sine) is taken.
    #[error(
        "{origin}: base.harmonics: this command solves the unit and chain forms under the \
         fundamental alone; a scene whose base has harmonics runs in the structure form \
         (bodies `outer`, `inner`; in a chain `outer0`, `inner0`, …), taken by {commands}",
        commands = STRUCTURE_COMMANDS
    )]
    CellsHarmonics {
        /// The file, or `built-in`.
        origin: String,
    },
    /// A structure scene given where only the unit and chain forms are taken.
    #[error(
        "{origin}: structure: the structure form is taken by {commands} so far; this command \
         takes the unit form (`unit`, `base`, with `cells` or `chain` for a chain)",
        commands = STRUCTURE_COMMANDS
    )]
    StructureForm {
        /// The file, or `built-in`.
        origin: String,
    },
    /// The chain's length is out of range, or given twice.
    #[error("{origin}: {field}: {message}")]
    Chain {
        /// The file, or `built-in`.
        origin: String,
        /// `cells` or `chain`.
        field: &'static str,
        /// What is wrong, with the allowed range.
        message: String,
    },
}

/// Most cells a chain may have: the simulator's [`rattle_event_driven::MAX_CELLS`] (its
/// dense `2N`-dimensional modal flow costs `O(N³)` to set up and `O(N²)` per step).
pub const MAX_CELLS: usize = rattle_event_driven::MAX_CELLS;

/// The unit's masses and springs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnitSpec {
    /// `m_o`, kg.
    pub outer_mass: f64,
    /// `m_i`, kg.
    pub inner_mass: f64,
    /// `k_o`, N/m: base to outer mass.
    pub outer_stiffness: f64,
    /// `k_i`, N/m: outer to inner mass.
    pub inner_stiffness: f64,
}

/// The base motion `u_g cos(ω t) + Σ a_k cos(kωt + φ_k)`: the fundamental and any higher
/// harmonics ([`HarmonicSpec`]), all of the period `2π/ω`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BaseSpec {
    /// `u_g`, m: the fundamental's amplitude.
    pub amplitude: f64,
    /// The higher harmonics, each order once (empty: the fundamental alone).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub harmonics: Vec<HarmonicSpec>,
}

impl BaseSpec {
    /// The base motion `u_g cos ωt` of the fundamental alone.
    pub fn fundamental(amplitude: f64) -> Self {
        Self {
            amplitude,
            harmonics: Vec::new(),
        }
    }
}

/// Highest order of a [`HarmonicSpec`]: the analytic solver's
/// [`rattle_analytic::MAX_HARMONIC_ORDER`] (its multi-start over impact phases samples more
/// finely the higher the order), the lower of the two solvers' caps, so that every periodic
/// study runs on a scene that parses.
pub const MAX_HARMONIC_ORDER: u32 =
    if rattle_analytic::MAX_HARMONIC_ORDER < rattle_event_driven::MAX_HARMONIC_ORDER {
        rattle_analytic::MAX_HARMONIC_ORDER
    } else {
        rattle_event_driven::MAX_HARMONIC_ORDER
    };

/// One higher harmonic `a cos(kωt + φ)` of a base motion or a force: integer order `k ≥ 2`,
/// so the forcing keeps the period `2π/ω`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HarmonicSpec {
    /// `k`, an integer in `2..=`[`MAX_HARMONIC_ORDER`], each order once per list.
    pub order: u32,
    /// `a`: m for the base, N for a force; finite.
    pub amplitude: f64,
    /// `φ`, rad, finite (default 0): the harmonic's phase against the fundamental's `ωt`.
    #[serde(default)]
    pub phase: f64,
}

/// The reason `harmonics` (the list at JSON path `field`) is refused, if it is: an order out
/// of `2..=`[`MAX_HARMONIC_ORDER`] or repeated, an amplitude or phase not finite.
pub fn check_harmonics(field: &str, harmonics: &[HarmonicSpec]) -> Result<(), (String, String)> {
    for (i, h) in harmonics.iter().enumerate() {
        let at = format!("{field}[{i}]");
        if !(2..=MAX_HARMONIC_ORDER).contains(&h.order) {
            return Err((
                format!("{at}.order"),
                format!(
                    "{} is out of range: must be an integer in 2..={MAX_HARMONIC_ORDER} (order 1 \
                     is the fundamental)",
                    h.order
                ),
            ));
        }
        if harmonics[..i].iter().any(|g| g.order == h.order) {
            return Err((
                format!("{at}.order"),
                format!("{} is repeated: each order once per list", h.order),
            ));
        }
        for (name, v) in [("amplitude", h.amplitude), ("phase", h.phase)] {
            if !v.is_finite() {
                return Err((
                    format!("{at}.{name}"),
                    format!("{v} is out of range: must be finite"),
                ));
            }
        }
    }
    Ok(())
}

/// Dashpots.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    /// `c_o`, N·s/m: base to outer mass, acting on `u̇_o − u̇_g`.
    #[serde(default)]
    pub outer: f64,
    /// `c_i`, N·s/m: outer to inner mass.
    #[serde(default)]
    pub inner: f64,
}

/// One scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// A name for outputs and figures.
    #[serde(default = "unnamed")]
    pub name: String,
    /// Masses and springs.
    pub unit: UnitSpec,
    /// Base motion.
    pub base: BaseSpec,
    /// Stops, if the unit has them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stops: Option<StopsSpec>,
    /// Dashpots, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<DampingSpec>,
    /// A chain of this many identical cells in series (outer mass `j` tied to outer mass
    /// `j − 1` by `k_o` and `c_o`, the first to the base); absent: one cell, the unit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cells: Option<usize>,
    /// A graded chain: one entry per cell, each replacing the blocks it gives (`unit`,
    /// `stops`, `damping`) of the scene's own, which it inherits otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chain: Option<Vec<CellSpec>>,
}

/// One cell of a graded chain: the blocks it gives replace the scene's.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CellSpec {
    /// The cell's masses and springs (`outer_stiffness` ties it to the previous cell).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<UnitSpec>,
    /// The cell's stops.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stops: Option<StopsSpec>,
    /// The cell's dashpots.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<DampingSpec>,
}

fn unnamed() -> String {
    "unnamed".to_owned()
}

/// An optional effect of a scene, as named in outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effect {
    /// The inner mass impacts stops.
    Stops,
    /// Viscous damping is present (some dashpot `> 0`).
    Damping,
}

impl Effect {
    /// The name used in JSON (`"stops"`, `"damping"`).
    pub fn name(self) -> &'static str {
        match self {
            Effect::Stops => "stops",
            Effect::Damping => "damping",
        }
    }
}

impl Scene {
    /// Parses and validates a scene; `origin` names it in error messages.
    ///
    /// # Errors
    /// [`SceneError::Format`] for malformed JSON, an unknown field or a wrong type (with the
    /// field's path, line and column); [`SceneError::Value`] for a value out of its range;
    /// [`SceneError::StructureForm`] for a scene in the structure form and
    /// [`SceneError::CellsHarmonics`] for one whose base has harmonics ([`AnyScene::parse`]
    /// takes both).
    pub fn parse(text: &str, origin: &str) -> Result<Scene, SceneError> {
        if is_structure(text) {
            return Err(SceneError::StructureForm {
                origin: origin.to_owned(),
            });
        }
        let scene: Scene = deserialize(text, origin)?;
        let scene = scene.validated(origin)?;
        if scene.has_compliant_stops() {
            return Err(SceneError::CellsCompliant {
                origin: origin.to_owned(),
            });
        }
        Ok(scene)
    }

    /// The scene with its chain in one form (see [`Scene::parse`]) and every value checked;
    /// `origin` names it in error messages. For a scene built in code rather than parsed.
    ///
    /// # Errors
    /// [`SceneError::Chain`] for the chain's length, [`SceneError::Value`] or
    /// [`SceneError::CellValue`] for a value out of its range, [`SceneError::CellsHarmonics`]
    /// when the base has harmonics ([`AnyScene::of_cells`] takes such a scene).
    pub fn validated(self, origin: &str) -> Result<Scene, SceneError> {
        if !self.base.harmonics.is_empty() {
            return Err(SceneError::CellsHarmonics {
                origin: origin.to_owned(),
            });
        }
        let scene = self.normalized(origin)?;
        scene.validate_in(origin)?;
        Ok(scene)
    }

    /// The scene with its chain in one form: `cells` and `chain` are exclusive, a chain of one
    /// cell is that cell as the scene's own unit (so every one-cell scene reads the same),
    /// and `cells: 1` is no chain.
    fn normalized(mut self, origin: &str) -> Result<Scene, SceneError> {
        let chain_error = |field, message: String| SceneError::Chain {
            origin: origin.to_owned(),
            field,
            message,
        };
        if self.cells.is_some() && self.chain.is_some() {
            return Err(chain_error(
                "cells",
                "give either `cells` (identical cells) or `chain` (one entry per cell), not both"
                    .to_owned(),
            ));
        }
        let count = self.cell_count();
        if !(1..=MAX_CELLS).contains(&count) {
            let field = if self.chain.is_some() {
                "chain"
            } else {
                "cells"
            };
            return Err(chain_error(
                field,
                format!("{count} cells is out of range: must be 1..={MAX_CELLS}"),
            ));
        }
        if count == 1 {
            if let Some(cell) = self.chain.take().and_then(|c| c.first().copied()) {
                self = self.cell_scene(&cell);
            }
            self.cells = None;
        }
        Ok(self)
    }

    fn validate_in(&self, origin: &str) -> Result<(), SceneError> {
        let law = |prefix: String, stops: Option<StopsSpec>| match stops.and_then(|s| s.law_error())
        {
            Some((field, reason)) => Err(SceneError::Stops {
                origin: origin.to_owned(),
                field: format!("{prefix}stops.{field}"),
                reason,
            }),
            None => Ok(()),
        };
        law(String::new(), self.stops)?;
        for (k, cell) in self.chain.iter().flatten().enumerate() {
            law(format!("chain[{k}]."), cell.stops)?;
        }
        match &self.chain {
            Some(chain) => chain.iter().enumerate().try_for_each(|(cell, spec)| {
                self.cell_scene(spec)
                    .validate()
                    .map_err(|source| SceneError::CellValue {
                        origin: origin.to_owned(),
                        cell,
                        source,
                    })
            }),
            None => self.validate().map_err(|source| SceneError::Value {
                origin: origin.to_owned(),
                source,
            }),
        }
    }

    /// Number of cells in series (1 for a single unit).
    pub fn cell_count(&self) -> usize {
        match (&self.chain, self.cells) {
            (Some(chain), _) => chain.len(),
            (None, Some(n)) => n,
            (None, None) => 1,
        }
    }

    /// Number of contact pairs: the cells with stops.
    pub fn pair_count(&self) -> usize {
        self.cell_effect_blocks()
            .filter(|(stops, _)| stops.is_some())
            .count()
    }

    /// Each cell's contact pair (`None` for a cell without stops), from the base out: pairs are
    /// numbered over the cells with stops, as the models number them.
    pub fn cell_pairs(&self) -> Vec<Option<usize>> {
        let mut next = 0;
        self.cell_effect_blocks()
            .map(|(stops, _)| {
                stops.map(|_| {
                    next += 1;
                    next - 1
                })
            })
            .collect()
    }

    /// Each cell's stops and dashpots (the blocks behind its effects), without building the
    /// cell's scene: the effect queries run for every output record.
    fn cell_effect_blocks(
        &self,
    ) -> impl Iterator<Item = (Option<StopsSpec>, Option<DampingSpec>)> + '_ {
        let own = (self.stops, self.damping);
        let listed = self
            .chain
            .iter()
            .flatten()
            .map(move |c| (c.stops.or(own.0), c.damping.or(own.1)));
        let repeated = std::iter::repeat_n(
            own,
            if self.chain.is_some() {
                0
            } else {
                self.cell_count()
            },
        );
        listed.chain(repeated)
    }

    /// Whether the scene is a chain of more than one cell.
    pub fn is_chain(&self) -> bool {
        self.cell_count() > 1
    }

    /// Refuses a chain for `command`, a command (or function) that works on a single unit only.
    ///
    /// # Errors
    /// [`ChainRefused`], naming the scene's `cells` or `chain` field and the commands that take
    /// chains, when the scene is a chain.
    pub fn refuse_chain(&self, command: &str) -> Result<(), ChainRefused> {
        if !self.is_chain() {
            return Ok(());
        }
        Err(ChainRefused {
            scene: self.name.clone(),
            cells: self.cell_count(),
            field: if self.chain.is_some() {
                "chain"
            } else {
                "cells"
            },
            command: command.to_owned(),
        })
    }

    /// Each cell as a one-cell scene (the scene's name; no `cells`, no `chain`), in order
    /// from the base; a single unit gives itself.
    pub fn cell_scenes(&self) -> Vec<Scene> {
        match &self.chain {
            Some(chain) => chain.iter().map(|c| self.cell_scene(c)).collect(),
            None => {
                let one = self.cell_scene(&CellSpec::default());
                vec![one; self.cell_count()]
            }
        }
    }

    /// This scene's blocks with those `cell` gives in their place.
    fn cell_scene(&self, cell: &CellSpec) -> Scene {
        Scene {
            name: self.name.clone(),
            unit: cell.unit.unwrap_or(self.unit),
            base: self.base.clone(),
            stops: cell.stops.or(self.stops),
            damping: cell.damping.or(self.damping),
            cells: None,
            chain: None,
        }
    }

    /// Reads, parses and validates the scene file at `path`.
    ///
    /// # Errors
    /// [`SceneError::Read`] when the file cannot be read, else as [`Scene::parse`].
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
            path: path.to_owned(),
            source,
        })?;
        Scene::parse(&text, &path.display().to_string())
    }

    /// The built-in paper scene.
    ///
    /// # Panics
    /// Never: the built-in scene is a fixed, valid text (tested).
    pub fn paper() -> Scene {
        Scene::parse(PAPER_SCENE, "built-in").expect("the built-in scene is valid")
    }

    /// Checks every value against its physical range.
    ///
    /// # Errors
    /// The first value out of range, with its field and the allowed range.
    pub fn validate(&self) -> Result<(), UnitError> {
        self.unit_with(self.damping).validate()?;
        if let Some(stops) = self.stops_model() {
            stops.validate()?;
        }
        Ok(())
    }

    /// The effects this scene calls for, in a fixed order.
    pub fn effects(&self) -> Vec<Effect> {
        let mut effects = Vec::new();
        if self.cell_effect_blocks().any(|(stops, _)| stops.is_some()) {
            effects.push(Effect::Stops);
        }
        if self.is_damped() {
            effects.push(Effect::Damping);
        }
        effects
    }

    /// The names of [`Scene::effects`], as outputs list them.
    pub fn effect_names(&self) -> Vec<&'static str> {
        self.effects().iter().map(|e| e.name()).collect()
    }

    /// The effects in words, for tables: `stops, damping`, or `none (linear, undamped)`.
    pub fn effect_words(&self) -> String {
        let names = self.effect_names();
        if names.is_empty() {
            "none (linear, undamped)".to_owned()
        } else {
            names.join(", ")
        }
    }

    /// The scene's gap `Δ`, if it has stops.
    pub fn gap(&self) -> Option<f64> {
        self.stops.map(|s| s.gap)
    }

    /// Whether the scene has a dashpot that is not zero (in any cell).
    pub fn is_damped(&self) -> bool {
        self.cell_effect_blocks()
            .any(|(_, damping)| active(damping).is_some())
    }

    /// The dashpots, if the scene has any that is not zero.
    fn active_damping(&self) -> Option<DampingSpec> {
        active(self.damping)
    }

    /// The unit as the analytic solver's problem. A damping block whose dashpots are both zero
    /// is no damping at all.
    pub fn unit_model(&self) -> Unit {
        self.unit_with(self.active_damping())
    }

    fn unit_with(&self, damping: Option<DampingSpec>) -> Unit {
        Unit {
            outer_mass: self.unit.outer_mass,
            inner_mass: self.unit.inner_mass,
            outer_stiffness: self.unit.outer_stiffness,
            inner_stiffness: self.unit.inner_stiffness,
            base_amplitude: self.base.amplitude,
            damping: damping.map(|d| Damping {
                outer: d.outer,
                inner: d.inner,
            }),
        }
    }

    /// The stops as the analytic solver's problem, if the scene has rigid ones.
    pub fn stops_model(&self) -> Option<Stops> {
        self.stops.and_then(|s| {
            Some(Stops {
                gap: s.gap,
                restitution: s.restitution?,
            })
        })
    }

    /// Whether any cell's stops are compliant.
    pub fn has_compliant_stops(&self) -> bool {
        self.cell_effect_blocks()
            .any(|(stops, _)| stops.is_some_and(|s| s.is_compliant()))
    }
}

/// The dashpots of `damping` if either is not zero.
fn active(damping: Option<DampingSpec>) -> Option<DampingSpec> {
    damping.filter(|d| d.outer != 0.0 || d.inner != 0.0)
}

/// serde_json appends " at line L column C"; the position is reported separately.
fn strip_position(message: &str) -> String {
    match message.rfind(" at line ") {
        Some(i) => message[..i].to_owned(),
        None => message.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn built_in_scene_is_the_paper_unit() {
        let s = Scene::paper();
        assert_eq!(s.unit.outer_mass, 2.0);
        assert_eq!(s.stops.map(|s| s.gap), Some(0.5));
        assert_eq!(s.effects(), vec![Effect::Stops]);
    }

    #[test]
    fn unknown_fields_are_refused_with_their_path() {
        let text = PAPER_SCENE.replace("\"gap\"", "\"gapp\"");
        let err = Scene::parse(&text, "x.json").unwrap_err().to_string();
        assert!(
            err.contains("stops.gapp") && err.contains("unknown field"),
            "{err}"
        );
    }

    #[test]
    fn malformed_json_gives_line_and_column() {
        let err = Scene::parse("{\n \"name\": ,\n}", "x.json").unwrap_err();
        match err {
            SceneError::Format { line, column, .. } => assert_eq!((line, column), (2, 10)),
            other => panic!("{other}"),
        }
    }

    #[test]
    fn out_of_range_values_name_the_field_and_range() {
        let text = PAPER_SCENE.replace("\"restitution\": 0.8", "\"restitution\": 1.5");
        let err = Scene::parse(&text, "x.json").unwrap_err().to_string();
        assert!(
            err.contains("stops.restitution") && err.contains("[0, 1]"),
            "{err}"
        );
        let text = PAPER_SCENE.replace("\"outer_mass\": 2.0", "\"outer_mass\": 1e400");
        let err = Scene::parse(&text, "x.json").unwrap_err().to_string();
        assert!(err.contains("unit.outer_mass"), "{err}");
        let text = PAPER_SCENE.replace("\"outer_mass\": 2.0", "\"outer_mass\": \"2\"");
        let err = Scene::parse(&text, "x.json").unwrap_err().to_string();
        assert!(
            err.contains("unit.outer_mass") && err.contains("invalid type"),
            "{err}"
        );
    }

    #[test]
    fn zero_damping_is_no_damping() {
        let mut s = Scene::paper();
        s.damping = Some(DampingSpec {
            outer: 0.0,
            inner: 0.0,
        });
        assert_eq!(s.effects(), vec![Effect::Stops]);
        assert!(s.unit_model().damping.is_none());
        s.damping = Some(DampingSpec {
            outer: 0.1,
            inner: 0.0,
        });
        assert_eq!(s.effects(), vec![Effect::Stops, Effect::Damping]);
        assert!(s.unit_model().damping.is_some());
        s.damping = Some(DampingSpec {
            outer: -0.1,
            inner: 0.0,
        });
        assert!(s
            .validate()
            .unwrap_err()
            .to_string()
            .contains("damping.outer"));
    }

    fn chain_scene(extra: &str) -> Result<Scene, SceneError> {
        let text = PAPER_SCENE.trim_end().trim_end_matches('}').to_owned() + "," + extra + "}";
        Scene::parse(&text, "x.json")
    }

    #[test]
    fn cells_repeat_the_unit_and_one_cell_is_the_unit() {
        let five = chain_scene(r#""cells": 5"#).expect("a valid chain");
        assert_eq!(five.cell_count(), 5);
        assert!(five.is_chain());
        assert!(five
            .cell_scenes()
            .iter()
            .all(|c| c.unit == five.unit && !c.is_chain()));
        assert_eq!(five.pair_count(), 5);
        let one = chain_scene(r#""cells": 1"#).expect("a valid chain");
        assert_eq!(one, Scene::paper());
        let listed = chain_scene(r#""chain": [{"stops": {"gap": 0.3, "restitution": 0.5}}]"#)
            .expect("a valid chain");
        assert!(!listed.is_chain());
        assert_eq!(
            listed.stops.map(|s| (s.gap, s.restitution)),
            Some((0.3, Some(0.5)))
        );
        assert_eq!(listed.unit, Scene::paper().unit);
    }

    #[test]
    fn a_graded_chain_inherits_the_blocks_a_cell_does_not_give() {
        let s = chain_scene(
            r#""chain": [{}, {"stops": {"gap": 0.2, "restitution": 0.4}}, {"damping": {"outer": 0.3}}]"#,
        )
        .expect("a valid chain");
        let cells = s.cell_scenes();
        assert_eq!(cells.len(), 3);
        assert_eq!(cells[0].unit, s.unit);
        assert_eq!(cells[0].stops, Scene::paper().stops);
        assert_eq!(cells[1].stops.map(|s| s.gap), Some(0.2));
        assert_eq!(cells[2].damping.map(|d| d.outer), Some(0.3));
        assert!(s.is_damped());
        assert_eq!(s.effect_names(), vec!["stops", "damping"]);
    }

    #[test]
    fn bad_chains_are_refused_naming_the_field_and_range() {
        let err = |extra: &str| chain_scene(extra).unwrap_err().to_string();
        let e = err(r#""cells": 0"#);
        assert!(e.contains("cells") && e.contains("1..=64"), "{e}");
        let e = err(r#""cells": 65"#);
        assert!(e.contains("cells") && e.contains("1..=64"), "{e}");
        let e = err(r#""cells": -1"#);
        assert!(e.contains("cells") && e.contains("invalid value"), "{e}");
        let e = err(r#""chain": []"#);
        assert!(e.contains("chain") && e.contains("1..=64"), "{e}");
        let e = err(r#""cells": 2, "chain": [{}, {}]"#);
        assert!(e.contains("cells") && e.contains("not both"), "{e}");
        let e = err(r#""chain": [{}, {"stops": {"gap": -0.1, "restitution": 0.5}}]"#);
        assert!(e.contains("chain[1].stops.gap") && e.contains("> 0"), "{e}");
        let e = err(r#""chain": [{}, {"unit": {"outer_mass": 2.0}}]"#);
        assert!(
            e.contains("chain[1].unit") && e.contains("missing field"),
            "{e}"
        );
        let e = err(r#""chain": [{"stop": {}}]"#);
        assert!(
            e.contains("chain[0].stop") && e.contains("unknown field"),
            "{e}"
        );
    }
}
