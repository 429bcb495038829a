//! The `vito` command: arguments (clap derive), errors, exit codes and the dispatch here;
//! each subcommand's reading of its arguments and printing of its results in its own file.
//! The work itself is the library's.
//!
//! Exit codes: [`EXIT_CODE_TABLE`].

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use clap::{Parser, Subcommand, ValueEnum};

use vito::discrete::Integrator;
use vito::ipopt::OptionValue;
use vito::model::BaseType;
use vito::pipeline;
use vito::problem::{LoadedProblem, Override, ProblemError, RobotInfo, TimeSteps, load};
use vito::report::{self, status_name};
use vito::transcription::Solution;

/// A closed stdout (`vito check x | head -1`) ends the command quietly with success,
/// like ripgrep; any other write error is left to the caller.
fn exit_quietly_on_broken_pipe(e: &std::io::Error) {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        std::process::exit(0);
    }
}

/// `eprintln!` that escapes control characters and never fails: a standard error that
/// cannot be written (`2> /dev/full`) must not stop a command before its results are
/// written; the failure is remembered and turns the exit code into [`EXIT_OUTPUT`].
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::cli::write_stderr(&format!($($arg)*))
    };
}

/// `println!` that escapes control characters (names from a URDF reach it) and treats a
/// broken pipe as the end of the output; any other write error (a full disk, `> /dev/full`)
/// ends the command with an error.
macro_rules! out {
    ($($arg:tt)*) => {
        write_stdout(&format!($($arg)*))?
    };
}

mod check;
mod interrupt;
mod regress;
mod robot;
mod simulate;
mod solve;
mod study;
mod sweep;
mod view;

use check::*;
use interrupt::*;
use regress::*;
use robot::*;
use simulate::*;
use solve::*;
use study::*;
use sweep::*;
use view::*;

/// Set when standard output or standard error could not be written.
static OUTPUT_FAILED: AtomicBool = AtomicBool::new(false);

/// Writes one line to stderr (see [`note!`]).
pub(crate) fn write_stderr(line: &str) {
    let mut stderr = std::io::stderr().lock();
    if writeln!(stderr, "{}", vito::files::names::escape_controls(line))
        .and_then(|()| stderr.flush())
        .is_err()
    {
        OUTPUT_FAILED.store(true, Ordering::SeqCst);
    }
}

/// Writes one line to stdout (see [`out!`]).
fn write_stdout(line: &str) -> Result<(), CliError> {
    let mut stdout = std::io::stdout().lock();
    let result = writeln!(stdout, "{}", vito::files::names::escape_controls(line))
        .and_then(|()| stdout.flush());
    result.map_err(|e| {
        exit_quietly_on_broken_pipe(&e);
        OUTPUT_FAILED.store(true, Ordering::SeqCst);
        CliError::Output(e.to_string())
    })
}

/// Exit code: solved (check, inspect, regress: passed).
pub const EXIT_OK: u8 = 0;
/// Exit code: finished but not solved.
pub const EXIT_NOT_SOLVED: u8 = 1;
/// Exit code: input or usage error (clap's usage errors are 2 as well).
pub const EXIT_INPUT: u8 = 2;
/// Exit code: internal error (a bug, or the solver failing to start).
pub const EXIT_INTERNAL: u8 = 3;
/// Exit code: standard output or standard error could not be written.
pub const EXIT_OUTPUT: u8 = 4;

/// Every exit code vito returns and what it means: the one table behind `--help` and the
/// README's.
pub const EXIT_CODE_TABLE: [(u8, &str); 5] = [
    (EXIT_OK, "solved (check, inspect, regress: passed)"),
    (
        EXIT_NOT_SOLVED,
        "finished but not solved (not optimal, relaxed_contact); stopped by a signal (Ctrl-C, SIGTERM, SIGHUP); a sweep with a run that did not solve or was stopped; sweep collect with points missing; regress: a result differs",
    ),
    (
        EXIT_INPUT,
        "input or usage error (the message names the file, line and field), found before solving; also a problem regress cannot set up",
    ),
    (EXIT_INTERNAL, "internal error"),
    (
        EXIT_OUTPUT,
        "standard output or error could not be written (a full disk, `> /dev/full`); the result files were written",
    ),
];

/// [`EXIT_CODE_TABLE`] as `--help` prints it.
fn exit_codes_help() -> String {
    let mut text = "Exit codes:".to_owned();
    for (code, meaning) in EXIT_CODE_TABLE {
        text.push_str(&format!("\n  {code}  {meaning}"));
    }
    text
}

/// vito: variational contact-implicit trajectory optimisation for legged robots.
#[derive(Debug, Parser)]
#[command(name = "vito", version = vito::ipopt::LONG_VERSION, about, after_help = exit_codes_help())]
pub struct Args {
    #[command(subcommand)]
    pub command: Command,
}

/// Base joint choice on the command line (`init` and `inspect` alike).
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum BaseArg {
    /// `fixed` when the URDF already moves its root itself (prismatic joints from its root
    /// link, as a planar hopper's x and z), else `floating`.
    Auto,
    Fixed,
    Planar,
    Floating,
}

impl BaseArg {
    /// The base for `urdf`: as asked, or for `auto` by [`vito::model::Model::slides_its_root`].
    fn resolve(self, urdf: &Path) -> Result<BaseType, CliError> {
        Ok(match self {
            BaseArg::Auto => {
                let fixed = vito::model::Model::from_urdf_file(urdf, BaseType::Fixed)
                    .map_err(|e| CliError::Input(vito::model::describe(urdf, &e)))?;
                if fixed.slides_its_root() {
                    BaseType::Fixed
                } else {
                    BaseType::Floating
                }
            }
            BaseArg::Fixed => BaseType::Fixed,
            BaseArg::Planar => BaseType::Planar,
            BaseArg::Floating => BaseType::Floating,
        })
    }
}

/// `--integrator`: the names of [`Integrator::name`], listed in the help, parsed by
/// Integrator's own `FromStr`.
fn integrator_parser() -> impl clap::builder::TypedValueParser<Value = Integrator> {
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(Integrator::ALL.map(Integrator::name))
        .try_map(|name| name.parse::<Integrator>())
}

/// PD feedback choice on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum FeedbackArg {
    Explicit,
    Implicit,
}

impl From<FeedbackArg> for vito::sim::Feedback {
    fn from(f: FeedbackArg) -> Self {
        match f {
            FeedbackArg::Explicit => vito::sim::Feedback::Explicit,
            FeedbackArg::Implicit => vito::sim::Feedback::Implicit,
        }
    }
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Solve a problem file and write trajectory.csv, summary.json and plots.
    #[command(after_help = exit_codes_help())]
    Solve {
        /// Problem file (TOML).
        file: PathBuf,
        /// Override a value of the file before checking it, e.g. `--set slack.weight=1e3`
        /// or `--set contacts.friction=0.5` (repeatable; value parsed as TOML).
        #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
        set: Vec<String>,
        /// Output directory (default: `output.dir` of the file, else `out/<problem name>`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// No live progress lines.
        #[arg(long, short)]
        quiet: bool,
        /// Also write Ipopt's own log (`file_print_level 5`) as `ipopt.log` in the output
        /// directory (with a slack continuation, the last solve's).
        #[arg(long)]
        ipopt_log: bool,
        /// Solve from K starts (the file's guess, then K−1 seeded perturbations of it) and
        /// keep the best feasible; summary.json lists all under `starts`.
        #[arg(long, value_name = "K", default_value_t = 1)]
        starts: usize,
        /// Seed of the multi-start perturbations.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Internal: the process id of the sweep that started this run (the run dies with it).
        #[arg(long, hide = true, value_name = "PID")]
        sweep_parent: Option<u32>,
    },
    /// Simulate a problem file's robot forward with the planner's mechanics and contact model.
    #[command(after_help = exit_codes_help())]
    Simulate {
        /// Problem file (TOML): robot, terrain, contacts, initial state.
        file: PathBuf,
        /// Overrides as for `solve`.
        #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
        set: Vec<String>,
        /// Replay the inputs of a trajectory CSV (zero-order hold); default: zero inputs.
        #[arg(long, conflicts_with = "track")]
        inputs: Option<PathBuf>,
        /// Track a trajectory CSV with PD feedback (its inputs as feedforward).
        #[arg(long)]
        track: Option<PathBuf>,
        /// PD gains by input name, `NAME=KP,KD` or `all=KP,KD` (repeatable; kp in input units
        /// per coordinate unit, kd per coordinate rate), on top of the file's `[tracking] gains`.
        #[arg(long, value_name = "NAME=KP,KD", requires = "track")]
        gains: Vec<String>,
        /// Where the PD reads the state: the step's start (explicit) or end (implicit,
        /// solved with the step; stable at stiff gains) [default: the file's
        /// `[tracking] feedback`, else explicit].
        #[arg(long, value_enum, requires = "track")]
        feedback: Option<FeedbackArg>,
        /// Simulated time (default: the CSV's last time, else the problem's horizon).
        #[arg(long)]
        duration: Option<f64>,
        /// Steps per time unit (default: 1/h of the problem).
        #[arg(long)]
        rate: Option<f64>,
        /// Integrator (default: the problem's).
        #[arg(long, value_parser = integrator_parser())]
        integrator: Option<Integrator>,
        /// Output directory (default: `out/<problem name>-simulate`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Write the animation page of result directories (one, or several overlaid), or a strip
    /// of poses as SVG.
    #[command(after_help = exit_codes_help())]
    View {
        /// Result directories (each with trajectory.csv and summary.json).
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// The problem file (default: each summary's `problem_file`, with its parameters).
        #[arg(long)]
        problem: Option<PathBuf>,
        /// The page to write (default: animation.html in the one directory given).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Poses in the strip (with --svg).
        #[arg(long, requires = "svg")]
        strip: Option<usize>,
        /// Write the strip as SVG (an orthographic side view) to this file.
        #[arg(long, requires = "strip")]
        svg: Option<PathBuf>,
    },
    /// The paper's accuracy studies: first-order against variational time stepping.
    #[command(after_help = exit_codes_help())]
    Study {
        #[command(subcommand)]
        study: StudyKind,
    },
    /// Check a problem file without solving and print its size.
    #[command(after_help = exit_codes_help())]
    Check {
        /// Problem file (TOML).
        file: PathBuf,
        /// Overrides as for `solve`.
        #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
        set: Vec<String>,
        /// Compare the gradient, Jacobian and Lagrangian Hessian with central finite
        /// differences (exit 1 when an entry exceeds its tolerance).
        #[arg(long)]
        derivatives: bool,
        /// With `--derivatives`: check at this trajectory CSV (one row per knot) instead of
        /// the initial guess.
        #[arg(long, value_name = "TRAJECTORY_CSV", requires = "derivatives")]
        at: Option<PathBuf>,
        /// With `--derivatives`: seed of the random multipliers of the Hessian check.
        #[arg(long, default_value_t = 1, requires = "derivatives")]
        seed: u64,
    },
    /// Write a commented starter problem for a URDF (to stdout, or to `--out`).
    Init {
        /// Robot model (URDF).
        urdf: PathBuf,
        /// Base joint [default: auto: fixed when the URDF already moves its root itself
        /// (prismatic joints from its root link, like the planar hopper's x and z: a free base
        /// would add coordinates it already has), else floating (a legged robot's torso)].
        #[arg(long, value_enum, default_value = "auto", hide_default_value = true)]
        base: BaseArg,
        /// File to write (refuses to overwrite an existing one).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Print what vito reads from a URDF: coordinates, inputs, limits, springs, contacts.
    Inspect {
        /// Robot model (URDF).
        urdf: PathBuf,
        /// Base joint [default: auto: fixed when the URDF already moves its root itself
        /// (prismatic joints from its root link, like the planar hopper's x and z: a free base
        /// would add coordinates it already has), else floating (a legged robot's torso)].
        #[arg(long, value_enum, default_value = "auto", hide_default_value = true)]
        base: BaseArg,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Time the NLP callbacks of problems and print a table (default: the reference problems).
    Bench {
        /// Problem files (default: problems/{hopper_2d,brick_3d,spring_flamingo_walk,littledog_step}.toml).
        files: Vec<PathBuf>,
        /// Override a value of every file, e.g. `--set horizon.knots=40` (repeatable).
        #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
        set: Vec<String>,
        /// Leave out the side-by-side CasADi solves (tools/independent/spec_casadi.py), which
        /// otherwise run for the reference problems when Python imports casadi.
        #[arg(long)]
        no_casadi: bool,
    },
    /// Solve a problem over a grid of values, each run in its own process; resumable.
    #[command(
        after_help = "Examples:\n  vito sweep problems/hopper_2d.toml --grid contacts.friction=0.3,0.8 --grid slack.weight=10,100 --out out/sweep\n  vito sweep report out/sweep --metric objective\n  vito sweep collect out/shard-0 out/shard-1 --out out/all\n\nExit codes: 0 every run finished and solved, 1 some run failed, timed out, did not solve or was stopped by a signal (collect: points missing, without --partial), 2 input or usage error, 3 internal error",
        args_conflicts_with_subcommands = true,
        subcommand_negates_reqs = true
    )]
    Sweep {
        #[command(subcommand)]
        action: Option<SweepAction>,
        #[command(flatten)]
        run: SweepRunArgs,
    },
    /// Solve every problem of a regression record and compare status, objective and max
    /// slack; `--bless` rewrites it.
    #[command(after_help = exit_codes_help())]
    Regress {
        /// Rewrite the record with the new results (atomically).
        #[arg(long)]
        bless: bool,
        /// The regression record [default: `golden.toml` beside the first FILE, else
        /// problems/golden.toml].
        #[arg(long)]
        record: Option<PathBuf>,
        /// Problems to check or add (relative to the working directory); default: the record's.
        files: Vec<PathBuf>,
    },
}

/// `vito study ...`.
#[derive(Debug, Subcommand)]
pub enum StudyKind {
    /// Figure 5: a tumbling brick from seeded random states, each method at K knots over the
    /// horizon (h = T/(K − 1)) against a first-order reference at 2 kHz; RMS configuration
    /// error per K and method (brick_accuracy.csv, brick_accuracy_runs.csv, brick_accuracy.svg).
    BrickAccuracy {
        /// The brick's problem file (robot, contacts, terrain, gravity; its initial state is
        /// replaced by the seeded ones).
        #[arg(long, default_value = "problems/brick_3d.toml")]
        problem: PathBuf,
        /// Random initial states (seeds 0..N).
        #[arg(long, default_value_t = 20)]
        seeds: usize,
        /// Knot counts (comma-separated).
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "3,4,5,6,7,8,9,10,11,12,13,14,15,16"
        )]
        knots: Vec<usize>,
        /// Horizon T (s).
        #[arg(long, default_value_t = 0.5)]
        horizon: f64,
        /// Largest initial rate of each roll–pitch–yaw angle (rad/s).
        #[arg(long, default_value_t = 0.5)]
        spin: f64,
        /// Largest initial roll and pitch (rad).
        #[arg(long, default_value_t = 0.2)]
        tilt: f64,
        /// Output directory.
        #[arg(long, default_value = "out/brick_accuracy")]
        out: PathBuf,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Figure 6: plans of a problem solved at K knots by each method, each tracked by PD
    /// feedback (the plan's inputs as feedforward) in a first-order simulation at 2 kHz; RMS
    /// state error per K and method (tracking.csv, tracking_runs.csv, tracking.svg, the
    /// plans' records in tracking_plans.csv and trajectories in plans/). One gait: the
    /// smallest K's variational plan starts from the file's guess, each next K's from the
    /// previous one, the first-order plan at each K from the variational plan at that K.
    Tracking {
        /// The problem file planned (its horizon kept: a fixed step becomes T/(K − 1)).
        #[arg(long, default_value = "problems/hopper_2d.toml")]
        problem: PathBuf,
        /// Overrides of the problem, as for `solve` (repeatable).
        #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
        set: Vec<String>,
        /// Knot counts (comma-separated).
        #[arg(long, value_delimiter = ',', default_value = "10,15,20,25,30,35,40")]
        knots: Vec<usize>,
        /// PD gains by input name, `NAME=KP,KD` or `all=KP,KD` (repeatable), on top of the
        /// file's `[tracking] gains` [default without either: all=100,10].
        #[arg(long, value_name = "NAME=KP,KD")]
        gains: Vec<String>,
        /// Where the PD reads the state [default: the file's `[tracking] feedback`, else
        /// explicit]; see `vito simulate --feedback`.
        #[arg(long, value_enum)]
        feedback: Option<FeedbackArg>,
        /// Output directory.
        #[arg(long, default_value = "out/tracking")]
        out: PathBuf,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Figure 6 over a set of gaits ("a set of walking trajectories"): reads the output
    /// directories of several `vito study tracking` runs (one gait each, run in parallel or
    /// as array tasks) into one table per measure, mean ± std over the gaits at each K and
    /// method (tracking.csv, tracking_configuration.csv, tracking_joints.csv, their runs and
    /// SVGs), every plan in tracking_plans.csv with its gait, and the falls: plans whose
    /// simulated robot left its plan by more than --max-deviation (tracking_falls.csv), and
    /// the state error over the others (tracking_upright.csv and .svg).
    #[command(
        after_help = "Example:\n  vito study tracking --problem problems/littledog_walk.toml --set final.q.base_x=0.15 --out out/walk/x0.15 &\n  vito study tracking --problem problems/littledog_walk.toml --set final.q.base_x=0.25 --out out/walk/x0.25 &\n  wait; vito study tracking-collect out/walk/x0.15 out/walk/x0.25 --out out/walk/all"
    )]
    TrackingCollect {
        /// The gaits' study directories (each written by `vito study tracking`; its name is
        /// the gait's).
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// A plan whose simulation leaves it by more than this in any coordinate (problem
        /// units: m, rad) counts as fallen.
        #[arg(long, default_value_t = 0.5)]
        max_deviation: f64,
        /// Output directory.
        #[arg(long, default_value = "out/tracking_set")]
        out: PathBuf,
    },
}

/// `vito sweep FILE --grid ...`.
#[derive(Debug, clap::Args)]
pub struct SweepRunArgs {
    /// Problem file (TOML).
    #[arg(required = true)]
    file: Option<PathBuf>,
    /// A swept key and its values: any `--set` key or family parameter (repeatable; the
    /// grid is the product, the last --grid varying fastest).
    #[arg(long, value_name = "KEY=V1,V2,...", required = true)]
    grid: Vec<String>,
    /// Overrides for every run, as for `solve` (repeatable).
    #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
    set: Vec<String>,
    /// Runs at a time (default: the number of cores).
    #[arg(long)]
    jobs: Option<usize>,
    /// Sweep directory: the table and each run's own directory (default: out/sweep-<file stem>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Per-run wall-time limit in seconds; a run still going then is killed (status timeout).
    #[arg(long, value_name = "S")]
    time_limit: Option<f64>,
    /// Run a deterministic part of the grid: the points whose index is I mod N
    /// (Slurm: --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT).
    #[arg(long, value_name = "I/N")]
    shard: Option<String>,
    /// `neighbour`: start each run from the trajectory of its nearest finished grid point.
    #[arg(long, value_enum, default_value = "none")]
    warm_start: WarmStartArg,
}

/// `--warm-start` of a sweep.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum WarmStartArg {
    None,
    Neighbour,
}

/// `vito sweep report` and `vito sweep collect`.
#[derive(Debug, Subcommand)]
pub enum SweepAction {
    /// Print a sweep's table and write an SVG of one metric over the grid.
    Report {
        /// The sweep directory (holding sweep.json).
        dir: PathBuf,
        /// The column to plot: objective, iterations, wall_time_s, max_slack or a metric.
        #[arg(long, default_value = "objective")]
        metric: String,
    },
    /// Merge the tables of sweep shards into one table (sweep.json, sweep.csv) in --out.
    Collect {
        /// The shards' sweep directories.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Directory for the merged table.
        #[arg(long)]
        out: PathBuf,
        /// Exit 0 even when points have no result (without it: exit 1 naming them).
        #[arg(long)]
        partial: bool,
    },
}

/// Everything that ends a command early; the variant decides the exit code.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    #[error(transparent)]
    Problem(#[from] ProblemError),
    #[error("{0}")]
    Input(String),
    #[error(transparent)]
    Report(#[from] report::ReportError),
    #[error(transparent)]
    Golden(#[from] report::GoldenError),
    #[error("internal error: {0}")]
    Internal(String),
    #[error("cannot write to standard output: {0}")]
    Output(String),
    #[error(transparent)]
    Sweep(#[from] vito::sweep::SweepError),
    #[error("simulation stopped: {0}")]
    Simulation(#[from] vito::sim::SimulationError),
    #[error(transparent)]
    Transcription(#[from] vito::transcription::TranscriptionError),
    #[error("study: {0}")]
    Study(#[from] vito::study::StudyError),
}

impl CliError {
    /// Exit code: 2 for input errors, 3 for internal ones.
    pub fn exit_code(&self) -> u8 {
        match self {
            // Like an output directory that cannot be written: the user's redirection.
            CliError::Problem(_) | CliError::Input(_) | CliError::Golden(_) => EXIT_INPUT,
            CliError::Output(_) => EXIT_OUTPUT,
            CliError::Transcription(e) => match e {
                vito::transcription::TranscriptionError::Solver(_) => 3,
                _ => 2,
            },
            // A target vito may not replace is the user's input, found before solving.
            CliError::Report(report::ReportError::Output(
                report::OutputDirError::NotOurs { .. }
                | report::OutputDirError::Protected { .. }
                | report::OutputDirError::Invalid { .. },
            )) => 2,
            CliError::Sweep(e) => match e {
                vito::sweep::SweepError::Usage(_)
                | vito::sweep::SweepError::NotOurs { .. }
                | vito::sweep::SweepError::Link { .. }
                | vito::sweep::SweepError::NoTable { .. }
                | vito::sweep::SweepError::Table { .. } => 2,
                _ => 3,
            },
            CliError::Report(_) | CliError::Internal(_) => 3,
            CliError::Simulation(_) => 1,
            CliError::Study(e) => match e {
                vito::study::StudyError::Invalid { .. }
                | vito::study::StudyError::Transcription(_) => 2,
                vito::study::StudyError::Write { .. } => 3,
                _ => 1,
            },
        }
    }
}

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
            sweep_parent,
        } => {
            if starts == 0 {
                return Err(CliError::Input("--starts 0: give at least 1".into()));
            }
            let multi_start = vito::transcription::MultiStart { starts, seed };
            solve(
                &file,
                &set,
                out.as_deref(),
                quiet,
                ipopt_log,
                multi_start,
                sweep_parent,
            )
        }
        Command::Check {
            file,
            set,
            derivatives,
            at,
            seed,
        } => {
            if derivatives {
                check_derivatives(&file, &set, at.as_deref(), seed)
            } else {
                check(&file, &set)
            }
        }
        Command::Simulate {
            file,
            set,
            inputs,
            track,
            gains,
            feedback,
            duration,
            rate,
            integrator,
            out,
            quiet,
        } => {
            let request = pipeline::SimulateRequest {
                inputs,
                track,
                gains,
                feedback: feedback.map(Into::into),
                duration,
                rate,
                integrator,
            };
            simulate(&file, &set, &request, out.as_deref(), quiet)
        }
        Command::Study {
            study:
                StudyKind::BrickAccuracy {
                    problem,
                    seeds,
                    knots,
                    horizon,
                    spin,
                    tilt,
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
                ..Default::default()
            };
            brick_accuracy(&problem, &study, &out, quiet)
        }
        Command::Study {
            study:
                StudyKind::Tracking {
                    problem,
                    set,
                    knots,
                    gains,
                    feedback,
                    out,
                    quiet,
                },
        } => {
            let study = vito::study::tracking::Tracking {
                knots,
                gains,
                feedback: feedback.map(Into::into),
                rate: 2000.0,
            };
            tracking(&problem, &set, &study, &out, quiet)
        }
        Command::Study {
            study:
                StudyKind::TrackingCollect {
                    dirs,
                    max_deviation,
                    out,
                },
        } => tracking_collect(&dirs, max_deviation, &out),
        Command::View {
            dirs,
            problem,
            out,
            strip,
            svg,
        } => view(
            &dirs,
            problem.as_deref(),
            out.as_deref(),
            strip,
            svg.as_deref(),
        ),
        Command::Init { urdf, base, out } => init(&urdf, base.resolve(&urdf)?, out.as_deref()),
        Command::Inspect { urdf, base, json } => inspect(&urdf, base.resolve(&urdf)?, json),
        Command::Bench {
            files,
            set,
            no_casadi,
        } => bench(&files, &set, !no_casadi),
        Command::Regress {
            bless,
            record,
            files,
        } => regress(&record_path(record.as_deref(), &files), &files, bless),
        Command::Sweep { action, run } => match action {
            Some(SweepAction::Report { dir, metric }) => sweep_report(&dir, &metric),
            Some(SweepAction::Collect { dirs, out, partial }) => {
                sweep_collect(&dirs, &out, partial)
            }
            None => sweep(run),
        },
    }
}

fn print_error(e: &CliError) {
    let mut message = format!("error: {e}");
    let mut source = std::error::Error::source(e);
    while let Some(s) = source {
        let text = s.to_string();
        if !message.contains(&text) {
            message.push_str(&format!("\n  caused by: {text}"));
        }
        source = s.source();
    }
    write_stderr(&message);
}

fn parse_overrides(set: &[String]) -> Result<Vec<Override>, CliError> {
    Ok(set
        .iter()
        .map(|s| Override::parse(s))
        .collect::<Result<_, _>>()?)
}

/// The URDF reader's warnings (repairs, ignored elements), on stderr.
fn print_model_warnings(robot: &RobotInfo) {
    for w in &robot.warnings {
        note!("warning: {}: {w}", robot.urdf.display());
    }
}
