//! Forward simulation with the planner's own mechanics and contact model: each step solves
//! the problem of eq. (32) of the paper, the knot's discrete equations (`crate::discrete::del`,
//! midpoint or Euler) with the NLP's contact rows (`crate::contact`: impulses J(q)ᵀλ, signed distance, tangential velocity, polyhedral friction cone) held as
//! exact complementarity, by a smoothed Fischer–Burmeister Newton method with warm starts.
//!
//! Where things are: `step` (one step's complementarity problem: its data, equations and the
//! order in which the solvers are tried), `ncp` (the complementarity solvers, one file per
//! strategy, with Lemke's pivoting method), `run` (a horizon: warm starts, the per-step
//! record, knot energies), `inputs` (zero, replayed or PD-tracking inputs).

pub mod guess;
mod inputs;
mod ncp;
mod run;
mod step;

pub use inputs::{Feedback, Gain, InputSource};
pub use run::{
    Simulation, SimulationError, SimulationOptions, knot_energies, simulate, simulate_until,
};
pub use step::{
    Before, ContactStep, EndStateGain, Impulses, StepFailure, StepInput, StepOptions, StepOutcome,
};
