//! The variational contact NLP: variable layout, constraint blocks, costs, sparse assembly.
//!
//! [`Transcription`] builds SPEC.md's nonlinear program for a [`ProblemSpec`] and a robot
//! given as [`Mechanics`]; its value methods assemble exact sparse derivatives from
//! per-block forward-mode AD.

mod assemble;
mod blocks;
mod error;
mod layout;
mod mechanics;
mod model_mechanics;
mod nlp;
mod pattern;
mod solution;
mod solve;

pub use assemble::{InitialGuessReport, Transcription};
pub use blocks::{Context, ScalarKind, VectorKind};
pub use error::TranscriptionError;
pub use layout::{Dims, Layout};
pub use mechanics::{Mechanics, contact_jet_by_autodiff};
pub use model_mechanics::ModelMechanics;
pub use nlp::{Progress, ProgressFn, TranscriptionNlp};
pub use pattern::{Pattern, PatternBuilder};
pub use solution::{NlpSize, Solution};
pub use solve::{
    BenchRow, SolveOptions, bench, bench_with, evaluate_initial_guess, solve, solve_with,
};

#[allow(unused_imports)]
use crate::problem::ProblemSpec;
