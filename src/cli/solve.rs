//! `vito solve`: progress, the solve, its summary.

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use vito::ipopt::OptionValue;
use vito::pipeline;
use vito::problem::{LoadedProblem, load};
use vito::report::{self, status_name};
use vito::transcription::Solution;

use super::args::parse_overrides;
use super::error::CliError;
use super::interrupt::on_stop_request;
use super::output::print_model_warnings;

/// Progress line printed on stderr at each Ipopt iteration.
pub(super) fn progress_line(
    iteration: usize,
    objective: f64,
    inf_pr: f64,
    inf_du: f64,
    max_slack: f64,
) -> String {
    format!("{iteration:>5}  {objective:>14.7e}  {inf_pr:>9.2e}  {inf_du:>9.2e}  {max_slack:>9.2e}")
}

pub(super) fn solve(
    file: &Path,
    set: &[String],
    out: Option<&Path>,
    quiet: bool,
    ipopt_log: bool,
    multi_start: vito::transcription::MultiStart,
    sweep_parent: Option<u32>,
) -> Result<u8, CliError> {
    if let Some(parent) = sweep_parent
        && !vito::sweep::die_with_sweep(parent)
    {
        eprintln!(
            "error: {} {parent}: the sweep that started this run has ended; not solving",
            vito::sweep::PARENT_FLAG
        );
        return Ok(1);
    }
    let overrides = parse_overrides(set)?;
    let problem = load(file, &overrides)?;
    print_model_warnings(&problem.robot);
    pipeline::check_solver_options(&problem)?;
    let target =
        pipeline::output::checked_output_dir(&problem, out).map_err(report::ReportError::from)?;
    // With --ipopt-log, staged before solving so that Ipopt's log goes straight into the
    // directory that replaces the target atomically; otherwise staged once there is
    // something to write, so a run killed while solving leaves nothing behind.
    let mut staged = None;
    let mut ipopt_options = Vec::new();
    if ipopt_log {
        let dir = staged.insert(target.stage().map_err(report::ReportError::from)?);
        let log = dir.path().join("ipopt.log");
        let log = log.to_str().ok_or_else(|| {
            CliError::Input(format!(
                "--ipopt-log: the output path {} is not UTF-8, which Ipopt cannot take",
                log.display()
            ))
        })?;
        ipopt_options.push(("output_file".to_owned(), OptionValue::Str(log.to_owned())));
        ipopt_options.push(("file_print_level".to_owned(), OptionValue::Int(5)));
    }
    // SIGINT, SIGTERM, SIGHUP: stop at the next iteration and write the iterate
    // (`user_requested_stop`, exit 1). A later request exits at once (exit 1) without
    // writing, leaving any previous output untouched.
    let cancel = on_stop_request(
        || note!("interrupted: stopping after this iteration (interrupt again to quit now)"),
        || {
            note!("interrupted again: exiting without writing results");
            std::process::exit(1);
        },
    );
    if !quiet {
        if let vito::problem::InitialGuess::Simulation(g) = &problem.spec.initial_guess {
            note!(
                "simulating the initial guess: {} periods of {} {} on {} knots",
                g.cycles,
                g.period,
                problem.units.time,
                problem.spec.knots
            );
        }
        note!(
            "solving {} ({} knots)",
            problem.spec.name,
            problem.spec.knots
        );
        note!(" iter       objective     inf_pr     inf_du  max_slack");
    }
    let solution = run_solver(&problem, cancel.clone(), quiet, ipopt_options, multi_start)?;
    let staged = match staged {
        Some(staged) => staged,
        None => target.stage().map_err(report::ReportError::from)?,
    };
    let written = report::write_outputs(staged, &problem, &solution)?;
    print_summary(&problem, &solution, &written)?;
    Ok(if solution.verdict().is_solved() { 0 } else { 1 })
}

/// Calls the transcription's solver with live progress (stderr) and the cancel flag.
pub(super) fn run_solver(
    problem: &LoadedProblem,
    cancel: Arc<AtomicBool>,
    quiet: bool,
    ipopt_options: Vec<(String, OptionValue)>,
    multi_start: vito::transcription::MultiStart,
) -> Result<Solution, CliError> {
    let progress = move |p: &vito::transcription::Progress| {
        if !quiet {
            note!(
                "{}",
                progress_line(p.iteration, p.objective, p.inf_pr, p.inf_du, p.max_slack)
            );
        }
    };
    let options = vito::transcription::SolveOptions {
        progress: Some(Box::new(progress)),
        cancel: Some(cancel),
        ipopt_options,
        multi_start: Some(multi_start),
    };
    pipeline::solve(&problem.spec, &options).map_err(CliError::Transcription)
}

pub(super) fn print_summary(
    problem: &LoadedProblem,
    s: &Solution,
    dir: &Path,
) -> Result<(), CliError> {
    out!("problem      {}", problem.spec.name);
    let verdict = s.verdict();
    if verdict.name() == status_name(s.status) {
        out!("status       {verdict}");
    } else {
        out!("status       {verdict} (Ipopt: {})", status_name(s.status));
    }
    out!("objective    {:.10e}", s.objective);
    // Aligned at 22 columns, or wider for a longer name ("complementarity_penalty").
    let width = s
        .objective_terms
        .iter()
        .map(|(name, _)| name.chars().count())
        .fold(22, usize::max);
    for (name, value) in &s.objective_terms {
        let pad = " ".repeat(width - name.chars().count());
        out!("  {name}{pad} {value:.6e}");
    }
    out!("iterations   {}", s.iterations);
    out!(
        "time         {:.3} s wall ({:.3} s in vito callbacks, {:.3} s in Ipopt)",
        s.wall_time_s,
        s.callback_time_s,
        s.ipopt_time_s
    );
    out!("callbacks    {}", s.callback_split.describe());
    if s.solves > 1 {
        out!(
            "max slack    {:.3e} after {} solves (slack weight raised to {:e})",
            s.max_slack,
            s.solves,
            s.slack_weight
        );
    } else {
        out!("max slack    {:.3e}", s.max_slack);
    }
    for (k, r) in s.starts.iter().enumerate() {
        out!(
            "  start {k:<3} {:<28} objective {:.10e}  max slack {:.3e}  {} iterations{}",
            r.verdict.name(),
            r.objective,
            r.max_slack,
            r.iterations,
            if k == s.best_start { "  (best)" } else { "" }
        );
    }
    out!("max compl.   {:.3e}", s.max_complementarity);
    out!("max viol.    {:.3e}", s.max_constraint_violation);
    out!(
        "size         {} variables, {} constraints, nnz J {}, nnz H {}",
        s.size.n_variables,
        s.size.n_constraints,
        s.size.nnz_jacobian,
        s.size.nnz_hessian
    );
    if let Some(t) = s.times.last() {
        out!("horizon      T = {t:.6} {}", problem.units.time);
    }
    out!("written to   {}", dir.display());
    if let Some(line) = report::plots_not_written(s.input_names.len(), s.contact_names.len()) {
        out!("plots        {line}");
    }
    for line in verdict_explanation(s, &problem.units.time) {
        out!("{line}");
    }
    Ok(())
}

/// Why a solve is not solved and what to try, one line each (nothing when it is solved):
/// where a relaxed plan breaks contact, or the rows an unsolved one violates most.
pub(super) fn verdict_explanation(s: &Solution, time_unit: &str) -> Vec<String> {
    use vito::transcription::SolveVerdict;
    let mut lines = Vec::new();
    match s.verdict() {
        SolveVerdict::Solved(_) => {}
        SolveVerdict::RelaxedContact => {
            let at = match &s.slack_peak {
                Some(p) => {
                    let knots = match (s.times.get(p.interval), s.times.get(p.interval + 1)) {
                        (Some(a), Some(b)) => format!(", t = {a}–{b} {time_unit}"),
                        _ => String::new(),
                    };
                    let contact = p
                        .contact
                        .as_deref()
                        .map_or("contact".to_owned(), |c| format!("contact `{c}`"));
                    format!(
                        "{contact} at interval {} (knots {}–{}{knots}, row {} of trajectory.csv)",
                        p.interval,
                        p.interval,
                        p.interval + 1,
                        p.interval
                    )
                }
                None => "some contact".to_owned(),
            };
            lines.push(format!(
                "not solved:  Ipopt's optimum relaxes the contact model: {at} keeps slack {:.3e}, above slack.tolerance {:e}",
                s.max_slack, s.slack_tolerance
            ));
            lines.push(
                "try:         --starts 4 (other starts), a warm start ([initial_guess] warm_start = a solved trajectory.csv), \
                 or a higher slack weight (--set slack.weight=..., or slack.target for a continuation)"
                    .to_owned(),
            );
        }
        SolveVerdict::NotSolved(_) => {
            if !s.worst_rows.is_empty() {
                lines.push(
                    "worst rows:  the most violated constraints (knots and intervals from 0; \
                     `vito check --derivatives` names rows alike)"
                        .to_owned(),
                );
                for r in &s.worst_rows {
                    lines.push(format!("  [{}]  violation {:.3e}", r.row, r.violation));
                }
            }
        }
    }
    lines
}
