//! The unit and chain forms written as structures: the same bodies, springs, dashpots and stops
//! drawn element by element, so that a scene of either form runs on the structure's road when
//! its base motion has harmonics (the unit's own road solves the single sine alone).
//!
//! A cell `j` of `N` has the bodies `outer{j}` and `inner{j}` (`outer`, `inner` for the unit);
//! `k_o` and `c_o` tie `outer{j}` to `outer{j-1}` (the first cell to the base), `k_i` and
//! `c_i` tie `inner{j}` to `outer{j}`, and the cell's stops confine
//! `r = u_inner − u_outer` to `[−Δ, Δ]` (stop `j`). The observed body is the last cell's outer
//! mass, as a chain's outputs observe it.

use super::spec::{
    BodySpec, DashpotSpec, ForcingSpec, SpringSpec, StopSpec, StructureScene, StructureSpec,
};
use super::BASE;
use crate::scene::{BaseSpec, Scene};

impl Scene {
    /// The scene in the structure form, driven by `base` (the scene's own base motion, or one
    /// with harmonics): the bodies, springs, dashpots and stops of every cell, named as the
    /// module describes. Dashpots of zero damping are left out.
    pub fn structure_scene(&self, base: BaseSpec) -> StructureScene {
        let cells = self.cell_scenes();
        let name = |kind: &str, j: usize| {
            if cells.len() == 1 {
                kind.to_owned()
            } else {
                format!("{kind}{j}")
            }
        };
        let mut spec = StructureSpec {
            bodies: Vec::new(),
            springs: Vec::new(),
            dashpots: Vec::new(),
            stops: Vec::new(),
        };
        for (j, cell) in cells.iter().enumerate() {
            let (outer, inner) = (name("outer", j), name("inner", j));
            let below = if j == 0 {
                BASE.to_owned()
            } else {
                name("outer", j - 1)
            };
            spec.bodies.push(BodySpec {
                name: outer.clone(),
                mass: cell.unit.outer_mass,
            });
            spec.bodies.push(BodySpec {
                name: inner.clone(),
                mass: cell.unit.inner_mass,
            });
            spec.springs.push(SpringSpec {
                between: [below.clone(), outer.clone()],
                stiffness: cell.unit.outer_stiffness,
            });
            spec.springs.push(SpringSpec {
                between: [outer.clone(), inner.clone()],
                stiffness: cell.unit.inner_stiffness,
            });
            let (c_o, c_i) = cell.damping.map_or((0.0, 0.0), |d| (d.outer, d.inner));
            for (ends, c) in [
                ([below, outer.clone()], c_o),
                ([outer.clone(), inner.clone()], c_i),
            ] {
                if c != 0.0 {
                    spec.dashpots.push(DashpotSpec {
                        between: ends,
                        damping: c,
                    });
                }
            }
            if let Some(stops) = cell.stops {
                spec.stops.push(StopSpec {
                    between: [outer, inner],
                    gap: Some(stops.gap),
                    gap_plus: None,
                    gap_minus: None,
                    restitution: stops.restitution,
                    contact_stiffness: stops.contact_stiffness,
                    contact_damping: stops.contact_damping,
                });
            }
        }
        StructureScene {
            name: self.name.clone(),
            structure: spec,
            forcing: ForcingSpec {
                base: Some(base),
                forces: Vec::new(),
            },
            observe: Some(name("outer", cells.len() - 1)),
        }
    }
}
