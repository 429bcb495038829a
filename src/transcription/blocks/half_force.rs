//! ½Fd(qa, qb, u, h), the discrete force's half in each of the two DEL rows of an interval
//! (midpoint); z = [qa; qb; u; h]. Generic AD.

use super::{Context, RowBlock};
use crate::autodiff::Scalar;
use crate::discrete::{Mechanics, half_force};

/// ½Fd(qa, qb, u, h).
#[derive(Debug, Clone, PartialEq)]
pub struct HalfForce;

impl RowBlock for HalfForce {
    const NAME: &'static str = "HalfForce";
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, _: &Context, z: &[D], out: &mut [D]) {
        half_force(mech, z, out)
    }
}
