//! The `vito` command: the dispatch here; arguments (clap derive) in `args.rs`, errors and
//! exit codes in `error.rs`, writing to stdout and stderr in `output.rs`;
//! each subcommand's reading of its arguments and printing of its results in its own file.
//! The work itself is the library's.
//!
//! Exit codes: [`error::EXIT_CODE_TABLE`].

use std::process::ExitCode;
use std::sync::atomic::Ordering;

/// `eprintln!` that escapes control characters and never fails: a standard error that
/// cannot be written (`2> /dev/full`) must not stop a command before its results are
/// written; the failure is remembered and turns the exit code into [`EXIT_OUTPUT`].
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::cli::output::write_stderr(&format!($($arg)*))
    };
}

/// `println!` that escapes control characters (names from a URDF reach it) and treats a
/// broken pipe as the end of the output; any other write error (a full disk, `> /dev/full`)
/// ends the command with an error.
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::cli::output::write_stdout(&format!($($arg)*))?
    };
}

mod args;
mod bench;
mod check;
mod error;
mod init;
mod inspect;
mod interrupt;
mod output;
mod regress;
mod simulate;
mod solve;
mod starts;
mod study;
mod sweep;
mod view;

pub use args::Args;
use args::{Command, StudyKind, SweepAction};
use error::{CliError, EXIT_OUTPUT};
use output::{OUTPUT_FAILED, print_error};

/// Runs a parsed command; prints the error (once, with its chain) and returns the exit code.
pub fn run(args: Args) -> ExitCode {
    // A panic is a bug, never an input error: report it as internal (exit 3), once.
    let outcome = std::panic::catch_unwind(move || dispatch(args));
    let result = outcome.unwrap_or_else(|_| {
        Err(CliError::Internal(
            "vito panicked (a bug; the message above says where)".into(),
        ))
    });
    match result {
        // A command that did its work but could not say so completely.
        Ok(_) if OUTPUT_FAILED.load(Ordering::SeqCst) => ExitCode::from(EXIT_OUTPUT),
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            print_error(&e);
            ExitCode::from(e.exit_code())
        }
    }
}

fn dispatch(args: Args) -> Result<u8, CliError> {
    match args.command {
        Command::Solve {
            file,
            set,
            out,
            quiet,
            ipopt_log,
            starts,
            seed,
            jobs,
            only_start,
            start_result,
            time_limit,
            progress,
            sweep_parent,
            no_refine,
        } => {
            let starts = args::count("--starts", starts, vito::transcription::MAX_STARTS)?;
            let jobs = args::jobs(jobs)?;
            if only_start.is_some_and(|k| k >= starts) {
                return Err(CliError::Input(format!(
                    "--only-start {}: give a start below --starts {starts}",
                    only_start.unwrap_or(0)
                )));
            }
            let time_limit = args::time_limit(time_limit)?;
            let run = solve::SolveRun {
                quiet,
                ipopt_log,
                multi_start: vito::transcription::MultiStart {
                    starts,
                    seed,
                    only: only_start,
                },
                jobs,
                start_result,
                time_limit,
                progress: solve::ProgressMode::from_arg(progress),
                sweep_parent,
                refine: !no_refine,
            };
            solve::solve(&file, &set, out.as_deref(), &run)
        }
        Command::Check {
            file,
            set,
            derivatives,
            at,
            seed,
        } => {
            if derivatives {
                check::check_derivatives(&file, &set, at.as_deref(), seed)
            } else {
                check::check(&file, &set)
            }
        }
        Command::Simulate {
            file,
            set,
            request,
            out,
            quiet,
        } => simulate::simulate(&file, &set, &request.into(), out.as_deref(), quiet),
        Command::Study {
            study:
                StudyKind::BrickAccuracy {
                    problem,
                    seeds,
                    knots,
                    horizon,
                    spin,
                    tilt,
                    methods,
                    out,
                    quiet,
                },
        } => {
            let study = vito::study::brick::BrickAccuracy {
                seeds,
                knots,
                horizon,
                spin,
                tilt,
                methods: methods.methods.clone(),
                reference: methods.reference,
                reference_rate: methods.reference_rate,
            };
            study::brick_accuracy(&problem, &study, &out, quiet)
        }
        Command::Study {
            study:
                StudyKind::Tracking {
                    problem,
                    set,
                    knots,
                    gains,
                    feedback,
                    methods,
                    out,
                    quiet,
                },
        } => {
            let study = vito::study::tracking::Tracking {
                knots,
                gains,
                feedback,
                rate: methods.reference_rate,
                methods: methods.methods.clone(),
                reference: methods.reference,
            };
            study::tracking(&problem, &set, &study, &out, quiet)
        }
        Command::Study {
            study:
                StudyKind::TrackingCollect {
                    dirs,
                    max_deviation,
                    out,
                },
        } => study::tracking_collect(&dirs, max_deviation, &out),
        Command::View {
            dirs,
            problem,
            out,
            strip,
            svg,
            world,
        } => view::view(
            &dirs,
            problem.as_deref(),
            out.as_deref(),
            strip,
            svg.as_deref(),
            if world {
                vito::view::StripLayout::World
            } else {
                vito::view::StripLayout::Panels
            },
        ),
        Command::Init { urdf, base, out } => {
            init::init(&urdf, base.resolve(&urdf)?.0, out.as_deref())
        }
        Command::Inspect { urdf, base, json } => {
            inspect::inspect(&urdf, base.resolve(&urdf)?, json)
        }
        Command::Bench {
            files,
            set,
            no_casadi,
        } => bench::bench(&files, &set, !no_casadi),
        Command::Regress {
            bless,
            record,
            files,
        } => regress::regress(
            &regress::record_path(record.as_deref(), &files),
            &files,
            bless,
        ),
        Command::Sweep { action, run } => match action {
            Some(SweepAction::Report { dir, metric }) => sweep::sweep_report(&dir, &metric),
            Some(SweepAction::Collect { dirs, out, partial }) => {
                sweep::sweep_collect(&dirs, &out, partial)
            }
            None => sweep::sweep(run),
        },
    }
}
