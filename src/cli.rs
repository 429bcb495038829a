//! The `vito` command: arguments (clap derive), the subcommands, and exit codes.
//!
//! Exit codes: 0 solved (or check/inspect/regress passed), 1 solved but not optimal (or a
//! regression differs), 2 input or usage error, 3 internal error.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use clap::{Parser, Subcommand, ValueEnum};

use vito::model::BaseType;
use vito::pipeline;
use vito::problem::{
    LoadedProblem, OptionValue, Override, ProblemError, RobotInfo, TimeSteps, load,
};
use vito::report::{self, is_solved, status_name};
use vito::transcription::Solution;

/// A closed stdout (`vito check x | head -1`) ends the command quietly with success,
/// like ripgrep; any other write error is left to the caller.
fn exit_quietly_on_broken_pipe(e: &std::io::Error) {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        std::process::exit(0);
    }
}

/// `println!` that escapes control characters (names from a URDF reach it) and treats a
/// broken pipe as the end of the output; any other write error (a full disk, `> /dev/full`)
/// ends the command with an error.
macro_rules! out {
    ($($arg:tt)*) => {
        write_stdout(&format!($($arg)*))?
    };
}

/// Writes one line to stdout (see [`out!`]).
fn write_stdout(line: &str) -> Result<(), CliError> {
    let mut stdout = std::io::stdout().lock();
    let result =
        writeln!(stdout, "{}", vito::names::escape_controls(line)).and_then(|()| stdout.flush());
    result.map_err(|e| {
        exit_quietly_on_broken_pipe(&e);
        CliError::Output(e.to_string())
    })
}

const EXIT_CODES: &str = "Exit codes:\n  0  solved (check, inspect, regress: passed)\n  1  finished but not optimal (or stopped with Ctrl-C; regress: a result differs)\n  2  input or usage error (the message names the file, line and field)\n  3  internal error";

/// vito: variational contact-implicit trajectory optimisation for legged robots.
#[derive(Debug, Parser)]
#[command(name = "vito", version = vito::ipopt::LONG_VERSION, about, after_help = EXIT_CODES)]
pub struct Args {
    #[command(subcommand)]
    pub command: Command,
}

/// Base joint choice on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum BaseArg {
    Fixed,
    Planar,
    Floating,
}

impl From<BaseArg> for BaseType {
    fn from(b: BaseArg) -> BaseType {
        match b {
            BaseArg::Fixed => BaseType::Fixed,
            BaseArg::Planar => BaseType::Planar,
            BaseArg::Floating => BaseType::Floating,
        }
    }
}

/// Integrator choice on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum IntegratorArg {
    Midpoint,
    Euler,
}

impl From<IntegratorArg> for vito::discrete::Integrator {
    fn from(i: IntegratorArg) -> Self {
        match i {
            IntegratorArg::Midpoint => vito::discrete::Integrator::Midpoint,
            IntegratorArg::Euler => vito::discrete::Integrator::Euler,
        }
    }
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Solve a problem file and write trajectory.csv, summary.json and plots.
    #[command(after_help = EXIT_CODES)]
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
    },
    /// Simulate a problem file's robot forward with the planner's mechanics and contact model.
    #[command(after_help = EXIT_CODES)]
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
        #[arg(long, requires = "gains")]
        track: Option<PathBuf>,
        /// PD gains by input name, `NAME=KP,KD` or `all=KP,KD` (repeatable).
        #[arg(long, value_name = "NAME=KP,KD", requires = "track")]
        gains: Vec<String>,
        /// Simulated time (default: the CSV's last time, else the problem's horizon).
        #[arg(long)]
        duration: Option<f64>,
        /// Steps per time unit (default: 1/h of the problem).
        #[arg(long)]
        rate: Option<f64>,
        /// Integrator (default: the problem's).
        #[arg(long, value_enum)]
        integrator: Option<IntegratorArg>,
        /// Output directory (default: `out/<problem name>-simulate`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
    },
    /// The paper's accuracy studies: first-order against variational time stepping.
    #[command(after_help = EXIT_CODES)]
    Study {
        #[command(subcommand)]
        study: StudyKind,
    },
    /// Check a problem file without solving and print its size.
    #[command(after_help = EXIT_CODES)]
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
        /// Base joint.
        #[arg(long, value_enum, default_value = "floating")]
        base: BaseArg,
        /// File to write (refuses to overwrite an existing one).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Print what vito reads from a URDF: coordinates, inputs, limits, springs, contacts.
    Inspect {
        /// Robot model (URDF).
        urdf: PathBuf,
        /// Base joint.
        #[arg(long, value_enum, default_value = "fixed")]
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
    },
    /// Solve a problem over a grid of values, each run in its own process; resumable.
    #[command(
        after_help = "Examples:\n  vito sweep problems/hopper_2d.toml --grid contacts.friction=0.3,0.8 --grid slack.weight=10,100 --out out/sweep\n  vito sweep report out/sweep --metric objective\n  vito sweep collect out/shard-0 out/shard-1 --out out/all\n\nExit codes: 0 every run finished and solved, 1 some run failed, timed out or did not solve, 2 input or usage error, 3 internal error",
        args_conflicts_with_subcommands = true,
        subcommand_negates_reqs = true
    )]
    Sweep {
        #[command(subcommand)]
        action: Option<SweepAction>,
        #[command(flatten)]
        run: SweepRunArgs,
    },
    /// Solve every problem of the regression record and compare objectives; `--bless` rewrites it.
    #[command(after_help = EXIT_CODES)]
    Regress {
        /// Rewrite the record with the new results (atomically).
        #[arg(long)]
        bless: bool,
        /// The regression record.
        #[arg(long, default_value = "problems/golden.toml")]
        record: PathBuf,
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
    /// state error per K and method (tracking.csv, tracking_runs.csv, tracking.svg).
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
        /// PD gains by input name, `NAME=KP,KD` or `all=KP,KD` (repeatable).
        #[arg(long, value_name = "NAME=KP,KD", default_values_t = ["all=100,10".to_string()])]
        gains: Vec<String>,
        /// Output directory.
        #[arg(long, default_value = "out/tracking")]
        out: PathBuf,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
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
            CliError::Problem(_)
            | CliError::Input(_)
            | CliError::Golden(_)
            | CliError::Output(_) => 2,
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
        } => {
            if starts == 0 {
                return Err(CliError::Input("--starts 0: give at least 1".into()));
            }
            let multi_start = vito::transcription::MultiStart { starts, seed };
            solve(&file, &set, out.as_deref(), quiet, ipopt_log, multi_start)
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
                duration,
                rate,
                integrator: integrator.map(Into::into),
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
                    out,
                    quiet,
                },
        } => {
            let study = vito::study::tracking::Tracking {
                knots,
                gains,
                rate: 2000.0,
            };
            tracking(&problem, &set, &study, &out, quiet)
        }
        Command::Init { urdf, base, out } => init(&urdf, base.into(), out.as_deref()),
        Command::Inspect { urdf, base, json } => inspect(&urdf, base.into(), json),
        Command::Bench { files, set } => bench(&files, &set),
        Command::Regress {
            bless,
            record,
            files,
        } => regress(&record, &files, bless),
        Command::Sweep { action, run } => match action {
            Some(SweepAction::Report { dir, metric }) => sweep_report(&dir, &metric),
            Some(SweepAction::Collect { dirs, out }) => sweep_collect(&dirs, &out),
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
    let _ = writeln!(
        std::io::stderr(),
        "{}",
        vito::names::escape_controls(&message)
    );
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
        eprintln!(
            "{}",
            vito::names::escape_controls(&format!("warning: {}: {w}", robot.urdf.display()))
        );
    }
}

fn check(file: &Path, set: &[String]) -> Result<u8, CliError> {
    let overrides = parse_overrides(set)?;
    let p = load(file, &overrides)?;
    print_model_warnings(&p.robot);
    pipeline::check_solver_options(&p)?;
    let s = &p.spec;
    let nlp = pipeline::build_nlp(s)?;
    let size = nlp.size();
    let horizon = match s.time_steps {
        TimeSteps::Fixed(h) => format!(
            "{} knots, fixed h = {h} {t} (T = {} {t})",
            s.knots,
            h * (s.knots - 1) as f64,
            t = p.units.time
        ),
        TimeSteps::FreeEqual { t_min, t_max } => format!(
            "{} knots, free equal steps, T in [{t_min}, {t_max}] {}",
            s.knots, p.units.time
        ),
    };
    out!("{}: ok ({})", file.display(), s.name);
    if let Some(d) = &p.description {
        out!("  {}", d.trim());
    }
    out!(
        "  robot:       {} ({:?} base)",
        s.robot.urdf.display(),
        s.robot.base
    );
    out!(
        "  coordinates: {} ({})",
        p.robot.coordinates.len(),
        p.robot.coordinates.join(", ")
    );
    out!(
        "  inputs:      {} ({}), from {}",
        p.robot.inputs.len(),
        p.robot.inputs.join(", "),
        p.robot.actuation
    );
    let contacts: Vec<String> = s
        .contacts
        .iter()
        .map(|c| format!("{} (mu {})", c.name, c.friction))
        .collect();
    out!(
        "  contacts:    {} ({})",
        s.contacts.len(),
        contacts.join(", ")
    );
    out!("  horizon:     {horizon}");
    out!(
        "  costs:       {} terms, slack weight {}",
        s.costs.len(),
        s.slack_weight
    );
    out!(
        "  NLP size:    {} variables, {} constraints, nnz J {}, nnz H {} ({} friction directions per contact, {} loop-closure rows per interval)",
        size.n_variables,
        size.n_constraints,
        size.nnz_jacobian,
        size.nnz_hessian,
        nlp.layout().nd,
        nlp.layout().nl
    );
    let feasibility = pipeline::feasibility(s, &nlp);
    if !feasibility.clearances.is_empty() {
        out!(
            "  distance to the terrain [{}], first / last knot of the initial guess:",
            p.units.length
        );
        for c in &feasibility.clearances {
            out!("    {:<20} {:>11.4e} / {:.4e}", c.name, c.first, c.last);
        }
    }
    for w in &feasibility.warnings {
        eprintln!("{}", vito::names::escape_controls(&format!("warning: {w}")));
    }
    Ok(0)
}

/// `vito check --derivatives`: the derivative check of the solver's NLP at the initial guess
/// or at a trajectory; prints the worst entries of each kind and every failure (up to 40).
fn check_derivatives(
    file: &Path,
    set: &[String],
    at: Option<&Path>,
    seed: u64,
) -> Result<u8, CliError> {
    use vito::transcription::{DerivativeKind, EntryNames};
    let overrides = parse_overrides(set)?;
    let p = load(file, &overrides)?;
    let nlp = pipeline::build_nlp(&p.spec)?;
    let contacts: Vec<String> = p.spec.contacts.iter().map(|c| c.name.clone()).collect();
    let x = match at {
        None => nlp.initial_point().to_vec(),
        Some(path) => {
            let text = vito::input::read_regular_text(path, vito::input::MAX_TEXT_BYTES)
                .map_err(|e| CliError::Input(format!("{}: {e}", path.display())))?;
            pipeline::point_from_trajectory(&nlp, &p.robot, &contacts, &text)
                .map_err(|e| CliError::Input(format!("{}: {e}", path.display())))?
        }
    };
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(CliError::Input(format!(
            "the point to check has a non-finite value at variable {i}"
        )));
    }
    let names = EntryNames {
        coordinates: &p.robot.coordinates,
        inputs: &p.robot.inputs,
        contacts: &contacts,
    };
    let check = nlp.check_derivatives(&x, seed);
    let point = at.map_or("the initial guess".to_string(), |a| a.display().to_string());
    out!(
        "{}: derivative check at {point} ({} entries compared, {} fixed variables left out, {} evaluations, multiplier seed {seed})",
        file.display(),
        check.entries.len(),
        check.fixed_variables,
        check.evaluations
    );
    out!(
        "  tolerance: |analytic - fd| <= 1e-4 max(|analytic|, |fd|) + 1e-6 max(1, |F(x)|), steps 1e-6 max(1, |x_j|)"
    );
    for (kind, label) in [
        (DerivativeKind::Gradient, "gradient"),
        (DerivativeKind::Jacobian, "jacobian"),
        (DerivativeKind::Hessian, "hessian"),
    ] {
        let entries: Vec<_> = check.entries.iter().filter(|e| e.kind == kind).collect();
        let failed = entries.iter().filter(|e| e.fails()).count();
        let outside = entries.iter().filter(|e| !e.declared && e.fails()).count();
        out!(
            "  {label}: {} nonzero entries, {failed} exceed tolerance ({outside} outside the declared structure); worst:",
            entries.len()
        );
        for e in entries.iter().take(3) {
            out!("    {}", nlp.describe_entry(e, names));
        }
    }
    let failures: Vec<_> = check.failures().collect();
    if failures.is_empty() {
        out!("  passed");
        return Ok(0);
    }
    out!("  FAILED: {} entries exceed tolerance:", failures.len());
    for e in failures.iter().take(40) {
        out!("    {}", nlp.describe_entry(e, names));
    }
    Ok(1)
}

/// Progress line printed on stderr at each Ipopt iteration.
pub fn progress_line(
    iteration: usize,
    objective: f64,
    inf_pr: f64,
    inf_du: f64,
    max_slack: f64,
) -> String {
    format!("{iteration:>5}  {objective:>14.7e}  {inf_pr:>9.2e}  {inf_du:>9.2e}  {max_slack:>9.2e}")
}

fn solve(
    file: &Path,
    set: &[String],
    out: Option<&Path>,
    quiet: bool,
    ipopt_log: bool,
    multi_start: vito::transcription::MultiStart,
) -> Result<u8, CliError> {
    vito::sweep::die_with_sweep();
    let overrides = parse_overrides(set)?;
    let problem = load(file, &overrides)?;
    print_model_warnings(&problem.robot);
    pipeline::check_solver_options(&problem)?;
    let target = pipeline::checked_output_dir(&problem, out).map_err(report::ReportError::from)?;
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
    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        // First Ctrl-C: stop at the next iteration and write the best iterate. A second one
        // exits at once (exit 1) without writing, leaving any previous output untouched.
        // A second handler cannot be installed in one process; ignoring that error keeps the
        // first (which sets the same kind of flag) in place.
        let _ = ctrlc::set_handler(move || {
            if cancel.swap(true, Ordering::SeqCst) {
                eprintln!("interrupted again: exiting without writing results");
                std::process::exit(1);
            }
            eprintln!("interrupted: stopping after this iteration (Ctrl-C again to quit now)");
        });
    }
    if !quiet {
        if let vito::problem::InitialGuess::Simulation(g) = &problem.spec.initial_guess {
            eprintln!(
                "simulating the initial guess: {} periods of {} {} on {} knots",
                g.cycles, g.period, problem.units.time, problem.spec.knots
            );
        }
        eprintln!(
            "solving {} ({} knots)",
            problem.spec.name, problem.spec.knots
        );
        eprintln!(" iter       objective     inf_pr     inf_du  max_slack");
    }
    let solution = run_solver(&problem, cancel.clone(), quiet, ipopt_options, multi_start)?;
    let staged = match staged {
        Some(staged) => staged,
        None => target.stage().map_err(report::ReportError::from)?,
    };
    let written = report::write_outputs(staged, &problem, &solution)?;
    print_summary(&problem, &solution, &written)?;
    Ok(if is_solved(solution.status) { 0 } else { 1 })
}

fn simulate(
    file: &Path,
    set: &[String],
    request: &pipeline::SimulateRequest,
    out: Option<&Path>,
    quiet: bool,
) -> Result<u8, CliError> {
    let overrides = parse_overrides(set)?;
    let problem = load(file, &overrides)?;
    let prepared = pipeline::prepare_simulation(&problem, request)?;
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
    let start = std::time::Instant::now();
    let sim = pipeline::run_simulation(&prepared, |_| bar.inc(1));
    bar.finish_and_clear();
    let sim = sim?;
    let wall = start.elapsed().as_secs_f64();
    let energies = pipeline::conservative_energies(&prepared, &sim);
    let summary = report::simulation_summary_json(
        &problem,
        &sim,
        prepared.options.integrator,
        energies.as_deref(),
        wall,
    );
    let columns = report::SimulationColumns::new(&problem, &sim, prepared.ctx.nd());
    let staged = target.stage().map_err(report::ReportError::from)?;
    let written =
        report::write_trajectory_outputs(staged, &problem, &columns.trajectory(&sim), &summary)?;
    out!("problem        {}", problem.spec.name);
    out!(
        "steps          {steps} of h = {} {} ({:?})",
        prepared.options.h,
        problem.units.time,
        prepared.options.integrator
    );
    let largest = |v: &[f64]| v.iter().cloned().fold(0.0_f64, f64::max);
    out!("max residual   {:.3e}", largest(&sim.dynamics_residual));
    out!("max compl.     {:.3e}", largest(&sim.complementarity));
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
        1e6 * wall / steps as f64,
        summary["newton_iterations"]["mean"]
    );
    out!("written to     {}", written.display());
    Ok(0)
}

/// A progress bar counting runs (hidden when `quiet`).
fn study_bar(quiet: bool, what: &str) -> indicatif::ProgressBar {
    let bar = if quiet {
        indicatif::ProgressBar::hidden()
    } else {
        indicatif::ProgressBar::new(0)
    };
    if let Ok(style) = indicatif::ProgressStyle::with_template(&format!(
        "{what} {{bar:40}} {{pos}}/{{len}} runs, ETA {{eta}}"
    )) {
        bar.set_style(style);
    }
    bar
}

/// Prints a study's table with each method's log-log slope of error against knot count.
fn print_study(table: &vito::study::StudyTable) -> Result<(), CliError> {
    use vito::study::{Method, log_log_slope};
    out!("knots  first_order mean ± std     variational mean ± std");
    let mut knots: Vec<usize> = table.rows.iter().map(|r| r.knots).collect();
    knots.dedup();
    for k in knots {
        let cell = |m| {
            table.row(k, m).map_or_else(String::new, |r| {
                format!("{:.4e} ± {:.2e}", r.mean(), r.std())
            })
        };
        out!(
            "{k:>5}  {:<26} {}",
            cell(Method::FirstOrder),
            cell(Method::Variational)
        );
    }
    for m in Method::BOTH {
        if let Some(slope) = log_log_slope(&table.means(m)) {
            out!("{:<12} log-log slope {slope:.3}", m.name());
        }
    }
    Ok(())
}

fn brick_accuracy(
    file: &Path,
    study: &vito::study::brick::BrickAccuracy,
    out: &Path,
    quiet: bool,
) -> Result<u8, CliError> {
    study.check()?;
    let problem = load(file, &[])?;
    let protected = [problem.file.as_path(), problem.spec.robot.urdf.as_path()];
    let target = report::OutputTarget::check(out, &protected).map_err(report::ReportError::from)?;
    let bar = study_bar(quiet, "brick study");
    let table = study.run(&problem.spec, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    let table = table?;
    let staged = target.stage().map_err(report::ReportError::from)?;
    table.write(
        staged.path(),
        "brick_accuracy",
        "Tumbling brick: RMS configuration error against the 2 kHz first-order reference",
        "RMS error (m, rad)",
    )?;
    let written = staged.commit().map_err(report::ReportError::from)?;
    print_study(&table)?;
    out!("written to {}", written.display());
    Ok(0)
}

fn tracking(
    file: &Path,
    set: &[String],
    study: &vito::study::tracking::Tracking,
    out: &Path,
    quiet: bool,
) -> Result<u8, CliError> {
    study.check()?;
    let overrides = parse_overrides(set)?;
    let problem = load(file, &overrides)?;
    let protected = [problem.file.as_path(), problem.spec.robot.urdf.as_path()];
    let target = report::OutputTarget::check(out, &protected).map_err(report::ReportError::from)?;
    let bar = study_bar(quiet, "tracking study");
    let table = study.run(file, &overrides, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    let result = table?;
    let table = &result.table;
    let staged = target.stage().map_err(report::ReportError::from)?;
    let plans_csv = staged.path().join("tracking_plans.csv");
    report::write_file_atomic(&plans_csv, result.plans_csv().as_bytes())
        .map_err(|e| CliError::Internal(format!("{}: {e}", plans_csv.display())))?;
    table.write(
        staged.path(),
        "tracking",
        &format!(
            "{}: RMS state error of PD tracking at 2 kHz",
            problem.spec.name
        ),
        "RMS state error (q and v, problem units)",
    )?;
    let written = staged.commit().map_err(report::ReportError::from)?;
    print_study(table)?;
    for p in &result.plans {
        out!(
            "plan {:>3} knots {:<12} objective {:.6e}, max slack {:.2e}, {} iterations",
            p.knots,
            p.method.name(),
            p.objective,
            p.max_slack,
            p.iterations
        );
    }
    out!("written to {}", written.display());
    Ok(0)
}

/// Calls the transcription's solver with live progress (stderr) and the cancel flag.
fn run_solver(
    problem: &LoadedProblem,
    cancel: Arc<AtomicBool>,
    quiet: bool,
    ipopt_options: Vec<(String, OptionValue)>,
    multi_start: vito::transcription::MultiStart,
) -> Result<Solution, CliError> {
    let progress = move |p: &vito::transcription::Progress| {
        if !quiet {
            eprintln!(
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

fn print_summary(problem: &LoadedProblem, s: &Solution, dir: &Path) -> Result<(), CliError> {
    out!("problem      {}", problem.spec.name);
    out!("status       {}", status_name(s.status));
    out!("objective    {:.10e}", s.objective);
    for (name, value) in &s.objective_terms {
        out!("  {name:<22} {value:.6e}");
    }
    out!("iterations   {}", s.iterations);
    out!(
        "time         {:.3} s wall ({:.3} s in vito callbacks, {:.3} s in Ipopt)",
        s.wall_time_s,
        s.callback_time_s,
        s.ipopt_time_s
    );
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
            status_name(r.status),
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
    Ok(())
}

/// The regular file standard output is redirected to, if it is one (Linux's /proc).
fn stdout_file() -> Option<PathBuf> {
    let target = std::fs::read_link("/proc/self/fd/1").ok()?;
    std::fs::metadata(&target)
        .ok()
        .filter(std::fs::Metadata::is_file)
        .map(|_| target)
}

fn init(urdf: &Path, base: BaseType, out: Option<&Path>) -> Result<u8, CliError> {
    let robot = RobotInfo::read(urdf, base, &vito::model::Actuation::Default)
        .map_err(|e| CliError::Input(e.to_string()))?;
    let model = vito::model::Model::from_urdf_file(urdf, base)
        .map_err(|e| CliError::Input(vito::model::describe(urdf, &e)))?;
    let urdf_text = match out {
        Some(_) => vito::paths::reference_from(urdf, out),
        // Printed: relative to the file stdout goes to, when it is one; else absolute, so
        // that the text names the URDF wherever it is saved.
        None => match stdout_file() {
            Some(file) => vito::paths::reference_from(urdf, Some(&file)),
            None => std::path::absolute(urdf)
                .unwrap_or_else(|_| urdf.to_owned())
                .display()
                .to_string(),
        },
    };
    let text = vito::problem::starter_problem(&model, &robot, base, &urdf_text);
    match out {
        None => {
            let mut stdout = std::io::stdout().lock();
            let written = stdout
                .write_all(vito::names::escape_controls(&text).as_bytes())
                .and_then(|()| stdout.flush());
            if let Err(e) = written {
                exit_quietly_on_broken_pipe(&e);
                return Err(CliError::Output(e.to_string()));
            }
        }
        Some(path) => {
            if path.exists() {
                return Err(CliError::Input(format!(
                    "{} exists; vito init never overwrites a file (choose another --out)",
                    path.display()
                )));
            }
            std::fs::write(path, text)
                .map_err(|e| CliError::Input(format!("cannot write {}: {e}", path.display())))?;
            eprintln!("wrote {}", path.display());
        }
    }
    Ok(0)
}

fn inspect(urdf: &Path, base: BaseType, json: bool) -> Result<u8, CliError> {
    let model = vito::model::Model::from_urdf_file(urdf, base)
        .map_err(|e| CliError::Input(vito::model::describe(urdf, &e)))?;
    let inspection = vito::model::inspect(&model);
    if json {
        let text = serde_json::to_string_pretty(&inspection)
            .map_err(|e| CliError::Internal(e.to_string()))?;
        out!("{text}");
    } else {
        out!("{inspection}");
    }
    Ok(0)
}

/// Prints one `transcription::bench` row per problem (sizes, solve and derivative times).
fn bench(files: &[PathBuf], set: &[String]) -> Result<u8, CliError> {
    let overrides = parse_overrides(set)?;
    let files: Vec<PathBuf> = if files.is_empty() {
        pipeline::REFERENCE_PROBLEMS
            .iter()
            .map(PathBuf::from)
            .collect()
    } else {
        files.to_vec()
    };
    let problems = files
        .iter()
        .map(|f| load(f, &overrides))
        .collect::<Result<Vec<_>, _>>()?;
    out!(
        "{:<24} {:>5} {:>6} {:>6} {:>7} {:>7} {:>28} {:>15} {:>9} {:>6} {:>9} {:>9} {:>9} {:>10}",
        "problem",
        "knots",
        "vars",
        "cons",
        "nnz J",
        "nnz H",
        "status",
        "objective",
        "max slack",
        "iter",
        "wall s",
        "callb. s",
        "ipopt s",
        "J+H eval s"
    );
    for p in &problems {
        let r = pipeline::bench(&p.spec).map_err(CliError::Transcription)?;
        out!(
            "{:<24} {:>5} {:>6} {:>6} {:>7} {:>7} {:>28} {:>15.8e} {:>9.2e} {:>6} {:>9.3} {:>9.3} {:>9.3} {:>10.2e}",
            r.name,
            p.spec.knots,
            r.size.n_variables,
            r.size.n_constraints,
            r.size.nnz_jacobian,
            r.size.nnz_hessian,
            status_name(r.status),
            r.objective,
            r.max_slack,
            r.iterations,
            r.wall_time_s,
            r.callback_time_s,
            r.ipopt_time_s,
            r.derivative_eval_s
        );
    }
    Ok(0)
}

fn regress(record_path: &Path, files: &[PathBuf], bless: bool) -> Result<u8, CliError> {
    use vito::regress::{RegressError, Verdict};
    let exe = std::env::current_exe().map_err(|e| CliError::Internal(e.to_string()))?;
    let rows = vito::regress::regress(&exe, record_path, files, bless).map_err(|e| match e {
        RegressError::Record(e) => CliError::Golden(e),
        e @ RegressError::NoProblems { .. } => CliError::Input(e.to_string()),
        e @ (RegressError::Spawn { .. } | RegressError::Scratch { .. }) => {
            CliError::Internal(e.to_string())
        }
    })?;
    out!(
        "{:<32} {:<28} {:>18} {:>18} {:>10}  result",
        "problem",
        "status",
        "objective",
        "recorded",
        "rel. diff"
    );
    for r in &rows {
        let fmt = |x: Option<f64>| x.map_or("-".to_owned(), |v| format!("{v:.10e}"));
        let diff = r
            .relative_difference()
            .map_or("-".to_owned(), |d| format!("{d:.2e}"));
        out!(
            "{:<32} {:<28} {:>18} {:>18} {:>10}  {}",
            r.file,
            r.status,
            fmt(r.objective),
            fmt(r.recorded),
            diff,
            r.verdict
        );
    }
    if bless {
        out!("blessed {}", record_path.display());
        return Ok(if rows.iter().any(|r| r.verdict == Verdict::Fail) {
            1
        } else {
            0
        });
    }
    Ok(if rows.iter().all(|r| r.verdict == Verdict::Ok) {
        0
    } else {
        1
    })
}

fn sweep(args: SweepRunArgs) -> Result<u8, CliError> {
    use vito::sweep::{Axis, Grid, Shard, SweepOptions, WarmStart};
    let file = args
        .file
        .ok_or_else(|| CliError::Input("give a problem file".into()))?;
    let grid = Grid::new(
        args.grid
            .iter()
            .map(|g| Axis::parse(g))
            .collect::<Result<_, _>>()?,
    )?;
    let shard = args
        .shard
        .as_deref()
        .map(Shard::parse)
        .transpose()?
        .unwrap_or(Shard::ALL);
    let time_limit = match args.time_limit {
        Some(t) if !(t.is_finite() && t > 0.0) => {
            return Err(CliError::Input(format!(
                "--time-limit {t}: give a positive number of seconds"
            )));
        }
        t => t.map(std::time::Duration::from_secs_f64),
    };
    if args.jobs == Some(0) {
        return Err(CliError::Input("--jobs 0: give at least 1".into()));
    }
    let overrides = parse_overrides(&args.set)?;
    let problem = load(&file, &overrides)?;
    vito::sweep::check_grid_keys(&file, &overrides, &grid)?;
    let out = args.out.unwrap_or_else(|| {
        let stem = file
            .file_stem()
            .map_or("problem".into(), |s| s.to_string_lossy());
        PathBuf::from(format!("out/sweep-{stem}"))
    });
    let options = SweepOptions {
        exe: std::env::current_exe().map_err(|e| CliError::Internal(e.to_string()))?,
        problem: std::path::absolute(&file).map_err(|e| CliError::Internal(e.to_string()))?,
        sets: args.set.clone(),
        grid,
        shard,
        jobs: args.jobs.unwrap_or_else(|| {
            std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
        }),
        time_limit,
        out: out.clone(),
        warm_start: match args.warm_start {
            WarmStartArg::None => WarmStart::None,
            WarmStartArg::Neighbour => WarmStart::Neighbour,
        },
    };
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:30} {pos}/{len} runs  {msg}  elapsed {elapsed}, ETA {eta}",
        )
        .map_err(|e| CliError::Internal(e.to_string()))?,
    );
    let started = std::time::Instant::now();
    let (table, counts) = vito::sweep::run_sweep(&options, &problem.sha256, |p| {
        bar.set_length(p.total as u64);
        bar.set_position((p.done + p.failed) as u64);
        bar.set_message(format!(
            "done {}, failed {}, running {}{}",
            p.done,
            p.failed,
            p.running,
            if p.skipped > 0 {
                format!(" ({} finished before)", p.skipped)
            } else {
                String::new()
            }
        ));
    })?;
    bar.finish_and_clear();
    print_sweep_table(&table)?;
    let solved = table.rows.iter().all(|r| {
        r.solver_status
            .as_deref()
            .is_some_and(|s| s == "solve_succeeded" || s == "solved_to_acceptable_level")
    });
    out!(
        "{} runs: {} finished ({} of them before this sweep), {} failed, {} timed out, in {:.1} s; table in {}",
        table.rows.len(),
        table.count(vito::sweep::RunStatus::Finished),
        counts.skipped,
        table.count(vito::sweep::RunStatus::Failed),
        table.count(vito::sweep::RunStatus::Timeout),
        started.elapsed().as_secs_f64(),
        out.join(vito::sweep::TABLE_CSV).display()
    );
    Ok(if solved { 0 } else { 1 })
}

/// Prints a sweep table with aligned columns (the CSV's columns).
fn print_sweep_table(table: &vito::sweep::Table) -> Result<(), CliError> {
    let columns = table.columns();
    let cells = table.cells();
    let widths: Vec<usize> = columns
        .iter()
        .enumerate()
        .map(|(j, c)| {
            cells
                .iter()
                .map(|r| r[j].chars().count())
                .chain([c.chars().count()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let line = |row: &[String]| {
        row.iter()
            .zip(&widths)
            .map(|(c, w)| format!("{c:<w$}"))
            .collect::<Vec<_>>()
            .join("  ")
            .trim_end()
            .to_owned()
    };
    out!("{}", line(&columns));
    for r in &cells {
        out!("{}", line(r));
    }
    Ok(())
}

fn sweep_report(dir: &Path, metric: &str) -> Result<u8, CliError> {
    let table = vito::sweep::Table::read(dir)?;
    print_sweep_table(&table)?;
    let known = ["objective", "iterations", "wall_time_s", "max_slack"];
    let metrics = table.metric_names();
    let bare = metric.strip_prefix("metrics.").unwrap_or(metric);
    if !known.contains(&metric) && !metrics.iter().any(|m| m == bare) {
        return Err(CliError::Input(format!(
            "--metric {metric}: not a column of {}; choose one of: {}",
            dir.join(vito::sweep::TABLE_JSON).display(),
            known
                .iter()
                .map(|s| s.to_string())
                .chain(metrics)
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    let file_name: String = bare
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let path = dir.join(format!("sweep-{file_name}.svg"));
    let plotted = vito::sweep::metric_svg(&table, metric, &path)?;
    out!("{metric} of {plotted} runs plotted in {}", path.display());
    Ok(0)
}

fn sweep_collect(dirs: &[PathBuf], out: &Path) -> Result<u8, CliError> {
    vito::sweep::prepare_dir(out)?;
    let table = vito::sweep::collect(dirs, out)?;
    table.write(out)?;
    print_sweep_table(&table)?;
    out!(
        "{} points from {} directories: {} finished, {} failed, {} timed out, {} missing; table in {}",
        table.rows.len(),
        dirs.len(),
        table.count(vito::sweep::RunStatus::Finished),
        table.count(vito::sweep::RunStatus::Failed),
        table.count(vito::sweep::RunStatus::Timeout),
        table.count(vito::sweep::RunStatus::Pending),
        out.join(vito::sweep::TABLE_CSV).display()
    );
    Ok(0)
}
