//! `rattle.Scene`'s native half: a scene loaded from a file, built from a dictionary or the
//! built-in paper scene, validated as the command validates it.

use crate::common::json;
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::prelude::*;
use rattle_compare::scene::{Scene, SceneError};
use std::path::PathBuf;

/// The origin a scene built from a Python dictionary is named by in error messages (the
/// command names the file, or `built-in`).
pub(crate) const DICT_ORIGIN: &str = "dict";

/// A validated scene, as the command loads it.
#[pyclass(frozen, module = "rattle._rattle")]
pub(crate) struct NativeScene {
    /// The scene.
    pub(crate) scene: Scene,
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
    /// Reads and validates the scene file at `path`, as `rattle … PATH` does.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        Scene::load(&path)
            .map(|scene| NativeScene { scene })
            .map_err(scene_error)
    }

    /// Parses and validates a scene given as JSON text built from a dictionary.
    ///
    /// JSON has no NaN or infinity, so the dictionary's non-finite numbers come apart, as
    /// `(field path, value)` pairs, with finite placeholders at their places in `text`: once
    /// the text has the scene's shape they are put back and the scene is validated, so that a
    /// NaN is refused as the command refuses any value out of range (field path and range).
    #[staticmethod]
    fn from_dict_json(text: &str, non_finite: Vec<(String, f64)>) -> PyResult<Self> {
        let checked = Scene::parse(text, DICT_ORIGIN);
        if non_finite.is_empty() {
            return checked
                .map(|scene| NativeScene { scene })
                .map_err(scene_error);
        }
        if let Err(e @ (SceneError::Format { .. } | SceneError::Read { .. })) = checked {
            return Err(scene_error(e));
        }
        let mut scene: Scene =
            serde_json::from_str(text).map_err(|e| PyValueError::new_err(e.to_string()))?;
        for (path, value) in &non_finite {
            set_number(&mut scene, path, *value)?;
        }
        scene
            .validated(DICT_ORIGIN)
            .map(|scene| NativeScene { scene })
            .map_err(scene_error)
    }

    /// The command's built-in paper scene.
    #[staticmethod]
    fn paper() -> Self {
        NativeScene {
            scene: Scene::paper(),
        }
    }

    /// The scene as JSON text (the format of a scene file).
    fn to_json(&self) -> PyResult<String> {
        json(&self.scene)
    }

    /// The scene's name.
    #[getter]
    fn name(&self) -> &str {
        &self.scene.name
    }

    /// The scene's active effects, as outputs list them.
    #[getter]
    fn effects(&self) -> Vec<&'static str> {
        self.scene.effect_names()
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

/// Registers the scene class.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeScene>()
}
