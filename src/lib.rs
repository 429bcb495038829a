//! vito: variational contact-implicit trajectory optimisation for legged robots.
//!
//! The pipeline (see `../shared/DESIGN.md`): a TOML problem file is parsed and checked into a
//! [`problem::ProblemSpec`]; the robot comes from a URDF as a [`model::Model`]; the
//! [`transcription`] turns both into a sparse nonlinear program whose derivatives come from
//! [`autodiff`] over the [`discrete`] mechanics and [`contact`] geometry; [`ipopt`] solves it;
//! [`report`] writes what a researcher reads.
//!
//! Module map:
//! - `ipopt`: the only place with `unsafe`: FFI bindings and the safe solver wrapper.
//! - `model`: URDF → kinematic tree, energies, springs, dampers, loop closures (generic scalar).
//! - `dependency`: a scalar that tracks which inputs a value depends on (sparsity by construction).
//! - `autodiff`: dense local Jacobians and Hessians of small functions by forward-mode duals.
//! - `discrete`: the robot's mechanics traits (`Mechanics`, `MechanicsDerivatives`, for a URDF
//!   robot `ModelMechanics`), discrete Lagrangians (midpoint, first-order Euler) and forces, the
//!   DEL equations (`discrete/del.rs`), forward stepping. A new integrator goes here.
//! - `contact`: contact physics: terrain (`contact/terrain/`), signed distance, the friction
//!   basis and its one rule (`FrictionBasis::for_robot`, from `Model::moves_in_xz_plane`), the
//!   contact model of a problem, and the contact rows (distance, impulses, tangential velocity,
//!   friction cone, complementarity) with their closed-form derivatives, for the NLP and `sim`.
//! - `transcription`: variable layout, constraint blocks (placing `contact`'s rows), cost
//!   terms (one file each in `transcription/costs/`), placement, sparsity, start, evaluation,
//!   the NLP adapter for Ipopt.
//! - `problem`: TOML schema, validation into a checked `ProblemSpec`.
//! - `report`: trajectory CSV, summary JSON, SVG plots, regression records.
//! - `sim`: forward simulation with the same DEL and contact rows as the NLP (each step a
//!   small complementarity problem, solved by the strategies of `sim/ncp/`), the inputs of
//!   `vito simulate`.
//! - `study`: the paper's accuracy studies (figures 5 and 6) over `sim` and `pipeline`.
//! - `testing`: the seeded generator of test and benchmark inputs.
//! - `pipeline`: the steps the commands run on a loaded problem (Ipopt's option check, the
//!   solver's NLP and its size, solve, bench), so that `check` reports what `solve` builds.
//! - `fuzz`: the fuzz harness: the project's own files, mutated, through problem and URDF
//!   loading (`make fuzz`).
//! - `regress`: solving a regression record's problems, one process each, and blessing it.
//! - `paths`: a path as another file's directory names it.
//! - `trajectory_csv`: the trajectory CSV format (columns, units, numbers, parsing), written
//!   by `report` and read by `problem` for warm starts.
//! - `names`: how messages list names.
//! - `input`: reading the files a user names: regular files only, of bounded size.
//! - `blas_kernels`: the pinned OpenBLAS core type (set by the `vito` binary before OpenBLAS
//!   loads, and by the Python package before it loads the library).
#![deny(unsafe_code)]

pub mod autodiff;
pub mod blas_kernels;
pub mod contact;
pub mod dependency;
pub mod discrete;
pub mod fuzz;
pub mod independent;
pub mod input;
#[allow(unsafe_code)]
pub mod ipopt;
pub mod model;
pub mod names;
pub mod paths;
pub mod pipeline;
pub mod problem;
pub mod regress;
pub mod report;
pub mod scalar;
pub mod sim;
pub mod simulated_guess;
pub mod study;
pub mod sweep;
pub mod testing;
pub mod trajectory_csv;
pub mod transcription;
pub mod view;
