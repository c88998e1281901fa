//! The problem: the mass-in-mass unit, its optional dashpots and its optional stops.

use nalgebra::{Matrix2, Matrix4, Matrix6};
use thiserror::Error;

/// A parameter of the unit that lies outside its physical range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum UnitError {
    /// The named parameter is not finite or lies outside its allowed range.
    #[error("{field} = {value} is out of range: must be {allowed}")]
    OutOfRange {
        /// Path of the parameter, e.g. `unit.outer_mass`.
        field: &'static str,
        /// The rejected value.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
}

/// Checks that `value` is finite and satisfies `ok`; otherwise names the field.
pub(crate) fn check(
    field: &'static str,
    value: f64,
    ok: bool,
    allowed: &'static str,
) -> Result<(), UnitError> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(UnitError::OutOfRange {
            field,
            value,
            allowed,
        })
    }
}

/// Viscous dashpots: `outer` between base and outer mass (acting on `u̇_o − u̇_g`),
/// `inner` between the two masses (acting on `u̇_i − u̇_o`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damping {
    /// Base-to-outer-mass dashpot `c_o ≥ 0`.
    pub outer: f64,
    /// Outer-to-inner-mass dashpot `c_i ≥ 0`.
    pub inner: f64,
}

/// Two rigid stops inside the outer mass at relative displacement `r = u_i − u_o = ±gap`,
/// with instantaneous Newton restitution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stops {
    /// Half clearance `Δ > 0`: side 1 is the stop at `r = +Δ`, side 2 at `r = −Δ`.
    pub gap: f64,
    /// Newton coefficient of restitution `e ∈ [0, 1]`: `ṙ⁺ = −e ṙ⁻`.
    pub restitution: f64,
}

/// The mass-in-mass unit driven through `k_o` (and `c_o`) by the base motion `u_g cos(ω t)`.
///
/// Equations of motion `M ü + C u̇ + K u = f(t)`, `u = (u_o, u_i)`, `M = diag(m_o, m_i)`,
/// `K = [[k_o + k_i, −k_i], [−k_i, k_i]]`, `C = [[c_o + c_i, −c_i], [−c_i, c_i]]`,
/// `f = (k_o u_g cos ωt − c_o u_g ω sin ωt, 0)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unit {
    /// Outer mass `m_o > 0`.
    pub outer_mass: f64,
    /// Inner mass `m_i > 0`.
    pub inner_mass: f64,
    /// Base-to-outer spring `k_o > 0`.
    pub outer_stiffness: f64,
    /// Outer-to-inner spring `k_i > 0`.
    pub inner_stiffness: f64,
    /// Base displacement amplitude `u_g > 0`.
    pub base_amplitude: f64,
    /// Dashpots, if the unit has any; `None` means no damping terms at all.
    pub damping: Option<Damping>,
}

impl Unit {
    /// Checks every parameter: masses, stiffnesses and base amplitude finite and `> 0`,
    /// dashpots finite and `≥ 0`.
    ///
    /// # Errors
    /// [`UnitError::OutOfRange`] naming the first parameter that fails, in the order of the
    /// fields.
    pub fn validate(&self) -> Result<(), UnitError> {
        check(
            "unit.outer_mass",
            self.outer_mass,
            self.outer_mass > 0.0,
            "> 0",
        )?;
        check(
            "unit.inner_mass",
            self.inner_mass,
            self.inner_mass > 0.0,
            "> 0",
        )?;
        check(
            "unit.outer_stiffness",
            self.outer_stiffness,
            self.outer_stiffness > 0.0,
            "> 0",
        )?;
        check(
            "unit.inner_stiffness",
            self.inner_stiffness,
            self.inner_stiffness > 0.0,
            "> 0",
        )?;
        check(
            "base.amplitude",
            self.base_amplitude,
            self.base_amplitude > 0.0,
            "> 0",
        )?;
        if let Some(d) = self.damping {
            check("damping.outer", d.outer, d.outer >= 0.0, ">= 0")?;
            check("damping.inner", d.inner, d.inner >= 0.0, ">= 0")?;
        }
        Ok(())
    }

    /// Mass matrix `M = diag(m_o, m_i)`.
    pub fn mass(&self) -> Matrix2<f64> {
        Matrix2::new(self.outer_mass, 0.0, 0.0, self.inner_mass)
    }

    /// Stiffness matrix `K = [[k_o + k_i, −k_i], [−k_i, k_i]]`.
    pub fn stiffness(&self) -> Matrix2<f64> {
        let (ko, ki) = (self.outer_stiffness, self.inner_stiffness);
        Matrix2::new(ko + ki, -ki, -ki, ki)
    }

    /// Damping matrix `C = [[c_o + c_i, −c_i], [−c_i, c_i]]` (zero without dashpots).
    pub fn damping_matrix(&self) -> Matrix2<f64> {
        match self.damping {
            Some(Damping { outer, inner }) => Matrix2::new(outer + inner, -inner, -inner, inner),
            None => Matrix2::zeros(),
        }
    }

    /// First-order system matrix `A = [[0, I], [−M⁻¹K, −M⁻¹C]]` for the state
    /// `x = (u_o, u_i, u̇_o, u̇_i)`.
    pub fn system_matrix(&self) -> Matrix4<f64> {
        let minv = Matrix2::new(1.0 / self.outer_mass, 0.0, 0.0, 1.0 / self.inner_mass);
        let mk = -(minv * self.stiffness());
        let mc = -(minv * self.damping_matrix());
        let mut a = Matrix4::zeros();
        a[(0, 2)] = 1.0;
        a[(1, 3)] = 1.0;
        a.fixed_view_mut::<2, 2>(2, 0).copy_from(&mk);
        a.fixed_view_mut::<2, 2>(2, 2).copy_from(&mc);
        a
    }

    /// The system augmented with the forcing's two states `p = (cos θ, sin θ)`, `θ = ωt + α`:
    /// `ż = Â z`, `z = (x, p)`, `Â = [[A, B], [0, W]]`, `W = [[0, −ω], [ω, 0]]`, and `B` carries
    /// `f = (k_o u_g cos θ − c_o u_g ω sin θ, 0)` into the accelerations.
    ///
    /// Its exponential is the exact forced flow, finite at every `ω` (including exact resonance).
    pub fn augmented_matrix(&self, omega: f64) -> Matrix6<f64> {
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<4, 4>(0, 0)
            .copy_from(&self.system_matrix());
        let co = self.damping.map_or(0.0, |d| d.outer);
        m[(2, 4)] = self.outer_stiffness * self.base_amplitude / self.outer_mass;
        m[(2, 5)] = -co * self.base_amplitude * omega / self.outer_mass;
        m[(4, 5)] = -omega;
        m[(5, 4)] = omega;
        m
    }

    /// Reduced mass `μ = m_o m_i / (m_o + m_i)` of the impacting pair.
    pub fn reduced_mass(&self) -> f64 {
        self.outer_mass * self.inner_mass / (self.outer_mass + self.inner_mass)
    }
}

impl Stops {
    /// Checks `gap` finite and `> 0`, `restitution` in `[0, 1]`.
    ///
    /// # Errors
    /// [`UnitError::OutOfRange`] naming `stops.gap` or `stops.restitution`, the gap first.
    pub fn validate(&self) -> Result<(), UnitError> {
        check("stops.gap", self.gap, self.gap > 0.0, "> 0")?;
        check(
            "stops.restitution",
            self.restitution,
            (0.0..=1.0).contains(&self.restitution),
            "in [0, 1]",
        )
    }

    /// Velocity map of an impact, `v⁺ = G v⁻` on `v = (u̇_o, u̇_i)`:
    /// `G = 1/(m_i+m_o) [[m_o − m_i e, m_i(1+e)], [m_o(1+e), m_i − m_o e]]`.
    /// It conserves momentum and maps the relative velocity `ṙ⁺ = −e ṙ⁻`.
    pub fn impact_map(&self, unit: &Unit) -> Matrix2<f64> {
        let (mo, mi, e) = (unit.outer_mass, unit.inner_mass, self.restitution);
        Matrix2::new(mo - mi * e, mi * (1.0 + e), mo * (1.0 + e), mi - mo * e) / (mo + mi)
    }
}
