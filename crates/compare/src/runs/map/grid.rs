//! A map's grid: what its two axes set in the scene and the values they take, the scene of
//! every line, and the checks of the whole grid before anything is computed.
//!
//! The axes are either the map's default, the restitution `e` and the gap over the base
//! amplitude `Δ/u_g` of every stop of a unit or a chain ([`MapAxes::Stops`], [`MapGrid`]), or
//! any two numbers of a scene of any form named by their JSON paths
//! ([`MapAxes::Parameters`], [`AnyParameter`]). Either way a line's scene is the scene with its
//! two axes set ([`AnyMapGrid::line_scenes`]), and every line runs alike.

use super::MapError;
use crate::runs::axis::Axis;
use crate::scene::frequency::FrequencyBounds;
use crate::scene::parameter::AnyParameter;
use crate::scene::{AnyScene, Scene, StopsSpec};

/// The grid of the map over restitution and gap, its default axes: restitution `e`, gap
/// relative to the base amplitude `Δ/u_g`, and angular frequency `ω` (rad/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapGrid {
    /// Restitution values, in `[0, 1]`.
    pub restitution: Axis,
    /// `Δ/u_g` values, finite and > 0.
    pub gap_over_base_amplitude: Axis,
    /// Frequencies, rad/s, finite and > 0.
    pub omega: Axis,
}

/// What the two axes of a map set in its scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapAxes {
    /// The restitution `e` (x) and the gap over the base amplitude `Δ/u_g` (y) of every stop
    /// of a unit or a chain, each cell's own stops replaced: the map's default.
    Stops,
    /// Two numbers of the scene by their JSON paths (`structure.stops[0].gap_plus`,
    /// `unit.inner_mass`, `chain[2].stops.gap`), each line's scene the scene with both set.
    Parameters {
        /// The x axis's parameter.
        x: AnyParameter,
        /// The y axis's parameter.
        y: AnyParameter,
    },
}

impl MapAxes {
    /// The command-line flags of each axis (`[min, max, count]` of x, then of y), as errors
    /// name them.
    pub fn flags(&self) -> [[&'static str; 3]; 2] {
        match self {
            MapAxes::Stops => [
                ["--restitution-min", "--restitution-max", "--restitutions"],
                ["--gap-min", "--gap-max", "--gaps"],
            ],
            MapAxes::Parameters { .. } => [
                ["--x-min", "--x-max", "--x-count"],
                ["--y-min", "--y-max", "--y-count"],
            ],
        }
    }
}

/// A map's grid on any two axes: what they set ([`MapAxes`]), their values, and the
/// frequencies of every line. Lines are x-major: every y of the first x, then the next x.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnyMapGrid {
    /// What the axes set.
    pub axes: MapAxes,
    /// The x axis's values (the restitution on the default axes).
    pub x: Axis,
    /// The y axis's values (`Δ/u_g` on the default axes).
    pub y: Axis,
    /// Frequencies, rad/s, finite and > 0.
    pub omega: Axis,
}

impl From<MapGrid> for AnyMapGrid {
    /// The default axes: x the restitution, y `Δ/u_g`.
    fn from(grid: MapGrid) -> AnyMapGrid {
        AnyMapGrid {
            axes: MapAxes::Stops,
            x: grid.restitution,
            y: grid.gap_over_base_amplitude,
            omega: grid.omega,
        }
    }
}

/// One line of a map: its axes' values and the scene with both set.
#[derive(Debug, Clone, PartialEq)]
pub struct LineScene {
    /// The x axis's value.
    pub x: f64,
    /// The y axis's value.
    pub y: f64,
    /// The scene of the line.
    pub scene: AnyScene,
}

fn check_axis(
    axis: &Axis,
    names: [&'static str; 3],
    valid: impl Fn(f64) -> bool,
    allowed: &'static str,
) -> Result<(), MapError> {
    let [min, max, count] = names;
    if !valid(axis.min) {
        return Err(MapError::OutOfRange {
            field: min,
            value: axis.min.to_string(),
            allowed,
        });
    }
    if !valid(axis.max) || axis.max < axis.min {
        return Err(MapError::OutOfRange {
            field: max,
            value: axis.max.to_string(),
            allowed: "must be in the same range and ≥ the minimum",
        });
    }
    if axis.count == 0 {
        return Err(MapError::OutOfRange {
            field: count,
            value: "0".into(),
            allowed: "must be ≥ 1",
        });
    }
    Ok(())
}

impl MapGrid {
    /// Checks every axis; errors name the command-line field.
    pub fn validate(&self) -> Result<(), MapError> {
        AnyMapGrid::from(*self).validate()
    }

    /// Number of `(e, Δ/u_g)` lines.
    pub fn lines(&self) -> usize {
        AnyMapGrid::from(*self).lines()
    }

    /// Number of steady states the map computes.
    pub fn points(&self) -> usize {
        AnyMapGrid::from(*self).points()
    }
}

impl AnyMapGrid {
    /// Checks every axis's shape and, on the default axes, its range; errors name the
    /// command-line field. A parameter's range depends on the scene: [`AnyMapGrid::check`].
    pub fn validate(&self) -> Result<(), MapError> {
        let [x, y] = self.axes.flags();
        match self.axes {
            MapAxes::Stops => {
                check_axis(
                    &self.x,
                    x,
                    |e| (0.0..=1.0).contains(&e),
                    "must be in [0, 1]",
                )?;
                check_axis(
                    &self.y,
                    y,
                    |g| g.is_finite() && g > 0.0,
                    "must be finite and > 0 (gap Δ over base amplitude u_g)",
                )?;
            }
            MapAxes::Parameters { .. } => {
                let finite = |v: f64| v.is_finite();
                check_axis(&self.x, x, finite, "must be finite")?;
                check_axis(&self.y, y, finite, "must be finite")?;
            }
        }
        check_axis(
            &self.omega,
            ["--omega-min", "--omega-max", "--points"],
            |w| w.is_finite() && w > 0.0,
            "must be finite and > 0 (rad/s)",
        )
    }

    /// Number of lines, one per `(x, y)`.
    pub fn lines(&self) -> usize {
        self.x.count * self.y.count
    }

    /// Number of steady states the map computes.
    pub fn points(&self) -> usize {
        self.lines() * self.omega.count
    }

    /// Checks the grid on `scene` before anything is computed ([`AnyMapGrid::line_scenes`]).
    ///
    /// # Errors
    /// As [`AnyMapGrid::line_scenes`].
    pub fn check(&self, scene: &AnyScene) -> Result<(), MapError> {
        self.line_scenes(scene).map(drop)
    }

    /// The scene of every line, x-major, after every check of the grid on `scene`: the axes'
    /// shapes ([`AnyMapGrid::validate`]); on the default axes, a unit or chain with stops and
    /// the frequencies within its bounds; on two parameters, two different paths, each axis's
    /// ends within its parameter's range (each end set alone), and every line's scene valid
    /// and runnable at the lowest and highest frequency.
    ///
    /// # Errors
    /// [`MapError`] naming the flag (`--x-min`, `--omega-max`) or the line, with the allowed
    /// range.
    pub fn line_scenes(&self, scene: &AnyScene) -> Result<Vec<LineScene>, MapError> {
        self.validate()?;
        let (xs, ys) = (self.x.values(), self.y.values());
        let keys = xs.iter().flat_map(|&x| ys.iter().map(move |&y| (x, y)));
        match self.axes {
            MapAxes::Stops => {
                let cells = match scene {
                    AnyScene::Cells(cells) if cells.stops.is_some() => cells,
                    AnyScene::Cells(_) => return Err(MapError::NoStops),
                    AnyScene::Structure(form) => {
                        return Err(MapError::NoDefaultAxes {
                            scene: form.scene.name.clone(),
                        })
                    }
                };
                let bounds = FrequencyBounds::of(cells);
                bounds.check("--omega-min", self.omega.min)?;
                bounds.check("--omega-max", self.omega.max)?;
                Ok(keys
                    .map(|(x, y)| LineScene {
                        x,
                        y,
                        scene: AnyScene::Cells(scene_at(cells, x, y)),
                    })
                    .collect())
            }
            MapAxes::Parameters { x, y } => {
                if x == y {
                    return Err(MapError::Parameter {
                        flag: "--y".into(),
                        message: format!(
                            "the same parameter as --x (`{x}`): a map needs two different \
                             parameters"
                        ),
                    });
                }
                let [x_flags, y_flags] = self.axes.flags();
                for (parameter, axis, [min, max, _], flag) in
                    [(x, self.x, x_flags, "--x"), (y, self.y, y_flags, "--y")]
                {
                    // The number must exist before its range is asked about.
                    parameter.value(scene).map_err(|e| MapError::Parameter {
                        flag: flag.into(),
                        message: e.to_string(),
                    })?;
                    for (flag, value) in [(min, axis.min), (max, axis.max)] {
                        parameter
                            .with_value(scene, value)
                            .map_err(|e| MapError::Parameter {
                                flag: format!("{flag} = {value}"),
                                message: e.to_string(),
                            })?;
                    }
                }
                keys.map(|(xv, yv)| {
                    let at = || format!("at {x} = {xv}, {y} = {yv}");
                    let line = x
                        .with_value(scene, xv)
                        .and_then(|s| y.with_value(&s, yv))
                        .map_err(|e| MapError::Parameter {
                            flag: at(),
                            message: e.to_string(),
                        })?;
                    for (flag, omega) in [
                        ("--omega-min", self.omega.min),
                        ("--omega-max", self.omega.max),
                    ] {
                        check_frequency(&line, flag, omega).map_err(|e| MapError::Parameter {
                            flag: at(),
                            message: e.to_string(),
                        })?;
                    }
                    Ok(LineScene {
                        x: xv,
                        y: yv,
                        scene: line,
                    })
                })
                .collect()
            }
        }
    }
}

/// `omega` if `scene`, of either form, can be run at it in bounded time.
fn check_frequency(
    scene: &AnyScene,
    flag: &str,
    omega: f64,
) -> Result<f64, crate::scene::frequency::FrequencyError> {
    match scene {
        AnyScene::Cells(cells) => FrequencyBounds::of(cells).check(flag, omega),
        AnyScene::Structure(form) => {
            FrequencyBounds::of_structure(&form.structure).check(flag, omega)
        }
    }
}

/// The scene with its stops replaced by gap `gap_over_base_amplitude · u_g` and restitution
/// `restitution`: of every cell, for a chain (the default axes' line scene).
pub fn scene_at(scene: &Scene, restitution: f64, gap_over_base_amplitude: f64) -> Scene {
    let mut s = scene.clone();
    s.stops = Some(StopsSpec::rigid(
        gap_over_base_amplitude * scene.base.amplitude,
        restitution,
    ));
    // Every cell of a graded chain takes the map's stops.
    if let Some(chain) = &mut s.chain {
        for cell in chain {
            cell.stops = None;
        }
    }
    s
}
