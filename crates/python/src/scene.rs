//! `rattle.Scene`'s native half: a scene of either form (the unit and chain forms, or the
//! structure form) loaded from a file, built from a dictionary or the built-in paper scene,
//! validated as the command validates it.

use crate::common::json;
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::prelude::*;
use rattle_compare::output::structure::StructureAt;
use rattle_compare::scene::structure::{StructureForm, StructureScene};
use rattle_compare::scene::{AnyScene, Scene, SceneError};
use std::path::PathBuf;

/// The origin a scene built from a Python dictionary is named by in error messages (the
/// command names the file, or `built-in`).
pub(crate) const DICT_ORIGIN: &str = "dict";

/// The functions of the package that take a scene in the structure form, as the command's
/// [`rattle_compare::scene::STRUCTURE_COMMANDS`].
pub(crate) const STRUCTURE_CALLS: &str = "rattle.simulate, rattle.orbit with a signature, \
     rattle.orbit_trajectory, rattle.compare, rattle.sweep, rattle.continue_branch, rattle.boundary, \
     rattle.basins and rattle.map with x and y";

/// A validated scene of either form, as the command loads it.
#[pyclass(frozen, module = "rattle._rattle")]
pub(crate) struct NativeScene {
    /// The scene.
    pub(crate) scene: AnyScene,
}

impl NativeScene {
    /// The scene in the unit or chain form, or the `ValueError` refusing a structure for
    /// `call`, naming it and the forms it takes.
    pub(crate) fn cells(&self, call: &str) -> PyResult<&Scene> {
        match &self.scene {
            AnyScene::Cells(scene) => Ok(scene),
            AnyScene::Structure(form) => Err(structure_refused(form, call)),
        }
    }
}

/// The `ValueError` refusing the structure scene `form` for `call`.
pub(crate) fn structure_refused(form: &StructureForm, call: &str) -> PyErr {
    PyValueError::new_err(format!(
        "{call} does not take scene '{}' in the structure form: it takes the unit and chain \
         forms (`unit`, `base`, with `cells` or `chain` for a chain); the structure form is \
         taken by {STRUCTURE_CALLS}",
        form.scene.name
    ))
}

/// The Python exception for a scene that could not be used: the command's message. A scene
/// from a dictionary has no lines, so its format errors leave out the line and column.
fn scene_error(error: SceneError) -> PyErr {
    match error {
        SceneError::Read { ref source, .. } => {
            if source.kind() == std::io::ErrorKind::NotFound {
                PyFileNotFoundError::new_err(error.to_string())
            } else {
                PyOSError::new_err(error.to_string())
            }
        }
        SceneError::Format {
            ref origin,
            ref path_in_scene,
            ref message,
            ..
        } if origin == DICT_ORIGIN => {
            PyValueError::new_err(format!("{origin}: {path_in_scene}: {message}"))
        }
        SceneError::Format { .. }
        | SceneError::Value { .. }
        | SceneError::CellValue { .. }
        | SceneError::Chain { .. }
        | SceneError::Structure { .. }
        | SceneError::StructureForm { .. } => PyValueError::new_err(error.to_string()),
    }
}

#[pymethods]
impl NativeScene {
    /// Reads and validates the scene file at `path`, in either form, as `rattle … PATH` does.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        AnyScene::load(&path)
            .map(|scene| NativeScene { scene })
            .map_err(scene_error)
    }

    /// Parses and validates a scene given as JSON text built from a dictionary.
    ///
    /// JSON has no NaN or infinity, so the dictionary's non-finite numbers come apart, as
    /// `(field path, value)` pairs, with finite placeholders at their places in `text`: once
    /// the text has the scene's shape they are put back and the scene is validated, so that a
    /// NaN is refused as the command refuses any value out of range (field path and range).
    ///
    /// Either form is taken (the structure form when the dictionary has a `structure` field).
    #[staticmethod]
    fn from_dict_json(text: &str, non_finite: Vec<(String, f64)>) -> PyResult<Self> {
        let checked = AnyScene::parse(text, DICT_ORIGIN);
        if non_finite.is_empty() {
            return checked
                .map(|scene| NativeScene { scene })
                .map_err(scene_error);
        }
        let structure = match checked {
            Err(e @ (SceneError::Format { .. } | SceneError::Read { .. })) => {
                return Err(scene_error(e))
            }
            Ok(AnyScene::Structure(_)) | Err(SceneError::Structure { .. }) => true,
            Ok(AnyScene::Cells(_)) | Err(_) => false,
        };
        if structure {
            let mut scene: StructureScene =
                serde_json::from_str(text).map_err(|e| PyValueError::new_err(e.to_string()))?;
            for (path, value) in &non_finite {
                set_structure_number(&mut scene, path, *value)?;
            }
            let checked = scene
                .structure()
                .map_err(|source| SceneError::Structure {
                    origin: DICT_ORIGIN.to_owned(),
                    source,
                })
                .map_err(scene_error)?;
            return Ok(NativeScene {
                scene: AnyScene::Structure(Box::new(StructureForm {
                    scene,
                    structure: checked,
                })),
            });
        }
        let mut scene: Scene =
            serde_json::from_str(text).map_err(|e| PyValueError::new_err(e.to_string()))?;
        for (path, value) in &non_finite {
            set_number(&mut scene, path, *value)?;
        }
        scene
            .validated(DICT_ORIGIN)
            .map(|scene| NativeScene {
                scene: AnyScene::Cells(scene),
            })
            .map_err(scene_error)
    }

    /// The command's built-in paper scene.
    #[staticmethod]
    fn paper() -> Self {
        NativeScene {
            scene: AnyScene::Cells(Scene::paper()),
        }
    }

    /// The scene as JSON text (the format of a scene file, in the scene's form).
    fn to_json(&self) -> PyResult<String> {
        match &self.scene {
            AnyScene::Cells(scene) => json(scene),
            AnyScene::Structure(form) => json(&form.scene),
        }
    }

    /// The scene's name.
    #[getter]
    fn name(&self) -> &str {
        self.scene.name()
    }

    /// The scene's form: `cells` (the unit and chain forms) or `structure`.
    #[getter]
    fn form(&self) -> &'static str {
        match &self.scene {
            AnyScene::Cells(_) => "cells",
            AnyScene::Structure(_) => "structure",
        }
    }

    /// The scene's active effects, as outputs list them (a structure's: as the heading of
    /// its records, [`StructureAt`]).
    #[getter]
    fn effects(&self) -> Vec<&'static str> {
        match &self.scene {
            AnyScene::Cells(scene) => scene.effect_names(),
            AnyScene::Structure(form) => {
                StructureAt::new(&form.scene, &form.structure, 1.0).effects
            }
        }
    }
}

/// Sets the number at `path` (e.g. `stops.gap`) of `scene` to `value`.
fn set_number(scene: &mut Scene, path: &str, value: f64) -> PyResult<()> {
    let field = match path {
        "unit.outer_mass" => Some(&mut scene.unit.outer_mass),
        "unit.inner_mass" => Some(&mut scene.unit.inner_mass),
        "unit.outer_stiffness" => Some(&mut scene.unit.outer_stiffness),
        "unit.inner_stiffness" => Some(&mut scene.unit.inner_stiffness),
        "base.amplitude" => Some(&mut scene.base.amplitude),
        "stops.gap" => scene.stops.as_mut().map(|s| &mut s.gap),
        "stops.restitution" => scene.stops.as_mut().map(|s| &mut s.restitution),
        "damping.outer" => scene.damping.as_mut().map(|d| &mut d.outer),
        "damping.inner" => scene.damping.as_mut().map(|d| &mut d.inner),
        _ => None,
    };
    match field {
        Some(field) => {
            *field = value;
            Ok(())
        }
        None => Err(PyValueError::new_err(format!(
            "{DICT_ORIGIN}: {path}: {value} is not a value of the scene format"
        ))),
    }
}

/// Sets the number at `path` (e.g. `structure.bodies[0].mass`) of the structure scene
/// `scene` to `value`.
fn set_structure_number(scene: &mut StructureScene, path: &str, value: f64) -> PyResult<()> {
    let refused = || {
        PyValueError::new_err(format!(
            "{DICT_ORIGIN}: {path}: {value} is not a value of the scene format"
        ))
    };
    // `list[index].field` at the start of `rest`: the index and the field.
    let indexed = |rest: &str, list: &str| -> Option<(usize, String)> {
        let rest = rest.strip_prefix(list)?.strip_prefix('[')?;
        let (index, field) = rest.split_once("].")?;
        Some((index.parse().ok()?, field.to_owned()))
    };
    let spec = &mut scene.structure;
    let field: Option<&mut f64> = if let Some((j, f)) = indexed(path, "structure.bodies") {
        spec.bodies
            .get_mut(j)
            .and_then(|b| (f == "mass").then_some(&mut b.mass))
    } else if let Some((j, f)) = indexed(path, "structure.springs") {
        spec.springs
            .get_mut(j)
            .and_then(|s| (f == "stiffness").then_some(&mut s.stiffness))
    } else if let Some((j, f)) = indexed(path, "structure.dashpots") {
        spec.dashpots
            .get_mut(j)
            .and_then(|d| (f == "damping").then_some(&mut d.damping))
    } else if let Some((j, f)) = indexed(path, "structure.stops") {
        spec.stops.get_mut(j).and_then(|s| match f.as_str() {
            "gap" => s.gap.as_mut(),
            "gap_plus" => s.gap_plus.as_mut(),
            "gap_minus" => s.gap_minus.as_mut(),
            "restitution" => Some(&mut s.restitution),
            _ => None,
        })
    } else if let Some((j, f)) = indexed(path, "forcing.forces") {
        scene
            .forcing
            .forces
            .get_mut(j)
            .and_then(|force| match f.as_str() {
                "amplitude" => Some(&mut force.amplitude),
                "phase" => Some(&mut force.phase),
                _ => None,
            })
    } else if path == "forcing.base.amplitude" {
        scene.forcing.base.as_mut().map(|b| &mut b.amplitude)
    } else {
        None
    };
    let field = field.ok_or_else(refused)?;
    *field = value;
    Ok(())
}

/// Registers the scene class.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeScene>()
}
