//! The problem: the unit and its stops ([`mod@unit`]), impact signatures of one pair
//! ([`signature`]), general linear models with contact pairs ([`model`]), impact sequences of
//! several pairs ([`sequence`]) and chains of cells ([`chain`]).

pub mod chain;
pub mod model;
pub mod sequence;
pub mod signature;
pub mod unit;
