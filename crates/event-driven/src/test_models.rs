//! Reference problems for tests and benchmarks: the paper's unit (`m_o = 2, m_i = 1, k_o = 6,
//! k_i = 3, u_g = 1`, `ω_n² = 1.5, 6`) in the variants the tests need.

use crate::model::Model;

/// The paper's unit at `omega`, with optional dashpots `(c_o, c_i)` and stops `(gap, e)`.
pub fn paper_unit(omega: f64, damping: Option<(f64, f64)>, stops: Option<(f64, f64)>) -> Model {
    Model::two_dof_unit(
        2.0,
        1.0,
        6.0,
        3.0,
        damping.map(|d| d.0),
        damping.map(|d| d.1),
        1.0,
        omega,
        stops,
    )
    .expect("the paper's unit is valid")
}

/// Light dashpots `c_o = 0.1`, `c_i = 0.05`.
pub const LIGHT_DAMPING: (f64, f64) = (0.1, 0.05);
