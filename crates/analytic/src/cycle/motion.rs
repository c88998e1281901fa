//! The motion of a periodic orbit of the unit at any time of its cycle, from its closed form:
//! flight after flight on the exact forced flow, from the state just after each impact.
//!
//! [`UnitMotion`] serves the orbits of any signature ([`SignatureOrbit`]) and the two-impact
//! orbits of the symmetric and β families ([`Orbit`]); callers sample it without touching the
//! flow itself.

use crate::cycle::SignatureOrbit;
use crate::flow::ForcedFlow;
use crate::orbit::Orbit;
use crate::unit::Unit;
use nalgebra::{Vector2, Vector4};

/// Where one flight starts: its time from the first impact, the state just after the impact
/// that opens it and the forcing phase `(cos θ, sin θ)` there.
#[derive(Debug, Clone)]
struct FlightStart {
    time: f64,
    state: Vector4<f64>,
    phase: Vector2<f64>,
}

/// The motion `x(t) = (u_o, u_i, u̇_o, u̇_i)` of a periodic orbit of a [`Unit`] over one cycle,
/// `t` measured from the orbit's first impact (the first canonical impact of a signature
/// orbit, the side-1 impact of a two-impact orbit).
#[derive(Debug, Clone)]
pub struct UnitMotion {
    flow: ForcedFlow,
    cycle: f64,
    flights: Vec<FlightStart>,
}

impl UnitMotion {
    /// The motion of `orbit`, an orbit of `unit`.
    pub fn of_signature_orbit(unit: &Unit, orbit: &SignatureOrbit) -> Self {
        let flow = ForcedFlow::new(unit, orbit.omega);
        let cycle = f64::from(orbit.period) * flow.period();
        let p0 = Vector2::new(orbit.alpha.cos(), orbit.alpha.sin());
        let flights = orbit
            .impact_phases
            .iter()
            .zip(&orbit.states_after_impacts)
            .map(|(&phase, &state)| {
                let time = phase * cycle;
                FlightStart {
                    time,
                    state,
                    phase: flow.transition(time).rotation * p0,
                }
            })
            .collect();
        Self {
            flow,
            cycle,
            flights,
        }
    }

    /// The motion of the two-impact `orbit`, an orbit of `unit`: its first flight from the
    /// side-1 impact, its second from the side-2 impact at `βT`.
    pub fn of_orbit(unit: &Unit, orbit: &Orbit) -> Self {
        let flow = ForcedFlow::new(unit, orbit.omega);
        let cycle = flow.period();
        let p0 = Vector2::new(orbit.alpha.cos(), orbit.alpha.sin());
        let side2 = orbit.beta * cycle;
        let flights = vec![
            FlightStart {
                time: 0.0,
                state: orbit.state_after_impact,
                phase: p0,
            },
            FlightStart {
                time: side2,
                state: orbit.state_after_side2,
                phase: flow.transition(side2).rotation * p0,
            },
        ];
        Self {
            flow,
            cycle,
            flights,
        }
    }

    /// Length of the cycle, `pT`.
    pub fn cycle(&self) -> f64 {
        self.cycle
    }

    /// The state at time `t ∈ [0, pT]` after the first impact; at an impact's time, the state
    /// just after it. A `t` outside the cycle continues the flight that holds the nearest end
    /// (the first flight before 0, the last after `pT`): the exact flow, not the orbit.
    pub fn state_at(&self, t: f64) -> Vector4<f64> {
        let j = self.flights.iter().rposition(|f| f.time <= t).unwrap_or(0);
        self.in_flight(j, t)
    }

    /// The state at time `t` as [`Self::state_at`], but at an impact's time the state just
    /// before it (the end of the flight it closes); at `t = 0` the state just after the first
    /// impact.
    pub fn state_before(&self, t: f64) -> Vector4<f64> {
        let j = self.flights.iter().rposition(|f| f.time < t).unwrap_or(0);
        self.in_flight(j, t)
    }

    /// The state at `t` along flight `j`.
    fn in_flight(&self, j: usize, t: f64) -> Vector4<f64> {
        let start = &self.flights[j];
        self.flow
            .transition(t - start.time)
            .apply(&start.state, &start.phase)
            .0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_models::{damped_paper_unit, paper_stops};
    use crate::{signature_orbits, symmetric_orbits, Signature};

    /// Every flight of a signature orbit ends, to the rounding of its exact flow, in the state
    /// just before the next impact, and the cycle closes on the state before the first.
    #[test]
    fn a_signature_orbit_flies_into_each_of_its_impacts() {
        let (unit, stops) = (damped_paper_unit(), paper_stops());
        let signature = Signature::parse("++--", 1).expect("a valid signature");
        let orbits = signature_orbits(&unit, &stops, 1.5, &signature);
        assert!(!orbits.is_empty());
        for orbit in &orbits {
            let motion = UnitMotion::of_signature_orbit(&unit, orbit);
            let n = orbit.impact_phases.len();
            let scale = orbit.states_before_impacts[0].norm();
            for j in 0..n {
                let (end, before) = match j + 1 {
                    k if k < n => (orbit.impact_phases[k] * motion.cycle(), k),
                    _ => (motion.cycle(), 0),
                };
                let reached = motion.state_before(end);
                let expected = orbit.states_before_impacts[before];
                assert!((reached - expected).norm() < 1e-10 * scale, "flight {j}");
                if before > 0 {
                    let after = motion.state_at(end);
                    assert_eq!(after, orbit.states_after_impacts[before]);
                }
            }
        }
    }

    /// The two-impact orbit's motion: the side-2 impact's states at `βT`, and the cycle closes.
    #[test]
    fn a_two_impact_orbit_flies_into_both_impacts() {
        let (unit, stops) = (damped_paper_unit(), paper_stops());
        let orbits = symmetric_orbits(&unit, &stops, 2.6).expect("the paper unit's orbits");
        assert!(!orbits.is_empty());
        for orbit in &orbits {
            let motion = UnitMotion::of_orbit(&unit, orbit);
            let side2 = orbit.beta * motion.cycle();
            let scale = orbit.state_before_impact.norm();
            let before2 = motion.state_before(side2);
            assert!((before2 - orbit.state_before_side2).norm() < 1e-10 * scale);
            assert_eq!(motion.state_at(side2), orbit.state_after_side2);
            let end = motion.state_before(motion.cycle());
            assert!((end - orbit.state_before_impact).norm() < 1e-10 * scale);
        }
    }
}
