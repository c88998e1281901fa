//! Orbits of an impact sequence on a chain of damped paper cells, found by `sequence_orbits`,
//! one JSON line per orbit; with `--refine`, the same search on grids twice and three times as
//! fine, to see whether the default grid misses a viable orbit (the measurement behind the
//! grid claim for chains).
//!
//! `cargo run --release -p rattle-analytic --example chain_orbits -- [CELLS] [OMEGA] [SEQUENCE]
//! [PERIOD] [--refine]`, defaults `2 3.3 "0+ 1- 0- 1+" 1`.
use rattle_analytic::eigenvalues;
use rattle_analytic::test_models::{damped_paper_unit, paper_stops};
use rattle_analytic::{
    sequence_orbits, sequence_orbits_on_grid, ImpactSequence, LinearModel, SequenceOrbit,
};
use rattle_analytic::{GRID_PER_OSCILLATION, MIN_GRID};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let refine = args.iter().any(|a| a == "--refine");
    let args: Vec<&String> = args.iter().filter(|a| *a != "--refine").collect();
    let cells: usize = args.first().map_or(Ok(2), |a| a.parse())?;
    let omega: f64 = args.get(1).map_or(Ok(3.3), |a| a.parse())?;
    let text = args.get(2).map_or("0+ 1- 0- 1+", |a| a.as_str());
    let period: u32 = args.get(3).map_or(Ok(1), |a| a.parse())?;
    let model = LinearModel::chain(&damped_paper_unit(), &paper_stops(), cells)?;
    let sequence = ImpactSequence::parse(text, period)?;
    let t = Instant::now();
    let orbits = sequence_orbits(&model, omega, &sequence)?;
    let elapsed = t.elapsed();
    for o in &orbits {
        println!("{}", serde_json::to_string(o)?);
    }
    let viable = |v: &[SequenceOrbit]| v.iter().filter(|o| o.viable).count();
    eprintln!(
        "{cells} cells, ω = {omega}, {sequence}/{period}: {} orbits, {} viable, {elapsed:.2?}",
        orbits.len(),
        viable(&orbits)
    );
    if refine {
        let impacts = sequence.impacts().len();
        for factor in [2, 3] {
            // The default grid's rule of `sequence_orbits` (before any coarsening), refined.
            let natural = eigenvalues(&model.system_matrix())
                .map_or(0.0, |l| l.iter().fold(0.0, |a: f64, z| a.max(z.norm())));
            let default = (GRID_PER_OSCILLATION * f64::from(period) * omega.max(natural) / omega)
                .ceil() as usize;
            let grid = factor * default.max(MIN_GRID);
            let t = Instant::now();
            let fine = sequence_orbits_on_grid(&model, omega, &sequence, grid.max(impacts))?;
            let missed = fine
                .iter()
                .filter(|f| f.viable)
                .filter(|f| {
                    !orbits.iter().any(|o| {
                        (o.alpha - f.alpha).abs() < 1e-8
                            && o.impact_phases
                                .iter()
                                .zip(&f.impact_phases)
                                .all(|(a, b)| (a - b).abs() < 1e-8)
                    })
                })
                .count();
            eprintln!(
                "  grid {grid}: {} orbits, {} viable, {missed} viable missed by the default grid, {:.2?}",
                fine.len(),
                viable(&fine),
                t.elapsed()
            );
        }
    }
    Ok(())
}
