//! `vito simulate`'s set-up: the request checked against the problem, run, and summarised.

use std::path::{Path, PathBuf};

use super::gains::parse_gains;
use super::mechanics;
use crate::discrete::Mechanics;
use crate::problem::LoadedProblem;
use crate::transcription::{ModelMechanics, TranscriptionError};

/// What `vito simulate` was asked for, before checking.
#[derive(Debug, Clone, Default)]
pub struct SimulateRequest {
    /// A trajectory CSV whose inputs are replayed (zero-order hold).
    pub inputs: Option<PathBuf>,
    /// A trajectory CSV tracked with PD feedback (its inputs as feedforward).
    pub track: Option<PathBuf>,
    /// `NAME=KP,KD` per input (or `all=KP,KD`), for `track`.
    pub gains: Vec<String>,
    /// Where the PD reads the state (default: the file's `[tracking] feedback`).
    pub feedback: Option<crate::sim::Feedback>,
    /// Simulated time (default: the inputs' or reference's last time, else the horizon).
    pub duration: Option<f64>,
    /// Steps per time unit (default: 1/h of the problem).
    pub rate: Option<f64>,
    /// Integrator (default: the problem's).
    pub integrator: Option<crate::discrete::Integrator>,
}

/// A checked simulation: everything [`run_simulation`] needs, found valid before simulating.
#[derive(Debug)]
pub struct PreparedSimulation {
    /// The robot.
    pub mech: ModelMechanics,
    /// The contact model (the NLP's).
    pub contact: crate::contact::ContactModel,
    /// Initial configuration and velocity.
    pub q0: Vec<f64>,
    /// v_0 (the problem's, else zero).
    pub v0: Vec<f64>,
    /// Steps, step and integrator.
    pub options: crate::sim::SimulationOptions,
    /// The input policy.
    pub source: crate::sim::InputSource,
    /// Files the output directory must not hold (the problem, its robot, the CSV).
    pub inputs: Vec<PathBuf>,
}

/// Checks a simulation request against the problem: one error naming the option or file at
/// fault, before anything is simulated.
pub fn prepare_simulation(
    problem: &LoadedProblem,
    request: &SimulateRequest,
) -> Result<PreparedSimulation, TranscriptionError> {
    use crate::sim::{InputSource, SimulationOptions, StepOptions};
    let invalid = |field: &str, message: String| TranscriptionError::Invalid {
        field: field.to_owned(),
        message,
    };
    let spec = &problem.spec;
    let positive = |field: &str, value: Option<f64>| -> Result<Option<f64>, TranscriptionError> {
        value
            .map(|x| crate::files::input::checked_span(field, x).map_err(|m| invalid(field, m)))
            .transpose()
    };
    let duration = positive("--duration", request.duration)?;
    let rate = positive("--rate", request.rate)?;
    let problem_h = spec.time_steps.guess_step(spec.knots);
    let h = rate.map_or(problem_h, |r| 1.0 / r);
    let robot = &problem.robot;
    let read = |path: &Path| -> Result<_, TranscriptionError> {
        let text =
            crate::files::input::read_regular_text(path, crate::files::input::MAX_TEXT_BYTES)
                .map_err(|e| {
                    invalid(
                        "--inputs/--track",
                        format!("cannot read {}: {e}", path.display()),
                    )
                })?;
        recorded_inputs(&text, robot)
            .map_err(|m| invalid("--inputs/--track", format!("{}: {m}", path.display())))
    };
    let mut inputs: Vec<PathBuf> = vec![problem.file.clone(), spec.robot.urdf.clone()];
    let (source, recorded_end) = match (&request.inputs, &request.track) {
        (Some(_), Some(_)) => {
            return Err(invalid(
                "--inputs",
                "give --inputs or --track, not both".into(),
            ));
        }
        (Some(path), None) => {
            let r = read(path)?;
            inputs.push(path.clone());
            let end = r.times.last().copied();
            (InputSource::Replay(r), end)
        }
        (None, Some(path)) => {
            let r = read(path)?;
            inputs.push(path.clone());
            let gains = parse_gains(&problem.tracking_gains, &request.gains, robot)?;
            if gains.is_empty() {
                return Err(invalid(
                    "--gains",
                    format!(
                        "--track needs PD gains: --gains NAME=KP,KD (or all=KP,KD), or `[tracking] gains = {{ all = [KP, KD] }}` in {}",
                        problem.file.display()
                    ),
                ));
            }
            let end = r.times.last().copied();
            (
                InputSource::Track {
                    reference: r,
                    gains,
                    feedback: request.feedback.unwrap_or(problem.tracking_feedback),
                },
                end,
            )
        }
        (None, None) => {
            if !request.gains.is_empty() {
                return Err(invalid("--gains", "--gains needs --track".into()));
            }
            if request.feedback.is_some() {
                return Err(invalid("--feedback", "--feedback needs --track".into()));
            }
            (InputSource::Zero, None)
        }
    };
    let duration = duration
        .or(recorded_end)
        .unwrap_or(problem_h * (spec.knots - 1) as f64);
    let steps = (duration / h).round();
    if !(1.0..=1e8).contains(&steps) {
        return Err(invalid(
            "--duration/--rate",
            format!(
                "{duration} at a step of {h} (rate {}) gives {steps} steps; choose 1 to 10⁸",
                1.0 / h
            ),
        ));
    }
    let mech = mechanics(spec)?;
    let contact = spec.contact_model(&mech);
    let numbers = numbers_per_step(spec.q_initial.len(), robot.inputs.len(), &contact);
    let bytes = steps * numbers * BYTES_PER_NUMBER;
    let available = crate::problem::memory_available();
    if bytes > available {
        let gib = |b: f64| b / (1024.0 * 1024.0 * 1024.0);
        return Err(invalid(
            "--duration/--rate",
            format!(
                "{steps} steps of {numbers} recorded numbers would need about {:.3} GiB of \
                 memory, more than the {:.1} GiB this process may use (RAM, `ulimit -v`, \
                 cgroup): simulate a shorter time or at a lower rate",
                gib(bytes),
                gib(available)
            ),
        ));
    }
    let gravity = spec.robot.gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
    Ok(PreparedSimulation {
        q0: spec.q_initial.clone(),
        v0: spec
            .v_initial
            .clone()
            .unwrap_or_else(|| vec![0.0; spec.q_initial.len()]),
        options: SimulationOptions {
            integrator: request.integrator.unwrap_or(spec.integrator),
            h,
            steps: steps as usize,
            step: StepOptions {
                gravity,
                ..StepOptions::default()
            },
        },
        source,
        inputs,
        mech,
        contact,
    })
}

/// Memory a simulated step takes per number it records (its value in the trajectory, the
/// vectors of its knot, its text in trajectory.csv and its copies in the page and the plots):
/// about 60 bytes on the hopper (1.3 kB per step of 22 numbers at its peak), with room for the
/// address space beyond what is resident.
const BYTES_PER_NUMBER: f64 = 100.0;

/// The numbers a step records: its time, q and v, the inputs, per contact its normal and
/// friction impulses, distance and position, and the step solver's four figures.
fn numbers_per_step(
    coordinates: usize,
    inputs: usize,
    contact: &crate::contact::ContactModel,
) -> f64 {
    let contacts = contact.friction.len() as f64;
    (1 + 2 * coordinates + inputs + 4) as f64 + contacts * (5.0 + contact.nd() as f64)
}

/// Runs a prepared simulation; `progress(k)` after each step.
pub fn run_simulation(
    prepared: &PreparedSimulation,
    mut progress: impl FnMut(usize),
) -> Result<crate::sim::Simulation, crate::sim::SimulationError> {
    run_simulation_until(prepared, |k| {
        progress(k);
        std::ops::ControlFlow::Continue(())
    })
}

/// [`run_simulation`] that stops early, keeping the steps made, when `progress(k)` breaks
/// (`vito simulate` on a stop request).
pub fn run_simulation_until(
    prepared: &PreparedSimulation,
    progress: impl FnMut(usize) -> std::ops::ControlFlow<()>,
) -> Result<crate::sim::Simulation, crate::sim::SimulationError> {
    let p = prepared;
    let (m, h) = (p.mech.nu(), p.options.h);
    crate::sim::simulate_until(
        &p.mech,
        &p.contact,
        &p.q0,
        &p.v0,
        &p.options,
        |_, t, q, v| p.source.step_input(m, t, h, q, v),
        progress,
    )
}

/// A simulation run and summarised: what `vito simulate` writes and prints.
#[derive(Debug)]
pub struct SimulationRun {
    /// The trajectory and the contact solver's record.
    pub sim: crate::sim::Simulation,
    /// The knot energies of a conservative run ([`conservative_energies`]).
    pub energies: Option<Vec<f64>>,
    /// `summary.json` ([`simulation_summary`]).
    pub summary: serde_json::Value,
    /// The columns of `trajectory.csv`.
    pub columns: crate::report::SimulationColumns,
    /// Wall time of the simulation [s].
    pub wall_time_s: f64,
}

/// Runs a prepared simulation and summarises it (`vito simulate` between checking its output
/// directory and writing): `progress(k)` after each step; when it breaks, the run ends with
/// the steps made (a stop request).
pub fn simulate_prepared(
    problem: &LoadedProblem,
    prepared: &PreparedSimulation,
    progress: impl FnMut(usize) -> std::ops::ControlFlow<()>,
) -> Result<SimulationRun, crate::sim::SimulationError> {
    let start = std::time::Instant::now();
    let sim = run_simulation_until(prepared, progress)?;
    let wall_time_s = start.elapsed().as_secs_f64();
    let energies = conservative_energies(prepared, &sim);
    let summary = simulation_summary(problem, prepared, &sim, energies.as_deref(), wall_time_s);
    let columns = crate::report::SimulationColumns::new(problem, &sim, prepared.contact.nd());
    Ok(SimulationRun {
        sim,
        energies,
        summary,
        columns,
        wall_time_s,
    })
}

/// The knot energies of a conservative run (no inputs, no damping, no contact impulse),
/// for the summary's energy drift; None otherwise.
pub fn conservative_energies(
    prepared: &PreparedSimulation,
    sim: &crate::sim::Simulation,
) -> Option<Vec<f64>> {
    let touched = sim
        .impulses
        .iter()
        .any(|i| i.normal.iter().any(|&c| c > 1e-12));
    if prepared.mech.has_discrete_force() || touched {
        return None;
    }
    Some(crate::sim::knot_energies(
        &prepared.mech,
        sim,
        prepared.options.integrator,
        prepared.options.h,
    ))
}

/// `summary.json` of a simulation as `vito simulate` writes it (with the PD law that ran,
/// when it tracked a trajectory); `energies` are its [`conservative_energies`].
pub fn simulation_summary(
    problem: &LoadedProblem,
    prepared: &PreparedSimulation,
    sim: &crate::sim::Simulation,
    energies: Option<&[f64]>,
    wall_time_s: f64,
) -> serde_json::Value {
    let mut summary = crate::report::simulation_summary_json(
        problem,
        sim,
        prepared.options.integrator,
        energies,
        wall_time_s,
    );
    if let crate::sim::InputSource::Track { feedback, .. } = &prepared.source {
        // Which PD law ran: the numbers differ at stiff gains.
        summary["feedback"] = serde_json::Value::from(feedback.name());
    }
    summary
}

/// The recording a trajectory CSV's text holds for `vito simulate --inputs`/`--track`: as
/// [`crate::files::trajectory_csv::read_trajectory`] reads it, with a column for every input
/// (replayed or fed forward, the inputs are the file's); the message says what is wrong (the
/// caller names the file).
pub fn recorded_inputs(
    text: &str,
    robot: &crate::problem::RobotInfo,
) -> Result<crate::files::trajectory_csv::RecordedTrajectory, String> {
    let r = crate::files::trajectory_csv::read_trajectory(text, &robot.coordinates, &robot.inputs)?;
    if r.u.is_empty() && !robot.inputs.is_empty() {
        return Err(format!(
            "it has no column for every input (u_<name> for {})",
            crate::files::names::list_names(&robot.inputs, 12)
        ));
    }
    Ok(r)
}
