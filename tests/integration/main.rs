//! vito's integration tests: one test crate (the library is linked once), a module per area.
//!
//! Solving tests need the optimised build: `cargo test --release` (one module:
//! `cargo test --release --test integration cli::`).

mod common;

mod architecture;
mod cli;
mod constraints;
mod discrete;
mod frames;
mod fuzz;
mod galerkin;
mod hamr;
mod ipopt;
mod model_adjoint;
mod model_errors;
mod model_mechanics;
mod model_point_jet;
mod model_robots;
mod model_ros_urdfs;
mod model_user_urdfs;
mod sim;
mod study;
mod transcription_derivative_check;
mod transcription_derivatives;
mod transcription_initial_guess;
mod transcription_solve;
mod transcription_urdf;
mod view;
