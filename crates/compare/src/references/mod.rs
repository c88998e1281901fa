//! Answers computed here in closed form, apart from both solvers, that the solvers are checked
//! against: the impact oscillator's period-1 orbit ([`impact_oscillator`]) and the impact
//! damper's symmetric two-impact motion ([`impact_damper`]).

pub mod impact_damper;
pub mod impact_oscillator;
