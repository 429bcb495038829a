//! Safe wrapper over Debian's system Ipopt, 3.11 to 3.14 (C interface `IpStdCInterface.h`,
//! bindings by bindgen in `build.rs`; the differences between versions live in `compat.rs`).
//! The only module with `unsafe`.
//!
//! A problem implements [`Nlp`]; a [`Solver`] holds the options (vito's defaults from
//! `vendor-config/ipopt-defaults.opt`, then the caller's) and returns a [`SolveReport`]. A
//! problem may supply its own [`Scaling`] (`nlp_scaling_method user-scaling`).
//!
//! Safety rules the wrapper keeps, because Debian's Ipopt 3.11.9 (and 3.14.17) breaks otherwise:
//! - one solve per process at a time (a global lock; parallel work uses processes; on Debian
//!   13 MUMPS calls MPI, which `libipopt` initialises for one thread when it loads, see
//!   [`mpi_state`]);
//! - a panic in a callback is caught and returned as [`IpoptError::CallbackPanicked`], never
//!   unwound into C++; a NaN or Inf output is reported to Ipopt as a failed evaluation;
//! - `linear_solver` other than `mumps` is refused (`ma97` would end the process: `exit(1)` in
//!   3.11, a segfault in 3.14.17);
//! - no stray `ipopt.opt` in the working directory is read;
//! - the linear algebra runs on one thread whatever the environment says
//!   ([`pin_one_thread`], before every solve), so that a result does not depend on the
//!   machine's core count.
//!
//! ```no_run
//! use vito::ipopt::{Solver, Status};
//! # fn demo<P: vito::ipopt::Nlp>(problem: &mut P) -> Result<(), vito::ipopt::IpoptError> {
//! let mut solver = Solver::new();
//! solver.set_option("max_iter", 500)?;
//! let report = solver.solve(problem)?;
//! if report.status == Status::SolveSucceeded {
//!     println!("f* = {} after {} iterations", report.objective, report.iterations);
//! }
//! # Ok(()) }
//! ```

pub mod blas_kernels;
mod callbacks;
mod compat;
mod error;
mod handle;
mod nlp;
mod options;
pub mod sample;
mod scaling;
mod solver;
mod status;
mod sys;
mod threads;

pub use compat::{LONG_VERSION, MpiState, VERSION, mpi_state};
pub use error::IpoptError;
pub use handle::Multipliers;
pub use nlp::{IterationInfo, Nlp};
pub use options::{
    DEFAULTS_FILE, OptionValue, PROBLEM_FILE_OPTIONS, check_allowed, check_problem_option,
    default_options, parse_option_file,
};
pub use scaling::{GradientRule, JacobianEntries, Scaling};
pub use solver::{CallbackSplit, CallbackStat, SolveReport, Solver, others_waiting_for_ipopt};
pub use status::Status;
pub use threads::{BlasThreads, pin_one_thread};
