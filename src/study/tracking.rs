//! Figure 6 of the paper: plans of a problem solved at K knots over its horizon by each
//! method (first order: `integrator = "euler"`, variational: `"midpoint"`; also the Galerkin
//! members), each tracked from the plan's initial state by PD feedback on its joints (the
//! plan's inputs as feedforward) in a first-order simulation at 2 kHz (or another
//! integrator and rate). A plan's error is the RMS over the simulation's
//! knots of ‖x − x_plan(t)‖, x = (q, v) in the problem's units, q_plan linear between the
//! plan's knots and v_plan its slope (the reference the PD controller tracks).
//!
//! The plans are one gait at different accuracies, not a local optimum per K (which made the
//! errors of independent solves incomparable: BENCHMARKS.md): the variational plan at the
//! smallest K starts from the file's guess, each next K's from the previous variational plan
//! resampled to its knots, and the other methods' plans at each K from the variational plan
//! at that K.
//!
//! Each plan's record also holds its solve's cost (NLP variables, wall time) and its error at
//! its own knots: the accuracy-for-cost frontier (`super::frontier`).

use std::path::{Path, PathBuf};

use super::{StudyError, StudyMethod, StudyTable, table_order};
use crate::discrete::{Integrator, Mechanics};
use crate::files::trajectory_csv::RecordedTrajectory;
use crate::problem::{InitialGuess, Override, TimeSteps, WarmStart, load};
use crate::sim::{InputSource, Simulation, SimulationOptions, StepOptions, simulate};
use crate::transcription::{SolveOptions, SolveVerdict};

/// The header of `tracking_plans.csv`.
pub const PLANS_CSV_HEADER: &str =
    "knots,method,objective,max_slack,iterations,start,max_deviation,outcome";

/// One plan of the study.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanRecord {
    /// Knot count.
    pub knots: usize,
    /// Integrator.
    pub method: Integrator,
    /// Objective (with the slack penalty).
    pub objective: f64,
    /// Largest complementarity slack: a plan with slack above the solver's tolerance relaxes
    /// contact, and no simulation can follow it.
    pub max_slack: f64,
    /// Ipopt iterations.
    pub iterations: usize,
    /// Where the solve started: `guess` (the file's) or the plan it was warm started from,
    /// e.g. `variational K=10`.
    pub start: String,
    /// The plan as `vito solve` writes `trajectory.csv` (empty in a record read back from
    /// `tracking_plans.csv`: the trajectory is in the study's `plans/`).
    pub trajectory_csv: String,
    /// The largest deviation of any coordinate from the plan over the tracking simulation,
    /// max over steps and coordinates of |q_i − q_ref,i(t)| (problem units; None when not
    /// tracked): a body that tips over shows here as a deviation of its base's attitude
    /// beyond a few tenths of a radian.
    pub max_deviation: Option<f64>,
    /// NLP variables of the plan's solve.
    pub variables: usize,
    /// Wall time of the plan's solve (s).
    pub wall_time_s: f64,
    /// RMS over the plan's knots of ‖q_sim(t_k) − q_k‖ (problem units; None when not
    /// tracked): the configuration error where the plan states it, free of any interpolation
    /// between knots.
    pub knot_error: Option<f64>,
    /// `tracked`, or why the plan has no error row (Ipopt's status when it was not solved,
    /// `relaxed contact` when its slack exceeds the problem's `slack.tolerance`
    /// ([`SolveVerdict::RelaxedContact`]: its feet push through the ground or pull on it, and
    /// no simulation can follow it; it still warm starts the chain),
    /// the simulation's failure); the study goes on without it.
    pub outcome: String,
}

impl PlanRecord {
    /// Its line of `tracking_plans.csv` (the columns of [`PLANS_CSV_HEADER`]; the outcome
    /// quoted, `max_deviation` empty when not tracked).
    pub fn csv_cells(&self) -> String {
        format!(
            "{},{},{:.10e},{:.3e},{},{},{},\"{}\"",
            self.knots,
            self.method.study_name(),
            self.objective,
            self.max_slack,
            self.iterations,
            self.start,
            self.max_deviation
                .map_or(String::new(), |d| format!("{d:.4e}")),
            self.outcome.replace('"', "'")
        )
    }
}

/// One of the study's error tables: its file stem, its plot's title and y label.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TrackingMeasure {
    /// `<stem>.csv`, `<stem>_runs.csv`, `<stem>.svg`.
    pub stem: &'static str,
    /// What it measures, the plot's title.
    pub title: &'static str,
    /// The plot's y label.
    pub y_label: &'static str,
}

/// The study's three measures, in the order of [`TrackingResult::tables`].
pub const TRACKING_MEASURES: [TrackingMeasure; 3] = [
    TrackingMeasure {
        stem: "tracking",
        title: "RMS state error of PD tracking at 2 kHz",
        y_label: "RMS state error (q and v, problem units)",
    },
    TrackingMeasure {
        stem: "tracking_configuration",
        title: "RMS configuration error of PD tracking at 2 kHz",
        y_label: "RMS configuration error (q, problem units)",
    },
    TrackingMeasure {
        stem: "tracking_joints",
        title: "RMS state error of the PD-driven coordinates at 2 kHz",
        y_label: "RMS state error of the driven joints (problem units)",
    },
];

/// The study's result: the table and each plan's record.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackingResult {
    /// RMS state error per knot count and method.
    pub table: StudyTable,
    /// RMS configuration error (q alone) per knot count and method: free of the O(h) error
    /// of the plan's piecewise-constant velocity reference, which bounds the state error of
    /// either method from below.
    pub configuration: StudyTable,
    /// RMS state error (q and v) over the coordinates the PD controller drives (those of the
    /// inputs with gains) alone: how well the joints follow the plan, whatever an unactuated
    /// base does.
    pub joints: StudyTable,
    /// The plans, in the table's order.
    pub plans: Vec<PlanRecord>,
}

impl TrackingResult {
    /// The three tables with their measures ([`TRACKING_MEASURES`]).
    pub fn tables(&self) -> [(TrackingMeasure, &StudyTable); 3] {
        let [state, configuration, joints] = TRACKING_MEASURES;
        [
            (state, &self.table),
            (configuration, &self.configuration),
            (joints, &self.joints),
        ]
    }

    /// The plans as CSV: [`PLANS_CSV_HEADER`], a line per plan.
    pub fn plans_csv(&self) -> String {
        let mut s = String::from(PLANS_CSV_HEADER);
        s.push('\n');
        for p in &self.plans {
            s += &p.csv_cells();
            s.push('\n');
        }
        s
    }

    /// The file name of a plan's trajectory in the study's output (`plans/K10_variational.csv`).
    pub fn plan_file_name(plan: &PlanRecord) -> String {
        format!("K{}_{}.csv", plan.knots, plan.method.study_name())
    }
}

/// The study's settings.
#[derive(Debug, Clone, PartialEq)]
pub struct Tracking {
    /// Knot counts K of the plans (each ≥ 3).
    pub knots: Vec<usize>,
    /// PD gains, `NAME=KP,KD` or `all=KP,KD` (as `vito simulate --gains`), on top of the
    /// problem file's `[tracking] gains`; all=100,10 when both are empty.
    pub gains: Vec<String>,
    /// Where the PD reads the state (None: the problem file's `[tracking] feedback`).
    pub feedback: Option<crate::sim::Feedback>,
    /// Steps per time unit of the tracking simulation.
    pub rate: f64,
    /// The methods planned (the paper's: first order and variational).
    pub methods: Vec<Integrator>,
    /// The tracking simulation's integrator (the paper's: first order).
    pub reference: crate::discrete::Integrator,
}

impl Tracking {
    /// Checks the settings (one error naming the option).
    pub fn check(&self) -> Result<(), StudyError> {
        let invalid = |field: &str, message: &str| {
            Err(StudyError::Invalid {
                field: field.into(),
                message: message.into(),
            })
        };
        if self.knots.is_empty() || self.knots.iter().any(|&k| !(3..=10_000).contains(&k)) {
            return invalid("--knots", "give knot counts from 3 to 10000, e.g. 10,15,20");
        }
        if self.methods.is_empty() {
            return invalid(
                "--methods",
                "give at least one integrator, e.g. euler,midpoint",
            );
        }
        if !(self.rate.is_finite() && self.rate > 0.0 && self.rate <= 1e6) {
            return invalid(
                "--rate",
                "give a positive rate of at most 1e6 steps per time unit",
            );
        }
        Ok(())
    }

    /// Runs the study on the problem `file` (with `overrides`): for each knot count and
    /// method, a solve with `horizon.knots = K` (and, for a fixed step, the step that keeps
    /// the file's horizon), then the tracking simulation. `progress(done, total)` after each
    /// plan.
    pub fn run(
        &self,
        file: &Path,
        overrides: &[Override],
        mut progress: impl FnMut(usize, usize),
    ) -> Result<TrackingResult, StudyError> {
        self.check()?;
        let base = load(file, overrides).map_err(|e| StudyError::Invalid {
            field: file.display().to_string(),
            message: e.to_string(),
        })?;
        let horizon = match base.spec.time_steps {
            TimeSteps::Fixed(h) => Some(h * (base.spec.knots - 1) as f64),
            TimeSteps::FreeEqual { .. } => None,
        };
        let mut gains =
            crate::pipeline::gains::parse_gains(&base.tracking_gains, &self.gains, &base.robot)?;
        if gains.is_empty() {
            gains = crate::pipeline::gains::parse_gains(&[], &["all=100,10".into()], &base.robot)?;
        }
        let mut table = StudyTable::default();
        let mut configuration = StudyTable::default();
        let mut joints = StudyTable::default();
        let mut driven: Vec<usize> = gains.iter().map(|g| g.coordinate).collect();
        driven.sort_unstable();
        driven.dedup();
        let mut plans = Vec::new();
        let mut knots = self.knots.clone();
        knots.sort_unstable();
        knots.dedup();
        // The variational plan first at each K: the others start from it.
        let mut methods = self.methods.clone();
        methods.sort_by_key(|&m| (m != Integrator::Midpoint, table_order(0, m)));
        methods.dedup();
        let total = methods.len() * knots.len();
        // The last solved variational plan: the start of the next K's variational plan and of
        // this K's other plans.
        let mut previous: Option<(String, WarmStart)> = None;
        for &knots in &knots {
            for &method in &methods {
                let what = format!("{} with {knots} knots", method.study_name());
                let start = previous.clone();
                let mut set = overrides.to_vec();
                let mut texts = vec![
                    format!("horizon.knots={knots}"),
                    format!("solver.integrator=\"{}\"", method.name()),
                ];
                if let Some(t) = horizon {
                    texts.push(format!("horizon.time_step={:e}", t / (knots - 1) as f64));
                }
                for text in &texts {
                    set.push(Override::parse(text).map_err(|e| StudyError::Invalid {
                        field: "--knots".into(),
                        message: e.to_string(),
                    })?);
                }
                let mut problem = load(file, &set).map_err(|e| StudyError::Invalid {
                    field: file.display().to_string(),
                    message: e.to_string(),
                })?;
                let start_name = match start {
                    Some((name, warm)) => {
                        problem.spec.initial_guess = InitialGuess::WarmStart(warm);
                        name
                    }
                    None => "guess".to_owned(),
                };
                let plan = crate::pipeline::solve(&problem.spec, &SolveOptions::default())?;
                let verdict = plan.verdict();
                let relaxed = verdict == SolveVerdict::RelaxedContact;
                // Solved, or an optimum of the relaxed problem (which still warm starts).
                let solved = verdict.is_solved() || relaxed;
                let units = crate::report::column_units(&problem.robot, &problem.units);
                plans.push(PlanRecord {
                    knots,
                    method,
                    objective: plan.objective,
                    max_slack: plan.max_slack,
                    iterations: plan.iterations,
                    variables: plan.size.n_variables,
                    wall_time_s: plan.wall_time_s,
                    knot_error: None,
                    start: start_name,
                    trajectory_csv: crate::report::trajectory_csv(&plan, &units),
                    max_deviation: None,
                    outcome: if !solved {
                        format!("not solved: {}", crate::report::status_name(plan.status))
                    } else if relaxed {
                        format!(
                            "relaxed contact: max slack {:.3e} above slack.tolerance {:e}",
                            plan.max_slack, plan.slack_tolerance
                        )
                    } else {
                        "tracked".to_owned()
                    },
                });
                progress(plans.len(), total);
                if !solved {
                    // Recorded, not tracked; the chain goes on from the last solved plan.
                    continue;
                }
                // A relaxed plan still warm starts the chain (the next K's solve may close
                // its slack), but is not tracked.
                if method == Integrator::Midpoint {
                    let name = format!("{} K={knots}", method.study_name());
                    let warm = plan.warm_start(PathBuf::from(&name));
                    previous = Some((name, warm));
                }
                if relaxed {
                    continue;
                }
                let reference = RecordedTrajectory {
                    times: plan.times.clone(),
                    q: plan.q.clone(),
                    u: plan.u.clone(),
                };
                let mech = crate::pipeline::mechanics(&problem.spec)?;
                let contact = problem.spec.contact_model(&mech);
                let h = 1.0 / self.rate;
                let duration = plan.times.last().copied().unwrap_or(0.0);
                let options = SimulationOptions {
                    integrator: self.reference,
                    h,
                    steps: (duration / h).round().max(1.0) as usize,
                    step: StepOptions {
                        gravity: problem
                            .spec
                            .robot
                            .gravity
                            .iter()
                            .map(|g| g * g)
                            .sum::<f64>()
                            .sqrt(),
                        ..StepOptions::default()
                    },
                };
                let source = InputSource::Track {
                    reference: reference.clone(),
                    gains: gains.clone(),
                    feedback: self.feedback.unwrap_or(base.tracking_feedback),
                };
                let m = mech.nu();
                let sim = simulate(
                    &mech,
                    &contact,
                    &plan.q[0],
                    &plan.v[0],
                    &options,
                    |_, t, q, v| source.step_input(m, t, h, q, v),
                    |_| {},
                )
                .map_err(|source| StudyError::Simulation {
                    what: what.clone(),
                    source,
                });
                let sim = match sim {
                    Ok(sim) => sim,
                    Err(e) => {
                        // Recorded, no error row: the other plans' rows still count.
                        if let Some(p) = plans.last_mut() {
                            p.outcome = format!("tracking failed: {e}");
                        }
                        continue;
                    }
                };
                if let Some(p) = plans.last_mut() {
                    p.max_deviation = Some(max_deviation(&sim, &reference));
                    p.knot_error = Some(knot_error(&sim, &reference));
                }
                table.add_run(knots, method, rms_error(&sim, &reference, true));
                joints.add_run(knots, method, rms_error_of(&sim, &reference, true, &driven));
                configuration.add_run(knots, method, rms_error(&sim, &reference, false));
            }
        }
        // The tables in their usual order: first order, then variational, at each K.
        for t in [&mut table, &mut configuration, &mut joints] {
            t.sort();
        }
        plans.sort_by_key(|p| table_order(p.knots, p.method));
        Ok(TrackingResult {
            table,
            configuration,
            joints,
            plans,
        })
    }
}

/// √(mean over the simulation's knots of ‖q − q_ref(t)‖² + ‖v − v_ref(t)‖²), q_ref linear
/// between the plan's knots, v_ref its slope (0 after the plan's end); without the velocity
/// term unless `with_velocity`.
pub fn rms_error(sim: &Simulation, plan: &RecordedTrajectory, with_velocity: bool) -> f64 {
    let all: Vec<usize> = (0..plan.q.first().map_or(0, Vec::len)).collect();
    rms_error_of(sim, plan, with_velocity, &all)
}

/// [`rms_error`] over the coordinates `coordinates` alone.
pub fn rms_error_of(
    sim: &Simulation,
    plan: &RecordedTrajectory,
    with_velocity: bool,
    coordinates: &[usize],
) -> f64 {
    let mut sum = 0.0;
    for_each_error(sim, plan, coordinates, |dq, dv| {
        let dv = if with_velocity { dv } else { 0.0 };
        sum += dq * dq + dv * dv;
    });
    (sum / sim.q.len() as f64).sqrt()
}

/// √(mean over the plan's knots t_k within the simulation of ‖q_sim(t_k) − q_k‖²), q_sim
/// linear between the simulation's steps.
pub fn knot_error(sim: &Simulation, plan: &RecordedTrajectory) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    let last = sim.times.len().saturating_sub(1);
    for (&t, q_plan) in plan.times.iter().zip(&plan.q) {
        if last == 0 || t > sim.times[last] + 1e-9 * t.abs().max(1.0) {
            continue;
        }
        let j = sim.times.partition_point(|&s| s <= t).clamp(1, last);
        let (t0, t1) = (sim.times[j - 1], sim.times[j]);
        let s = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
        for (i, &p) in q_plan.iter().enumerate() {
            let q = sim.q[j - 1][i] + s * (sim.q[j][i] - sim.q[j - 1][i]);
            sum += (q - p) * (q - p);
        }
        count += 1;
    }
    if count == 0 {
        return f64::NAN;
    }
    (sum / count as f64).sqrt()
}

/// max over the simulation's knots and coordinates of |q_i − q_ref,i(t)|.
pub fn max_deviation(sim: &Simulation, plan: &RecordedTrajectory) -> f64 {
    let all: Vec<usize> = (0..plan.q.first().map_or(0, Vec::len)).collect();
    let mut max = 0.0_f64;
    for_each_error(sim, plan, &all, |dq, _| max = max.max(dq.abs()));
    max
}

/// Calls `f(q_i − q_ref,i(t), v_i − v_ref,i(t))` for every knot of the simulation and every
/// coordinate i of `coordinates`: q_ref linear between the plan's knots, v_ref its slope (0
/// after the plan's end).
fn for_each_error(
    sim: &Simulation,
    plan: &RecordedTrajectory,
    coordinates: &[usize],
    mut f: impl FnMut(f64, f64),
) {
    let times = &plan.times;
    let last = times.len() - 1;
    for (&t, (q, v)) in sim.times.iter().zip(sim.q.iter().zip(&sim.v)) {
        let j = times.partition_point(|&s| s <= t).clamp(1, last);
        let (t0, t1) = (times[j - 1], times[j]);
        let s = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
        let after = t > times[last];
        for &i in coordinates {
            let (a, b) = (plan.q[j - 1][i], plan.q[j][i]);
            let q_ref = a + s * (b - a);
            let v_ref = if after { 0.0 } else { (b - a) / (t1 - t0) };
            f(q[i] - q_ref, v[i] - v_ref);
        }
    }
}
