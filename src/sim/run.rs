//! A simulation over a horizon: knots q_0..q_N at a fixed step h, inputs held over each
//! interval (zero-order hold, as the NLP holds them), one contact step per interval, warm
//! started from the previous one.

use nalgebra::{DMatrix, DVector};
use std::ops::ControlFlow;

use super::step::{Before, ContactStep, Impulses, StepFailure, StepInput, StepOptions};
use crate::contact::ContactModel;
use crate::discrete::{
    Integrator, Mechanics, MechanicsDerivatives, arriving_momentum, initial_momentum,
};

/// Settings of a simulation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimulationOptions {
    /// Discrete mechanics.
    pub integrator: Integrator,
    /// Time step h (the problem's time unit).
    pub h: f64,
    /// Number of steps N (knots 0..N).
    pub steps: usize,
    /// The per-step solver's settings.
    pub step: StepOptions,
}

/// Why a simulation stopped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimulationError {
    /// A step's contact problem was not solved.
    #[error("step {step} (t = {time}): {source}")]
    Step {
        /// Step index (0 = from the initial state).
        step: usize,
        /// Time at the start of the step.
        time: f64,
        /// What went wrong.
        source: StepFailure,
    },
    /// The input policy returned the wrong number of inputs.
    #[error("step {step}: {found} inputs given, the robot has {expected}")]
    InputLength {
        /// Step index.
        step: usize,
        /// Inputs the robot has.
        expected: usize,
        /// Inputs given.
        found: usize,
    },
    /// The state left every plausible motion behind ([`StepOptions::max_speed`]).
    #[error(
        "step {step} (t = {time}): the simulation diverged: `{coordinate}` moves at {speed:e} \
         per time unit (bound {bound:e}); lower the PD gains, raise the rate, or use \
         `--feedback implicit`"
    )]
    Diverged {
        /// Step index.
        step: usize,
        /// Time at the start of the step.
        time: f64,
        /// The fastest coordinate.
        coordinate: String,
        /// Its speed (NaN when not finite).
        speed: f64,
        /// The bound.
        bound: f64,
    },
    /// The input policy's end-state feedback names an input or coordinate the robot lacks.
    #[error("step {step}: feedback on an input or coordinate the robot does not have")]
    FeedbackIndex {
        /// Step index.
        step: usize,
    },
}

/// A simulated trajectory with the per-step record of the contact solver.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Simulation {
    /// Knot times t_k = k·h (N + 1).
    pub times: Vec<f64>,
    /// Configurations (N + 1 × n).
    pub q: Vec<Vec<f64>>,
    /// Velocities: v_0, then the backward differences (q_k − q_{k−1})/h (N + 1 × n).
    pub v: Vec<Vec<f64>>,
    /// Inputs per interval (N × m).
    pub u: Vec<Vec<f64>>,
    /// Impulses per interval (N).
    pub impulses: Vec<Impulses>,
    /// Signed distance per contact at every knot (N + 1 × nc): the impulses of step k are
    /// complementary to the distance at knot k + 1.
    pub distance: Vec<Vec<f64>>,
    /// World position of each contact point at every knot (N + 1 × nc; a sphere's lowest
    /// point), the plan's `<contact>_x`, `_y`, `_z` columns. Empty in a record written before
    /// it was kept.
    #[serde(default)]
    pub contact_positions: Vec<Vec<[f64; 3]>>,
    /// Newton iterations per step (N).
    pub iterations: Vec<usize>,
    /// The NLP's complementarity products per step (N; see [`super::StepOutcome`]).
    pub complementarity: Vec<f64>,
    /// Max-norm of the discrete equations per step (N, impulse units).
    pub dynamics_residual: Vec<f64>,
    /// Max-norm of each step's whole system (N, impulse units; see
    /// [`super::StepOutcome::residual`]).
    pub residual: Vec<f64>,
    /// Steps accepted at the acceptable tolerance (their residual above the tolerance).
    pub relaxed_steps: Vec<usize>,
}

impl Simulation {
    /// The deepest penetration max(0, −φ) over every contact and knot (length units).
    pub fn max_penetration(&self) -> f64 {
        self.distance
            .iter()
            .flatten()
            .fold(0.0_f64, |a, &d| a.max(-d))
    }
}

/// Every contact point's world position at `q`.
fn contact_positions<M: Mechanics>(mech: &M, q: &[f64]) -> Vec<[f64; 3]> {
    (0..mech.num_contacts())
        .map(|i| mech.contact_position(i, q))
        .collect()
}

/// Simulates from q_0 = `q0` with velocity v_0 = `v0`. `input(k, t_k, q_k, v_k)` gives u_k,
/// held over [t_k, t_{k+1}] (v_k as in [`Simulation::v`]), either as a vector or as a
/// [`StepInput`] whose feedback on q_{k+1} is solved with the step; `progress(k)` is called
/// after each step.
pub fn simulate<M: MechanicsDerivatives, U: Into<StepInput>>(
    mech: &M,
    contact: &ContactModel,
    q0: &[f64],
    v0: &[f64],
    options: &SimulationOptions,
    input: impl FnMut(usize, f64, &[f64], &[f64]) -> U,
    mut progress: impl FnMut(usize),
) -> Result<Simulation, SimulationError> {
    simulate_until(mech, contact, q0, v0, options, input, |k| {
        progress(k);
        ControlFlow::Continue(())
    })
}

/// [`simulate`] that stops early, keeping the steps made, when `progress(k)` (called after
/// each step) breaks: a stop request ends a simulation with what it has simulated.
pub fn simulate_until<M: MechanicsDerivatives, U: Into<StepInput>>(
    mech: &M,
    contact: &ContactModel,
    q0: &[f64],
    v0: &[f64],
    options: &SimulationOptions,
    mut input: impl FnMut(usize, f64, &[f64], &[f64]) -> U,
    mut progress: impl FnMut(usize) -> ControlFlow<()>,
) -> Result<Simulation, SimulationError> {
    let (n, m, h) = (mech.nq(), mech.nu(), options.h);
    let mut sim = Simulation {
        times: vec![0.0],
        q: vec![q0.to_vec()],
        v: vec![v0.to_vec()],
        distance: vec![
            (0..mech.num_contacts())
                .map(|i| crate::contact::distance_with_gradient(mech, contact, i, q0).0)
                .collect(),
        ],
        contact_positions: vec![contact_positions(mech, q0)],
        ..Simulation::default()
    };
    let mut warm = Impulses::zeros(mech, contact);
    for k in 0..options.steps {
        let t = k as f64 * h;
        let u: StepInput = input(k, t, &sim.q[k], &sim.v[k]).into();
        let misplaced = u.feedback.iter().any(|g| g.input >= m || g.coordinate >= n);
        if u.held.len() != m {
            return Err(SimulationError::InputLength {
                step: k,
                expected: m,
                found: u.held.len(),
            });
        }
        if misplaced {
            return Err(SimulationError::FeedbackIndex { step: k });
        }
        let before = match (options.integrator, k) {
            (Integrator::Midpoint | Integrator::Galerkin4 | Integrator::Galerkin6, 0) => {
                let mut p = vec![0.0; n];
                initial_momentum(mech, &[q0, v0].concat(), &mut p);
                Before::Momentum(p)
            }
            (Integrator::Midpoint | Integrator::Galerkin4 | Integrator::Galerkin6, _) => {
                let rule = options.integrator.galerkin_rule();
                let p = arriving_momentum(
                    mech,
                    rule.as_ref(),
                    &sim.q[k - 1],
                    &sim.q[k],
                    &sim.u[k - 1],
                    h,
                )
                .map_err(|e| SimulationError::Step {
                    step: k,
                    time: t,
                    source: StepFailure::Interval(e),
                })?;
                Before::Momentum(p)
            }
            (Integrator::Euler, 0) => Before::Euler {
                before: v0,
                first_step: true,
                h_prev: h,
            },
            (Integrator::Euler, _) => Before::Euler {
                before: &sim.q[k - 1],
                first_step: false,
                h_prev: h,
            },
        };
        let q_curr = &sim.q[k];
        let guess: Vec<f64> = q_curr
            .iter()
            .zip(&sim.v[k])
            .map(|(q, v)| q + h * v)
            .collect();
        let step = ContactStep {
            mech,
            contact,
            integrator: options.integrator,
            before,
            q_curr,
            u: &u,
            h,
        };
        let outcome =
            step.solve(&guess, &warm, &options.step)
                .map_err(|source| SimulationError::Step {
                    step: k,
                    time: t,
                    source,
                })?;
        let v_next: Vec<f64> = q_curr
            .iter()
            .zip(&outcome.q_next)
            .map(|(a, b)| (b - a) / h)
            .collect();
        let bound = options.step.max_speed;
        if let Some((i, speed)) = v_next
            .iter()
            .map(|v| v.abs())
            .enumerate()
            .find(|(_, v)| v.is_nan() || *v > bound)
        {
            return Err(SimulationError::Diverged {
                step: k,
                time: t,
                coordinate: mech
                    .coordinate_names()
                    .get(i)
                    .cloned()
                    .unwrap_or_else(|| format!("coordinate {i}")),
                speed,
                bound,
            });
        }
        sim.times
            .push(crate::files::trajectory_csv::knot_time(k + 1, h));
        sim.contact_positions
            .push(contact_positions(mech, &outcome.q_next));
        sim.q.push(outcome.q_next);
        sim.v.push(v_next);
        sim.u.push(outcome.input.clone());
        warm = outcome.impulses.clone();
        sim.impulses.push(outcome.impulses);
        sim.distance.push(outcome.distance);
        sim.iterations.push(outcome.iterations);
        sim.complementarity.push(outcome.complementarity);
        sim.dynamics_residual.push(outcome.dynamics_residual);
        sim.residual.push(outcome.residual);
        if outcome.residual > outcome.tolerance {
            sim.relaxed_steps.push(k);
        }
        if progress(k).is_break() {
            break;
        }
    }
    Ok(sim)
}

/// Total energy T + V at each knot of a run without inputs, for mechanics whose Lagrangian
/// is T − V with T quadratic in v: E = vᵀ(M v) − L(q, v), L(q, v) = Ld(q − hv/2, q + hv/2, h)/h.
/// The knot velocity is the integrator's own: midpoint and Galerkin, v_k = M(q_k)⁻¹ p_k⁻ from
/// the discrete Legendre transform (v_0 at the first knot); Euler, (q_k − q_{k−1})/h.
pub fn knot_energies<M: MechanicsDerivatives>(
    mech: &M,
    sim: &Simulation,
    integrator: Integrator,
    h: f64,
) -> Vec<f64> {
    let n = mech.nq();
    (0..sim.q.len())
        .map(|k| {
            let q = &sim.q[k];
            let v = match (integrator, k) {
                (_, 0) | (Integrator::Euler, _) => sim.v[k].clone(),
                (Integrator::Midpoint | Integrator::Galerkin4 | Integrator::Galerkin6, _) => {
                    let u = &sim.u[k - 1];
                    let rule = integrator.galerkin_rule();
                    let p = arriving_momentum(mech, rule.as_ref(), &sim.q[k - 1], q, u, h);
                    let mass = mass_matrix(mech, q);
                    p.ok()
                        .and_then(|p| mass.lu().solve(&DVector::from_vec(p)))
                        .map_or_else(|| vec![f64::NAN; n], |v| v.as_slice().to_vec())
                }
            };
            energy(mech, q, &v, h)
        })
        .collect()
}

/// M(q) from the momentum map, column by column.
fn mass_matrix<M: MechanicsDerivatives>(mech: &M, q: &[f64]) -> DMatrix<f64> {
    let n = mech.nq();
    let mut mass = DMatrix::zeros(n, n);
    let mut column = vec![0.0; n];
    for j in 0..n {
        let mut unit = vec![0.0; n];
        unit[j] = 1.0;
        mech.momentum(q, &unit, &mut column);
        mass.column_mut(j).copy_from_slice(&column);
    }
    mass
}

/// T + V at (q, v) from the momentum and the discrete Lagrangian (see [`knot_energies`]).
fn energy<M: MechanicsDerivatives>(mech: &M, q: &[f64], v: &[f64], h: f64) -> f64 {
    let n = mech.nq();
    let mut p = vec![0.0; n];
    mech.momentum(q, v, &mut p);
    let twice_kinetic: f64 = p.iter().zip(v).map(|(a, b)| a * b).sum();
    let qa: Vec<f64> = q.iter().zip(v).map(|(q, v)| q - 0.5 * h * v).collect();
    let qb: Vec<f64> = q.iter().zip(v).map(|(q, v)| q + 0.5 * h * v).collect();
    let lagrangian = mech.discrete_lagrangian(&qa, &qb, h) / h;
    twice_kinetic - lagrangian
}
