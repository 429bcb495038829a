//! `vito solve`: progress, the solve, its summary.

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use vito::ipopt::OptionValue;
use vito::pipeline;
use vito::problem::LoadedProblem;
use vito::report::{self, status_name};
use vito::transcription::Solution;

use super::args::parse_overrides;
use super::error::CliError;
use super::interrupt::on_stop_request;
use super::output::print_model_warnings;

/// How often progress lines are printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum ProgressMode {
    /// Every iteration.
    Full,
    /// The first iteration, then the first one at least [`COMPACT_INTERVAL`] after the last
    /// line printed.
    Compact,
}

/// The spacing of compact progress lines.
pub(super) const COMPACT_INTERVAL: std::time::Duration = std::time::Duration::from_secs(1);

impl ProgressMode {
    /// `--progress`: `auto` is full on a terminal, compact otherwise (a log, a sweep's run).
    pub(super) fn from_arg(arg: super::args::ProgressArg) -> ProgressMode {
        use std::io::IsTerminal;
        match arg {
            super::args::ProgressArg::Full => ProgressMode::Full,
            super::args::ProgressArg::Compact => ProgressMode::Compact,
            super::args::ProgressArg::Auto if std::io::stderr().is_terminal() => ProgressMode::Full,
            super::args::ProgressArg::Auto => ProgressMode::Compact,
        }
    }
}

/// How `vito solve` runs besides its problem and output.
pub(super) struct SolveRun {
    /// No progress lines.
    pub(super) quiet: bool,
    /// Ipopt's own log into the output directory.
    pub(super) ipopt_log: bool,
    /// Starts (and, in a parallel multi-start's process, the one to solve).
    pub(super) multi_start: vito::transcription::MultiStart,
    /// Starts at a time, each in its own process.
    pub(super) jobs: usize,
    /// In a parallel multi-start's process: where to write the start's solution.
    pub(super) start_result: Option<std::path::PathBuf>,
    /// Wall-time limit of the whole solve.
    pub(super) time_limit: Option<std::time::Duration>,
    /// How often progress lines are printed.
    pub(super) progress: ProgressMode,
    /// The sweep that started this run.
    pub(super) sweep_parent: Option<u32>,
    /// A grid finer than the file's is solved through the file's grid and its doublings.
    pub(super) refine: bool,
}

/// The header above the progress lines.
pub(super) const PROGRESS_HEADER: &str =
    " iter       objective     inf_pr     inf_du  max_slack    elapsed";

/// Progress line printed on stderr at an Ipopt iteration (`elapsed`: seconds since the solve
/// started).
pub(super) fn progress_line(p: &vito::transcription::Progress, elapsed: f64) -> String {
    format!(
        "{:>5}  {:>14.7e}  {:>9.2e}  {:>9.2e}  {:>9.2e}  {elapsed:>8.1} s",
        p.iteration, p.objective, p.inf_pr, p.inf_du, p.max_slack
    )
}

/// The iteration limit a solve runs under: the problem's `max_iter`, else vito's default.
fn max_iter(problem: &LoadedProblem) -> Option<i64> {
    problem
        .spec
        .solver_options
        .iter()
        .chain(&vito::ipopt::default_options())
        .find(|(name, _)| name == "max_iter")
        .and_then(|(_, v)| match v {
            OptionValue::Int(i) => Some(*i),
            OptionValue::Num(x) => Some(*x as i64),
            OptionValue::Str(_) => None,
        })
}

pub(super) fn solve(
    file: &Path,
    set: &[String],
    out: Option<&Path>,
    run: &SolveRun,
) -> Result<u8, CliError> {
    let quiet = run.quiet;
    if let Some(parent) = run.sweep_parent
        && !vito::sweep::die_with_sweep(parent)
    {
        note!(
            "error: {} {parent}: the sweep that started this run has ended; not solving",
            vito::sweep::PARENT_FLAG
        );
        return Ok(1);
    }
    let overrides = parse_overrides(set)?;
    let problem = pipeline::load_checked(file, &overrides)?;
    let multi_start = run.multi_start;
    // A grid finer than the file's: solved through the file's grid (`pipeline::levels`).
    let levels = if run.refine {
        pipeline::levels::levels_for(&problem)
    } else {
        None
    };
    if let Some(result) = &run.start_result {
        // One start of a parallel multi-start: its solution to the file, nothing else.
        let cancel = on_stop_request(|| {}, || std::process::exit(1));
        vito::sweep::stop_when_the_parent_asks(cancel.clone());
        let solution = run_solver(&problem, cancel, run, Vec::new(), None)?;
        super::starts::write_start_result(result, &solution)?;
        return Ok(0);
    }
    print_model_warnings(&problem.robot, !problem.spec.contacts.is_empty());
    // Parallel starts run in processes of their own; Ipopt's log is one solve's and a time
    // limit is the whole solve's, so --ipopt-log and --time-limit keep the starts in this
    // process.
    let parallel = multi_start.starts > 1
        && run.jobs > 1
        && !run.ipopt_log
        && run.time_limit.is_none()
        && levels.is_none();
    let target =
        pipeline::output::checked_output_dir(&problem, out).map_err(report::ReportError::from)?;
    // With --ipopt-log, staged before solving so that Ipopt's log goes straight into the
    // directory that replaces the target atomically; otherwise staged once there is
    // something to write, so a run killed while solving leaves nothing behind.
    let mut staged = None;
    let mut ipopt_options = Vec::new();
    if run.ipopt_log {
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
    if run.sweep_parent.is_some() {
        vito::sweep::stop_when_the_parent_asks(cancel.clone());
    }
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
        let limit = run.time_limit.map_or(String::new(), |t| {
            format!(", time limit {} s", t.as_secs_f64())
        });
        let iterations = max_iter(&problem).map_or(String::new(), |m| format!(", max_iter {m}"));
        let compact = if run.progress == ProgressMode::Compact {
            ", a line about every second"
        } else {
            ""
        };
        note!(
            "solving {} ({} knots{iterations}{limit}{compact})",
            problem.spec.name,
            problem.spec.knots
        );
        if !parallel {
            note!("{PROGRESS_HEADER}");
        }
    }
    let deadline = run.time_limit.map(|t| std::time::Instant::now() + t);
    let solution = if parallel {
        if !quiet {
            note!(
                "{} starts, {} at a time, each in its own process",
                multi_start.starts,
                run.jobs.min(multi_start.starts)
            );
        }
        super::starts::solve_in_parallel(file, set, multi_start, run.jobs, &cancel, quiet)?
    } else if let Some(ladder) = &levels {
        if !quiet {
            let steps: Vec<String> = ladder.iter().map(|n| n.to_string()).collect();
            note!(
                "grid continuation: {} knots (the file's grid, doubled up to the one asked; --no-refine solves on {} knots alone)",
                steps.join(" → "),
                problem.spec.knots
            );
        }
        let mut options = solve_options(cancel.clone(), run, ipopt_options, deadline);
        pipeline::levels::solve_on_levels(&problem, ladder, &mut options, |level, l, count| {
            if !quiet {
                note!("{}", level_line(level, l, count));
            }
        })?
    } else {
        run_solver(&problem, cancel.clone(), run, ipopt_options, deadline)?
    };
    if solution.status == vito::ipopt::Status::MaximumWallTimeExceeded && !quiet {
        note!(
            "time limit: stopped after {} iterations; writing the iterate",
            solution.iterations
        );
    }
    let staged = match staged {
        Some(staged) => staged,
        None => target.stage().map_err(report::ReportError::from)?,
    };
    let written = report::write_outputs(staged, &problem, &solution)?;
    print_summary(&problem, &solution, &written)?;
    Ok(if solution.verdict().is_solved() { 0 } else { 1 })
}

/// Calls the transcription's solver with live progress (stderr), the cancel flag and the
/// deadline.
fn run_solver(
    problem: &LoadedProblem,
    cancel: Arc<AtomicBool>,
    run: &SolveRun,
    ipopt_options: Vec<(String, OptionValue)>,
    deadline: Option<std::time::Instant>,
) -> Result<Solution, CliError> {
    let options = solve_options(cancel, run, ipopt_options, deadline);
    pipeline::solve(&problem.spec, &options).map_err(CliError::Transcription)
}

/// The solve's options: live progress (stderr), the cancel flag, the deadline and the starts.
fn solve_options(
    cancel: Arc<AtomicBool>,
    run: &SolveRun,
    ipopt_options: Vec<(String, OptionValue)>,
    deadline: Option<std::time::Instant>,
) -> vito::transcription::SolveOptions {
    let (quiet, mode) = (run.quiet, run.progress);
    let started = std::time::Instant::now();
    let last_line = std::sync::Mutex::new(None::<std::time::Instant>);
    let progress = move |p: &vito::transcription::Progress| {
        if quiet {
            return;
        }
        let now = std::time::Instant::now();
        let mut last = last_line.lock().unwrap_or_else(|e| e.into_inner());
        let due = match (mode, *last) {
            (ProgressMode::Full, _) | (ProgressMode::Compact, None) => true,
            (ProgressMode::Compact, Some(t)) => now.duration_since(t) >= COMPACT_INTERVAL,
        };
        if due {
            *last = Some(now);
            note!(
                "{}",
                progress_line(p, now.duration_since(started).as_secs_f64())
            );
        }
    };
    vito::transcription::SolveOptions {
        progress: Some(Box::new(progress)),
        cancel: Some(cancel),
        ipopt_options,
        multi_start: Some(run.multi_start),
        deadline,
    }
}

/// A level of a grid continuation as the terminal shows it when it ends.
fn level_line(level: &vito::transcription::GridLevel, index: usize, count: usize) -> String {
    let moved = level.max_q_difference.map_or(String::new(), |d| {
        format!(", q moved up to {d:.2e} from the level below")
    });
    let modes = match level.carried_modes_kept {
        Some(true) => ", the contact modes of the level below kept (lower than the relaxed solve)",
        Some(false) => ", the relaxed solve kept (lower than the contact modes of the level below)",
        None => "",
    };
    format!(
        "level {}/{count}, {} knots: {}, objective {:.6e}, max slack {:.1e}, {} iterations, {:.1} s{modes}{moved}",
        index + 1,
        level.knots,
        level.verdict.name(),
        level.objective,
        level.max_slack,
        level.iterations,
        level.wall_time_s
    )
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
    // A robot without contacts has no slack: its (zero) slack penalty and slack lines are
    // left out.
    let contacts = !s.contact_names.is_empty();
    for (name, value) in &s.objective_terms {
        if contacts || name != "slack_penalty" {
            let pad = " ".repeat(width.saturating_sub(name.chars().count()));
            // Ipopt relaxes the slacks' lower bound 0 by 1e-8, so slacks that are zero can
            // sum to a slightly negative penalty: say so rather than print a bare negative.
            let why = if name == "slack_penalty" && *value < 0.0 {
                " (slacks at Ipopt's relaxed bound −1e-8: zero within its tolerance)"
            } else {
                ""
            };
            out!("  {name}{pad} {value:.6e}{why}");
        }
    }
    out!("iterations   {}", s.iterations);
    out!(
        "time         {:.3} s wall ({:.3} s in vito callbacks, {:.3} s in Ipopt)",
        s.wall_time_s,
        s.callback_time_s,
        s.ipopt_time_s
    );
    out!("callbacks    {}", s.callback_split.describe());
    if contacts && s.solves > 1 {
        // `[slack] tied_tolerances`: how many solves stopped at a looser tolerance.
        let loose = s
            .continuation
            .iter()
            .filter(|c| c.tied_tol.is_some())
            .count();
        let loose = match loose {
            0 => String::new(),
            n => format!("; {n} at tolerances tied to the relaxation"),
        };
        out!(
            "max slack    {:.3e} after {} solves (slack weight raised to {:e}{loose})",
            s.max_slack,
            s.solves,
            s.slack_weight
        );
    } else if contacts {
        out!("max slack    {:.3e}", s.max_slack);
    }
    if !s.levels.is_empty() {
        let steps: Vec<String> = s
            .levels
            .iter()
            .map(|l| {
                format!(
                    "{} knots {} {:.6e} ({} it, {:.1} s)",
                    l.knots,
                    l.verdict.name(),
                    l.objective,
                    l.iterations,
                    l.wall_time_s
                )
            })
            .collect();
        out!("levels       {}", steps.join(" → "));
    }
    if let Some(start) = &s.simulation_start {
        out!(
            "simulation   {} steps ({:.3} s, step residual up to {:.1e}), solved with its contact modes fixed: {} after {} iterations, q within {:.1e} of the simulation{}",
            start.steps,
            start.simulation_time_s,
            start.simulation_residual,
            start.verdict.name(),
            start.iterations,
            start.max_q_difference,
            if start.kept {
                ""
            } else {
                "; not kept, the usual solve followed"
            },
        );
    }
    if let Some(p) = &s.polish {
        out!(
            "polish       {} from objective {:.10e} (max slack {:.3e}{}): {} {:.10e} after {} iterations{}",
            if p.kept { "kept" } else { "not kept" },
            p.objective_before,
            p.max_slack_before,
            if p.status_before.is_success() {
                ""
            } else {
                "; the relaxed solve stopped at Ipopt's iteration limit"
            },
            p.verdict.name(),
            p.objective,
            p.iterations,
            if p.kept || !p.verdict.is_solved() {
                ""
            } else {
                " (higher)"
            },
        );
    }
    if let (Some(first), false) = (s.levels.first(), s.starts.is_empty()) {
        out!(
            "starts       on the first level ({} knots); the levels above refined the best",
            first.knots
        );
    }
    for (k, r) in s.starts.iter().enumerate() {
        match &r.outcome {
            vito::transcription::StartOutcome::Ended(e) => out!(
                "  start {k:<3} {:<28} objective {:.10e}  max slack {:.3e}  {} iterations{}",
                e.verdict.name(),
                e.objective,
                e.max_slack,
                e.iterations,
                if k == s.best_start { "  (best)" } else { "" }
            ),
            vito::transcription::StartOutcome::Lost(lost) => {
                out!("  start {k:<3} {:<28} {}", lost.status(), lost.how)
            }
        }
    }
    if contacts {
        out!("max compl.   {:.3e}", s.max_complementarity);
    }
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
                        (Some(a), Some(b)) => {
                            // To 1e-4 of the unit, without the steps' round-off digits.
                            let t = |t: f64| vito::model::trimmed_decimal(t, 4);
                            format!(", t = {}–{} {time_unit}", t(*a), t(*b))
                        }
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
            // Hidden products are not the slack variables' doing: a higher weight does not
            // close them.
            let hidden = s.slack_peak.as_ref().is_some_and(|p| p.hidden);
            let (what, remedy) = if hidden {
                (
                    format!(
                        "complementarity products of {:.3e}, above slack.tolerance {:e}, which other products of \
                         opposite sign cancel in the rows' sums (its slack variables are within it)",
                        s.max_slack, s.slack_tolerance
                    ),
                    "contacts.max_slip_speed (bounds ψ and η, whose huge flight values make the cancelling products), \
                     or --set solver.ipopt.bound_relax_factor=0 (no negative factors); a higher slack weight does not close it",
                )
            } else {
                (
                    format!(
                        "slack {:.3e}, above slack.tolerance {:e}",
                        s.max_slack, s.slack_tolerance
                    ),
                    "or a higher slack weight (--set slack.weight=..., or slack.target for a continuation)",
                )
            };
            lines.push(format!(
                "not solved:  Ipopt's optimum relaxes the contact model: {at} keeps {what}"
            ));
            lines.push(format!(
                "try:         --starts 4 (other starts), a warm start ([initial_guess] warm_start = a solved trajectory.csv), {remedy}"
            ));
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
