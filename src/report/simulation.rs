//! A simulation's outputs: its trajectory in the solve's file format (the slack column holds
//! each step's largest complementarity product, the slack the NLP would need for it) and its
//! summary.

use serde_json::{Value, json};

use crate::contact::{ContactModel, interval_world_impulses};
use crate::discrete::Integrator;
use crate::files::trajectory_csv::Trajectory;
use crate::problem::LoadedProblem;
use crate::sim::Simulation;

/// The owned columns of a simulation's trajectory file.
#[derive(Debug, Clone)]
pub struct SimulationColumns {
    coordinate_names: Vec<String>,
    input_names: Vec<String>,
    contact_names: Vec<String>,
    friction_directions: usize,
    normal: Vec<Vec<f64>>,
    friction: Vec<Vec<Vec<f64>>>,
    world_impulse: Vec<Vec<[f64; 3]>>,
    slack: Vec<Vec<f64>>,
}

impl SimulationColumns {
    /// The names from `problem` and the impulses of `sim`.
    pub fn new(problem: &LoadedProblem, sim: &Simulation, friction_directions: usize) -> Self {
        let normal: Vec<Vec<f64>> = sim.impulses.iter().map(|i| i.normal.clone()).collect();
        let friction: Vec<Vec<Vec<f64>>> =
            sim.impulses.iter().map(|i| i.friction.clone()).collect();
        let model = ContactModel::new(
            problem.robot.moves_in_xz_plane,
            problem.spec.contacts.iter().map(|c| c.friction).collect(),
            problem.spec.terrain.clone(),
        );
        let world_impulse =
            interval_world_impulses(&model, &sim.contact_positions, &normal, &friction);
        SimulationColumns {
            world_impulse,
            coordinate_names: problem.robot.coordinates.clone(),
            input_names: problem.robot.inputs.clone(),
            contact_names: problem
                .spec
                .contacts
                .iter()
                .map(|c| c.name.clone())
                .collect(),
            friction_directions,
            normal,
            friction,
            slack: sim.complementarity.iter().map(|&c| vec![c]).collect(),
        }
    }

    /// The trajectory file's view of `sim`.
    pub fn trajectory<'a>(&'a self, sim: &'a Simulation) -> Trajectory<'a> {
        Trajectory {
            times: &sim.times,
            coordinate_names: &self.coordinate_names,
            q: &sim.q,
            v: &sim.v,
            input_names: &self.input_names,
            u: &sim.u,
            contact_names: &self.contact_names,
            friction_directions: self.friction_directions,
            normal_impulse: &self.normal,
            friction_impulse: &self.friction,
            world_impulse: &self.world_impulse,
            signed_distance: &sim.distance,
            contact_positions: &sim.contact_positions,
            slack: &self.slack,
        }
    }
}

/// What `summary.json` of `vito simulate` holds. `energy` is the knot energies of a run
/// without inputs and without contact impulses (None otherwise: energy drift applies only to
/// a conservative run).
pub fn simulation_summary_json(
    problem: &LoadedProblem,
    sim: &Simulation,
    integrator: Integrator,
    energy: Option<&[f64]>,
    wall_time_s: f64,
) -> Value {
    let steps = sim.iterations.len();
    let max = |v: &[f64]| v.iter().cloned().fold(0.0_f64, f64::max);
    let total_iterations: usize = sim.iterations.iter().sum();
    let drift = energy.map(|e| {
        let e0 = e.first().copied().unwrap_or(0.0);
        json!({
            "initial": e0,
            "max_abs_change": e.iter().fold(0.0_f64, |a, x| a.max((x - e0).abs())),
            "final_change": e.last().copied().unwrap_or(e0) - e0,
        })
    });
    json!({
        "kind": "simulation",
        "problem": problem.spec.name,
        "problem_file": problem.file.display().to_string(),
        "problem_sha256": problem.sha256,
        "integrator": integrator.name(),
        "steps": steps,
        "time_step": sim.times.get(1).copied().unwrap_or(0.0),
        "duration": sim.times.last().copied().unwrap_or(0.0),
        "max_dynamics_residual": max(&sim.dynamics_residual),
        "max_complementarity": max(&sim.complementarity),
        "max_step_residual": max(&sim.residual),
        "relaxed_steps": {
            "count": sim.relaxed_steps.len(),
            "first": sim.relaxed_steps.iter().take(20).collect::<Vec<_>>(),
        },
        "max_penetration": sim.max_penetration(),
        "newton_iterations": {
            "total": total_iterations,
            "mean": total_iterations as f64 / steps.max(1) as f64,
            "max": sim.iterations.iter().copied().max().unwrap_or(0),
        },
        "energy": drift,
        "wall_time_s": wall_time_s,
        "wall_time_per_step_us": 1e6 * wall_time_s / steps.max(1) as f64,
        "units": {
            "length": problem.units.length,
            "time": problem.units.time,
        },
    })
}
