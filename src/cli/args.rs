//! The command line: arguments (clap derive) and their parsing.

use std::path::{Path, PathBuf};

use clap::{Parser, Subcommand, ValueEnum};
use vito::discrete::Integrator;
use vito::model::BaseType;
use vito::problem::Override;
use vito::sim::Feedback;

use super::error::{CliError, EXIT_CODE_TABLE};

/// [`EXIT_CODE_TABLE`] as `--help` prints it.
pub(super) fn exit_codes_help() -> String {
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
    /// `fixed` for a robot bolted down (a root link `world`, prismatic joints from its root
    /// link as a planar hopper's x and z, or no end link below its root: an arm, a hand),
    /// else `floating`.
    Auto,
    Fixed,
    Planar,
    Floating,
}

impl BaseArg {
    /// The base for `urdf`: as asked, or for `auto` by [`vito::model::Model::auto_base`],
    /// with the reason it gives.
    pub(super) fn resolve(self, urdf: &Path) -> Result<(BaseType, Option<String>), CliError> {
        Ok(match self {
            BaseArg::Auto => {
                let fixed = vito::model::Model::from_urdf_file(urdf, BaseType::Fixed)
                    .map_err(|e| CliError::Input(vito::model::describe(urdf, &e)))?;
                let choice = fixed.auto_base();
                (choice.base, Some(choice.reason))
            }
            BaseArg::Fixed => (BaseType::Fixed, None),
            BaseArg::Planar => (BaseType::Planar, None),
            BaseArg::Floating => (BaseType::Floating, None),
        })
    }
}

/// What `simulate` runs: the inputs or the reference, the feedback, the duration and the
/// integrator.
#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
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
    #[arg(long, value_parser = feedback_parser(), requires = "track")]
    feedback: Option<Feedback>,
    /// Simulated time (default: the CSV's last time, else the problem's horizon).
    #[arg(long)]
    duration: Option<f64>,
    /// Steps per time unit (default: 1/h of the problem).
    #[arg(long)]
    rate: Option<f64>,
    /// Integrator (default: the problem's).
    #[arg(long, value_parser = integrator_parser())]
    integrator: Option<Integrator>,
}

impl From<SimulateArgs> for vito::pipeline::simulation::SimulateRequest {
    fn from(args: SimulateArgs) -> Self {
        vito::pipeline::simulation::SimulateRequest {
            inputs: args.inputs,
            track: args.track,
            gains: args.gains,
            feedback: args.feedback,
            duration: args.duration,
            rate: args.rate,
            integrator: args.integrator,
        }
    }
}

/// `--integrator`: the names of [`Integrator::name`], listed in the help, parsed by
/// Integrator's own `FromStr`.
fn integrator_parser() -> impl clap::builder::TypedValueParser<Value = Integrator> {
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(Integrator::ALL.map(Integrator::name))
        .try_map(|name| name.parse::<Integrator>())
}

/// `--feedback`: the names of [`Feedback::name`], listed in the help, parsed by Feedback's own
/// `FromStr` (the names the problem file and the Python package accept too).
fn feedback_parser() -> impl clap::builder::TypedValueParser<Value = Feedback> {
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(Feedback::ALL.map(Feedback::name))
        .try_map(|name| name.parse::<Feedback>())
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
        /// directory (a slack continuation's solve k as `ipopt.solve<k>.log`, the polish's as
        /// `ipopt.polish.log`).
        #[arg(long)]
        ipopt_log: bool,
        /// Solve from K starts (1 to 10000: the file's guess, then K−1 seeded perturbations of
        /// it) and keep the best feasible; summary.json lists all under `starts`.
        #[arg(long, value_name = "K", default_value_t = 1)]
        starts: usize,
        /// Seed of the multi-start perturbations.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Starts solved at a time (1 to 1024), each in its own process (default: the number
        /// of cores); the result is the same as with --jobs 1.
        #[arg(long, value_name = "J")]
        jobs: Option<usize>,
        /// Internal: solve only this start of the --starts (a parallel multi-start's share).
        #[arg(long, hide = true, value_name = "K", requires = "start_result")]
        only_start: Option<usize>,
        /// Internal: write that start's solution (JSON) to this file, no output directory.
        #[arg(long, hide = true, value_name = "FILE", requires = "only_start")]
        start_result: Option<PathBuf>,
        /// Wall-time limit in seconds: the solve stops at the first iteration after it, as
        /// Ctrl-C does, and writes its iterate (status `timeout`, exit 1).
        #[arg(long, value_name = "S")]
        time_limit: Option<f64>,
        /// Progress lines on stderr: `full` (every iteration), `compact` (about one a second)
        /// or `auto` (full on a terminal, compact otherwise: logs, sweeps, batch jobs).
        #[arg(long, value_enum, default_value = "auto")]
        progress: ProgressArg,
        /// Internal: the process id of the sweep that started this run (the run dies with it).
        #[arg(long, hide = true, value_name = "PID")]
        sweep_parent: Option<u32>,
        /// With `--set horizon.knots` finer than the file's: solve on the asked grid alone,
        /// cold, instead of through the file's grid and its doublings (docs/solve.md).
        #[arg(long)]
        no_refine: bool,
    },
    /// Simulate a problem file's robot forward with the planner's mechanics and contact model.
    #[command(after_help = exit_codes_help())]
    Simulate {
        /// Problem file (TOML): robot, terrain, contacts, initial state.
        file: PathBuf,
        /// Overrides as for `solve`.
        #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
        set: Vec<String>,
        #[command(flatten)]
        request: SimulateArgs,
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
        /// Write the strip of the one result directory given as SVG (an orthographic side
        /// view) to this file.
        #[arg(long, requires = "strip")]
        svg: Option<PathBuf>,
        /// Draw the strip in one world frame: each pose at its true x over one terrain, earlier
        /// poses lighter (default: side by side, each over its own piece of terrain).
        #[arg(long, requires = "strip")]
        world: bool,
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
        after_help = "Examples:\n  vito sweep problems/hopper_2d.toml --grid contacts.friction=0.3,0.8 --grid slack.weight=10,100 --out out/sweep\n  vito sweep report out/sweep --metric objective\n  vito sweep collect out/shard-0 out/shard-1 --out out/all\n\nExit codes: 0 every run finished and solved, 1 some run failed, timed out, did not solve or was stopped by a signal (collect: points missing, without --partial), 2 input or usage error, 3 internal error, 4 output could not be written (standard output or error, or a table or plot on a full or read-only disk)",
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

/// The methods a study compares and its reference simulation (`vito study brick-accuracy` and
/// `tracking`).
#[derive(Debug, clap::Args)]
pub struct StudyMethods {
    /// The integrators compared (comma-separated; the paper's figures: euler,midpoint).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "euler,midpoint",
        value_parser = integrator_parser()
    )]
    pub methods: Vec<Integrator>,
    /// The reference simulation's integrator (the paper's: euler).
    #[arg(long, default_value = "euler", value_parser = integrator_parser())]
    pub reference: Integrator,
    /// The reference simulation's steps per time unit.
    #[arg(long, default_value_t = 2000.0)]
    pub reference_rate: f64,
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
        /// The methods and the reference simulation.
        #[command(flatten)]
        methods: StudyMethods,
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
    /// previous one, the other methods' plans at each K from the variational plan at that K;
    /// tracking_frontier.csv and its plots: each plan's error at its knots against its solve's
    /// wall time and variables.
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
        #[arg(long, value_parser = feedback_parser())]
        feedback: Option<Feedback>,
        /// The methods and the reference simulation.
        #[command(flatten)]
        methods: StudyMethods,
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
    pub(super) file: Option<PathBuf>,
    /// A swept key and its values: any `--set` key or family parameter (repeatable; the
    /// grid is the product, the last --grid varying fastest).
    #[arg(long, value_name = "KEY=V1,V2,...", required = true)]
    pub(super) grid: Vec<String>,
    /// Overrides for every run, as for `solve` (repeatable).
    #[arg(long = "set", value_name = "KEY.PATH=VALUE")]
    pub(super) set: Vec<String>,
    /// Runs at a time (1 to 1024; default: the number of cores).
    #[arg(long)]
    pub(super) jobs: Option<usize>,
    /// Sweep directory: the table and each run's own directory (default: out/sweep-<file stem>).
    #[arg(long)]
    pub(super) out: Option<PathBuf>,
    /// Per-run wall-time limit in seconds; a run still going then is killed (status timeout).
    #[arg(long, value_name = "S")]
    pub(super) time_limit: Option<f64>,
    /// Run a deterministic part of the grid: the points whose index is I mod N
    /// (Slurm: --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT).
    #[arg(long, value_name = "I/N")]
    pub(super) shard: Option<String>,
    /// `neighbour`: start each run from the trajectory of its nearest finished grid point.
    #[arg(long, value_enum, default_value = "none")]
    pub(super) warm_start: WarmStartArg,
    /// Solve each point from K starts (1 to 10000) and keep its best (as `vito solve
    /// --starts`); the table gets the solved starts' objectives (objective_starts_min, _max).
    #[arg(long, value_name = "K", default_value_t = 1)]
    pub(super) starts: usize,
    /// Seed of the starts' perturbations (as `vito solve --seed`).
    #[arg(long, default_value_t = 0)]
    pub(super) seed: u64,
    /// Rounds of the neighbour pass: after every point is solved, each is solved again from
    /// its grid neighbours' plans while that lowers its objective by more than 1 % (0: no
    /// neighbour pass).
    #[arg(long, value_name = "N", default_value_t = vito::sweep::DEFAULT_ROUNDS)]
    pub(super) neighbour_rounds: usize,
}

/// A `--time-limit` in seconds, checked (a positive number up to the largest span).
pub(super) fn time_limit(seconds: Option<f64>) -> Result<Option<std::time::Duration>, CliError> {
    seconds
        .map(|t| vito::files::input::checked_span("--time-limit", t))
        .transpose()
        .map_err(CliError::Input)
        .map(|t| t.map(std::time::Duration::from_secs_f64))
}

/// A count given on the command line (`--starts`, `--jobs`), checked: 1 to `max`.
pub(super) fn count(option: &str, value: usize, max: usize) -> Result<usize, CliError> {
    vito::files::input::checked_count(value, max)
        .map_err(|m| CliError::Input(format!("{option} {value}: {m}")))
}

/// `--jobs`, checked ([`vito::sweep::MAX_JOBS`]); default: the number of cores.
pub(super) fn jobs(jobs: Option<usize>) -> Result<usize, CliError> {
    match jobs {
        Some(j) => count("--jobs", j, vito::sweep::MAX_JOBS),
        None => Ok(std::thread::available_parallelism()
            .map_or(1, std::num::NonZero::get)
            .min(vito::sweep::MAX_JOBS)),
    }
}

/// How often `vito solve` prints a progress line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ProgressArg {
    /// Full on a terminal, compact otherwise.
    Auto,
    /// Every iteration.
    Full,
    /// The first iteration, then about one a second.
    Compact,
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

pub(super) fn parse_overrides(set: &[String]) -> Result<Vec<Override>, CliError> {
    Ok(set
        .iter()
        .map(|s| Override::parse(s))
        .collect::<Result<_, _>>()?)
}
