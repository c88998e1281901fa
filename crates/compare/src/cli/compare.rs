//! `rattle compare`: both solvers on the motion the unit settles on, whatever its signature.

use super::{check_omega, heading, load_any, pretty, Accuracy, Common, RattleError};
use crate::api::{self, Comparison};
use crate::output::records::{ChainCompareRecord, CrossCheckRecord};
use crate::scene::{AnyScene, Scene};
use clap::Args;
use std::fmt::Write as _;

/// Arguments of `rattle compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    #[command(flatten)]
    #[allow(missing_docs)]
    pub common: Common,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub accuracy: Accuracy,
}

/// Runs `rattle compare`.
///
/// # Errors
/// Bad arguments or scene; a failure of the simulator.
pub fn run(args: CompareArgs) -> Result<String, RattleError> {
    let omega = check_omega("--omega", args.common.omega)?;
    let options = args.accuracy.options()?;
    let any = load_any(&args.common.scene)?;
    api::check_frequency(&any, "--omega", omega)?;
    let comparison = api::compare(&any, omega, &options)?;
    if args.common.json {
        return pretty(&comparison);
    }
    Ok(match (&any, &comparison) {
        (AnyScene::Cells(scene), Comparison::Unit(r)) => unit_table(scene, omega, r),
        (AnyScene::Cells(scene), Comparison::Chain(r)) => chain_table(scene, omega, r),
        (AnyScene::Structure(form), Comparison::Structure(r)) => {
            super::structure::comparison_table(form, omega, r)
        }
        _ => unreachable!("a comparison has the form of its scene"),
    })
}

/// The table `rattle compare` prints for a single unit's record `r`.
fn unit_table(scene: &Scene, omega: f64, r: &CrossCheckRecord) -> String {
    let mut out = heading(scene, omega);
    let num = |x: Option<f64>| x.map_or("-".to_owned(), |v| format!("{v:.9}"));
    let _ = writeln!(
        out,
        "simulated from rest: {}, signature {}, period {}, X_o = {}",
        r.simulated.status,
        r.simulated.signature.as_deref().unwrap_or("-"),
        r.simulated.period.map_or("-".to_owned(), |p| p.to_string()),
        num(r.simulated.outer_amplitude)
    );
    match &r.analytic {
        Some(a) => {
            let _ = writeln!(
                out,
                "analytic {} orbit from the simulated phases: X_o = {}, viable {}, stable {}, energy residual {:.1e}",
                a.signature,
                num(a.outer_amplitude),
                a.viable,
                a.stable,
                a.energy_residual.unwrap_or(f64::NAN)
            );
        }
        None => {
            let _ = writeln!(
                out,
                "analytic: {}",
                r.analytic_error.as_deref().unwrap_or("nothing to solve")
            );
        }
    }
    out.push_str(&super::class_line(
        r.class,
        &super::detail(&r.class_detail),
        r.relative_difference,
        r.multiplier_difference,
    ));
    for k in &r.confirmed_orbits {
        let _ = writeln!(
            out,
            "viable analytic orbit α = {}, stable {}: {} by the simulator's Newton{}",
            num(k.alpha),
            k.stable,
            if k.confirmed {
                "confirmed"
            } else {
                "not confirmed"
            },
            k.error
                .as_ref()
                .map_or(String::new(), |e| format!(" ({e})"))
        );
    }
    out
}

/// The table `rattle compare` prints for a chain's record `r`.
fn chain_table(scene: &Scene, omega: f64, r: &ChainCompareRecord) -> String {
    let mut out = heading(scene, omega);
    let num = |x: Option<f64>| x.map_or("-".to_owned(), |v| format!("{v:.9}"));
    let signatures = r
        .simulated
        .pair_signatures
        .as_ref()
        .map_or("-".to_owned(), |l| {
            l.iter()
                .map(|s| match s.as_deref() {
                    Some("") => "·".to_owned(),
                    Some(s) => s.to_owned(),
                    None => "?".to_owned(),
                })
                .collect::<Vec<_>>()
                .join(" | ")
        });
    let _ = writeln!(
        out,
        "chain of {} cells simulated from rest: {}, period {}, pair signatures {signatures}, X_N = {}",
        r.cells,
        r.simulated.status,
        r.simulated.period.map_or("-".to_owned(), |p| p.to_string()),
        num(r.simulated.outer_amplitude)
    );
    match &r.analytic {
        Some(a) => {
            let _ = writeln!(
                out,
                "analytic orbit of {} from the simulated impact times: X_N = {}, viable {}, stable {}, energy residual {:.1e}",
                a.sequence,
                num(a.outer_amplitude),
                a.viable,
                a.stable,
                a.energy_residual.unwrap_or(f64::NAN)
            );
        }
        None => {
            let _ = writeln!(
                out,
                "analytic: {}",
                r.analytic_error
                    .as_deref()
                    .unwrap_or("no impact sequence to solve")
            );
        }
    }
    out.push_str(&super::class_line(
        r.class,
        &r.reason
            .map_or(String::new(), |w| format!(" ({w}: {})", r.class_detail)),
        r.relative_difference,
        r.multiplier_difference,
    ));
    if let Some(k) = &r.confirmation {
        let _ = writeln!(
            out,
            "the analytic orbit {} by the simulator's Newton started on it{}",
            if k.confirmed {
                "confirmed"
            } else {
                "not confirmed"
            },
            match (&k.error, k.state_difference, k.map_residual) {
                (Some(e), _, _) => format!(" ({e})"),
                (None, Some(d), Some(r)) => format!(
                    " ({} Newton steps, map residual {r:.1e}, state difference {d:.1e})",
                    k.newton_iterations.unwrap_or(0)
                ),
                _ => String::new(),
            }
        );
    }
    out
}
