//! Viable orbits found by `signature_orbits` on the paper unit (undamped and damped), with the
//! cost of each call: the measurement behind the grid choices in `cycle.rs`.
use rattle_analytic::test_models::{damped_paper_unit, paper_stops, paper_unit};
use rattle_analytic::{signature_orbits, Signature};
use std::time::Instant;
fn main() {
    let stops = paper_stops();
    for (text, p) in [
        ("+-", 1),
        ("++--", 1),
        ("+-+-", 1),
        ("+-", 2),
        ("++--", 2),
        ("+-+-", 2),
    ] {
        let s = Signature::parse(text, p).unwrap();
        for (u, unit) in [paper_unit(), damped_paper_unit()].iter().enumerate() {
            for omega in [1.0, 1.2, 1.5, 1.8, 2.0, 2.5] {
                let t = Instant::now();
                let a = signature_orbits(unit, &stops, omega, &s);
                let v: Vec<String> = a
                    .iter()
                    .filter(|o| o.viable)
                    .map(|o| format!("{:.9}", o.alpha))
                    .collect();
                println!(
                    "{text}/{p} u{u} ω {omega}: {} orbits, viable {:?} [{:.2}s]",
                    a.len(),
                    v,
                    t.elapsed().as_secs_f64()
                );
            }
        }
    }
}
