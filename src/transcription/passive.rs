//! A passive problem poses a simulation. With no inputs, fixed steps, and q_1 and v_0 given,
//! the NLP's points at zero slack are the motions its integrator steps to from that state
//! under its own contact model: the answer is what `vito simulate` computes, at any N. The
//! solve therefore starts there: it simulates the problem with its own integrator and step,
//! makes the NLP point of that motion (impulses, sliding speeds and their duals included),
//! and solves the NLP with the contact modes of the simulation fixed (a regular NLP, from a
//! point that satisfies it to the simulation's tolerance). Solved, that is the plan; else the
//! usual solve follows from the problem's own guess, and the attempt is recorded.
//!
//! The interior-point relaxation cannot find such a motion itself at fine grids: every
//! complementarity pair of a simulation holds exactly, so its solution has no interior.

use super::solve::{SolveOptions, set_unless_given, solve_modes_fixed};
use super::{MechanicsDerivatives, Solution, Transcription, TranscriptionError};
use crate::ipopt::OptionValue;
use crate::problem::{ProblemSpec, TimeSteps};
use crate::sim::{Simulation, SimulationOptions, StepOptions, simulate};

/// The solve of a passive problem from its simulation, as `summary.json` records it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SimulationStart {
    /// Simulation steps (the problem's intervals).
    pub steps: usize,
    /// Wall time of the simulation [s].
    pub simulation_time_s: f64,
    /// The largest residual of a simulation step's equations (impulse units).
    pub simulation_residual: f64,
    /// The verdict of the NLP solved from it with the simulation's contact modes fixed.
    pub verdict: super::SolveVerdict,
    /// Its Ipopt iterations (also counted in the solution's).
    pub iterations: usize,
    /// The largest |q_k − q_k(simulation)| over knots and coordinates of its plan.
    pub max_q_difference: f64,
    /// Whether its plan is the solution (solved); if not, the usual solve followed.
    pub kept: bool,
}

/// Whether `spec` poses a simulation that the transcription `t` can start from: no inputs,
/// fixed steps, every coordinate of q_1 and v_0 given, contacts, and one point per knot
/// (the midpoint rule or Euler; no closed loops).
pub fn is_passive<M: MechanicsDerivatives>(t: &Transcription<M>, spec: &ProblemSpec) -> bool {
    let l = t.layout();
    l.m == 0
        && l.nc > 0
        && l.nl == 0
        && l.interior == 0
        && spec.mode_block <= 1
        && matches!(spec.time_steps, TimeSteps::Fixed(_))
        && spec.v_initial.is_some()
        && !spec.q_initial_free.iter().any(|&free| free)
}

/// The steps' relative residual tolerance, that of `vito simulate`.
const SIMULATION_TOLERANCE: f64 = 1e-10;

/// Solves a passive problem from its simulation (module docs); `None` when `spec` is not
/// passive, the simulation fails, or a stop was requested. The solution carries its
/// [`SimulationStart`] either way; the caller keeps it only if it is solved.
pub(super) fn solve_from_simulation<M: MechanicsDerivatives>(
    t: &mut Transcription<M>,
    spec: &ProblemSpec,
    options: &SolveOptions,
) -> Result<Option<Solution>, TranscriptionError> {
    if !is_passive(t, spec) || options.stopped() {
        return Ok(None);
    }
    let started = std::time::Instant::now();
    let Some(sim) = simulation(t, spec) else {
        return Ok(None);
    };
    let simulation_time_s = started.elapsed().as_secs_f64();
    let x = point(t, &sim);
    let (report, _) = solve_modes_fixed(t, spec, options, &x, |solver, _| {
        // The point satisfies the rows already: stay near it.
        set_unless_given(
            solver,
            spec,
            options,
            vec![
                ("bound_push", OptionValue::Num(1e-8)),
                ("bound_frac", OptionValue::Num(1e-8)),
                ("slack_bound_push", OptionValue::Num(1e-8)),
                ("slack_bound_frac", OptionValue::Num(1e-8)),
                ("mu_init", OptionValue::Num(1e-8)),
            ],
        )
    })?;
    let mut solution = Solution::read_off(t, spec, &report);
    let max_q_difference = solution
        .q
        .iter()
        .zip(&sim.q)
        .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
        .fold(0.0, f64::max);
    solution.simulation_start = Some(SimulationStart {
        steps: sim.u.len(),
        simulation_time_s,
        simulation_residual: sim.residual.iter().copied().fold(0.0, f64::max),
        verdict: solution.verdict(),
        iterations: solution.iterations,
        max_q_difference,
        kept: solution.verdict().is_solved(),
    });
    solution.wall_time_s += simulation_time_s;
    Ok(Some(solution))
}

/// The problem's motion from q_1 and v_0 with its integrator, step and contact model; `None`
/// when a step fails (the usual solve then decides).
fn simulation<M: MechanicsDerivatives>(
    t: &Transcription<M>,
    spec: &ProblemSpec,
) -> Option<Simulation> {
    let TimeSteps::Fixed(h) = spec.time_steps else {
        return None;
    };
    let mech = t.mechanics();
    let gravity = spec.robot.gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
    let options = SimulationOptions {
        integrator: spec.integrator,
        h,
        steps: t.layout().intervals(),
        step: StepOptions {
            gravity,
            relative_tolerance: SIMULATION_TOLERANCE,
            ..StepOptions::default()
        },
    };
    let v0 = spec.v_initial.as_ref()?;
    let contact = spec.contact_model(mech);
    simulate(
        mech,
        &contact,
        &spec.q_initial,
        v0,
        &options,
        |_, _, _, _| Vec::<f64>::new(),
        |_| {},
    )
    .ok()
}

/// The NLP point of `sim`: q, v_0, h and the impulses as simulated, ψ and η from the
/// tangential rows (they are linear in both), the slacks at zero.
fn point<M: MechanicsDerivatives>(t: &Transcription<M>, sim: &Simulation) -> Vec<f64> {
    let l = t.layout();
    let mut x = t.initial_point().to_vec();
    for (k, q) in sim.q.iter().enumerate().take(l.knots) {
        x[l.q(k)].copy_from_slice(q);
    }
    x[l.v0()].copy_from_slice(&sim.v[0]);
    for (j, impulses) in sim.impulses.iter().enumerate().take(l.intervals()) {
        x[l.h(j)] = sim.times[j + 1] - sim.times[j];
        for i in 0..l.nc {
            x[l.c(j, i)] = impulses.normal[i];
            x[l.beta(j, i)].copy_from_slice(&impulses.friction[i]);
            x[l.psi(j, i)] = impulses.slip[i];
        }
    }
    for s in l.slacks() {
        x[s] = 0.0;
    }
    // Off the ground the simulation's ψ is 0, which leaves η negative in the directions
    // the point moves away from: ψ (free there, as c = 0 and β = 0) is raised.
    super::start::sliding_from_rows(t, &mut x);
    x
}
