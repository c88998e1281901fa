//! The structure form of a scene: bodies, springs, dashpots and stops as the user draws them,
//! driven by the moving base and by forces on the bodies.
//!
//! ```json
//! {"name": "impact-oscillator",
//!  "structure": {
//!    "bodies":   [{"name": "x", "mass": 1.0}],
//!    "springs":  [{"between": ["frame", "x"], "stiffness": 1.0}],
//!    "dashpots": [{"between": ["frame", "x"], "damping": 0.1}],
//!    "stops":    [{"between": ["frame", "x"], "gap_plus": 0.5, "restitution": 0.8}]},
//!  "forcing": {"forces": [{"on": "x", "amplitude": 1.0, "phase": 0.0}]},
//!  "observe": "x"}
//! ```
//!
//! - `between: [a, b]` acts on `u_b − u_a`. An end is a body's name, `"frame"` (fixed, `u = 0`)
//!   or `"base"` (moving as `u_g cos ωt`: every spring and dashpot tied to it forces the body
//!   at its other end with `k u_g cos ωt − c ω u_g sin ωt`).
//! - A stop confines `r = u_b − u_a` to `[−gap_minus, gap_plus]`: side 1 (`+` in a signature)
//!   is `r = +gap_plus`, side 2 (`-`) is `r = −gap_minus`. `gap` gives both sides the same
//!   distance; a side left out has no stop (one-sided), but not both. Stops are the contact
//!   pairs, numbered from 0 in file order.
//! - `forcing.base.amplitude` is `u_g`; `forcing.forces[j]` is `F cos(ωt + φ)` on body `on`
//!   (`amplitude` `F`, `phase` `φ` in radians, default 0). At least one of the two drives the
//!   structure.
//! - `observe` (default: the last body) is the body whose amplitude outputs call the outer
//!   amplitude and whose transmittance (against `u_g`) they report.
//!
//! What has no bounded motion is refused, naming the JSON path and the reason: a name that does
//! not exist, an element between an end and itself, a gap `≤ 0`, a stop against the moving
//! base, and a body (or group of bodies) that nothing holds: a body no spring or dashpot ties
//! to the frame or the base (a free body, such as an impact damper's mass) must be held both
//! ways by stops against ends that are held themselves.
//!
//! [`Structure`] is the checked, resolved form: indices instead of names, the matrices
//! `M`, `C`, `K` assembled element by element, and each solver's model built from it
//! ([`Structure::event_model`], [`Structure::analytic_model`]).

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Most bodies a structure may have: twice the chain's cell count (the simulator's dense modal
/// flow costs `O(n³)` to set up, as for a chain of [`crate::scene::MAX_CELLS`] cells).
pub const MAX_BODIES: usize = 2 * crate::scene::MAX_CELLS;

/// The fixed frame's name as an end of an element.
pub const FRAME: &str = "frame";
/// The moving base's name as an end of an element.
pub const BASE: &str = "base";

/// A structure scene as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructureScene {
    /// A name for outputs and figures.
    #[serde(default = "unnamed")]
    pub name: String,
    /// Bodies, springs, dashpots and stops.
    pub structure: StructureSpec,
    /// What drives the structure.
    pub forcing: ForcingSpec,
    /// The observed body (default: the last body).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub observe: Option<String>,
}

fn unnamed() -> String {
    "unnamed".to_owned()
}

/// The elements of a structure.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructureSpec {
    /// The bodies, in the order of the state's coordinates.
    pub bodies: Vec<BodySpec>,
    /// Linear springs.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub springs: Vec<SpringSpec>,
    /// Linear dashpots.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub dashpots: Vec<DashpotSpec>,
    /// Rigid stops with Newton restitution: the contact pairs.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stops: Vec<StopSpec>,
}

/// One body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Its name (not `frame` or `base`; unique).
    pub name: String,
    /// Its mass, kg, `> 0`.
    pub mass: f64,
}

/// A spring between two ends.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    /// The ends `[a, b]`; the spring acts on `u_b − u_a`.
    pub between: [String; 2],
    /// Stiffness, N/m, `> 0`.
    pub stiffness: f64,
}

/// A dashpot between two ends.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DashpotSpec {
    /// The ends `[a, b]`; the dashpot acts on `u̇_b − u̇_a`.
    pub between: [String; 2],
    /// Damping coefficient, N·s/m, `≥ 0`.
    pub damping: f64,
}

/// A stop: `r = u_b − u_a` confined to `[−gap_minus, gap_plus]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopSpec {
    /// The ends `[a, b]`: a body and a body, or a body and the frame.
    pub between: [String; 2],
    /// Both sides' distance, m (`gap_plus = gap_minus = gap`); not with `gap_plus` or
    /// `gap_minus`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap: Option<f64>,
    /// Distance to side 1 (`r = +gap_plus`), m, `> 0`; absent: no stop on side 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap_plus: Option<f64>,
    /// Distance to side 2 (`r = −gap_minus`), m, `> 0`; absent: no stop on side 2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap_minus: Option<f64>,
    /// Newton restitution `e ∈ [0, 1]`: `ṙ⁺ = −e ṙ⁻`.
    pub restitution: f64,
}

/// What drives a structure.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForcingSpec {
    /// The base motion `u_g cos ωt`, through the springs and dashpots tied to `"base"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<crate::scene::BaseSpec>,
    /// Forces on bodies.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub forces: Vec<ForceSpec>,
}

/// A harmonic force `F cos(ωt + φ)` on one body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceSpec {
    /// The body's name.
    pub on: String,
    /// `F`, N, finite.
    pub amplitude: f64,
    /// `φ`, rad, finite (default 0).
    #[serde(default)]
    pub phase: f64,
}

/// A scene in the structure form with its checked structure.
#[derive(Debug, Clone, PartialEq)]
pub struct StructureForm {
    /// The scene as written.
    pub scene: StructureScene,
    /// The checked structure.
    pub structure: Structure,
}

/// The ends of an element, resolved (the function [`StructureScene::structure`] checks them
/// with).
type Ends<'a> = dyn Fn(&str, &[String; 2]) -> Result<[End; 2], StructureError> + 'a;

/// A structure that has no bounded motion, or names what does not exist: the JSON path of the
/// field and the reason.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{field}: {reason}")]
pub struct StructureError {
    /// The JSON path, e.g. `structure.springs[2].between[1]`.
    pub field: String,
    /// What is wrong, with the allowed range where there is one.
    pub reason: String,
}

fn refuse(field: impl Into<String>, reason: impl Into<String>) -> StructureError {
    StructureError {
        field: field.into(),
        reason: reason.into(),
    }
}

/// An end of an element, resolved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// The fixed frame.
    Frame,
    /// The moving base.
    Base,
    /// A body, by index.
    Body(usize),
}

/// One stop, resolved: a contact pair `r = u[plus] − u[minus]` (`None`: the frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stop {
    /// The body counted positive in `r` (`None`: the frame).
    pub plus: Option<usize>,
    /// The body counted negative in `r` (`None`: the frame).
    pub minus: Option<usize>,
    /// Distance to side 1; `+∞`: no stop there.
    pub gap_plus: f64,
    /// Distance to side 2; `+∞`: no stop there.
    pub gap_minus: f64,
    /// Newton restitution.
    pub restitution: f64,
}

/// A checked structure with its matrices: `M ü + C u̇ + K u = f_c cos ωt + (f_s + ω f_ω) sin ωt`.
#[derive(Debug, Clone, PartialEq)]
pub struct Structure {
    /// The bodies' names, in coordinate order.
    pub names: Vec<String>,
    /// `M` (diagonal: the bodies' masses).
    pub mass: DMatrix<f64>,
    /// `K`, assembled from the springs (those to the frame or base on the diagonal only).
    pub stiffness: DMatrix<f64>,
    /// `C`, assembled from the dashpots; `None` when every dashpot is zero (or there is none).
    pub damping: Option<DMatrix<f64>>,
    /// `f_c`: the base's springs times `u_g`, plus each force's `F cos φ`.
    pub forcing_cos: DVector<f64>,
    /// `f_s`: each force's `−F sin φ`.
    pub forcing_sin: DVector<f64>,
    /// `f_ω`: the base's dashpots times `−u_g` (the sine part per unit `ω`).
    pub forcing_sin_per_omega: DVector<f64>,
    /// The contact pairs.
    pub stops: Vec<Stop>,
    /// `u_g`, when the base moves.
    pub base_amplitude: Option<f64>,
    /// The observed body.
    pub observe: usize,
    /// Per body, the group it floats in when no chain of springs ties it to the frame or the
    /// base (an id shared by the bodies of one group), `None` when springs hold it. A floating
    /// group's position is not set by the linear dynamics (`K` is singular on its
    /// translation): its motion clear of the stops is a family, offset anywhere the stops
    /// allow.
    pub floating: Vec<Option<usize>>,
}

impl StructureScene {
    /// The checked structure.
    ///
    /// # Errors
    /// [`StructureError`] naming the field and the reason for the first thing that is wrong.
    pub fn structure(&self) -> Result<Structure, StructureError> {
        let spec = &self.structure;
        let n = spec.bodies.len();
        if !(1..=MAX_BODIES).contains(&n) {
            return Err(refuse(
                "structure.bodies",
                format!("{n} bodies is out of range: must be 1..={MAX_BODIES}"),
            ));
        }
        let mut names: Vec<String> = Vec::with_capacity(n);
        let mut mass = DMatrix::zeros(n, n);
        for (j, body) in spec.bodies.iter().enumerate() {
            let field = format!("structure.bodies[{j}]");
            if body.name.is_empty() || body.name == FRAME || body.name == BASE {
                return Err(refuse(
                    format!("{field}.name"),
                    format!(
                        "{:?} is not a body's name: must be non-empty and not \"{FRAME}\" or \"{BASE}\"",
                        body.name
                    ),
                ));
            }
            if names.contains(&body.name) {
                return Err(refuse(
                    format!("{field}.name"),
                    format!("a second body named {:?}: names must be unique", body.name),
                ));
            }
            positive(&format!("{field}.mass"), body.mass)?;
            names.push(body.name.clone());
            mass[(j, j)] = body.mass;
        }
        let end = |field: String, name: &str| -> Result<End, StructureError> {
            match name {
                FRAME => Ok(End::Frame),
                BASE => Ok(End::Base),
                _ => names.iter().position(|b| b == name).map(End::Body).ok_or_else(|| {
                    refuse(
                        field,
                        format!(
                            "no body named {name:?} (bodies: {}; an end may also be \"{FRAME}\" or \"{BASE}\")",
                            names.join(", ")
                        ),
                    )
                }),
            }
        };
        let ends = |field: &str, between: &[String; 2]| -> Result<[End; 2], StructureError> {
            let a = end(format!("{field}.between[0]"), &between[0])?;
            let b = end(format!("{field}.between[1]"), &between[1])?;
            if !matches!(a, End::Body(_)) && !matches!(b, End::Body(_)) {
                return Err(refuse(
                    format!("{field}.between"),
                    "ties no body: one end at least must be a body",
                ));
            }
            if a == b {
                return Err(refuse(
                    format!("{field}.between"),
                    format!("both ends are {:?}: an element needs two ends", between[0]),
                ));
            }
            Ok([a, b])
        };
        let mut stiffness = DMatrix::zeros(n, n);
        let mut base_springs = DVector::zeros(n);
        let mut held = Grounding::new(n);
        let mut sprung = Grounding::new(n);
        for (j, spring) in spec.springs.iter().enumerate() {
            let field = format!("structure.springs[{j}]");
            let [a, b] = ends(&field, &spring.between)?;
            positive(&format!("{field}.stiffness"), spring.stiffness)?;
            assemble(&mut stiffness, &mut base_springs, [a, b], spring.stiffness);
            held.tie(a, b);
            sprung.tie(a, b);
        }
        let mut damping = DMatrix::zeros(n, n);
        let mut base_dashpots = DVector::zeros(n);
        for (j, dashpot) in spec.dashpots.iter().enumerate() {
            let field = format!("structure.dashpots[{j}]");
            let [a, b] = ends(&field, &dashpot.between)?;
            let c = dashpot.damping;
            if !(c.is_finite() && c >= 0.0) {
                return Err(refuse(
                    format!("{field}.damping"),
                    format!("{c} is out of range: must be finite and >= 0"),
                ));
            }
            assemble(&mut damping, &mut base_dashpots, [a, b], c);
            if c > 0.0 {
                held.tie(a, b);
            }
        }
        let mut stops = Vec::with_capacity(spec.stops.len());
        for (j, stop) in spec.stops.iter().enumerate() {
            stops.push(resolve_stop(&format!("structure.stops[{j}]"), stop, &ends)?);
        }
        if let Some((group, direction)) = held.unbounded(&stops) {
            let list: Vec<&str> = group.iter().map(|&j| names[j].as_str()).collect();
            return Err(refuse(
                "structure.stops",
                format!(
                    "nothing holds {} {}: no spring or dashpot ties {} to the frame or the \
                     base, and no stop against a held end bounds {} motion towards {} u; \
                     add a spring, or a stop on that side",
                    if list.len() == 1 { "body" } else { "bodies" },
                    list.join(", "),
                    if list.len() == 1 { "it" } else { "them" },
                    if list.len() == 1 { "its" } else { "their" },
                    if direction > 0.0 {
                        "growing"
                    } else {
                        "shrinking"
                    },
                ),
            ));
        }
        let (base_amplitude, forcing_cos, forcing_sin, forcing_sin_per_omega) =
            self.forcing_vectors(&names, &base_springs, &base_dashpots)?;
        let observe = match &self.observe {
            None => n - 1,
            Some(name) => names.iter().position(|b| b == name).ok_or_else(|| {
                refuse(
                    "observe",
                    format!("no body named {name:?} (bodies: {})", names.join(", ")),
                )
            })?,
        };
        let damped = damping.iter().any(|&c| c != 0.0);
        Ok(Structure {
            names,
            mass,
            stiffness,
            damping: damped.then_some(damping),
            forcing_cos,
            forcing_sin,
            forcing_sin_per_omega,
            stops,
            base_amplitude,
            observe,
            floating: sprung.floating(),
        })
    }

    /// `u_g` and the forcing vectors `f_c`, `f_s`, `f_ω` from the base's springs and dashpots
    /// and the forces.
    #[allow(clippy::type_complexity)]
    fn forcing_vectors(
        &self,
        names: &[String],
        base_springs: &DVector<f64>,
        base_dashpots: &DVector<f64>,
    ) -> Result<(Option<f64>, DVector<f64>, DVector<f64>, DVector<f64>), StructureError> {
        let n = names.len();
        let tied = base_springs
            .iter()
            .chain(base_dashpots.iter())
            .any(|&v| v != 0.0);
        let base_amplitude = match &self.forcing.base {
            Some(base) => {
                positive("forcing.base.amplitude", base.amplitude)?;
                if !tied {
                    return Err(refuse(
                        "forcing.base",
                        format!(
                            "no spring or dashpot is tied to \"{BASE}\": the base's motion drives nothing"
                        ),
                    ));
                }
                Some(base.amplitude)
            }
            None if tied => {
                return Err(refuse(
                    "forcing.base",
                    format!("missing: elements are tied to \"{BASE}\", so give its amplitude"),
                ))
            }
            None => None,
        };
        let ug = base_amplitude.unwrap_or(0.0);
        let mut cos = base_springs * ug;
        let mut sin = DVector::zeros(n);
        let sin_per_omega = base_dashpots * -ug;
        for (j, force) in self.forcing.forces.iter().enumerate() {
            let field = format!("forcing.forces[{j}]");
            let body = names.iter().position(|b| *b == force.on).ok_or_else(|| {
                refuse(
                    format!("{field}.on"),
                    format!(
                        "no body named {:?} (bodies: {})",
                        force.on,
                        names.join(", ")
                    ),
                )
            })?;
            for (name, v) in [("amplitude", force.amplitude), ("phase", force.phase)] {
                if !v.is_finite() {
                    return Err(refuse(
                        format!("{field}.{name}"),
                        format!("{v} is out of range: must be finite"),
                    ));
                }
            }
            let (s, c) = force.phase.sin_cos();
            cos[body] += force.amplitude * c;
            sin[body] -= force.amplitude * s;
        }
        if base_amplitude.is_none() && self.forcing.forces.iter().all(|f| f.amplitude == 0.0) {
            return Err(refuse(
                "forcing",
                "drives nothing: give `base` (with elements tied to \"base\") or `forces`",
            ));
        }
        Ok((base_amplitude, cos, sin, sin_per_omega))
    }
}

/// A stop's ends and gaps, checked.
fn resolve_stop(field: &str, stop: &StopSpec, ends: &Ends<'_>) -> Result<Stop, StructureError> {
    let [a, b] = ends(field, &stop.between)?;
    let body = |end: End| match end {
        End::Body(j) => Ok(Some(j)),
        End::Frame => Ok(None),
        End::Base => Err(refuse(
            format!("{field}.between"),
            format!(
                "a stop against \"{BASE}\" moves with it: not supported; put the stop on the \
                 frame or on a body"
            ),
        )),
    };
    let (minus, plus) = (body(a)?, body(b)?);
    let (gap_plus, gap_minus) = match (stop.gap, stop.gap_plus, stop.gap_minus) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
            return Err(refuse(
                format!("{field}.gap"),
                "give either `gap` (both sides) or `gap_plus`/`gap_minus`, not both",
            ))
        }
        (Some(gap), None, None) => {
            positive(&format!("{field}.gap"), gap)?;
            (gap, gap)
        }
        (None, None, None) => {
            return Err(refuse(
                format!("{field}.gap_plus"),
                "missing: a stop needs `gap`, `gap_plus` or `gap_minus`",
            ))
        }
        (None, plus_gap, minus_gap) => {
            let side = |name: &str, gap: Option<f64>| -> Result<f64, StructureError> {
                match gap {
                    Some(g) => positive(&format!("{field}.{name}"), g).map(|()| g),
                    None => Ok(f64::INFINITY),
                }
            };
            (side("gap_plus", plus_gap)?, side("gap_minus", minus_gap)?)
        }
    };
    let e = stop.restitution;
    if !(0.0..=1.0).contains(&e) {
        return Err(refuse(
            format!("{field}.restitution"),
            format!("{e} is out of range: must be in [0, 1]"),
        ));
    }
    Ok(Stop {
        plus,
        minus,
        gap_plus,
        gap_minus,
        restitution: e,
    })
}

/// `value` finite and `> 0`, or the error naming `field`.
fn positive(field: &str, value: f64) -> Result<(), StructureError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(refuse(
            field,
            format!("{value} is out of range: must be finite and > 0"),
        ))
    }
}

/// Adds an element of coefficient `k` between `ends` to `matrix`; a body tied to the base also
/// gains `k` in `base` (its forcing per unit base motion).
fn assemble(matrix: &mut DMatrix<f64>, base: &mut DVector<f64>, ends: [End; 2], k: f64) {
    match ends {
        [End::Body(i), End::Body(j)] => {
            matrix[(i, i)] += k;
            matrix[(j, j)] += k;
            matrix[(i, j)] -= k;
            matrix[(j, i)] -= k;
        }
        [End::Body(i), other] | [other, End::Body(i)] => {
            matrix[(i, i)] += k;
            if other == End::Base {
                base[i] += k;
            }
        }
        // `ends` refuses elements that tie no body.
        _ => {}
    }
}

/// Which bodies springs and dashpots hold to the ground (frame or base): union–find over the
/// elements, each group grounded when one of its bodies is tied to the frame or the base.
struct Grounding {
    parent: Vec<usize>,
    grounded: Vec<bool>,
}

impl Grounding {
    fn new(n: usize) -> Self {
        Self {
            parent: (0..n).collect(),
            grounded: vec![false; n],
        }
    }

    fn root(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    fn tie(&mut self, a: End, b: End) {
        match (a, b) {
            (End::Body(i), End::Body(j)) => {
                let (ri, rj) = (self.root(i), self.root(j));
                if ri != rj {
                    self.parent[ri] = rj;
                    self.grounded[rj] |= self.grounded[ri];
                }
            }
            (End::Body(i), _) | (_, End::Body(i)) => {
                let r = self.root(i);
                self.grounded[r] = true;
            }
            _ => {}
        }
    }

    /// Per body, its group's id when the group is not grounded.
    fn floating(&mut self) -> Vec<Option<usize>> {
        (0..self.parent.len())
            .map(|i| {
                let r = self.root(i);
                (!self.grounded[r]).then_some(r)
            })
            .collect()
    }

    /// The first group whose translation nothing bounds, with the direction it is free in
    /// (`+1`: growing `u`, `−1`: shrinking), if any.
    ///
    /// A group no spring or dashpot ties to the ground translates freely (a rigid mode). It is
    /// held when stops bound its translation both ways against ends that are held themselves
    /// (the frame, a grounded group, or a group held so): a stop `[a, b]` on group `b` bounds
    /// growth by `gap_plus` and shrinking by `gap_minus`, on group `a` the other way round.
    /// Held groups are found by repeating that rule until nothing changes.
    fn unbounded(&mut self, stops: &[Stop]) -> Option<(Vec<usize>, f64)> {
        let n = self.parent.len();
        let roots: Vec<usize> = (0..n).map(|i| self.root(i)).collect();
        let mut held: Vec<bool> = (0..n).map(|i| self.grounded[roots[i]]).collect();
        let end_held = |held: &[bool], end: Option<usize>| end.is_none_or(|j| held[roots[j]]);
        loop {
            let mut changed = false;
            for g in 0..n {
                if roots[g] != g || held[g] {
                    continue;
                }
                let (mut up, mut down) = (false, false);
                for stop in stops {
                    let (at_plus, at_minus) = (
                        stop.plus.is_some_and(|j| roots[j] == g),
                        stop.minus.is_some_and(|j| roots[j] == g),
                    );
                    if at_plus && !at_minus && end_held(&held, stop.minus) {
                        up |= stop.gap_plus.is_finite();
                        down |= stop.gap_minus.is_finite();
                    } else if at_minus && !at_plus && end_held(&held, stop.plus) {
                        up |= stop.gap_minus.is_finite();
                        down |= stop.gap_plus.is_finite();
                    }
                }
                if up && down {
                    held[g] = true;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        let first = (0..n).find(|&i| !held[roots[i]])?;
        let group: Vec<usize> = (0..n).filter(|&i| roots[i] == roots[first]).collect();
        // Name the direction the group is free in: the first the stops leave open.
        let g = roots[first];
        let up = stops.iter().any(|stop| {
            let at_plus = stop.plus.is_some_and(|j| roots[j] == g);
            let at_minus = stop.minus.is_some_and(|j| roots[j] == g);
            (at_plus && !at_minus && end_held(&held, stop.minus) && stop.gap_plus.is_finite())
                || (at_minus
                    && !at_plus
                    && end_held(&held, stop.plus)
                    && stop.gap_minus.is_finite())
        });
        Some((group, if up { -1.0 } else { 1.0 }))
    }
}

impl Structure {
    /// Whether the structure has floating bodies ([`Structure::floating`]).
    pub fn has_floating(&self) -> bool {
        self.floating.iter().any(Option::is_some)
    }

    /// Whether `stop`'s relative coordinate moves with a floating group's offset: its ends
    /// lie in different groups and one at least floats (the frame never does).
    pub fn floats(&self, stop: &Stop) -> bool {
        let group = |end: Option<usize>| end.and_then(|j| self.floating[j]);
        let (a, b) = (group(stop.minus), group(stop.plus));
        (a.is_some() || b.is_some()) && a != b
    }

    /// Degrees of freedom (bodies).
    pub fn dofs(&self) -> usize {
        self.names.len()
    }

    /// `f_s + ω f_ω`: the sine part of the forcing at `omega`.
    pub fn forcing_sin_at(&self, omega: f64) -> DVector<f64> {
        &self.forcing_sin + &self.forcing_sin_per_omega * omega
    }

    /// The event-driven simulator's model at `omega`: the matrices as assembled, a contact
    /// pair per stop (a side without a stop has gap `+∞`), damping terms only where a dashpot
    /// is not zero.
    ///
    /// # Errors
    /// [`rattle_event_driven::ModelError`] for `omega` not finite and `> 0`.
    pub fn event_model(
        &self,
        omega: f64,
    ) -> Result<rattle_event_driven::Model, rattle_event_driven::ModelError> {
        if !(omega.is_finite() && omega > 0.0) {
            return Err(rattle_event_driven::ModelError::OutOfRange {
                field: "omega".into(),
                value: omega,
                allowed: "> 0",
            });
        }
        let contacts = self
            .stops
            .iter()
            .map(|s| rattle_event_driven::ContactPair {
                plus_dof: s.plus,
                minus_dof: s.minus,
                gap_plus: s.gap_plus,
                gap_minus: s.gap_minus,
                restitution: s.restitution,
            })
            .collect();
        rattle_event_driven::Model::new(
            self.mass.clone(),
            self.stiffness.clone(),
            self.damping.clone(),
            self.forcing_cos.clone(),
            self.forcing_sin_at(omega),
            contacts,
        )
    }

    /// The analytic solver's model: the same matrices, each stop a contact pair of direction
    /// `w = e_plus − e_minus` (the frame's entry left out).
    ///
    /// # Errors
    /// [`rattle_analytic::ModelError`] when the analytic model's own checks refuse it (they
    /// accept every checked structure).
    pub fn analytic_model(
        &self,
    ) -> Result<rattle_analytic::LinearModel, rattle_analytic::ModelError> {
        let n = self.dofs();
        let pairs = self
            .stops
            .iter()
            .map(|s| {
                let mut w = DVector::zeros(n);
                if let Some(i) = s.plus {
                    w[i] = 1.0;
                }
                if let Some(i) = s.minus {
                    w[i] = -1.0;
                }
                rattle_analytic::ContactPair {
                    direction: w,
                    gap_side1: s.gap_plus,
                    gap_side2: s.gap_minus,
                    restitution: s.restitution,
                }
            })
            .collect();
        rattle_analytic::LinearModel::new(
            self.mass.clone(),
            self.damping.clone().unwrap_or_else(|| DMatrix::zeros(n, n)),
            self.stiffness.clone(),
            rattle_analytic::HarmonicForcing {
                cosine: self.forcing_cos.clone(),
                sine: self.forcing_sin.clone(),
                sine_per_omega: self.forcing_sin_per_omega.clone(),
                harmonics: Vec::new(),
            },
            pairs,
        )
    }

    /// The start at rest at `t = 0`: the `2n` state entries zero.
    pub fn rest(&self) -> rattle_event_driven::Start {
        rattle_event_driven::Start::rest(self.dofs())
    }

    /// The transmittance `20 log10(X / u_g)` of the observed body's amplitude `X`, when the
    /// base moves and the value is finite.
    pub fn transmittance_db(&self, amplitude: f64) -> Option<f64> {
        self.base_amplitude
            .map(|ug| rattle_analytic::linear::transmittance_db(amplitude, ug))
            .filter(|t| t.is_finite())
    }

    /// The impact sequence of the stops `text` over `period` forcing periods: `<stop><side>`
    /// tokens (`0+ 1- 0- 1+`), or with one stop the side characters alone (`+-` reads as
    /// `0+ 0-`).
    ///
    /// # Errors
    /// [`rattle_analytic::SequenceError`] for a text that does not parse or a period out of
    /// range.
    pub fn sequence(
        &self,
        text: &str,
        period: u32,
    ) -> Result<rattle_analytic::ImpactSequence, rattle_analytic::SequenceError> {
        let bare = !text.is_empty() && text.chars().all(|c| matches!(c, '+' | '-'));
        let text = if self.stops.len() == 1 && bare {
            text.chars()
                .map(|c| format!("0{c}"))
                .collect::<Vec<_>>()
                .join(" ")
        } else {
            text.to_owned()
        };
        rattle_analytic::ImpactSequence::parse(&text, period)
    }

    /// Whether some dashpot is not zero.
    pub fn is_damped(&self) -> bool {
        self.damping.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Structure, StructureError> {
        let scene: StructureScene = serde_json::from_str(text).expect("the scene parses");
        scene.structure()
    }

    const OSCILLATOR: &str = r#"{"name": "impact-oscillator",
        "structure": {
          "bodies":   [{"name": "x", "mass": 2.0}],
          "springs":  [{"between": ["frame", "x"], "stiffness": 3.0}],
          "dashpots": [{"between": ["frame", "x"], "damping": 0.1}],
          "stops":    [{"between": ["frame", "x"], "gap_plus": 0.5, "restitution": 0.8}]},
        "forcing": {"forces": [{"on": "x", "amplitude": 1.5, "phase": 0.3}]},
        "observe": "x"}"#;

    #[test]
    fn the_impact_oscillator_is_one_body_against_the_frame() {
        let s = parse(OSCILLATOR).unwrap();
        assert_eq!(s.mass, DMatrix::from_element(1, 1, 2.0));
        assert_eq!(s.stiffness, DMatrix::from_element(1, 1, 3.0));
        assert_eq!(s.damping, Some(DMatrix::from_element(1, 1, 0.1)));
        assert_eq!(s.forcing_cos[0], 1.5 * 0.3f64.cos());
        assert_eq!(s.forcing_sin[0], -1.5 * 0.3f64.sin());
        assert_eq!(s.base_amplitude, None);
        let stop = s.stops[0];
        assert_eq!((stop.plus, stop.minus), (Some(0), None));
        assert_eq!((stop.gap_plus, stop.gap_minus), (0.5, f64::INFINITY));
        assert!(s.event_model(1.0).is_ok());
        assert!(s.analytic_model().is_ok());
    }

    /// The unit written as a structure assembles the unit's matrices and base forcing.
    #[test]
    fn the_unit_as_a_structure_has_the_units_matrices() {
        let s = parse(
            r#"{"structure": {
                 "bodies": [{"name": "outer", "mass": 2.0}, {"name": "inner", "mass": 1.0}],
                 "springs": [{"between": ["base", "outer"], "stiffness": 6.0},
                             {"between": ["outer", "inner"], "stiffness": 3.0}],
                 "dashpots": [{"between": ["base", "outer"], "damping": 0.1}],
                 "stops": [{"between": ["outer", "inner"], "gap": 0.5, "restitution": 0.8}]},
               "forcing": {"base": {"amplitude": 1.0}}}"#,
        )
        .unwrap();
        assert_eq!(
            s.stiffness,
            DMatrix::from_row_slice(2, 2, &[9.0, -3.0, -3.0, 3.0])
        );
        assert_eq!(s.forcing_cos.as_slice(), &[6.0, 0.0]);
        assert_eq!(s.forcing_sin_per_omega.as_slice(), &[-0.1, 0.0]);
        assert_eq!(s.observe, 1);
        let stop = s.stops[0];
        assert_eq!((stop.plus, stop.minus), (Some(1), Some(0)));
        assert_eq!((stop.gap_plus, stop.gap_minus), (0.5, 0.5));
    }

    #[test]
    fn what_has_no_bounded_motion_is_refused_naming_the_field() {
        let err = |from: &str, to: &str| {
            parse(&OSCILLATOR.replace(from, to))
                .unwrap_err()
                .to_string()
        };
        let e = err(
            r#"["frame", "x"], "stiffness""#,
            r#"["frame", "y"], "stiffness""#,
        );
        assert!(
            e.starts_with("structure.springs[0].between[1]: no body named \"y\""),
            "{e}"
        );
        let e = err(r#"["frame", "x"], "gap_plus""#, r#"["x", "x"], "gap_plus""#);
        assert!(
            e.starts_with("structure.stops[0].between: both ends"),
            "{e}"
        );
        let e = err(r#""gap_plus": 0.5"#, r#""gap_plus": 0.0"#);
        assert!(
            e.starts_with("structure.stops[0].gap_plus: 0 is out of range"),
            "{e}"
        );
        let e = err(r#""gap_plus": 0.5, "#, "");
        assert!(e.starts_with("structure.stops[0].gap_plus: missing"), "{e}");
        let e = err(r#""gap_plus": 0.5"#, r#""gap": 0.5, "gap_minus": 0.2"#);
        assert!(e.starts_with("structure.stops[0].gap: give either"), "{e}");
        let e = err(
            r#"["frame", "x"], "gap_plus""#,
            r#"["base", "x"], "gap_plus""#,
        );
        assert!(
            e.starts_with("structure.stops[0].between: a stop against \"base\""),
            "{e}"
        );
        let e = err(r#""stiffness": 3.0"#, r#""stiffness": -3.0"#);
        assert!(
            e.starts_with("structure.springs[0].stiffness: -3 is out of range"),
            "{e}"
        );
        let e = err(r#""mass": 2.0"#, r#""mass": 0.0"#);
        assert!(e.starts_with("structure.bodies[0].mass"), "{e}");
        let e = err(r#""name": "x""#, r#""name": "frame""#);
        assert!(e.starts_with("structure.bodies[0].name"), "{e}");
        let e = err(r#""observe": "x""#, r#""observe": "z""#);
        assert!(e.starts_with("observe: no body named \"z\""), "{e}");
        let e = err(r#""on": "x""#, r#""on": "q""#);
        assert!(e.starts_with("forcing.forces[0].on"), "{e}");
        let e = err(
            r#"{"forces": [{"on": "x", "amplitude": 1.5, "phase": 0.3}]}"#,
            r#"{"base": {"amplitude": 1.0}}"#,
        );
        assert!(e.starts_with("forcing.base: no spring or dashpot"), "{e}");
        let e = err(r#""restitution": 0.8"#, r#""restitution": 1.2"#);
        assert!(e.starts_with("structure.stops[0].restitution"), "{e}");
    }

    /// A body no spring holds (a free impact mass) is a structure when stops hold it both
    /// ways against held ends; a group nothing holds, or holds one way only, is refused,
    /// naming it and the open direction.
    #[test]
    fn a_free_body_needs_stops_on_both_sides() {
        let damper = |stops: &str| {
            parse(&format!(
                r#"{{"structure": {{
                     "bodies": [{{"name": "primary", "mass": 2.0}}, {{"name": "ball", "mass": 0.1}},
                                {{"name": "pebble", "mass": 0.01}}],
                     "springs": [{{"between": ["frame", "primary"], "stiffness": 6.0}}],
                     "stops": [{stops}]}},
                   "forcing": {{"forces": [{{"on": "primary", "amplitude": 1.0}}]}}}}"#
            ))
        };
        let inside = r#"{"between": ["primary", "ball"], "gap": 0.5, "restitution": 0.8},
                        {"between": ["ball", "pebble"], "gap": 0.1, "restitution": 0.5}"#;
        let s = damper(inside).unwrap();
        assert_eq!(s.stiffness[(1, 1)], 0.0);
        assert_eq!(s.floating, [None, Some(1), Some(2)]);
        let walls = r#"{"between": ["frame", "ball"], "gap_plus": 0.5, "restitution": 0.8},
                       {"between": ["ball", "frame"], "gap_plus": 0.5, "restitution": 0.8},
                       {"between": ["pebble", "primary"], "gap": 0.1, "restitution": 0.5}"#;
        assert!(damper(walls).is_ok());
        let one_sided = r#"{"between": ["primary", "ball"], "gap_plus": 0.5, "restitution": 0.8},
                           {"between": ["ball", "pebble"], "gap": 0.1, "restitution": 0.5}"#;
        let e = damper(one_sided).unwrap_err().to_string();
        assert!(
            e.starts_with("structure.stops: nothing holds body ball:")
                && e.contains("towards shrinking u"),
            "{e}"
        );
        let loose = r#"{"between": ["primary", "ball"], "gap": 0.5, "restitution": 0.8}"#;
        let e = damper(loose).unwrap_err().to_string();
        assert!(
            e.starts_with("structure.stops: nothing holds body pebble"),
            "{e}"
        );
        let e = parse(
            r#"{"structure": {
                 "bodies": [{"name": "a", "mass": 2.0}, {"name": "b", "mass": 1.0}],
                 "springs": [{"between": ["a", "b"], "stiffness": 6.0}]},
               "forcing": {"forces": [{"on": "a", "amplitude": 1.0}]}}"#,
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("structure.stops: nothing holds bodies a, b"),
            "{e}"
        );
        // A dashpot to the frame holds a body's mean (its velocity decays to the forced one).
        let e = parse(
            r#"{"structure": {
                 "bodies": [{"name": "a", "mass": 2.0}],
                 "dashpots": [{"between": ["frame", "a"], "damping": 0.5}]},
               "forcing": {"forces": [{"on": "a", "amplitude": 1.0}]}}"#,
        );
        assert!(e.is_ok(), "{e:?}");
    }
}
