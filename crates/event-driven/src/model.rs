//! The problem: a linear structure with harmonic forcing and impacting contact pairs.

use nalgebra::{DMatrix, DVector};
use thiserror::Error;

/// A value of the model outside its allowed range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModelError {
    /// A named parameter is not finite or out of range.
    #[error("{field} = {value} is out of range: must be {allowed}")]
    OutOfRange {
        /// Which parameter.
        field: String,
        /// Its value.
        value: f64,
        /// The allowed range.
        allowed: &'static str,
    },
    /// Matrices or vectors of mismatched sizes.
    #[error("size mismatch: {0}")]
    Size(String),
}

fn check(field: &str, value: f64, ok: bool, allowed: &'static str) -> Result<(), ModelError> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(ModelError::OutOfRange {
            field: field.to_owned(),
            value,
            allowed,
        })
    }
}

/// Two degrees of freedom that impact, or one against the fixed frame: `r = u[plus_dof] −
/// u[minus_dof]` (an end that is `None` is the frame, `u = 0`) is confined to
/// `[−gap_minus, gap_plus]`. Side 1 is the stop at `r = +gap_plus`, side 2 at `r = −gap_minus`.
/// A side whose gap is `+∞` has no stop (a one-sided stop); at least one side has one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPair {
    /// The degree of freedom counted positive in `r`; `None`: the frame.
    pub plus_dof: Option<usize>,
    /// The degree of freedom counted negative in `r`; `None`: the frame.
    pub minus_dof: Option<usize>,
    /// Distance to side 1, `> 0`; `+∞`: no stop on side 1.
    pub gap_plus: f64,
    /// Distance to side 2, `> 0`; `+∞`: no stop on side 2.
    pub gap_minus: f64,
    /// Newton restitution `e ∈ [0, 1]`: `ṙ⁺ = −e ṙ⁻`.
    pub restitution: f64,
}

/// Largest number of cells of [`Model::chain`]. The solver's cost grows with the cube of the
/// size: the modal flow is a dense eigendecomposition of the `4N × 4N` state matrix (again for
/// each set of held pairs met, `O((4N)³)`: some 10⁸ flops at 64 cells), and every flight
/// expands each of the `N` pairs' gaps over all `4N` modes, `O(N²)` per flight with `O(N)`
/// impacting pairs per period, so a period costs `O(N³)`: 512 times an 8-cell chain's at 64
/// cells (the 8-cell chain takes about 4.3 µs of one core per impact, example `chain8`,
/// `benches/chain.rs`). Beyond that
/// the crowding of a long chain's modal frequencies (spacing `∝ 1/N²` at the band edges) also
/// erodes the conditioning of the eigenvectors the closed form rests on.
pub const MAX_CELLS: usize = 64;

/// The stops of one cell: `r = u_i − u_o ∈ [−gap_minus, gap_plus]`, Newton restitution `e`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellStops {
    /// Distance to side 1 (`r = +gap_plus`), `> 0`.
    pub gap_plus: f64,
    /// Distance to side 2 (`r = −gap_minus`), `> 0`.
    pub gap_minus: f64,
    /// Newton restitution `e ∈ [0, 1]`.
    pub restitution: f64,
}

impl CellStops {
    /// Stops at `±gap` (the unit's `stops = Some((gap, restitution))`).
    pub fn symmetric(gap: f64, restitution: f64) -> CellStops {
        CellStops {
            gap_plus: gap,
            gap_minus: gap,
            restitution,
        }
    }
}

impl ContactPair {
    /// The contact direction `d` (length `n`): `r = d·u`, `+1` at `plus_dof`, `−1` at
    /// `minus_dof`.
    pub fn direction(&self, n: usize) -> DVector<f64> {
        let mut d = DVector::zeros(n);
        if let Some(i) = self.plus_dof {
            d[i] = 1.0;
        }
        if let Some(i) = self.minus_dof {
            d[i] = -1.0;
        }
        d
    }

    /// The relative displacement `r = u[plus_dof] − u[minus_dof]` of the displacements (or
    /// velocities) `u`: the frame's entries are 0.
    pub fn relative(&self, u: &[f64]) -> f64 {
        self.plus_dof.map_or(0.0, |i| u[i]) - self.minus_dof.map_or(0.0, |i| u[i])
    }
}

/// One cell of a chain ([`Model::chain`]): the unit's parameters without the base's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellParameters {
    /// `m_o > 0`.
    pub outer_mass: f64,
    /// `m_i > 0`.
    pub inner_mass: f64,
    /// `k_o > 0`: to the previous cell's outer mass (the base for the first cell).
    pub outer_stiffness: f64,
    /// `k_i > 0`: inner to outer mass.
    pub inner_stiffness: f64,
    /// `c_o ≥ 0`, beside `k_o`; `None` adds no damping term of its own.
    pub outer_damping: Option<f64>,
    /// `c_i ≥ 0`, beside `k_i`; `None` adds no damping term of its own.
    pub inner_damping: Option<f64>,
    /// The cell's contact pair, if any.
    pub stops: Option<CellStops>,
}

/// Highest order of a [`Harmonic`]: a harmonic of order `k` makes the searches step at an
/// eighth of its period `2π/(kω)`, so an order far beyond any physical forcing's would only
/// slow every flight down.
pub const MAX_HARMONIC_ORDER: u32 = 1000;

/// The Kelvin–Voigt contact law of a compliant stop ([`Model::with_compliance`]): while a
/// pair's penetration `δ = side·r − gap_side` is positive, a spring `stiffness` (`k_c`) and a
/// dashpot `damping` (`c_c`) act between the pair along its direction `d`, the generalised
/// force `−d (k_c (r − side·gap_side) + c_c ṙ)`. The contact starts when the pair reaches a
/// stop moving into it (no velocity jump) and ends when `δ` returns to `0`, whatever the sign
/// of the force then (the dashpot may pull at the very end: the law stays linear, so each
/// contact phase is an exact modal flow). Both sides of the pair use it. For a pair of
/// reduced mass `μ = 1/(dᵀM⁻¹d)` and no other force, the contact lasts `π/ω_d`
/// (`ω_d = √(k_c/μ) √(1 − ζ²)`, `ζ = c_c/(2√(k_c μ))`) and returns the relative velocity
/// times `−e`, `e = exp(−ζπ/√(1 − ζ²))` ([`Compliance::restitution`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Compliance {
    /// `k_c > 0`, finite.
    pub stiffness: f64,
    /// `c_c ≥ 0`, finite.
    pub damping: f64,
}

impl Compliance {
    /// The damping ratio `ζ = c_c/(2√(k_c μ))` of the contact for a pair of reduced mass `mu`.
    pub fn damping_ratio(&self, mu: f64) -> f64 {
        self.damping / (2.0 * (self.stiffness * mu).sqrt())
    }

    /// The isolated pair's coefficient of restitution `e = exp(−ζπ/√(1 − ζ²))` for reduced
    /// mass `mu` (`0` for `ζ ≥ 1`: an overdamped contact of an isolated pair never ends).
    pub fn restitution(&self, mu: f64) -> f64 {
        let zeta = self.damping_ratio(mu);
        if zeta >= 1.0 {
            0.0
        } else {
            (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp()
        }
    }

    /// The contact damping `c_c = 2ζ√(k_c μ)` that gives an isolated pair of reduced mass
    /// `mu` the restitution `e ∈ (0, 1]` at contact stiffness `stiffness`:
    /// `ζ = −ln e / √(π² + ln² e)`.
    pub fn matching(stiffness: f64, restitution: f64, mu: f64) -> Compliance {
        let l = restitution.ln();
        let zeta = -l / (std::f64::consts::PI * std::f64::consts::PI + l * l).sqrt();
        Compliance {
            stiffness,
            damping: 2.0 * zeta * (stiffness * mu).sqrt(),
        }
    }
}

/// Largest ratio of a compliant stop's contact rate `√(k_c/μ)` to the forcing frequency `ω`
/// ([`Model::check_compliance`]): the contact then lasts at least `π/(10⁶ ω) = T/(2·10⁶)`.
/// The contact's entry and exit are times within the period, known to its rounding
/// `ε T ≈ 2.2e-16 T`; the state there moves on the contact's time scale, so that rounding
/// alone moves the exit state by about `√(k_c/μ) ε T ≈ 1.4e-9` of its size at this bound,
/// the periodicity test's tolerance ([`crate::DEFAULT_PERIODICITY_TOLERANCE`]): a stiffer
/// contact could no longer be resolved by the time it is carried in. It also keeps the
/// shortest contact `5000` times longer than the grace after its exit
/// (`1e-10 T`, in which the pair's stop is not watched).
pub const MAX_CONTACT_RATE_RATIO: f64 = 1e6;

/// One higher harmonic of the forcing, `f_c cos kωt + f_s sin kωt` (`k = order`): the model
/// is then forced by `f_c cos ωt + f_s sin ωt + Σ_harmonics (f_c,k cos kωt + f_s,k sin kωt)`,
/// still of period `2π/ω`.
#[derive(Debug, Clone, PartialEq)]
pub struct Harmonic {
    /// The order `k`, an integer in `2..=`[`MAX_HARMONIC_ORDER`] (the fundamental, order 1,
    /// is the model's own forcing).
    pub order: u32,
    /// `f_c,k`, one entry per degree of freedom, finite.
    pub cos: DVector<f64>,
    /// `f_s,k`, one entry per degree of freedom, finite.
    pub sin: DVector<f64>,
}

impl Harmonic {
    /// Whether both amplitude vectors are zero: such a harmonic forces nothing, and the
    /// simulator leaves it out (the model then flies exactly as without it).
    pub fn is_zero(&self) -> bool {
        self.cos.iter().chain(self.sin.iter()).all(|&v| v == 0.0)
    }
}

/// `M ü + C u̇ + K u = f_c cos ωt + f_s sin ωt + Σ_k (f_c,k cos kωt + f_s,k sin kωt)`, with
/// contact pairs; the higher harmonics (orders `k ≥ 2`) are optional
/// ([`Model::with_harmonics`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    pub(crate) mass: DMatrix<f64>,
    pub(crate) stiffness: DMatrix<f64>,
    pub(crate) damping: Option<DMatrix<f64>>,
    pub(crate) forcing_cos: DVector<f64>,
    pub(crate) forcing_sin: DVector<f64>,
    /// The higher harmonics, as given (orders distinct, each `≥ 2`).
    pub(crate) harmonics: Vec<Harmonic>,
    pub(crate) contacts: Vec<ContactPair>,
    /// Per contact: `d` and `M⁻¹d`.
    pub(crate) directions: Vec<(DVector<f64>, DVector<f64>)>,
    /// Whether every flight flies in the resonance-safe general form
    /// ([`Self::with_general_form`]).
    pub(crate) general_form: bool,
    /// Per contact, its compliant contact law, `None` for a rigid stop (Newton restitution).
    pub(crate) compliances: Vec<Option<Compliance>>,
}

impl Model {
    /// A model from its matrices. `damping` `None` means no damping terms at all. Checks sizes,
    /// finiteness, a positive mass diagonal and every contact's indices, gaps and restitution.
    pub fn new(
        mass: DMatrix<f64>,
        stiffness: DMatrix<f64>,
        damping: Option<DMatrix<f64>>,
        forcing_cos: DVector<f64>,
        forcing_sin: DVector<f64>,
        contacts: Vec<ContactPair>,
    ) -> Result<Model, ModelError> {
        let n = mass.nrows();
        let square = |m: &DMatrix<f64>| m.nrows() == n && m.ncols() == n;
        if n == 0
            || !square(&mass)
            || !square(&stiffness)
            || damping.as_ref().is_some_and(|c| !square(c))
        {
            return Err(ModelError::Size(
                "mass, stiffness and damping must be n×n, n ≥ 1".into(),
            ));
        }
        if forcing_cos.len() != n || forcing_sin.len() != n {
            return Err(ModelError::Size(
                "forcing vectors must have n entries".into(),
            ));
        }
        for i in 0..n {
            check(
                &format!("mass[{i}][{i}]"),
                mass[(i, i)],
                mass[(i, i)] > 0.0,
                "> 0",
            )?;
        }
        let all = mass
            .iter()
            .chain(stiffness.iter())
            .chain(damping.iter().flat_map(|c| c.iter()))
            .chain(forcing_cos.iter())
            .chain(forcing_sin.iter());
        for &v in all {
            check("matrix entry", v, true, "finite")?;
        }
        for (k, c) in contacts.iter().enumerate() {
            let out = |dof: Option<usize>| dof.is_some_and(|i| i >= n);
            if out(c.plus_dof)
                || out(c.minus_dof)
                || c.plus_dof == c.minus_dof
                || (c.plus_dof.is_none() && c.minus_dof.is_none())
            {
                return Err(ModelError::Size(format!(
                    "contact {k}: degrees of freedom out of range, equal, or both the frame"
                )));
            }
            for (side, gap) in [("gap_plus", c.gap_plus), ("gap_minus", c.gap_minus)] {
                if gap.is_nan() || gap <= 0.0 {
                    return Err(ModelError::OutOfRange {
                        field: format!("contacts[{k}].{side}"),
                        value: gap,
                        allowed: "> 0 (+inf: no stop on that side)",
                    });
                }
            }
            if !(c.gap_plus.is_finite() || c.gap_minus.is_finite()) {
                return Err(ModelError::OutOfRange {
                    field: format!("contacts[{k}].gap_plus"),
                    value: c.gap_plus,
                    allowed: "finite on at least one side",
                });
            }
            check(
                &format!("contacts[{k}].restitution"),
                c.restitution,
                (0.0..=1.0).contains(&c.restitution),
                "in [0, 1]",
            )?;
        }
        let minv = mass
            .clone()
            .try_inverse()
            .ok_or_else(|| ModelError::Size("the mass matrix is singular".into()))?;
        let directions = contacts
            .iter()
            .map(|c| {
                let d = c.direction(n);
                let mobility = &minv * &d;
                (d, mobility)
            })
            .collect();
        let compliances = vec![None; contacts.len()];
        Ok(Model {
            mass,
            stiffness,
            damping,
            forcing_cos,
            forcing_sin,
            harmonics: Vec::new(),
            contacts,
            directions,
            general_form: false,
            compliances,
        })
    }

    /// The model with the higher harmonics `harmonics` added to its forcing (replacing any it
    /// had): `f(t) = f_c cos ωt + f_s sin ωt + Σ (f_c,k cos kωt + f_s,k sin kωt)`, in any order
    /// of the orders. An empty list gives the model back as [`Self::new`] built it, and a
    /// harmonic whose amplitudes are all zero forces nothing ([`Harmonic::is_zero`]).
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming the field: `harmonics[i].order` outside
    /// `2..=`[`MAX_HARMONIC_ORDER`] or equal to an earlier harmonic's order,
    /// `harmonics[i].cos` or `harmonics[i].sin` (its value the number of entries) not of one
    /// entry per degree of freedom, and `harmonics[i].cos[j]` or `harmonics[i].sin[j]` not
    /// finite.
    pub fn with_harmonics(mut self, harmonics: Vec<Harmonic>) -> Result<Model, ModelError> {
        let n = self.dofs();
        for (i, h) in harmonics.iter().enumerate() {
            let order = h.order as f64;
            check(
                &format!("harmonics[{i}].order"),
                order,
                (2..=MAX_HARMONIC_ORDER).contains(&h.order),
                "an integer in 2..=1000 (order 1 is the model's own forcing)",
            )?;
            check(
                &format!("harmonics[{i}].order"),
                order,
                harmonics[..i].iter().all(|g| g.order != h.order),
                "distinct from every other harmonic's order",
            )?;
            for (name, amplitudes) in [("cos", &h.cos), ("sin", &h.sin)] {
                check(
                    &format!("harmonics[{i}].{name}"),
                    amplitudes.len() as f64,
                    amplitudes.len() == n,
                    "one entry per degree of freedom (the model's n)",
                )?;
                for (j, &v) in amplitudes.iter().enumerate() {
                    check(&format!("harmonics[{i}].{name}[{j}]"), v, true, "finite")?;
                }
            }
        }
        self.harmonics = harmonics;
        Ok(self)
    }

    /// The model with contact pair `pair`'s stops compliant, of contact law `compliance`
    /// (both sides; replacing any law it had): its [`ContactPair::restitution`] is then
    /// unused, and the pair's contacts are phases of finite duration ([`Compliance`]) rather
    /// than impacts. Other pairs stay as they are.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming the field: `pair` (its value the index) not a
    /// contact pair of the model, `compliance.stiffness` not finite or `≤ 0`, and
    /// `compliance.damping` not finite or `< 0`. The stiffness's upper bound depends on the
    /// forcing frequency: [`Self::check_compliance`], which the simulation applies.
    pub fn with_compliance(
        mut self,
        pair: usize,
        compliance: Compliance,
    ) -> Result<Model, ModelError> {
        check(
            "pair",
            pair as f64,
            pair < self.contacts.len(),
            "the index of one of the model's contact pairs",
        )?;
        check(
            "compliance.stiffness",
            compliance.stiffness,
            compliance.stiffness > 0.0,
            "finite and > 0",
        )?;
        check(
            "compliance.damping",
            compliance.damping,
            compliance.damping >= 0.0,
            "finite and >= 0",
        )?;
        self.compliances[pair] = Some(compliance);
        Ok(self)
    }

    /// The contact law of pair `pair`: `Some` for a compliant stop ([`Self::with_compliance`]),
    /// `None` for a rigid one (or a pair out of range).
    pub fn compliance(&self, pair: usize) -> Option<Compliance> {
        self.compliances.get(pair).copied().flatten()
    }

    /// Whether any contact pair is compliant.
    pub fn has_compliance(&self) -> bool {
        self.compliances.iter().any(Option::is_some)
    }

    /// The reduced mass `μ = 1/(dᵀM⁻¹d)` of contact pair `pair`: the mass an isolated pair's
    /// contact law acts on.
    ///
    /// # Panics
    /// If `pair` is not a contact pair of the model.
    pub fn reduced_mass(&self, pair: usize) -> f64 {
        let (d, mobility) = &self.directions[pair];
        1.0 / d.dot(mobility)
    }

    /// Whether every compliant stop can be resolved at forcing frequency `omega`: its contact
    /// rate `√(k_c/μ)` is at most [`MAX_CONTACT_RATE_RATIO`] times `omega`.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] with field `compliance[p].stiffness` for the first pair `p`
    /// whose stiffness exceeds `μ (10⁶ ω)²`.
    pub fn check_compliance(&self, omega: f64) -> Result<(), ModelError> {
        for (p, law) in self.compliances.iter().enumerate() {
            if let Some(law) = law {
                let rate = (law.stiffness / self.reduced_mass(p)).sqrt();
                check(
                    &format!("compliance[{p}].stiffness"),
                    law.stiffness,
                    rate <= MAX_CONTACT_RATE_RATIO * omega,
                    "at most μ (1e6 ω)²: a contact rate √(k_c/μ) up to 1e6 times the forcing \
                     frequency (MAX_CONTACT_RATE_RATIO)",
                )?;
            }
        }
        Ok(())
    }

    /// The model with every free and stuck flight in the resonance-safe general form, whether
    /// or not the flow's steady-response form exists: the same motion to rounding, slower. It
    /// is the reference the steady-response form is checked against, not for use.
    #[doc(hidden)]
    pub fn with_general_form(mut self) -> Model {
        self.general_form = true;
        self
    }

    /// The higher harmonics of the forcing (orders `≥ 2`), as given to
    /// [`Self::with_harmonics`]; empty for a model forced at `ω` alone.
    pub fn harmonics(&self) -> &[Harmonic] {
        &self.harmonics
    }

    /// The harmonics that force anything (not [`Harmonic::is_zero`]): the ones the
    /// simulator's flows and events carry.
    pub(crate) fn active_harmonics(&self) -> impl Iterator<Item = &Harmonic> {
        self.harmonics.iter().filter(|h| !h.is_zero())
    }

    /// The mass-in-mass unit of one `cell`: DOF 0 the outer mass `u_o`, DOF 1 the inner mass
    /// `u_i`, base motion `u_g cos ωt` (`u_g = base_amplitude`) through `k_o` (and `c_o`):
    /// `f = (k_o u_g cos ωt − c_o u_g ω sin ωt, 0)`; with stops, one contact pair
    /// `r = u_i − u_o ∈ [−gap_minus, gap_plus]`. A dashpot given as `None` (or both `None`)
    /// adds no damping terms.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming the field (`unit.outer_mass`, `unit.inner_mass`,
    /// `unit.outer_stiffness`, `unit.inner_stiffness`, `base.amplitude`, `omega`,
    /// `damping.outer`, `damping.inner`, and the contact pair's gaps and restitution) for a
    /// value out of range.
    pub fn unit(
        cell: &CellParameters,
        base_amplitude: f64,
        omega: f64,
    ) -> Result<Model, ModelError> {
        let CellParameters {
            outer_mass,
            inner_mass,
            outer_stiffness,
            inner_stiffness,
            outer_damping,
            inner_damping,
            stops,
        } = *cell;
        check("unit.outer_mass", outer_mass, outer_mass > 0.0, "> 0")?;
        check("unit.inner_mass", inner_mass, inner_mass > 0.0, "> 0")?;
        check(
            "unit.outer_stiffness",
            outer_stiffness,
            outer_stiffness > 0.0,
            "> 0",
        )?;
        check(
            "unit.inner_stiffness",
            inner_stiffness,
            inner_stiffness > 0.0,
            "> 0",
        )?;
        check(
            "base.amplitude",
            base_amplitude,
            base_amplitude > 0.0,
            "> 0",
        )?;
        check("omega", omega, omega > 0.0, "> 0")?;
        let (co, ci) = (outer_damping.unwrap_or(0.0), inner_damping.unwrap_or(0.0));
        check("damping.outer", co, co >= 0.0, ">= 0")?;
        check("damping.inner", ci, ci >= 0.0, ">= 0")?;
        let (mo, mi, ko, ki) = (outer_mass, inner_mass, outer_stiffness, inner_stiffness);
        let mass = DMatrix::from_row_slice(2, 2, &[mo, 0.0, 0.0, mi]);
        let stiffness = DMatrix::from_row_slice(2, 2, &[ko + ki, -ki, -ki, ki]);
        let damping = (outer_damping.is_some() || inner_damping.is_some())
            .then(|| DMatrix::from_row_slice(2, 2, &[co + ci, -ci, -ci, ci]));
        let forcing_cos = DVector::from_vec(vec![ko * base_amplitude, 0.0]);
        let forcing_sin = DVector::from_vec(vec![-co * base_amplitude * omega, 0.0]);
        let contacts = match stops {
            Some(stops) => vec![ContactPair {
                plus_dof: Some(1),
                minus_dof: Some(0),
                gap_plus: stops.gap_plus,
                gap_minus: stops.gap_minus,
                restitution: stops.restitution,
            }],
            None => Vec::new(),
        };
        Model::new(mass, stiffness, damping, forcing_cos, forcing_sin, contacts)
    }

    /// A chain of `cells.len()` mass-in-mass cells in series (the impacting metamaterial):
    /// outer mass `j` is tied to outer mass `j − 1` by cell `j`'s `k_o` (and `c_o`), the first
    /// to the base, which moves as `u_g cos ωt` and forces it as in [`Self::unit`];
    /// inner mass `j` sits inside outer mass `j` on `k_i` (and `c_i`), with its own contact
    /// pair when the cell has stops.
    ///
    /// State ordering: `u = (u_o1, u_i1, u_o2, u_i2, …)` (DOF `2j` the outer mass of cell
    /// `j + 1`, DOF `2j + 1` its inner mass); the contact pairs are listed in cell order, one
    /// per cell with stops, each `r_j = u_ij − u_oj ∈ [−gap_minus, gap_plus]`. One cell builds
    /// the very matrices of [`Self::unit`] (same entries, same floating-point sums).
    /// Damping terms are present when any cell has a dashpot.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming the cell and field (`cells[j].outer_mass`, …,
    /// `cells[j].stops.gap_plus`, `base.amplitude`, `omega`) for a value out of range, and
    /// for a number of cells outside `1..=`[`MAX_CELLS`] (field `cells`).
    pub fn chain(
        cells: &[CellParameters],
        base_amplitude: f64,
        omega: f64,
    ) -> Result<Model, ModelError> {
        let count = cells.len();
        check(
            "cells",
            count as f64,
            (1..=MAX_CELLS).contains(&count),
            "a number of cells in 1..=64",
        )?;
        for (j, c) in cells.iter().enumerate() {
            let field = |name: &str| format!("cells[{j}].{name}");
            check(
                &field("outer_mass"),
                c.outer_mass,
                c.outer_mass > 0.0,
                "> 0",
            )?;
            check(
                &field("inner_mass"),
                c.inner_mass,
                c.inner_mass > 0.0,
                "> 0",
            )?;
            check(
                &field("outer_stiffness"),
                c.outer_stiffness,
                c.outer_stiffness > 0.0,
                "> 0",
            )?;
            check(
                &field("inner_stiffness"),
                c.inner_stiffness,
                c.inner_stiffness > 0.0,
                "> 0",
            )?;
            let (co, ci) = (
                c.outer_damping.unwrap_or(0.0),
                c.inner_damping.unwrap_or(0.0),
            );
            check(&field("outer_damping"), co, co >= 0.0, ">= 0")?;
            check(&field("inner_damping"), ci, ci >= 0.0, ">= 0")?;
            if let Some(stops) = &c.stops {
                check(
                    &field("stops.gap_plus"),
                    stops.gap_plus,
                    stops.gap_plus > 0.0,
                    "> 0",
                )?;
                check(
                    &field("stops.gap_minus"),
                    stops.gap_minus,
                    stops.gap_minus > 0.0,
                    "> 0",
                )?;
                check(
                    &field("stops.restitution"),
                    stops.restitution,
                    (0.0..=1.0).contains(&stops.restitution),
                    "in [0, 1]",
                )?;
            }
        }
        check(
            "base.amplitude",
            base_amplitude,
            base_amplitude > 0.0,
            "> 0",
        )?;
        check("omega", omega, omega > 0.0, "> 0")?;
        let n = 2 * count;
        let damped = cells
            .iter()
            .any(|c| c.outer_damping.is_some() || c.inner_damping.is_some());
        let mut mass = DMatrix::zeros(n, n);
        let mut stiffness = DMatrix::zeros(n, n);
        let mut damping = DMatrix::zeros(n, n);
        let mut contacts = Vec::new();
        for (j, c) in cells.iter().enumerate() {
            let (o, i) = (2 * j, 2 * j + 1);
            let (co, ci) = (
                c.outer_damping.unwrap_or(0.0),
                c.inner_damping.unwrap_or(0.0),
            );
            mass[(o, o)] = c.outer_mass;
            mass[(i, i)] = c.inner_mass;
            // Cell j's own springs, summed as in the unit: k_o + k_i on the outer diagonal.
            stiffness[(o, o)] = c.outer_stiffness + c.inner_stiffness;
            stiffness[(o, i)] = -c.inner_stiffness;
            stiffness[(i, o)] = -c.inner_stiffness;
            stiffness[(i, i)] = c.inner_stiffness;
            damping[(o, o)] = co + ci;
            damping[(o, i)] = -ci;
            damping[(i, o)] = -ci;
            damping[(i, i)] = ci;
            // Cell j + 1's outer spring ties outer mass j + 1 to outer mass j.
            if let Some(next) = cells.get(j + 1) {
                let p = o + 2;
                stiffness[(o, o)] += next.outer_stiffness;
                stiffness[(o, p)] = -next.outer_stiffness;
                stiffness[(p, o)] = -next.outer_stiffness;
                let cn = next.outer_damping.unwrap_or(0.0);
                damping[(o, o)] += cn;
                damping[(o, p)] = -cn;
                damping[(p, o)] = -cn;
            }
            if let Some(stops) = c.stops {
                contacts.push(ContactPair {
                    plus_dof: Some(i),
                    minus_dof: Some(o),
                    gap_plus: stops.gap_plus,
                    gap_minus: stops.gap_minus,
                    restitution: stops.restitution,
                });
            }
        }
        // Only the first cell's outer spring and dashpot reach the base.
        let first = &cells[0];
        let co = first.outer_damping.unwrap_or(0.0);
        let mut forcing_cos = DVector::zeros(n);
        let mut forcing_sin = DVector::zeros(n);
        forcing_cos[0] = first.outer_stiffness * base_amplitude;
        forcing_sin[0] = -co * base_amplitude * omega;
        Model::new(
            mass,
            stiffness,
            damped.then_some(damping),
            forcing_cos,
            forcing_sin,
            contacts,
        )
    }

    /// Whether damping terms are present.
    pub fn has_damping(&self) -> bool {
        self.damping.is_some()
    }

    /// Whether there are contact pairs (and so event machinery).
    pub fn has_contacts(&self) -> bool {
        !self.contacts.is_empty()
    }

    /// Degrees of freedom `n`.
    pub fn dofs(&self) -> usize {
        self.mass.nrows()
    }

    /// The contact pairs.
    pub fn contacts(&self) -> &[ContactPair] {
        &self.contacts
    }

    /// The mass matrix.
    pub fn mass(&self) -> &DMatrix<f64> {
        &self.mass
    }

    /// Velocities just after an impact of contact pair `pair`, from those just before:
    /// Newton's restitution along the contact direction `d`,
    /// `v⁺ = v⁻ − (1 + e) (d·v⁻) M⁻¹d / (dᵀM⁻¹d)`. Momentum `Σ M v` is conserved, the relative
    /// velocity maps as `ṙ⁺ = −e ṙ⁻`, and the kinetic energy drops by `½ μ (1 − e²) ṙ⁻²`,
    /// `μ = 1/(dᵀM⁻¹d)`. With `restitution = Some(e')`, `e'` replaces the pair's own.
    pub fn impact_velocities(
        &self,
        pair: usize,
        before: &DVector<f64>,
        restitution: Option<f64>,
    ) -> DVector<f64> {
        let n = self.dofs();
        let mut state = DVector::zeros(2 * n);
        state.rows_mut(n, n).copy_from(before);
        self.apply_impact(pair, &mut state, restitution);
        state.rows(n, n).into_owned()
    }

    /// [`Self::impact_velocities`] in place on the velocity half of a state `y = (u, u̇)`
    /// (length `2n`); the positions are left as they are.
    pub fn apply_impact(&self, pair: usize, state: &mut DVector<f64>, restitution: Option<f64>) {
        let n = self.dofs();
        let e = restitution.unwrap_or(self.contacts[pair].restitution);
        let (d, mobility) = &self.directions[pair];
        let rdot: f64 = (0..n).map(|i| d[i] * state[n + i]).sum();
        let scale = (1.0 + e) * rdot / d.dot(mobility);
        for i in 0..n {
            state[n + i] -= mobility[i] * scale;
        }
    }

    /// True when nothing dissipates: no damping, every rigid stop's restitution is 1 and
    /// every compliant stop's damping 0.
    pub fn conservative(&self) -> bool {
        !self.has_damping()
            && self
                .contacts
                .iter()
                .zip(&self.compliances)
                .all(|(c, law)| match law {
                    Some(law) => law.damping == 0.0,
                    None => c.restitution == 1.0,
                })
    }
}
