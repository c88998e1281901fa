//! `rattle.Scene`'s native half: a scene of either form (the unit and chain forms, or the
//! structure form) loaded from a file, built from a dictionary or the built-in paper scene,
//! validated as the command validates it.

use crate::common::json;
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::prelude::*;
use rattle_compare::output::structure::StructureAt;
use rattle_compare::scene::structure::{StructureForm, StructureScene};
use rattle_compare::scene::structure_parameter::StructureParameter;
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
        | SceneError::StructureForm { .. }
        | SceneError::Harmonic { .. }
        | SceneError::Stops { .. }
        | SceneError::CellsCompliant { .. }
        | SceneError::CellsHarmonics { .. } => PyValueError::new_err(error.to_string()),
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
        if let Err(e @ (SceneError::Format { .. } | SceneError::Read { .. })) = checked {
            return Err(scene_error(e));
        }
        // The form is the document's (a unit whose base has harmonics parses as a structure).
        let structure = serde_json::from_str::<serde_json::Value>(text)
            .is_ok_and(|document| document.get("structure").is_some());
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
        AnyScene::of_cells(scene, DICT_ORIGIN)
            .map(|scene| NativeScene { scene })
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
        _ if path.starts_with("base.harmonics[") => path
            .strip_prefix("base.harmonics[")
            .and_then(|rest| rest.split_once("]."))
            .and_then(|(k, field)| Some((k.parse::<usize>().ok()?, field)))
            .and_then(|(k, field)| {
                let h = scene.base.harmonics.get_mut(k)?;
                match field {
                    "amplitude" => Some(&mut h.amplitude),
                    "phase" => Some(&mut h.phase),
                    _ => None,
                }
            }),
        "stops.gap" => scene.stops.as_mut().map(|s| &mut s.gap),
        "stops.restitution" => scene.stops.as_mut().and_then(|s| s.restitution.as_mut()),
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
/// `scene` to `value`, unchecked: the scene is checked once every number is back.
fn set_structure_number(scene: &mut StructureScene, path: &str, value: f64) -> PyResult<()> {
    path.parse::<StructureParameter>()
        .and_then(|p| p.set_unchecked(scene, value))
        .map_err(|_| {
            PyValueError::new_err(format!(
                "{DICT_ORIGIN}: {path}: {value} is not a value of the scene format"
            ))
        })
}

/// Registers the scene class.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeScene>()
}
