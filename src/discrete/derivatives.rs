//! The derivatives of a robot's mechanics that the NLP and the forward step need, each with a
//! default by forward AD through [`Mechanics`] and overridable by a faster path: the gradient,
//! Hessian and contracted third derivative of Ld over one segment z = [qa; qb; h] (the URDF
//! model overrides them with its adjoint, [`super::midpoint_derivatives`]), and the jet of a
//! contact point (the URDF model overrides it with [`crate::model::point_jet`]).

use nalgebra::DMatrix;

use super::Mechanics;
use crate::autodiff::Scalar;
use crate::autodiff::{
    ScalarFunction, SymmetricGroups, ThirdOrder, VectorFunction, gradient, gradient_hessian,
    gradient_hessian_third, jacobian, weighted_hessian,
};
use crate::model::{LoopJet, PointJet};

/// Derivatives of [`Mechanics`]: every method has a forward-AD default; an implementation
/// overrides the ones it has a faster path for (same numbers up to rounding).
pub trait MechanicsDerivatives: Mechanics + Sized {
    /// World position of contact point `contact` at q and its derivatives in q up to `order`
    /// (1 to 3). The default differentiates [`Mechanics::contact_position`] by forward AD over
    /// all n coordinates ([`contact_jet_by_autodiff`]).
    fn contact_jet(&self, contact: usize, q: &[f64], order: usize) -> PointJet {
        contact_jet_by_autodiff(self, contact, q, order)
    }
    /// [`MechanicsDerivatives::contact_jet`] into `jet`, whose storage an implementation may
    /// reuse (the same numbers); the default replaces it.
    fn contact_jet_into(&self, contact: usize, q: &[f64], order: usize, jet: &mut PointJet) {
        *jet = self.contact_jet(contact, q, order);
    }
    /// Gradient of Ld at z = [qa; qb; h] (length 2n + 1: D1Ld, D2Ld, ∂Ld/∂h). The DEL row of
    /// knot k adds D2Ld of segment k−1 and D1Ld of segment k.
    fn segment_gradient(&self, z: &[f64]) -> Vec<f64> {
        gradient(&SegmentLagrangian { mech: self }, z).1
    }
    /// Gradient and Hessian of Ld at z = [qa; qb; h] (the DEL rows' Jacobian blocks).
    fn segment_gradient_hessian(&self, z: &[f64]) -> (Vec<f64>, DMatrix<f64>) {
        let (_, gradient, hessian) = gradient_hessian(&SegmentLagrangian { mech: self }, z);
        (gradient, hessian)
    }
    /// Value, gradient, Hessian and third derivative of Ld contracted with `dir` at
    /// z = [qa; qb; h] (the DEL rows' share of the Lagrangian Hessian). With `columns`, only
    /// entries between marked inputs need be exact (the others belong to fixed variables);
    /// the default computes them all.
    fn segment_third_order(&self, z: &[f64], dir: &[f64], columns: Option<&[bool]>) -> ThirdOrder {
        let _ = columns;
        gradient_hessian_third(&SegmentLagrangian { mech: self }, z, dir)
    }
    /// [`MechanicsDerivatives::segment_gradient_hessian`] with the input columns seeded
    /// together by `groups` (of the dependency pattern of the Hessian of Ld); the default
    /// ignores them.
    fn segment_gradient_hessian_grouped(
        &self,
        z: &[f64],
        groups: &SymmetricGroups,
    ) -> (Vec<f64>, DMatrix<f64>) {
        let _ = groups;
        self.segment_gradient_hessian(z)
    }
    /// [`MechanicsDerivatives::segment_third_order`] with the input columns seeded together
    /// by `groups`; entries with an input outside every group (a fixed variable) need not be
    /// exact. The default ignores the groups.
    fn segment_third_order_grouped(
        &self,
        z: &[f64],
        dir: &[f64],
        groups: &SymmetricGroups,
    ) -> ThirdOrder {
        let _ = groups;
        self.segment_third_order(z, dir, None)
    }
    /// Per coordinate, whether Ld's Lagrangian depends on it at most linearly (a base
    /// translation: [`crate::model::Model::translation_coordinates`]), so that a segment's
    /// qa column is minus its qb column ([`crate::discrete::midpoint_segment_groups`]). The
    /// default claims none.
    fn translation_coordinates(&self) -> Vec<bool> {
        vec![false; self.nq()]
    }
    /// The loop-closure residual [`Mechanics::loop_residual`] at q and its derivatives up to
    /// `order` (1 to 3), the third contracted with `along` (length n, read at order 3), as
    /// groups of rows over the coordinates each depends on. The default is one group of all
    /// rows over all n coordinates by forward AD ([`loop_jets_by_autodiff`]).
    fn loop_jets(&self, q: &[f64], order: usize, along: &[f64]) -> Vec<LoopJet> {
        loop_jets_by_autodiff(self, q, order, along)
    }
    /// The Jacobian (n × (2n + m + 1)) of the half discrete force ½Fd at z = [qa; qb; u; h]
    /// ([`crate::discrete::half_force`]) in closed form; `None` (the default): the NLP
    /// differentiates [`Mechanics::discrete_force`] by forward AD.
    fn half_force_jacobian(&self, z: &[f64]) -> Option<DMatrix<f64>> {
        let _ = z;
        None
    }
    /// Σ_r w_r ∇²(½Fd)_r at z = [qa; qb; u; h] in closed form ((2n + m + 1)², w of length
    /// n); `None` (the default): by forward AD.
    fn half_force_hessian(&self, z: &[f64], w: &[f64]) -> Option<DMatrix<f64>> {
        let _ = (z, w);
        None
    }
}

/// [`MechanicsDerivatives::loop_jets`] by forward AD through [`Mechanics::loop_residual`]:
/// one group of every row over all n coordinates (one Hessian and one contracted third
/// derivative pass per row: the reference the analytic jets are tested against).
pub fn loop_jets_by_autodiff<M: Mechanics>(
    mech: &M,
    q: &[f64],
    order: usize,
    along: &[f64],
) -> Vec<LoopJet> {
    let (n, rows) = (q.len(), mech.num_loop_constraints());
    if rows == 0 {
        return Vec::new();
    }
    let (value, jac) = jacobian(&LoopResidualFn { mech, row: 0 }, q);
    let mut jet = LoopJet {
        coords: (0..n).collect(),
        first_row: 0,
        value,
        first: (0..rows)
            .flat_map(|r| (0..n).map(move |a| (r, a)))
            .map(|(r, a)| jac[(r, a)])
            .collect(),
        second: Vec::new(),
        third_along: Vec::new(),
    };
    if order >= 2 {
        for r in 0..rows {
            let mut w = vec![0.0; rows];
            w[r] = 1.0;
            let h = weighted_hessian(&LoopResidualFn { mech, row: r }, q, &w);
            jet.second.extend(h.transpose().iter());
        }
    }
    if order >= 3 {
        for r in 0..rows {
            let t = gradient_hessian_third(&LoopResidualFn { mech, row: r }, q, along).contracted;
            jet.third_along.extend(t.transpose().iter());
        }
    }
    vec![jet]
}

/// The loop-closure residual as an AD-able function of q (all rows, or the one `row`).
struct LoopResidualFn<'a, M> {
    mech: &'a M,
    row: usize,
}

impl<M: Mechanics> VectorFunction for LoopResidualFn<'_, M> {
    fn dim_in(&self) -> usize {
        self.mech.nq()
    }
    fn dim_out(&self) -> usize {
        self.mech.num_loop_constraints()
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        self.mech.loop_residual(z, out);
    }
}

impl<M: Mechanics> ScalarFunction for LoopResidualFn<'_, M> {
    fn dim(&self) -> usize {
        self.mech.nq()
    }
    fn eval<D: Scalar>(&self, z: &[D]) -> D {
        let mut out = vec![D::from(0.0); self.mech.num_loop_constraints()];
        self.mech.loop_residual(z, &mut out);
        out[self.row]
    }
}

/// One segment's Ld(qa, qb, h) of any [`Mechanics`] as a [`ScalarFunction`] of
/// z = [qa; qb; h] (dim 2n + 1).
#[derive(Debug, Clone, Copy)]
pub struct SegmentLagrangian<'a, M> {
    /// The robot.
    pub mech: &'a M,
}

impl<M: Mechanics> ScalarFunction for SegmentLagrangian<'_, M> {
    fn dim(&self) -> usize {
        2 * self.mech.nq() + 1
    }
    fn eval<D: Scalar>(&self, z: &[D]) -> D {
        let n = self.mech.nq();
        self.mech
            .discrete_lagrangian(&z[..n], &z[n..2 * n], z[2 * n])
    }
}

/// The contact point's position as an AD-able function of q (all three components, or the
/// one `component`).
struct ContactPositionFn<'a, M> {
    mech: &'a M,
    contact: usize,
    component: usize,
}

impl<M: Mechanics> VectorFunction for ContactPositionFn<'_, M> {
    fn dim_in(&self) -> usize {
        self.mech.nq()
    }
    fn dim_out(&self) -> usize {
        3
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        out.copy_from_slice(&self.mech.contact_position(self.contact, z));
    }
}

impl<M: Mechanics> ScalarFunction for ContactPositionFn<'_, M> {
    fn dim(&self) -> usize {
        self.mech.nq()
    }
    fn eval<D: Scalar>(&self, z: &[D]) -> D {
        self.mech.contact_position(self.contact, z)[self.component]
    }
}

/// [`MechanicsDerivatives::contact_jet`] by forward AD through [`Mechanics::contact_position`], over all
/// n coordinates (the third order costs 3n passes: meant for small closed-form mechanics and
/// as the reference the analytic jets are tested against).
pub fn contact_jet_by_autodiff<M: Mechanics>(
    mech: &M,
    contact: usize,
    q: &[f64],
    order: usize,
) -> PointJet {
    let n = q.len();
    let f = |component| ContactPositionFn {
        mech,
        contact,
        component,
    };
    let (position, jac) = jacobian(&f(0), q);
    let mut jet = PointJet {
        coords: (0..n).collect(),
        position: [position[0], position[1], position[2]],
        first: (0..n)
            .map(|a| [jac[(0, a)], jac[(1, a)], jac[(2, a)]])
            .collect(),
        second: Vec::new(),
        third: Vec::new(),
    };
    if order >= 2 {
        jet.second = vec![[0.0; 3]; n * n];
        for m in 0..3 {
            let mut w = [0.0; 3];
            w[m] = 1.0;
            let h = weighted_hessian(&f(0), q, &w);
            for (entry, value) in jet.second.iter_mut().zip(h.iter()) {
                entry[m] = *value;
            }
        }
    }
    if order >= 3 {
        jet.third = vec![[0.0; 3]; n * n * n];
        for e in 0..n {
            let mut dir = vec![0.0; n];
            dir[e] = 1.0;
            for m in 0..3 {
                let t = gradient_hessian_third(&f(m), q, &dir).contracted;
                for a in 0..n {
                    for b in 0..n {
                        jet.third[(a * n + b) * n + e][m] = t[(a, b)];
                    }
                }
            }
        }
    }
    jet
}
