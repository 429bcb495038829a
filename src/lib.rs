//! vito: variational contact-implicit trajectory optimisation for legged robots.
//!
//! The pipeline (see `ARCHITECTURE.md`): a TOML problem file is parsed and checked into a
//! [`problem::ProblemSpec`]; the robot comes from a URDF as a [`model::Model`]; the
//! [`transcription`] turns both into a sparse nonlinear program whose derivatives come from
//! [`autodiff`] over the [`discrete`] mechanics and [`contact`] geometry; [`ipopt`] solves it;
//! [`report`] writes what a researcher reads.
//!
//! Module map (each path below is a file or directory under `src/`):
//! - `ipopt/`: the only place with `unsafe`: FFI bindings, the safe solver wrapper and its
//!   options (`ipopt/options.rs`, whose `OptionValue` the problem's `[solver.ipopt]` uses), the
//!   BLAS thread pin (`ipopt/threads.rs`) and the pinned OpenBLAS core type
//!   (`ipopt/blas_kernels.rs`, set by the `vito` binary before OpenBLAS loads, and by the
//!   Python package before it loads the library).
//! - `model/`: URDF → kinematic tree (`model/urdf/`), energies, springs, dampers, loop closures
//!   (generic scalar).
//! - `autodiff/`: the one scalar bound of model code (`autodiff/scalar.rs`), dense local
//!   Jacobians and Hessians of small functions by forward-mode duals, and a scalar that tracks
//!   which inputs a value depends on (`autodiff/dependency.rs`, sparsity by construction).
//! - `discrete/`: the robot's mechanics traits (`Mechanics`, `MechanicsDerivatives`, for a URDF
//!   robot `ModelMechanics`), discrete Lagrangians (midpoint, first-order Euler) and forces, the
//!   DEL equations (`discrete/del.rs`), forward stepping. A new integrator goes here.
//! - `contact/`: contact physics: terrain (`contact/terrain/`), signed distance, the friction
//!   basis and its one rule (`FrictionBasis::for_robot`, from `Model::moves_in_xz_plane`), the
//!   contact model of a problem, and the contact rows (distance, impulses, tangential velocity,
//!   friction cone, complementarity) with their closed-form derivatives, for the NLP and `sim`.
//! - `transcription/`: variable layout, constraint blocks (`transcription/blocks/`, one file
//!   per kind: its value, closed-form derivatives, placement and the rows it owns in each
//!   interval; a new kind is one file plus its line in the kinds list there), sparsity,
//!   start, evaluation, the NLP adapter for Ipopt.
//! - `problem/`: TOML schema, validation into a checked `ProblemSpec`; cost terms, one file
//!   each (`problem/costs/`), and constraints (`problem/constraints/`).
//! - `files/`: the files a user names: reading them (regular files only, of bounded size), a
//!   path as another file's directory names it, the trajectory CSV format
//!   (`files/trajectory_csv.rs`: columns, units, numbers, parsing; written by `report`, read
//!   by `problem` for warm starts), and how messages list names.
//! - `report/`: trajectory CSV, summary JSON, SVG plots, regression records.
//! - `sim/`: forward simulation with the same DEL and contact rows as the NLP (each step a
//!   small complementarity problem, solved by the strategies of `sim/ncp/`), and the
//!   simulated initial guess (`sim/guess.rs`).
//! - `pipeline.rs`: the steps the commands run on a loaded problem (Ipopt's option check, the
//!   solver's NLP, solve, bench), so that `check` reports what `solve` builds; beside it in
//!   `pipeline/`: where results go (`output.rs`), what `check` shows before solving
//!   (`feasibility.rs`, `trajectory_point.rs`), and `vito simulate`'s set-up (`simulation.rs`,
//!   `gains.rs`).
//! - `study/`: the paper's accuracy studies (figures 5 and 6) over `sim` and `pipeline`.
//! - `sweep/`: a problem solved over a grid of values, one process per point.
//! - `regress/`: solving a regression record's problems, one process each, and blessing it;
//!   the reference problems (`regress/reference.rs`) and the independent CasADi
//!   implementation run beside them by `vito bench` (`regress/independent.rs`).
//! - `view/`: the animation page and SVG strips of a trajectory.
//! - `random.rs`: the one seeded generator (multi-start points, derivative-check samples, the
//!   brick study's perturbations, fuzzing, test inputs).
//! - `fuzz/`: the fuzz harness (`make fuzz`): the project's own files mutated (`mutate.rs`)
//!   and generated inputs (`generate.rs`: deep expressions, long chains, many attributes,
//!   trajectory CSVs) through the library calls the commands make.
#![deny(unsafe_code)]

pub mod autodiff;
pub mod contact;
pub mod discrete;
pub mod files;
pub mod fuzz;
#[allow(unsafe_code)]
pub mod ipopt;
pub mod model;
pub mod pipeline;
pub mod problem;
pub mod random;
pub mod regress;
pub mod report;
pub mod sim;
pub mod study;
pub mod sweep;
pub mod transcription;
pub mod view;
