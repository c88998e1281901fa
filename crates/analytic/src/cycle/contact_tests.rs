//! Checks of the contact phases against answers derived independently of the cycle
//! equations: the isolated pair's exact restitution and contact duration, the exact Jacobian
//! against central differences, and the Floquet multipliers against a central difference of
//! the flow map composed here (events located by Newton on the exact flows).

use crate::cycle_equations::balanced_exp;
use crate::model::{Compliance, ContactPair, HarmonicForcing, LinearModel};
use crate::sequence::{EventKind, ImpactSequence};
use crate::sequence_orbit::SequenceProblem;
use crate::sequence_verdicts::SequenceOrbit;
use crate::test_models::{damped_paper_unit, paper_stops};
use nalgebra::{Complex, DMatrix, DVector};

fn unforced(n: usize) -> HarmonicForcing {
    HarmonicForcing {
        cosine: DVector::zeros(n),
        sine: DVector::zeros(n),
        sine_per_omega: DVector::zeros(n),
        harmonics: Vec::new(),
    }
}

/// Two free masses `m₁ = 1`, `m₂ = 3` (no spring, no dashpot, no force): pair 0 between them
/// (`r = u₁ − u₂`, gaps 0.5, reduced mass `μ = 3/4`), pair 1 from mass 2 to the frame (rigid,
/// restraining the common translation).
fn isolated_pair() -> LinearModel {
    let pair = |direction: Vec<f64>, gap: f64| ContactPair {
        direction: DVector::from_vec(direction),
        gap_side1: gap,
        gap_side2: gap,
        restitution: 0.5,
    };
    LinearModel::new(
        DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 3.0])),
        DMatrix::zeros(2, 2),
        DMatrix::zeros(2, 2),
        unforced(2),
        vec![pair(vec![1.0, -1.0], 0.5), pair(vec![0.0, 1.0], 1.0)],
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// The isolated pair's contact on the exact contact flow, for stiffnesses from 1 to `1e8`
/// (`1e8` times the test models' unit stiffness) and damping ratios from 0 to 0.9: entering
/// side 1 at `ṙ = 1.3`, the pair is back at its stop after exactly `π/ω_d` (the root of the
/// penetration located by Newton on the exact flow agrees to `1e-12` of the duration, or to
/// the coordinate's rounding over the exit velocity where that is larger: `ζ = 0.9` leaves at
/// `1.5e-3` of the entry velocity) and
/// leaves at `ṙ = −e · 1.3`, `e = exp(−ζπ/√(1 − ζ²))`, to `1e-12`; the penetration at `π/ω_d`
/// is zero to the rounding of the coordinate (8 ulps of the gap, 0.5), which at
/// `ω_c ≈ 1.15e4` is about `1e-12` of the largest penetration.
#[test]
fn isolated_pair_has_the_exact_restitution_and_duration() {
    let base = isolated_pair();
    let mu = base.reduced_mass(0);
    assert!((mu - 0.75).abs() <= 4.0 * f64::EPSILON);
    let entry = 1.3;
    let mut worst: f64 = 0.0;
    for k in [1.0, 1e4, 1e8] {
        for zeta in [0.0, 0.05, 0.3, 0.9] {
            let law = Compliance {
                stiffness: k,
                damping: 2.0 * zeta * (k * mu).sqrt(),
            };
            assert!((law.damping_ratio(mu) - zeta).abs() <= 1e-15);
            let model = base
                .clone()
                .with_compliance(0, law)
                .unwrap_or_else(|e| panic!("{e}"));
            let a = model.compliant_augmented(1.0) + model.contact_increment(0, 1);
            // At the stop r = u₁ − u₂ = 0.5, ṙ = v₁ − v₂ = 1.3; phases (1, 0), constant (1, 0).
            let z0 = DVector::from_vec(vec![0.5, 0.0, 1.0, -0.3, 1.0, 0.0, 1.0, 0.0]);
            let state = |t: f64| {
                balanced_exp(&a, 2, crate::cycle_equations::velocity_balance(&a, 2), t) * &z0
            };
            let duration = law.contact_duration(mu);
            let e = law.restitution(mu);
            let exact = (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp();
            assert!((e - exact).abs() <= 1e-15);
            let at_exit = state(duration);
            let rdot = at_exit[2] - at_exit[3];
            let velocity_error = (rdot + e * entry).abs() / entry;
            let depth = state(0.5 * duration);
            let depth = (depth[0] - depth[1] - 0.5).max(1e-300);
            let penetration_error = (at_exit[0] - at_exit[1] - 0.5).abs();
            // The exit located by Newton from 0.9 of the duration on the exact flow.
            let mut t = 0.9 * duration;
            for _ in 0..50 {
                let z = state(t);
                let step = (z[0] - z[1] - 0.5) / (z[2] - z[3]);
                t -= step;
                if step.abs() <= 1e-17 * duration {
                    break;
                }
            }
            let time_error = (t - duration).abs() / duration;
            println!(
                "k_c = {k:e}, zeta = {zeta}: velocity {velocity_error:e}, penetration at exit \
                 {penetration_error:e} (of the largest {depth:e}), exit time {time_error:e}"
            );
            assert!(
                velocity_error <= 1e-12,
                "k_c = {k}, ζ = {zeta}: exit velocity {velocity_error:e}"
            );
            // The root moves by the coordinate's rounding over the exit velocity: `1e-12` of
            // the duration, or more where the heavily damped contact leaves slowly.
            let root = 8.0 * f64::EPSILON * 0.5 / (e * entry * duration);
            assert!(
                time_error <= root.max(1e-12),
                "k_c = {k}, ζ = {zeta}: exit time {time_error:e}"
            );
            worst = worst.max(velocity_error);
            // The coordinate is the difference of displacements of the gap's size: zero to
            // a few of its ulps.
            assert!(
                penetration_error <= 8.0 * f64::EPSILON * 0.5,
                "k_c = {k}, ζ = {zeta}: penetration at exit {penetration_error:e}"
            );
        }
    }
    println!("largest exit velocity error {worst:e}");
}

/// A cell of the two-cell chain with a compliant pair 0 (`k_c = 200`, `c_c = 2`).
fn compliant_chain() -> LinearModel {
    LinearModel::chain(&damped_paper_unit(), &paper_stops(), 2)
        .and_then(|m| {
            m.with_compliance(
                0,
                Compliance {
                    stiffness: 200.0,
                    damping: 2.0,
                },
            )
        })
        .unwrap_or_else(|e| panic!("{e}"))
}

/// A primary mass on a spring and dashpot with a free mass in its clearance (pair 0, gaps 1
/// and 0.8), compliant: the cycle equations are bordered by the free mass's offset.
fn compliant_free_mass() -> LinearModel {
    let mut cosine = DVector::zeros(2);
    cosine[0] = 1.0;
    LinearModel::new(
        DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 0.15])),
        DMatrix::from_diagonal(&DVector::from_vec(vec![0.05, 0.0])),
        DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 0.0])),
        HarmonicForcing {
            cosine,
            ..unforced(2)
        },
        vec![ContactPair {
            direction: DVector::from_vec(vec![-1.0, 1.0]),
            gap_side1: 1.0,
            gap_side2: 0.8,
            restitution: 0.7,
        }],
    )
    .and_then(|m| {
        m.with_compliance(
            0,
            Compliance {
                stiffness: 500.0,
                damping: 1.0,
            },
        )
    })
    .unwrap_or_else(|e| panic!("{e}"))
}

/// The two masses with two pairs of the fixtures ([`crate::test_models::two_masses_two_pairs`],
/// base amplitude 2) with pair 1 (mass 1 against the frame) landing without rebound
/// (restitution 0): it may stick.
fn sticking_pair() -> LinearModel {
    let model = crate::test_models::two_masses_two_pairs(&[crate::test_models::fundamental(2.0)]);
    let mut pairs = model.pairs().to_vec();
    pairs[1].restitution = 0.0;
    LinearModel::new(
        model.mass().clone(),
        model.damping().clone(),
        model.stiffness().clone(),
        model.forcing().clone(),
        pairs,
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// `dÂ/dω` of a cycle with contact phases: the model's, with the constant phase pair's two
/// rows and columns (zero).
fn padded_rate(model: &LinearModel) -> DMatrix<f64> {
    let size = model.augmented_size();
    let mut rate = DMatrix::zeros(size + 2, size + 2);
    rate.view_mut((0, 0), (size, size))
        .copy_from(&model.augmented_rate());
    rate
}

/// The exact Jacobian of cycles with contact phases in `(x, ω)` against central differences
/// of the residuals: on the two-cell chain (`0+c 1- 0-c 1+`: six events), on the bordered
/// free mass (`0+c 0-c`: four events) and, in `x`, on two masses whose pair 1 sticks
/// (`0+ 1+s 0-`: four events, a release among them), to `1e-8` of the Jacobian's largest
/// entry with the step chosen in the body.
#[test]
fn contact_jacobian_is_the_derivative_of_the_residuals() {
    let cases = [
        (
            compliant_chain(),
            "0+c 1- 0-c 1+",
            2.3,
            vec![0.7, 0.05, 0.21, 0.48, 0.53, 0.83],
        ),
        (
            compliant_free_mass(),
            "0+c 0-c",
            1.3,
            vec![0.4, 0.03, 0.45, 0.5],
        ),
        (sticking_pair(), "0+ 1+s 0-", 1.1, vec![0.3, 0.2, 0.45, 0.7]),
    ];
    for (model, text, omega, x) in cases {
        let sequence = ImpactSequence::parse(text, 1).unwrap_or_else(|e| panic!("{e}"));
        let problem =
            SequenceProblem::new(&model, omega, &sequence).unwrap_or_else(|e| panic!("{e}"));
        assert!(problem.equations().has_contact_phases());
        let m = x.len();
        let exact = problem
            .equations()
            .evaluate_in_omega(&x, &padded_rate(&model))
            .unwrap_or_else(|| panic!("singular"))
            .jacobian;
        let in_x = problem
            .equations()
            .evaluate_with(&x, true)
            .unwrap_or_else(|| panic!("singular"))
            .jacobian;
        assert!((exact.columns(0, m) - &in_x).amax() <= 1e-12 * in_x.amax());
        let scale = exact.amax();
        // The quotient's truncation is `(ω_c T h)²/6` of the Jacobian's scale (the residuals
        // turn at the contact's `ω_c` over the cycle `T`), its rounding `ε/(ω_c T h)`: the
        // step `h = 5e-5/(ω_c T)` keeps both below `1e-9`.
        let law = model.compliance(0).unwrap_or(Compliance {
            stiffness: 1.0,
            damping: 0.0,
        });
        let turn = (law.stiffness / model.reduced_mass(0)).sqrt() * problem.cycle();
        let step = 5e-5 / turn.max(1.0);
        // A sticking phase's `Δ_s` and release functional depend on `ω`, which the `ω` column
        // leaves out (such sequences are not continued): its `ω` column is not compared.
        let columns = if text.contains('s') { m } else { m + 1 };
        let mut worst: f64 = 0.0;
        for i in 0..columns {
            let at = |d: f64| {
                let mut y = x.clone();
                let w = if i < m {
                    y[i] += d;
                    omega
                } else {
                    omega + d
                };
                let p =
                    SequenceProblem::new(&model, w, &sequence).unwrap_or_else(|e| panic!("{e}"));
                p.equations()
                    .evaluate_with(&y, false)
                    .unwrap_or_else(|| panic!("singular"))
                    .residual
            };
            let quotient = (at(step) - at(-step)) / (2.0 * step);
            for j in 0..m {
                let error = (quotient[j] - exact[(j, i)]).abs() / scale;
                worst = worst.max(error);
                assert!(
                    error <= 1e-8,
                    "{text}: ∂r{j}/∂x{i}: {} vs {}",
                    quotient[j],
                    exact[(j, i)]
                );
            }
        }
        println!("{text}: largest difference {worst:e} of {scale:e}");
    }
}

/// The flow map over one cycle from the time `start` (after the first event) in flight
/// `first`, composed here: each flight by its own exact flow, each event located by Newton on
/// its condition (the pair's coordinate at the stop, or a held pair's release functional at
/// zero) from its time on the orbit, a rigid impact's velocity jump applied, a contact's entry
/// and exit and a release continuous. `y` is the mechanical state at `start`, `p` the phase
/// states there.
fn cycle_map(
    problem: &SequenceProblem<'_>,
    phases: &[f64],
    (first, start): (usize, f64),
    y: &DVector<f64>,
    p: &DVector<f64>,
) -> DVector<f64> {
    let (model, equations, events) = (problem.model(), problem.equations(), problem.events());
    let (n, m, cycle) = (model.dofs(), events.len(), equations.cycle());
    let size = equations.augmented_matrix().nrows();
    let flow = |f: usize, tau: f64| equations.flight_flow(f, tau);
    let mut z = DVector::zeros(size);
    z.rows_mut(0, 2 * n).copy_from(y);
    z.rows_mut(2 * n, size - 2 * n).copy_from(p);
    let mut now = start;
    for k in first + 1..=first + m {
        let (j, f) = (k % m, (k - 1) % m);
        let (impact, kind) = events[j];
        // The event's condition `h·z = c`: the pair at its stop, or a release.
        let (h, stop) = (equations.contact_functional(j), equations.stops()[j]);
        let field = equations.flight_matrix(f);
        let mut t = phases[j] * cycle + if k >= m { cycle } else { 0.0 };
        for _ in 0..50 {
            let at = flow(f, t - now) * &z;
            let step = (h.dot(&at) - stop) / h.dot(&(field * &at));
            t -= step;
            if step.abs() <= 1e-16 * cycle {
                break;
            }
        }
        z = flow(f, t - now) * &z;
        if kind == EventKind::Impact {
            let velocities = model.impact_map(impact.pair) * z.rows(n, n);
            z.rows_mut(n, n).copy_from(&velocities);
        }
        now = t;
    }
    z = flow(first, start + cycle - now) * z;
    z.rows(0, 2 * n).into_owned()
}

/// The eigenvalues of the central difference (step `h` on every coordinate) of the composed
/// cycle map from the middle of the orbit's longest free flight: the stroboscopic map there is
/// conjugate to the monodromy from just after the first event, so its eigenvalues are the
/// Floquet multipliers. (Inside a stiff contact the stroboscopic matrix is far from normal,
/// its entries `ω_c` times its eigenvalues, which then amplify the quotient's error: a free
/// flight is where the eigenvalues of the difference quotient are well conditioned.)
fn differenced_multipliers(
    problem: &SequenceProblem<'_>,
    orbit: &SequenceOrbit,
    h: f64,
) -> Vec<Complex<f64>> {
    let equations = problem.equations();
    let n2 = 2 * problem.model().dofs();
    let cycle = equations.cycle();
    let m = orbit.impact_phases.len();
    let end = |f: usize| orbit.impact_phases.get(f + 1).copied().unwrap_or(1.0);
    let first = (0..m)
        .filter(|&f| equations.contact_matrix(f).is_none())
        .max_by(|&a, &b| {
            (end(a) - orbit.impact_phases[a]).total_cmp(&(end(b) - orbit.impact_phases[b]))
        })
        .unwrap_or_else(|| panic!("a free flight"));
    let start = 0.5 * (orbit.impact_phases[first] + end(first)) * cycle;
    let mut x = orbit.impact_phases.clone();
    x[0] = orbit.alpha;
    let e = equations
        .evaluate_with(&x, false)
        .unwrap_or_else(|| panic!("singular"));
    let at_first = if first == 0 {
        e.z1.clone()
    } else {
        e.before_impacts()[first].clone()
    };
    let z = equations.flight_flow(first, start - orbit.impact_phases[first] * cycle) * at_first;
    let y = z.rows(0, n2).into_owned();
    let p = z.rows(n2, z.len() - n2).into_owned();
    let jacobian = DMatrix::from_fn(n2, n2, |_, _| 0.0);
    let mut jacobian = jacobian;
    for i in 0..n2 {
        let shifted = |d: f64| {
            let mut s = y.clone();
            s[i] += d;
            cycle_map(problem, &orbit.impact_phases, (first, start), &s, &p)
        };
        let column = (shifted(h) - shifted(-h)) / (2.0 * h);
        jacobian.set_column(i, &column);
    }
    crate::model_flight::eigenvalues(&jacobian).unwrap_or_else(|| panic!("no eigenvalues"))
}

/// Largest distance from a multiplier of `a` to the nearest of `b`, both ways.
fn multiplier_distance(a: &[Complex<f64>], b: &[Complex<f64>]) -> f64 {
    let one_way = |a: &[Complex<f64>], b: &[Complex<f64>]| {
        a.iter()
            .map(|x| {
                b.iter()
                    .map(|y| (x - y).norm())
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    };
    one_way(a, b).max(one_way(b, a))
}

/// The Floquet multipliers (monodromy with the saltation at every entry and exit) against the
/// central difference of the cycle map composed event by event: on the impact oscillator
/// with a compliant stop (`k_c = 1e4` and `1e8`, `e = 0.8`), on the unit with a compliant pair
/// (`0+c 0-c`), on the two-cell chain with compliant pair 0 and rigid pair 1
/// (`0+c 1+ 0-c 1-`) and on two masses whose pair 1 sticks (`1+s`, `0+ 1+s 0-`: the landing's
/// saltation into the held flow and the release's through the forcing's phase). Each of these
/// orbits also closes its energy balance to rounding. The difference quotient's step is chosen for each contact's time scale
/// (see the bound in the body).
#[test]
fn contact_multipliers_are_the_cycle_maps() {
    let oscillator = |k: f64| {
        crate::test_models::impact_oscillator(&[crate::test_models::fundamental(1.0)])
            .with_compliance(0, Compliance::matched(k, 0.8, 1.0))
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let unit = LinearModel::unit(&damped_paper_unit(), &paper_stops())
        .and_then(|m| {
            m.with_compliance(
                0,
                Compliance {
                    stiffness: 2e3,
                    damping: 5.0,
                },
            )
        })
        .unwrap_or_else(|e| panic!("{e}"));
    let chain = compliant_chain();
    let rigid = crate::test_models::impact_oscillator(&[crate::test_models::fundamental(1.0)]);
    let cases = [
        (rigid, "0+", 0.8),
        (oscillator(1e4), "0+c", 0.8),
        (oscillator(1e8), "0+c", 0.8),
        (unit, "0+c 0-c", 1.3),
        (chain, "0+c 1+ 0-c 1-", 1.2),
        (sticking_pair(), "1+s", 0.6),
        (sticking_pair(), "0+ 1+s 0-", 0.6),
    ];
    let mut worst: f64 = 0.0;
    for (model, text, omega) in cases {
        let sequence = ImpactSequence::parse(text, 1).unwrap_or_else(|e| panic!("{e}"));
        let found =
            crate::sequence_orbits(&model, omega, &sequence).unwrap_or_else(|e| panic!("{e}"));
        assert!(!found.is_empty(), "{text}: an orbit");
        let problem =
            SequenceProblem::new(&model, omega, &sequence).unwrap_or_else(|e| panic!("{e}"));
        // The difference quotient's rounding: the states inside a contact carry `ε` of the
        // motion times the balance `σ ≈ ω_c` in their velocities, divided by the step.
        let balance = (0..problem.events().len())
            .filter_map(|f| problem.equations().contact_matrix(f))
            .map(|a| crate::cycle_equations::velocity_balance(a, model.dofs()))
            .fold(1.0, f64::max);
        let h = 1e-5;
        let tolerance = (4.0 * f64::EPSILON * balance / h).max(1e-8);
        // Orbits whose contact and sticking phases are such (no early or wrong exit or
        // release, no landing from outside the stop): there the composed map's events are the
        // orbit's, transversal, and the map is smooth.
        let sticking = |pair: usize| {
            sequence
                .impacts()
                .iter()
                .any(|i| i.pair == pair && i.kind == crate::ImpactKind::Stick)
        };
        let right_way = |o: &&SequenceOrbit| {
            !o.violations.iter().any(|v| {
                matches!(v, crate::SequenceViolation::WrongApproach { pair, .. } if sticking(*pair))
            })
        };
        let proper: Vec<&SequenceOrbit> = found
            .iter()
            .filter(|o| o.contact_violations.is_empty())
            .filter(right_way)
            .collect();
        assert!(!proper.is_empty(), "{text}: an orbit with proper contacts");
        for orbit in proper {
            let differenced = differenced_multipliers(&problem, orbit, h);
            let distance = multiplier_distance(&differenced, &orbit.floquet_multipliers);
            println!(
                "{text}: viable {}, multipliers {:?}, distance {distance:e} (tolerance \
                 {tolerance:e}), energy residual {:e}",
                orbit.viable, orbit.floquet_multipliers, orbit.energy_residual
            );
            // The energy balance closes to rounding: `ε` per term, times the balance `σ` of a
            // stiff contact's velocities (see the compliant oscillator's test), 16 for the sums.
            let rounding = 16.0 * f64::EPSILON * balance;
            assert!(
                orbit.energy_residual <= rounding,
                "{text}: energy residual {:e} above {rounding:e}",
                orbit.energy_residual
            );
            assert!(
                distance <= tolerance,
                "{text}: {distance:e} {:?} {:?}",
                orbit.violations,
                orbit.contacts
            );
            worst = worst.max(distance / tolerance);
        }
    }
    println!("largest distance {worst} of the tolerance");
}
