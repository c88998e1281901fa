//! Orbits in closed form, beside the general path of [`crate::cycle`] (and tested equal to
//! it): the two-impact orbit of the Nigm–Shabana method with its verdicts ([`orbit`]), the
//! symmetric two-impact orbits by the half-period symmetry ([`symmetric`]) and the two-impact
//! family of any impact spacing `β` ([`family`]).

pub mod family;
pub mod orbit;
pub mod symmetric;
