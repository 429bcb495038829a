//! The variational contact NLP: variable layout, constraint blocks, costs, sparse assembly.
//!
//! [`Transcription`] builds the variational contact NLP (docs/reference-problems.md) for a [`ProblemSpec`] and a robot
//! given as [`Mechanics`] (with [`MechanicsDerivatives`]); its value methods assemble exact
//! sparse derivatives from per-block derivatives.
//!
//! Where things are: `layout` (variable indices, the dynamics rows and the rows the kinds
//! declare), `blocks` (each block kind in its own file: its value, closed-form derivatives,
//! placement and the rows it owns; dynamics pieces from `discrete::del`, contact rows from
//! `crate::contact`; cost terms, one file each, are `crate::problem::costs`), `placement`
//! (the driver that has every kind place its blocks), `structure` (sparsity patterns),
//! `start` (bounds, initial guess, warm start), `evaluate` (values and derivatives),
//! `program` (the [`Transcription`] itself), `nlp` (the Ipopt callbacks' adapter), `scaling`
//! (Ipopt's user scaling from the problem's units, `[solver] scaling = "units"`), `solve`
//! (solving a problem file's NLP, slack continuation; the entry point is
//! `crate::pipeline::solve`), `robot` (a problem's URDF mechanics).

mod blocks;
mod derivative_check;
mod error;
mod evaluate;
mod layout;
mod nlp;
mod pattern;
mod placement;
mod program;
mod robot;
mod scaling;
mod solution;
mod solve;
mod start;
mod structure;
mod verdict;

pub use crate::discrete::{
    Mechanics, MechanicsDerivatives, ModelMechanics, contact_jet_by_autodiff,
};
pub use blocks::Context;
pub use derivative_check::{DerivativeCheck, DerivativeKind, EntryCheck};
pub use error::TranscriptionError;
pub use layout::{Dims, EntryNames, IntervalRows, Layout};
pub use nlp::{Progress, ProgressFn, TranscriptionNlp};
pub use pattern::{Pattern, PatternBuilder};
pub use program::{InitialGuessReport, Transcription};
pub use solution::{NlpSize, Solution};
pub use solve::{
    BenchRow, MultiStart, PENALTY_BOUND_RELAX, PERTURBATION, SolveOptions, StartRecord, best_of,
};
pub(crate) use solve::{bench_with, solve_with};
pub use verdict::{
    DEFAULT_SLACK_TOLERANCE, RELAXED_CONTACT, RowViolation, SlackPeak, SolveVerdict, TIMEOUT,
};

#[allow(unused_imports)]
use crate::problem::ProblemSpec;
