//! Reference problems with known answers, shared by the tests of this crate and its users.

use crate::unit::{Damping, Stops, Unit};

/// The paper's §2.2 unit: `m_i = 1, m_o = 2, k_i = 3, k_o = 6, u_g = 1`, undamped.
/// `ω² = 1.5, 6`; anti-resonance `√(k_i/m_i)`.
pub fn paper_unit() -> Unit {
    Unit {
        outer_mass: 2.0,
        inner_mass: 1.0,
        outer_stiffness: 6.0,
        inner_stiffness: 3.0,
        base_amplitude: 1.0,
        damping: None,
    }
}

/// The paper's unit with light dashpots `c_o = 0.1`, `c_i = 0.05`.
pub fn damped_paper_unit() -> Unit {
    Unit {
        damping: Some(Damping {
            outer: 0.1,
            inner: 0.05,
        }),
        ..paper_unit()
    }
}

/// The paper's stops under the reading "0.5 m to each side": `Δ = 0.5`, and restitution
/// `e = 0.8` (the paper does not state `e`).
pub fn paper_stops() -> Stops {
    Stops {
        gap: 0.5,
        restitution: 0.8,
    }
}
