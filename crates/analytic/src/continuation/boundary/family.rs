//! The models of a boundary curve as functions of the parameter: the unit with its stops
//! ([`UnitFamily`]) or any [`LinearModel`], such as a chain ([`ModelFamily`]), each giving
//! the branch model of the curve's label at a parameter value.

use crate::continuation::model::ModelBranch;
use crate::continuation::system::{BranchModel, Label};
use crate::continuation::unit::UnitBranch;
use crate::model::LinearModel;
use crate::sequence::ImpactSequence;
use crate::signature::Signature;
use crate::unit::{Stops, Unit};

/// The models of one curve in the parameter.
pub(crate) trait Family {
    /// The label of the curve's orbits.
    type Label: Label;
    /// What is built at one parameter value (the unit and stops, or the model).
    type Owned;
    /// The branch model borrowing what was built.
    type Model<'m>: BranchModel<Label = Self::Label>;
    /// What is built at `p`, or why `p` gives none.
    fn build(&self, p: f64) -> Result<Self::Owned, String>;
    /// The branch model of `label` on `owned`; `None` when the label does not fit it.
    fn model<'m>(owned: &'m Self::Owned, label: &Self::Label) -> Option<Self::Model<'m>>;
}

/// The unit and its stops as a function of the parameter.
pub(crate) struct UnitFamily<'a, F> {
    /// `p ↦ (unit, stops)`.
    pub(crate) unit_at: &'a F,
}

impl<F, E> Family for UnitFamily<'_, F>
where
    F: Fn(f64) -> Result<(Unit, Stops), E>,
    E: std::fmt::Display,
{
    type Label = Signature;
    type Owned = (Unit, Stops);
    type Model<'m> = UnitBranch<'m>;

    fn build(&self, p: f64) -> Result<(Unit, Stops), String> {
        (self.unit_at)(p).map_err(|e| e.to_string())
    }

    fn model<'m>(owned: &'m (Unit, Stops), label: &Signature) -> Option<UnitBranch<'m>> {
        // The difference steps of the curve's corrector share most flights.
        Some(UnitBranch::new(&owned.0, &owned.1, label.clone()).with_remembered_flights())
    }
}

/// A [`LinearModel`] (a chain) as a function of the parameter.
pub(crate) struct ModelFamily<'a, F> {
    /// `p ↦ model`.
    pub(crate) model_at: &'a F,
}

impl<F, E> Family for ModelFamily<'_, F>
where
    F: Fn(f64) -> Result<LinearModel, E>,
    E: std::fmt::Display,
{
    type Label = ImpactSequence;
    type Owned = LinearModel;
    type Model<'m> = ModelBranch<'m>;

    fn build(&self, p: f64) -> Result<LinearModel, String> {
        (self.model_at)(p).map_err(|e| e.to_string())
    }

    fn model<'m>(owned: &'m LinearModel, label: &ImpactSequence) -> Option<ModelBranch<'m>> {
        ModelBranch::new(owned, label.clone()).ok()
    }
}
