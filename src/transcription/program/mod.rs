//! The [`Transcription`]: the NLP of one problem. [`Transcription::new`] builds its data once
//! from the builders of the sibling modules (`blocks::place_blocks`: which blocks;
//! `structure`: sparsity; `start`: bounds and initial guess), and only this module and its
//! children see the fields: `evaluate` (values and derivatives) and `inspect` (what reports
//! read, the derivative check) read them; the evaluation settings and the starting point are
//! changed here.

mod evaluate;
mod inspect;
mod modes;

pub use inspect::{DerivativeCheck, DerivativeKind, EntryCheck};
pub use modes::FixedModes;

use super::blocks::{Block, Context, ScalarKind, VectorKind, place_blocks};
use super::error::check_len;
use super::layout::{Dims, Layout};
use super::pattern::Pattern;
use super::start::{bounds, initial_guess, interior_points};
use super::structure::build_patterns;
use super::{NlpSize, TranscriptionError};
use crate::discrete::{Mechanics, MechanicsDerivatives};
use crate::problem::costs::{CostSizes, length_mismatch};
use crate::problem::frames::FrameReads;
use crate::problem::{HessianMode, InitialGuess, ProblemSpec, TimeSteps};
use evaluate::{ContactDerivatives, JetPools};

/// From this many Jacobian nonzeros on, the Jacobian and Hessian blocks are evaluated on
/// rayon's pool (see [`Transcription::set_parallel`]).
pub const PARALLEL_FROM_JACOBIAN_NNZ: usize = 100_000;

/// The values at the initial guess (docs/reference-problems.md) (no solver involved).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialGuessReport {
    /// Objective f(x₀) (problem cost + slack penalty).
    pub objective: f64,
    /// Largest constraint violation at x₀.
    pub max_constraint_violation: f64,
    /// 2-norm of the equality-constraint residuals at x₀.
    pub equality_residual_norm: f64,
}

/// The variational contact NLP of one problem (docs/reference-problems.md), ready for Ipopt.
pub struct Transcription<M> {
    mech: M,
    ctx: Context,
    layout: Layout,
    hessian_mode: HessianMode,
    x_lower: Vec<f64>,
    x_upper: Vec<f64>,
    g_lower: Vec<f64>,
    g_upper: Vec<f64>,
    /// The starting point (see [`Transcription::set_initial_point`]).
    x_initial: Vec<f64>,
    vector_blocks: Vec<Block<VectorKind>>,
    gradient_blocks: Vec<Block<ScalarKind>>,
    cost_blocks: Vec<Block<ScalarKind>>,
    jacobian: Pattern,
    hessian: Pattern,
    parallel: bool,
    /// How the contact blocks' derivatives are taken when evaluating.
    contact_derivatives: ContactDerivatives,
    /// See [`Transcription::set_skip_fixed_variables`].
    skip_fixed: bool,
    /// Storage of the contact geometries' point jets, kept from one derivative call to the
    /// next.
    jets: JetPools,
}

impl<M: MechanicsDerivatives> Transcription<M> {
    /// Lay out the NLP of `spec` for the robot `mech` (whose contacts are `spec.contacts`,
    /// in order) and compute its sparsity patterns.
    pub fn new(mech: M, spec: &ProblemSpec) -> Result<Self, TranscriptionError> {
        let (n, m, nl) = (mech.nq(), mech.nu(), mech.num_loop_constraints());
        let nc = spec.contacts.len();
        check_len("contacts", mech.num_contacts(), nc)?;
        check_len("q_initial", n, spec.q_initial.len())?;
        check_len("q_final", n, spec.q_final.len())?;
        check_len("input_bounds", m, spec.input_bounds.len())?;
        if let Some(v) = &spec.v_initial {
            check_len("v_initial", n, v.len())?;
        }
        if spec.knots < 2 {
            return Err(TranscriptionError::Invalid {
                field: "knots".into(),
                message: format!("{} knots; a trajectory needs at least 2", spec.knots),
            });
        }
        if spec.mode_block < 1 || spec.mode_block > spec.knots - 1 {
            return Err(TranscriptionError::Invalid {
                field: "mode_block".into(),
                message: format!(
                    "{} intervals per contact-mode block; give 1 to the horizon's {} intervals",
                    spec.mode_block,
                    spec.knots - 1
                ),
            });
        }
        let ctx = Context::new(&mech, spec);
        let nd = ctx.nd();
        for (t, term) in spec.costs.iter().enumerate() {
            if let Some((field, expected, found)) = length_mismatch(term, CostSizes { n, m, nc }) {
                return Err(TranscriptionError::Length {
                    field: format!("costs[{t}].{field}"),
                    expected,
                    found,
                });
            }
        }
        // Validation checks this for problem files; a spec built in code is checked here.
        for (c, constraint) in spec.constraints.iter().enumerate() {
            if let Some(message) = constraint
                .missing_knot(spec.knots)
                .or_else(|| constraint.integrator_problem(spec.integrator))
            {
                return Err(TranscriptionError::Invalid {
                    field: format!("constraints[{c}]"),
                    message,
                });
            }
        }
        if let Some((field, message)) = frame_problem(&mech, spec) {
            return Err(TranscriptionError::Invalid { field, message });
        }
        let equal_steps = matches!(spec.time_steps, TimeSteps::FreeEqual { .. });
        let dims = Dims {
            n,
            m,
            nc,
            nd,
            nl,
            interior: spec.integrator.galerkin_degree().map_or(0, |s| s - 1),
        };
        let layout = Layout::new(
            dims,
            spec.knots,
            spec.slack_mode,
            equal_steps,
            spec.constraints
                .iter()
                .flat_map(|c| c.rows().into_iter().map(|row| row.label))
                .chain(frame_row_labels(spec))
                .collect(),
            VectorKind::interval_rows(&dims, spec.slack_mode),
        );
        let mut blocks = place_blocks(&mech, &layout, &ctx);
        let bounds = bounds(&mech, &layout, spec)?;
        let x_initial = initial_guess(&mech, &ctx, &layout, &bounds, spec)?;
        let (jacobian, hessian) = build_patterns(
            &mech,
            &ctx,
            &mut blocks,
            &x_initial,
            (&bounds.x_lower, &bounds.x_upper),
        );
        // Measured in solves on the shared 2-core machine (BENCHMARKS.md): the
        // pool pays for HAMR's Jacobian and Hessian (143,302 Jacobian nonzeros: J 41 ms, H
        // 127 ms a call against 63 and 170 serial) and costs on the brick's (32,546: callbacks
        // 6.4 s a solve against 3.9 s serial), whose J + H now take 5 ms.
        let parallel = jacobian.nnz() >= PARALLEL_FROM_JACOBIAN_NNZ;
        let mut transcription = Transcription {
            ctx,
            layout,
            hessian_mode: spec.hessian,
            x_lower: bounds.x_lower,
            x_upper: bounds.x_upper,
            g_lower: bounds.g_lower,
            g_upper: bounds.g_upper,
            x_initial,
            vector_blocks: blocks.vector,
            gradient_blocks: blocks.gradient,
            cost_blocks: blocks.cost,
            jacobian,
            hessian,
            parallel,
            contact_derivatives: ContactDerivatives::ChainRule,
            skip_fixed: false,
            jets: JetPools::default(),
            mech,
        };
        // A start carrying its impulses (a coarser level's plan) gets the sliding speeds,
        // their duals and the slacks that go with them.
        if matches!(&spec.initial_guess, InitialGuess::WarmStart(w) if !w.forces.is_empty()) {
            let mut x = std::mem::take(&mut transcription.x_initial);
            super::start::sliding_from_rows(&transcription, &mut x);
            super::start::slacks_from_rows(&transcription, &mut x);
            transcription.x_initial = x;
        }
        Ok(transcription)
    }

    /// Slack weight α of the objective α Σ s.
    pub fn slack_weight(&self) -> f64 {
        self.ctx.slack_weight
    }

    /// Change α (for the exact-penalty continuation; in penalty mode the products' weight).
    pub fn set_slack_weight(&mut self, weight: f64) {
        self.ctx.slack_weight = weight;
    }

    /// Evaluate the Jacobian's and the Hessian's blocks on rayon's thread pool or on one
    /// thread (the default is parallel from [`PARALLEL_FROM_JACOBIAN_NNZ`] Jacobian
    /// nonzeros on; f, ∇f and g are always serial). Results are the same either way.
    pub fn set_parallel(&mut self, parallel: bool) {
        self.parallel = parallel;
    }

    /// Differentiate the contact blocks (tangential rate, contact work, signed distance, c·φ)
    /// by the chain rule through the contact point's jet, and the bilinear complementarity rows
    /// in closed form (the default), or all of them by generic forward AD over the whole block
    /// (for comparison; the sparsity pattern, from dependencies, is the same).
    pub fn set_contact_chain_rule(&mut self, enabled: bool) {
        self.contact_derivatives = if enabled {
            ContactDerivatives::ChainRule
        } else {
            ContactDerivatives::GenericAd
        };
    }

    /// Leave the Hessian entries of variables fixed by their bounds at zero where that saves
    /// work (generic-AD blocks). Ipopt drops those entries with its default
    /// `fixed_variable_treatment make_parameter`; the solve turns this on unless that option
    /// says otherwise. Off by default, so that every entry is exact.
    pub fn set_skip_fixed_variables(&mut self, skip: bool) {
        self.skip_fixed = skip;
    }

    /// The variable and row layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The robot mechanics.
    pub fn mechanics(&self) -> &M {
        &self.mech
    }

    /// Variable bounds (lower, upper), length = number of variables.
    pub fn variable_bounds(&self) -> (&[f64], &[f64]) {
        (&self.x_lower, &self.x_upper)
    }

    /// Constraint bounds (lower, upper), length = number of rows.
    pub fn constraint_bounds(&self) -> (&[f64], &[f64]) {
        (&self.g_lower, &self.g_upper)
    }

    /// The starting point.
    pub fn initial_point(&self) -> &[f64] {
        &self.x_initial
    }

    /// Jacobian sparsity.
    pub fn jacobian_pattern(&self) -> &Pattern {
        &self.jacobian
    }

    /// Lagrangian-Hessian sparsity (lower triangle).
    pub fn hessian_pattern(&self) -> &Pattern {
        &self.hessian
    }

    /// How the Hessian is obtained.
    pub fn hessian_mode(&self) -> HessianMode {
        self.hessian_mode
    }

    /// The sizes Ipopt is given: variables, constraints and nonzeros (no Hessian entries
    /// under L-BFGS). The one definition `check`, `solve` and `bench` report.
    pub fn size(&self) -> NlpSize {
        NlpSize {
            n_variables: self.layout().num_variables(),
            n_constraints: self.layout().num_constraints(),
            nnz_jacobian: self.jacobian.nnz(),
            nnz_hessian: match self.hessian_mode {
                HessianMode::Exact => self.hessian.nnz(),
                HessianMode::Lbfgs => 0,
            },
        }
    }

    /// Problem constants of the blocks.
    pub fn context(&self) -> &Context {
        &self.ctx
    }

    /// Start the next solve from `x` (all variables, e.g. a previous solution), clamped to the
    /// variable bounds.
    pub fn set_initial_point(&mut self, x: &[f64]) -> Result<(), TranscriptionError> {
        check_len("initial point", self.x_initial.len(), x.len())?;
        for (i, (&xi, out)) in x.iter().zip(self.x_initial.iter_mut()).enumerate() {
            *out = xi.clamp(self.x_lower[i], self.x_upper[i]);
        }
        Ok(())
    }

    /// Sets a Galerkin integrator's interior points in `x` from its knots: on the chord between
    /// each interval's knots, or with `from_dynamics` where the interval's dynamics put them
    /// (stationary, as at a solution). Nothing for another integrator.
    pub fn set_interior_points(&self, x: &mut [f64], from_dynamics: bool) {
        interior_points(&self.mech, &self.ctx, &self.layout, x, from_dynamics);
    }
}

/// The labels of the frame terms' rows, in row order (after the problem file's constraints).
fn frame_row_labels(spec: &ProblemSpec) -> impl Iterator<Item = String> + '_ {
    spec.frames
        .iter()
        .filter(|f| f.has_rows())
        .flat_map(|f| f.knots.iter().map(|&k| f.row_label(k)))
}

/// Why the frame terms of a spec built in code cannot be placed (validation checks these for
/// problem files): a knot outside the horizon, a velocity at knot 0, or a link point on
/// mechanics without link poses.
fn frame_problem<M: Mechanics>(mech: &M, spec: &ProblemSpec) -> Option<(String, String)> {
    let q = vec![0.0; mech.nq()];
    spec.frames.iter().enumerate().find_map(|(t, f)| {
        let field = format!("frames[{t}]");
        let reads_interval = f.quantity.reads() == FrameReads::IntervalEndingAt;
        if let Some(&k) = f
            .knots
            .iter()
            .find(|&&k| k >= spec.knots || (reads_interval && k == 0))
        {
            return Some((field, format!("knot {k} has no {}", f.quantity.name())));
        }
        (f.quantity.point().needs_link_poses() && mech.link_pose(0, &q).is_none()).then(|| {
            (
                field,
                "a link's point needs a robot with link poses (a URDF model)".to_string(),
            )
        })
    })
}
