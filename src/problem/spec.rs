//! The checked problem: what the transcription builds an NLP from.
//!
//! A `ProblemSpec` is produced by validating a TOML file (`problem::load`) or built in Rust.
//! Everything a user names (coordinates, inputs, links) is resolved here to indices into
//! the model's coordinate and input order, and every vector has its full length, so the
//! transcription never looks up a name and never checks a length.
//! Units are the robot's units (SI unless the problem declares otherwise).

use std::path::PathBuf;

use super::constraints::Constraint;
use super::costs::CostTerm;
use super::frames::FrameTerm;
use crate::contact::{ContactModel, Terrain};
pub use crate::discrete::Integrator;
use crate::discrete::Mechanics;
use crate::ipopt::OptionValue;
use crate::model::{Actuation, BaseType};

/// How the Lagrangian Hessian is obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HessianMode {
    /// Exact, assembled from AD per block.
    #[default]
    Exact,
    /// Ipopt's limited-memory quasi-Newton approximation.
    Lbfgs,
}

/// How the complementarity is relaxed: elastic rows with slacks, or a penalty.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SlackMode {
    /// One slack s_k per interval shared by all contacts (the paper's and the reference problems').
    #[default]
    PerInterval,
    /// One slack per interval, contact and complementarity pair.
    PerContact,
    /// No slacks and no complementarity rows: the objective gets α Σ_j Σ_i (ηᵀβ + c·φ +
    /// ψ(μc − eᵀβ)), each factor kept ≥ 0 by bounds and the distance and cone rows (the
    /// penalty form of Leyffer, López-Calva & Nocedal 2006). A plan's "slack" is then the
    /// largest of an interval's three product sums, what the elastic slack would be there.
    Penalty,
}

/// How the NLP is scaled for Ipopt (`[solver] scaling`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ScalingMode {
    /// Ipopt's own (`nlp_scaling_method`, gradient-based by default): no user scaling.
    #[default]
    Ipopt,
    /// Each variable kind by its physical unit (`transcription`'s scaling from units), the
    /// objective and rows by Ipopt's gradient rule in the scaled variables.
    Units,
}

impl ScalingMode {
    /// The names a problem file gives.
    pub const NAMES: [&str; 2] = ["ipopt", "units"];
}

/// The robot model and its environment constants.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotSpec {
    /// URDF file (absolute, or relative to the working directory once resolved).
    pub urdf: PathBuf,
    /// Base joint the problem chooses.
    pub base: BaseType,
    /// Gravity vector in world coordinates (robot units), e.g. [0, 0, −9.81].
    pub gravity: [f64; 3],
    /// Which joints take an input.
    pub actuation: Actuation,
}

/// One point contact: a point fixed on a link, against the terrain.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSpec {
    /// Display name (defaults to the collision or link name), used in outputs.
    pub name: String,
    /// Link the point is fixed to (URDF link name; resolved by the model).
    pub link: String,
    /// Point in the link frame: a sphere's centre.
    pub point: [f64; 3],
    /// The sphere's radius (0: a point); its distance to the terrain is the centre's minus
    /// the radius, and friction acts at its lowest point.
    pub radius: f64,
    /// Coulomb friction coefficient μ ≥ 0.
    pub friction: f64,
}

/// Time steps h_k, k = 1..N−1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TimeSteps {
    /// Every h_k fixed to this value (> 0).
    Fixed(f64),
    /// Free, equal steps with total time T in [t_min, t_max]: bounds T/(N−1) on each h_k, N−2
    /// rows h_k − h_{k+1} = 0 after all per-interval rows; guess h = t_max/(N−1).
    FreeEqual { t_min: f64, t_max: f64 },
}

impl TimeSteps {
    /// The step of `knots` knots at the guess: h fixed, else t_max/(N−1).
    pub fn guess_step(&self, knots: usize) -> f64 {
        match *self {
            TimeSteps::Fixed(h) => h,
            TimeSteps::FreeEqual { t_max, .. } => t_max / (knots - 1) as f64,
        }
    }
}

/// Lower and upper bound (±∞ for none).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    pub lower: f64,
    pub upper: f64,
}

impl Interval {
    pub const FREE: Interval = Interval {
        lower: f64::NEG_INFINITY,
        upper: f64::INFINITY,
    };
    pub fn fixed(value: f64) -> Interval {
        Interval {
            lower: value,
            upper: value,
        }
    }
}

/// Which knots (1-based in the maths, 0-based here: knot 0 is q_1) a bound applies to.
#[derive(Debug, Clone, PartialEq)]
pub enum KnotSet {
    All,
    /// All but the first and last knot.
    Interior,
    First,
    Last,
    /// Explicit 0-based knot indices.
    List(Vec<usize>),
}

/// A bound on one coordinate at a set of knots (intersected with other bounds).
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateBound {
    /// Index into the model's coordinates.
    pub coordinate: usize,
    pub knots: KnotSet,
    pub bound: Interval,
}

/// Where the solver starts.
#[derive(Debug, Clone, PartialEq)]
pub enum InitialGuess {
    /// The common rule of the reference problems: q linear from `from` (q_1) to `to`, u = 0, contact
    /// variables 0.01, s = 0.01, h as given (t_max/(N−1) when free), v_0 its fixed value or 0.
    Linear { from: Vec<f64>, to: Vec<f64> },
    /// A previous solution resampled to this problem's knots (times from 0 to T).
    WarmStart(WarmStart),
    /// An open-loop simulation, run by `pipeline::resolve_initial_guess` into a
    /// [`InitialGuess::WarmStart`] before a solve (until then, q_1 held at every knot).
    Simulation(SimulatedGuess),
}

/// `[initial_guess.simulation]`, checked: u_i(t) = offset_i + amplitude_i · sin(2π (t /
/// period + phase_i)), clipped to the input bounds, from q_1 with v_0 (zero when free) for
/// `cycles` periods at the step period / ((N − 1) · substeps); the guess is the last period.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulatedGuess {
    /// Period [time] (> 0).
    pub period: f64,
    /// Periods simulated (≥ 1).
    pub cycles: usize,
    /// Simulation steps per knot interval (≥ 1).
    pub substeps: usize,
    /// Per input (length m).
    pub amplitude: Vec<f64>,
    /// Per input, in periods (length m).
    pub phase: Vec<f64>,
    /// Per input (length m).
    pub offset: Vec<f64>,
}

impl SimulatedGuess {
    /// The inputs at time t, before clipping. With more than one period the whole signal is
    /// ramped in linearly over the first period, so the robot is not struck at t = 0 (the
    /// guess is a later period, which the ramp does not reach).
    pub fn input(&self, t: f64) -> Vec<f64> {
        let angle = |phase: f64| std::f64::consts::TAU * (t / self.period + phase);
        let ramp = if self.cycles > 1 {
            (t / self.period).clamp(0.0, 1.0)
        } else {
            1.0
        };
        (self.offset.iter().zip(&self.amplitude).zip(&self.phase))
            .map(|((o, a), p)| ramp * (o + a * angle(*p).sin()))
            .collect()
    }
}

/// A quantity of a solution that `summary.json` reports under `metrics`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Metric {
    /// q_N − q_1 of the forward coordinate: the distance per cycle when the horizon is one
    /// period [length per cycle].
    ForwardPerCycle,
    /// The same over the total time T [length/time].
    ForwardSpeed,
    /// The paper's eq. 38: the distance each contact point moves backwards (world frame,
    /// intervals where its forward displacement is negative) over the body's forward
    /// distance, averaged over the contacts [dimensionless].
    Slip,
    /// max_k q_k − q_1 of the vertical coordinate [length].
    JumpHeight,
}

impl Metric {
    /// Every metric, by its name in `[metrics] report` and in `summary.json`.
    pub const ALL: [(&'static str, Metric); 4] = [
        ("forward_per_cycle", Metric::ForwardPerCycle),
        ("forward_speed", Metric::ForwardSpeed),
        ("slip", Metric::Slip),
        ("jump_height", Metric::JumpHeight),
    ];

    /// Its name.
    pub fn name(self) -> &'static str {
        Metric::ALL
            .iter()
            .find(|(_, m)| *m == self)
            .map_or("", |(name, _)| name)
    }
}

/// `[metrics]`, checked.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MetricsSpec {
    /// What to report, in file order.
    pub report: Vec<Metric>,
    /// Index of the forward coordinate.
    pub forward: usize,
    /// Index of the vertical coordinate.
    pub vertical: usize,
}

/// A previous trajectory to start from, by knot times.
#[derive(Debug, Clone, PartialEq)]
pub struct WarmStart {
    /// File it was read from (for messages).
    pub source: PathBuf,
    /// Knot times of the previous solution (length N').
    pub times: Vec<f64>,
    /// Configurations at those times (N' × n).
    pub q: Vec<Vec<f64>>,
    /// Inputs per interval (N'−1 × m), empty when absent.
    pub u: Vec<Vec<f64>>,
    /// Contact forces per interval (N'−1 × nc × (1 + nd), N): each contact's normal impulse
    /// then its friction impulses, divided by the interval's step so that they keep their
    /// size on another grid; empty when absent (a trajectory file or a simulation).
    pub forces: Vec<Vec<Vec<f64>>>,
}

/// `[slack] target`: the exact-penalty continuation. While the largest slack exceeds
/// `target`, multiply α by `growth` and solve again (from the last solution after an
/// optimum, from the initial guess after an iteration or time limit), at most `rounds` more
/// times.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlackContinuation {
    /// Largest acceptable slack (> 0).
    pub target: f64,
    /// Factor on α per extra solve (> 1).
    pub growth: f64,
    /// Extra solves allowed.
    pub rounds: usize,
    /// Where a raised-weight solve starts after an optimum.
    pub restart: SlackRestart,
    /// `[slack] tied_tolerances`: the relaxation σ the first solve stands for, the slack the
    /// problem accepts (`tolerance`) times the file's weight over the first solve's weight.
    /// Solve r stands for σ / growth^r and stops at Ipopt tolerance 0.1 σ (`tol`, `mu_init`
    /// and `mu_target`, monotone μ) while that is above the file's own `tol`. After such a
    /// loose solve the polish is the tight solve; when the polish is off or not kept, one
    /// relaxed solve at the same weight and the file's own tolerances (μ monotone from a
    /// tenth of the loose tolerance) comes first. `None`: every solve at the file's
    /// tolerances.
    pub tied_sigma: Option<f64>,
}

/// `[slack] restart`: the start of a raised-weight solve that follows an optimum.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SlackRestart {
    /// The last solution's x, with a small barrier parameter and bound push.
    Primal,
    /// The last solution's x and multipliers (Ipopt's `warm_start_init_point`).
    PrimalDual,
    /// The problem's initial guess, as the first solve.
    InitialGuess,
}

/// A complete, checked trajectory-optimisation problem.
#[derive(Debug, Clone, PartialEq)]
pub struct ProblemSpec {
    /// Short name (the file stem), used in outputs and regression records.
    pub name: String,
    pub robot: RobotSpec,
    pub contacts: Vec<ContactSpec>,
    pub terrain: Terrain,
    /// Number of knots N ≥ 2.
    pub knots: usize,
    pub time_steps: TimeSteps,
    pub integrator: Integrator,
    /// Slack penalty α > 0 in the objective α Σ s (with [`SlackMode::Penalty`], the weight
    /// of the complementarity products in the objective).
    pub slack_weight: f64,
    pub slack_mode: SlackMode,
    /// Upper bound on every ψ (sliding speed), when set.
    pub max_slip_speed: Option<f64>,
    /// Intervals per contact-mode block m ≥ 1 (`contacts.mode_block`): the complementarity
    /// rows of interval j pair its ψ, η, c with the sums of the cone, β and φ over j's block
    /// of m consecutive intervals (the last block may be shorter); 1 is the reference NLP.
    pub mode_block: usize,
    /// Largest slack of a solved plan (`slack.tolerance`): above it the plan relaxes the
    /// contact model and is not solved ([`crate::transcription::SolveVerdict`]).
    pub slack_tolerance: f64,
    /// Re-solve with a growing slack weight until the largest slack is below a target.
    pub slack_continuation: Option<SlackContinuation>,
    /// Finish with a mode-fixed re-solve (`slack.polish`; `transcription::polish`).
    pub slack_polish: bool,
    /// q_1 (length n): fixed, except where `q_initial_free` is set (there only the guess).
    pub q_initial: Vec<f64>,
    /// Coordinates whose q_1 is a variable (length n).
    pub q_initial_free: Vec<bool>,
    /// v_0 fixed to this value when set (length n); free otherwise.
    pub v_initial: Option<Vec<f64>>,
    /// Bounds on q_N per coordinate (length n); `Interval::fixed` for a fixed goal.
    pub q_final: Vec<Interval>,
    /// Extra coordinate bounds (joint limits from the URDF are added when `joint_limits`).
    pub bounds: Vec<CoordinateBound>,
    /// Apply the URDF joint limits on every knot.
    pub joint_limits: bool,
    /// Bounds per input (length m).
    pub input_bounds: Vec<Interval>,
    pub costs: Vec<CostTerm>,
    /// The problem file's constraints (`[[periodic]]`, `[[constraint]]`).
    pub constraints: Vec<Constraint>,
    /// `[[frame]]` terms, then the clearance terms of `[[contact_window]]` and `[gait]`.
    pub frames: Vec<FrameTerm>,
    /// (contact, interval j) pairs whose normal impulse c_{j,contact} is held at 0 (flight
    /// windows), ascending.
    pub zero_impulse: Vec<(usize, usize)>,
    pub initial_guess: InitialGuess,
    pub hessian: HessianMode,
    /// How the NLP is scaled for Ipopt.
    pub scaling: ScalingMode,
    /// Ipopt options in the order given (checked by the wrapper).
    pub solver_options: Vec<(String, OptionValue)>,
    /// What the summary reports under `metrics`.
    pub metrics: MetricsSpec,
}

impl ProblemSpec {
    /// The contact model of the problem for the robot `mech`, whose contacts are
    /// [`ProblemSpec::contacts`] in order: the NLP and the forward simulator build their contact
    /// rows from this.
    pub fn contact_model<M: Mechanics>(&self, mech: &M) -> ContactModel {
        ContactModel::new(
            mech.moves_in_xz_plane(),
            self.contacts.iter().map(|c| c.friction).collect(),
            self.terrain.clone(),
        )
    }

    /// The step at the guess of this problem's grid ([`TimeSteps::guess_step`]).
    pub fn guess_step(&self) -> f64 {
        self.time_steps.guess_step(self.knots)
    }

    /// The slack's tolerance and continuation target, which `file` (this problem on the
    /// grid its file gives) states, carried to this problem's grid. An interval's
    /// complementarity products pair an impulse (force × h) with a distance or a speed, so a
    /// grid of half the step holds the same force and distance at half the slack: the
    /// numbers scale with the step at the guess. The weight needs nothing: α Σ s sums the
    /// intervals' force × distance × h, an integral over time at every grid.
    pub fn rescale_slack_to(&mut self, file: &ProblemSpec) {
        let ratio = self.guess_step() / file.guess_step();
        if !(ratio.is_finite() && ratio > 0.0) {
            return;
        }
        self.slack_tolerance = file.slack_tolerance * ratio;
        if let (Some(c), Some(f)) = (&mut self.slack_continuation, &file.slack_continuation) {
            c.target = f.target * ratio;
        }
    }
}

/// `slack.tolerance` when the problem file gives none (problem units: the products c·φ, ηᵀβ,
/// ψ(μc − eᵀβ) in impulse × length or impulse × speed), the paper's order of a closed slack.
pub const DEFAULT_SLACK_TOLERANCE: f64 = 1e-4;
