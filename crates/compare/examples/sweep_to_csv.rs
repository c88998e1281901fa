//! Sweeps a scene over a frequency range with the analytic solver, the simulator or both, and
//! writes the rows to a CSV file as `rattle sweep --out FILE.csv` does (the same columns), each
//! row as soon as it and those before it are done.
//!
//! ```text
//! cargo run --release -p rattle-compare --example sweep_to_csv -- data/scenes/paper.json sweep.csv
//! ```
//!
//! Without arguments it sweeps the repository's `data/scenes/paper.json` over ω ∈ [0.5, 3]
//! rad/s, 26 frequencies, both solvers, into `sweep.csv`.

use rattle_compare::api::{self, ApiError};
use rattle_compare::output::{writer, Format};
use rattle_compare::runs::axis::Axis;
use rattle_compare::runs::parallel::Progress;
use rattle_compare::runs::sweep::{header, Solver};
use rattle_compare::scene::AnyScene;
use rattle_event_driven::SimulationOptions;
use std::collections::BTreeMap;

/// What can stop the example: the facade's errors and the file's.
#[derive(Debug, thiserror::Error)]
enum Error {
    #[error(transparent)]
    Api(#[from] ApiError),
    #[error("cannot write the CSV file: {0}")]
    Io(#[from] std::io::Error),
}

fn main() -> Result<(), Error> {
    let mut args = std::env::args().skip(1);
    let path = args.next().unwrap_or_else(|| {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/paper.json").to_owned()
    });
    let out = args.next().unwrap_or_else(|| "sweep.csv".to_owned());

    let AnyScene::Cells(scene) = api::load(&path)? else {
        // A structure sweeps the same way with `api::structure_sweep_each`.
        return Err(
            ApiError::Argument("this example sweeps the unit and chain forms".into()).into(),
        );
    };
    let omegas = Axis::new(0.5, 3.0, 26).values();
    let solver = Solver::Both;
    let file = std::io::BufWriter::new(std::fs::File::create(&out)?);
    let mut table = writer(
        Format::Csv,
        file,
        &header(&scene, solver, omegas.len(), None),
        None,
    )?;
    let mut classes: BTreeMap<&str, usize> = BTreeMap::new();
    api::sweep_each(
        &scene,
        &omegas,
        solver,
        &SimulationOptions::default(),
        &Progress::hidden(),
        |row| {
            if let Some(class) = row.class {
                *classes.entry(class).or_default() += 1;
            }
            table.row(&row).map_err(Error::from)
        },
    )?;
    table.finish()?;
    println!(
        "wrote {out} ({} frequencies); classes: {classes:?}",
        omegas.len()
    );
    Ok(())
}
