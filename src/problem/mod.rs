//! Problem files: the TOML schema, its validation, and the checked [`ProblemSpec`].
//!
//! `load(path, overrides)` reads a problem file, applies `--set` overrides, resolves every
//! name against the robot and returns a [`LoadedProblem`] holding the [`ProblemSpec`].

pub mod constraints;
pub mod costs;
mod error;
pub mod family;
pub mod frames;
mod load;
mod overrides;
mod robot;
pub mod schema;
mod source;
mod spec;
mod starter;
pub mod tracking;
pub mod units;
mod validate;

pub use crate::model::CoordinateKind;
pub use constraints::Constraint;
pub use costs::CostTerm;
pub use error::{Location, ProblemError};
pub use load::{LoadedProblem, load, load_from_str, loads};
pub use overrides::Override;
pub use robot::{RobotError, RobotInfo, UrdfContact};
pub(crate) use source::toml_error_message;
pub use source::{edit_distance, nearest};
pub use spec::*;
pub use starter::starter_problem;
pub use tracking::{TrackingFeedback, TrackingGain};
pub use units::Units;
pub(crate) use validate::memory_available;
pub(crate) use validate::warm_start_from_text;
