//! Constraint and cost blocks: small dense functions of a few NLP variables.
//!
//! Each block reads its local vector z = x[vars] and is either a *vector* block (outputs
//! that add into constraint rows; derivatives by `jacobian` and `weighted_hessian`), a
//! *gradient* block (a scalar whose gradient components add into rows, like the DEL
//! equations, which are sums of gradients of Ld; derivatives by the third-order driver),
//! or a *cost* block (a scalar added to the objective; each term's value is in
//! `transcription/costs/`). The dynamics blocks evaluate the DEL pieces of `discrete::del`,
//! the contact blocks the contact rows of `crate::contact`.

mod loops;

pub(crate) use loops::{
    loop_closure_hessian, loop_closure_jacobian, loop_work_gradient, loop_work_hessian,
    loop_work_third,
};

use std::sync::Arc;

use crate::autodiff::Scalar;
use crate::autodiff::{ScalarFunction, SymmetricGroups, VectorFunction};
use crate::contact::{self, ContactModel};
use crate::discrete::{
    Mechanics, SegmentLagrangian, euler_knot, half_force, initial_momentum, loop_work,
};
use crate::problem::costs::{CostSizes, cost_value};
use crate::problem::{Constraint, CostTerm, Integrator, ProblemSpec};

/// Problem constants the block functions need besides the mechanics.
#[derive(Debug, Clone)]
pub struct Context {
    /// Coordinates n.
    pub n: usize,
    /// Inputs m.
    pub m: usize,
    /// Loop constraints nl.
    pub nl: usize,
    /// The contact model: terrain, friction basis and coefficients.
    pub contact: ContactModel,
    /// Discrete mechanics used by the dynamics rows.
    pub integrator: Integrator,
    /// The problem's cost terms (blocks refer to them by index).
    pub costs: Vec<CostTerm>,
    /// The problem file's constraints (blocks refer to them by index).
    pub constraints: Vec<Constraint>,
}

impl Context {
    /// The constants of `spec` for the robot `mech` (whose contacts are `spec.contacts`, in
    /// order; the contact model by [`ProblemSpec::contact_model`]).
    pub fn new<M: Mechanics>(mech: &M, spec: &ProblemSpec) -> Context {
        Context {
            n: mech.nq(),
            m: mech.nu(),
            nl: mech.num_loop_constraints(),
            contact: spec.contact_model(mech),
            integrator: spec.integrator,
            costs: spec.costs.clone(),
            constraints: spec.constraints.clone(),
        }
    }

    /// Friction directions per contact.
    pub fn nd(&self) -> usize {
        self.contact.nd()
    }
}

/// What a vector block computes; z layouts in the comments.
#[derive(Debug, Clone, PartialEq)]
pub enum VectorKind {
    /// ½Fd(qa, qb, u, h) (midpoint rows); z = [qa; qb; u; h].
    HalfForce,
    /// M(q_0)v_0 (midpoint first step); z = [q_0; v_0].
    InitialMomentum,
    /// Semi-implicit Euler residual at a knot (eq. 1); z = [v_0; q_0; q_1; h_0; u_0] when
    /// `first_step`, else [q_{k−1}; q_k; q_{k+1}; h_{k−1}; h_k; u_k].
    EulerKnot { first_step: bool },
    /// ±P_i(qb)(qb − qa)/h (tangential-velocity rows, nonlinear part); z = [qa; qb; h].
    TangentialRate { contact: usize },
    /// ψ e − η (tangential-velocity rows, linear part); z = [ψ; η].
    TangentialSlack,
    /// The spin part of a rolling sphere's friction impulse in the DEL rows (its friction
    /// directions are no gradient, so it is not in [`ScalarKind::ContactWork`]); z = [q; c_i;
    /// β_i], out length n.
    SpinFriction { contact: usize },
    /// −c_i φ_i(q) (the c·φ complementarity row's product); z = [q; c_i].
    ContactGap { contact: usize },
    /// φ_i(q); z = [q].
    Distance { contact: usize },
    /// μ c − eᵀβ; z = [c; β].
    FrictionCone { contact: usize },
    /// The relaxed products ηᵀβ and ψ(μc − eᵀβ) of the listed contacts with the slacks;
    /// z = [(c, β, ψ, η) per contact; slacks (0: added by another block, 1 shared, or 3)].
    Complementarity { contacts: Vec<usize>, slacks: usize },
    /// a(q); z = [q].
    LoopClosure,
    /// h_a − h_b; z = [h_a; h_b].
    EqualStep,
    /// The rows of the problem file's constraint `index` (`problem::constraints`); z as it
    /// declares.
    Constraint { index: usize },
}

/// What a gradient (or cost) block computes.
#[derive(Debug, Clone, PartialEq)]
pub enum ScalarKind {
    /// Midpoint Ld(qa, qb, h); z = [qa; qb; h].
    Segment,
    /// c_i φ_i(q) + β_iᵀ P_i t_i(q), whose q-gradient is contact i's J(q)ᵀλ (with
    /// [`VectorKind::SpinFriction`] for a rolling sphere); z = [q; c_i; β_i].
    ContactWork { contact: usize },
    /// γᵀa(q), whose q-gradient is A(q)ᵀγ; z = [q; γ].
    LoopWork,
    /// Cost term `term` of the problem on one interval (or the last knot); z per term.
    Cost { term: usize },
}

/// Placement of one block: its variables and where its local outputs go.
#[derive(Debug, Clone)]
pub struct Block<K> {
    /// What it computes.
    pub kind: K,
    /// Global variable index of each local input.
    pub vars: Vec<usize>,
    /// Leading inputs that enter nonlinearly (the Hessian block is over these).
    pub nonlinear: usize,
    /// Inputs from this index on never multiply each other (the function is linear in
    /// them jointly), so their mutual Hessian pairs are left out of the pattern.
    pub linear_from: usize,
    /// For each local output (vector) or gradient component (gradient block): rows it adds into.
    pub targets: Vec<Vec<usize>>,
    /// Jacobian slot for each (output, target row, input) in loop order.
    pub jacobian_slots: Vec<usize>,
    /// Hessian slot and multiplicity for each lower pair (a, b ≤ a) of nonlinear inputs.
    pub hessian_slots: Vec<(usize, f64)>,
    /// Nonlinear inputs with at least one pair in the Hessian pattern: generic AD
    /// differentiates over these only (e.g. u and h of ½Fd when B is constant).
    pub hessian_inputs: Vec<usize>,
    /// [`Block::hessian_inputs`] without the variables fixed by their bounds, whose Hessian
    /// entries Ipopt drops (its default `fixed_variable_treatment make_parameter`).
    pub hessian_free_inputs: Vec<usize>,
    /// For each input: whether its variable is free (not fixed by its bounds).
    pub free_input_mask: Vec<bool>,
    /// Column groups of the block's second derivative (a cost's Hessian over
    /// [`Block::hessian_inputs`]; a DEL segment's Hessian of Ld over all inputs) when its
    /// dependency structure lets columns share a pass; `None` when every group would hold one.
    pub second_derivative_groups: Option<Arc<SymmetricGroups>>,
    /// The same over [`Block::hessian_free_inputs`] (cost) or the free inputs (segment).
    pub free_second_derivative_groups: Option<Arc<SymmetricGroups>>,
}

impl<K> Block<K> {
    /// Whether the lower Hessian pair (a, b ≤ a) of local inputs is in the pattern.
    pub fn has_hessian_pair(&self, a: usize, b: usize) -> bool {
        a < self.nonlinear && b < self.linear_from
    }

    /// A block with empty slot maps (filled by the pattern pass).
    pub fn new(kind: K, vars: Vec<usize>, nonlinear: usize, targets: Vec<Vec<usize>>) -> Self {
        Block {
            kind,
            vars,
            nonlinear,
            linear_from: nonlinear,
            targets,
            jacobian_slots: Vec::new(),
            hessian_slots: Vec::new(),
            hessian_inputs: Vec::new(),
            hessian_free_inputs: Vec::new(),
            free_input_mask: Vec::new(),
            second_derivative_groups: None,
            free_second_derivative_groups: None,
        }
    }
}

/// A vector block bound to the mechanics, as an AD-able function.
pub struct VectorBlockFn<'a, M> {
    /// Robot mechanics.
    pub mech: &'a M,
    /// Problem constants.
    pub ctx: &'a Context,
    /// The block.
    pub kind: &'a VectorKind,
    /// Local inputs.
    pub dim_in: usize,
    /// Local outputs.
    pub dim_out: usize,
}

impl<M: Mechanics> VectorFunction for VectorBlockFn<'_, M> {
    fn dim_in(&self) -> usize {
        self.dim_in
    }
    fn dim_out(&self) -> usize {
        self.dim_out
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        let (mech, ctx) = (self.mech, self.ctx);
        let model = &ctx.contact;
        match self.kind {
            VectorKind::HalfForce => half_force(mech, z, out),
            VectorKind::InitialMomentum => initial_momentum(mech, z, out),
            VectorKind::EulerKnot { first_step } => euler_knot(mech, *first_step, z, out),
            VectorKind::TangentialRate { contact } => {
                contact::tangential_rate(mech, model, *contact, z, out)
            }
            VectorKind::TangentialSlack => contact::tangential_slack(z, out),
            VectorKind::SpinFriction { contact } => {
                contact::spin_friction(mech, model, *contact, z, out)
            }
            VectorKind::ContactGap { contact } => {
                out[0] = contact::contact_gap(mech, model, *contact, z)
            }
            VectorKind::Distance { contact } => {
                out[0] = contact::distance(mech, model, *contact, z)
            }
            VectorKind::FrictionCone { contact } => {
                out[0] = contact::friction_cone(model, *contact, z)
            }
            VectorKind::Complementarity { contacts, slacks } => {
                contact::complementarity(model, contacts, *slacks, z, out)
            }
            VectorKind::LoopClosure => mech.loop_residual(z, out),
            VectorKind::EqualStep => out[0] = z[0] - z[1],
            VectorKind::Constraint { index } => ctx.constraints[*index].value(mech, z, out),
        }
    }
}

/// A gradient or cost block bound to the mechanics, as an AD-able scalar function.
pub struct ScalarBlockFn<'a, M> {
    /// Robot mechanics.
    pub mech: &'a M,
    /// Problem constants.
    pub ctx: &'a Context,
    /// The block.
    pub kind: &'a ScalarKind,
    /// Local inputs.
    pub dim: usize,
}

impl<M: Mechanics> ScalarFunction for ScalarBlockFn<'_, M> {
    fn dim(&self) -> usize {
        self.dim
    }
    fn eval<D: Scalar>(&self, z: &[D]) -> D {
        let (mech, ctx) = (self.mech, self.ctx);
        match self.kind {
            ScalarKind::Segment => SegmentLagrangian { mech }.eval(z),
            ScalarKind::ContactWork { contact } => {
                contact::contact_work(mech, &ctx.contact, *contact, z)
            }
            ScalarKind::LoopWork => loop_work(mech, z),
            ScalarKind::Cost { term } => {
                let sizes = CostSizes { n: ctx.n, m: ctx.m };
                cost_value(&ctx.costs[*term], sizes, z)
            }
        }
    }
}
