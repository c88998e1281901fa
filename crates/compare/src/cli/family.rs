//! `rattle family`: the member of the two-impact family at `β`.

use super::orbit::orbit_table;
use super::{check_frequency, check_omega, load_unit, pretty, Common, RattleError};
use crate::output::finite;
use crate::output::records::{At, FamilyRecord, OrbitRecord};
use clap::Args;
use rattle_analytic::gap_for_beta;

/// Arguments of `rattle family`.
#[derive(Debug, Args)]
pub struct FamilyArgs {
    #[command(flatten)]
    #[allow(missing_docs)]
    pub common: Common,
    /// Fraction of the period from the side-1 to the side-2 impact, in (0, 1).
    #[arg(long, allow_hyphen_values = true)]
    pub beta: f64,
}

/// Runs `rattle family`.
///
/// # Errors
/// Bad arguments, a scene without stops; a numerical failure of the family solve.
pub fn run(args: FamilyArgs) -> Result<String, RattleError> {
    let omega = check_omega("--omega", args.common.omega)?;
    let beta = args.beta;
    if !(beta.is_finite() && beta > 0.0 && beta < 1.0) {
        return Err(RattleError::Argument(format!(
            "--beta = {beta} is out of range: must be in (0, 1)"
        )));
    }
    let scene = load_unit(&args.common.scene, "rattle family")?;
    check_frequency(&scene, "--omega", omega)?;
    let Some(stops) = scene.stops_model() else {
        return Err(RattleError::Argument(
            "the family needs stops: the scene has no `stops` (its restitution sets the impact law)".into(),
        ));
    };
    let unit = scene.unit_model();
    let point = gap_for_beta(&unit, stops.restitution, omega, beta)
        .map_err(|e| RattleError::Numerical(e.to_string()))?;
    let record = FamilyRecord {
        at: At::new(&scene, omega),
        gap_over_base_amplitude: finite(point.gap / unit.base_amplitude),
        orbit: OrbitRecord::new(&point.orbit, 0),
    };
    if args.common.json {
        return pretty(&record);
    }
    Ok(format!(
        "scene {} at ω = {omega} rad/s, β = {beta}: gap Δ*(β) = {:.9} (Δ*/u_g = {:.9})\n{}",
        scene.name,
        point.gap,
        point.gap / unit.base_amplitude,
        orbit_table(&[record.orbit])
    ))
}
