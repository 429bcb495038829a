//! M(q_0)v_0, the initial momentum in the first-step rows (midpoint); z = [q_0; v_0].
//! Generic AD.

use super::{Context, RowBlock};
use crate::autodiff::Scalar;
use crate::discrete::{Mechanics, initial_momentum};

/// M(q_0)v_0.
#[derive(Debug, Clone, PartialEq)]
pub struct InitialMomentum;

impl RowBlock for InitialMomentum {
    const NAME: &'static str = "InitialMomentum";
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, _: &Context, z: &[D], out: &mut [D]) {
        initial_momentum(mech, z, out)
    }
}
