//! A number of a scene in the structure form named by its JSON path, read and set: the
//! parameter a two-parameter study varies beside the frequency on a structure
//! (`structure.stops[0].gap_plus`, `structure.bodies[1].mass`, `forcing.forces[0].amplitude`,
//! `forcing.base.harmonics[0].amplitude`, `forcing.forces[0].harmonics[1].phase`).
//!
//! The paths are the scene file's own: a list's entry by its index from 0, then its field.
//! `structure.stops[K].gap` names both sides' distance and is taken only on a stop whose two
//! sides are equal (set, it moves both); `gap_plus` and `gap_minus` name one side each (set on a
//! stop written with `gap`, the stop is written out side by side first, so that only that side
//! moves). A side the stop does not have, a base the scene does not move and an index beyond
//! its list are refused naming the path. Every value set is checked by the structure's own
//! checks ([`StructureScene::structure`]), so a value out of a field's range is refused with the
//! range.

use super::structure::{StructureError, StructureForm, StructureScene, StructureSpec};
use std::fmt;
use std::str::FromStr;
use thiserror::Error;

/// A field of a structure scene that a [`StructureParameter`] can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StructureField {
    /// `structure.bodies[K].mass`, kg.
    Mass,
    /// `structure.springs[K].stiffness`, N/m.
    Stiffness,
    /// `structure.dashpots[K].damping`, N·s/m.
    Damping,
    /// `structure.stops[K].gap`: both sides' distance, m.
    Gap,
    /// `structure.stops[K].gap_plus`: the distance to side 1, m.
    GapPlus,
    /// `structure.stops[K].gap_minus`: the distance to side 2, m.
    GapMinus,
    /// `structure.stops[K].restitution` (a rigid stop's).
    Restitution,
    /// `structure.stops[K].contact_stiffness`, N/m (a compliant stop's).
    ContactStiffness,
    /// `structure.stops[K].contact_damping`, N·s/m (a compliant stop's).
    ContactDamping,
    /// `forcing.base.amplitude`, `u_g`, m (no index).
    BaseAmplitude,
    /// `forcing.forces[K].amplitude`, N.
    ForceAmplitude,
    /// `forcing.forces[K].phase`, rad.
    ForcePhase,
    /// `forcing.base.harmonics[K].amplitude`, m.
    BaseHarmonicAmplitude,
    /// `forcing.base.harmonics[K].phase`, rad.
    BaseHarmonicPhase,
    /// `forcing.forces[J].harmonics[K].amplitude`, N.
    ForceHarmonicAmplitude,
    /// `forcing.forces[J].harmonics[K].phase`, rad.
    ForceHarmonicPhase,
}

impl StructureField {
    /// Every field, in the order of the scene format.
    pub const ALL: [StructureField; 16] = [
        StructureField::Mass,
        StructureField::Stiffness,
        StructureField::Damping,
        StructureField::Gap,
        StructureField::GapPlus,
        StructureField::GapMinus,
        StructureField::Restitution,
        StructureField::ContactStiffness,
        StructureField::ContactDamping,
        StructureField::BaseAmplitude,
        StructureField::ForceAmplitude,
        StructureField::ForcePhase,
        StructureField::BaseHarmonicAmplitude,
        StructureField::BaseHarmonicPhase,
        StructureField::ForceHarmonicAmplitude,
        StructureField::ForceHarmonicPhase,
    ];

    /// The list the field's entry belongs to (`structure.stops`), `None` for the base.
    pub fn list(self) -> Option<&'static str> {
        match self {
            StructureField::Mass => Some("structure.bodies"),
            StructureField::Stiffness => Some("structure.springs"),
            StructureField::Damping => Some("structure.dashpots"),
            StructureField::Gap
            | StructureField::GapPlus
            | StructureField::GapMinus
            | StructureField::Restitution
            | StructureField::ContactStiffness
            | StructureField::ContactDamping => Some("structure.stops"),
            StructureField::BaseAmplitude => None,
            StructureField::ForceAmplitude
            | StructureField::ForcePhase
            | StructureField::ForceHarmonicAmplitude
            | StructureField::ForceHarmonicPhase => Some("forcing.forces"),
            StructureField::BaseHarmonicAmplitude | StructureField::BaseHarmonicPhase => {
                Some("forcing.base.harmonics")
            }
        }
    }

    /// Whether the field is a force harmonic's: its path has two indices,
    /// `forcing.forces[J].harmonics[K]`.
    pub fn of_force_harmonic(self) -> bool {
        matches!(
            self,
            StructureField::ForceHarmonicAmplitude | StructureField::ForceHarmonicPhase
        )
    }

    /// The field's name within its entry (`gap_plus`), or the whole path for the base.
    pub fn name(self) -> &'static str {
        match self {
            StructureField::Mass => "mass",
            StructureField::Stiffness => "stiffness",
            StructureField::Damping => "damping",
            StructureField::Gap => "gap",
            StructureField::GapPlus => "gap_plus",
            StructureField::GapMinus => "gap_minus",
            StructureField::Restitution => "restitution",
            StructureField::ContactStiffness => "contact_stiffness",
            StructureField::ContactDamping => "contact_damping",
            StructureField::BaseAmplitude => "forcing.base.amplitude",
            StructureField::ForceAmplitude
            | StructureField::BaseHarmonicAmplitude
            | StructureField::ForceHarmonicAmplitude => "amplitude",
            StructureField::ForcePhase
            | StructureField::BaseHarmonicPhase
            | StructureField::ForceHarmonicPhase => "phase",
        }
    }

    /// The path's pattern, `structure.stops[K].gap_plus`
    /// (`forcing.forces[J].harmonics[K].phase` for a force harmonic's).
    pub fn pattern(self) -> String {
        match self.list() {
            Some(list) if self.of_force_harmonic() => {
                format!("{list}[J].harmonics[K].{}", self.name())
            }
            Some(list) => format!("{list}[K].{}", self.name()),
            None => self.name().to_owned(),
        }
    }
}

/// A number of a structure scene, by its JSON path: see the [module](self).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StructureParameter {
    /// The field.
    pub field: StructureField,
    /// The entry of the field's list (0 for the base, which has none; the force for a force
    /// harmonic's field).
    pub index: usize,
    /// The entry of a force's `harmonics` for a force harmonic's field (0 for any other).
    pub harmonic: usize,
}

/// Why a structure parameter path cannot be read or used on a scene. Every message names the
/// path.
#[derive(Debug, Error)]
pub enum StructureParameterError {
    /// The text is not a structure parameter path.
    #[error(
        "parameter `{path}` is not a field of a structure scene: give one of {}",
        StructureField::ALL.map(StructureField::pattern).join(", ")
    )]
    Unknown {
        /// The text as given.
        path: String,
    },
    /// The index is beyond the scene's list.
    #[error("parameter `{path}`: {list} has {count} entr{}: {}", if *count == 1 { "y" } else { "ies" }, range(*count))]
    IndexOutOfRange {
        /// The path as given.
        path: String,
        /// The list, e.g. `structure.stops` or `forcing.forces[0].harmonics`.
        list: String,
        /// Its length in the scene.
        count: usize,
    },
    /// The scene has no such number (a side without a stop, a base that does not move, a
    /// `gap` of a stop with unequal sides).
    #[error("parameter `{path}`: {reason}")]
    Absent {
        /// The path as given.
        path: String,
        /// Why, with the path to give instead where there is one.
        reason: String,
    },
    /// The value set makes the structure invalid.
    #[error("parameter {}", value_message(path, source))]
    Value {
        /// The path as given.
        path: String,
        /// The structure's own refusal, naming the field and its range.
        source: StructureError,
    },
}

/// The refusal of a value of `path`: the structure's reason, after the path once (the
/// structure names the field it refuses, which is the path itself unless another field
/// breaks, such as a body left unheld when a stop's gap changes).
fn value_message(path: &str, source: &StructureError) -> String {
    if source.field == path {
        format!("`{path}`: {}", source.reason)
    } else {
        format!("`{path}`: {source}")
    }
}

/// The indices a list of `count` entries takes, as words.
fn range(count: usize) -> String {
    match count {
        0 => "none to vary".to_owned(),
        n => format!("indices 0..={}", n - 1),
    }
}

impl FromStr for StructureParameter {
    type Err = StructureParameterError;

    /// Reads `structure.stops[0].gap_plus`, `forcing.base.amplitude`, ….
    fn from_str(path: &str) -> Result<Self, StructureParameterError> {
        let unknown = || StructureParameterError::Unknown {
            path: path.to_owned(),
        };
        if path == StructureField::BaseAmplitude.name() {
            return Ok(StructureParameter {
                field: StructureField::BaseAmplitude,
                index: 0,
                harmonic: 0,
            });
        }
        // `<list>[<index>].<name>`, the name `harmonics[<k>].<field>` for a force harmonic.
        let entry = |text: &str| -> Option<(usize, String)> {
            let (index, name) = text.split_once("].")?;
            Some((index.parse().ok()?, name.to_owned()))
        };
        let (list, rest) = path.split_once('[').ok_or_else(unknown)?;
        let (index, name) = entry(rest).ok_or_else(unknown)?;
        let (harmonic, name, two) = match name.strip_prefix("harmonics[") {
            Some(inner) => {
                let (k, name) = entry(inner).ok_or_else(unknown)?;
                (k, name, true)
            }
            None => (0, name, false),
        };
        let field = StructureField::ALL
            .into_iter()
            .find(|f| f.list() == Some(list) && f.name() == name && f.of_force_harmonic() == two)
            .ok_or_else(unknown)?;
        Ok(StructureParameter {
            field,
            index,
            harmonic,
        })
    }
}

impl fmt::Display for StructureParameter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.field.list() {
            Some(list) if self.field.of_force_harmonic() => write!(
                f,
                "{list}[{}].harmonics[{}].{}",
                self.index,
                self.harmonic,
                self.field.name()
            ),
            Some(list) => write!(f, "{list}[{}].{}", self.index, self.field.name()),
            None => f.write_str(self.field.name()),
        }
    }
}

impl StructureParameter {
    /// The parameter's value in `scene`.
    ///
    /// # Errors
    /// [`StructureParameterError::IndexOutOfRange`] for an entry beyond its list,
    /// [`StructureParameterError::Absent`] for a number the scene does not have.
    pub fn value(&self, scene: &StructureScene) -> Result<f64, StructureParameterError> {
        let mut copy = scene.clone();
        self.slot(&mut copy).map(|slot| *slot)
    }

    /// `scene` with this parameter set to `value`, with its checked structure.
    ///
    /// # Errors
    /// As [`StructureParameter::value`], and [`StructureParameterError::Value`] when `value`
    /// is outside the field's range (the structure's own message, with the range).
    pub fn with_value(
        &self,
        scene: &StructureScene,
        value: f64,
    ) -> Result<StructureForm, StructureParameterError> {
        let mut out = scene.clone();
        *self.slot(&mut out)? = value;
        let structure = out
            .structure()
            .map_err(|source| StructureParameterError::Value {
                path: self.to_string(),
                source,
            })?;
        Ok(StructureForm {
            scene: out,
            structure,
        })
    }

    /// Writes `value` at the path in `scene` without checking the structure: for a caller
    /// that sets several numbers and checks the scene once, as [`StructureScene::structure`]
    /// does.
    ///
    /// # Errors
    /// As [`StructureParameter::value`].
    pub fn set_unchecked(
        &self,
        scene: &mut StructureScene,
        value: f64,
    ) -> Result<(), StructureParameterError> {
        *self.slot(scene)? = value;
        Ok(())
    }

    /// The number the path names in `scene`, the scene rewritten where setting it needs (a
    /// stop written with `gap` written side by side for `gap_plus` or `gap_minus`; a stop with
    /// equal sides written with `gap` for `gap`).
    fn slot<'a>(
        &self,
        scene: &'a mut StructureScene,
    ) -> Result<&'a mut f64, StructureParameterError> {
        let path = self.to_string();
        let absent = |reason: String| StructureParameterError::Absent {
            path: path.clone(),
            reason,
        };
        let out_of_range = |count: usize| StructureParameterError::IndexOutOfRange {
            path: path.clone(),
            list: self.field.list().unwrap_or_default().to_owned(),
            count,
        };
        let k = self.index;
        let StructureScene {
            structure:
                StructureSpec {
                    bodies,
                    springs,
                    dashpots,
                    stops,
                },
            forcing,
            ..
        } = scene;
        Ok(match self.field {
            StructureField::Mass => {
                let n = bodies.len();
                &mut bodies.get_mut(k).ok_or_else(|| out_of_range(n))?.mass
            }
            StructureField::Stiffness => {
                let n = springs.len();
                &mut springs.get_mut(k).ok_or_else(|| out_of_range(n))?.stiffness
            }
            StructureField::Damping => {
                let n = dashpots.len();
                &mut dashpots.get_mut(k).ok_or_else(|| out_of_range(n))?.damping
            }
            StructureField::BaseAmplitude => {
                &mut forcing
                    .base
                    .as_mut()
                    .ok_or_else(|| {
                        absent("the scene's base does not move (no `forcing.base`)".into())
                    })?
                    .amplitude
            }
            StructureField::ForceAmplitude | StructureField::ForcePhase => {
                let n = forcing.forces.len();
                let force = forcing.forces.get_mut(k).ok_or_else(|| out_of_range(n))?;
                if self.field == StructureField::ForcePhase {
                    &mut force.phase
                } else {
                    &mut force.amplitude
                }
            }
            StructureField::BaseHarmonicAmplitude | StructureField::BaseHarmonicPhase => {
                let base = forcing.base.as_mut().ok_or_else(|| {
                    absent("the scene's base does not move (no `forcing.base`)".into())
                })?;
                let n = base.harmonics.len();
                harmonic_slot(
                    base.harmonics.get_mut(k).ok_or_else(|| out_of_range(n))?,
                    self.field,
                )
            }
            StructureField::ForceHarmonicAmplitude | StructureField::ForceHarmonicPhase => {
                let n = forcing.forces.len();
                let force = forcing.forces.get_mut(k).ok_or_else(|| out_of_range(n))?;
                let count = force.harmonics.len();
                let h = force.harmonics.get_mut(self.harmonic).ok_or_else(|| {
                    StructureParameterError::IndexOutOfRange {
                        path: path.clone(),
                        list: format!("forcing.forces[{k}].harmonics"),
                        count,
                    }
                })?;
                harmonic_slot(h, self.field)
            }
            StructureField::Restitution => {
                let n = stops.len();
                let stop = stops.get_mut(k).ok_or_else(|| out_of_range(n))?;
                stop.restitution.as_mut().ok_or_else(|| {
                    absent(format!(
                        "the stop is compliant (no `restitution`): vary \
                         `structure.stops[{k}].contact_stiffness` or `contact_damping`"
                    ))
                })?
            }
            StructureField::ContactStiffness | StructureField::ContactDamping => {
                let n = stops.len();
                let stop = stops.get_mut(k).ok_or_else(|| out_of_range(n))?;
                if stop.contact_stiffness.is_none() {
                    return Err(absent(format!(
                        "the stop is rigid (no `contact_stiffness`): vary \
                         `structure.stops[{k}].restitution`"
                    )));
                }
                if self.field == StructureField::ContactStiffness {
                    stop.contact_stiffness.get_or_insert(0.0)
                } else {
                    stop.contact_damping.get_or_insert(0.0)
                }
            }
            StructureField::Gap | StructureField::GapPlus | StructureField::GapMinus => {
                let n = stops.len();
                let stop = stops.get_mut(k).ok_or_else(|| out_of_range(n))?;
                let prefix = format!("structure.stops[{k}]");
                if let Some(gap) = stop.gap.take() {
                    (stop.gap_plus, stop.gap_minus) = (Some(gap), Some(gap));
                }
                match self.field {
                    StructureField::Gap => {
                        let (Some(plus), Some(minus)) = (stop.gap_plus, stop.gap_minus) else {
                            return Err(absent(format!(
                                "the stop has one side only: give `{prefix}.gap_plus` or \
                                 `{prefix}.gap_minus`"
                            )));
                        };
                        if plus != minus {
                            return Err(absent(format!(
                                "the stop's sides differ ({plus} and {minus}): give \
                                 `{prefix}.gap_plus` or `{prefix}.gap_minus`"
                            )));
                        }
                        (stop.gap_plus, stop.gap_minus) = (None, None);
                        stop.gap.insert(plus)
                    }
                    StructureField::GapPlus => stop.gap_plus.as_mut().ok_or_else(|| {
                        absent(format!(
                            "the stop has no side 1 (no `gap_plus`): a side cannot be added by \
                             varying it; give `{prefix}.gap_minus`"
                        ))
                    })?,
                    _ => stop.gap_minus.as_mut().ok_or_else(|| {
                        absent(format!(
                            "the stop has no side 2 (no `gap_minus`): a side cannot be added by \
                             varying it; give `{prefix}.gap_plus`"
                        ))
                    })?,
                }
            }
        })
    }
}

/// A harmonic's amplitude or phase, as `field` names it.
fn harmonic_slot(h: &mut crate::scene::HarmonicSpec, field: StructureField) -> &mut f64 {
    match field {
        StructureField::BaseHarmonicPhase | StructureField::ForceHarmonicPhase => &mut h.phase,
        _ => &mut h.amplitude,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DAMPER: &str = r#"{"name": "damper",
        "structure": {
          "bodies":   [{"name": "primary", "mass": 1.0}, {"name": "ball", "mass": 0.1}],
          "springs":  [{"between": ["base", "primary"], "stiffness": 1.0}],
          "dashpots": [{"between": ["base", "primary"], "damping": 0.05}],
          "stops":    [{"between": ["primary", "ball"], "gap": 0.4, "restitution": 0.6},
                       {"between": ["frame", "primary"], "gap_plus": 2.0, "restitution": 0.9}]},
        "forcing": {"base": {"amplitude": 0.2,
                             "harmonics": [{"order": 3, "amplitude": 0.05, "phase": 0.2}]},
                    "forces": [{"on": "primary", "amplitude": 0.1, "phase": 0.3,
                                "harmonics": [{"order": 2, "amplitude": 0.02},
                                              {"order": 3, "amplitude": 0.01, "phase": 1.0}]}]}}"#;

    fn scene() -> StructureScene {
        serde_json::from_str(DAMPER).expect("the scene parses")
    }

    fn param(text: &str) -> StructureParameter {
        text.parse().unwrap_or_else(|e| panic!("{text}: {e}"))
    }

    #[test]
    fn every_field_reads_back_what_is_set_and_nothing_else_moves() {
        let scene = scene();
        let paths = [
            "structure.bodies[1].mass",
            "structure.springs[0].stiffness",
            "structure.dashpots[0].damping",
            "structure.stops[0].gap",
            "structure.stops[0].gap_plus",
            "structure.stops[0].gap_minus",
            "structure.stops[1].gap_plus",
            "structure.stops[1].restitution",
            "forcing.base.amplitude",
            "forcing.forces[0].amplitude",
            "forcing.forces[0].phase",
            "forcing.base.harmonics[0].amplitude",
            "forcing.base.harmonics[0].phase",
            "forcing.forces[0].harmonics[0].amplitude",
            "forcing.forces[0].harmonics[1].phase",
        ];
        for text in paths {
            let p = param(text);
            assert_eq!(p.to_string(), text);
            let set = p
                .with_value(&scene, 0.375)
                .expect("0.375 is in every range");
            assert_eq!(p.value(&set.scene).ok(), Some(0.375), "{text}");
            for other in paths.iter().filter(|&&o| o != text) {
                let q = param(other);
                let moves_with = |a: &str, b: &str| {
                    // `gap` is both sides of the first stop: it moves with each side.
                    let gaps = [
                        "structure.stops[0].gap",
                        "structure.stops[0].gap_plus",
                        "structure.stops[0].gap_minus",
                    ];
                    a == "structure.stops[0].gap" && gaps.contains(&b)
                };
                if moves_with(text, other) {
                    assert_eq!(q.value(&set.scene).ok(), Some(0.375), "{text} → {other}");
                } else if moves_with(other, text) {
                    // Setting one side makes the stop's sides unequal: `gap` has no value.
                    assert!(q.value(&set.scene).is_err(), "{text} → {other}");
                } else {
                    assert_eq!(
                        q.value(&set.scene).ok(),
                        q.value(&scene).ok(),
                        "{text} moved {other}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_checked_structure_follows_the_value_set() {
        let set = param("structure.stops[0].gap_minus")
            .with_value(&scene(), 0.25)
            .expect("valid");
        let stop = set.structure.stops[0];
        assert_eq!((stop.gap_plus, stop.gap_minus), (0.4, 0.25));
        let set = param("structure.bodies[1].mass")
            .with_value(&scene(), 0.5)
            .expect("valid");
        assert_eq!(set.structure.mass[(1, 1)], 0.5);
    }

    #[test]
    fn bad_paths_and_values_are_refused_naming_the_path_and_the_range() {
        for text in [
            "structure.stops[0].gapp",
            "structure.stop[0].gap",
            "stops.gap",
            "structure.stops[x].gap",
            "structure.stops[0]gap",
            "forcing.forces[0].mass",
            "forcing.forces[0].harmonics[0].order",
            "forcing.base.harmonics[0].harmonics[0].phase",
            "forcing.forces[0].harmonics[x].phase",
        ] {
            let e = text.parse::<StructureParameter>().expect_err(text);
            assert!(e.to_string().contains(text), "{e}");
            assert!(e.to_string().contains("structure.stops[K].gap_plus"), "{e}");
        }
        let e = param("structure.stops[2].gap")
            .value(&scene())
            .expect_err("2 stops");
        assert!(e.to_string().contains("indices 0..=1"), "{e}");
        let e = param("structure.stops[1].gap_minus")
            .value(&scene())
            .expect_err("one-sided");
        assert!(e.to_string().contains("no side 2"), "{e}");
        let e = param("structure.stops[1].gap")
            .value(&scene())
            .expect_err("one side");
        assert!(e.to_string().contains("gap_plus"), "{e}");
        let e = param("structure.bodies[0].mass")
            .with_value(&scene(), -1.0)
            .expect_err("negative");
        let text = e.to_string();
        assert!(
            text.contains("structure.bodies[0].mass") && text.contains("> 0"),
            "{text}"
        );
        let e = param("structure.stops[0].restitution")
            .with_value(&scene(), 1.5)
            .expect_err("above 1");
        assert!(e.to_string().contains("[0, 1]"), "{e}");
        let e = param("forcing.forces[0].harmonics[2].phase")
            .value(&scene())
            .expect_err("2 harmonics");
        let text = e.to_string();
        assert!(
            text.contains("forcing.forces[0].harmonics has 2 entries") && text.contains("0..=1"),
            "{text}"
        );
        let e = param("forcing.base.harmonics[0].phase")
            .with_value(&scene(), f64::INFINITY)
            .expect_err("not finite");
        let text = e.to_string();
        assert!(
            text.contains("forcing.base.harmonics[0].phase") && text.contains("finite"),
            "{text}"
        );
        let mut still = scene();
        still.forcing.base = None;
        let e = param("forcing.base.amplitude")
            .value(&still)
            .expect_err("no base");
        assert!(e.to_string().contains("does not move"), "{e}");
    }
}
