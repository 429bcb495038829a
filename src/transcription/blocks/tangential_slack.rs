//! ψ e − η, the linear part of the tangential-velocity rows; z = [ψ; η]. Generic AD (its
//! Jacobian is constant).

use super::place::each;
use super::tangential_rate;
use super::{Block, Context, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::contact;
use crate::discrete::Mechanics;

/// ψ e − η.
#[derive(Debug, Clone, PartialEq)]
pub struct TangentialSlack;

impl RowBlock for TangentialSlack {
    const NAME: &'static str = "TangentialSlack";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // ψ + η on the same tangential rows (linear).
        let Stage::ContactRows { j, contact } = stage else {
            return;
        };
        let l = p.layout;
        let mut vars = vec![l.psi(j, contact)];
        vars.extend(l.eta(j, contact));
        p.vector.push(Block::new(
            VectorKind::TangentialSlack(TangentialSlack),
            vars,
            0,
            each(tangential_rate::rows(l, j, contact)),
        ));
    }
    fn value<D: Scalar, M: Mechanics>(&self, _: &M, _: &Context, z: &[D], out: &mut [D]) {
        contact::tangential_slack(z, out)
    }
}
