//! The steps `vito check`, `vito solve` and `vito bench` run on a loaded problem, in one place
//! so that what `check` reports is what `solve` builds: Ipopt's verdict on the problem's
//! options, the robot's mechanics, the solver's NLP and its size, the solve itself.

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use crate::discrete::Mechanics;
use crate::ipopt;
use crate::problem::{InitialGuess, LoadedProblem, ProblemError, ProblemSpec};
use crate::transcription::{
    self, BenchRow, MechanicsDerivatives, ModelMechanics, Solution, SolveOptions, Transcription,
    TranscriptionError,
};

/// The robot of `spec` as the transcription sees it (URDF model, gravity, contacts).
pub fn mechanics(spec: &ProblemSpec) -> Result<ModelMechanics, TranscriptionError> {
    ModelMechanics::load(spec)
}

/// The solver's NLP for `spec`, built as [`solve`] builds it, but for a simulated initial
/// guess, which only [`solve`] and [`bench`] run (it holds q_1 here).
pub fn build_nlp(spec: &ProblemSpec) -> Result<Transcription<ModelMechanics>, TranscriptionError> {
    Transcription::new(mechanics(spec)?, spec)
}

/// Solves `spec` with the robot from its URDF.
pub fn solve(spec: &ProblemSpec, options: &SolveOptions) -> Result<Solution, TranscriptionError> {
    let mech = mechanics(spec)?;
    let spec = resolve_initial_guess(&mech, spec)?;
    transcription::solve_with(mech, &spec, options)
}

/// `spec` with a simulated initial guess run into the warm start it stands for
/// ([`crate::simulated_guess`]); every other guess as it is.
pub fn resolve_initial_guess<'a>(
    mech: &ModelMechanics,
    spec: &'a ProblemSpec,
) -> Result<Cow<'a, ProblemSpec>, TranscriptionError> {
    let InitialGuess::Simulation(guess) = &spec.initial_guess else {
        return Ok(Cow::Borrowed(spec));
    };
    let start = crate::simulated_guess::simulate_guess(mech, spec, guess).map_err(|e| {
        TranscriptionError::Invalid {
            field: "initial_guess.simulation".into(),
            message: format!("the simulation of the initial guess failed: {e}"),
        }
    })?;
    let mut resolved = spec.clone();
    resolved.initial_guess = InitialGuess::WarmStart(start.warm_start);
    Ok(Cow::Owned(resolved))
}

/// The reference problems of SPEC.md, as `vito bench` runs them by default.
pub const REFERENCE_PROBLEMS: [&str; 4] = [
    "problems/hopper_2d.toml",
    "problems/brick_3d.toml",
    "problems/spring_flamingo_walk.toml",
    "problems/littledog_step.toml",
];

/// Benchmarks `spec` (sizes, one derivative evaluation, a full solve) with the robot from its
/// URDF.
pub fn bench(spec: &ProblemSpec) -> Result<BenchRow, TranscriptionError> {
    let mech = mechanics(spec)?;
    let spec = resolve_initial_guess(&mech, spec)?;
    transcription::bench_with(mech, &spec)
}

/// Asks Ipopt whether it takes every option of the problem (name, type, range), so that a
/// typo in `[solver.ipopt]` is an input error naming its line, before any solve.
pub fn check_solver_options(problem: &LoadedProblem) -> Result<(), ProblemError> {
    for (name, value) in &problem.spec.solver_options {
        let value = ipopt::OptionValue::from(value);
        ipopt::Solver::new()
            .set_option(name, value)
            .map_err(|e| problem.field_error(&format!("solver.ipopt.{name}"), e.to_string()))?;
    }
    Ok(())
}

/// Where `vito solve` writes: `--out` if given, else the file's `output.dir`, else
/// `out/<problem name>`.
pub fn output_dir(problem: &LoadedProblem, out: Option<&Path>) -> PathBuf {
    match (out, &problem.output_dir) {
        (Some(o), _) => o.to_owned(),
        (None, Some(d)) => d.clone(),
        (None, None) => PathBuf::from("out").join(&problem.spec.name),
    }
}

/// [`output_dir`] checked before any solving against the rule of
/// [`crate::report::OutputTarget`]: only vito's own results or an empty directory are
/// replaced, and never the current directory or one holding the problem file or its robot.
pub fn checked_output_dir(
    problem: &LoadedProblem,
    out: Option<&Path>,
) -> Result<crate::report::OutputTarget, crate::report::OutputDirError> {
    let target = output_dir(problem, out);
    crate::report::OutputTarget::check(&target, &[&problem.file, &problem.spec.robot.urdf])
}

/// The NLP point a trajectory CSV (as `vito solve` writes it, with one row per knot of this
/// problem) describes: q, h from the times, u, the normal and friction impulses and the
/// slacks from their columns where present; ψ, η and anything absent keep the NLP's initial
/// guess. The message names the column or the row count at fault.
pub fn point_from_trajectory<M: MechanicsDerivatives>(
    nlp: &Transcription<M>,
    robot: &crate::problem::RobotInfo,
    contacts: &[String],
    text: &str,
) -> Result<Vec<f64>, String> {
    use crate::trajectory_csv::{friction_direction_names, read_csv, read_trajectory};
    let l = nlp.layout();
    let recorded = read_trajectory(text, &robot.coordinates, &robot.inputs)?;
    if recorded.times.len() != l.knots {
        return Err(format!(
            "it has {} rows, the problem has {} knots (run the problem with `--set knots={}`, or solve it first)",
            recorded.times.len(),
            l.knots,
            recorded.times.len()
        ));
    }
    let table = read_csv(text)?;
    let mut x = nlp.initial_point().to_vec();
    for (k, q) in recorded.q.iter().enumerate() {
        for (i, v) in l.q(k).zip(q) {
            x[i] = *v;
        }
    }
    let (lower, upper) = nlp.variable_bounds();
    for j in 0..l.intervals() {
        let h = recorded.times[j + 1] - recorded.times[j];
        // The problem's step bounds, with the round-off of times written as decimals.
        let slack = 1e-9 * upper[l.h(j)].abs().max(1.0);
        if !(lower[l.h(j)] - slack..=upper[l.h(j)] + slack).contains(&h) {
            return Err(format!(
                "rows {} and {} are {h} apart in time, outside the problem's step [{}, {}]",
                j + 2,
                j + 3,
                lower[l.h(j)],
                upper[l.h(j)]
            ));
        }
        x[l.h(j)] = h;
        if let Some(u) = recorded.u.get(j) {
            for (i, v) in l.u(j).zip(u) {
                x[i] = *v;
            }
        }
    }
    let set = |x: &mut Vec<f64>, column: &str, index: &dyn Fn(usize) -> usize| {
        if let Some(values) = table.column(column) {
            for (j, v) in values.iter().take(l.intervals()).enumerate() {
                if v.is_finite() {
                    x[index(j)] = *v;
                }
            }
        }
    };
    let directions = friction_direction_names(l.nd);
    for (i, name) in contacts.iter().enumerate() {
        set(&mut x, &format!("{name}_normal"), &|j| l.c(j, i));
        for (d, dir) in directions.iter().enumerate() {
            set(&mut x, &format!("{name}_friction_{dir}"), &|j| {
                l.beta(j, i).start + d
            });
        }
    }
    set(&mut x, "slack", &|j| l.slack(j).start);
    for s in 0..l.slacks_per_interval() {
        set(&mut x, &format!("slack_{s}"), &|j| l.slack(j).start + s);
    }
    Ok(x)
}

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
            .map(|x| crate::input::checked_span(field, x).map_err(|m| invalid(field, m)))
            .transpose()
    };
    let duration = positive("--duration", request.duration)?;
    let rate = positive("--rate", request.rate)?;
    let problem_h = spec.time_steps.guess_step(spec.knots);
    let h = rate.map_or(problem_h, |r| 1.0 / r);
    let robot = &problem.robot;
    let read = |path: &Path| -> Result<_, TranscriptionError> {
        let text =
            crate::input::read_regular_text(path, crate::input::MAX_TEXT_BYTES).map_err(|e| {
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

/// The recording a trajectory CSV's text holds for `vito simulate --inputs`/`--track`: as
/// [`crate::trajectory_csv::read_trajectory`] reads it, with a column for every input
/// (replayed or fed forward, the inputs are the file's); the message says what is wrong (the
/// caller names the file).
pub fn recorded_inputs(
    text: &str,
    robot: &crate::problem::RobotInfo,
) -> Result<crate::trajectory_csv::RecordedTrajectory, String> {
    let r = crate::trajectory_csv::read_trajectory(text, &robot.coordinates, &robot.inputs)?;
    if r.u.is_empty() && !robot.inputs.is_empty() {
        return Err(format!(
            "it has no column for every input (u_<name> for {})",
            crate::names::list_names(&robot.inputs, 12)
        ));
    }
    Ok(r)
}

/// The gains `base` (the problem file's `[tracking] gains`) with `NAME=KP,KD` per input
/// (`all=KP,KD` for every input) from the command line on top; later entries win.
pub fn parse_gains(
    base: &[crate::problem::TrackingGain],
    gains: &[String],
    robot: &crate::problem::RobotInfo,
) -> Result<Vec<crate::sim::Gain>, TranscriptionError> {
    use crate::problem::tracking::{GainError, gains_for, merge_gains};
    let invalid = |message: String| TranscriptionError::Invalid {
        field: "--gains".into(),
        message,
    };
    let mut out = base.to_vec();
    for text in gains {
        let parsed = text.split_once('=').and_then(|(name, values)| {
            let (kp, kd) = values.split_once(',')?;
            Some((
                name.trim(),
                kp.trim().parse::<f64>().ok()?,
                kd.trim().parse::<f64>().ok()?,
            ))
        });
        let Some((name, kp, kd)) = parsed else {
            return Err(invalid(format!(
                "`{text}`: write NAME=KP,KD, e.g. knee=50,2"
            )));
        };
        let resolved = gains_for(robot, name, kp, kd).map_err(|e| match e {
            GainError::Value => invalid(format!("`{text}`: gains must be finite and ≥ 0")),
            GainError::UnknownInput => invalid(format!(
                "`{name}` is not an input of the robot (inputs: {})",
                crate::names::list_names(&robot.inputs, 24)
            )),
            GainError::NoCoordinate(input) => invalid(format!(
                "input `{input}` acts on no coordinate of that name"
            )),
        })?;
        merge_gains(&mut out, &resolved);
    }
    Ok(out)
}

/// Runs a prepared simulation; `progress(k)` after each step.
pub fn run_simulation(
    prepared: &PreparedSimulation,
    progress: impl FnMut(usize),
) -> Result<crate::sim::Simulation, crate::sim::SimulationError> {
    let p = prepared;
    let (m, h) = (p.mech.nu(), p.options.h);
    crate::sim::simulate(
        &p.mech,
        &p.contact,
        &p.q0,
        &p.v0,
        &p.options,
        |_, t, q, v| p.source.step_input(m, t, h, q, v),
        progress,
    )
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

/// One contact's distance to the terrain at the first and last knot of the initial guess
/// (length units; negative below the terrain).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactClearance {
    /// The contact's name.
    pub name: String,
    /// φ at the first knot (the initial pose).
    pub first: f64,
    /// φ at the last knot of the initial guess.
    pub last: f64,
}

/// What `vito check` shows about whether a problem can be solved, before solving it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Feasibility {
    /// Per contact, its distance to the terrain at the first and last knot.
    pub clearances: Vec<ContactClearance>,
    /// Plain-language warnings (a contact below the terrain, a floating robot with no
    /// contacts or no inputs, a pitch near ±π/2).
    pub warnings: Vec<String>,
}

/// How far below the terrain (length units) a contact may start before `check` warns: more
/// than round-off of a pose placed on it.
const BELOW_TERRAIN: f64 = 1e-9;

/// How close to ±π/2 a floating base's pitch may come before `check` warns (rad): the
/// roll–pitch–yaw angles are singular there.
const PITCH_MARGIN: f64 = 0.2;

/// The feasibility report of a built NLP: clearances from its initial guess, warnings from
/// its bounds and the problem.
pub fn feasibility<M: MechanicsDerivatives>(
    spec: &ProblemSpec,
    nlp: &Transcription<M>,
) -> Feasibility {
    let layout = nlp.layout();
    let x = nlp.initial_point();
    let mech = nlp.mechanics();
    let terrain = &nlp.context().contact.terrain;
    let last = layout.knots - 1;
    let distance = |i: usize, k: usize| {
        crate::contact::signed_distance(terrain, &mech.contact_position(i, &x[layout.q(k)]))
    };
    let mut report = Feasibility::default();
    for (i, contact) in spec.contacts.iter().enumerate() {
        let clearance = ContactClearance {
            name: contact.name.clone(),
            first: distance(i, 0),
            last: distance(i, last),
        };
        // Below round-off of a pose placed exactly on the terrain.
        if clearance.first < -BELOW_TERRAIN {
            report.warnings.push(format!(
                "contact `{}` starts {:.3e} below the terrain (at the first knot): the \
                 problem is infeasible unless the slack absorbs it; raise the base in \
                 [initial] q",
                contact.name, -clearance.first
            ));
        }
        report.clearances.push(clearance);
    }
    let base = spec.robot.base;
    if base != crate::model::BaseType::Fixed {
        if spec.contacts.is_empty() {
            report.warnings.push(
                "the robot has a free base but no contacts: nothing holds it up, it falls; \
                 add [contacts] (from_urdf or [[contacts.point]])"
                    .into(),
            );
        }
        if layout.m == 0 {
            report.warnings.push(
                "the robot has a free base but no inputs: it can only fall or tumble; \
                 see [inputs] actuated"
                    .into(),
            );
        }
    }
    if base == crate::model::BaseType::Floating
        && let Some(pitch) = mech
            .coordinate_names()
            .iter()
            .position(|n| n == "base_pitch")
    {
        let near = |v: f64| v.is_finite() && v.abs() >= std::f64::consts::FRAC_PI_2 - PITCH_MARGIN;
        let (lower, upper) = nlp.variable_bounds();
        let bounded = (0..layout.knots)
            .map(|k| layout.q(k).start + pitch)
            // A fixed coordinate (lower = upper) is a pose, reported below.
            .find(|&j| lower[j] < upper[j] && (near(lower[j]) || near(upper[j])));
        if let Some(j) = bounded {
            report.warnings.push(format!(
                "a bound on base_pitch ([{}, {}]) comes within {PITCH_MARGIN} rad of ±π/2, \
                 where roll–pitch–yaw angles are singular; bound |base_pitch| further from π/2",
                lower[j], upper[j]
            ));
        }
        if let Some(k) = (0..layout.knots).find(|&k| near(x[layout.q(k).start + pitch])) {
            report.warnings.push(format!(
                "the initial guess's base_pitch {} at knot {} is within {PITCH_MARGIN} rad of \
                 ±π/2, where roll–pitch–yaw angles are singular",
                x[layout.q(k).start + pitch],
                k + 1
            ));
        }
    }
    report
}
