//! A unit's or a cell's stops as written: rigid with a restitution, or compliant with a
//! contact stiffness and damping.

use serde::{Deserialize, Serialize};

/// The stops at `r = u_i − u_o = ±gap`: rigid (`restitution`) or compliant
/// (`contact_stiffness`, `contact_damping`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopsSpec {
    /// `Δ`, m: half the clearance.
    pub gap: f64,
    /// Rigid stops' Newton restitution `e ∈ [0, 1]` (0: plastic, the pair sticks). Not with
    /// `contact_stiffness`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// Compliant (Kelvin–Voigt) stops' contact stiffness `k_c`, N/m, `> 0`. Not with
    /// `restitution`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_stiffness: Option<f64>,
    /// Compliant stops' contact damping `c_c`, N·s/m, `≥ 0` (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_damping: Option<f64>,
}

impl StopsSpec {
    /// Rigid stops at `±gap` with restitution `restitution`.
    pub fn rigid(gap: f64, restitution: f64) -> StopsSpec {
        StopsSpec {
            gap,
            restitution: Some(restitution),
            contact_stiffness: None,
            contact_damping: None,
        }
    }

    /// Whether the stops are compliant (they have a contact stiffness).
    pub fn is_compliant(&self) -> bool {
        self.contact_stiffness.is_some()
    }

    /// The rigid stops' restitution. Compliant stops have none and give NaN: the unit and
    /// chain roads never hold them ([`crate::scene::AnyScene::of_cells`] writes such a scene as a
    /// structure), and a number computed from a NaN is not mistaken for one.
    pub fn rigid_restitution(&self) -> f64 {
        self.restitution.unwrap_or(f64::NAN)
    }

    /// The reason the stops' contact law is refused, if it is: the field within the stops
    /// (`contact_damping`) and what is wrong. Exactly one law: `restitution`, or
    /// `contact_stiffness` with an optional `contact_damping`; a compliant stop's gap finite
    /// and `> 0` (a rigid one's is checked with its restitution).
    pub(crate) fn law_error(&self) -> Option<(&'static str, String)> {
        match (
            self.restitution,
            self.contact_stiffness,
            self.contact_damping,
        ) {
            (Some(_), Some(_), _) => Some((
                "contact_stiffness",
                "give either `restitution` (rigid stops) or `contact_stiffness` (compliant \
                 stops), not both"
                    .into(),
            )),
            (Some(_), None, Some(_)) => Some((
                "contact_damping",
                "rigid stops (`restitution`) have no contact damping: give `contact_stiffness` \
                 for compliant stops"
                    .into(),
            )),
            (None, None, _) => Some((
                "restitution",
                "missing: stops need `restitution` (rigid) or `contact_stiffness` (compliant)"
                    .into(),
            )),
            (Some(_), None, None) => None,
            (None, Some(k), c) => {
                let c = c.unwrap_or(0.0);
                if !(self.gap.is_finite() && self.gap > 0.0) {
                    Some(("gap", format!("{} is out of range: must be > 0", self.gap)))
                } else if !(k.is_finite() && k > 0.0) {
                    Some((
                        "contact_stiffness",
                        format!("{k} is out of range: must be finite and > 0"),
                    ))
                } else if !(c.is_finite() && c >= 0.0) {
                    Some((
                        "contact_damping",
                        format!("{c} is out of range: must be finite and ≥ 0"),
                    ))
                } else {
                    None
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::{structure, AnyScene, Scene, PAPER_SCENE};

    #[test]
    fn compliant_stops_take_the_structure_road_and_bad_laws_are_refused_by_path() {
        let compliant = PAPER_SCENE.replace(
            r#""restitution": 0.8"#,
            r#""contact_stiffness": 400.0, "contact_damping": 2.0"#,
        );
        let AnyScene::Structure(form) = AnyScene::parse(&compliant, "x.json").unwrap() else {
            panic!("a unit with compliant stops is written as a structure");
        };
        assert_eq!(
            form.structure.stops[0].law,
            structure::ContactLaw::Compliant {
                stiffness: 400.0,
                damping: 2.0
            }
        );
        let e = Scene::parse(&compliant, "x.json").unwrap_err().to_string();
        assert!(
            e.starts_with("x.json: stops.contact_stiffness: this command solves"),
            "{e}"
        );
        let refused = |law: &str, path: &str, words: &str| {
            let text = PAPER_SCENE.replace(r#""restitution": 0.8"#, law);
            let e = AnyScene::parse(&text, "x.json").unwrap_err().to_string();
            assert!(
                e.starts_with(&format!("x.json: {path}")) && e.contains(words),
                "{law}: {e}"
            );
        };
        refused(
            r#""restitution": 0.8, "contact_stiffness": 400.0"#,
            "stops.contact_stiffness",
            "not both",
        );
        refused(r#""contact_damping": 2.0"#, "stops.restitution", "missing");
        refused(
            r#""contact_stiffness": -1.0"#,
            "stops.contact_stiffness",
            "must be finite and > 0",
        );
        refused(
            r#""contact_stiffness": 4.0, "contact_damping": -2.0"#,
            "stops.contact_damping",
            "≥ 0",
        );
        let chain = |cells: &str| {
            let text = PAPER_SCENE.trim_end().trim_end_matches('}').to_owned() + "," + cells + "}";
            AnyScene::parse(&text, "x.json")
        };
        let Ok(AnyScene::Structure(form)) =
            chain(r#""chain": [{}, {"stops": {"gap": 0.2, "contact_stiffness": 100.0}}]"#)
        else {
            panic!("a chain with a compliant cell is written as a structure");
        };
        let laws: Vec<_> = form.structure.stops.iter().map(|s| s.law).collect();
        assert_eq!(
            laws,
            [
                structure::ContactLaw::Rigid { restitution: 0.8 },
                structure::ContactLaw::Compliant {
                    stiffness: 100.0,
                    damping: 0.0
                }
            ]
        );
        let e = chain(
            r#""chain": [{}, {"stops": {"gap": 0.2, "contact_stiffness": 100.0, "restitution": 0.5}}]"#,
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("x.json: chain[1].stops.contact_stiffness"),
            "{e}"
        );
    }
}
