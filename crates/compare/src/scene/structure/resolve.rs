//! The checks of a structure as written and its resolution into a [`Structure`]: names to
//! indices, the matrices assembled element by element, the stops and the forcing checked, and
//! what has no bounded motion refused, naming the JSON path and the reason.

use super::grounding::Grounding;
use super::model::{ContactLaw, ForcingHarmonic, Stop, Structure};
use super::spec::{StopSpec, StructureScene};
use super::{End, BASE, FRAME, MAX_BODIES};
use crate::scene::{check_harmonics, HarmonicSpec};
use nalgebra::{DMatrix, DVector};
use thiserror::Error;

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
        let harmonics = self.forcing_harmonics(&names, &base_springs, &base_dashpots)?;
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
        let structure = Structure {
            names,
            mass,
            stiffness,
            damping: damped.then_some(damping),
            forcing_cos,
            forcing_sin,
            forcing_sin_per_omega,
            harmonics,
            base_stiffness: base_springs,
            base_damping: base_dashpots,
            stops,
            base_amplitude,
            observe,
            floating: sprung.floating(),
        };
        compliances_resolved(&structure)?;
        Ok(structure)
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
        let silent = |f: &super::spec::ForceSpec| {
            f.amplitude == 0.0 && f.harmonics.iter().all(|h| h.amplitude == 0.0)
        };
        if base_amplitude.is_none() && self.forcing.forces.iter().all(silent) {
            return Err(refuse(
                "forcing",
                "drives nothing: give `base` (with elements tied to \"base\") or `forces`",
            ));
        }
        Ok((base_amplitude, cos, sin, sin_per_omega))
    }

    /// The forcing's higher harmonics, one per order by increasing order: the base's (its
    /// springs times `a_k`, its dashpots times `−a_k` per unit `kω`, at its phase) and the
    /// forces' on their bodies (their phases folded in against it).
    fn forcing_harmonics(
        &self,
        names: &[String],
        base_springs: &DVector<f64>,
        base_dashpots: &DVector<f64>,
    ) -> Result<Vec<ForcingHarmonic>, StructureError> {
        let n = names.len();
        let checked = |field: String, list: &[HarmonicSpec]| {
            check_harmonics(&field, list).map_err(|(field, reason)| refuse(field, reason))
        };
        let mut harmonics: Vec<ForcingHarmonic> = Vec::new();
        let mut of_order = |order: u32, phase: f64| -> usize {
            match harmonics.iter().position(|h| h.order == order) {
                Some(i) => i,
                None => {
                    harmonics.push(ForcingHarmonic {
                        order,
                        cosine: DVector::zeros(n),
                        sine: DVector::zeros(n),
                        sine_per_omega: DVector::zeros(n),
                        phase,
                    });
                    harmonics.len() - 1
                }
            }
        };
        let mut slots = Vec::new();
        if let Some(base) = &self.forcing.base {
            checked("forcing.base.harmonics".to_owned(), &base.harmonics)?;
            for h in &base.harmonics {
                slots.push((of_order(h.order, h.phase), None, *h));
            }
        }
        for (j, force) in self.forcing.forces.iter().enumerate() {
            checked(format!("forcing.forces[{j}].harmonics"), &force.harmonics)?;
            let body = names.iter().position(|b| *b == force.on).ok_or_else(|| {
                refuse(
                    format!("forcing.forces[{j}].on"),
                    format!("no body named {:?}", force.on),
                )
            })?;
            for h in &force.harmonics {
                slots.push((of_order(h.order, 0.0), Some(body), *h));
            }
        }
        for (i, body, h) in slots {
            let entry = &mut harmonics[i];
            match body {
                None => {
                    entry.cosine += base_springs * h.amplitude;
                    entry.sine_per_omega -= base_dashpots * h.amplitude;
                }
                Some(j) => {
                    let (s, c) = (h.phase - entry.phase).sin_cos();
                    entry.cosine[j] += h.amplitude * c;
                    entry.sine[j] -= h.amplitude * s;
                }
            }
        }
        harmonics.sort_by_key(|h| h.order);
        Ok(harmonics)
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
    Ok(Stop {
        plus,
        minus,
        gap_plus,
        gap_minus,
        law: contact_law(field, stop)?,
    })
}

/// The analytic model's refusal of a compliant stop, named by the stop's JSON path: a contact
/// stiffness whose time scale falls below the rounding of the cycle's times
/// ([`rattle_analytic::MAX_CONTACT_FREQUENCY_RATIO`] times the structure's fastest rate; the
/// simulator's own bound, against the forcing frequency, bounds the frequencies the scene is
/// run at instead).
fn compliances_resolved(structure: &Structure) -> Result<(), StructureError> {
    if !structure.has_compliant_stops() {
        return Ok(());
    }
    match structure.analytic_model() {
        Err(rattle_analytic::ModelError::OutOfRange {
            field,
            value,
            allowed,
        }) if field.starts_with("compliances[") => {
            let stop = field
                .trim_start_matches("compliances[")
                .split(']')
                .next()
                .unwrap_or_default();
            Err(refuse(
                format!("structure.stops[{stop}].contact_stiffness"),
                format!("{value} is out of range: must be {allowed}"),
            ))
        }
        _ => Ok(()),
    }
}

/// A stop's contact law: rigid with its restitution, or compliant with its contact stiffness
/// and damping; exactly one of the two, each value in range.
fn contact_law(field: &str, stop: &StopSpec) -> Result<ContactLaw, StructureError> {
    match (
        stop.restitution,
        stop.contact_stiffness,
        stop.contact_damping,
    ) {
        (Some(_), Some(_), _) => Err(refuse(
            format!("{field}.contact_stiffness"),
            "give either `restitution` (a rigid stop) or `contact_stiffness` (a compliant \
             stop), not both",
        )),
        (Some(_), None, Some(_)) => Err(refuse(
            format!("{field}.contact_damping"),
            "a rigid stop (`restitution`) has no contact damping: give `contact_stiffness` \
             for a compliant stop",
        )),
        (None, None, _) => Err(refuse(
            format!("{field}.restitution"),
            "missing: a stop needs `restitution` (rigid) or `contact_stiffness` (compliant)",
        )),
        (Some(e), None, None) => {
            if (0.0..=1.0).contains(&e) {
                Ok(ContactLaw::Rigid { restitution: e })
            } else {
                Err(refuse(
                    format!("{field}.restitution"),
                    format!("{e} is out of range: must be in [0, 1]"),
                ))
            }
        }
        (None, Some(stiffness), damping) => {
            positive(&format!("{field}.contact_stiffness"), stiffness)?;
            let damping = damping.unwrap_or(0.0);
            if !(damping.is_finite() && damping >= 0.0) {
                return Err(refuse(
                    format!("{field}.contact_damping"),
                    format!("{damping} is out of range: must be finite and ≥ 0"),
                ));
            }
            Ok(ContactLaw::Compliant { stiffness, damping })
        }
    }
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

    #[test]
    fn a_compliant_stop_has_its_law_and_bad_laws_are_refused_by_field() {
        let compliant = |law: &str| OSCILLATOR.replace(r#""restitution": 0.8"#, law);
        let s = parse(&compliant(
            r#""contact_stiffness": 400.0, "contact_damping": 2.0"#,
        ))
        .unwrap();
        assert_eq!(
            s.stops[0].law,
            ContactLaw::Compliant {
                stiffness: 400.0,
                damping: 2.0
            }
        );
        let s = parse(&compliant(r#""contact_stiffness": 400.0"#)).unwrap();
        assert_eq!(
            s.stops[0].law,
            ContactLaw::Compliant {
                stiffness: 400.0,
                damping: 0.0
            }
        );
        assert_eq!(s.stops[0].law.restitution(), None);
        let plastic = parse(&compliant(r#""restitution": 0.0"#)).unwrap();
        assert_eq!(plastic.stops[0].law.restitution(), Some(0.0));
        let refused = |law: &str, field: &str, words: &str| {
            let e = parse(&compliant(law)).unwrap_err().to_string();
            assert!(
                e.starts_with(&format!("structure.stops[0].{field}")) && e.contains(words),
                "{law}: {e}"
            );
        };
        refused(
            r#""restitution": 0.8, "contact_stiffness": 400.0"#,
            "contact_stiffness",
            "not both",
        );
        refused(
            r#""restitution": 0.8, "contact_damping": 2.0"#,
            "contact_damping",
            "no contact damping",
        );
        refused(r#""contact_damping": 2.0"#, "restitution", "missing");
        refused(
            r#""contact_stiffness": -400.0"#,
            "contact_stiffness",
            "must be finite and > 0",
        );
        refused(
            r#""contact_stiffness": 0.0"#,
            "contact_stiffness",
            "must be finite and > 0",
        );
        refused(
            r#""contact_stiffness": 400.0, "contact_damping": -1.0"#,
            "contact_damping",
            "must be finite and ≥ 0",
        );
        refused(r#""restitution": 1.5"#, "restitution", "[0, 1]");
    }
}
