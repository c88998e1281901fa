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
//!   structure. Each may carry `harmonics` ([`crate::scene::HarmonicSpec`]), `a cos(kωt + φ)`
//!   of integer order `k ≥ 2`, summed order by order into [`Structure::harmonics`].
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
//!
//! The module is split by job: the scene as written ([`StructureScene`]), its checks and
//! resolution into a [`Structure`] ([`StructureScene::structure`]), the grouping of the bodies
//! that springs and dashpots hold, which finds the floating ones and those nothing holds, and
//! the checked structure with each solver's model.

mod cells;
mod grounding;
mod model;
mod resolve;
mod spec;

pub use model::{ContactLaw, ForcingHarmonic, Stop, Structure};
pub use resolve::StructureError;
pub use spec::{
    BodySpec, DashpotSpec, ForceSpec, ForcingSpec, SpringSpec, StopSpec, StructureForm,
    StructureScene, StructureSpec,
};

/// Most bodies a structure may have: twice the chain's cell count (the simulator's dense modal
/// flow costs `O(n³)` to set up, as for a chain of [`crate::scene::MAX_CELLS`] cells).
pub const MAX_BODIES: usize = 2 * crate::scene::MAX_CELLS;

/// The fixed frame's name as an end of an element.
pub const FRAME: &str = "frame";
/// The moving base's name as an end of an element.
pub const BASE: &str = "base";

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
