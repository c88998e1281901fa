//! Survey of the orbits of a few impact signatures on the paper unit (e = 0.8, Δ = 0.5).
use rattle_analytic::test_models::{paper_stops, paper_unit};
use rattle_analytic::{signature_orbits, symmetric_orbits, Signature};
use std::time::Instant;

fn main() {
    let unit = paper_unit();
    let stops = paper_stops();
    let args: Vec<String> = std::env::args().collect();
    let omegas: Vec<f64> = if args.len() > 1 {
        args[1..].iter().map(|a| a.parse().unwrap()).collect()
    } else {
        vec![1.2, 1.5, 2.0]
    };
    for &omega in &omegas {
        let sym = symmetric_orbits(&unit, &stops, omega).unwrap();
        println!("ω = {omega}: symmetric solver: {} orbits", sym.len());
        for o in &sym {
            let s = Signature::parse("+-", 1).unwrap();
            let g = rattle_analytic::solve_signature(&unit, &stops, omega, &s, &[o.alpha, 0.5])
                .unwrap();
            let dmu = g
                .floquet_multipliers
                .iter()
                .map(|a| {
                    o.floquet_multipliers
                        .iter()
                        .map(|b| (a - b).norm())
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0, f64::max);
            println!(
                "   general vs symmetric: dα {:.1e} dstate {:.1e} dX_o {:.1e} dμ {:.1e} (Newton iterations {})",
                (g.alpha - o.alpha).abs(),
                (g.state_after_impact - o.state_after_impact).amax(),
                (g.outer_amplitude - o.outer_amplitude).abs(),
                dmu,
                g.newton_iterations
            );
            println!(
                "   sym α = {:.15} viable {} stable {} X_o {:.12}",
                o.alpha, o.viable, o.stable, o.outer_amplitude
            );
        }
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
            let dt = t.elapsed();
            println!(
                "  {text} p={p}: {} orbits in {:.3} s",
                orbits.len(),
                dt.as_secs_f64()
            );
            for o in &orbits {
                let maxmu = o
                    .floquet_multipliers
                    .iter()
                    .map(|m| m.norm())
                    .fold(0.0, f64::max);
                println!(
                    "    α = {:+.12} φ = {:?} viable {} stable {} |μ|max {:.6} X_o {:.6} T {:.3} dB it {} E-res {:.1e} viol {:?}",
                    o.alpha,
                    o.impact_phases.iter().map(|v| format!("{v:.6}")).collect::<Vec<_>>(),
                    o.viable, o.stable, maxmu, o.outer_amplitude, o.transmittance_db, o.newton_iterations, o.energy_residual,
                    o.violations.iter().map(|v| format!("{v:?}").split_whitespace().next().unwrap().to_string()).collect::<Vec<_>>()
                );
            }
        }
    }
}
