//! A Galerkin interval's action A(q_j, q_j^1 … q_j^{s−1}, q_{j+1}, h_j)
//! (`crate::discrete::GalerkinRule`), whose gradient is ∂A/∂q^0 into interval j's dynamics
//! rows, ∂A/∂q^ν into its interior-stationarity rows (owned by [`GalerkinForce`]) and ∂A/∂q^s
//! into the next interval's; z = [q_j; interior points; q_{j+1}; h_j]. The degree-s analogue
//! of [`super::Segment`], with derivatives chained from the mechanics' segment derivatives at
//! each quadrature point.

use nalgebra::DMatrix;

use super::place::range_vec;
use super::{
    Block, Context, Eval, GalerkinForce, GradientBlock, Placement, RowBlock, ScalarKind, Stage,
};
use crate::autodiff::{Scalar, ThirdOrder};
use crate::discrete::{
    Mechanics, MechanicsDerivatives, action_gradient, action_gradient_hessian, action_third_order,
};

/// A(q_j, interior, q_{j+1}, h_j).
#[derive(Debug, Clone, PartialEq)]
pub struct GalerkinSegment;

impl GradientBlock for GalerkinSegment {
    const NAME: &'static str = "GalerkinSegment";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        let Stage::Dynamics(j) = stage else { return };
        if p.ctx.galerkin.is_none() {
            return;
        }
        let l = p.layout;
        let mut vars = range_vec(l.q(j));
        vars.extend(l.interior_points(j));
        vars.extend(l.q(j + 1));
        vars.push(l.h(j));
        let mut targets = p.dynamics_targets(j);
        targets.extend(
            l.rows_of(<GalerkinForce as RowBlock>::NAME, j)
                .map(|row| vec![row]),
        );
        targets.extend((0..l.n).map(|c| p.after_rows(j, c)));
        targets.push(vec![]);
        let len = vars.len();
        p.gradient.push(Block::new(
            ScalarKind::GalerkinSegment(GalerkinSegment),
            vars,
            len,
            targets,
        ));
    }
    const ALWAYS_CLOSED_FORM: bool = true;
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D]) -> D {
        // Placed only with a Galerkin rule.
        let Some(rule) = &ctx.galerkin else {
            return D::zero();
        };
        let (control, h) = z.split_at(z.len() - 1);
        rule.action(mech, control, h[0])
    }
    fn gradient<M: MechanicsDerivatives>(&self, at: &Eval<M>, z: &[f64]) -> Option<Vec<f64>> {
        let rule = at.ctx.galerkin.as_ref()?;
        Some(action_gradient(at.mech, rule, z))
    }
    fn hessian<M: MechanicsDerivatives>(&self, at: &Eval<M>, z: &[f64]) -> Option<DMatrix<f64>> {
        let rule = at.ctx.galerkin.as_ref()?;
        Some(action_gradient_hessian(at.mech, rule, z).1)
    }
    fn third<M: MechanicsDerivatives>(
        &self,
        at: &Eval<M>,
        z: &[f64],
        dir: &[f64],
    ) -> Option<ThirdOrder> {
        let rule = at.ctx.galerkin.as_ref()?;
        Some(action_third_order(at.mech, rule, z, dir))
    }
}
