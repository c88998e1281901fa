//! A structure scene as written: its bodies, springs, dashpots and stops, what drives it and
//! the observed body, each read from JSON as the user gives it, unchecked.

use super::model::Structure;
use serde::{Deserialize, Serialize};

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
    /// The stops (rigid with Newton restitution, or compliant): the contact pairs.
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
    /// A rigid stop's Newton restitution `e ∈ [0, 1]`: `ṙ⁺ = −e ṙ⁻` (0: plastic, the pair
    /// sticks). Not with `contact_stiffness`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// A compliant (Kelvin–Voigt) stop's contact stiffness `k_c`, N/m, `> 0`: while the
    /// penetration `δ > 0` a spring `k_c` and a dashpot `c_c` act between the pair. Not with
    /// `restitution`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_stiffness: Option<f64>,
    /// A compliant stop's contact damping `c_c`, N·s/m, `≥ 0` (default 0); only with
    /// `contact_stiffness`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_damping: Option<f64>,
}

/// What drives a structure.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForcingSpec {
    /// The base motion `u_g cos ωt` and its harmonics, through the springs and dashpots tied
    /// to `"base"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<crate::scene::BaseSpec>,
    /// Forces on bodies.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub forces: Vec<ForceSpec>,
}

/// A periodic force `F cos(ωt + φ) + Σ F_k cos(kωt + φ_k)` on one body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForceSpec {
    /// The body's name.
    pub on: String,
    /// `F`, N, finite: the fundamental's amplitude.
    pub amplitude: f64,
    /// `φ`, rad, finite (default 0).
    #[serde(default)]
    pub phase: f64,
    /// The higher harmonics, each order once (empty: the fundamental alone).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub harmonics: Vec<crate::scene::HarmonicSpec>,
}

/// A scene in the structure form with its checked structure.
#[derive(Debug, Clone, PartialEq)]
pub struct StructureForm {
    /// The scene as written.
    pub scene: StructureScene,
    /// The checked structure.
    pub structure: Structure,
}
