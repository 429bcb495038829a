//! The variational contact NLP: variable layout, constraint blocks, costs, sparse assembly.
//!
//! [`Transcription`] builds the variational contact NLP (docs/reference-problems.md) for a [`ProblemSpec`] and a robot
//! given as [`Mechanics`] (with [`MechanicsDerivatives`]); its value methods assemble exact
//! sparse derivatives from per-block derivatives.
//!
//! Where things are: `layout` (variable indices, the dynamics rows and the rows the kinds
//! declare), `blocks` (each block kind in its own file: its value, closed-form derivatives,
//! placement and the rows it owns; dynamics pieces from `discrete::del`, contact rows from
//! `crate::contact`; cost terms, one file each, are `crate::problem::costs`; `place_blocks`
//! has every kind place its blocks), `structure` (sparsity patterns), `start` (bounds and
//! initial guess), `program` (the [`Transcription`], the one owner of the NLP's data, with
//! `evaluate`: values and derivatives, and `inspect`: what reports read at a point and the
//! derivative check), `nlp` (the Ipopt callbacks' adapter), `scaling` (Ipopt's user scaling
//! from the problem's units, `[solver] scaling = "units"`), `solve` (the solve driver:
//! multi-start, slack continuation; `carried`, a finer level's solve with the contact modes
//! of the level below; the entry point is `crate::pipeline::solve`), `solution`
//! (what a solve returns, read off Ipopt's final iterate), `robot` (a problem's URDF
//! mechanics).

mod blocks;
mod carried;
mod error;
mod layout;
mod nlp;
mod passive;
mod pattern;
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
pub use carried::CarriedModes;
pub use error::TranscriptionError;
pub use layout::{Dims, EntryNames, IntervalRows, Layout};
pub use nlp::{Progress, ProgressFn, TranscriptionNlp};
pub use passive::{SimulationStart, is_passive};
pub use pattern::{Pattern, PatternBuilder};
pub use program::{DerivativeCheck, DerivativeKind, EntryCheck, FixedModes};
pub use program::{InitialGuessReport, Transcription};
pub use scaling::{units_scaling, variable_units};
pub use solution::{GridLevel, NlpSize, Solution};
pub use solve::{
    BenchRow, ContinuationSolve, LostStart, MAX_STARTS, MultiStart, PENALTY_BOUND_RELAX,
    PERTURBATION, PolishRecord, SolveOptions, StartOutcome, StartRecord, StartSolve, best_of,
};
pub(crate) use solve::{bench_with, solve_with};
pub use verdict::{
    DEFAULT_SLACK_TOLERANCE, RELAXED_CONTACT, RowViolation, SlackPeak, SolveVerdict, TIMEOUT,
};

#[allow(unused_imports)]
use crate::problem::ProblemSpec;

/// The shipped hopper (`problems/hopper_2d.toml`), the small problem of the module's unit
/// tests.
#[cfg(test)]
pub(crate) mod fixture {
    use super::{ModelMechanics, Transcription};
    use crate::problem::{Override, ProblemSpec, load};

    /// The hopper's spec with `overrides` (`--set` syntax) applied.
    pub fn hopper_spec(overrides: &[&str]) -> ProblemSpec {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/hopper_2d.toml");
        let overrides: Vec<Override> = overrides
            .iter()
            .map(|o| Override::parse(o).expect("a valid override"))
            .collect();
        load(&path, &overrides)
            .expect("the shipped hopper loads")
            .spec
    }

    /// The hopper's NLP with `overrides` applied.
    pub fn hopper(overrides: &[&str]) -> Transcription<ModelMechanics> {
        let spec = hopper_spec(overrides);
        let mech = ModelMechanics::load(&spec).expect("the hopper's URDF loads");
        Transcription::new(mech, &spec).expect("the hopper's NLP builds")
    }
}
