//! A general linear model with contact pairs: `n` degrees of freedom, mass `M`, damping `C`,
//! stiffness `K`, harmonic base forcing, and rigid two-sided stops on relative coordinates.
//!
//! This is the model the signature solver is generalised onto ([`crate::sequence_orbit`]), so
//! that a chain of cells is a new model, not a new solver. The unit ([`LinearModel::unit`]) and a chain of `N` unit
//! cells in series ([`LinearModel::chain`]) are built here. The crate's own numerics only: the
//! impact map, the augmented matrix of the forced flow and the linear steady state are derived
//! here from `M`, `C`, `K` and the forcing.
//!
//! The unit's signature solver and continuation stay on the faster fixed-size path of
//! [`crate::cycle`]; the tests check that this model reproduces the unit's impact map,
//! augmented matrix and linear steady state, and that the general sequence solver on it finds
//! the fixed-size solver's orbits.

use crate::problem::forcing::trig_extremes;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use thiserror::Error;

mod compliance;

pub(crate) use compliance::fastest_rate;
pub use compliance::{Compliance, MAX_CONTACT_FREQUENCY_RATIO};

/// A model that is not a physical linear model with contact pairs.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModelError {
    /// The named parameter is not finite or lies outside its allowed range.
    #[error("{field} = {value} is out of range: must be {allowed}")]
    OutOfRange {
        /// Path of the parameter, e.g. `model.mass[1][1]` or `pairs[0].gap_side1`.
        field: String,
        /// The rejected value.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// The named matrix or vector does not have the model's dimension.
    #[error("{field} has {found} entries per dimension: must have {expected}")]
    Dimension {
        /// Name of the matrix or vector, e.g. `model.damping`.
        field: String,
        /// The model's number of degrees of freedom (at least 1).
        expected: usize,
        /// The rejected size.
        found: usize,
    },
    /// The named matrix lacks a structural property (symmetry, positive definiteness).
    #[error("{field} must be {required}")]
    Structure {
        /// Name of the matrix, e.g. `model.mass`.
        field: String,
        /// The required property, in words.
        required: &'static str,
    },
    /// The model has rigid modes (free bodies) that neither a dashpot nor a contact pair
    /// restrains: nothing ever stops such a body, which drifts at any velocity it is given
    /// (no bounded motion).
    #[error(
        "{free} of the model's {modes} rigid modes are restrained by neither a dashpot nor a \
         contact pair: such a free body drifts (no bounded motion); every rigid mode must be \
         seen by a pair's direction or damped"
    )]
    Drift {
        /// Number of rigid modes (the nullity of `K`).
        modes: usize,
        /// Number of independent rigid directions free of both dashpots and pairs.
        free: usize,
    },
    /// The linear steady state does not exist: `K − (kω)²M + ikωC` is singular for the
    /// fundamental (`k = 1`) or a harmonic of order `k` (an undamped resonance at `kω`).
    #[error(
        "no bounded linear steady state at omega = {omega}: K - (k omega)^2 M + i k omega C is \
         singular for the forcing's harmonic of order k = {order}"
    )]
    Unbounded {
        /// The forcing frequency `ω`.
        omega: f64,
        /// The order `k` of the harmonic at resonance: 1 for the fundamental.
        order: u32,
    },
}

/// Relative tolerance of the symmetry check of `M`, `C`, `K`: entries `a_jk` and `a_kj` must
/// agree to this many ulps of the matrix's largest entry. Matrices built from physical springs
/// and dashpots are symmetric bit for bit; 16 ulps leave room for matrices assembled by sums in
/// another order, and no more.
pub(crate) const SYMMETRY_ULPS: f64 = 16.0;

/// Smallest reciprocal condition estimate (`min |u_kk| / max |u_kk|` of the LU factor) of the
/// `2n × 2n` real steady-state system below which it is reported as singular
/// ([`ModelError::Unbounded`]): `n` times the unit roundoff, the accuracy floor of LU with
/// partial pivoting on a well-scaled system.
pub(crate) fn singular_pivot_ratio(dofs: usize) -> f64 {
    dofs as f64 * f64::EPSILON
}

pub use crate::problem::forcing::{Harmonic, HarmonicForcing};

/// Highest order of a [`Harmonic`]: the multi-start over impact phases samples the base phase
/// and the cycle more finely the higher the order ([`crate::sequence_orbits`]), so its work
/// and memory grow with it; 16 keeps them within four times a single harmonic's.
pub const MAX_HARMONIC_ORDER: u32 = 16;

/// One contact pair: the relative coordinate `r = wᵀu`, stops at `r = +gap_side1` (side 1,
/// `+` in a signature) and `r = −gap_side2` (side 2, `-`), Newton restitution along `w`. A gap
/// of `+∞` is a side without a stop (a one-sided pair); at least one side has one. A stop
/// against the fixed frame is a direction with one entry (`w = e_k`).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPair {
    /// The direction `w` (length `n`, not zero).
    pub direction: DVector<f64>,
    /// Distance `> 0` from `r = 0` to the side-1 stop; `+∞`: no stop on side 1.
    pub gap_side1: f64,
    /// Distance `> 0` from `r = 0` to the side-2 stop; `+∞`: no stop on side 2.
    pub gap_side2: f64,
    /// Newton coefficient of restitution `e ∈ [0, 1]`: `ṙ⁺ = −e ṙ⁻`.
    pub restitution: f64,
}

impl ContactPair {
    /// The relative coordinate `r = wᵀu` of the displacements `u`.
    pub fn relative(&self, displacements: &DVector<f64>) -> f64 {
        self.direction.dot(displacements)
    }
}

/// A linear model `M ü + C u̇ + K u = f(t)` with contact pairs.
///
/// Built only through [`LinearModel::new`] (or [`LinearModel::unit`], [`LinearModel::chain`]),
/// which check it; its fields are read through accessors.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearModel {
    mass: DMatrix<f64>,
    damping: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    forcing: HarmonicForcing,
    pairs: Vec<ContactPair>,
    mass_inverse: DMatrix<f64>,
    /// Orthonormal basis of the null space of `K` (`n × r`), see [`crate::problem::rigid`].
    rigid_modes: DMatrix<f64>,
    /// The contact law of each pair: `None` rigid (restitution), `Some` compliant.
    compliances: Vec<Option<Compliance>>,
}

pub(crate) fn out_of_range(field: String, value: f64, allowed: &'static str) -> ModelError {
    ModelError::OutOfRange {
        field,
        value,
        allowed,
    }
}

fn check_matrix(
    name: &str,
    matrix: &DMatrix<f64>,
    dofs: usize,
    symmetric: bool,
) -> Result<(), ModelError> {
    if matrix.nrows() != dofs || matrix.ncols() != dofs {
        let found = if matrix.nrows() != dofs {
            matrix.nrows()
        } else {
            matrix.ncols()
        };
        return Err(ModelError::Dimension {
            field: format!("model.{name}"),
            expected: dofs,
            found,
        });
    }
    for j in 0..dofs {
        for k in 0..dofs {
            let v = matrix[(j, k)];
            if !v.is_finite() {
                return Err(out_of_range(format!("model.{name}[{j}][{k}]"), v, "finite"));
            }
        }
    }
    if symmetric {
        let scale = matrix.amax();
        for j in 0..dofs {
            for k in 0..j {
                if (matrix[(j, k)] - matrix[(k, j)]).abs() > SYMMETRY_ULPS * f64::EPSILON * scale {
                    return Err(ModelError::Structure {
                        field: format!("model.{name}"),
                        required: "symmetric",
                    });
                }
            }
        }
    }
    Ok(())
}

fn check_vector(name: &str, vector: &DVector<f64>, dofs: usize) -> Result<(), ModelError> {
    if vector.len() != dofs {
        return Err(ModelError::Dimension {
            field: name.to_string(),
            expected: dofs,
            found: vector.len(),
        });
    }
    for (j, v) in vector.iter().enumerate() {
        if !v.is_finite() {
            return Err(out_of_range(format!("{name}[{j}]"), *v, "finite"));
        }
    }
    Ok(())
}

/// Checks the harmonics of a forcing on `dofs` degrees of freedom: orders from 2 to
/// [`MAX_HARMONIC_ORDER`], each once; vectors of `dofs` finite entries; a finite phase.
fn check_harmonics(harmonics: &[Harmonic], dofs: usize) -> Result<(), ModelError> {
    for (i, h) in harmonics.iter().enumerate() {
        let field = |name: &str| format!("forcing.harmonics[{i}].{name}");
        let repeated = harmonics[..i]
            .iter()
            .any(|earlier| earlier.order == h.order);
        if !(2..=MAX_HARMONIC_ORDER).contains(&h.order) || repeated {
            return Err(out_of_range(
                field("order"),
                f64::from(h.order),
                "an integer from 2 to 16, unlike every other harmonic's order",
            ));
        }
        check_vector(&field("cosine"), &h.cosine, dofs)?;
        check_vector(&field("sine"), &h.sine, dofs)?;
        check_vector(&field("sine_per_omega"), &h.sine_per_omega, dofs)?;
        if !h.phase.is_finite() {
            return Err(out_of_range(field("phase"), h.phase, "finite"));
        }
    }
    Ok(())
}

impl LinearModel {
    /// A checked model.
    ///
    /// # Errors
    /// - [`ModelError::Dimension`] if the mass matrix is empty or not square, or `C`, `K`, the
    ///   forcing (its harmonics' vectors included) or a pair's direction does not have `n`
    ///   entries per dimension;
    /// - [`ModelError::OutOfRange`] naming the first non-finite entry, a pair's gap that is not
    ///   `> 0`, a restitution outside `[0, 1]`, or a harmonic's order outside
    ///   `2 ..= `[`MAX_HARMONIC_ORDER`] or repeated (`forcing.harmonics[i].order`) or its
    ///   phase not finite;
    /// - [`ModelError::Structure`] if `M`, `C` or `K` is not symmetric, `M` not positive
    ///   definite, `K` or `C` not positive semidefinite (no bounded motion), or a pair's
    ///   direction is zero;
    /// - [`ModelError::Drift`] if a rigid mode is restrained by neither a dashpot nor a pair
    ///   (`CΦa = 0` and `wᵀΦa = 0` for every pair, for some `a ≠ 0`).
    ///
    /// A singular `K` is accepted: its null vectors are the model's rigid modes (free bodies,
    /// [`LinearModel::rigid_modes`]), handled by the linear steady state
    /// ([`LinearModel::clear_family`]) and the cycle equations
    /// ([`crate::CycleEquations`]).
    pub fn new(
        mass: DMatrix<f64>,
        damping: DMatrix<f64>,
        stiffness: DMatrix<f64>,
        forcing: HarmonicForcing,
        pairs: Vec<ContactPair>,
    ) -> Result<Self, ModelError> {
        let dofs = mass.nrows();
        if dofs == 0 {
            return Err(ModelError::Dimension {
                field: "model.mass".to_string(),
                expected: 1,
                found: 0,
            });
        }
        check_matrix("mass", &mass, dofs, true)?;
        check_matrix("damping", &damping, dofs, true)?;
        check_matrix("stiffness", &stiffness, dofs, true)?;
        for j in 0..dofs {
            if mass[(j, j)] <= 0.0 {
                return Err(out_of_range(
                    format!("model.mass[{j}][{j}]"),
                    mass[(j, j)],
                    "> 0",
                ));
            }
        }
        let Some(cholesky) = mass.clone().cholesky() else {
            return Err(ModelError::Structure {
                field: "model.mass".to_string(),
                required: "positive definite",
            });
        };
        check_vector("forcing.cosine", &forcing.cosine, dofs)?;
        check_vector("forcing.sine", &forcing.sine, dofs)?;
        check_vector("forcing.sine_per_omega", &forcing.sine_per_omega, dofs)?;
        check_harmonics(&forcing.harmonics, dofs)?;
        for (p, pair) in pairs.iter().enumerate() {
            check_vector(&format!("pairs[{p}].direction"), &pair.direction, dofs)?;
            if pair.direction.amax() == 0.0 {
                return Err(ModelError::Structure {
                    field: format!("pairs[{p}].direction"),
                    required: "not zero",
                });
            }
            for (name, gap) in [("gap_side1", pair.gap_side1), ("gap_side2", pair.gap_side2)] {
                if gap.is_nan() || gap <= 0.0 {
                    return Err(out_of_range(
                        format!("pairs[{p}].{name}"),
                        gap,
                        "> 0 (+inf: no stop on that side)",
                    ));
                }
            }
            if !(pair.gap_side1.is_finite() || pair.gap_side2.is_finite()) {
                return Err(out_of_range(
                    format!("pairs[{p}].gap_side1"),
                    pair.gap_side1,
                    "finite on at least one side",
                ));
            }
            if !(0.0..=1.0).contains(&pair.restitution) {
                return Err(out_of_range(
                    format!("pairs[{p}].restitution"),
                    pair.restitution,
                    "in [0, 1]",
                ));
            }
        }
        let rigid_modes = rigid_basis(&stiffness, &damping)?;
        check_restrained(&rigid_modes, &damping, &pairs)?;
        let mass_inverse = cholesky.inverse();
        let compliances = vec![None; pairs.len()];
        Ok(Self {
            mass,
            damping,
            stiffness,
            forcing,
            pairs,
            mass_inverse,
            rigid_modes,
            compliances,
        })
    }

    /// Number of degrees of freedom `n`.
    pub fn dofs(&self) -> usize {
        self.mass.nrows()
    }

    /// Mass matrix `M` (symmetric positive definite).
    pub fn mass(&self) -> &DMatrix<f64> {
        &self.mass
    }

    /// Damping matrix `C` (symmetric).
    pub fn damping(&self) -> &DMatrix<f64> {
        &self.damping
    }

    /// Stiffness matrix `K` (symmetric).
    pub fn stiffness(&self) -> &DMatrix<f64> {
        &self.stiffness
    }

    /// The harmonic forcing.
    pub fn forcing(&self) -> &HarmonicForcing {
        &self.forcing
    }

    /// The contact pairs, in the order in which signatures index them.
    pub fn pairs(&self) -> &[ContactPair] {
        &self.pairs
    }

    /// The rigid modes: an orthonormal basis `Φ` (`n × r`) of the null space of `K`, `r = 0`
    /// (no columns) for a model without free bodies. A translation along a column is kept by
    /// every flight and impact map ([`crate::ClearFamily`]).
    pub fn rigid_modes(&self) -> &DMatrix<f64> {
        &self.rigid_modes
    }

    /// Whether `K` is singular: the model has free bodies (rigid modes), its linear steady
    /// states are a family ([`LinearModel::clear_family`]) and its cycle equations bordered
    /// ([`crate::CycleEquations`]).
    pub fn has_rigid_modes(&self) -> bool {
        self.rigid_modes.ncols() > 0
    }

    /// First-order system matrix `A = [[0, I], [−M⁻¹K, −M⁻¹C]]` for the state `x = (u, u̇)`.
    pub fn system_matrix(&self) -> DMatrix<f64> {
        let n = self.dofs();
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        a.view_mut((0, n), (n, n))
            .copy_from(&DMatrix::identity(n, n));
        a.view_mut((n, 0), (n, n))
            .copy_from(&-(&self.mass_inverse * &self.stiffness));
        a.view_mut((n, n), (n, n))
            .copy_from(&-(&self.mass_inverse * &self.damping));
        a
    }

    /// Number of phase states of the forcing: two for the fundamental, two per harmonic
    /// ([`HarmonicForcing::phase_states`]).
    pub fn phase_states(&self) -> usize {
        self.forcing.phase_states()
    }

    /// Size of the augmented state `z = (u, u̇, p)`: `2n` plus the phase states (`2n + 2`
    /// without harmonics).
    pub fn augmented_size(&self) -> usize {
        2 * self.dofs() + self.phase_states()
    }

    /// The phase states `p = (cos kθ, sin kθ)` of every order ([`HarmonicForcing::orders`]) at
    /// `θ = alpha`: the augmented state's phase rows at the first impact.
    pub fn phase_at(&self, alpha: f64) -> DVector<f64> {
        DVector::from_vec(crate::problem::forcing::phase_state(
            &self.forcing.orders(),
            alpha,
        ))
    }

    /// The system augmented with the forcing's phase states
    /// `p = (cos θ, sin θ, cos k₁θ, sin k₁θ, …)` (see [`crate::HarmonicForcing`]):
    /// `ż = Â z`, `z = (x, p)`, `Â = [[A, B], [0, W]]`, `W = diag(ωJ, k₁ωJ, …)`,
    /// `J = [[0, −1], [1, 0]]`, `B = [[0], [M⁻¹F(ω)]]` with the force columns `F(ω)`
    /// ([`HarmonicForcing::columns`]): `M⁻¹f_c`, `M⁻¹(f_s + ω f_ω)`, then two per harmonic.
    /// Its exponential is the exact forced flow. Without harmonics it is
    /// `(2n + 2) × (2n + 2)`.
    pub fn augmented_matrix(&self, omega: f64) -> DMatrix<f64> {
        let n = self.dofs();
        let size = self.augmented_size();
        let mut m = DMatrix::zeros(size, size);
        m.view_mut((0, 0), (2 * n, 2 * n))
            .copy_from(&self.system_matrix());
        let bc = &self.mass_inverse * &self.forcing.cosine;
        let bs = &self.mass_inverse * self.forcing.sine_at(omega);
        m.view_mut((n, 2 * n), (n, 1)).copy_from(&bc);
        m.view_mut((n, 2 * n + 1), (n, 1)).copy_from(&bs);
        m[(2 * n, 2 * n + 1)] = -omega;
        m[(2 * n + 1, 2 * n)] = omega;
        for (i, h) in self.forcing.harmonics.iter().enumerate() {
            let at = 2 * n + 2 + 2 * i;
            let (c, s) = h.columns_at(omega);
            m.view_mut((n, at), (n, 1))
                .copy_from(&(&self.mass_inverse * c));
            m.view_mut((n, at + 1), (n, 1))
                .copy_from(&(&self.mass_inverse * s));
            let rate = f64::from(h.order) * omega;
            m[(at, at + 1)] = -rate;
            m[(at + 1, at)] = rate;
        }
        m
    }

    /// `dÂ/dω` of [`LinearModel::augmented_matrix`], exact for continuation (`Â` is affine in
    /// `ω`): `M⁻¹F'` in the velocity rows of the phase columns (`M⁻¹f_ω` in the fundamental's
    /// sine column, `k M⁻¹f_ω,k (sin φ_k, cos φ_k)` in harmonic `k`'s,
    /// [`HarmonicForcing::columns_rate`]) and the rotations' `diag(J, k₁J, …)`.
    pub fn augmented_rate(&self) -> DMatrix<f64> {
        let n = self.dofs();
        let size = self.augmented_size();
        let mut m = DMatrix::zeros(size, size);
        m.view_mut((n, 2 * n + 1), (n, 1))
            .copy_from(&(&self.mass_inverse * &self.forcing.sine_per_omega));
        m[(2 * n, 2 * n + 1)] = -1.0;
        m[(2 * n + 1, 2 * n)] = 1.0;
        for (i, h) in self.forcing.harmonics.iter().enumerate() {
            let at = 2 * n + 2 + 2 * i;
            let (c, s) = h.columns_rate();
            m.view_mut((n, at), (n, 1))
                .copy_from(&(&self.mass_inverse * c));
            m.view_mut((n, at + 1), (n, 1))
                .copy_from(&(&self.mass_inverse * s));
            let k = f64::from(h.order);
            m[(at, at + 1)] = -k;
            m[(at + 1, at)] = k;
        }
        m
    }

    /// Velocity map `v⁺ = G v⁻` of an impact of pair `pair`: Newton restitution along `w`
    /// conserving momentum, `G = I − (1 + e) M⁻¹w wᵀ / (wᵀM⁻¹w)`. It maps `wᵀv⁺ = −e wᵀv⁻`,
    /// and the momentum change `M(v⁺ − v⁻)` is parallel to `w` (the contact impulse).
    ///
    /// # Panics
    /// If `pair` is not an index of [`LinearModel::pairs`].
    pub fn impact_map(&self, pair: usize) -> DMatrix<f64> {
        let contact = &self.pairs[pair];
        let w = &contact.direction;
        let minv_w = &self.mass_inverse * w;
        let effective = w.dot(&minv_w);
        let n = self.dofs();
        DMatrix::identity(n, n)
            - (minv_w * w.transpose()) * ((1.0 + contact.restitution) / effective)
    }

    /// The linear steady state (no contact) at `omega`: the fundamental's
    /// `U_c cos θ + U_s sin θ`, from the real `2n × 2n` system
    /// `(K − ω²M) U_c + ωC U_s = f_c`, `−ωC U_c + (K − ω²M) U_s = f_s + ω f_ω`, and each
    /// harmonic's response `U_c,k cos kθ + U_s,k sin kθ`, from the same system at `kω` with the
    /// harmonic's force on `(cos kθ, sin kθ)` ([`Harmonic::columns_at`]): the system is linear,
    /// so the steady state is their sum. A harmonic whose force is zero at `omega` responds
    /// with zero, without a solve. With rigid modes this is one member of a family (the one
    /// without a constant offset along the rigid modes): whether the motion clear of the stops
    /// exists is [`LinearModel::clear_family`]'s question, not this member's.
    ///
    /// # Errors
    /// [`ModelError::Unbounded`] if the system of the fundamental, or of a harmonic with a
    /// force, is singular to within `singular_pivot_ratio` (an undamped resonance at `ω` or
    /// `kω`).
    pub fn linear_steady_state(&self, omega: f64) -> Result<HarmonicState, ModelError> {
        let (cosine, sine) =
            self.steady_harmonic(omega, 1, &self.forcing.cosine, &self.forcing.sine_at(omega))?;
        let mut harmonics = Vec::with_capacity(self.forcing.harmonics.len());
        for h in &self.forcing.harmonics {
            let (c, s) = h.columns_at(omega);
            let (cosine, sine) = if c.amax() == 0.0 && s.amax() == 0.0 {
                (c, s)
            } else {
                self.steady_harmonic(omega, h.order, &c, &s)?
            };
            harmonics.push(HarmonicResponse {
                order: h.order,
                cosine,
                sine,
            });
        }
        Ok(HarmonicState {
            cosine,
            sine,
            harmonics,
        })
    }

    /// The steady response `(U_c, U_s)` to the force `f_c cos kθ + f_s sin kθ` at the
    /// frequency `kω` (`order` = `k`), by LU of the real `2n × 2n` system.
    ///
    /// # Errors
    /// [`ModelError::Unbounded`] when the system is singular to within
    /// `singular_pivot_ratio`.
    fn steady_harmonic(
        &self,
        omega: f64,
        order: u32,
        cosine: &DVector<f64>,
        sine: &DVector<f64>,
    ) -> Result<(DVector<f64>, DVector<f64>), ModelError> {
        let n = self.dofs();
        let frequency = if order == 1 {
            omega
        } else {
            f64::from(order) * omega
        };
        let dynamic = &self.stiffness - &self.mass * (frequency * frequency);
        let coupling = &self.damping * frequency;
        let mut system = DMatrix::zeros(2 * n, 2 * n);
        system.view_mut((0, 0), (n, n)).copy_from(&dynamic);
        system.view_mut((0, n), (n, n)).copy_from(&coupling);
        system.view_mut((n, 0), (n, n)).copy_from(&-&coupling);
        system.view_mut((n, n), (n, n)).copy_from(&dynamic);
        let mut rhs = DVector::zeros(2 * n);
        rhs.rows_mut(0, n).copy_from(cosine);
        rhs.rows_mut(n, n).copy_from(sine);
        let lu = system.lu();
        let pivots = lu.u().diagonal().map(f64::abs);
        let (smallest, largest) = (pivots.min(), pivots.max());
        let unbounded = ModelError::Unbounded { omega, order };
        if smallest.is_nan() || smallest <= singular_pivot_ratio(n) * largest {
            return Err(unbounded);
        }
        let solution = lu.solve(&rhs).ok_or(unbounded)?;
        Ok((
            solution.rows(0, n).into_owned(),
            solution.rows(n, n).into_owned(),
        ))
    }
}

/// The forced flow of a [`LinearModel`] over a time `t`, the blocks of `exp(Â t)`:
/// `x(t) = E x(0) + F p(0)`, `p(t) = R p(0)`, `x = (u, u̇)`, `p` the `P` phase states
/// (`(cos θ, sin θ)` without harmonics, `P = 2`; see [`LinearModel::phase_at`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ModelTransition {
    /// `E(t)` (`2n × 2n`): the free flow, also the variational flow.
    pub homogeneous: DMatrix<f64>,
    /// `F(t)` (`2n × P`): the response to the initial forcing phase.
    pub forced: DMatrix<f64>,
    /// `R(t)` (`P × P`): the rotation of the phase states, `kωt` for the pair of order `k`.
    pub rotation: DMatrix<f64>,
}

impl ModelTransition {
    /// Applies the flow: `(x, p) ↦ (E x + F p, R p)`.
    pub fn apply(&self, x: &DVector<f64>, p: &DVector<f64>) -> (DVector<f64>, DVector<f64>) {
        (&self.homogeneous * x + &self.forced * p, &self.rotation * p)
    }
}

impl LinearModel {
    /// The exact forced flow over time `t` at `omega`: `exp(Â t)` of
    /// [`LinearModel::augmented_matrix`], split into blocks.
    pub fn transition(&self, omega: f64, t: f64) -> ModelTransition {
        let (n2, phases) = (2 * self.dofs(), self.phase_states());
        let full = (self.augmented_matrix(omega) * t).exp();
        ModelTransition {
            homogeneous: full.view((0, 0), (n2, n2)).into_owned(),
            forced: full.view((0, n2), (n2, phases)).into_owned(),
            rotation: full.view((n2, n2), (phases, phases)).into_owned(),
        }
    }

    /// The vector field `ẋ = A x + M⁻¹F(ω) p` of the state `x = (u, u̇)` at the phase states
    /// `p` (`(cos θ, sin θ)`, then `(cos kθ, sin kθ)` per harmonic: [`LinearModel::phase_at`]).
    ///
    /// # Panics
    /// If `x` does not have `2n` entries or `p` fewer than [`LinearModel::phase_states`].
    pub fn vector_field(&self, omega: f64, x: &DVector<f64>, p: &DVector<f64>) -> DVector<f64> {
        let n = self.dofs();
        let mut field = self.system_matrix() * x;
        let mut force = &self.forcing.cosine * p[0] + self.forcing.sine_at(omega) * p[1];
        for (i, h) in self.forcing.harmonics.iter().enumerate() {
            let (c, s) = h.columns_at(omega);
            force += c * p[2 + 2 * i] + s * p[3 + 2 * i];
        }
        let mut accelerations = field.rows_mut(n, n);
        accelerations += &self.mass_inverse * force;
        field
    }

    /// The state after an impact of `pair`: positions kept, velocities mapped by
    /// [`LinearModel::impact_map`].
    ///
    /// # Panics
    /// If `pair` is not an index of [`LinearModel::pairs`] or `x` does not have `2n` entries.
    pub fn impact_state(&self, pair: usize, x: &DVector<f64>) -> DVector<f64> {
        let n = self.dofs();
        let mut after = x.clone();
        let velocities = self.impact_map(pair) * x.rows(n, n);
        after.rows_mut(n, n).copy_from(&velocities);
        after
    }

    /// Saltation matrix (`2n × 2n`) of an impact of `pair` from the state `before` at phase
    /// `p`, on the surface `h = wᵀu ∓ gap`: `S = Ĝ + (f⁺ − Ĝ f⁻) h_xᵀ / (h_x · f⁻)`,
    /// `Ĝ = diag(I, G)`, `h_x = (w, 0)`, `f∓` the vector field before and after.
    ///
    /// # Panics
    /// As [`LinearModel::impact_state`].
    pub fn saltation(
        &self,
        omega: f64,
        pair: usize,
        before: &DVector<f64>,
        p: &DVector<f64>,
    ) -> DMatrix<f64> {
        let n = self.dofs();
        let after = self.impact_state(pair, before);
        let f_minus = self.vector_field(omega, before, p);
        let f_plus = self.vector_field(omega, &after, p);
        let mut g_hat = DMatrix::identity(2 * n, 2 * n);
        g_hat
            .view_mut((n, n), (n, n))
            .copy_from(&self.impact_map(pair));
        let mut hx = DVector::zeros(2 * n);
        hx.rows_mut(0, n).copy_from(&self.pairs[pair].direction);
        let jump = &f_plus - &g_hat * &f_minus;
        let rate = hx.dot(&f_minus);
        g_hat + jump * hx.transpose() / rate
    }
}

/// The response `U_c cos kθ + U_s sin kθ` to one harmonic of order `k` of the forcing.
#[derive(Debug, Clone, PartialEq)]
pub struct HarmonicResponse {
    /// The order `k` (the harmonic's, [`Harmonic::order`]).
    pub order: u32,
    /// `U_c,k`.
    pub cosine: DVector<f64>,
    /// `U_s,k`.
    pub sine: DVector<f64>,
}

/// A periodic motion `u(t) = U_c cos θ + U_s sin θ + Σ_k (U_c,k cos kθ + U_s,k sin kθ)`,
/// `θ = ωt + α`: the fundamental's response and one per harmonic of the forcing (none for a
/// purely harmonic forcing).
#[derive(Debug, Clone, PartialEq)]
pub struct HarmonicState {
    /// `U_c`.
    pub cosine: DVector<f64>,
    /// `U_s`.
    pub sine: DVector<f64>,
    /// The responses to the forcing's harmonics, in the forcing's order.
    pub harmonics: Vec<HarmonicResponse>,
}

impl HarmonicState {
    /// The displacements `u` at `θ`.
    pub fn displacements(&self, theta: f64) -> DVector<f64> {
        let mut u = &self.cosine * theta.cos() + &self.sine * theta.sin();
        for h in &self.harmonics {
            let (s, c) = (f64::from(h.order) * theta).sin_cos();
            u += &h.cosine * c + &h.sine * s;
        }
        u
    }

    /// The terms `(k, a, b)` of the coordinate `cᵀu`, `cᵀu = Σ a cos kθ + b sin kθ`.
    fn terms(&self, c: impl Fn(&DVector<f64>) -> f64) -> Vec<(u32, f64, f64)> {
        std::iter::once((1, c(&self.cosine), c(&self.sine)))
            .chain(
                self.harmonics
                    .iter()
                    .map(|h| (h.order, c(&h.cosine), c(&h.sine))),
            )
            .collect()
    }

    /// Amplitude `max_t |u_k(t)|` of every coordinate: `√(U_c,k² + U_s,k²)` without
    /// harmonics (or with harmonics of zero response), otherwise the extremes of the
    /// trigonometric polynomial, sampled and polished by Newton to rounding.
    pub fn amplitudes(&self) -> DVector<f64> {
        if self.harmonics.is_empty() {
            return self.cosine.zip_map(&self.sine, f64::hypot);
        }
        DVector::from_fn(self.cosine.len(), |k, _| {
            let (low, high) = trig_extremes(&self.terms(|v| v[k]));
            high.max(-low)
        })
    }

    /// `(min, max)` over a period of the relative coordinate `r = wᵀu` of `pair`:
    /// `(−A, A)`, `A = √((wᵀU_c)² + (wᵀU_s)²)`, without harmonics. The linear motion stays
    /// clear of its stops exactly when `max ≤ gap_side1` and `−min ≤ gap_side2`.
    pub fn relative_extremes(&self, pair: &ContactPair) -> (f64, f64) {
        trig_extremes(&self.terms(|v| pair.relative(v)))
    }

    /// Amplitude `max_t |r(t)|` of the relative coordinate `r = wᵀu` of `pair`: the linear
    /// motion stays clear of its stops when this is `≤` the smaller gap (exactly so without
    /// harmonics, whose motion is symmetric; [`HarmonicState::relative_extremes`] tells each
    /// side).
    pub fn relative_amplitude(&self, pair: &ContactPair) -> f64 {
        if self.harmonics.is_empty() {
            return pair.relative(&self.cosine).hypot(pair.relative(&self.sine));
        }
        let (low, high) = self.relative_extremes(pair);
        high.max(-low)
    }
}

// The rigid modes of a model, found when it is built (their use, the family of linear
// motions clear of the stops, is in `rigid`).

/// An eigenvalue of `K` (or `C`) is zero when its modulus is at most this many units of
/// roundoff times `n` and the largest modulus: the accuracy of the symmetric eigen-solver on
/// an exactly singular matrix, with room for matrices assembled by sums in another order.
pub const RIGID_EIGENVALUE: f64 = 64.0 * f64::EPSILON;

/// A pair's coordinate involves a rigid mode when `|Φᵀw|` exceeds this fraction of `|w|`:
/// far above the rounding of an orthonormal basis computed from `K`, far below any coupling a
/// model means.
pub const RIGID_COUPLING: f64 = 1e-10;

/// The orthonormal basis (`n × r`, `r = 0` when `K` is regular) of the null space of the
/// symmetric `stiffness`, checking that it and `damping` are positive semidefinite.
///
/// # Errors
/// [`ModelError::Structure`] naming `model.stiffness` or `model.damping` when it has an
/// eigenvalue below `−`[`RIGID_EIGENVALUE`]` · n · max |λ|`.
pub(crate) fn rigid_basis(
    stiffness: &DMatrix<f64>,
    damping: &DMatrix<f64>,
) -> Result<DMatrix<f64>, ModelError> {
    let n = stiffness.nrows();
    let floor = |values: &DVector<f64>| RIGID_EIGENVALUE * n as f64 * values.amax();
    let damping_values = damping.clone().symmetric_eigenvalues();
    if damping_values.min() < -floor(&damping_values) {
        return Err(ModelError::Structure {
            field: "model.damping".to_string(),
            required: "positive semidefinite (a negative damping has no bounded motion)",
        });
    }
    let eigen = SymmetricEigen::new(stiffness.clone());
    let zero = floor(&eigen.eigenvalues);
    if eigen.eigenvalues.min() < -zero {
        return Err(ModelError::Structure {
            field: "model.stiffness".to_string(),
            required: "positive semidefinite (a negative stiffness has no bounded motion)",
        });
    }
    let columns: Vec<DVector<f64>> = (0..n)
        .filter(|&k| eigen.eigenvalues[k].abs() <= zero)
        .map(|k| eigen.eigenvectors.column(k).into_owned())
        .collect();
    if columns.is_empty() {
        return Ok(DMatrix::zeros(n, 0));
    }
    Ok(DMatrix::from_columns(&columns))
}

/// Checks that every rigid direction `Φa` is restrained by a dashpot or a pair: the stacked
/// `[CΦ / max|C|; w_pᵀΦ / |w_p|]` has full column rank `r`, its singular values above
/// [`RIGID_COUPLING`] (`Φ` orthonormal, every row scaled to at most unit size).
///
/// # Errors
/// [`ModelError::Drift`] with the number of free directions otherwise.
pub(crate) fn check_restrained(
    rigid: &DMatrix<f64>,
    damping: &DMatrix<f64>,
    pairs: &[ContactPair],
) -> Result<(), ModelError> {
    let (n, r) = rigid.shape();
    if r == 0 {
        return Ok(());
    }
    let damping_scale = damping.amax();
    let mut stacked = DMatrix::zeros(n + pairs.len(), r);
    if damping_scale > 0.0 {
        stacked
            .view_mut((0, 0), (n, r))
            .copy_from(&(damping * rigid / damping_scale));
    }
    for (p, pair) in pairs.iter().enumerate() {
        let row = rigid.tr_mul(&pair.direction) / pair.direction.norm();
        stacked
            .view_mut((n + p, 0), (1, r))
            .copy_from(&row.transpose());
    }
    let restrained = stacked
        .singular_values()
        .iter()
        .filter(|&&s| s > RIGID_COUPLING)
        .count();
    if restrained < r {
        return Err(ModelError::Drift {
            modes: r,
            free: r - restrained,
        });
    }
    Ok(())
}

/// Whether `b = Φᵀw` of a pair's direction `w` is a coupling to the rigid modes
/// (`|b| > `[`RIGID_COUPLING`]` |w|`).
pub(crate) fn couples(b: &DVector<f64>, w: &DVector<f64>) -> bool {
    b.norm() > RIGID_COUPLING * w.norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::ForcedFlow;
    use crate::test_models::{damped_paper_unit, paper_stops};
    use nalgebra::{Vector2, Vector4};

    /// The unit's model carries the unit's own flow and saltation (crate-private in
    /// [`crate::orbit`]): the same matrices computed in another order, to a few ulps of the
    /// exponential's accuracy.
    #[test]
    fn unit_model_has_the_units_flow_and_saltation() {
        const TOLERANCE: f64 = 1e-13;
        let unit = damped_paper_unit();
        let stops = paper_stops();
        let model = LinearModel::unit(&unit, &stops).unwrap_or_else(|e| panic!("{e}"));
        let omega = 1.7;
        let flow = ForcedFlow::new(&unit, omega);
        let t = 0.37 * flow.period();
        let fixed = flow.transition(t);
        let general = model.transition(omega, t);
        let x = Vector4::new(0.2, 0.7, -0.3, 1.1);
        let p = Vector2::new(0.6, 0.8);
        let (fx, fp) = fixed.apply(&x, &p);
        let (gx, gp) = general.apply(
            &DVector::from_column_slice(x.as_slice()),
            &DVector::from_column_slice(p.as_slice()),
        );
        for k in 0..4 {
            assert!((fx[k] - gx[k]).abs() <= TOLERANCE * fx.amax(), "state {k}");
        }
        assert!((fp[0] - gp[0]).abs() <= TOLERANCE && (fp[1] - gp[1]).abs() <= TOLERANCE);
        let g = stops.impact_map(&unit);
        let fixed = crate::orbit::saltation(&flow, &g, &x, &p);
        let general = model.saltation(
            omega,
            0,
            &DVector::from_column_slice(x.as_slice()),
            &DVector::from_column_slice(p.as_slice()),
        );
        for j in 0..4 {
            for k in 0..4 {
                assert!(
                    (fixed[(j, k)] - general[(j, k)]).abs() <= TOLERANCE * fixed.amax(),
                    "saltation ({j}, {k})"
                );
            }
        }
    }
}
