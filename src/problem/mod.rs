//! Problem files: the TOML schema, its validation, and the checked [`ProblemSpec`].

mod spec;

pub use spec::*;
