//! Basins of attraction: a grid of starts over two coordinates of a scene, each run to its
//! steady state and coloured by the attractor it reaches.
//!
//! The plane of starts is spanned by two coordinates of the scene ([`Coordinate`]: a body's
//! displacement `u:NAME` or velocity `v:NAME`); every other coordinate starts at rest, at time 0
//! (the base, or the forces, at phase 0). The unit's default plane is its outer and inner
//! displacements ([`BasinGrid`], `u:outer × u:inner`): the plane a unit meets when released from
//! a displaced position.
//!
//! On the unit an attractor is identified by its impact signature (from the sides of the final
//! cycle's impacts, no Newton polish), its least period and its amplitude `X_o`, to
//! [`BASIN_AMPLITUDE_TOLERANCE`] ([`Attractor::Periodic`]). On a chain or a structure it is
//! identified by each stop's signature, the least period and every body's amplitude, to the
//! same tolerance relative to the largest ([`Attractor::Motion`]); a floating body that no
//! impact of the cycle touches has no amplitude there (it rests anywhere the stops leave room
//! for, a family). The motions that do not repeat within the cap form one class, as do those
//! without dissipation and those that stick (by status). Attractors are numbered by first
//! appearance in grid order (the second coordinate fastest), so the grid and its numbers do not
//! depend on the number of threads.
//!
//! A start converging slowly on a periodic attractor would run to the cap before it repeats
//! to the periodicity tolerance; so the periodic attractors of a coarse reference grid
//! ([`BASIN_REFERENCE_STRIDE`]) are found first, and a start is attributed to one of them as
//! soon as its stroboscopic state comes within [`BASIN_PROXIMITY`] of that attractor's, checked
//! at every section `t = kT` by the simulator's section watch, which ends the run there. A
//! family (a motion with a floating body untouched by impacts) is no reference: being near one
//! of its members does not say which member, or whether an impact comes.

use crate::output::{
    finite, number_list, table_row, CsvWriter, Format, Header, JsonLinesWriter, JsonWriter, Row,
    TableWriter,
};
use crate::runs::axis::Axis;
use crate::runs::map::MAP_PERIODICITY_TOLERANCE;
use crate::runs::parallel::{parallel_map, Grain, Progress};
use crate::runs::shard::{check_cover, Shard};
use crate::scene::simulator::{run_watched, SimulatedPoint};
use crate::scene::structure::Structure;
use crate::scene::{AnyScene, Scene};
use nalgebra::DVector;
use rattle_analytic::Signature;
use rattle_event_driven::{
    simulate_watched, Model, SimulationOptions, Start, Status, SteadyState, Stop,
};
use serde::ser::{SerializeMap, SerializeTuple};
use serde::{Deserialize, Serialize, Serializer};
use std::io::Write;
use thiserror::Error;

/// Periods each start runs at most: a start that has not repeated by then is `not periodic`.
/// From rest the paper's unit at the coexistence frequency ω = 1.86 settles within 150–212
/// periods (to 1e-5 and 1e-9); twice that leaves slower starts a margin while bounding the
/// cost of the motions that never repeat.
pub const BASIN_MAX_PERIODS: u64 = 400;

/// Two periodic motions of one signature are one attractor when their amplitudes `X_o`
/// differ by less than this, relative to the larger: far above the amplitude's error at the
/// periodicity tolerance ([`MAP_PERIODICITY_TOLERANCE`] relative to the gap), far below the
/// difference between coexisting orbits (tens of percent on the paper's unit).
pub const BASIN_AMPLITUDE_TOLERANCE: f64 = 1e-3;

/// The simulator's options for basins: the map's periodicity tolerance, the
/// [`BASIN_MAX_PERIODS`] cap, no Newton polish.
pub fn basin_options() -> SimulationOptions {
    SimulationOptions {
        periodicity_tolerance: MAP_PERIODICITY_TOLERANCE,
        max_periods: BASIN_MAX_PERIODS,
        polish: false,
        ..SimulationOptions::default()
    }
}

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

/// The scene a basins grid runs on, with what its runs need.
enum System<'a> {
    /// A single unit: the unit's attractors ([`Attractor::Periodic`]).
    Unit(&'a Scene),
    /// A chain of cells.
    Chain(&'a Scene),
    /// A structure and its simulator model at the frequency (`None`: the model was refused,
    /// every start fails).
    Structure(&'a Structure, Option<Box<Model>>),
}

impl<'a> System<'a> {
    fn of(scene: &'a AnyScene, omega: f64) -> System<'a> {
        match scene {
            AnyScene::Cells(s) if s.is_chain() => System::Chain(s),
            AnyScene::Cells(s) => System::Unit(s),
            AnyScene::Structure(form) => System::Structure(
                &form.structure,
                form.structure.event_model(omega).ok().map(Box::new),
            ),
        }
    }

    fn dofs(&self) -> usize {
        match self {
            System::Unit(s) | System::Chain(s) => 2 * s.cell_count(),
            System::Structure(s, _) => s.dofs(),
        }
    }

    /// The length the attribution distance is relative to, at least: the unit's or chain's
    /// gap, a structure's smallest stop distance, else 1.
    fn gap(&self) -> f64 {
        match self {
            System::Unit(s) | System::Chain(s) => s.gap().unwrap_or(1.0),
            System::Structure(s, _) => {
                let smallest = s
                    .stops
                    .iter()
                    .flat_map(|stop| [stop.gap_plus, stop.gap_minus])
                    .filter(|g| g.is_finite())
                    .fold(f64::INFINITY, f64::min);
                if smallest.is_finite() {
                    smallest
                } else {
                    1.0
                }
            }
        }
    }

    /// Whether `start` lies outside a structure's stop clearance (never for the unit and
    /// chain forms, whose starts run as given).
    fn outside(&self, start: &Start) -> bool {
        let System::Structure(s, _) = self else {
            return false;
        };
        let u = |end: Option<usize>| end.map_or(0.0, |j| start.state[j]);
        s.stops.iter().any(|stop| {
            let r = u(stop.plus) - u(stop.minus);
            r > stop.gap_plus || r < -stop.gap_minus
        })
    }

    /// One run from `start`, watched: the steady state and the outer (observed) amplitude,
    /// or `None` when the simulator fails; the attractor it is.
    fn run(
        &self,
        omega: f64,
        start: &Start,
        options: &SimulationOptions,
        watch: &mut dyn FnMut(u64, &DVector<f64>) -> bool,
    ) -> Option<(Attractor, f64, SteadyState)> {
        match self {
            System::Unit(scene) => {
                let sim = run_watched(scene, omega, start, options, watch).ok()?;
                Some((Attractor::of(&sim), sim.outer_amplitude, sim.steady))
            }
            System::Chain(scene) => {
                let sim = run_watched(scene, omega, start, options, watch).ok()?;
                let attractor = Attractor::motion(&sim.steady, scene.pair_count(), |_| true);
                Some((attractor, sim.outer_amplitude, sim.steady))
            }
            System::Structure(structure, model) => {
                let steady =
                    simulate_watched(model.as_deref()?, omega, start, options, watch).ok()?;
                let outer = steady
                    .amplitudes
                    .get(structure.observe)
                    .copied()
                    .unwrap_or(f64::NAN);
                // The floating groups some impact of the cycle touches.
                let touched: Vec<usize> = steady
                    .cycle_impacts
                    .iter()
                    .flat_map(|i| {
                        let stop = structure.stops[i.pair];
                        [stop.plus, stop.minus]
                    })
                    .flatten()
                    .filter_map(|j| structure.floating[j])
                    .collect();
                let held = |j: usize| structure.floating[j].is_none_or(|g| touched.contains(&g));
                let attractor = Attractor::motion(&steady, structure.stops.len(), held);
                Some((attractor, outer, steady))
            }
        }
    }
}

/// The kind of motion a start ends on (as JSON in a part's header, [`write_basins`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Attractor {
    /// A periodic motion: its canonical signature (`None` without impacts) and `X_o`, m.
    Periodic {
        /// The canonical impact signature, `None` without impacts.
        signature: Option<String>,
        /// Least period, forcing periods.
        period: u32,
        /// `X_o = max|u_o|` over the cycle, m.
        outer_amplitude: f64,
    },
    /// A periodic motion of a chain or a structure: each stop's signature and every body's
    /// amplitude.
    Motion {
        /// Each stop's canonical impact signature over the cycle, in stop order: `""` for a
        /// stop without impacts, `None` for impacts beyond what a signature holds.
        signatures: Vec<Option<String>>,
        /// Least period, forcing periods.
        period: u32,
        /// Every body's amplitude `max|u|` over the cycle, m, in body order; `None` for a
        /// floating body that no impact of the cycle touches (it rests anywhere the stops
        /// leave room for).
        amplitudes: Vec<Option<f64>>,
    },
    /// Sticking in the final cycle.
    Sticking,
    /// Not periodic within the cap.
    NotPeriodic,
    /// No dissipation: the transient persists.
    NoDissipation,
    /// The simulation failed.
    Failed,
    /// The start lies outside a stop's clearance of a structure: not run.
    OutsideClearance,
}

impl Attractor {
    /// The attractor `sim` reached.
    pub fn of(sim: &SimulatedPoint) -> Attractor {
        match sim.steady.status {
            Status::NoDissipation => Attractor::NoDissipation,
            Status::NonPeriodic => Attractor::NotPeriodic,
            Status::Periodic if sim.steady.sticking => Attractor::Sticking,
            Status::Periodic => {
                let period = sim.steady.period.unwrap_or(1);
                let sides: Vec<i8> = sim.steady.cycle_impacts.iter().map(|i| i.side).collect();
                Attractor::Periodic {
                    signature: Signature::from_cycle(&sides, period)
                        .ok()
                        .map(|s| s.to_string()),
                    period,
                    outer_amplitude: sim.outer_amplitude,
                }
            }
        }
    }

    /// The attractor a chain's or a structure's `steady` state of `pairs` stops is: by status
    /// as [`Attractor::of`], a periodic motion by each stop's signature, its least period and
    /// every body's amplitude, `None` for each body `j` not `held(j)`.
    pub fn motion(steady: &SteadyState, pairs: usize, held: impl Fn(usize) -> bool) -> Attractor {
        match steady.status {
            Status::NoDissipation => Attractor::NoDissipation,
            Status::NonPeriodic => Attractor::NotPeriodic,
            Status::Periodic if steady.sticking => Attractor::Sticking,
            Status::Periodic => {
                let period = steady.period.unwrap_or(1);
                let signatures = (0..pairs)
                    .map(|pair| {
                        let sides: Vec<i8> = steady
                            .cycle_impacts
                            .iter()
                            .filter(|i| i.pair == pair)
                            .map(|i| i.side)
                            .collect();
                        if sides.is_empty() {
                            Some(String::new())
                        } else {
                            Signature::from_cycle(&sides, period)
                                .ok()
                                .map(|s| s.to_string())
                        }
                    })
                    .collect();
                let amplitudes = steady
                    .amplitudes
                    .iter()
                    .enumerate()
                    .map(|(j, &a)| held(j).then_some(a))
                    .collect();
                Attractor::Motion {
                    signatures,
                    period,
                    amplitudes,
                }
            }
        }
    }

    /// Every body's amplitude of a [`Attractor::Motion`] (empty for the other kinds).
    pub fn body_amplitudes(&self) -> &[Option<f64>] {
        match self {
            Attractor::Motion { amplitudes, .. } => amplitudes,
            _ => &[],
        }
    }

    /// Whether the attractor is a family: a motion with a floating body no impact touches.
    pub fn is_family(&self) -> bool {
        self.body_amplitudes().iter().any(Option::is_none)
    }

    /// Whether the attractor is a periodic motion ([`Attractor::Periodic`] or
    /// [`Attractor::Motion`]).
    pub fn is_periodic(&self) -> bool {
        matches!(self, Attractor::Periodic { .. } | Attractor::Motion { .. })
    }

    /// Whether `self` and `other` are one attractor (same kind; for periodic motions the same
    /// signatures and period, and amplitudes within [`BASIN_AMPLITUDE_TOLERANCE`]: relative
    /// to the larger `X_o` on the unit, to the largest of every body's on a chain or a
    /// structure, where a body without amplitude matches only one without).
    pub fn same(&self, other: &Attractor) -> bool {
        match (self, other) {
            (
                Attractor::Motion {
                    signatures: a,
                    period: p,
                    amplitudes: x,
                },
                Attractor::Motion {
                    signatures: b,
                    period: q,
                    amplitudes: y,
                },
            ) => {
                let scale = x
                    .iter()
                    .chain(y)
                    .flatten()
                    .fold(0.0_f64, |m, v| m.max(v.abs()));
                a == b
                    && p == q
                    && x.len() == y.len()
                    && x.iter().zip(y).all(|(u, v)| match (u, v) {
                        (Some(u), Some(v)) => (u - v).abs() <= BASIN_AMPLITUDE_TOLERANCE * scale,
                        (None, None) => true,
                        _ => false,
                    })
            }
            (
                Attractor::Periodic {
                    signature: a,
                    period: p,
                    outer_amplitude: x,
                },
                Attractor::Periodic {
                    signature: b,
                    period: q,
                    outer_amplitude: y,
                },
            ) => {
                a == b
                    && p == q
                    && (x - y).abs() <= BASIN_AMPLITUDE_TOLERANCE * x.abs().max(y.abs())
            }
            _ => self == other,
        }
    }

    /// Words for a legend or a table.
    pub fn words(&self) -> String {
        match self {
            Attractor::Periodic {
                signature,
                period,
                outer_amplitude,
            } => format!(
                "{} (p = {period}), X_o = {outer_amplitude:.4}",
                signature.as_deref().unwrap_or("no impact")
            ),
            Attractor::Motion {
                signatures,
                period,
                amplitudes,
            } => {
                let impacts = if signatures.iter().all(|s| s.as_deref() == Some("")) {
                    "no impact".to_owned()
                } else if signatures.len() == 1 {
                    signatures[0].clone().unwrap_or_else(|| "?".into())
                } else {
                    signatures
                        .iter()
                        .enumerate()
                        .map(|(k, s)| match s.as_deref() {
                            Some("") => format!("{k}: none"),
                            Some(s) => format!("{k}: {s}"),
                            None => format!("{k}: ?"),
                        })
                        .collect::<Vec<_>>()
                        .join("; ")
                };
                let amplitudes = amplitudes
                    .iter()
                    .map(|a| a.map_or_else(|| "free".to_owned(), |a| format!("{a:.4}")))
                    .collect::<Vec<_>>()
                    .join(", ");
                format!("{impacts} (p = {period}), amplitudes [{amplitudes}]")
            }
            Attractor::Sticking => "sticking".into(),
            Attractor::NotPeriodic => "not periodic within the cap".into(),
            Attractor::NoDissipation => "no dissipation".into(),
            Attractor::Failed => "simulation failed".into(),
            Attractor::OutsideClearance => "start outside a stop's clearance (not run)".into(),
        }
    }
}

/// One start of the grid and where it went.
#[derive(Debug, Clone, PartialEq)]
pub struct BasinCell {
    /// The first coordinate at the start: the outer displacement on the default plane, m.
    pub outer: f64,
    /// The second coordinate at the start: the inner displacement on the default plane, m.
    pub inner: f64,
    /// Index into [`Basins::attractors`].
    pub attractor: usize,
    /// `X_o` of the motion reached, m (NaN on failure).
    pub outer_amplitude: f64,
    /// Periods run.
    pub periods_run: u64,
}

/// The basins of one frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct Basins {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The grid of starts: the values of the plane's two axes (`plane.grid`).
    pub grid: BasinGrid,
    /// The plane of starts: its two coordinates and their values.
    pub plane: BasinPlane,
    /// The attractors, numbered by first appearance in grid order.
    pub attractors: Vec<Attractor>,
    /// Starts reaching each attractor (same order).
    pub counts: Vec<usize>,
    /// The cells, the first coordinate slowest, the second fastest.
    pub cells: Vec<BasinCell>,
    /// Every body's amplitude of the motion each cell reached, m (same order as `cells`; as
    /// [`Attractor::body_amplitudes`]: empty on the unit and for motions that are not
    /// periodic).
    pub body_amplitudes: Vec<Vec<Option<f64>>>,
}

/// The start at rest with displacements `outer`, `inner` at time 0.
pub fn start_at_rest(outer: f64, inner: f64) -> Start {
    Start {
        state: DVector::from_column_slice(&[outer, inner, 0.0, 0.0]),
        time: 0.0,
    }
}

/// A start belongs to a reference periodic attractor once its stroboscopic state (at `t = kT`)
/// lies within this distance of one of the attractor's, relative to the larger of that state's
/// norm and the gap, unless the references lie closer together than that (then a third of their
/// smallest separation).
///
/// Measured on the undamped paper unit at ω = 1.9 rad/s (`rattle basins --omega 1.9`, ±1.5 m,
/// 100 × 100 starts), where the stable `++--` orbit attracts slowly (λ₁ = −0.008 /s, 2.6 % per
/// period) and a `+-` orbit coexists: at 1e-2, 31 starts stayed `not periodic` within the
/// 400-period cap (177 periods per start on average); at 3e-2, 17 of them were attributed to
/// `++--` (137 periods per start); at 1e-1, 26 (89 periods per start), and every one of the 26,
/// run on alone for up to 20 000 periods, repeats on `++--` after 677–757 periods. No start
/// changed between the two periodic attractors at any of the three values.
pub const BASIN_PROXIMITY: f64 = 1e-1;

/// The reference grid takes every this-many-th start on each axis (both ends included): 400
/// of a 200 × 200 grid, run to the cap without references.
pub const BASIN_REFERENCE_STRIDE: usize = 10;

/// The attribution distance for `references`: [`BASIN_PROXIMITY`], or a third of the smallest
/// relative distance between the stroboscopic states of two different references if that is
/// smaller, so that no state lies within it of two attractors.
fn proximity(references: &[Reference], gap: f64) -> f64 {
    let mut closest = f64::INFINITY;
    for (k, a) in references.iter().enumerate() {
        for b in &references[k + 1..] {
            for s in &a.states {
                for t in &b.states {
                    let scale = s.norm().max(t.norm()).max(gap);
                    closest = closest.min((s - t).norm() / scale);
                }
            }
        }
    }
    BASIN_PROXIMITY.min(closest / 3.0)
}

/// A periodic attractor reached from the reference grid, with its stroboscopic states.
#[derive(Debug, Clone)]
struct Reference {
    attractor: Attractor,
    outer_amplitude: f64,
    states: Vec<DVector<f64>>,
}

/// Where `start` goes on `system` at `omega`: the attractor, `X_o`, periods run, and for a
/// periodic motion its stroboscopic states. One run up to the options' cap, watched at every
/// section `t = kT` before it is decided: a start whose state lies within `proximity` (relative,
/// see [`BASIN_PROXIMITY`]) of a reference's belongs to that attractor, and the run ends there.
/// A structure's start outside a stop's clearance is not run.
fn reach(
    system: &System<'_>,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
    references: &[Reference],
    proximity: f64,
) -> (Attractor, f64, u64, Vec<DVector<f64>>) {
    if system.outside(start) {
        return (Attractor::OutsideClearance, f64::NAN, 0, Vec::new());
    }
    let gap = system.gap();
    let mut near: Option<&Reference> = None;
    let mut watch = |_: u64, x: &DVector<f64>| {
        near = references.iter().find(|r| {
            r.states
                .iter()
                .any(|s| x.metric_distance(s) <= proximity * s.norm().max(gap))
        });
        near.is_some()
    };
    let Some((attractor, amplitude, steady)) = system.run(omega, start, options, &mut watch) else {
        return (Attractor::Failed, f64::NAN, 0, Vec::new());
    };
    let periods = steady.periods_run;
    match near {
        Some(r) if steady.stopped == Stop::Watched => {
            (r.attractor.clone(), r.outer_amplitude, periods, Vec::new())
        }
        _ => (attractor, amplitude, periods, steady.stroboscopic),
    }
}

/// Where `start` goes on `scene` at `omega`, run to the options' cap (no references): the
/// attractor, `X_o` and periods run.
pub fn destination(
    scene: &Scene,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
) -> (Attractor, f64, u64) {
    let system = if scene.is_chain() {
        System::Chain(scene)
    } else {
        System::Unit(scene)
    };
    let (attractor, amplitude, periods, _) = reach(&system, omega, start, options, &[], 0.0);
    (attractor, amplitude, periods)
}

/// Where `start` goes on a scene of any form at `omega`, run to the options' cap (no
/// references): the attractor, the outer (observed) amplitude and periods run. A structure's
/// start outside a stop's clearance is [`Attractor::OutsideClearance`], not run.
pub fn destination_of(
    scene: &AnyScene,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
) -> (Attractor, f64, u64) {
    let system = System::of(scene, omega);
    let (attractor, amplitude, periods, _) = reach(&system, omega, start, options, &[], 0.0);
    (attractor, amplitude, periods)
}

/// The starts of `grid`, the first axis slowest, the second fastest.
fn starts(grid: &BasinGrid) -> Vec<(f64, f64)> {
    let inner = grid.inner.values();
    grid.outer
        .values()
        .into_iter()
        .flat_map(|o| inner.iter().map(move |&i| (o, i)))
        .collect()
}

/// The periodic attractors of the coarse reference subgrid of `plane` (every
/// [`BASIN_REFERENCE_STRIDE`]-th start on each axis, both ends included), run without
/// references, in grid order (so they do not depend on the number of threads), and the
/// attribution distance for them ([`proximity`]). Families are no references.
fn references(
    system: &System<'_>,
    omega: f64,
    plane: &BasinPlane,
    options: &SimulationOptions,
) -> (Vec<Reference>, f64) {
    let (outer, inner) = (plane.grid.outer.values(), plane.grid.inner.values());
    let every = |n: usize| -> Vec<usize> {
        let mut k: Vec<usize> = (0..n).step_by(BASIN_REFERENCE_STRIDE).collect();
        if n > 0 && k.last() != Some(&(n - 1)) {
            k.push(n - 1);
        }
        k
    };
    let coarse: Vec<(f64, f64)> = every(outer.len())
        .into_iter()
        .flat_map(|a| every(inner.len()).into_iter().map(move |b| (a, b)))
        .map(|(a, b)| (outer[a], inner[b]))
        .collect();
    let dofs = system.dofs();
    let mut references: Vec<Reference> = Vec::new();
    for (attractor, outer_amplitude, _, states) in
        parallel_map(&coarse, Grain::Uneven, &Progress::hidden(), |&xy| {
            reach(system, omega, &plane.start(dofs, xy), options, &[], 0.0)
        })
    {
        let periodic = attractor.is_periodic() && !attractor.is_family();
        if periodic && !references.iter().any(|r| r.attractor.same(&attractor)) {
            references.push(Reference {
                attractor,
                outer_amplitude,
                states,
            });
        }
    }
    let within = proximity(&references, system.gap());
    (references, within)
}

/// Where one start went, before the attractors are numbered.
#[derive(Debug, Clone, PartialEq)]
pub struct Reached {
    /// The first coordinate at the start (the outer displacement on the default plane).
    pub outer: f64,
    /// The second coordinate at the start (the inner displacement on the default plane).
    pub inner: f64,
    /// The attractor reached; a periodic one with this start's own amplitudes.
    pub attractor: Attractor,
    /// `X_o` of the motion reached (a structure's observed body's amplitude), m (NaN on
    /// failure).
    pub outer_amplitude: f64,
    /// Periods run.
    pub periods_run: u64,
}

/// Where each of `starts` goes, in parallel, in order.
fn reach_all(
    system: &System<'_>,
    omega: f64,
    plane: &BasinPlane,
    starts: &[(f64, f64)],
    (references, within): &(Vec<Reference>, f64),
    options: &SimulationOptions,
    progress: &Progress,
) -> Vec<Reached> {
    let dofs = system.dofs();
    parallel_map(starts, Grain::Uneven, progress, |&(outer, inner)| {
        let (attractor, outer_amplitude, periods_run, _) = reach(
            system,
            omega,
            &plane.start(dofs, (outer, inner)),
            options,
            references,
            *within,
        );
        Reached {
            outer,
            inner,
            attractor,
            outer_amplitude,
            periods_run,
        }
    })
}

/// Numbers the attractors of `reached` (in order) by first appearance: each start takes the
/// first attractor so far that is [`Attractor::same`] as its own, or a new one. Returns the
/// attractors, the starts reaching each, and the cells.
pub fn number(reached: Vec<Reached>) -> (Vec<Attractor>, Vec<usize>, Vec<BasinCell>) {
    let mut attractors: Vec<Attractor> = Vec::new();
    let mut counts: Vec<usize> = Vec::new();
    let cells = reached
        .into_iter()
        .map(|r| {
            let index = match attractors.iter().position(|a| a.same(&r.attractor)) {
                Some(k) => k,
                None => {
                    attractors.push(r.attractor);
                    counts.push(0);
                    attractors.len() - 1
                }
            };
            counts[index] += 1;
            BasinCell {
                outer: r.outer,
                inner: r.inner,
                attractor: index,
                outer_amplitude: r.outer_amplitude,
                periods_run: r.periods_run,
            }
        })
        .collect();
    (attractors, counts, cells)
}

/// The basins of the unit or chain `scene` at `omega` over `grid` (the unit's outer and inner
/// displacements), in parallel, deterministic.
pub fn basins(
    scene: &Scene,
    omega: f64,
    grid: BasinGrid,
    options: &SimulationOptions,
    progress: &Progress,
) -> Basins {
    basins_part(scene, omega, grid, options, None, progress)
}

/// The starts of one part of the unit's basins over its outer and inner displacements (all of
/// them for `None`): [`plane_basins_part`] on the default plane ([`BasinPlane::unit`]).
pub fn basins_part(
    scene: &Scene,
    omega: f64,
    grid: BasinGrid,
    options: &SimulationOptions,
    shard: Option<Shard>,
    progress: &Progress,
) -> Basins {
    let system = if scene.is_chain() {
        System::Chain(scene)
    } else {
        System::Unit(scene)
    };
    part_of(
        &system,
        omega,
        &BasinPlane::unit(grid),
        options,
        shard,
        progress,
    )
}

/// The starts of one part of the basins of `scene` (any form) over `plane` (all of them for
/// `None`): part `K` of `N` is block `K` of `N` nearly equal contiguous blocks of the starts in
/// grid order ([`Shard::range`]), each start run as in the whole grid (every part finds the
/// same references on the whole grid's coarse subgrid), so that its cells are the whole
/// grid's bit for bit. The attractors are numbered within the part; [`merge_parts`] numbers
/// them over the whole grid.
pub fn plane_basins_part(
    scene: &AnyScene,
    omega: f64,
    plane: &BasinPlane,
    options: &SimulationOptions,
    shard: Option<Shard>,
    progress: &Progress,
) -> Basins {
    part_of(
        &System::of(scene, omega),
        omega,
        plane,
        options,
        shard,
        progress,
    )
}

fn part_of(
    system: &System<'_>,
    omega: f64,
    plane: &BasinPlane,
    options: &SimulationOptions,
    shard: Option<Shard>,
    progress: &Progress,
) -> Basins {
    let all = starts(&plane.grid);
    let range = shard.map_or(0..all.len(), |s| s.range(all.len()));
    // A part without starts needs no references.
    let references = if range.is_empty() {
        (Vec::new(), BASIN_PROXIMITY)
    } else {
        references(system, omega, plane, options)
    };
    let reached = reach_all(
        system,
        omega,
        plane,
        &all[range],
        &references,
        options,
        progress,
    );
    let body_amplitudes = reached
        .iter()
        .map(|r| r.attractor.body_amplitudes().to_vec())
        .collect();
    let (attractors, counts, cells) = number(reached);
    Basins {
        omega,
        grid: plane.grid,
        plane: plane.clone(),
        attractors,
        counts,
        cells,
        body_amplitudes,
    }
}

table_row! {
    /// One start of a basins grid.
    pub struct BasinRow {
        /// Outer displacement at the start, m.
        pub outer_start: Option<f64>,
        /// Inner displacement at the start, m.
        pub inner_start: Option<f64>,
        /// The attractor's number (first appearance in grid order).
        pub attractor: usize,
        /// The attractor in words.
        pub attractor_words: String,
        /// `X_o` of the motion reached, m.
        pub outer_amplitude: Option<f64>,
        /// Forcing periods run.
        pub periods_run: u64,
    }
}

/// The rows of `cells` numbered into `attractors`, in grid order.
pub fn rows<'a>(
    attractors: &'a [Attractor],
    cells: &'a [BasinCell],
) -> impl Iterator<Item = BasinRow> + 'a {
    cells.iter().map(|c| BasinRow {
        outer_start: finite(c.outer),
        inner_start: finite(c.inner),
        attractor: c.attractor,
        attractor_words: attractors[c.attractor].words(),
        outer_amplitude: finite(c.outer_amplitude),
        periods_run: c.periods_run,
    })
}

/// The header of a basins JSON table: the scene and the frequency.
pub fn header(scene: &Scene, omega: f64) -> Header {
    let mut h = Header::default();
    h.push("scene", scene);
    h.push("omega", &omega);
    h
}

/// The header of a basins JSON table on a scene of any form: the scene as written and the
/// frequency.
fn any_header(scene: &AnyScene, omega: f64) -> Header {
    match scene {
        AnyScene::Cells(scene) => header(scene, omega),
        AnyScene::Structure(form) => {
            let mut h = Header::default();
            h.push("scene", &form.scene);
            h.push("omega", &omega);
            h
        }
    }
}

/// The column of every body's amplitude in a chain's or a structure's basins table.
pub const BODY_AMPLITUDES: &str = "body_amplitudes";

/// One row of a basins table with the plane's columns: a [`BasinRow`] whose first two cells
/// are named by the plane's coordinates, and on a chain or a structure every body's amplitude
/// as a list cell ([`number_list`], an empty element for a body without amplitude).
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneRow {
    /// The columns of the two starts ([`BasinPlane::columns`]).
    pub columns: [String; 2],
    /// The row's cells.
    pub row: BasinRow,
    /// The `body_amplitudes` cell; `None` on the unit, whose table has no such column.
    pub body_amplitudes: Option<Option<String>>,
    /// Written as a JSON object (JSON and JSON Lines), else as a CSV record.
    pub keyed: bool,
}

impl Serialize for PlaneRow {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let r = &self.row;
        let extra = usize::from(self.body_amplitudes.is_some());
        if self.keyed {
            let mut m = serializer.serialize_map(Some(6 + extra))?;
            m.serialize_entry(&self.columns[0], &r.outer_start)?;
            m.serialize_entry(&self.columns[1], &r.inner_start)?;
            m.serialize_entry("attractor", &r.attractor)?;
            m.serialize_entry("attractor_words", &r.attractor_words)?;
            m.serialize_entry("outer_amplitude", &r.outer_amplitude)?;
            m.serialize_entry("periods_run", &r.periods_run)?;
            if let Some(b) = &self.body_amplitudes {
                m.serialize_entry(BODY_AMPLITUDES, b)?;
            }
            m.end()
        } else {
            let mut t = serializer.serialize_tuple(6 + extra)?;
            t.serialize_element(&r.outer_start)?;
            t.serialize_element(&r.inner_start)?;
            t.serialize_element(&r.attractor)?;
            t.serialize_element(&r.attractor_words)?;
            t.serialize_element(&r.outer_amplitude)?;
            t.serialize_element(&r.periods_run)?;
            if let Some(b) = &self.body_amplitudes {
                t.serialize_element(b)?;
            }
            t.end()
        }
    }
}

impl Row for PlaneRow {
    /// The default plane's columns; a plane's table names its first two by its coordinates
    /// and adds [`BODY_AMPLITUDES`] on a chain or a structure ([`PlaneRow::columns`]).
    const COLUMNS: &'static [&'static str] = BasinRow::COLUMNS;
}

/// The columns of a basins table: the two starts', then [`BasinRow`]'s others, then
/// [`BODY_AMPLITUDES`] when `bodies`.
fn table_columns(starts: &[String; 2], bodies: bool) -> Vec<String> {
    let mut columns: Vec<String> = starts.to_vec();
    columns.extend(BasinRow::COLUMNS[2..].iter().map(|c| (*c).to_owned()));
    if bodies {
        columns.push(BODY_AMPLITUDES.to_owned());
    }
    columns
}

/// A `body_amplitudes` cell: the list, an empty element for a body without amplitude.
fn amplitudes_cell(amplitudes: &[Option<f64>]) -> Option<String> {
    let values: Vec<f64> = amplitudes.iter().map(|a| a.unwrap_or(f64::NAN)).collect();
    number_list(&values)
}

/// The rows of a plane's table: `cells` numbered into `attractors` with `body_amplitudes`
/// (`None`: the unit's table, without that column).
fn plane_rows<'a>(
    columns: &'a [String; 2],
    attractors: &'a [Attractor],
    cells: &'a [BasinCell],
    body_amplitudes: Option<&'a [Vec<Option<f64>>]>,
    keyed: bool,
) -> impl Iterator<Item = PlaneRow> + 'a {
    rows(attractors, cells)
        .enumerate()
        .map(move |(k, row)| PlaneRow {
            columns: columns.clone(),
            row,
            body_amplitudes: body_amplitudes.map(|b| amplitudes_cell(&b[k])),
            keyed,
        })
}

/// A table writer of `format` for a plane's rows with `columns`.
fn plane_writer<'w, W: Write + 'w>(
    format: Format,
    out: W,
    header: &Header,
    preamble: Option<&str>,
    columns: &[String],
) -> std::io::Result<Box<dyn TableWriter<PlaneRow> + 'w>> {
    let names: Vec<&str> = columns.iter().map(String::as_str).collect();
    Ok(match format {
        Format::Csv => Box::new(CsvWriter::new(out, preamble, &names)?),
        Format::Json => Box::new(JsonWriter::new(out, header)?),
        Format::JsonLines => Box::new(JsonLinesWriter::new(out)),
    })
}

/// Computes the unit's basins over its outer and inner displacements (or one part of them,
/// [`basins_part`]) and writes their table to `out` in `format`: [`write_plane_basins`] on the
/// default plane ([`BasinPlane::unit`]), the table `rattle basins --out …` writes without
/// `--x`/`--y`.
///
/// # Errors
/// The writer's.
pub fn write_basins<W: Write>(
    scene: &Scene,
    omega: f64,
    grid: BasinGrid,
    options: &SimulationOptions,
    shard: Option<Shard>,
    out: (Format, W),
    progress: &Progress,
) -> std::io::Result<Basins> {
    let b = basins_part(scene, omega, grid, options, shard, progress);
    write_table(&AnyScene::Cells(scene.clone()), b, shard, out)
}

/// Computes the basins of `scene` (any form) over `plane` (or one part of them,
/// [`plane_basins_part`]) and writes their table to `out` in `format`: the table
/// `rattle basins --out …` writes. Its columns are the two starts' ([`BasinPlane::columns`]),
/// `attractor`, `attractor_words`, `outer_amplitude`, `periods_run`, and on a chain or a
/// structure `body_amplitudes`. A part's JSON header adds the whole grid's `starts`, its
/// `shard` and its `attractors` (numbered within the part, in full); a CSV part starts with
/// `# shard K/N of P starts, attractors: [...]` (the same list, JSON). Its rows are numbered
/// within the part; [`crate::runs::shard::merge`] numbers them over the whole grid and writes
/// exactly the whole grid's table. Returns the basins computed (of the part: its cells and
/// attractors).
///
/// # Errors
/// The writer's.
pub fn write_plane_basins<W: Write>(
    scene: &AnyScene,
    omega: f64,
    plane: &BasinPlane,
    options: &SimulationOptions,
    shard: Option<Shard>,
    out: (Format, W),
    progress: &Progress,
) -> std::io::Result<Basins> {
    let b = plane_basins_part(scene, omega, plane, options, shard, progress);
    write_table(scene, b, shard, out)
}

/// Writes the table of `b` (part `shard` of the grid, or all of it).
fn write_table<W: Write>(
    scene: &AnyScene,
    b: Basins,
    shard: Option<Shard>,
    (format, out): (Format, W),
) -> std::io::Result<Basins> {
    let mut h = any_header(scene, b.omega);
    let total = b.grid.starts();
    let preamble = match shard {
        Some(s) => {
            h.push("starts", &total);
            h.push("shard", &s);
            h.push("attractors", &b.attractors);
            let list = serde_json::to_string(&b.attractors).map_err(std::io::Error::other)?;
            Some(format!(
                "{}, attractors: {list}",
                s.csv_preamble_of(total, "starts")
            ))
        }
        None => None,
    };
    let bodies = !matches!(scene, AnyScene::Cells(s) if !s.is_chain());
    let starts = b.plane.columns();
    let columns = table_columns(&starts, bodies);
    let mut table = plane_writer(format, out, &h, preamble.as_deref(), &columns)?;
    let amplitudes = bodies.then_some(&b.body_amplitudes[..]);
    let keyed = format != Format::Csv;
    for row in plane_rows(&starts, &b.attractors, &b.cells, amplitudes, keyed) {
        table.row(&row)?;
    }
    table.finish()?;
    Ok(b)
}

/// Whether `text` is a part of sharded basins (its header or first line lists the part's
/// attractors).
pub fn is_basins_part(text: &str) -> bool {
    let first = text.lines().next().unwrap_or_default();
    (first.starts_with("# shard ") && first.contains(" starts, attractors: "))
        || (first.starts_with('{') && first.contains(",\"attractors\":"))
}

/// One part of sharded basins, read back: its shard, the whole grid's starts, the opening of
/// the whole grid's JSON document (for a JSON part), its columns (none for a JSON part
/// without rows) and its starts with every body's amplitude of each (empty without a
/// `body_amplitudes` column).
struct BasinsPart {
    shard: Shard,
    total: usize,
    opening: Option<String>,
    columns: Vec<String>,
    reached: Vec<Reached>,
    amplitudes: Vec<Vec<Option<f64>>>,
}

/// A number cell of a part: empty or `null` is NaN (as [`finite`] wrote it).
fn number_cell(text: &str) -> Result<f64, String> {
    if text.is_empty() || text == "null" {
        return Ok(f64::NAN);
    }
    text.parse()
        .map_err(|_| format!("{text:?} is not a number"))
}

/// Whether `columns` are a basins table's: two starts' (`…_start`), [`BasinRow`]'s others, and
/// optionally [`BODY_AMPLITUDES`].
fn basins_columns(columns: &[String]) -> bool {
    let rest = BasinRow::COLUMNS[2..].iter().map(|c| (*c).to_owned());
    (columns.len() == 6 || (columns.len() == 7 && columns[6] == BODY_AMPLITUDES))
        && columns[..2].iter().all(|c| c.ends_with("_start"))
        && columns[2..6].iter().cloned().eq(rest)
}

/// A start of a part from its cells: the attractor is the part's `attractors[attractor]`, a
/// periodic one with the start's own `X_o` or, with a `body_amplitudes` cell, its own body
/// amplitudes (as [`reach`] found it). Returns the start and its body amplitudes.
fn reached_of(
    attractors: &[Attractor],
    [outer, inner, attractor, amplitude, periods]: [&str; 5],
    bodies: Option<&str>,
) -> Result<(Reached, Vec<Option<f64>>), String> {
    let outer_amplitude = number_cell(amplitude)?;
    let index: usize = attractor
        .parse()
        .map_err(|_| format!("attractor {attractor:?} is not a number"))?;
    let mut attractor = attractors
        .get(index)
        .cloned()
        .ok_or_else(|| format!("attractor {index} is not in the part's list"))?;
    if let Attractor::Periodic {
        outer_amplitude: x, ..
    } = &mut attractor
    {
        *x = outer_amplitude;
    }
    if let (Attractor::Motion { amplitudes, .. }, Some(cell)) = (&mut attractor, bodies) {
        let n = amplitudes.len();
        let own: Vec<Option<f64>> = if cell.is_empty() || cell == "null" {
            vec![None; n]
        } else {
            cell.trim_matches('"')
                .split(';')
                .map(|x| number_cell(x).map(|x| x.is_finite().then_some(x)))
                .collect::<Result<_, _>>()?
        };
        if own.len() != n {
            return Err(format!("{BODY_AMPLITUDES} {cell:?}: {n} bodies expected"));
        }
        *amplitudes = own;
    }
    let own = attractor.body_amplitudes().to_vec();
    Ok((
        Reached {
            outer: number_cell(outer)?,
            inner: number_cell(inner)?,
            attractor,
            outer_amplitude,
            periods_run: periods
                .parse()
                .map_err(|_| format!("periods_run {periods:?} is not a count"))?,
        },
        own,
    ))
}

/// A JSON object's entries in the order written.
struct Entries(Vec<(String, serde_json::Value)>);

impl<'de> Deserialize<'de> for Entries {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visit;
        impl<'de> serde::de::Visitor<'de> for Visit {
            type Value = Entries;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a JSON object")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<Entries, A::Error> {
                let mut entries = Vec::new();
                while let Some(entry) = map.next_entry()? {
                    entries.push(entry);
                }
                Ok(Entries(entries))
            }
        }
        deserializer.deserialize_map(Visit)
    }
}

fn json_basins_part(text: &str) -> Result<BasinsPart, String> {
    let mut lines = text.lines();
    let first = lines.next().unwrap_or_default();
    let head: serde_json::Value = serde_json::from_str(&format!("{first}]}}"))
        .map_err(|e| format!("not a basins document ({e})"))?;
    let shard: Shard =
        serde_json::from_value(head["shard"].clone()).map_err(|e| format!("shard: {e}"))?;
    let attractors: Vec<Attractor> = serde_json::from_value(head["attractors"].clone())
        .map_err(|e| format!("attractors: {e}"))?;
    let total = head["starts"].as_u64().ok_or("no \"starts\"")? as usize;
    let cut = first.rfind(",\"starts\":").ok_or("no \"starts\"")?;
    let opening = format!("{},\"results\":[", &first[..cut]);
    let mut rows: Vec<&str> = lines.collect();
    if rows.pop() != Some("]}") {
        return Err("truncated (no closing \"]}\")".into());
    }
    let mut columns: Vec<String> = Vec::new();
    let mut reached = Vec::with_capacity(rows.len());
    let mut amplitudes = Vec::with_capacity(rows.len());
    for line in rows {
        let Entries(row): Entries =
            serde_json::from_str(line.trim_end_matches(',')).map_err(|e| format!("a row: {e}"))?;
        let names: Vec<String> = row.iter().map(|(k, _)| k.clone()).collect();
        if !basins_columns(&names) {
            return Err("the columns are not those of a basins table".into());
        }
        if columns.is_empty() {
            columns = names;
        } else if columns != names {
            return Err("the rows' columns differ".into());
        }
        let cell = |k: usize| match &row[k].1 {
            serde_json::Value::Null => String::new(),
            v => v.to_string(),
        };
        let bodies = (row.len() == 7).then(|| cell(6));
        let (r, own) = reached_of(
            &attractors,
            [&cell(0), &cell(1), &cell(2), &cell(4), &cell(5)],
            bodies.as_deref(),
        )?;
        reached.push(r);
        amplitudes.push(own);
    }
    Ok(BasinsPart {
        shard,
        total,
        opening: Some(opening),
        columns,
        reached,
        amplitudes,
    })
}

fn csv_basins_part(text: &str) -> Result<BasinsPart, String> {
    let (first, body) = text.split_once('\n').ok_or("empty")?;
    let bad = || "not a basins part (no '# shard K/N of P starts, attractors: [...]' line)";
    let spec = first.strip_prefix("# shard ").ok_or_else(bad)?;
    let (kn, rest) = spec.split_once(" of ").ok_or_else(bad)?;
    let (total, list) = rest.split_once(" starts, attractors: ").ok_or_else(bad)?;
    let shard = Shard::parse(kn)?;
    let total: usize = total.parse().map_err(|_| bad())?;
    let attractors: Vec<Attractor> =
        serde_json::from_str(list).map_err(|e| format!("attractors: {e}"))?;
    let mut reader = ::csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(body.as_bytes());
    let columns: Vec<String> = reader
        .headers()
        .map_err(|e| e.to_string())?
        .iter()
        .map(str::to_owned)
        .collect();
    if !basins_columns(&columns) {
        return Err("the columns are not those of a basins table".into());
    }
    let bodies = columns.len() == 7;
    let mut reached = Vec::new();
    let mut amplitudes = Vec::new();
    for record in reader.records() {
        let r = record.map_err(|e| e.to_string())?;
        let cell = |k: usize| r.get(k).unwrap_or_default();
        let (one, own) = reached_of(
            &attractors,
            [cell(0), cell(1), cell(2), cell(4), cell(5)],
            bodies.then(|| cell(6)),
        )?;
        reached.push(one);
        amplitudes.push(own);
    }
    Ok(BasinsPart {
        shard,
        total,
        opening: None,
        columns,
        reached,
        amplitudes,
    })
}

/// Joins the parts of sharded basins (all JSON or all CSV, in any order) into exactly the
/// table the unsharded run writes: the starts in grid order, the attractors numbered by first
/// appearance over the whole grid, each start's attractor decided as the whole grid decides
/// it ([`number`]).
///
/// # Errors
/// A message when a part is not a basins part, when parts are missing, repeated or from
/// different grids, or when the rows do not add up to the grid's starts.
pub fn merge_parts(parts: &[String]) -> Result<String, String> {
    let mut parsed: Vec<BasinsPart> = parts
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let part = if p.trim_start().starts_with('{') {
                json_basins_part(p)
            } else {
                csv_basins_part(p)
            };
            part.map_err(|e| format!("part {}: {e}", i + 1))
        })
        .collect::<Result<_, _>>()?;
    check_cover(&parsed.iter().map(|p| p.shard).collect::<Vec<_>>())?;
    let columns = parsed
        .iter()
        .find(|p| !p.columns.is_empty())
        .map(|p| p.columns.clone())
        .unwrap_or_default();
    if parsed.iter().any(|p| {
        p.opening != parsed[0].opening
            || p.total != parsed[0].total
            || !(p.columns.is_empty() || p.columns == columns)
    }) {
        return Err(
            "the parts come from different basins (scene, frequency, grid or coordinates differ)"
                .into(),
        );
    }
    parsed.sort_by_key(|p| p.shard.index);
    let total = parsed[0].total;
    let opening = parsed[0].opening.clone();
    let mut reached: Vec<Reached> = Vec::with_capacity(total);
    let mut amplitudes: Vec<Vec<Option<f64>>> = Vec::with_capacity(total);
    for p in parsed {
        reached.extend(p.reached);
        amplitudes.extend(p.amplitudes);
    }
    if reached.len() != total {
        return Err(format!("{} starts for a grid of {total}", reached.len()));
    }
    if columns.len() < 6 {
        return Err("no part has rows".into());
    }
    let starts = [columns[0].clone(), columns[1].clone()];
    let bodies = (columns.len() == 7).then_some(&amplitudes[..]);
    let (attractors, _, cells) = number(reached);
    let mut out = Vec::new();
    let keyed = opening.is_some();
    let mut table: Box<dyn TableWriter<PlaneRow>> = match &opening {
        Some(opening) => {
            Box::new(JsonWriter::with_opening(&mut out, opening).map_err(|e| e.to_string())?)
        }
        None => {
            let names: Vec<&str> = columns.iter().map(String::as_str).collect();
            Box::new(CsvWriter::new(&mut out, None, &names).map_err(|e| e.to_string())?)
        }
    };
    for row in plane_rows(&starts, &attractors, &cells, bodies, keyed) {
        table.row(&row).map_err(|e| e.to_string())?;
    }
    table.finish().map_err(|e| e.to_string())?;
    String::from_utf8(out).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference(states: &[[f64; 4]]) -> Reference {
        Reference {
            attractor: Attractor::NotPeriodic,
            outer_amplitude: 1.0,
            states: states
                .iter()
                .map(|s| DVector::from_column_slice(s))
                .collect(),
        }
    }

    #[test]
    fn the_proximity_keeps_the_attractors_neighbourhoods_apart() {
        let a = reference(&[[1.0, 0.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0]]);
        // One state of `b` 0.06 from one of `a`'s (relative to norms about 1): a third of it.
        let b = reference(&[[1.06, 0.0, 0.0, 0.0], [0.0, 3.0, 0.0, 0.0]]);
        let guarded = proximity(&[a.clone(), b], 0.5);
        assert!((guarded - 0.06 / 1.06 / 3.0).abs() < 1e-15, "{guarded}");
        // Far apart, or alone: the constant.
        let c = reference(&[[0.0, 0.0, 5.0, 0.0]]);
        assert_eq!(proximity(&[a.clone(), c], 0.5), BASIN_PROXIMITY);
        assert_eq!(proximity(&[a], 0.5), BASIN_PROXIMITY);
        assert_eq!(proximity(&[], 0.5), BASIN_PROXIMITY);
    }

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
