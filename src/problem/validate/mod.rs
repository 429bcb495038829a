//! Problem file → checked [`ProblemSpec`]: name resolution against the robot and every check
//! a user can fail, each error naming the file, line and field (and the nearest valid name
//! for a typo). One module per section of the problem file; [`check`] runs them in order.

#![warn(missing_docs)]

mod bounds;
mod columns;
mod contacts;
pub(crate) mod context;
mod endpoints;
mod horizon;
mod initial_guess;
mod inputs;
mod metrics;
mod robot;
mod size;
mod slack;
mod solver;
mod terrain;
mod tracking;
pub(crate) mod values;

use std::path::Path;

pub(crate) use context::Context;
pub(crate) use initial_guess::warm_start_from_text;
pub(crate) use size::memory_available;

use crate::problem::schema::ProblemFile;
use crate::problem::{LoadedProblem, ProblemError, ProblemSpec};

/// Checks a parsed problem file, section by section, into a [`LoadedProblem`] (whose hash
/// and overrides the caller fills in).
pub(crate) fn check(ctx: &Context, raw: ProblemFile) -> Result<LoadedProblem, ProblemError> {
    let name = match &raw.name {
        Some(name) => values::file_name_component(ctx, "name", name)?.to_owned(),
        None => ctx
            .file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "problem".into()),
    };
    let robot::CheckedRobot {
        units,
        spec: robot_spec,
        robot,
    } = robot::check_robot(ctx, &raw)?;
    let contacts = contacts::check_contacts(ctx, &raw.contacts, &robot)?;
    let (slack_weight, slack_mode, slack_tolerance) = slack::check_slack_penalty(ctx, &raw)?;
    columns::check_csv_columns(ctx, &robot, &contacts, slack_mode)?;
    let terrain = terrain::check_terrain(ctx, &raw, &robot, &contacts)?;
    let knots = horizon::check_knots(ctx, &raw)?;
    size::check_nlp_fits(ctx, &robot, contacts.len(), knots)?;
    let time_steps = horizon::check_time_steps(ctx, &raw, knots)?;
    let endpoints = endpoints::check_endpoints(ctx, &raw, &robot)?;
    let bounds = bounds::check_bounds(ctx, &raw, &robot, knots)?;
    let joint_limits = raw.robot.joint_limits.unwrap_or(true);
    let input_bounds = inputs::check_inputs(ctx, &raw, &robot)?;
    let contact_names: Vec<String> = contacts.iter().map(|c| c.name.clone()).collect();
    let costs =
        crate::problem::costs::check_costs(ctx, &raw, &robot, &contact_names, &endpoints.goal)?;
    let max_slip_speed = contacts::check_max_slip_speed(ctx, &raw)?;
    let mode_block = contacts::check_mode_block(ctx, &raw, knots)?;
    let slack_continuation = slack::check_slack_continuation(ctx, &raw, slack_tolerance)?;
    let slack_polish = slack::check_polish(ctx, &raw, mode_block)?;
    let constraints = crate::problem::constraints::check_constraints(ctx, &raw, &robot, knots)?;
    let frame_scope =
        crate::problem::frames::FrameScope::new(ctx, &robot, &contacts, knots, &time_steps);
    let mut frames = crate::problem::frames::check_frames(&frame_scope, &raw)?;
    let windows = crate::problem::frames::check_windows(&frame_scope, &raw)?;
    frames.extend(windows.frames);
    let zero_impulse = windows.zero_impulse;
    let initial_guess = initial_guess::check_initial_guess(ctx, &raw, &robot, &endpoints, knots)?;
    let metrics = metrics::check_metrics(ctx, &raw, &robot)?;
    let tracking_gains = tracking::check_tracking(ctx, &raw, &robot)?;
    let tracking_feedback = raw.tracking.feedback;
    let solver::CheckedSolver {
        integrator,
        hessian,
        scaling,
        solver_options,
    } = solver::check_solver(ctx, &raw)?;
    slack::check_penalty_options(ctx, slack_mode, &solver_options)?;
    // `check_constraints` lists the `[[periodic]]` shorthands first, then `[[constraint]]`.
    for (i, constraint) in constraints.iter().enumerate() {
        if let Some(message) = constraint.integrator_problem(integrator) {
            let field = match i.checked_sub(raw.periodic.len()) {
                Some(k) => format!("constraint[{k}].type"),
                None => format!("periodic[{i}]"),
            };
            return Err(ctx.invalid(&field, message));
        }
    }
    let endpoints::Endpoints {
        q_initial,
        q_initial_free,
        v_initial,
        goal,
        q_final,
    } = endpoints;

    bounds::check_bounds_feasible(
        ctx,
        &robot,
        knots,
        joint_limits,
        &bounds,
        &q_initial,
        &q_final,
    )?;

    let spec = ProblemSpec {
        name,
        robot: robot_spec,
        contacts,
        terrain,
        knots,
        time_steps,
        integrator,
        slack_weight,
        slack_mode,
        slack_tolerance,
        slack_continuation,
        slack_polish,
        max_slip_speed,
        mode_block,
        q_initial,
        q_initial_free,
        v_initial,
        q_final,
        bounds,
        joint_limits,
        input_bounds,
        costs,
        constraints,
        frames,
        zero_impulse,
        initial_guess,
        hessian,
        scaling,
        solver_options,
        metrics,
    };
    Ok(LoadedProblem {
        spec,
        robot,
        file: ctx.file.clone(),
        sha256: String::new(),
        parameters: Vec::new(),
        family_parameters: Default::default(),
        // Relative to the problem file, like every path in it (`--out` is relative to the
        // working directory).
        output_dir: raw
            .output
            .dir
            .map(|d| ctx.file.parent().unwrap_or(Path::new("")).join(d)),
        units,
        description: raw.description,
        goal,
        tracking_gains,
        tracking_feedback,
    })
}
