//! Peers of the two solvers, kept for tests and for what accuracy costs: a conventional
//! Dormand–Prince 5(4) integrator with event location ([`baseline`]), Siconos's two schemes
//! on the same unit as measured by `crates/compare/peers/siconos_unit.py` ([`siconos`]), and
//! the accuracy-versus-cost study of the integrators against the analytic orbit
//! ([`work_precision`]).

pub mod baseline;
pub mod siconos;
pub mod work_precision;
