//! `vito simulate`: a forward simulation of a problem file.

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

use vito::pipeline;
use vito::problem::load;
use vito::report;

use super::args::parse_overrides;
use super::error::{CliError, EXIT_NOT_SOLVED};
use super::interrupt::on_stop_request;

pub(super) fn simulate(
    file: &Path,
    set: &[String],
    request: &pipeline::simulation::SimulateRequest,
    out: Option<&Path>,
    quiet: bool,
) -> Result<u8, CliError> {
    let overrides = parse_overrides(set)?;
    let problem = load(file, &overrides)?;
    let prepared = pipeline::simulation::prepare_simulation(&problem, request)?;
    let target = out.map_or_else(
        || PathBuf::from("out").join(format!("{}-simulate", problem.spec.name)),
        Path::to_owned,
    );
    let protected: Vec<&Path> = prepared.inputs.iter().map(PathBuf::as_path).collect();
    let target =
        report::OutputTarget::check(&target, &protected).map_err(report::ReportError::from)?;
    let steps = prepared.options.steps;
    let bar = if quiet {
        indicatif::ProgressBar::hidden()
    } else {
        indicatif::ProgressBar::new(steps as u64)
    };
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "simulating {bar:40} {pos}/{len} steps, {per_sec}, ETA {eta}",
    ) {
        bar.set_style(style);
    }
    // SIGINT, SIGTERM, SIGHUP: the simulation stops after its current step and writes the
    // steps it has made (exit 1); a later request quits at once.
    let stop = on_stop_request(
        || note!("interrupted: stopping after the current step and writing the steps made"),
        || {
            note!("interrupted again: exiting without writing");
            std::process::exit(1);
        },
    );
    if !quiet {
        note!(
            "simulating {}: {steps} steps of h = {} {} (Ctrl-C stops after the current step and writes the steps made)",
            problem.spec.name,
            prepared.options.h,
            problem.units.time
        );
    }
    let run = pipeline::simulation::simulate_prepared(&problem, &prepared, |_| {
        bar.inc(1);
        if stop.load(Ordering::SeqCst) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    bar.finish_and_clear();
    let pipeline::simulation::SimulationRun {
        sim,
        energies,
        mut summary,
        columns,
        wall_time_s: wall,
    } = run?;
    let made = sim.iterations.len();
    let stopped = stop.load(Ordering::SeqCst) && made < steps;
    if stopped && made == 0 {
        note!("interrupted before the first step: nothing written");
        return Ok(EXIT_NOT_SOLVED);
    }
    if stopped {
        summary["stopped_by_signal"] = serde_json::json!({ "steps_requested": steps });
    }
    let staged = target.stage().map_err(report::ReportError::from)?;
    let written =
        report::write_trajectory_outputs(staged, &problem, &columns.trajectory(&sim), &summary)?;
    out!("problem        {}", problem.spec.name);
    if stopped {
        out!("status         stopped by a signal after {made} of {steps} steps");
    }
    out!(
        "steps          {made} of h = {} {} ({:?})",
        prepared.options.h,
        problem.units.time,
        prepared.options.integrator
    );
    let largest = |v: &[f64]| v.iter().cloned().fold(0.0_f64, f64::max);
    out!("max residual   {:.3e}", largest(&sim.dynamics_residual));
    out!("max compl.     {:.3e}", largest(&sim.complementarity));
    if !sim.relaxed_steps.is_empty() {
        out!(
            "relaxed steps  {} (residual up to {:.3e}, accepted at the acceptable tolerance)",
            sim.relaxed_steps.len(),
            largest(&sim.residual)
        );
    }
    out!(
        "max penetr.    {:.3e} {}",
        sim.max_penetration(),
        problem.units.length
    );
    if let Some(e) = &energies {
        let e0 = e.first().copied().unwrap_or(0.0);
        let drift = e.iter().fold(0.0_f64, |a, x| a.max((x - e0).abs()));
        out!("energy drift   {drift:.3e} (max |E − E0|)");
    }
    out!(
        "time           {wall:.3} s wall ({:.1} µs per step, {:.2} Newton iterations per step)",
        1e6 * wall / made.max(1) as f64,
        summary["newton_iterations"]["mean"]
    );
    out!("written to     {}", written.display());
    if let Some(line) =
        report::plots_not_written(problem.robot.inputs.len(), problem.spec.contacts.len())
    {
        out!("plots          {line}");
    }
    Ok(if stopped { EXIT_NOT_SOLVED } else { 0 })
}
