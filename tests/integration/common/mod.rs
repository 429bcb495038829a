//! Shared fixtures of the integration tests: the reference problems (read from their
//! problem files, as given or edited), the robots of `problems/robots/`, and closed-form
//! mechanics of the hopper and the brick (independent of the URDF model code).
#![allow(dead_code)]

pub mod analytic;
pub mod reference;
pub mod robots;
pub mod swing;

use std::path::{Path, PathBuf};

/// The repository's `problems/` directory.
pub fn problems_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("problems")
}
