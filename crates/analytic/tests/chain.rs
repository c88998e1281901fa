//! Chains of cells: the graded chain's model against the unit and the uniform chain, bad cells
//! refused with the field named, and the linear chain's transfer-matrix steady state against a
//! direct complex solve of `(K − ω²M + iωC) U = F` assembled and solved here.

use nalgebra::{Complex, DMatrix, DVector};
use rattle_analytic::test_models::{damped_paper_unit, paper_stops, paper_unit};
use rattle_analytic::*;

/// Agreement of the transfer-matrix sweep with a direct LU solve, relative to the largest
/// amplitude: both are backward stable, and at the frequencies below (away from the chains'
/// resonances) the system's conditioning leaves them far inside this.
const AGREEMENT: f64 = 1e-10;

/// A graded chain of `n` cells: every parameter drifts cell by cell, so that no two cells are
/// alike, optionally with dashpots that differ too.
fn graded_cells(n: usize, damped: bool) -> Vec<Cell> {
    (0..n)
        .map(|j| {
            let x = j as f64;
            Cell {
                outer_mass: 2.0 + 0.25 * x,
                inner_mass: 1.0 - 0.05 * x,
                outer_stiffness: 6.0 - 0.3 * x,
                inner_stiffness: 3.0 + 0.2 * x,
                damping: damped.then_some(Damping {
                    outer: 0.1 + 0.01 * x,
                    inner: 0.05 + 0.02 * x,
                }),
            }
        })
        .collect()
}

/// `(K − ω²M + iωC) U = F` for a chain, assembled spring by spring and solved by complex LU:
/// `u = (u_o1, u_i1, u_o2, …)`, spring `k_o,j` (dashpot `c_o,j`) between outer masses `j − 1`
/// and `j` (the base for `j = 1`), `k_i,j` (`c_i,j`) between outer and inner mass `j`,
/// `F = ((k_o,1 + iω c_o,1) u_g, 0, …)`.
fn direct_solve(cells: &[Cell], base_amplitude: f64, omega: f64) -> DVector<Complex<f64>> {
    let n = 2 * cells.len();
    let mut a = DMatrix::from_element(n, n, Complex::new(0.0, 0.0));
    let mut spring = |p: Option<usize>, q: usize, k: Complex<f64>| {
        a[(q, q)] += k;
        if let Some(p) = p {
            a[(p, p)] += k;
            a[(p, q)] -= k;
            a[(q, p)] -= k;
        }
    };
    for (j, cell) in cells.iter().enumerate() {
        let (co, ci) = cell.damping.map_or((0.0, 0.0), |d| (d.outer, d.inner));
        let previous = (j > 0).then(|| 2 * j - 2);
        spring(
            previous,
            2 * j,
            Complex::new(cell.outer_stiffness, omega * co),
        );
        spring(
            Some(2 * j),
            2 * j + 1,
            Complex::new(cell.inner_stiffness, omega * ci),
        );
    }
    for (j, cell) in cells.iter().enumerate() {
        a[(2 * j, 2 * j)] -= omega * omega * cell.outer_mass;
        a[(2 * j + 1, 2 * j + 1)] -= omega * omega * cell.inner_mass;
    }
    let mut force = DVector::from_element(n, Complex::new(0.0, 0.0));
    let co = cells[0].damping.map_or(0.0, |d| d.outer);
    force[0] = Complex::new(cells[0].outer_stiffness, omega * co) * base_amplitude;
    a.lu().solve(&force).expect("off resonance")
}

fn assert_equals_direct(cells: &[Cell], base_amplitude: f64, omega: f64) {
    let r = chain_response(cells, base_amplitude, omega).unwrap();
    assert!(!r.unbounded, "ω = {omega}");
    let exact = direct_solve(cells, base_amplitude, omega);
    let scale = exact.iter().map(|z| z.norm()).fold(0.0, f64::max);
    for j in 0..cells.len() {
        for (got, want, what) in [
            (r.outer[j], exact[2 * j], "outer"),
            (r.inner[j], exact[2 * j + 1], "inner"),
        ] {
            assert!(
                (got - want).norm() <= AGREEMENT * scale,
                "N = {}, ω = {omega}, cell {j} {what}: {got} vs {want}",
                cells.len()
            );
        }
        assert_eq!(r.cell_outer_amplitudes[j], r.outer[j].norm());
    }
    let last = exact[2 * cells.len() - 2].norm();
    assert!((r.outer_amplitude - last).abs() <= AGREEMENT * scale);
    let t = 20.0 * (last / base_amplitude).log10();
    assert!(
        (r.transmittance_db - t).abs() <= 1e-8 * (1.0 + t.abs()),
        "T {} vs {t}",
        r.transmittance_db
    );
}

/// Agreement with the direct solve a relative `1e-6` from an undamped resonance, where both
/// solves lose the conditioning `~1e6` (times `ε`, and the eigen-solve's `ω` error is
/// magnified too): measured `6e-10` at worst over the chains below; `1e-8` leaves a margin
/// of 16.
const NEAR_RESONANCE: f64 = 1e-8;

/// Frequencies across both pass bands and both stop bands of the paper's cell (edges 1.61,
/// 2.12, 3.73) and beyond, none at a resonance of the chains tested.
const OFF_RESONANCE: [f64; 8] = [0.37, 0.83, 1.29, 1.9, 2.47, 3.01, 4.4, 6.3];

#[test]
fn transfer_matrices_equal_a_direct_complex_solve() {
    for n in [1, 2, 5, 8] {
        for unit in [paper_unit(), damped_paper_unit()] {
            let cells = vec![Cell::of_unit(&unit); n];
            for omega in OFF_RESONANCE {
                assert_equals_direct(&cells, unit.base_amplitude, omega);
            }
        }
        for damped in [false, true] {
            let cells = graded_cells(n, damped);
            for omega in OFF_RESONANCE {
                assert_equals_direct(&cells, 0.7, omega);
            }
        }
    }
}

#[test]
fn transfer_matrices_equal_the_models_linear_steady_state() {
    // u = Re{U e^{iθ}} = U_c cos θ + U_s sin θ with U = U_c − i U_s.
    for n in [1, 2, 5, 8] {
        for damped in [false, true] {
            let cells = graded_cells(n, damped);
            let with_stops: Vec<(Cell, Stops)> =
                cells.iter().map(|c| (*c, paper_stops())).collect();
            let model = LinearModel::graded_chain(&with_stops, 0.7).unwrap();
            for omega in OFF_RESONANCE {
                let r = chain_response(&cells, 0.7, omega).unwrap();
                let state = model.linear_steady_state(omega).unwrap();
                let scale = state.amplitudes().amax();
                for j in 0..n {
                    for (k, got) in [(2 * j, r.outer[j]), (2 * j + 1, r.inner[j])] {
                        let want = Complex::new(state.cosine[k], -state.sine[k]);
                        assert!(
                            (got - want).norm() <= AGREEMENT * scale,
                            "N = {n}, ω = {omega}, coordinate {k}: {got} vs {want}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn one_cell_is_the_units_linear_response() {
    for unit in [paper_unit(), damped_paper_unit()] {
        for omega in OFF_RESONANCE.into_iter().chain([3f64.sqrt()]) {
            let r = chain_response(&[Cell::of_unit(&unit)], unit.base_amplitude, omega).unwrap();
            let unit_response = linear_response(&unit, omega);
            let scale = unit_response
                .outer_amplitude
                .max(unit_response.inner_amplitude);
            assert!((r.outer[0] - unit_response.outer).norm() <= 1e-12 * scale);
            assert!((r.inner[0] - unit_response.inner).norm() <= 1e-12 * scale);
        }
    }
}

/// At the local resonance `ω² = k_i/m_i = 3` of the undamped paper cell, `m_eff` is infinite:
/// the first outer mass stands still, so every later cell does too, and the first inner mass
/// carries the base spring's whole force, `U_i,1 = −k_o u_g / k_i = −2` (the unit's table).
/// `√3` squared is `3` to an ulp, so "still" is to rounding of `1e-15` relative.
#[test]
fn local_resonance_pins_the_first_outer_mass() {
    let cells = vec![Cell::of_unit(&paper_unit()); 5];
    let r = chain_response(&cells, 1.0, 3f64.sqrt()).unwrap();
    assert!(!r.unbounded);
    assert!((r.inner[0] - Complex::new(-2.0, 0.0)).norm() < 1e-12);
    for j in 0..5 {
        assert!(r.outer[j].norm() < 1e-12, "cell {j}: {}", r.outer[j]);
        assert!(r.outer[j].re.is_finite() && r.inner[j].re.is_finite());
    }
}

/// At the undamped chain's natural frequencies (base fixed, last cell free), from a symmetric
/// eigen-solve written here (accurate to a few ulps of the largest `ω²`), the response is
/// reported unbounded (infinite, no NaN anywhere); a millionth off, it is bounded and agrees
/// with the direct solve to [`NEAR_RESONANCE`]; the damped chain is finite there. One cell
/// agrees with the unit's own resonance test.
#[test]
fn undamped_chain_resonances_are_unbounded_not_nan() {
    for n in [1, 2, 5] {
        let cells = vec![Cell::of_unit(&paper_unit()); n];
        let omegas = natural_frequencies(&cells);
        assert_eq!(omegas.len(), 2 * n);
        for w in omegas {
            let r = chain_response(&cells, 1.0, w).unwrap();
            for value in r.outer.iter().chain(&r.inner) {
                assert!(!value.re.is_nan() && !value.im.is_nan());
            }
            if n == 1 {
                // The unit's own resonance test agrees.
                assert_eq!(r.unbounded, linear_response(&paper_unit(), w).unbounded);
            }
            assert!(r.unbounded, "N = {n}, ω = {w}: {}", r.outer_amplitude);
            assert_eq!(r.outer_amplitude, f64::INFINITY);
            assert_eq!(r.transmittance_db, f64::INFINITY);
            // A millionth off, a bounded (large) steady state, the direct solve's.
            for off in [w * (1.0 - 1e-6), w * (1.0 + 1e-6)] {
                let r = chain_response(&cells, 1.0, off).unwrap();
                assert!(!r.unbounded && r.outer_amplitude.is_finite());
                let exact = direct_solve(&cells, 1.0, off);
                let scale = exact.iter().map(|z| z.norm()).fold(0.0, f64::max);
                assert!(scale > 1e3, "N = {n}, ω = {off}: {scale}");
                for j in 0..n {
                    assert!((r.outer[j] - exact[2 * j]).norm() <= NEAR_RESONANCE * scale);
                }
            }
            let damped = vec![Cell::of_unit(&damped_paper_unit()); n];
            let d = chain_response(&damped, 1.0, w).unwrap();
            assert!(!d.unbounded && d.outer_amplitude.is_finite());
        }
    }
}

/// `ω` of `det(K − ω²M) = 0`, from `M^{-1/2} K M^{-1/2}` (the masses are diagonal).
fn natural_frequencies(cells: &[Cell]) -> Vec<f64> {
    let n = 2 * cells.len();
    let mut k = DMatrix::<f64>::zeros(n, n);
    let mut m = vec![0.0; n];
    for (j, c) in cells.iter().enumerate() {
        let (o, i) = (2 * j, 2 * j + 1);
        m[o] = c.outer_mass;
        m[i] = c.inner_mass;
        k[(o, o)] += c.outer_stiffness + c.inner_stiffness;
        k[(i, i)] += c.inner_stiffness;
        k[(o, i)] -= c.inner_stiffness;
        k[(i, o)] -= c.inner_stiffness;
        if j > 0 {
            k[(o - 2, o - 2)] += c.outer_stiffness;
            k[(o, o - 2)] -= c.outer_stiffness;
            k[(o - 2, o)] -= c.outer_stiffness;
        }
    }
    let s = DMatrix::from_fn(n, n, |a, b| k[(a, b)] / (m[a] * m[b]).sqrt());
    let mut w: Vec<f64> = s.symmetric_eigenvalues().iter().map(|l| l.sqrt()).collect();
    w.sort_by(f64::total_cmp);
    w
}

/// One cell is the unit of the methods page (`docs/methods.md`): `M = diag(m_o, m_i)`,
/// `K = [[k_o + k_i, −k_i], [−k_i, k_i]]`, `C` likewise, forcing `(k_o u_g, 0)` in cosine and
/// `(−c_o u_g, 0)` in sine per ω (written here, not taken from the crate); `LinearModel::unit`
/// and `LinearModel::chain` are this constructor.
#[test]
fn graded_chain_of_one_cell_is_the_unit_of_the_physics_notes() {
    for unit in [paper_unit(), damped_paper_unit()] {
        let stops = paper_stops();
        let one = LinearModel::graded_chain(&[(Cell::of_unit(&unit), stops)], unit.base_amplitude)
            .unwrap();
        let (ko, ki) = (unit.outer_stiffness, unit.inner_stiffness);
        let (co, ci) = unit.damping.map_or((0.0, 0.0), |d| (d.outer, d.inner));
        assert_eq!(
            one.mass(),
            &DMatrix::from_row_slice(2, 2, &[unit.outer_mass, 0.0, 0.0, unit.inner_mass])
        );
        assert_eq!(
            one.stiffness(),
            &DMatrix::from_row_slice(2, 2, &[ko + ki, -ki, -ki, ki])
        );
        assert_eq!(
            one.damping(),
            &DMatrix::from_row_slice(2, 2, &[co + ci, -ci, -ci, ci])
        );
        assert_eq!(
            one.forcing().cosine.as_slice(),
            &[ko * unit.base_amplitude, 0.0]
        );
        assert_eq!(
            one.forcing().sine_per_omega.as_slice(),
            &[-co * unit.base_amplitude, 0.0]
        );
        assert_eq!(one, LinearModel::unit(&unit, &stops).unwrap());
    }
}

#[test]
fn graded_chain_keeps_each_cells_own_parameters() {
    let cells = graded_cells(3, true);
    let stops: Vec<Stops> = (0..3)
        .map(|j| Stops {
            gap: 0.5 + 0.1 * j as f64,
            restitution: 0.8 - 0.2 * j as f64,
        })
        .collect();
    let with_stops: Vec<(Cell, Stops)> = cells.iter().copied().zip(stops.iter().copied()).collect();
    let model = LinearModel::graded_chain(&with_stops, 0.7).unwrap();
    // Cell 2 (index 1): its own masses, its k_o to cell 1's outer mass, its k_i inside.
    let (o, i) = (2, 3);
    assert_eq!(model.mass()[(o, o)], 2.25);
    assert_eq!(model.mass()[(i, i)], 0.95);
    assert_eq!(model.stiffness()[(o, 0)], -5.7);
    assert_eq!(model.stiffness()[(o, i)], -3.2);
    assert_eq!(model.stiffness()[(o, o)], 5.7 + 3.2 + (6.0 - 0.3 * 2.0));
    assert_eq!(model.damping()[(o, 0)], -0.11);
    assert_eq!(model.forcing().cosine[0], 6.0 * 0.7);
    assert_eq!(model.forcing().sine_per_omega[0], -0.1 * 0.7);
    for (j, pair) in model.pairs().iter().enumerate() {
        assert_eq!(pair.gap_side1, stops[j].gap);
        assert_eq!(pair.gap_side2, stops[j].gap);
        assert_eq!(pair.restitution, stops[j].restitution);
    }
}

fn field_of<T: std::fmt::Debug>(result: Result<T, ModelError>) -> (String, String) {
    match result {
        Err(e @ ModelError::OutOfRange { .. }) => {
            let message = e.to_string();
            let ModelError::OutOfRange { field, .. } = e else {
                unreachable!()
            };
            (field, message)
        }
        other => panic!("expected OutOfRange, got {other:?}"),
    }
}

#[test]
fn bad_chains_are_refused_naming_the_field() {
    let good = Cell::of_unit(&damped_paper_unit());
    let stops = paper_stops();
    let chain = |cells: Vec<Cell>| -> Vec<(Cell, Stops)> {
        cells.into_iter().map(|c| (c, stops)).collect()
    };
    // Empty and too long.
    let (f, m) = field_of(LinearModel::graded_chain(&[], 1.0));
    assert_eq!(f, "chain");
    assert!(m.contains(&MAX_CELLS.to_string()), "{m}");
    let (f, _) = field_of(LinearModel::graded_chain(
        &chain(vec![good; MAX_CELLS + 1]),
        1.0,
    ));
    assert_eq!(f, "chain");
    assert!(LinearModel::graded_chain(&chain(vec![good; MAX_CELLS]), 1.0).is_ok());
    let (f, _) = field_of(chain_response(&[], 1.0, 1.0));
    assert_eq!(f, "chain");
    // Each field of a cell, in the third cell.
    let bad: [(Cell, &str, &str); 7] = [
        (
            Cell {
                outer_mass: 0.0,
                ..good
            },
            "chain[2].outer_mass",
            "> 0",
        ),
        (
            Cell {
                inner_mass: f64::NAN,
                ..good
            },
            "chain[2].inner_mass",
            "> 0",
        ),
        (
            Cell {
                outer_stiffness: -1.0,
                ..good
            },
            "chain[2].outer_stiffness",
            "> 0",
        ),
        (
            Cell {
                inner_stiffness: f64::INFINITY,
                ..good
            },
            "chain[2].inner_stiffness",
            "> 0",
        ),
        (
            Cell {
                damping: Some(Damping {
                    outer: -0.1,
                    inner: 0.0,
                }),
                ..good
            },
            "chain[2].damping.outer",
            ">= 0",
        ),
        (
            Cell {
                damping: Some(Damping {
                    outer: 0.0,
                    inner: f64::NAN,
                }),
                ..good
            },
            "chain[2].damping.inner",
            ">= 0",
        ),
        (good, "", ""),
    ];
    for (cell, field, allowed) in bad {
        let cells = vec![good, good, cell, good];
        if field.is_empty() {
            assert!(chain_response(&cells, 1.0, 1.0).is_ok());
            continue;
        }
        for (f, m) in [
            field_of(LinearModel::graded_chain(&chain(cells.clone()), 1.0)),
            field_of(chain_response(&cells, 1.0, 1.0)),
        ] {
            assert_eq!(f, field);
            assert!(m.contains(allowed), "{m}");
        }
    }
    let mut cells = chain(vec![good; 4]);
    cells[3].1.gap = 0.0;
    assert_eq!(
        field_of(LinearModel::graded_chain(&cells, 1.0)).0,
        "chain[3].stops.gap"
    );
    cells[3].1.gap = 0.5;
    cells[1].1.restitution = 1.5;
    let (f, m) = field_of(LinearModel::graded_chain(&cells, 1.0));
    assert_eq!(f, "chain[1].stops.restitution");
    assert!(m.contains("in [0, 1]"));
    for base in [0.0, -1.0, f64::NAN] {
        let (f, _) = field_of(chain_response(&[good], base, 1.0));
        assert_eq!(f, "base.amplitude");
    }
    for omega in [-1.0, f64::NAN, f64::INFINITY] {
        let (f, _) = field_of(chain_response(&[good], 1.0, omega));
        assert_eq!(f, "omega");
    }
}
