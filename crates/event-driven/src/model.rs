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

/// Two degrees of freedom that impact: `r = u[plus_dof] − u[minus_dof]` is confined to
/// `[−gap_minus, gap_plus]`. Side 1 is the stop at `r = +gap_plus`, side 2 at `r = −gap_minus`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPair {
    /// The degree of freedom counted positive in `r`.
    pub plus_dof: usize,
    /// The degree of freedom counted negative in `r`.
    pub minus_dof: usize,
    /// Distance to side 1, `> 0`.
    pub gap_plus: f64,
    /// Distance to side 2, `> 0`.
    pub gap_minus: f64,
    /// Newton restitution `e ∈ [0, 1]`: `ṙ⁺ = −e ṙ⁻`.
    pub restitution: f64,
}

/// `M ü + C u̇ + K u = f_c cos ωt + f_s sin ωt`, with contact pairs.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    pub(crate) mass: DMatrix<f64>,
    pub(crate) stiffness: DMatrix<f64>,
    pub(crate) damping: Option<DMatrix<f64>>,
    pub(crate) forcing_cos: DVector<f64>,
    pub(crate) forcing_sin: DVector<f64>,
    pub(crate) contacts: Vec<ContactPair>,
    /// Per contact: `d` and `M⁻¹d`.
    pub(crate) directions: Vec<(DVector<f64>, DVector<f64>)>,
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
            if c.plus_dof >= n || c.minus_dof >= n || c.plus_dof == c.minus_dof {
                return Err(ModelError::Size(format!(
                    "contact {k}: degrees of freedom out of range or equal"
                )));
            }
            check(
                &format!("contacts[{k}].gap_plus"),
                c.gap_plus,
                c.gap_plus > 0.0,
                "> 0",
            )?;
            check(
                &format!("contacts[{k}].gap_minus"),
                c.gap_minus,
                c.gap_minus > 0.0,
                "> 0",
            )?;
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
                let mut d = DVector::zeros(n);
                d[c.plus_dof] = 1.0;
                d[c.minus_dof] = -1.0;
                let mobility = &minv * &d;
                (d, mobility)
            })
            .collect();
        Ok(Model {
            mass,
            stiffness,
            damping,
            forcing_cos,
            forcing_sin,
            contacts,
            directions,
        })
    }

    /// The mass-in-mass unit: DOF 0 the outer mass `u_o`, DOF 1 the inner mass `u_i`, base
    /// motion `u_g cos ωt` through `k_o` (and `c_o`): `f = (k_o u_g cos ωt − c_o u_g ω sin ωt, 0)`;
    /// with `stops = Some((gap, restitution))` one contact pair `r = u_i − u_o ∈ [−gap, gap]`.
    /// A dashpot given as `None` (or both `None`) adds no damping terms.
    #[allow(clippy::too_many_arguments)]
    pub fn two_dof_unit(
        outer_mass: f64,
        inner_mass: f64,
        outer_stiffness: f64,
        inner_stiffness: f64,
        outer_damping: Option<f64>,
        inner_damping: Option<f64>,
        base_amplitude: f64,
        omega: f64,
        stops: Option<(f64, f64)>,
    ) -> Result<Model, ModelError> {
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
            Some((gap, restitution)) => vec![ContactPair {
                plus_dof: 1,
                minus_dof: 0,
                gap_plus: gap,
                gap_minus: gap,
                restitution,
            }],
            None => Vec::new(),
        };
        Model::new(mass, stiffness, damping, forcing_cos, forcing_sin, contacts)
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

    /// True when nothing dissipates: no damping and every restitution is 1.
    pub fn conservative(&self) -> bool {
        !self.has_damping() && self.contacts.iter().all(|c| c.restitution == 1.0)
    }
}
