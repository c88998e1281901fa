//! A number of a scene named by its JSON path, read and set: the parameter a two-parameter
//! study varies beside the frequency (`stops.gap`, `chain[2].stops.restitution`, …).
//!
//! A path names a field of the scene's own blocks (`unit.*`, `base.amplitude`, `stops.*`,
//! `damping.*`), which every cell of a chain inherits unless it gives its own block, or a field
//! of one cell of a chain (`chain[K].unit.*`, `chain[K].stops.*`, `chain[K].damping.*`; the
//! base is the chain's, not a cell's). Setting a cell's field of a chain of identical cells
//! (`cells: N`) writes the chain out cell by cell first, so that only that cell changes.

use super::structure_parameter::{StructureParameter, StructureParameterError};
use super::{AnyScene, CellSpec, DampingSpec, Scene, SceneError};
use std::fmt;
use std::str::FromStr;
use thiserror::Error;

/// A field a [`SceneParameter`] can name, within a block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    /// `unit.outer_mass`, `m_o`.
    OuterMass,
    /// `unit.inner_mass`, `m_i`.
    InnerMass,
    /// `unit.outer_stiffness`, `k_o`.
    OuterStiffness,
    /// `unit.inner_stiffness`, `k_i`.
    InnerStiffness,
    /// `base.amplitude`, `u_g` (the scene's only; not a cell's).
    BaseAmplitude,
    /// `stops.gap`, `Δ`.
    Gap,
    /// `stops.restitution`, `e`.
    Restitution,
    /// `damping.outer`, `c_o`.
    OuterDamping,
    /// `damping.inner`, `c_i`.
    InnerDamping,
}

impl Field {
    /// Every field, in the order of the scene format.
    pub const ALL: [Field; 9] = [
        Field::OuterMass,
        Field::InnerMass,
        Field::OuterStiffness,
        Field::InnerStiffness,
        Field::BaseAmplitude,
        Field::Gap,
        Field::Restitution,
        Field::OuterDamping,
        Field::InnerDamping,
    ];

    /// The field's path within the scene, e.g. `stops.gap`.
    pub fn path(self) -> &'static str {
        match self {
            Field::OuterMass => "unit.outer_mass",
            Field::InnerMass => "unit.inner_mass",
            Field::OuterStiffness => "unit.outer_stiffness",
            Field::InnerStiffness => "unit.inner_stiffness",
            Field::BaseAmplitude => "base.amplitude",
            Field::Gap => "stops.gap",
            Field::Restitution => "stops.restitution",
            Field::OuterDamping => "damping.outer",
            Field::InnerDamping => "damping.inner",
        }
    }
}

/// A number of a scene, by its JSON path: see the [module](self).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SceneParameter {
    /// The cell of a chain whose block it is, or `None` for the scene's own block.
    pub cell: Option<usize>,
    /// The field.
    pub field: Field,
}

/// Why a parameter path cannot be read or used on a scene. Every message names the path.
#[derive(Debug, Error)]
pub enum ParameterError {
    /// The text is not a parameter path.
    #[error(
        "parameter `{path}` is not a scene field: give one of {}, or one of the unit, stops \
         and damping fields of a cell as `chain[K].stops.gap`",
        Field::ALL.map(Field::path).join(", ")
    )]
    Unknown {
        /// The text as given.
        path: String,
    },
    /// The base belongs to the chain, not to a cell.
    #[error("parameter `{path}`: the base is the chain's, not a cell's: give `base.amplitude`")]
    CellBase {
        /// The path as given.
        path: String,
    },
    /// The cell index is beyond the scene's chain.
    #[error("parameter `{path}`: cell {cell} is out of range: the scene has {cells} cell(s), 0..={last}", last = cells - 1)]
    CellOutOfRange {
        /// The path as given.
        path: String,
        /// The cell asked for.
        cell: usize,
        /// The scene's number of cells.
        cells: usize,
    },
    /// The scene (or the cell) has no stops, so `stops.*` has no value.
    #[error("parameter `{path}`: the scene has no stops there, so it has no {path}")]
    NoStops {
        /// The path as given.
        path: String,
    },
    /// The value set makes the scene invalid (out of the field's physical range).
    #[error("parameter `{path}`: {source}")]
    Value {
        /// The path as given.
        path: String,
        /// The scene's own refusal, naming the range.
        source: Box<SceneError>,
    },
}

impl FromStr for SceneParameter {
    type Err = ParameterError;

    /// Reads `stops.gap`, `unit.inner_stiffness`, `chain[2].stops.gap`, ….
    fn from_str(path: &str) -> Result<Self, ParameterError> {
        let unknown = || ParameterError::Unknown {
            path: path.to_owned(),
        };
        let (cell, field_path) = match path.strip_prefix("chain[") {
            Some(rest) => {
                let (index, field) = rest.split_once("].").ok_or_else(unknown)?;
                (Some(index.parse::<usize>().map_err(|_| unknown())?), field)
            }
            None => (None, path),
        };
        let field = Field::ALL
            .into_iter()
            .find(|f| f.path() == field_path)
            .ok_or_else(unknown)?;
        if cell.is_some() && field == Field::BaseAmplitude {
            return Err(ParameterError::CellBase {
                path: path.to_owned(),
            });
        }
        Ok(SceneParameter { cell, field })
    }
}

impl fmt::Display for SceneParameter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.cell {
            Some(cell) => write!(f, "chain[{cell}].{}", self.field.path()),
            None => f.write_str(self.field.path()),
        }
    }
}

/// The blocks a field lives in, borrowed from one scene or one cell.
struct Blocks<'a> {
    base: &'a mut f64,
    unit: &'a mut super::UnitSpec,
    stops: &'a mut Option<super::StopsSpec>,
    damping: &'a mut Option<DampingSpec>,
}

impl SceneParameter {
    /// The parameter's value in `scene`: the cell's own block where it gives one, else the
    /// scene's (which the cell inherits); an absent damping block reads 0.
    ///
    /// # Errors
    /// [`ParameterError::CellOutOfRange`] for a cell beyond the chain,
    /// [`ParameterError::NoStops`] for `stops.*` where there are no stops.
    pub fn value(&self, scene: &Scene) -> Result<f64, ParameterError> {
        let mut scene = self.cell_scene(scene)?;
        let path = self.to_string();
        let blocks = Blocks {
            base: &mut scene.base.amplitude,
            unit: &mut scene.unit,
            stops: &mut scene.stops,
            damping: &mut scene.damping,
        };
        Ok(*self.slot(blocks, &path)?)
    }

    /// `scene` with this parameter set to `value`, validated.
    ///
    /// # Errors
    /// As [`SceneParameter::value`], and [`ParameterError::Value`] when `value` is outside
    /// the field's physical range (the scene's own message, with the range).
    pub fn with_value(&self, scene: &Scene, value: f64) -> Result<Scene, ParameterError> {
        let path = self.to_string();
        self.cell_scene(scene)?;
        let mut out = scene.clone();
        let blocks = match self.cell {
            None => Blocks {
                base: &mut out.base.amplitude,
                unit: &mut out.unit,
                stops: &mut out.stops,
                damping: &mut out.damping,
            },
            Some(cell) => {
                let base = &mut out.base.amplitude;
                let spec = &mut written_out(&mut out.cells, &mut out.chain)[cell];
                if spec.stops.is_none() {
                    spec.stops = scene.stops;
                }
                if spec.damping.is_none() {
                    spec.damping = scene.damping;
                }
                Blocks {
                    base,
                    unit: spec.unit.get_or_insert(scene.unit),
                    stops: &mut spec.stops,
                    damping: &mut spec.damping,
                }
            }
        };
        *self.slot(blocks, &path)? = value;
        let origin = format!("scene '{}'", scene.name);
        out.validated(&origin)
            .map_err(|source| ParameterError::Value {
                path,
                source: Box::new(source),
            })
    }

    /// The one-cell scene the parameter's block belongs to: the scene itself, or its cell.
    fn cell_scene(&self, scene: &Scene) -> Result<Scene, ParameterError> {
        match self.cell {
            None => Ok(scene.clone()),
            Some(cell) => {
                let cells = scene.cell_scenes();
                let count = cells.len();
                cells
                    .into_iter()
                    .nth(cell)
                    .ok_or_else(|| ParameterError::CellOutOfRange {
                        path: self.to_string(),
                        cell,
                        cells: count,
                    })
            }
        }
    }

    /// The number the field names within `blocks` (a zero damping block is made where none
    /// is given, for a damping field).
    fn slot<'a>(&self, blocks: Blocks<'a>, path: &str) -> Result<&'a mut f64, ParameterError> {
        let no_stops = || ParameterError::NoStops {
            path: path.to_owned(),
        };
        let zero = DampingSpec {
            outer: 0.0,
            inner: 0.0,
        };
        Ok(match self.field {
            Field::OuterMass => &mut blocks.unit.outer_mass,
            Field::InnerMass => &mut blocks.unit.inner_mass,
            Field::OuterStiffness => &mut blocks.unit.outer_stiffness,
            Field::InnerStiffness => &mut blocks.unit.inner_stiffness,
            Field::BaseAmplitude => blocks.base,
            Field::Gap => &mut blocks.stops.as_mut().ok_or_else(no_stops)?.gap,
            Field::Restitution => blocks
                .stops
                .as_mut()
                .and_then(|s| s.restitution.as_mut())
                .ok_or_else(no_stops)?,
            Field::OuterDamping => &mut blocks.damping.get_or_insert(zero).outer,
            Field::InnerDamping => &mut blocks.damping.get_or_insert(zero).inner,
        })
    }
}

/// The scene's chain as one entry per cell (a chain of identical cells written out as that
/// many empty entries, which inherit every block), for setting one cell's block.
fn written_out<'a>(
    cells: &mut Option<usize>,
    chain: &'a mut Option<Vec<CellSpec>>,
) -> &'a mut Vec<CellSpec> {
    let count = cells.take().unwrap_or(1);
    chain.get_or_insert_with(|| vec![CellSpec::default(); count])
}

/// A number of a scene of any form by its JSON path: a [`SceneParameter`] of the unit and
/// chain forms, a [`StructureParameter`] of the structure form.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnyParameter {
    /// A field of a unit or chain scene (`stops.gap`, `chain[2].unit.inner_mass`).
    Cells(SceneParameter),
    /// A field of a structure scene (`structure.stops[0].gap_plus`).
    Structure(StructureParameter),
}

/// Why a parameter path cannot be read or used on a scene of any form.
#[derive(Debug, Error)]
pub enum AnyParameterError {
    /// On a unit or chain scene.
    #[error(transparent)]
    Cells(#[from] ParameterError),
    /// On a structure scene.
    #[error(transparent)]
    Structure(#[from] StructureParameterError),
}

impl AnyParameter {
    /// Reads `path` as a parameter of `scene`'s form.
    ///
    /// # Errors
    /// The form's refusal of a path it does not know, listing the paths it takes.
    pub fn parse(scene: &AnyScene, path: &str) -> Result<AnyParameter, AnyParameterError> {
        Ok(match scene {
            AnyScene::Cells(_) => AnyParameter::Cells(path.parse()?),
            AnyScene::Structure(_) => AnyParameter::Structure(path.parse()?),
        })
    }

    /// The parameter's value in `scene`.
    ///
    /// # Errors
    /// As [`SceneParameter::value`] and [`StructureParameter::value`]; a parameter of one form
    /// on a scene of the other is [`StructureParameterError::Unknown`] or
    /// [`ParameterError::Unknown`].
    pub fn value(&self, scene: &AnyScene) -> Result<f64, AnyParameterError> {
        match (self, scene) {
            (AnyParameter::Cells(p), AnyScene::Cells(s)) => Ok(p.value(s)?),
            (AnyParameter::Structure(p), AnyScene::Structure(form)) => Ok(p.value(&form.scene)?),
            _ => Err(self.other_form()),
        }
    }

    /// `scene` with this parameter set to `value`, checked.
    ///
    /// # Errors
    /// As [`AnyParameter::value`], and the form's refusal of a value out of the field's range.
    pub fn with_value(&self, scene: &AnyScene, value: f64) -> Result<AnyScene, AnyParameterError> {
        match (self, scene) {
            (AnyParameter::Cells(p), AnyScene::Cells(s)) => {
                Ok(AnyScene::Cells(p.with_value(s, value)?))
            }
            (AnyParameter::Structure(p), AnyScene::Structure(form)) => Ok(AnyScene::Structure(
                Box::new(p.with_value(&form.scene, value)?),
            )),
            _ => Err(self.other_form()),
        }
    }

    /// The refusal of this parameter on a scene of the other form.
    fn other_form(&self) -> AnyParameterError {
        let path = self.to_string();
        match self {
            AnyParameter::Cells(_) => {
                AnyParameterError::Structure(StructureParameterError::Unknown { path })
            }
            AnyParameter::Structure(_) => {
                AnyParameterError::Cells(ParameterError::Unknown { path })
            }
        }
    }
}

impl FromStr for AnyParameter {
    type Err = AnyParameterError;

    /// Reads a path of either form without a scene: one that begins with `structure.` or
    /// `forcing.` as a [`StructureParameter`], any other as a [`SceneParameter`].
    fn from_str(path: &str) -> Result<Self, AnyParameterError> {
        if path.starts_with("structure.") || path.starts_with("forcing.") {
            Ok(AnyParameter::Structure(path.parse()?))
        } else {
            Ok(AnyParameter::Cells(path.parse()?))
        }
    }
}

impl fmt::Display for AnyParameter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AnyParameter::Cells(p) => p.fmt(f),
            AnyParameter::Structure(p) => p.fmt(f),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain(cells: usize) -> Scene {
        let mut scene = Scene::paper();
        scene.cells = Some(cells);
        scene.validated("test").expect("a valid chain")
    }

    #[test]
    fn every_field_reads_back_what_is_set_on_the_unit() {
        let scene = Scene::paper();
        for field in Field::ALL {
            let p = SceneParameter { cell: None, field };
            let text = p.to_string();
            assert_eq!(text.parse::<SceneParameter>().ok(), Some(p), "{text}");
            let set = p
                .with_value(&scene, 0.375)
                .expect("0.375 is in every range");
            assert_eq!(p.value(&set).ok(), Some(0.375), "{text}");
            // Nothing else moved.
            for other in Field::ALL.into_iter().filter(|&f| f != field) {
                let q = SceneParameter {
                    cell: None,
                    field: other,
                };
                assert_eq!(q.value(&set).ok(), q.value(&scene).ok(), "{text} moved {q}");
            }
        }
    }

    #[test]
    fn a_cell_of_identical_cells_changes_alone() {
        let scene = chain(3);
        let p: SceneParameter = "chain[1].stops.gap".parse().expect("a path");
        let set = p.with_value(&scene, 0.25).expect("valid");
        let gaps: Vec<f64> = set
            .cell_scenes()
            .iter()
            .map(|c| c.stops.expect("stops").gap)
            .collect();
        assert_eq!(gaps, [0.5, 0.25, 0.5]);
        assert_eq!(p.value(&set).ok(), Some(0.25));
        // The whole chain's gap: every cell that does not give its own.
        let all: SceneParameter = "stops.gap".parse().expect("a path");
        let set = all.with_value(&chain(2), 0.3).expect("valid");
        assert!(set
            .cell_scenes()
            .iter()
            .all(|c| c.stops.unwrap().gap == 0.3));
    }

    #[test]
    fn bad_paths_and_values_are_refused_naming_the_path() {
        for text in [
            "stops.gapp",
            "gap",
            "chain[x].stops.gap",
            "chain[1]stops.gap",
        ] {
            let e = text.parse::<SceneParameter>().expect_err(text);
            assert!(e.to_string().contains(text), "{e}");
        }
        let e = "chain[0].base.amplitude"
            .parse::<SceneParameter>()
            .expect_err("the base is not a cell's");
        assert!(matches!(e, ParameterError::CellBase { .. }), "{e}");
        let p: SceneParameter = "chain[3].stops.gap".parse().expect("a path");
        let e = p.value(&chain(3)).expect_err("cells 0..=2");
        assert!(e.to_string().contains("0..=2"), "{e}");
        let gap: SceneParameter = "stops.gap".parse().expect("a path");
        let e = gap.with_value(&Scene::paper(), -1.0).expect_err("negative");
        assert!(e.to_string().contains("stops.gap"), "{e}");
        let e = "stops.restitution"
            .parse::<SceneParameter>()
            .expect("a path")
            .with_value(&Scene::paper(), 1.5)
            .expect_err("above 1");
        assert!(e.to_string().contains("restitution"), "{e}");
        let mut linear = Scene::paper();
        linear.stops = None;
        assert!(matches!(
            gap.value(&linear),
            Err(ParameterError::NoStops { .. })
        ));
    }

    #[test]
    fn any_parameter_takes_the_path_of_the_scene_s_form() {
        let unit = AnyScene::Cells(Scene::paper());
        let p = AnyParameter::parse(&unit, "stops.gap").expect("a unit path");
        assert_eq!(p.value(&unit).ok(), Some(0.5));
        let set = p.with_value(&unit, 0.25).expect("valid");
        assert_eq!(p.value(&set).ok(), Some(0.25));
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../data/scenes/impact-oscillator.json"
        ))
        .expect("the gallery scene");
        let oscillator = AnyScene::parse(&text, "impact-oscillator.json").expect("valid");
        let e = AnyParameter::parse(&oscillator, "stops.gap").expect_err("a unit path");
        assert!(e.to_string().contains("structure.stops[K].gap_plus"), "{e}");
        let q = AnyParameter::parse(&oscillator, "structure.stops[0].restitution").expect("a path");
        let set = q.with_value(&oscillator, 0.5).expect("valid");
        assert_eq!(q.value(&set).ok(), Some(0.5));
        assert!(q.value(&unit).is_err() && p.value(&oscillator).is_err());
    }
}
