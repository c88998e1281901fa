//! The problem: the unit and its stops ([`mod@unit`]), impact signatures of one pair
//! ([`signature`]), general linear models with contact pairs ([`model`]) and their periodic
//! forcing ([`forcing`]), impact sequences of
//! several pairs ([`sequence`]), chains of cells ([`chain`]) and the free bodies of a model
//! ([`rigid`]).

pub mod chain;
pub mod forcing;
pub mod model;
pub mod rigid;
pub mod sequence;
pub mod signature;
pub mod unit;
