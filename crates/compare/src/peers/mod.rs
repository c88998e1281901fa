//! Peers of the two solvers, kept for tests and for what accuracy costs: a conventional
//! Dormand–Prince 5(4) integrator with event location ([`baseline`]), and the
//! accuracy-versus-cost study of both integrators against the analytic orbit
//! ([`work_precision`]).

pub mod baseline;
pub mod work_precision;
