//! The simulated initial guess (`[initial_guess.simulation]`): the robot simulated open loop
//! from q_1 under sinusoidal inputs for a few periods at the NLP's own step, the last period
//! resampled onto the knots. A gait settles towards its limit cycle over the first periods,
//! so the guess is nearly periodic, consistent with the discrete dynamics and contact, and
//! made by rule (amplitudes and phases in the problem file), not by hand per run.

use std::time::Instant;

use crate::discrete::MechanicsDerivatives;
use crate::problem::{Constraint, Interval, ProblemSpec, SimulatedGuess, WarmStart};
use crate::sim::{SimulationError, SimulationOptions, StepOptions, simulate};

/// The guess and how well the simulation settled.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulatedStart {
    /// The last period on the knots, times from 0, the base moved horizontally to q_1's
    /// base_x and base_y.
    pub warm_start: WarmStart,
    /// Largest |q_N − q_1 − offset| over the problem's position-periodicity rows (0 without
    /// them) on the last period: how far from a periodic cycle the simulation ended.
    pub periodicity_defect: f64,
    /// Steps simulated (in the successful run).
    pub steps: usize,
    /// Steps per knot interval it took (the problem's, doubled after each failed step).
    pub substeps: usize,
    /// Wall time of the simulation [s].
    pub wall_time_s: f64,
}

/// Simulates `guess` for `spec`'s robot; the step is period / ((knots − 1) · substeps), so
/// the last period lands on the knots exactly when T equals the period. When the contact
/// solver fails on a step, the whole run is repeated at half the step, up to 8 times finer.
pub fn simulate_guess<M: MechanicsDerivatives>(
    mech: &M,
    spec: &ProblemSpec,
    guess: &SimulatedGuess,
) -> Result<SimulatedStart, SimulationError> {
    let started = Instant::now();
    let mut substeps = guess.substeps.max(1);
    loop {
        match simulate_with(mech, spec, guess, substeps) {
            Ok(mut start) => {
                start.wall_time_s = started.elapsed().as_secs_f64();
                return Ok(start);
            }
            // A step the contact solver cannot take at this size: halve the step.
            Err(SimulationError::Step { .. }) if substeps < MAX_REFINEMENT * guess.substeps => {
                substeps *= 2;
            }
            Err(e) => return Err(e),
        }
    }
}

/// The contact solver's residual tolerance relative to the step's momentum scale: a guess
/// needs no more (`vito simulate` asks 1e-10), and HAMR's open-loop trot stalls at 1e-5
/// relative on some steps of any size.
const GUESS_TOLERANCE: f64 = 1e-4;

/// How much finer than asked the step may get after failed steps.
const MAX_REFINEMENT: usize = 8;

fn simulate_with<M: MechanicsDerivatives>(
    mech: &M,
    spec: &ProblemSpec,
    guess: &SimulatedGuess,
    substeps: usize,
) -> Result<SimulatedStart, SimulationError> {
    let intervals = spec.knots.saturating_sub(1).max(1);
    let per_period = intervals * substeps;
    let h = guess.period / per_period as f64;
    let steps = per_period * guess.cycles.max(1);
    let gravity = spec.robot.gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
    let options = SimulationOptions {
        integrator: spec.integrator,
        h,
        steps,
        step: StepOptions {
            gravity,
            relative_tolerance: GUESS_TOLERANCE,
            ..StepOptions::default()
        },
    };
    let contact = spec.contact_model(mech);
    let n = spec.q_initial.len();
    let v0 = spec.v_initial.clone().unwrap_or_else(|| vec![0.0; n]);
    let sim = simulate(
        mech,
        &contact,
        &spec.q_initial,
        &v0,
        &options,
        |_, t, _, _| clipped(guess.input(t), &spec.input_bounds),
        |_| {},
    )?;
    let first = steps - per_period;
    let mut q: Vec<Vec<f64>> = sim.q[first..=steps]
        .iter()
        .step_by(substeps)
        .cloned()
        .collect();
    let u: Vec<Vec<f64>> = sim.u[first..steps]
        .chunks(substeps)
        .map(|chunk| mean(chunk, spec.input_bounds.len()))
        .collect();
    let names = mech.coordinate_names();
    for base in ["base_x", "base_y"] {
        if let Some(c) = names.iter().position(|name| name == base) {
            let shift = spec.q_initial[c] - q[0][c];
            for qk in &mut q {
                qk[c] += shift;
            }
        }
    }
    let periodicity_defect = spec
        .constraints
        .iter()
        .filter_map(|c| match c {
            Constraint::Periodic(p) => p.offset.map(|offset| (p.coordinate, offset)),
            _ => None,
        })
        .map(|(c, offset)| (q[intervals][c] - q[0][c] - offset).abs())
        .fold(0.0, f64::max);
    Ok(SimulatedStart {
        warm_start: WarmStart {
            source: "[initial_guess.simulation]".into(),
            times: (0..=intervals).map(|k| (k * substeps) as f64 * h).collect(),
            q,
            u,
            forces: Vec::new(),
        },
        periodicity_defect,
        steps,
        substeps,
        wall_time_s: 0.0,
    })
}

/// The mean of `rows` (each of length `m`).
fn mean(rows: &[Vec<f64>], m: usize) -> Vec<f64> {
    let mut sum = vec![0.0; m];
    for row in rows {
        for (s, x) in sum.iter_mut().zip(row) {
            *s += x;
        }
    }
    sum.iter().map(|s| s / rows.len().max(1) as f64).collect()
}

/// `u` clipped into its bounds.
fn clipped(mut u: Vec<f64>, bounds: &[Interval]) -> Vec<f64> {
    for (ui, b) in u.iter_mut().zip(bounds) {
        *ui = ui.clamp(b.lower, b.upper);
    }
    u
}
