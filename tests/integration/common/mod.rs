//! Shared fixtures of the transcription tests: the reference problems (read from their
//! problem files) and closed-form mechanics of the hopper and the brick (independent of the
//! URDF model code).
#![allow(dead_code)]

pub mod analytic;
pub mod reference;
pub mod swing;
