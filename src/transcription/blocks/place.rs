//! Where blocks go: the NLP's skeleton as a sequence of [`Stage`]s, and the [`Placement`] each
//! kind pushes its blocks onto (its `place` method, in its own file, says which variables each
//! block reads and which rows it adds into).
//!
//! Per interval j the stages run in the order of [`Stage::sequence`]; at each stage every kind
//! is asked in the order of the `vector_kinds!` and `gradient_kinds!` lists. Blocks that add
//! into the same row add in that order, which is what makes a solve reproducible to the bit.

use std::ops::Range;

use super::{Block, Context, ScalarKind, VectorKind};
use crate::discrete::Mechanics;
use crate::transcription::layout::Layout;

/// Every block of an NLP, placed: the rows' vector and gradient blocks and the cost blocks,
/// each list in placement order.
#[derive(Debug, Default)]
pub struct PlacedBlocks {
    /// Vector blocks.
    pub vector: Vec<Block<VectorKind>>,
    /// Gradient blocks.
    pub gradient: Vec<Block<ScalarKind>>,
    /// Cost blocks.
    pub cost: Vec<Block<ScalarKind>>,
}

/// The blocks of the NLP laid out as `layout` for the robot `mech`: every kind places its
/// own, stage by stage ([`Placement::place_all`]).
pub fn place_blocks<M: Mechanics>(mech: &M, layout: &Layout, ctx: &Context) -> PlacedBlocks {
    let rolls = (0..layout.nc).map(|i| mech.contact_rolls(i)).collect();
    let mut placement = Placement::new(layout, ctx, mech.has_discrete_force(), rolls);
    placement.place_all();
    PlacedBlocks {
        vector: placement.vector,
        gradient: placement.gradient,
        cost: placement.cost,
    }
}

/// One step of the NLP's skeleton at which kinds place blocks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Interval j's dynamics: the pieces of the DEL (or Euler) equations on its dynamics rows.
    Dynamics(usize),
    /// The impulse of contact `contact` over interval j, on the dynamics rows.
    ContactImpulse {
        /// The interval.
        j: usize,
        /// The contact.
        contact: usize,
    },
    /// Interval j's loop-closure impulses (on the dynamics rows) and loop-closure rows.
    Loops(usize),
    /// The rows of contact `contact` in interval j: tangential velocity, distance, cone.
    ContactRows {
        /// The interval.
        j: usize,
        /// The contact.
        contact: usize,
    },
    /// Interval j's complementarity rows.
    Complementarity(usize),
    /// After every interval: the equal-step rows.
    EqualSteps,
    /// Then the loop closure at q_0.
    FirstLoops,
    /// Then the problem file's constraints.
    Constraints,
    /// Then the cost terms.
    Costs,
}

impl Stage {
    /// Every stage of an NLP with `intervals` intervals and `contacts` contacts, in order.
    pub fn sequence(intervals: usize, contacts: usize) -> impl Iterator<Item = Stage> {
        (0..intervals)
            .flat_map(move |j| {
                std::iter::once(Stage::Dynamics(j))
                    .chain((0..contacts).map(move |contact| Stage::ContactImpulse { j, contact }))
                    .chain(std::iter::once(Stage::Loops(j)))
                    .chain((0..contacts).map(move |contact| Stage::ContactRows { j, contact }))
                    .chain(std::iter::once(Stage::Complementarity(j)))
            })
            .chain([
                Stage::EqualSteps,
                Stage::FirstLoops,
                Stage::Constraints,
                Stage::Costs,
            ])
    }
}

/// The blocks placed so far, and what placing them reads.
pub struct Placement<'a> {
    /// Where variables and rows live.
    pub layout: &'a Layout,
    /// The problem's constants.
    pub ctx: &'a Context,
    /// Whether the robot's discrete force can be nonzero (inputs or damping).
    pub has_discrete_force: bool,
    /// Per contact, whether it is a rolling sphere.
    pub rolls: Vec<bool>,
    /// Rows that also receive component c of the momentum arriving at the last knot (the
    /// last interval's D2Ld and second half force, which otherwise target no row).
    pub end_rows: Vec<Vec<usize>>,
    /// Vector blocks.
    pub vector: Vec<Block<VectorKind>>,
    /// Gradient blocks.
    pub gradient: Vec<Block<ScalarKind>>,
    /// Cost blocks.
    pub cost: Vec<Block<ScalarKind>>,
}

impl<'a> Placement<'a> {
    /// Nothing placed yet.
    pub fn new(
        layout: &'a Layout,
        ctx: &'a Context,
        has_discrete_force: bool,
        rolls: Vec<bool>,
    ) -> Self {
        let mut end_rows: Vec<Vec<usize>> = vec![Vec::new(); layout.n];
        let mut row = layout.constraint_row(0);
        for constraint in &ctx.constraints {
            if constraint.receives_end_momentum() {
                for (c, rows) in end_rows.iter_mut().enumerate() {
                    rows.push(row + c);
                }
            }
            row += constraint.rows().len();
        }
        Placement {
            layout,
            ctx,
            has_discrete_force,
            rolls,
            end_rows,
            vector: Vec::new(),
            gradient: Vec::new(),
            cost: Vec::new(),
        }
    }

    /// Places every kind's blocks, stage by stage.
    pub fn place_all(&mut self) {
        for stage in Stage::sequence(self.layout.intervals(), self.layout.nc) {
            VectorKind::place(self, stage);
            ScalarKind::place(self, stage);
        }
    }

    /// Interval j's dynamics rows, one target each.
    pub fn dynamics_targets(&self, j: usize) -> Vec<Vec<usize>> {
        each(self.layout.dynamics_rows(j))
    }

    /// The rows of component c of the momentum at the knot that ends interval j: the next
    /// interval's dynamics row, or after the last interval the [`Placement::end_rows`].
    pub fn after_rows(&self, j: usize, c: usize) -> Vec<usize> {
        if j + 1 < self.layout.intervals() {
            vec![self.layout.dynamics_rows(j + 1).start + c]
        } else {
            self.end_rows[c].clone()
        }
    }

    /// Contact i's impulse variables over interval j after the configuration that carries
    /// them: [q_{j+1}; c; β].
    pub fn impulse_vars(&self, j: usize, i: usize) -> Vec<usize> {
        let l = self.layout;
        let mut vars = range_vec(l.q(j + 1));
        vars.push(l.c(j, i));
        vars.extend(l.beta(j, i));
        vars
    }
}

/// The indices of `r`.
pub fn range_vec(r: Range<usize>) -> Vec<usize> {
    r.collect()
}

/// One target per row of `rows`.
pub fn each(rows: impl IntoIterator<Item = usize>) -> Vec<Vec<usize>> {
    rows.into_iter().map(|r| vec![r]).collect()
}
