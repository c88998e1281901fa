//! The general linear model with contact pairs: built from the unit it must reproduce the unit's
//! own matrices, impact map and linear steady state; built as a chain it must match matrices
//! and a complex steady-state solve written out here independently; bad models are refused with
//! the field named.

use nalgebra::{Complex, DMatrix, DVector};
use rattle_analytic::test_models::{damped_paper_unit, paper_stops, paper_unit};
use rattle_analytic::*;

/// Rounding allowance of formulas that compute the same quantity in a different order: a few
/// ulps of the largest entry involved.
const ROUNDING_ULPS: f64 = 8.0;

fn assert_close(a: &DMatrix<f64>, b: &DMatrix<f64>, tol: f64, what: &str) {
    assert_eq!(a.shape(), b.shape(), "{what}: shapes");
    let scale = a.amax().max(b.amax()).max(f64::MIN_POSITIVE);
    let diff = (a - b).amax();
    assert!(
        diff <= tol * scale,
        "{what}: difference {diff:e} > {tol:e} × {scale}"
    );
}

#[test]
fn impact_map_of_the_unit_equals_stops_impact_map() {
    for unit in [paper_unit(), damped_paper_unit()] {
        for restitution in [0.0, 0.5, 0.8, 1.0] {
            let stops = Stops {
                restitution,
                ..paper_stops()
            };
            let model = LinearModel::unit(&unit, &stops).unwrap();
            let general = model.impact_map(0);
            let fixed = stops.impact_map(&unit);
            let fixed = DMatrix::from_iterator(2, 2, fixed.iter().copied());
            assert_close(&general, &fixed, ROUNDING_ULPS * f64::EPSILON, "impact map");
        }
    }
}

#[test]
fn augmented_matrix_of_the_unit_equals_the_units() {
    let unit = damped_paper_unit();
    let model = LinearModel::unit(&unit, &paper_stops()).unwrap();
    for omega in [0.3, 1.5f64.sqrt(), 2.0, 3.7] {
        let fixed = unit.augmented_matrix(omega);
        let fixed = DMatrix::from_iterator(6, 6, fixed.iter().copied());
        assert_close(
            &model.augmented_matrix(omega),
            &fixed,
            ROUNDING_ULPS * f64::EPSILON,
            "augmented matrix",
        );
    }
}

#[test]
fn linear_steady_state_of_the_unit_equals_linear_response() {
    // u = Re{U e^{iθ}} = U_c cos θ + U_s sin θ with U = U_c − i U_s.
    let unit = damped_paper_unit();
    let model = LinearModel::unit(&unit, &paper_stops()).unwrap();
    for omega in [0.3, 1.0, 2.0, 2.5, 3.7] {
        let state = model.linear_steady_state(omega).unwrap();
        let reference = linear_response(&unit, omega);
        let outer = Complex::new(state.cosine[0], -state.sine[0]);
        let inner = Complex::new(state.cosine[1], -state.sine[1]);
        let scale = reference.outer_amplitude.max(reference.inner_amplitude);
        assert!(
            (outer - reference.outer).norm() <= 1e-12 * scale,
            "outer at {omega}"
        );
        assert!(
            (inner - reference.inner).norm() <= 1e-12 * scale,
            "inner at {omega}"
        );
        let amplitudes = state.amplitudes();
        assert!((amplitudes[0] - reference.outer_amplitude).abs() <= 1e-12 * scale);
        let relative = state.relative_amplitude(&model.pairs()[0]);
        assert!((relative - reference.relative_amplitude).abs() <= 1e-12 * scale);
    }
}

/// The damped paper cell twice in series, written out by hand:
/// `u = (u_o1, u_i1, u_o2, u_i2)`, `m_o = 2, m_i = 1, k_o = 6, k_i = 3, c_o = 0.1, c_i = 0.05`.
fn two_cell_matrices() -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
    let mass = DMatrix::from_diagonal(&DVector::from_vec(vec![2.0, 1.0, 2.0, 1.0]));
    #[rustfmt::skip]
    let stiffness = DMatrix::from_row_slice(4, 4, &[
        6.0 + 6.0 + 3.0, -3.0, -6.0, 0.0,
        -3.0, 3.0, 0.0, 0.0,
        -6.0, 0.0, 6.0 + 3.0, -3.0,
        0.0, 0.0, -3.0, 3.0,
    ]);
    #[rustfmt::skip]
    let damping = DMatrix::from_row_slice(4, 4, &[
        0.1 + 0.1 + 0.05, -0.05, -0.1, 0.0,
        -0.05, 0.05, 0.0, 0.0,
        -0.1, 0.0, 0.1 + 0.05, -0.05,
        0.0, 0.0, -0.05, 0.05,
    ]);
    (mass, damping, stiffness)
}

#[test]
fn chain_matrices_are_the_cells_in_series() {
    let huge = Stops {
        gap: 1e6,
        restitution: 0.8,
    };
    let model = LinearModel::chain(&damped_paper_unit(), &huge, 2).unwrap();
    let (mass, damping, stiffness) = two_cell_matrices();
    assert_eq!(model.mass(), &mass);
    assert_eq!(model.damping(), &damping);
    assert_eq!(model.stiffness(), &stiffness);
    assert_eq!(model.pairs().len(), 2);
    assert_eq!(
        model.pairs()[1].direction,
        DVector::from_vec(vec![0.0, 0.0, -1.0, 1.0])
    );
}

#[test]
fn chain_with_huge_gaps_is_the_linear_chain_of_a_direct_complex_solve() {
    let huge = Stops {
        gap: 1e6,
        restitution: 0.8,
    };
    let model = LinearModel::chain(&damped_paper_unit(), &huge, 2).unwrap();
    let (mass, damping, stiffness) = two_cell_matrices();
    for omega in [0.2, 0.9, 1.7, 2.6, 4.0] {
        // (K − ω²M + iωC) U = F, F = (k_o + iω c_o) u_g on the first outer mass.
        let dynamic = DMatrix::from_fn(4, 4, |j, k| {
            Complex::new(
                stiffness[(j, k)] - omega * omega * mass[(j, k)],
                omega * damping[(j, k)],
            )
        });
        let mut force = DVector::from_element(4, Complex::new(0.0, 0.0));
        force[0] = Complex::new(6.0, omega * 0.1);
        let exact = dynamic.lu().solve(&force).unwrap();
        let state = model.linear_steady_state(omega).unwrap();
        let scale = exact.iter().map(|z| z.norm()).fold(0.0, f64::max);
        for k in 0..4 {
            let general = Complex::new(state.cosine[k], -state.sine[k]);
            assert!(
                (general - exact[k]).norm() <= 1e-12 * scale,
                "coordinate {k} at omega {omega}: {general} vs {}",
                exact[k]
            );
        }
        // Each pair's relative motion stays far inside its stops: the linear chain is the
        // chain's steady state.
        for pair in model.pairs() {
            assert!(state.relative_amplitude(pair) < pair.gap_side1.min(pair.gap_side2));
        }
    }
}

#[test]
fn impact_map_of_a_chain_pair_conserves_momentum_and_restitutes() {
    let model = LinearModel::chain(&damped_paper_unit(), &paper_stops(), 3).unwrap();
    let before = DVector::from_vec(vec![0.3, -1.1, 0.7, 2.0, -0.4, 0.9]);
    for (p, pair) in model.pairs().iter().enumerate() {
        let after = model.impact_map(p) * &before;
        let impulse = model.mass() * (&after - &before);
        // The impulse acts along w only: its part orthogonal to w vanishes.
        let w = &pair.direction;
        let along = w * (impulse.dot(w) / w.dot(w));
        assert!((&impulse - along).amax() <= ROUNDING_ULPS * f64::EPSILON * impulse.amax());
        let (vr_before, vr_after) = (w.dot(&before), w.dot(&after));
        assert!(
            (vr_after + pair.restitution * vr_before).abs()
                <= ROUNDING_ULPS * f64::EPSILON * vr_before.abs()
        );
        // Total momentum of the chain is conserved.
        let total: f64 = impulse.sum();
        assert!(total.abs() <= ROUNDING_ULPS * f64::EPSILON * impulse.amax());
    }
}

#[test]
fn undamped_resonance_has_no_linear_steady_state() {
    // One mass m = 1 on a spring k = 1 driven at ω = 1 exactly: K − ω²M = 0.
    let one = |v: f64| DMatrix::from_element(1, 1, v);
    let forcing = HarmonicForcing {
        cosine: DVector::from_element(1, 1.0),
        sine: DVector::zeros(1),
        sine_per_omega: DVector::zeros(1),
        harmonics: Vec::new(),
    };
    let model = LinearModel::new(one(1.0), one(0.0), one(1.0), forcing, Vec::new()).unwrap();
    assert_eq!(
        model.linear_steady_state(1.0),
        Err(ModelError::Unbounded {
            omega: 1.0,
            order: 1
        })
    );
    assert!(model.linear_steady_state(0.5).is_ok());
}

fn field_of(result: Result<LinearModel, ModelError>) -> String {
    match result {
        Err(ModelError::OutOfRange { field, .. })
        | Err(ModelError::Dimension { field, .. })
        | Err(ModelError::Structure { field, .. }) => field,
        other => panic!("expected a refused model, got {other:?}"),
    }
}

#[test]
fn bad_models_are_refused_with_the_field_named() {
    let (mass, damping, stiffness) = two_cell_matrices();
    let forcing = HarmonicForcing {
        cosine: DVector::from_vec(vec![6.0, 0.0, 0.0, 0.0]),
        sine: DVector::zeros(4),
        sine_per_omega: DVector::from_vec(vec![-0.1, 0.0, 0.0, 0.0]),
        harmonics: Vec::new(),
    };
    let pair = ContactPair {
        direction: DVector::from_vec(vec![-1.0, 1.0, 0.0, 0.0]),
        gap_side1: 0.5,
        gap_side2: 0.5,
        restitution: 0.8,
    };
    let build = |m: DMatrix<f64>, c: DMatrix<f64>, k: DMatrix<f64>, f: HarmonicForcing, p| {
        LinearModel::new(m, c, k, f, vec![p])
    };
    assert!(build(
        mass.clone(),
        damping.clone(),
        stiffness.clone(),
        forcing.clone(),
        pair.clone()
    )
    .is_ok());

    let mut m = mass.clone();
    m[(1, 1)] = 0.0;
    let f = field_of(build(
        m,
        damping.clone(),
        stiffness.clone(),
        forcing.clone(),
        pair.clone(),
    ));
    assert_eq!(f, "model.mass[1][1]");

    let mut m = mass.clone();
    m[(0, 1)] = 5.0;
    m[(1, 0)] = 5.0;
    let f = field_of(build(
        m,
        damping.clone(),
        stiffness.clone(),
        forcing.clone(),
        pair.clone(),
    ));
    assert_eq!(f, "model.mass");

    let mut k = stiffness.clone();
    k[(0, 1)] = 1.0;
    let f = field_of(build(
        mass.clone(),
        damping.clone(),
        k,
        forcing.clone(),
        pair.clone(),
    ));
    assert_eq!(f, "model.stiffness");

    let mut k = stiffness.clone();
    k[(2, 3)] = f64::NAN;
    let f = field_of(build(
        mass.clone(),
        damping.clone(),
        k,
        forcing.clone(),
        pair.clone(),
    ));
    assert_eq!(f, "model.stiffness[2][3]");

    let f = field_of(build(
        mass.clone(),
        DMatrix::zeros(3, 3),
        stiffness.clone(),
        forcing.clone(),
        pair.clone(),
    ));
    assert_eq!(f, "model.damping");

    let short = HarmonicForcing {
        cosine: DVector::zeros(2),
        ..forcing.clone()
    };
    let f = field_of(build(
        mass.clone(),
        damping.clone(),
        stiffness.clone(),
        short,
        pair.clone(),
    ));
    assert_eq!(f, "forcing.cosine");

    for (bad, name) in [
        (
            ContactPair {
                gap_side2: 0.0,
                ..pair.clone()
            },
            "pairs[0].gap_side2",
        ),
        (
            ContactPair {
                restitution: 1.5,
                ..pair.clone()
            },
            "pairs[0].restitution",
        ),
        (
            ContactPair {
                direction: DVector::zeros(4),
                ..pair.clone()
            },
            "pairs[0].direction",
        ),
    ] {
        let f = field_of(build(
            mass.clone(),
            damping.clone(),
            stiffness.clone(),
            forcing.clone(),
            bad,
        ));
        assert_eq!(f, name);
    }

    let f = field_of(LinearModel::chain(&paper_unit(), &paper_stops(), 0));
    assert_eq!(f, "chain.cells");
    let bad_unit = Unit {
        outer_mass: -2.0,
        ..paper_unit()
    };
    let f = field_of(LinearModel::unit(&bad_unit, &paper_stops()));
    assert_eq!(f, "unit.outer_mass");
    let bad_stops = Stops {
        gap: 0.0,
        ..paper_stops()
    };
    let f = field_of(LinearModel::unit(&paper_unit(), &bad_stops));
    assert_eq!(f, "stops.gap");
}

#[test]
fn impact_sequences_are_canonical_rotations_and_name_their_pairs() {
    // One pair: the sequence of a signature, in the signature's canonical form.
    let one = ImpactSequence::parse("-++-", 2).unwrap();
    assert_eq!(one.to_string(), "0+ 0+ 0- 0-");
    assert_eq!(
        one.as_signature(),
        Some(Signature::parse("++--", 2).unwrap())
    );
    // Two pairs, each `+-`: every rotation gives the same canonical sequence.
    let a = ImpactSequence::parse("1- 0+ 1+ 0-", 1).unwrap();
    let b = ImpactSequence::parse("0+ 1+ 0- 1-", 1).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.to_string(), "0+ 1+ 0- 1-");
    assert_eq!(a.as_signature(), None);
    assert_eq!(
        a.pair_signature(1),
        Some(Signature::parse("+-", 1).unwrap())
    );
    assert_eq!(a.pair_signature(2), None);
    let chain = LinearModel::chain(&damped_paper_unit(), &paper_stops(), 2).unwrap();
    assert_eq!(a.check(&chain), Ok(()));
    let unit = LinearModel::unit(&damped_paper_unit(), &paper_stops()).unwrap();
    assert_eq!(
        a.check(&unit),
        Err(SequenceError::Pair { pair: 1, pairs: 1 })
    );
    // Refused: bad tokens, empty, bad period.
    assert_eq!(
        ImpactSequence::parse("0+ 1x", 1),
        Err(SequenceError::BadToken {
            token: "1x".to_string()
        })
    );
    assert_eq!(
        ImpactSequence::parse("", 1),
        Err(SequenceError::Signature(SignatureError::Empty))
    );
    assert!(matches!(
        ImpactSequence::parse("0+ 0-", 0),
        Err(SequenceError::Signature(SignatureError::Period { .. }))
    ));
}

/// The general model's cycle equations (heap matrices), evaluated at the impact times and
/// phase of the unit's own signature orbits (`+-` and `++--`, the same equations on the unit's
/// fixed-size matrices and its own flow), reproduce their periodic state and close every
/// contact; the general solver started there gives the same Floquet multipliers.
#[test]
fn general_cycle_at_the_units_orbits_reproduces_them() {
    /// Agreement of two exact computations of the same cycle (different products of
    /// exponentials): the solver's own tolerance is 1e-12 relative.
    const AGREEMENT: f64 = 1e-12;
    /// Eigenvalues of two products of the same matrices: the conditioning of a possibly
    /// non-normal monodromy magnifies the 1e-12 agreement of the matrices; 1e-8 is the
    /// issue's tolerance for multipliers of two independent solvers.
    const MULTIPLIERS: f64 = 1e-8;
    let stops = paper_stops();
    let mut compared = 0;
    for unit in [paper_unit(), damped_paper_unit()] {
        let model = LinearModel::unit(&unit, &stops).unwrap();
        for (text, omega) in [("+-", 1.2), ("+-", 2.6), ("++--", 1.5), ("++--", 2.0)] {
            let signature = Signature::parse(text, 1).unwrap();
            let sequence = ImpactSequence::from_signature(&signature);
            let problem = SequenceProblem::new(&model, omega, &sequence).unwrap();
            for o in signature_orbits(&unit, &stops, omega, &signature) {
                let mut x = o.impact_phases.clone();
                x[0] = o.alpha;
                let cycle = problem.equations().evaluate_with(&x, false).unwrap();
                let before = cycle.before_impacts();
                let scale = o.state_after_impact.amax().max(1.0);
                for k in 0..4 {
                    let d = (cycle.z1[k] - o.state_after_impact[k]).abs();
                    assert!(
                        d <= AGREEMENT * scale,
                        "{text} at {omega}: state {k} off by {d:e}"
                    );
                    for (z, y) in before.iter().zip(&o.states_before_impacts) {
                        assert!((z[k] - y[k]).abs() <= AGREEMENT * scale);
                    }
                }
                assert!(cycle.residual.amax() <= AGREEMENT * scale);
                // Floquet multipliers: each of the fixed solver's has a general one within
                // the tolerance (matched one to one).
                let general = solve_sequence(&model, omega, &sequence, &x).unwrap();
                let mut general = general.floquet_multipliers;
                assert_eq!(general.len(), o.floquet_multipliers.len());
                for mu in &o.floquet_multipliers {
                    let (best, d) = general
                        .iter()
                        .enumerate()
                        .map(|(i, g)| (i, (g - mu).norm()))
                        .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
                    assert!(
                        d <= MULTIPLIERS,
                        "{text} at {omega}: multiplier {mu} off by {d:e}"
                    );
                    general.swap_remove(best);
                }
                compared += 1;
            }
        }
    }
    assert!(compared >= 8, "only {compared} orbits compared");
}
