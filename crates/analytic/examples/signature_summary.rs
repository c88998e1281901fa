//! One line per (signature, period, ω) on the paper unit (e = 0.8, Δ = 0.5): orbits found,
//! viable, stable, Newton iterations, worst energy residual and the cost of the call.
use rattle_analytic::test_models::{paper_stops, paper_unit};
use rattle_analytic::{signature_orbits, Signature};
use std::time::Instant;

fn main() {
    let (unit, stops) = (paper_unit(), paper_stops());
    for omega in [1.2, 1.5, 2.0] {
        for (text, p) in [
            ("+-", 1),
            ("+-", 2),
            ("++--", 1),
            ("++--", 2),
            ("+-+-", 1),
            ("+-+-", 2),
        ] {
            let s = Signature::parse(text, p).unwrap();
            let t = Instant::now();
            let orbits = signature_orbits(&unit, &stops, omega, &s);
            let dt = t.elapsed().as_secs_f64();
            let viable: Vec<_> = orbits.iter().filter(|o| o.viable).collect();
            let its: Vec<usize> = orbits.iter().map(|o| o.newton_iterations).collect();
            let worst = orbits.iter().map(|o| o.energy_residual).fold(0.0, f64::max);
            println!(
                "ω {omega} {text}/{p}: {} orbits, {} viable, {} stable, {} viable+stable; Newton its {}..{}; worst energy residual {:.1e}; {:.3} s",
                orbits.len(),
                viable.len(),
                orbits.iter().filter(|o| o.stable).count(),
                viable.iter().filter(|o| o.stable).count(),
                its.iter().min().unwrap_or(&0),
                its.iter().max().unwrap_or(&0),
                worst,
                dt
            );
            for o in viable {
                let mu = o
                    .floquet_multipliers
                    .iter()
                    .map(|m| m.norm())
                    .fold(0.0, f64::max);
                println!(
                    "    viable: α {:+.10} phases {:?} X_o {:.6} ({:+.3} dB) stable {} max|μ| {:.4} its {} energy {:.1e}",
                    o.alpha,
                    o.impact_phases.iter().map(|v| (v * 1e6).round() / 1e6).collect::<Vec<_>>(),
                    o.outer_amplitude,
                    o.transmittance_db,
                    o.stable,
                    mu,
                    o.newton_iterations,
                    o.energy_residual
                );
            }
        }
    }
}
