//! ψ e − η, the linear part of the tangential-velocity rows; z = [ψ; η]. Generic AD (its
//! Jacobian is constant).

use super::{Context, RowBlock};
use crate::autodiff::Scalar;
use crate::contact;
use crate::discrete::Mechanics;

/// ψ e − η.
#[derive(Debug, Clone, PartialEq)]
pub struct TangentialSlack;

impl RowBlock for TangentialSlack {
    const NAME: &'static str = "TangentialSlack";
    fn value<D: Scalar, M: Mechanics>(&self, _: &M, _: &Context, z: &[D], out: &mut [D]) {
        contact::tangential_slack(z, out)
    }
}
