//! `vito._vito`: the Python binding of the `vito` library (the package `vito` re-exports it).
//!
//! Nothing here solves, writes or checks anything itself: each call runs the library
//! functions the `vito` command runs (`pipeline::load_checked`, `pipeline::check_report`,
//! `pipeline::solve`, `pipeline::simulation`, `report`, `sweep`), and turns their results
//! into Python objects (numpy arrays, dicts) and their errors into Python exceptions. Long
//! calls run on their own thread without the GIL (`watch.rs`).
//!
//! One file per topic: `errors.rs` (exceptions), `convert.rs` (Python values ↔ the
//! library's), `watch.rs` (long calls, signals, progress), `problem.rs` (`Problem`),
//! `solve.rs` (a solve), `solution.rs` (`Trajectory`, `Solution`), `pickle.rs` (the state
//! results pickle with, checked on restoring), `simulation.rs` (`simulate`, `Simulation`),
//! `sweep.rs` (sweeps, executor jobs), `html.rs` (notebook display), `kinematics.rs` and
//! `dynamics.rs` (a robot's kinematics and dynamics at a configuration), `mujoco.rs` (a
//! problem's world as MJCF for `vito.mujoco`).

use pyo3::prelude::*;

mod convert;
mod dynamics;
mod errors;
mod html;
mod kinematics;
mod load;
mod mujoco;
mod pickle;
mod problem;
mod simulation;
mod solution;
mod solve;
mod sweep;
mod watch;

/// The OpenBLAS core type the `vito` command pins on this CPU (None: it pins none), which
/// the package sets before it loads the library.
#[pyfunction]
fn pinned_coretype() -> Option<&'static str> {
    vito::ipopt::blas_kernels::coretype()
}

/// How many problem files this process has been asked to load (`vito::problem::loads`):
/// what the tests count a set-up's work by.
#[pyfunction]
fn _problem_loads() -> usize {
    vito::problem::loads()
}

/// The native module `vito._vito`; the package `vito` re-exports it.
#[pymodule]
fn _vito(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    kinematics::register(m)?;
    dynamics::register(m)?;
    m.add_function(wrap_pyfunction!(mujoco::mujoco_model, m)?)?;
    m.add_class::<problem::Problem>()?;
    m.add_class::<solution::Trajectory>()?;
    m.add_class::<solution::Solution>()?;
    m.add_class::<simulation::Simulation>()?;
    m.add_class::<sweep::SweepJobs>()?;
    m.add_function(wrap_pyfunction!(simulation::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::_solve_point, m)?)?;
    m.add_function(wrap_pyfunction!(problem::_restore_problem, m)?)?;
    m.add_function(wrap_pyfunction!(solution::_restore_solution, m)?)?;
    m.add_function(wrap_pyfunction!(simulation::_restore_simulation, m)?)?;
    m.add_function(wrap_pyfunction!(pinned_coretype, m)?)?;
    m.add_function(wrap_pyfunction!(_problem_loads, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("IPOPT_VERSION", vito::ipopt::VERSION)?;
    Ok(())
}
