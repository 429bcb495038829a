//! Constraint and cost blocks: small dense functions of a few NLP variables, one kind per file.
//!
//! Each block reads its local vector z = x[vars] and is either a *vector* block (outputs
//! that add into constraint rows, [`RowBlock`]), a *gradient* block (a scalar whose gradient
//! components add into rows, like the DEL equations, which are sums of gradients of Ld,
//! [`GradientBlock`]), or a *cost* block (a scalar added to the objective, the gradient kind
//! [`cost::Cost`]; each term's value is in `crate::problem::costs`).
//!
//! A kind's file holds all of it: its value (generic over the scalar, so that the structure
//! is traced from its dependencies by `structure` and generic AD differentiates it), and its
//! closed-form derivatives where it has them (the trait methods left at their default `None`
//! fall back to generic forward AD). The dynamics kinds evaluate the DEL pieces of
//! `discrete::del`, the contact kinds the contact rows of `crate::contact`.
//!
//! A kind's file also places it: its `place` method pushes, at the [`Stage`]s of the NLP's
//! skeleton where the kind has blocks, each block's variables and the rows it adds into.
//!
//! A vector kind that owns rows in every interval declares them there too
//! ([`RowBlock::interval_rows`]: how many, equality or inequality, their names), and finds
//! them with `Layout::rows_of`.
//!
//! To add a kind: a file here with its type implementing [`RowBlock`] or [`GradientBlock`]
//! (value, derivatives where closed forms pay, placement, rows), and its line in the
//! `vector_kinds!` or `gradient_kinds!` list below. The list's order is the order in which
//! blocks placed at the same stage add into shared rows, and the order of the kinds' rows
//! in each interval.

mod complementarity;
pub(crate) mod complementarity_penalty;
mod constraint;
mod contact_work;
pub(crate) mod cost;
mod distance;
mod equal_step;
mod euler_knot;
mod frame_cost;
mod frame_row;
mod friction_cone;
mod galerkin_force;
mod galerkin_segment;
mod half_force;
mod initial_momentum;
mod interior_distance;
mod loop_closure;
mod loop_work;
mod loops;
mod place;
mod segment;
mod spin_friction;
mod tangential_rate;
mod tangential_slack;

pub(crate) use complementarity::Complementarity;
pub(crate) use complementarity_penalty::ComplementarityPenalty;
pub(crate) use constraint::Constraint;
pub(crate) use contact_work::ContactWork;
pub(crate) use cost::Cost;
pub(crate) use distance::Distance;
pub(crate) use equal_step::EqualStep;
pub(crate) use euler_knot::EulerKnot;
pub(crate) use frame_cost::FrameCost;
pub(crate) use frame_row::FrameRow;
pub(crate) use friction_cone::FrictionCone;
pub(crate) use galerkin_force::GalerkinForce;
pub(crate) use galerkin_segment::GalerkinSegment;
pub(crate) use half_force::HalfForce;
pub(crate) use initial_momentum::InitialMomentum;
pub(crate) use interior_distance::InteriorDistance;
pub(crate) use loop_closure::LoopClosure;
pub(crate) use loop_work::LoopWork;
pub(crate) use place::{PlacedBlocks, Placement, Stage, place_blocks};
pub(crate) use segment::Segment;
pub(crate) use spin_friction::SpinFriction;
pub(crate) use tangential_rate::TangentialRate;
pub(crate) use tangential_slack::TangentialSlack;

use loops::{
    loop_closure_hessian, loop_closure_jacobian, loop_work_gradient, loop_work_hessian,
    loop_work_third,
};

use std::ops::Range;
use std::sync::Arc;

use nalgebra::DMatrix;

use crate::autodiff::Scalar;
use crate::autodiff::{ScalarFunction, SymmetricGroups, ThirdOrder, VectorFunction};
use crate::contact::{ContactGeometry, ContactModel};
use crate::discrete::{GalerkinRule, Mechanics, MechanicsDerivatives};
use crate::problem::frames::FrameTerm;
use crate::problem::{
    Constraint as ProblemConstraint, CostTerm, Integrator, ProblemSpec, SlackMode,
};
use crate::transcription::layout::{Dims, IntervalRows};

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
    pub constraints: Vec<ProblemConstraint>,
    /// The problem's frame terms (blocks refer to them by index).
    pub frames: Vec<FrameTerm>,
    /// The Galerkin member of `integrator` when it has interior points.
    pub galerkin: Option<GalerkinRule>,
    /// Intervals per contact-mode block ([`ProblemSpec::mode_block`]).
    pub mode_block: usize,
    /// The slack weight α ([`ProblemSpec::slack_weight`], or raised by `[slack] target`):
    /// the weight of the products in penalty mode ([`ComplementarityPenalty`]).
    pub slack_weight: f64,
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
            frames: spec.frames.clone(),
            galerkin: spec.integrator.galerkin_rule(),
            mode_block: spec.mode_block,
            slack_weight: spec.slack_weight,
        }
    }

    /// The intervals of interval j's contact-mode block among `intervals`: the consecutive
    /// runs of [`Context::mode_block`] from interval 0, the last one possibly shorter.
    pub fn mode_block_of(&self, j: usize, intervals: usize) -> Range<usize> {
        let m = self.mode_block.max(1);
        let start = j / m * m;
        start..(start + m).min(intervals)
    }

    /// Contacts nc.
    pub fn nc(&self) -> usize {
        self.contact.friction.len()
    }

    /// Friction directions per contact.
    pub fn nd(&self) -> usize {
        self.contact.nd()
    }
}

/// Where a block's chain-rule derivatives read a contact's geometry ([`ContactGeometry`]:
/// K(q) = [φ, t] and its derivatives), so that the blocks at one configuration share it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GeometryUse {
    /// The contact.
    pub contact: usize,
    /// The configuration's inputs in z.
    pub q: Range<usize>,
    /// The derivative order of the geometry the block's first derivatives (its Jacobian
    /// rows) need; its second derivatives (the Hessian) need one more.
    pub order: usize,
}

/// One kind of vector block: the rows it adds into the constraints, and their derivatives.
pub trait RowBlock {
    /// Its name in `Transcription::derivative_time_by_kind`.
    const NAME: &'static str;
    /// Pushes its blocks of `stage` onto `p` (nothing at the stages where it has none).
    fn place(p: &mut Placement<'_>, stage: Stage);
    /// The rows it owns in every interval, after the dynamics rows (`None`: it adds into
    /// rows other kinds own).
    fn interval_rows(_dims: &Dims, _slack_mode: SlackMode) -> Option<IntervalRows> {
        None
    }
    /// The name of this block (its kind's [`RowBlock::NAME`] unless the kind has variants).
    fn name(&self) -> &'static str {
        Self::NAME
    }
    /// Its outputs at z (one per target of the block).
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D], out: &mut [D]);
    /// Where its chain-rule derivatives read a contact's geometry (`None`: they read none).
    fn geometry<M: Mechanics>(&self, _mech: &M, _n: usize) -> Option<GeometryUse> {
        None
    }
    /// Its Jacobian from the geometry of [`RowBlock::geometry`].
    fn jacobian_in(&self, _geometry: &ContactGeometry, _z: &[f64]) -> Option<DMatrix<f64>> {
        None
    }
    /// Σ_r w_r ∇²f_r from the geometry of [`RowBlock::geometry`].
    fn hessian_in(
        &self,
        _geometry: &ContactGeometry,
        _z: &[f64],
        _w: &[f64],
    ) -> Option<DMatrix<f64>> {
        None
    }
    /// Its Jacobian in closed form (`None`: generic forward AD).
    fn jacobian<M: MechanicsDerivatives>(
        &self,
        _mech: &M,
        _ctx: &Context,
        _z: &[f64],
    ) -> Option<DMatrix<f64>> {
        None
    }
    /// Σ_r w_r ∇²f_r in closed form (`None`: generic forward AD over the block's Hessian
    /// inputs).
    fn hessian<M: MechanicsDerivatives>(
        &self,
        _mech: &M,
        _ctx: &Context,
        _z: &[f64],
        _w: &[f64],
    ) -> Option<DMatrix<f64>> {
        None
    }
}

/// What a gradient block's closed-form derivatives see besides z.
pub struct Eval<'a, M> {
    /// Robot mechanics.
    pub mech: &'a M,
    /// Problem constants.
    pub ctx: &'a Context,
    /// The block.
    pub block: &'a Block<ScalarKind>,
    /// Whether the Hessian entries of fixed variables are left out
    /// (`Transcription::set_skip_fixed_variables`).
    pub skip_fixed: bool,
}

/// One kind of gradient block: a scalar whose gradient components add into rows (or, for a
/// cost, into the objective), and its derivatives.
pub trait GradientBlock {
    /// Its name in `Transcription::derivative_time_by_kind`.
    const NAME: &'static str;
    /// Pushes its blocks of `stage` onto `p` (nothing at the stages where it has none).
    fn place(p: &mut Placement<'_>, stage: Stage);
    /// Whether its closed forms are used also when `set_contact_chain_rule(false)` asks for
    /// generic AD (the mechanics' own derivatives, not a chain rule that switch compares).
    const ALWAYS_CLOSED_FORM: bool = false;
    /// Whether its second derivative's columns are grouped as a midpoint segment's
    /// ([`crate::discrete::midpoint_segment_groups`]).
    const SEGMENT_GROUPS: bool = false;
    /// Its value at z.
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D]) -> D;
    /// Where its chain-rule derivatives read a contact's geometry (`None`: they read none).
    fn geometry<M: Mechanics>(&self, _mech: &M, _n: usize) -> Option<GeometryUse> {
        None
    }
    /// Its Hessian (the Jacobian of its rows) from the geometry of
    /// [`GradientBlock::geometry`].
    fn hessian_in(&self, _geometry: &ContactGeometry, _z: &[f64]) -> Option<DMatrix<f64>> {
        None
    }
    /// Its third derivative contracted with `dir` from the geometry of
    /// [`GradientBlock::geometry`] (`None`: not for this direction).
    fn contracted_third_in(
        &self,
        _geometry: &ContactGeometry,
        _z: &[f64],
        _dir: &[f64],
    ) -> Option<DMatrix<f64>> {
        None
    }
    /// Its gradient (the rows' values) in closed form (`None`: generic forward AD).
    fn gradient<M: MechanicsDerivatives>(&self, _at: &Eval<M>, _z: &[f64]) -> Option<Vec<f64>> {
        None
    }
    /// Its Hessian in closed form (`None`: generic forward AD).
    fn hessian<M: MechanicsDerivatives>(&self, _at: &Eval<M>, _z: &[f64]) -> Option<DMatrix<f64>> {
        None
    }
    /// Its Hessian and third derivative contracted with `dir` in closed form (`None`:
    /// generic forward AD; only the Hessian and the contraction need be filled).
    fn third<M: MechanicsDerivatives>(
        &self,
        _at: &Eval<M>,
        _z: &[f64],
        _dir: &[f64],
    ) -> Option<ThirdOrder> {
        None
    }
}

/// The list of vector kinds: `Variant in module`; `module::Variant` implements [`RowBlock`].
/// Generates [`VectorKind`] and its dispatch.
macro_rules! vector_kinds {
    ($($variant:ident in $module:ident),* $(,)?) => {
        /// What a vector block computes (one kind per file; z layouts there).
        #[derive(Debug, Clone, PartialEq)]
        pub enum VectorKind {
            $(
                #[allow(missing_docs)]
                $variant($variant),
            )*
        }

        $(impl From<$variant> for VectorKind {
            fn from(kind: $variant) -> Self {
                VectorKind::$variant(kind)
            }
        })*

        impl VectorKind {
            /// Every vector kind's blocks of `stage`, in the list's order.
            pub fn place(p: &mut Placement<'_>, stage: Stage) {
                $(<$variant as RowBlock>::place(p, stage);)*
            }
            /// The rows the kinds own in every interval, in the list's order (their row
            /// order in the layout).
            pub fn interval_rows(dims: &Dims, slack_mode: SlackMode) -> Vec<IntervalRows> {
                let mut rows = Vec::new();
                $(rows.extend(<$variant as RowBlock>::interval_rows(dims, slack_mode));)*
                rows
            }
            /// See [`RowBlock::name`].
            pub fn name(&self) -> &'static str {
                match self {
                    $(VectorKind::$variant(k) => k.name(),)*
                }
            }
            /// See [`RowBlock::value`].
            pub fn value<D: Scalar, M: Mechanics>(
                &self,
                mech: &M,
                ctx: &Context,
                z: &[D],
                out: &mut [D],
            ) {
                match self {
                    $(VectorKind::$variant(k) => k.value(mech, ctx, z, out),)*
                }
            }
            /// See [`RowBlock::geometry`].
            pub fn geometry<M: Mechanics>(&self, mech: &M, n: usize) -> Option<GeometryUse> {
                match self {
                    $(VectorKind::$variant(k) => k.geometry(mech, n),)*
                }
            }
            /// See [`RowBlock::jacobian_in`].
            pub fn jacobian_in(&self, g: &ContactGeometry, z: &[f64]) -> Option<DMatrix<f64>> {
                match self {
                    $(VectorKind::$variant(k) => k.jacobian_in(g, z),)*
                }
            }
            /// See [`RowBlock::hessian_in`].
            pub fn hessian_in(
                &self,
                g: &ContactGeometry,
                z: &[f64],
                w: &[f64],
            ) -> Option<DMatrix<f64>> {
                match self {
                    $(VectorKind::$variant(k) => k.hessian_in(g, z, w),)*
                }
            }
            /// See [`RowBlock::jacobian`].
            pub fn jacobian<M: MechanicsDerivatives>(
                &self,
                mech: &M,
                ctx: &Context,
                z: &[f64],
            ) -> Option<DMatrix<f64>> {
                match self {
                    $(VectorKind::$variant(k) => k.jacobian(mech, ctx, z),)*
                }
            }
            /// See [`RowBlock::hessian`].
            pub fn hessian<M: MechanicsDerivatives>(
                &self,
                mech: &M,
                ctx: &Context,
                z: &[f64],
                w: &[f64],
            ) -> Option<DMatrix<f64>> {
                match self {
                    $(VectorKind::$variant(k) => k.hessian(mech, ctx, z, w),)*
                }
            }
        }
    };
}

/// The list of gradient kinds (costs included): `Variant in module`; `module::Variant`
/// implements [`GradientBlock`]. Generates [`ScalarKind`] and its dispatch.
macro_rules! gradient_kinds {
    ($($variant:ident in $module:ident),* $(,)?) => {
        /// What a gradient (or cost) block computes (one kind per file; z layouts there).
        #[derive(Debug, Clone, PartialEq)]
        pub enum ScalarKind {
            $(
                #[allow(missing_docs)]
                $variant($variant),
            )*
        }

        $(impl From<$variant> for ScalarKind {
            fn from(kind: $variant) -> Self {
                ScalarKind::$variant(kind)
            }
        })*

        impl ScalarKind {
            /// Every gradient and cost kind's blocks of `stage`, in the list's order.
            pub fn place(p: &mut Placement<'_>, stage: Stage) {
                $(<$variant as GradientBlock>::place(p, stage);)*
            }
            /// See [`GradientBlock::NAME`].
            pub fn name(&self) -> &'static str {
                match self {
                    $(ScalarKind::$variant(_) => <$variant as GradientBlock>::NAME,)*
                }
            }
            /// See [`GradientBlock::ALWAYS_CLOSED_FORM`].
            pub fn always_closed_form(&self) -> bool {
                match self {
                    $(ScalarKind::$variant(_) => <$variant as GradientBlock>::ALWAYS_CLOSED_FORM,)*
                }
            }
            /// See [`GradientBlock::SEGMENT_GROUPS`].
            pub fn segment_groups(&self) -> bool {
                match self {
                    $(ScalarKind::$variant(_) => <$variant as GradientBlock>::SEGMENT_GROUPS,)*
                }
            }
            /// See [`GradientBlock::value`].
            pub fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D]) -> D {
                match self {
                    $(ScalarKind::$variant(k) => k.value(mech, ctx, z),)*
                }
            }
            /// See [`GradientBlock::geometry`].
            pub fn geometry<M: Mechanics>(&self, mech: &M, n: usize) -> Option<GeometryUse> {
                match self {
                    $(ScalarKind::$variant(k) => k.geometry(mech, n),)*
                }
            }
            /// See [`GradientBlock::hessian_in`].
            pub fn hessian_in(&self, g: &ContactGeometry, z: &[f64]) -> Option<DMatrix<f64>> {
                match self {
                    $(ScalarKind::$variant(k) => k.hessian_in(g, z),)*
                }
            }
            /// See [`GradientBlock::contracted_third_in`].
            pub fn contracted_third_in(
                &self,
                g: &ContactGeometry,
                z: &[f64],
                dir: &[f64],
            ) -> Option<DMatrix<f64>> {
                match self {
                    $(ScalarKind::$variant(k) => k.contracted_third_in(g, z, dir),)*
                }
            }
            /// See [`GradientBlock::gradient`].
            pub fn gradient<M: MechanicsDerivatives>(
                &self,
                at: &Eval<M>,
                z: &[f64],
            ) -> Option<Vec<f64>> {
                match self {
                    $(ScalarKind::$variant(k) => k.gradient(at, z),)*
                }
            }
            /// See [`GradientBlock::hessian`].
            pub fn hessian<M: MechanicsDerivatives>(
                &self,
                at: &Eval<M>,
                z: &[f64],
            ) -> Option<DMatrix<f64>> {
                match self {
                    $(ScalarKind::$variant(k) => k.hessian(at, z),)*
                }
            }
            /// See [`GradientBlock::third`].
            pub fn third<M: MechanicsDerivatives>(
                &self,
                at: &Eval<M>,
                z: &[f64],
                dir: &[f64],
            ) -> Option<ThirdOrder> {
                match self {
                    $(ScalarKind::$variant(k) => k.third(at, z, dir),)*
                }
            }
        }
    };
}

vector_kinds! {
    HalfForce in half_force,
    GalerkinForce in galerkin_force,
    InitialMomentum in initial_momentum,
    EulerKnot in euler_knot,
    SpinFriction in spin_friction,
    LoopClosure in loop_closure,
    TangentialRate in tangential_rate,
    TangentialSlack in tangential_slack,
    Distance in distance,
    InteriorDistance in interior_distance,
    FrictionCone in friction_cone,
    Complementarity in complementarity,
    EqualStep in equal_step,
    Constraint in constraint,
    FrameRow in frame_row,
}

gradient_kinds! {
    Segment in segment,
    GalerkinSegment in galerkin_segment,
    ContactWork in contact_work,
    LoopWork in loop_work,
    ComplementarityPenalty in complementarity_penalty,
    Cost in cost,
    FrameCost in frame_cost,
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
    /// The inputs a generic-AD Hessian of the block runs over: those in the Hessian pattern,
    /// less the fixed variables when `skip_fixed` (`Transcription::set_skip_fixed_variables`).
    pub fn hessian_inputs_for(&self, skip_fixed: bool) -> &[usize] {
        if skip_fixed {
            &self.hessian_free_inputs
        } else {
            &self.hessian_inputs
        }
    }

    /// The column groups of the block's second derivative for the inputs its Hessian runs
    /// over (the free ones when `skip_fixed`), if any.
    pub fn groups_for(&self, skip_fixed: bool) -> Option<&SymmetricGroups> {
        if skip_fixed {
            self.free_second_derivative_groups.as_deref()
        } else {
            self.second_derivative_groups.as_deref()
        }
    }

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

impl<'a, M> VectorBlockFn<'a, M> {
    /// Block `b` bound to the mechanics and the problem's constants.
    pub fn new(mech: &'a M, ctx: &'a Context, b: &'a Block<VectorKind>) -> Self {
        VectorBlockFn {
            mech,
            ctx,
            kind: &b.kind,
            dim_in: b.vars.len(),
            dim_out: b.targets.len(),
        }
    }
}

impl<M: Mechanics> VectorFunction for VectorBlockFn<'_, M> {
    fn dim_in(&self) -> usize {
        self.dim_in
    }
    fn dim_out(&self) -> usize {
        self.dim_out
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        self.kind.value(self.mech, self.ctx, z, out)
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

impl<'a, M> ScalarBlockFn<'a, M> {
    /// Block `b` bound to the mechanics and the problem's constants.
    pub fn new(mech: &'a M, ctx: &'a Context, b: &'a Block<ScalarKind>) -> Self {
        ScalarBlockFn {
            mech,
            ctx,
            kind: &b.kind,
            dim: b.vars.len(),
        }
    }
}

impl<M: Mechanics> ScalarFunction for ScalarBlockFn<'_, M> {
    fn dim(&self) -> usize {
        self.dim
    }
    fn eval<D: Scalar>(&self, z: &[D]) -> D {
        self.kind.value(self.mech, self.ctx, z)
    }
}
