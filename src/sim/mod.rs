//! Forward simulation with the planner's own mechanics and contact model: each step solves
//! the problem of eq. (32) of the paper, the knot's discrete equations (`crate::discrete::del`,
//! midpoint or Euler) with the NLP's contact rows (`crate::transcription`'s contact blocks:
//! impulses J(q)ᵀλ, signed distance, tangential velocity, polyhedral friction cone) held as
//! exact complementarity, by a smoothed Fischer–Burmeister Newton method with warm starts.
//!
//! Where things are: `step` (one step's complementarity problem and its solver), `run` (a
//! horizon: warm starts, the per-step record, knot energies), `inputs` (zero, replayed or
//! PD-tracking inputs), `lemke` (the pivoting method the step solver falls back on for the
//! contact mode).

mod inputs;
mod lemke;
mod run;
mod step;

pub use inputs::{Feedback, Gain, InputSource};
pub use run::{Simulation, SimulationError, SimulationOptions, knot_energies, simulate};
pub use step::{
    Before, ContactStep, EndStateGain, Impulses, StepFailure, StepInput, StepOptions, StepOutcome,
};
