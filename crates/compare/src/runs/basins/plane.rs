//! The plane of starts: the coordinates of a scene's state ([`Coordinate`]), the grid of
//! their values ([`BasinGrid`]), the plane over two of them ([`BasinPlane`]) and the command's
//! options read into one ([`BasinAxes::starts`]), with the refusals of what is out of range.

use crate::runs::axis::Axis;
use crate::scene::AnyScene;
use rattle_event_driven::Start;
use thiserror::Error;

/// The values of the two axes of starts. On the unit's default plane `outer` is the outer
/// displacement `u_o` and `inner` the inner `u_i`, m; on a [`BasinPlane`] `outer` holds the
/// first coordinate's values (`--x`) and `inner` the second's (`--y`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BasinGrid {
    /// The first axis: outer displacement `u_o` at the start on the default plane, m.
    pub outer: Axis,
    /// The second axis: inner displacement `u_i` at the start on the default plane, m.
    pub inner: Axis,
}

/// A basins grid out of range; the message names the command-line field and its range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BasinsError {
    /// A side's ends are not finite or not in order.
    #[error("--{side}-min = {min}, --{side}-max = {max}: must be finite with min ≤ max")]
    Side {
        /// `outer` or `inner` (the default plane), `x` or `y` (a [`BasinPlane`]).
        side: &'static str,
        /// The smallest displacement given.
        min: f64,
        /// The largest displacement given.
        max: f64,
    },
    /// No starts per side.
    #[error("--points must be ≥ 1")]
    NoPoints,
    /// A coordinate the scene does not have.
    #[error("{flag} = {given:?}: the scene has no such coordinate; the coordinates are {names}")]
    Coordinate {
        /// `--x` or `--y`.
        flag: &'static str,
        /// The name given.
        given: String,
        /// The scene's coordinates, comma-separated.
        names: String,
    },
    /// Both axes name one coordinate.
    #[error("--x and --y both name {0}: they must be two different coordinates")]
    SameCoordinate(String),
    /// The unit's default plane's ranges given with named axes.
    #[error(
        "--outer-min/--outer-max/--inner-min/--inner-max set the unit's default plane \
         (u:outer × u:inner); with --x/--y give the ranges as --x-min/--x-max/--y-min/--y-max"
    )]
    MixedPlanes,
    /// The unit's default plane's ranges given on a chain or a structure.
    #[error(
        "--outer-min/--outer-max/--inner-min/--inner-max set the unit's default plane; on a \
         chain or a structure name the axes with --x and --y (coordinates: {coordinates})"
    )]
    DefaultPlaneOnUnit {
        /// The scene's coordinates, comma-separated.
        coordinates: String,
    },
    /// An axis left unnamed on a chain or a structure, which has no default plane.
    #[error("{flag} is required on a chain or a structure: one of {coordinates}")]
    Unnamed {
        /// `--x` or `--y`.
        flag: &'static str,
        /// The scene's coordinates, comma-separated.
        coordinates: String,
    },
}

impl BasinGrid {
    /// The grid of `points × points` starts with outer displacements over `outer` and inner
    /// over `inner` (each `(min, max)`, m), as `rattle basins` takes them.
    ///
    /// # Errors
    /// [`BasinsError`] for no points, or a side not finite or with `min > max`.
    pub fn new(
        outer: (f64, f64),
        inner: (f64, f64),
        points: usize,
    ) -> Result<BasinGrid, BasinsError> {
        if points == 0 {
            return Err(BasinsError::NoPoints);
        }
        let axis = |side: &'static str, (min, max): (f64, f64)| {
            if min.is_finite() && max.is_finite() && min <= max {
                Ok(Axis::new(min, max, points))
            } else {
                Err(BasinsError::Side { side, min, max })
            }
        };
        Ok(BasinGrid {
            outer: axis("outer", outer)?,
            inner: axis("inner", inner)?,
        })
    }

    /// Number of starts.
    pub fn starts(&self) -> usize {
        self.outer.count * self.inner.count
    }
}

/// What a coordinate of a body measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// The displacement `u`, m: `u:NAME`.
    Displacement,
    /// The velocity `v`, m/s: `v:NAME`.
    Velocity,
}

/// One coordinate of a scene's state: a body's displacement (`u:NAME`) or velocity
/// (`v:NAME`). Bodies are named as the scene's outputs name them ([`body_names`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Coordinate {
    /// Displacement or velocity.
    pub quantity: Quantity,
    /// The body's name.
    pub body: String,
    /// The body's index among the model's degrees of freedom.
    pub index: usize,
}

impl std::fmt::Display for Coordinate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.quantity {
            Quantity::Displacement => write!(f, "u:{}", self.body),
            Quantity::Velocity => write!(f, "v:{}", self.body),
        }
    }
}

impl Coordinate {
    /// The coordinate `text` (`u:NAME` or `v:NAME`) among `bodies` (the scene's body names in
    /// the model's order, [`body_names`]); `flag` names the option in the error.
    ///
    /// # Errors
    /// [`BasinsError::Coordinate`] naming `flag` and listing every coordinate, when `text` is
    /// not one of them.
    pub fn parse(
        flag: &'static str,
        text: &str,
        bodies: &[String],
    ) -> Result<Coordinate, BasinsError> {
        let found = text.split_once(':').and_then(|(q, name)| {
            let quantity = match q {
                "u" => Quantity::Displacement,
                "v" => Quantity::Velocity,
                _ => return None,
            };
            let index = bodies.iter().position(|b| b == name)?;
            Some(Coordinate {
                quantity,
                body: name.to_owned(),
                index,
            })
        });
        found.ok_or_else(|| BasinsError::Coordinate {
            flag,
            given: text.to_owned(),
            names: coordinate_names(bodies).join(", "),
        })
    }

    /// The coordinate's entry in the model's state `(u_0 … u_{n−1}, v_0 … v_{n−1})` of `dofs`
    /// bodies.
    pub fn state_index(&self, dofs: usize) -> usize {
        match self.quantity {
            Quantity::Displacement => self.index,
            Quantity::Velocity => dofs + self.index,
        }
    }

    /// The column of a basins table holding the coordinate's start: `NAME_start` for a
    /// displacement, `NAME_velocity_start` for a velocity (the unit's default plane writes
    /// `outer_start` and `inner_start`).
    pub fn column(&self) -> String {
        match self.quantity {
            Quantity::Displacement => format!("{}_start", self.body),
            Quantity::Velocity => format!("{}_velocity_start", self.body),
        }
    }
}

/// The bodies of `scene` by name, in the order of the model's degrees of freedom: `outer`,
/// `inner` for the unit; `outer0`, `inner0`, `outer1`, … for a chain (cells numbered from 0
/// at the base, as a chain's outputs number them); the bodies' own names for a structure.
pub fn body_names(scene: &AnyScene) -> Vec<String> {
    match scene {
        AnyScene::Cells(scene) if scene.is_chain() => (0..scene.cell_count())
            .flat_map(|j| [format!("outer{j}"), format!("inner{j}")])
            .collect(),
        AnyScene::Cells(_) => vec!["outer".to_owned(), "inner".to_owned()],
        AnyScene::Structure(form) => form.structure.names.clone(),
    }
}

/// Every coordinate of the bodies `bodies`: the displacements `u:NAME`, then the velocities
/// `v:NAME`.
pub fn coordinate_names(bodies: &[String]) -> Vec<String> {
    let u = bodies.iter().map(|b| format!("u:{b}"));
    let v = bodies.iter().map(|b| format!("v:{b}"));
    u.chain(v).collect()
}

/// The plane of starts over two coordinates of a scene: `rattle basins --x … --y …`.
#[derive(Debug, Clone, PartialEq)]
pub struct BasinPlane {
    /// The first coordinate (`--x`), slowest in grid order.
    pub x: Coordinate,
    /// The second coordinate (`--y`), fastest in grid order.
    pub y: Coordinate,
    /// The axes' values: `outer` the first coordinate's, `inner` the second's.
    pub grid: BasinGrid,
}

impl BasinPlane {
    /// The `points × points` starts of `scene` with coordinate `x.0` over `x.1 = (min, max)`
    /// and `y.0` over `y.1`, as `rattle basins --x … --x-min … --x-max … --y …` takes them.
    ///
    /// # Errors
    /// [`BasinsError`] for no points, a side not finite or with `min > max` (naming `--x-min`
    /// or `--y-min`), a coordinate the scene does not have (naming `--x` or `--y` and listing
    /// the scene's coordinates), or one coordinate on both axes.
    pub fn new(
        scene: &AnyScene,
        x: (&str, (f64, f64)),
        y: (&str, (f64, f64)),
        points: usize,
    ) -> Result<BasinPlane, BasinsError> {
        let bodies = body_names(scene);
        let cx = Coordinate::parse("--x", x.0, &bodies)?;
        let cy = Coordinate::parse("--y", y.0, &bodies)?;
        if cx == cy {
            return Err(BasinsError::SameCoordinate(cx.to_string()));
        }
        let grid = BasinGrid::new(x.1, y.1, points).map_err(|e| match e {
            BasinsError::Side { side, min, max } => BasinsError::Side {
                side: if side == "outer" { "x" } else { "y" },
                min,
                max,
            },
            e => e,
        })?;
        Ok(BasinPlane { x: cx, y: cy, grid })
    }

    /// The unit's default plane over `grid`: `u:outer × u:inner`.
    pub fn unit(grid: BasinGrid) -> BasinPlane {
        let body = |name: &str, index| Coordinate {
            quantity: Quantity::Displacement,
            body: name.to_owned(),
            index,
        };
        BasinPlane {
            x: body("outer", 0),
            y: body("inner", 1),
            grid,
        }
    }

    /// The table's columns of the two starts ([`Coordinate::column`]).
    pub fn columns(&self) -> [String; 2] {
        [self.x.column(), self.y.column()]
    }

    /// The start at `(x, y)` on a model of `dofs` bodies: at rest, at time 0, with the two
    /// coordinates set.
    pub fn start(&self, dofs: usize, (x, y): (f64, f64)) -> Start {
        let mut start = Start::rest(dofs);
        start.state[self.x.state_index(dofs)] = x;
        start.state[self.y.state_index(dofs)] = y;
        start
    }
}

/// The starts `rattle basins` is asked for, as its options give them (`None`: an option left
/// out): the unit's default plane (`--outer-min` … `--inner-max`) or a plane over two named
/// coordinates of any scene (`--x`, `--y`, `--x-min` … `--y-max`). The command and the Python
/// package's `basins` both read their options through [`BasinAxes::starts`], so that they take
/// and refuse the same requests with the same messages.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BasinAxes {
    /// `--x`: the first coordinate, `u:NAME` or `v:NAME`.
    pub x: Option<String>,
    /// `--y`: the second coordinate.
    pub y: Option<String>,
    /// `--x-min` and `--x-max`: the first coordinate's range at the start.
    pub x_range: (Option<f64>, Option<f64>),
    /// `--y-min` and `--y-max`: the second coordinate's range at the start.
    pub y_range: (Option<f64>, Option<f64>),
    /// `--outer-min` and `--outer-max`: the unit's outer displacement at the start, m.
    pub outer: (Option<f64>, Option<f64>),
    /// `--inner-min` and `--inner-max`: the unit's inner displacement at the start, m.
    pub inner: (Option<f64>, Option<f64>),
    /// `--points`: starts per side.
    pub points: usize,
}

/// The starts of a basins run, as [`BasinAxes::starts`] reads them.
#[derive(Debug, Clone, PartialEq)]
pub enum BasinStarts {
    /// The unit's default plane, `u:outer × u:inner` ([`crate::api::basins`]).
    Unit(BasinGrid),
    /// A plane over two coordinates of a scene of any form ([`crate::api::plane_basins`]).
    Plane(BasinPlane),
}

impl BasinStarts {
    /// The grid's number of starts.
    pub fn starts(&self) -> usize {
        match self {
            BasinStarts::Unit(grid) => grid.starts(),
            BasinStarts::Plane(plane) => plane.grid.starts(),
        }
    }
}

impl BasinAxes {
    /// The default range of every side at the start: `[−2, 2]` (m, or m/s for a velocity).
    pub const DEFAULT_RANGE: (f64, f64) = (-2.0, 2.0);

    /// The starts these options ask for on `scene`. On the unit, without a named axis, its
    /// default plane over `outer` and `inner`; else the plane over `x` and `y` (on the unit
    /// they default to `u:outer` and `u:inner`, which give the default plane's table byte for
    /// byte). A side left out is [`BasinAxes::DEFAULT_RANGE`].
    ///
    /// # Errors
    /// [`BasinsError`], naming the command's options: the default plane's ranges with named
    /// axes ([`BasinsError::MixedPlanes`]) or on a chain or a structure
    /// ([`BasinsError::DefaultPlaneOnUnit`]), an axis left unnamed on a chain or a structure
    /// ([`BasinsError::Unnamed`]), and [`BasinGrid::new`]'s and [`BasinPlane::new`]'s.
    pub fn starts(&self, scene: &AnyScene) -> Result<BasinStarts, BasinsError> {
        let given = |(lo, hi): (Option<f64>, Option<f64>)| lo.is_some() || hi.is_some();
        let default_plane = given(self.outer) || given(self.inner);
        let named =
            self.x.is_some() || self.y.is_some() || given(self.x_range) || given(self.y_range);
        if default_plane && named {
            return Err(BasinsError::MixedPlanes);
        }
        let unit = matches!(scene, AnyScene::Cells(s) if !s.is_chain());
        let coordinates = || coordinate_names(&body_names(scene)).join(", ");
        if default_plane && !unit {
            return Err(BasinsError::DefaultPlaneOnUnit {
                coordinates: coordinates(),
            });
        }
        let (lo, hi) = Self::DEFAULT_RANGE;
        let range = |(min, max): (Option<f64>, Option<f64>)| (min.unwrap_or(lo), max.unwrap_or(hi));
        if unit && !named {
            let grid = BasinGrid::new(range(self.outer), range(self.inner), self.points)?;
            return Ok(BasinStarts::Unit(grid));
        }
        let axis = |flag: &'static str, given: &Option<String>, default: &str| match (given, unit) {
            (Some(name), _) => Ok(name.clone()),
            (None, true) => Ok(default.to_owned()),
            (None, false) => Err(BasinsError::Unnamed {
                flag,
                coordinates: coordinates(),
            }),
        };
        let x = axis("--x", &self.x, "u:outer")?;
        let y = axis("--y", &self.y, "u:inner")?;
        let plane = BasinPlane::new(
            scene,
            (&x, range(self.x_range)),
            (&y, range(self.y_range)),
            self.points,
        )?;
        Ok(BasinStarts::Plane(plane))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    #[test]
    fn the_axes_are_read_as_the_command_reads_its_flags() {
        let unit = AnyScene::Cells(Scene::paper());
        let axes = |f: &dyn Fn(&mut BasinAxes)| {
            let mut a = BasinAxes {
                points: 3,
                ..BasinAxes::default()
            };
            f(&mut a);
            a
        };
        // The unit without named axes: its default plane, each side ±2 unless given.
        let Ok(BasinStarts::Unit(grid)) = axes(&|a| a.outer = (Some(-1.0), None)).starts(&unit)
        else {
            panic!("the unit's default plane")
        };
        assert_eq!((grid.outer.min, grid.outer.max), (-1.0, 2.0));
        assert_eq!((grid.inner.min, grid.inner.max), BasinAxes::DEFAULT_RANGE);
        // A named axis: a plane, the other axis the unit's default.
        let Ok(BasinStarts::Plane(plane)) = axes(&|a| a.y = Some("v:inner".into())).starts(&unit)
        else {
            panic!("a plane")
        };
        assert_eq!(plane.columns(), ["outer_start", "inner_velocity_start"]);
        assert_eq!(
            axes(&|a| {
                a.inner = (None, Some(1.0));
                a.x_range = (Some(0.0), None);
            })
            .starts(&unit),
            Err(BasinsError::MixedPlanes)
        );
        // A chain: no default plane, every axis named.
        let chain = AnyScene::Cells(Scene {
            cells: Some(2),
            ..Scene::paper()
        });
        let Err(BasinsError::Unnamed { flag, coordinates }) =
            axes(&|a| a.x = Some("u:outer1".into())).starts(&chain)
        else {
            panic!("--y is required on a chain")
        };
        assert_eq!(flag, "--y");
        assert!(
            coordinates.starts_with("u:outer0, u:inner0, u:outer1"),
            "{coordinates}"
        );
        assert!(matches!(
            axes(&|a| a.outer = (Some(-1.0), Some(1.0))).starts(&chain),
            Err(BasinsError::DefaultPlaneOnUnit { .. })
        ));
    }
}
