//! The analytic picture at one frequency: the linear steady state and every two-impact orbit.

use crate::scene::Scene;
use rattle_analytic::{
    asymmetric_orbits, linear_response, symmetric_orbits, LinearResponse, Orbit, OrbitError,
};

/// How many grid intervals on `β ∈ (0, 1)` bracket the asymmetric orbits.
pub const BETA_SAMPLES: usize = 400;

/// What the analytic solver says about a scene at one frequency.
#[derive(Debug, Clone)]
pub struct AnalyticPoint {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The linear steady state (stops ignored).
    pub linear: LinearResponse,
    /// Two-impact orbits with their branch numbers: symmetric branches 0 and 1 first, then
    /// asymmetric ones (numbered from 2) if asked for. Empty without stops.
    pub orbits: Vec<(usize, Orbit)>,
}

/// Solves the scene at `omega`; `asymmetric` also searches `β ≠ ½`.
pub fn analyse(scene: &Scene, omega: f64, asymmetric: bool) -> Result<AnalyticPoint, OrbitError> {
    let unit = scene.unit_model();
    let linear = linear_response(&unit, omega);
    let mut orbits = Vec::new();
    if let Some(stops) = scene.stops_model() {
        let symmetric = symmetric_orbits(&unit, &stops, omega)?;
        let count = symmetric.len();
        orbits.extend(symmetric.into_iter().enumerate());
        if asymmetric {
            let others = asymmetric_orbits(&unit, &stops, omega, BETA_SAMPLES);
            orbits.extend(
                others
                    .into_iter()
                    .enumerate()
                    .map(|(i, o)| (count.max(2) + i, o)),
            );
        }
    }
    Ok(AnalyticPoint {
        omega,
        linear,
        orbits,
    })
}
