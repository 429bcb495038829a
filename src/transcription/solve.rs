//! Solving a problem's NLP: build the transcription, run Ipopt (multi-start, slack
//! continuation) and keep the [`Solution`] it reads off; plus the benchmark row. The entry point is
//! [`crate::pipeline::solve`], which loads the robot and resolves the initial guess first.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use super::nlp::{ProgressFn, TranscriptionNlp};
use super::{
    FixedModes, MechanicsDerivatives, NlpSize, Solution, SolveVerdict, Transcription,
    TranscriptionError,
};
use crate::ipopt::{self, Multipliers, OptionValue, Solver};
use crate::problem::{HessianMode, ProblemSpec, ScalingMode, SlackMode, SlackRestart};

/// How to run a solve besides the problem itself.
#[derive(Default)]
pub struct SolveOptions {
    /// Called once per Ipopt iteration.
    pub progress: Option<Box<ProgressFn>>,
    /// Set to true (e.g. from a Ctrl-C handler) to stop at the next iteration; the solve then
    /// returns status `UserRequestedStop` with the current iterate.
    pub cancel: Option<Arc<AtomicBool>>,
    /// Ipopt options applied after the problem's own (so they win).
    pub ipopt_options: Vec<(String, OptionValue)>,
    /// Solve from several starts and keep the best (None: one start, the problem's guess).
    pub multi_start: Option<MultiStart>,
    /// A wall-time limit: the first iteration after this instant stops the solve (and any
    /// further start or continuation solve), which returns status
    /// `MaximumWallTimeExceeded` (verdict `timeout`) with the current iterate.
    pub deadline: Option<Instant>,
}

impl SolveOptions {
    /// Whether the caller asked to stop (the cancel flag) or the deadline has passed: no
    /// further solve starts.
    pub(super) fn stopped(&self) -> bool {
        self.cancel
            .as_ref()
            .is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed))
            || self.deadline.is_some_and(|d| Instant::now() >= d)
    }
}

/// Multi-start: start 0 is the problem's initial guess; start k ≥ 1 perturbs every knot's
/// configuration of it by a seeded uniform amount within ±[`PERTURBATION`] of that
/// coordinate's scale (its range over the guess, or its initial magnitude, at least 1 % of
/// the largest such scale), clamped to the bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MultiStart {
    /// Number of starts (≥ 1).
    pub starts: usize,
    /// Seed of the perturbations (start k uses `seed + k`).
    pub seed: u64,
    /// Solve only start `k` of the `starts` (its record the only one listed): one process's
    /// share of starts run in parallel, merged by [`best_of`].
    pub only: Option<usize>,
}

impl MultiStart {
    /// The perturbation seed of start `k` (None for start 0, the problem's own guess).
    pub fn seed_of(&self, k: usize) -> Option<u64> {
        (k > 0).then(|| self.seed.wrapping_add(k as u64))
    }
}

/// Relative size of a multi-start perturbation.
pub const PERTURBATION: f64 = 0.1;

/// Most starts of a multi-start solve (`--starts`): each is a whole solve with its record in
/// `summary.json`, checked before anything is allocated for them.
pub const MAX_STARTS: usize = 10_000;

/// One start of a multi-start solve, as `summary.json` lists it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StartRecord {
    /// None for the problem's own guess, else the perturbation's seed.
    pub seed: Option<u64>,
    /// Its solve, or how its process ended without one.
    pub outcome: StartOutcome,
}

/// How a start of a multi-start solve ended.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum StartOutcome {
    /// Its solve ended (with any status).
    Ended(Box<StartSolve>),
    /// It ran in a process of its own, which ended without a result.
    Lost(LostStart),
}

/// The solve of one start.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StartSolve {
    /// Ipopt's status.
    pub status: ipopt::Status,
    /// The start's verdict (Ipopt's status and its slack).
    pub verdict: SolveVerdict,
    /// Objective at the end of the start.
    pub objective: f64,
    /// Its terms (as [`Solution::objective_terms`]).
    pub objective_terms: Vec<(String, f64)>,
    /// Largest slack.
    pub max_slack: f64,
    /// Largest constraint violation.
    pub max_constraint_violation: f64,
    /// Ipopt iterations.
    pub iterations: usize,
    /// Wall time [s].
    pub wall_time_s: f64,
    /// The start's mode-fixed re-solve, if `[slack] polish` asked for one.
    #[serde(default)]
    pub polish: Option<PolishRecord>,
    /// The solves of its slack continuation (as [`Solution::continuation`]).
    #[serde(default)]
    pub continuation: Vec<ContinuationSolve>,
}

/// How the process of a start ended without a result.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LostStart {
    /// The signal that ended the process, if one did (`killed`, else `failed`).
    pub signal: Option<i32>,
    /// How it ended: `killed by signal 9 (SIGKILL)`, or its exit code and error.
    pub how: String,
}

impl LostStart {
    /// `killed` (by a signal) or `failed`: the start's status in `summary.json`.
    pub fn status(&self) -> &'static str {
        if self.signal.is_some() {
            "killed"
        } else {
            "failed"
        }
    }
}

/// One Ipopt solve of the slack continuation (`[slack] target` or `homotopy`), in order.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContinuationSolve {
    /// The slack weight α of this solve.
    pub slack_weight: f64,
    /// Ipopt's `tol`, `mu_init` and `mu_target` when `[slack] tied_tolerances` loosened this
    /// solve; `None`: the file's own tolerances.
    pub tied_tol: Option<f64>,
    /// Ipopt's status.
    pub status: ipopt::Status,
    /// Its objective.
    pub objective: f64,
    /// Its largest slack ([`Solution::max_slack`]).
    pub max_slack: f64,
    /// Its own Ipopt iterations.
    pub iterations: usize,
    /// Its own wall time [s].
    pub wall_time_s: f64,
}

impl ContinuationSolve {
    fn of(solution: &Solution, tied_tol: Option<f64>) -> Self {
        ContinuationSolve {
            slack_weight: solution.slack_weight,
            tied_tol,
            status: solution.status,
            objective: solution.objective,
            max_slack: solution.max_slack,
            iterations: solution.iterations,
            wall_time_s: solution.wall_time_s,
        }
    }
}

/// The mode-fixed re-solve that ends a solve under `[slack] polish`: from the relaxed
/// solution, each complementarity pair's smaller side fixed at zero
/// ([`Transcription::fix_contact_modes`]), the slacks at zero, solved warm from there.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PolishRecord {
    /// Ipopt's status of the re-solve.
    pub status: ipopt::Status,
    /// Its verdict, judged on the problem's own rows and bounds.
    pub verdict: SolveVerdict,
    /// Ipopt's status of the relaxed solve it started from: an optimum, or the iteration
    /// limit at a feasible point.
    pub status_before: ipopt::Status,
    /// The objective of the solution it started from.
    pub objective_before: f64,
    /// That solution's largest slack ([`Solution::max_slack`]).
    pub max_slack_before: f64,
    /// Its own objective.
    pub objective: f64,
    /// Its Ipopt iterations (also counted in the solution's).
    pub iterations: usize,
    /// Its wall time [s] (also counted in the solution's).
    pub wall_time_s: f64,
    /// Whether it replaced the solution it started from: solved, and that one not solved or
    /// no better.
    pub kept: bool,
    /// The modes it fixed.
    pub fixed: FixedModes,
}

/// One row of `vito bench`: sizes, iterations and where the time went.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchRow {
    /// Problem name.
    pub name: String,
    /// NLP sizes (variables, constraints, Jacobian and lower-Hessian nonzeros).
    pub size: NlpSize,
    /// Ipopt's final status.
    pub status: ipopt::Status,
    /// Whether it is solved (Ipopt's status and the slack).
    pub verdict: SolveVerdict,
    /// Final objective.
    pub objective: f64,
    /// Ipopt iterations (summed over the solves of a slack continuation).
    pub iterations: usize,
    /// Ipopt solves (more than 1 when `[slack] target` raised the weight).
    pub solves: usize,
    /// Largest slack of the solution.
    pub max_slack: f64,
    /// Wall time of the solve, s.
    pub wall_time_s: f64,
    /// Time in vito's callbacks, s.
    pub callback_time_s: f64,
    /// Time inside Ipopt (wall − callbacks), s.
    pub ipopt_time_s: f64,
    /// The callback time by callback.
    pub callback_split: ipopt::CallbackSplit,
    /// One evaluation of the Jacobian plus the Lagrangian Hessian at the initial point, s
    /// (median of repeated evaluations).
    pub derivative_eval_s: f64,
}

fn configure(spec: &ProblemSpec, options: &SolveOptions) -> Result<Solver, TranscriptionError> {
    let mut solver = Solver::new();
    for (name, value) in spec.solver_options.iter().chain(&options.ipopt_options) {
        let value = ipopt::OptionValue::from(value);
        solver.set_option(name, value)?;
    }
    if spec.hessian == HessianMode::Lbfgs {
        solver.set_option("hessian_approximation", "limited-memory")?;
    }
    if spec.slack_mode == SlackMode::Penalty
        && given_option(spec, options, PENALTY_BOUND_RELAX.0).is_none()
    {
        solver.set_option(PENALTY_BOUND_RELAX.0, PENALTY_BOUND_RELAX.1)?;
    }
    if let Some(flag) = &options.cancel {
        solver.set_cancel_flag(flag.clone());
    }
    if let Some(deadline) = options.deadline {
        solver.set_deadline(deadline);
    }
    Ok(solver)
}

/// The Ipopt option penalty mode sets unless the problem sets it (to 0, the only value
/// validation accepts then): Ipopt's default relaxes every bound and inequality row by 1e-8,
/// and a factor at −1e-8 makes its product with an unbounded partner (ψ or η of a foot in
/// flight) a direction of unbounded descent of the penalty. From the files' starts with the
/// default: Spring Flamingo's penalty reached −3.2e4 and LittleDog's −1.0e5 (relaxed_contact,
/// clipped products 3.2 and 1.0).
pub const PENALTY_BOUND_RELAX: (&str, f64) = ("bound_relax_factor", 0.0);

/// Solve `spec` for the given mechanics with its initial guess as it stands (a simulated guess
/// held at q_1): the solve behind [`crate::pipeline::solve_with`], which resolves the guess
/// first and is the entry point.
pub(crate) fn solve_with<M: MechanicsDerivatives>(
    mech: M,
    spec: &ProblemSpec,
    options: &SolveOptions,
) -> Result<Solution, TranscriptionError> {
    let mut transcription = Transcription::new(mech, spec)?;
    let Some(multi) = options.multi_start.filter(|m| m.starts > 1) else {
        return solve_transcription(&mut transcription, spec, options);
    };
    let guess = transcription.initial_point().to_vec();
    if let Some(k) = multi.only {
        let mut records = Vec::new();
        let seed = multi.seed_of(k);
        let start = start_point(&transcription, &guess, seed);
        let mut solution = solve_from(
            &mut transcription,
            spec,
            options,
            &start,
            seed,
            &mut records,
        )?;
        solution.starts = records;
        solution.best_start = k;
        return Ok(solution);
    }
    let mut records = Vec::new();
    let mut best = solve_from(
        &mut transcription,
        spec,
        options,
        &guess,
        None,
        &mut records,
    )?;
    let mut best_index = 0;
    for k in 1..multi.starts {
        if options.stopped() {
            break;
        }
        let seed = multi.seed_of(k);
        let start = start_point(&transcription, &guess, seed);
        let solution = solve_from(
            &mut transcription,
            spec,
            options,
            &start,
            seed,
            &mut records,
        )?;
        if better(&solution, &best) {
            best = solution;
            best_index = k;
        }
    }
    best.starts = records;
    best.best_start = best_index;
    Ok(best)
}

/// The initial point of the start with this perturbation seed (the guess itself for None:
/// start 0).
fn start_point<M: MechanicsDerivatives>(
    transcription: &Transcription<M>,
    guess: &[f64],
    seed: Option<u64>,
) -> Vec<f64> {
    match seed {
        None => guess.to_vec(),
        Some(seed) => perturbed(transcription, guess, seed),
    }
}

/// One start of a multi-start solve, recorded.
fn solve_from<M: MechanicsDerivatives>(
    transcription: &mut Transcription<M>,
    spec: &ProblemSpec,
    options: &SolveOptions,
    start: &[f64],
    seed: Option<u64>,
    records: &mut Vec<StartRecord>,
) -> Result<Solution, TranscriptionError> {
    transcription.set_initial_point(start)?;
    transcription.set_slack_weight(spec.slack_weight);
    let solution = solve_transcription(transcription, spec, options)?;
    records.push(StartRecord {
        seed,
        outcome: StartOutcome::Ended(Box::new(StartSolve {
            status: solution.status,
            verdict: solution.verdict(),
            objective: solution.objective,
            objective_terms: solution.objective_terms.clone(),
            max_slack: solution.max_slack,
            max_constraint_violation: solution.max_constraint_violation,
            iterations: solution.iterations,
            wall_time_s: solution.wall_time_s,
            polish: solution.polish.clone(),
            continuation: solution.continuation.clone(),
        })),
    });
    Ok(solution)
}

/// The best of starts solved one by one (each with `only` set, listing its own record): all
/// their records and those of the `lost` starts (their process ended without a result) in
/// start order, and the best solution, as one multi-start solve of them all returns it (ties
/// go to the earlier start). None when `solutions` is empty.
pub fn best_of(
    mut solutions: Vec<(usize, Solution)>,
    lost: Vec<(usize, StartRecord)>,
) -> Option<Solution> {
    solutions.sort_by_key(|(k, _)| *k);
    let mut records: Vec<(usize, StartRecord)> = solutions
        .iter()
        .flat_map(|(k, s)| s.starts.iter().map(|r| (*k, r.clone())))
        .chain(lost)
        .collect();
    records.sort_by_key(|(k, _)| *k);
    let mut best: Option<(usize, Solution)> = None;
    for (k, s) in solutions {
        if best.as_ref().is_none_or(|(_, b)| better(&s, b)) {
            best = Some((k, s));
        }
    }
    best.map(|(k, mut s)| {
        s.best_start = records.iter().position(|(j, _)| *j == k).unwrap_or(0);
        s.starts = records.into_iter().map(|(_, r)| r).collect();
        s
    })
}

/// A solved start ([`Solution::verdict`]) beats a relaxed one, which beats an unsolved one;
/// then, among solved ones the lower objective, among relaxed ones the smaller slack, among
/// unsolved ones the smaller constraint violation.
fn better(a: &Solution, b: &Solution) -> bool {
    let (va, vb) = (a.verdict(), b.verdict());
    if va.rank() != vb.rank() {
        return va.rank() < vb.rank();
    }
    match va {
        SolveVerdict::Solved(_) => a.objective < b.objective,
        SolveVerdict::RelaxedContact => a.max_slack < b.max_slack,
        SolveVerdict::NotSolved(_) => a.max_constraint_violation < b.max_constraint_violation,
    }
}

/// The guess with every knot's configuration moved by a seeded uniform amount (see
/// [`MultiStart`]); fixed and bounded variables are clamped by `set_initial_point`.
fn perturbed<M: MechanicsDerivatives>(t: &Transcription<M>, guess: &[f64], seed: u64) -> Vec<f64> {
    let l = t.layout();
    let first = &guess[l.q(0)];
    let n = first.len();
    let mut scale: Vec<f64> = first.iter().map(|v| v.abs()).collect();
    for k in 0..l.knots {
        for (j, v) in guess[l.q(k)].iter().enumerate() {
            scale[j] = scale[j].max((v - first[j]).abs());
        }
    }
    let floor = 0.01 * scale.iter().fold(0.0_f64, |a, &b| a.max(b));
    let mut rng = crate::random::SeededRng::new(seed);
    let mut x = guess.to_vec();
    for k in 0..l.knots {
        let range = l.q(k);
        for j in 0..n {
            x[range.start + j] += rng.symmetric(PERTURBATION * scale[j].max(floor));
        }
    }
    x
}

/// Solve, continue with a growing slack weight while `[slack] target` asks for it, and
/// polish with the contact modes fixed when `[slack] polish` does.
fn solve_transcription<M: MechanicsDerivatives>(
    transcription: &mut Transcription<M>,
    spec: &ProblemSpec,
    options: &SolveOptions,
) -> Result<Solution, TranscriptionError> {
    transcription.set_skip_fixed_variables(ipopt_drops_fixed_variables(spec, options));
    // A passive problem: its simulation, solved with its contact modes fixed, when that is
    // solved; else the usual solve, with the attempt's record and work.
    match super::passive::solve_from_simulation(transcription, spec, options)? {
        Some(s) if s.verdict().is_solved() || options.stopped() => Ok(s),
        attempt => {
            let carried = super::carried::solve_with_carried_modes(transcription, spec, options)?;
            let mut solution = match carried {
                Some(c) if options.stopped() => c,
                Some(c) => {
                    super::carried::keep_better(solve_usually(transcription, spec, options)?, c)
                }
                None => solve_usually(transcription, spec, options)?,
            };
            if let Some(attempt) = attempt {
                solution.add_work(&attempt);
                solution.simulation_start = attempt.simulation_start;
            }
            Ok(solution)
        }
    }
}

/// The relaxed solve with its continuation, then the polish ([`solve_transcription`]).
fn solve_usually<M: MechanicsDerivatives>(
    transcription: &mut Transcription<M>,
    spec: &ProblemSpec,
    options: &SolveOptions,
) -> Result<Solution, TranscriptionError> {
    let polishing = spec.slack_polish && transcription.layout().nc > 0;
    let (solution, report) = solve_relaxed(transcription, spec, options, polishing)?;
    if !polishing {
        return Ok(solution);
    }
    let loose = solution.loose_tol();
    let polished = polish(transcription, spec, options, solution, &report)?;
    let Some(loose) = loose else {
        return Ok(polished);
    };
    if polished.polish.as_ref().is_some_and(|p| p.kept) || options.stopped() {
        return Ok(polished);
    }
    // The polish did not replace a loose optimum (`[slack] tied_tolerances`; `polished` is
    // that optimum with the polish's iterations and times added): solve the relaxed NLP once
    // more at the file's tolerances from there, and polish that.
    let (tight, tight_report) = next_solve(
        transcription,
        spec,
        options,
        polished,
        &report,
        Tolerances::Final(loose),
    )?;
    polish(transcription, spec, options, tight, &tight_report)
}

/// Solve, then continue with a growing slack weight while `[slack] target` asks for it; the
/// solution and Ipopt's report of the last solve. With `[slack] tied_tolerances`, a loose
/// last solve is followed by one at the file's tolerances unless `polishing`: the polish
/// is then the tight solve.
fn solve_relaxed<M: MechanicsDerivatives>(
    transcription: &mut Transcription<M>,
    spec: &ProblemSpec,
    options: &SolveOptions,
    polishing: bool,
) -> Result<(Solution, ipopt::SolveReport), TranscriptionError> {
    let mut solver = configure(spec, options)?;
    let tied = tie_tolerances(&mut solver, spec, options, Tolerances::Round(0))?;
    let mut nlp = adapter(transcription, spec, options);
    let report = solver.solve(&mut nlp)?;
    let mut solution = Solution::read_off(transcription, spec, &report);
    let Some(continuation) = spec.slack_continuation else {
        return Ok((solution, report));
    };
    solution.continuation = vec![ContinuationSolve::of(&solution, tied)];
    let mut report = report;
    let mut weight = spec.slack_weight;
    let mut round = 0;
    loop {
        if !restartable(solution.status) || options.stopped() {
            break;
        }
        // The slack the weight prices: the slack variables (in penalty mode the products).
        let last = transcription.max_slack(&report.x) <= continuation.target
            || round == continuation.rounds;
        let tolerances = match (last, solution.loose_tol()) {
            (true, Some(loose)) if !polishing => Tolerances::Final(loose),
            (true, _) => break,
            (false, _) => {
                round += 1;
                weight *= continuation.growth;
                transcription.set_slack_weight(weight);
                Tolerances::Round(round)
            }
        };
        (solution, report) =
            next_solve(transcription, spec, options, solution, &report, tolerances)?;
        if last {
            break;
        }
    }
    Ok((solution, report))
}

/// The tolerances of a continuation solve after the first.
#[derive(Debug, Clone, Copy)]
enum Tolerances {
    /// Solve `round` of the continuation: tied to its relaxation ([`tie_tolerances`]).
    Round(usize),
    /// The file's own, μ monotone from a tenth of the last loose solve's tolerance (this).
    Final(f64),
}

/// One more solve of the continuation at the transcription's current slack weight, after
/// `solution` (Ipopt's `report`): the solution with every solve's iterations and times summed
/// and the solve's [`ContinuationSolve`] appended, and Ipopt's report.
///
/// Exact-penalty continuation: a finite α can leave the solve at a relaxed point; raise α and
/// restart from that point, near the central path (small μ and bound push, unless the problem
/// file or the caller sets them), so that the complementarity pattern found is kept. A solve
/// stopped by a limit is no such point (LittleDog with L-BFGS, stopped after 1500 iterations
/// at violation 4: the α = 3000 solve from there was still at violation 4 after 1100 more):
/// the raised-α solve then starts afresh from the guess.
fn next_solve<M: MechanicsDerivatives>(
    transcription: &mut Transcription<M>,
    spec: &ProblemSpec,
    options: &SolveOptions,
    solution: Solution,
    report: &ipopt::SolveReport,
    tolerances: Tolerances,
) -> Result<(Solution, ipopt::SolveReport), TranscriptionError> {
    let restart = match spec.slack_continuation {
        Some(c) if solution.status.is_success() => c.restart,
        _ => SlackRestart::InitialGuess,
    };
    let start = transcription.initial_point().to_vec();
    let warm = restart != SlackRestart::InitialGuess;
    if warm {
        transcription.set_initial_point(&report.x)?;
    }
    let mut solver = configure(spec, options)?;
    let mut warm_options = vec![
        ("bound_push", ipopt::OptionValue::Num(1e-6)),
        ("bound_frac", ipopt::OptionValue::Num(1e-6)),
    ];
    match restart {
        SlackRestart::InitialGuess => warm_options.clear(),
        SlackRestart::Primal => warm_options.push(("mu_init", ipopt::OptionValue::Num(1e-4))),
        SlackRestart::PrimalDual => {
            warm_options = primal_dual_warm_start();
            solver.set_starting_multipliers(Multipliers {
                g: report.mult_g.clone(),
                x_lower: report.mult_x_lower.clone(),
                x_upper: report.mult_x_upper.clone(),
            });
        }
    }
    set_unless_given(&mut solver, spec, options, warm_options)?;
    log_beside(
        &mut solver,
        options,
        &format!("solve{}", solution.solves + 1),
    )?;
    let tied = tie_tolerances(&mut solver, spec, options, tolerances)?;
    let mut nlp = adapter(transcription, spec, options);
    let outcome = solver.solve(&mut nlp);
    transcription.set_initial_point(&start)?;
    let next_report = outcome?;
    let mut next = Solution::read_off(transcription, spec, &next_report);
    let record = ContinuationSolve::of(&next, tied);
    next.add_work(&solution);
    next.solves = solution.solves + 1;
    next.continuation = solution.continuation;
    next.continuation.push(record);
    Ok((next, next_report))
}

/// `--ipopt-log` (Ipopt's `output_file` among the caller's options): a solve after the first
/// (a continuation's solve k, the polish) writes its log beside the first's, which it would
/// otherwise replace: `ipopt.log` → `ipopt.<tag>.log`.
fn log_beside(
    solver: &mut Solver,
    options: &SolveOptions,
    tag: &str,
) -> Result<(), TranscriptionError> {
    let log = options
        .ipopt_options
        .iter()
        .find(|(n, _)| n == "output_file");
    if let Some((_, OptionValue::Str(path))) = log {
        let beside = match path.strip_suffix(".log") {
            Some(stem) => format!("{stem}.{tag}.log"),
            None => format!("{path}.{tag}"),
        };
        solver.set_option("output_file", OptionValue::Str(beside))?;
    }
    Ok(())
}

/// `[slack] tied_tolerances` on a continuation solve; the tolerance it loosened, if any.
///
/// [`Tolerances::Round`] `r` (0 the first) stops at Ipopt tolerance 0.1 σ, σ the relaxation
/// its weight stands for ([`SlackContinuation::tied_sigma`]): `tol`, `mu_init` and
/// `mu_target` set to it and μ monotone (the file's `mu_strategy` notwithstanding: an adaptive
/// μ leaves the barrier problem the tolerance is tied to), while it is above the `tol` the
/// problem file or the caller gives (else Ipopt's 1e-8). [`Tolerances::Final`] after a loose
/// solve keeps the file's tolerances, μ monotone from a tenth of the loose solve's.
///
/// [`SlackContinuation::tied_sigma`]: crate::problem::SlackContinuation::tied_sigma
fn tie_tolerances(
    solver: &mut Solver,
    spec: &ProblemSpec,
    options: &SolveOptions,
    tolerances: Tolerances,
) -> Result<Option<f64>, TranscriptionError> {
    let Some(continuation) = spec.slack_continuation else {
        return Ok(None);
    };
    let Some(sigma) = continuation.tied_sigma else {
        return Ok(None);
    };
    let (mu_init, tol) = match tolerances {
        Tolerances::Final(loose) => (0.1 * loose, None),
        Tolerances::Round(round) => {
            let tol = 0.1 * sigma / continuation.growth.powi(round as i32);
            let own = given_number(spec, options, "tol").unwrap_or(IPOPT_TOL);
            // Not looser than the file's `tol` (up to round-off: 0.1 · 0.1 / 10⁴ is
            // 1.0000000000000002e-6).
            if tol <= own * (1.0 + 1e-9) {
                return Ok(None);
            }
            for name in ["tol", "mu_target"] {
                solver.set_option(name, OptionValue::Num(tol))?;
            }
            (tol, Some(tol))
        }
    };
    solver.set_option("mu_init", OptionValue::Num(mu_init))?;
    solver.set_option("mu_strategy", OptionValue::Str("monotone".into()))?;
    Ok(tol)
}

/// Ipopt's default `tol`.
const IPOPT_TOL: f64 = 1e-8;

/// The mode-fixed re-solve of `[slack] polish` ([`PolishRecord`]) from `solution`, an
/// optimum of the relaxed NLP or a feasible point at its iteration limit ([`polishable`];
/// Ipopt's `report`), started from its point and multipliers
/// (the freed complementarity rows' at zero) near the central path. The solution it returns
/// is the re-solve's if that is solved and `solution` is not, or its objective is no higher;
/// else `solution`; either way with the re-solve's iterations and times added and its record
/// attached.
fn polish<M: MechanicsDerivatives>(
    transcription: &mut Transcription<M>,
    spec: &ProblemSpec,
    options: &SolveOptions,
    mut solution: Solution,
    report: &ipopt::SolveReport,
) -> Result<Solution, TranscriptionError> {
    if transcription.layout().nc == 0 || !polishable(&solution, spec, options) || options.stopped()
    {
        return Ok(solution);
    }
    let (polished_report, fixed) =
        solve_modes_fixed(transcription, spec, options, &report.x, |solver, t| {
            let mut g = report.mult_g.clone();
            for r in t.freed_rows() {
                g[r] = 0.0;
            }
            solver.set_starting_multipliers(Multipliers {
                g,
                x_lower: report.mult_x_lower.clone(),
                x_upper: report.mult_x_upper.clone(),
            });
            set_unless_given(solver, spec, options, primal_dual_warm_start())?;
            log_beside(solver, options, "polish")
        })?;
    let mut polished = Solution::read_off(transcription, spec, &polished_report);
    let kept = polished.verdict().is_solved()
        && (!solution.verdict().is_solved() || polished.objective <= solution.objective);
    let record = PolishRecord {
        status: polished.status,
        verdict: polished.verdict(),
        status_before: solution.status,
        objective_before: solution.objective,
        max_slack_before: solution.max_slack,
        objective: polished.objective,
        iterations: polished.iterations,
        wall_time_s: polished.wall_time_s,
        kept,
        fixed,
    };
    let (mut kept_solution, other) = if kept {
        // `solves` and `continuation` are the relaxed NLP's solves, not the polish.
        polished.solves = solution.solves;
        polished.continuation = std::mem::take(&mut solution.continuation);
        (polished, solution)
    } else {
        (solution, polished)
    };
    kept_solution.add_work(&other);
    kept_solution.polish = Some(record);
    Ok(kept_solution)
}

/// Solves the NLP from `x` with the contact modes of `x` fixed
/// ([`Transcription::fix_contact_modes`]), `prepare` setting the solver up for it (it sees
/// the mode-fixed transcription); the bounds and the starting point are put back after.
/// Ipopt's report and the modes fixed.
pub(super) fn solve_modes_fixed<M: MechanicsDerivatives>(
    transcription: &mut Transcription<M>,
    spec: &ProblemSpec,
    options: &SolveOptions,
    x: &[f64],
    prepare: impl FnOnce(&mut Solver, &Transcription<M>) -> Result<(), TranscriptionError>,
) -> Result<(ipopt::SolveReport, FixedModes), TranscriptionError> {
    let (original, fixed) = transcription.fix_contact_modes(x);
    let start = transcription.initial_point().to_vec();
    let outcome = transcription.set_initial_point(x).and_then(|()| {
        let t: &Transcription<M> = transcription;
        let mut solver = configure(spec, options)?;
        prepare(&mut solver, t)?;
        let mut nlp = adapter(t, spec, options);
        Ok(solver.solve(&mut nlp)?)
    });
    transcription.restore_bounds(original);
    transcription.set_initial_point(&start)?;
    Ok((outcome?, fixed))
}

/// Ipopt's default `constr_viol_tol`: the largest constraint violation of a converged point.
const IPOPT_CONSTR_VIOL_TOL: f64 = 1e-4;

/// Whether the polish starts from `solution`: an optimum of the relaxed NLP, or a point where
/// Ipopt's iteration limit stopped it that satisfies the constraints within `constr_viol_tol`
/// (the problem's or the caller's, else Ipopt's default). From such a point the NLP with the
/// contact modes fixed, a regular one, may converge where the relaxed NLP wandered; its plan
/// is kept only if it is solved. A time limit or a stop request is the caller's end.
fn polishable(solution: &Solution, spec: &ProblemSpec, options: &SolveOptions) -> bool {
    if solution.status.is_success() {
        return true;
    }
    let tolerance = given_number(spec, options, "constr_viol_tol").unwrap_or(IPOPT_CONSTR_VIOL_TOL);
    solution.status == ipopt::Status::MaximumIterationsExceeded
        && solution.max_constraint_violation <= tolerance
}

/// A warm start from an optimum of a nearby NLP: its multipliers (given separately), a
/// barrier parameter near its own complementarity, and bounds and bound multipliers pushed
/// off zero as little.
fn primal_dual_warm_start() -> Vec<(&'static str, OptionValue)> {
    vec![
        ("bound_push", OptionValue::Num(1e-6)),
        ("bound_frac", OptionValue::Num(1e-6)),
        ("warm_start_init_point", OptionValue::Str("yes".into())),
        ("mu_init", OptionValue::Num(1e-6)),
        ("warm_start_bound_push", OptionValue::Num(1e-6)),
        ("warm_start_bound_frac", OptionValue::Num(1e-6)),
        ("warm_start_slack_bound_push", OptionValue::Num(1e-6)),
        ("warm_start_slack_bound_frac", OptionValue::Num(1e-6)),
        ("warm_start_mult_bound_push", OptionValue::Num(1e-6)),
    ]
}

/// The value of Ipopt option `name` as the problem file's `[solver.ipopt]` or the caller
/// gives it (the caller's last, which Ipopt applies last), if either does.
fn given_option<'a>(
    spec: &'a ProblemSpec,
    options: &'a SolveOptions,
    name: &str,
) -> Option<&'a OptionValue> {
    spec.solver_options
        .iter()
        .chain(&options.ipopt_options)
        .rev()
        .find(|(n, _)| n == name)
        .map(|(_, v)| v)
}

/// [`given_option`] `name` as a number (an integer counts), if it is given as one.
fn given_number(spec: &ProblemSpec, options: &SolveOptions, name: &str) -> Option<f64> {
    match given_option(spec, options, name)? {
        OptionValue::Num(x) => Some(*x),
        OptionValue::Int(i) => Some(*i as f64),
        OptionValue::Str(_) => None,
    }
}

/// Set each of `values` on `solver` unless the problem file or the caller gives it.
pub(super) fn set_unless_given(
    solver: &mut Solver,
    spec: &ProblemSpec,
    options: &SolveOptions,
    values: Vec<(&'static str, OptionValue)>,
) -> Result<(), TranscriptionError> {
    for (name, value) in values {
        if given_option(spec, options, name).is_none() {
            solver.set_option(name, value)?;
        }
    }
    Ok(())
}

/// The transcription as Ipopt's problem from its current starting point, with the scaling
/// `[solver] scaling` asks for (from units: taken at that point, as Ipopt's gradient rule is).
fn adapter<'a, M: MechanicsDerivatives>(
    transcription: &'a Transcription<M>,
    spec: &ProblemSpec,
    options: &'a SolveOptions,
) -> TranscriptionNlp<'a, M> {
    let scaling = match spec.scaling {
        ScalingMode::Ipopt => None,
        ScalingMode::Units => {
            let given: Vec<(String, OptionValue)> = spec
                .solver_options
                .iter()
                .chain(&options.ipopt_options)
                .cloned()
                .collect();
            Some(super::units_scaling(
                transcription,
                &given,
                ipopt_drops_fixed_variables(spec, options),
            ))
        }
    };
    TranscriptionNlp::new(transcription, options.progress.as_deref()).with_scaling(scaling)
}

/// Benchmark with the given mechanics and the initial guess as it stands: the benchmark behind
/// [`crate::pipeline::bench_with`], which resolves the guess first and is the entry point.
pub(crate) fn bench_with<M: MechanicsDerivatives>(
    mech: M,
    spec: &ProblemSpec,
) -> Result<BenchRow, TranscriptionError> {
    let options = SolveOptions {
        ipopt_options: vec![("print_level".into(), OptionValue::Int(0))],
        ..SolveOptions::default()
    };
    let mut t = Transcription::new(mech, spec)?;
    // Time the derivatives as the solve evaluates them.
    t.set_skip_fixed_variables(ipopt_drops_fixed_variables(spec, &options));
    let x = t.initial_point().to_vec();
    let mut jac = vec![0.0; t.jacobian_pattern().nnz()];
    let mut hess = vec![0.0; t.hessian_pattern().nnz()];
    let lambda = vec![1.0; t.layout().num_constraints()];
    let mut times = Vec::new();
    for _ in 0..7 {
        let start = Instant::now();
        t.jacobian_values(&x, &mut jac);
        t.hessian_values(&x, 1.0, &lambda, &mut hess);
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let derivative_eval_s = times[times.len() / 2];
    let s = solve_transcription(&mut t, spec, &options)?;
    Ok(BenchRow {
        name: spec.name.clone(),
        size: s.size,
        status: s.status,
        verdict: s.verdict(),
        objective: s.objective,
        iterations: s.iterations,
        solves: s.solves,
        max_slack: s.max_slack,
        wall_time_s: s.wall_time_s,
        callback_time_s: s.callback_time_s,
        ipopt_time_s: s.ipopt_time_s,
        callback_split: s.callback_split,
        derivative_eval_s,
    })
}

/// Whether Ipopt will drop the Hessian entries of variables fixed by their bounds: its default
/// `fixed_variable_treatment make_parameter`, unless the problem or the caller sets another.
fn ipopt_drops_fixed_variables(spec: &ProblemSpec, options: &SolveOptions) -> bool {
    match given_option(spec, options, "fixed_variable_treatment") {
        Some(OptionValue::Str(s)) => s == "make_parameter",
        Some(_) => false,
        None => true,
    }
}

/// Whether a solve that ended with `status` is worth continuing with a larger slack weight:
/// an optimum (warm start from it), or a solve stopped by an iteration or time limit (a fresh
/// start from the guess, where the larger weight often avoids the first solve's slow path).
/// Not after a cancel, a failure in the problem's functions or an infeasibility verdict.
fn restartable(status: ipopt::Status) -> bool {
    use ipopt::Status::*;
    status.is_success()
        || matches!(
            status,
            MaximumIterationsExceeded | MaximumCpuTimeExceeded | SearchDirectionBecomesTooSmall
        )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrete::ModelMechanics;
    use crate::transcription::fixture::hopper_spec;

    fn solve(spec: &ProblemSpec, options: &SolveOptions) -> Solution {
        let mech = ModelMechanics::load(spec).expect("the hopper's URDF loads");
        solve_with(mech, spec, options).expect("the solve runs")
    }

    /// The hopper's optimum, as the independent implementation finds it
    /// (`problems/golden.toml`).
    const HOPPER_OPTIMUM: f64 = 6.948567241208028;

    #[test]
    fn a_solve_reads_off_its_optimum() {
        let spec = hopper_spec(&[]);
        let s = solve(&spec, &SolveOptions::default());
        assert!(s.status.is_success(), "{:?}", s.status);
        assert!(matches!(s.verdict(), SolveVerdict::Solved(_)));
        assert!((s.objective - HOPPER_OPTIMUM).abs() <= 1e-6 * HOPPER_OPTIMUM);
        let terms: f64 = s.objective_terms.iter().map(|(_, v)| v).sum();
        assert!((s.objective - terms).abs() <= 1e-9 * s.objective);
        // The trajectory by knot: fixed start, the goal 0.5 m ahead, T = 1 s over 20 steps.
        assert_eq!(s.q.len(), 21);
        assert_eq!(s.q[0], spec.q_initial);
        assert!((s.q[20][0] - 0.5).abs() <= 1e-8);
        assert_eq!(s.times.last().copied(), Some(1.0));
        assert_eq!(s.slack.len(), 20);
        assert!(s.max_slack <= spec.slack_tolerance);
        // v_k = (q_k − q_{k−1}) / h from the knots themselves.
        let v = (s.q[10][1] - s.q[9][1]) / s.time_steps[9];
        assert!((s.v[10][1] - v).abs() <= 1e-12);
        assert_eq!(s.solves, 1);
    }

    /// The hopper's relaxed optimum (no polish), the transcription and Ipopt's report.
    fn relaxed_hopper() -> (
        ProblemSpec,
        Transcription<ModelMechanics>,
        Solution,
        ipopt::SolveReport,
    ) {
        let spec = hopper_spec(&["slack.polish=false"]);
        let mech = ModelMechanics::load(&spec).expect("the hopper's URDF loads");
        let mut t = Transcription::new(mech, &spec).expect("the hopper's NLP builds");
        let options = SolveOptions::default();
        let (solution, report) =
            solve_relaxed(&mut t, &spec, &options, false).expect("the solve runs");
        assert!(solution.verdict().is_solved(), "{:?}", solution.verdict());
        (spec, t, solution, report)
    }

    #[test]
    fn the_polish_fixes_one_side_of_every_pair_where_the_optimum_already_is() {
        let (_, mut t, _, report) = relaxed_hopper();
        let (x_lower, x_upper) = t.variable_bounds();
        let (g_lower, g_upper) = t.constraint_bounds();
        let before = (
            x_lower.to_vec(),
            x_upper.to_vec(),
            g_lower.to_vec(),
            g_upper.to_vec(),
        );
        let l = t.layout().clone();
        let (previous, fixed) = t.fix_contact_modes(&report.x);
        let pairs = l.intervals() * l.nc;
        assert_eq!(fixed.free + fixed.touching, pairs);
        assert_eq!(fixed.no_friction + fixed.opposing, pairs * l.nd);
        assert_eq!(fixed.sticking + fixed.sliding, pairs);
        // The hopper lands and takes off again: both modes occur.
        assert!(fixed.free > 0 && fixed.touching > 0, "{fixed:?}");
        // Each pair's fixed side is the one at zero, so the optimum, moved onto the new
        // bounds, still satisfies every row within Ipopt's tolerance; slacks are fixed at 0
        // and the complementarity rows are free.
        t.set_initial_point(&report.x).expect("the point's length");
        let x = t.initial_point().to_vec();
        let (violations, _) = t.row_violations(&x);
        let worst = violations.iter().fold(0.0_f64, |a, &b| a.max(b));
        assert!(
            worst <= 1e-6,
            "the optimum violates the mode-fixed rows by {worst:e}"
        );
        let moved = x
            .iter()
            .zip(&report.x)
            .fold(0.0_f64, |a, (p, q)| a.max((p - q).abs()));
        assert!(
            moved <= 1e-6,
            "fixing the modes moved the optimum by {moved:e}"
        );
        assert!(l.slacks().all(|s| t.variable_bounds().1[s] == 0.0));
        let freed: Vec<usize> = t.freed_rows().collect();
        assert_eq!(freed.len(), 3 * l.intervals());
        assert!(
            freed
                .iter()
                .all(|&r| t.constraint_bounds().0[r] == f64::NEG_INFINITY)
        );
        t.restore_bounds(previous);
        let (x_lower, x_upper) = t.variable_bounds();
        let (g_lower, g_upper) = t.constraint_bounds();
        assert_eq!(
            before,
            (
                x_lower.to_vec(),
                x_upper.to_vec(),
                g_lower.to_vec(),
                g_upper.to_vec()
            )
        );
    }

    #[test]
    fn the_polish_is_recorded_and_kept_only_when_no_worse() {
        let spec = hopper_spec(&[]);
        assert!(spec.slack_polish, "the polish is on by default");
        let s = solve(&spec, &SolveOptions::default());
        let p = s
            .polish
            .clone()
            .expect("a solve with contacts ends with the polish");
        assert!(p.verdict.is_solved(), "{:?}", p.verdict);
        assert_eq!(p.objective_before.to_bits(), s.objective.to_bits());
        assert!(p.status_before.is_success(), "{:?}", p.status_before);
        // The relaxed optimum is solved already; the mode-fixed one ends no lower (its
        // slack penalty is exactly zero where the relaxed one's is −2e-5), so it is not kept.
        assert!(!p.kept);
        assert!(p.objective >= p.objective_before);
        assert!((p.objective - HOPPER_OPTIMUM).abs() <= 1e-5 * HOPPER_OPTIMUM);
        assert!(p.iterations > 0 && s.iterations > p.iterations);
        assert_eq!(s.solves, 1, "solves counts the relaxed NLP's");
        let off = solve(
            &hopper_spec(&["slack.polish=false"]),
            &SolveOptions::default(),
        );
        assert!(off.polish.is_none());
        assert_eq!(off.objective.to_bits(), s.objective.to_bits());
        assert_eq!(off.iterations + p.iterations, s.iterations);
    }

    #[test]
    fn a_feasible_point_at_the_iteration_limit_is_polished_and_an_infeasible_one_is_not() {
        // Stopped two iterations before its optimum, the relaxed solve's point satisfies the
        // constraints: the polish from there solves the mode-fixed NLP near the optimum.
        let full = solve(
            &hopper_spec(&["slack.polish=false"]),
            &SolveOptions::default(),
        );
        assert!(full.verdict().is_solved(), "{:?}", full.verdict());
        let limit = full.iterations - 2;
        let max_iter = format!("solver.ipopt.max_iter={limit}");
        let spec = hopper_spec(&[max_iter.as_str()]);
        let s = solve(&spec, &SolveOptions::default());
        let p = s.polish.clone().unwrap_or_else(|| {
            panic!(
                "no polish at the limit {limit}: {:?}, violation {:e}",
                s.status, s.max_constraint_violation
            )
        });
        assert_eq!(
            s.iterations,
            limit + p.iterations,
            "the relaxed solve hit the limit"
        );
        assert_eq!(p.status_before, ipopt::Status::MaximumIterationsExceeded);
        assert!(p.kept && s.verdict().is_solved(), "{:?}", s.verdict());
        assert!(s.max_slack <= spec.slack_tolerance);
        assert!(s.max_constraint_violation <= 1e-6);
        assert!(
            (s.objective - HOPPER_OPTIMUM).abs() <= 1e-4 * HOPPER_OPTIMUM,
            "{}",
            s.objective
        );
        // After three iterations the constraints are violated by far more than Ipopt's
        // constr_viol_tol (1e-4): no polish, the iteration limit stays the verdict.
        let early = solve(
            &hopper_spec(&["solver.ipopt.max_iter=3"]),
            &SolveOptions::default(),
        );
        assert_eq!(early.status, ipopt::Status::MaximumIterationsExceeded);
        assert!(early.max_constraint_violation > 1e-4);
        assert!(early.polish.is_none());
        assert!(!early.verdict().is_solved());
    }

    #[test]
    fn a_product_hidden_by_another_in_the_rows_sum_is_slack() {
        // Interval 5's η_+ huge with β_+ at Ipopt's relaxed bound −1e-8 (a product of −0.01)
        // and a real η_−·β_− = 0.1·0.1: the ηᵀβ row's sum is unchanged, the plan is not.
        let (spec, t, solved, mut report) = relaxed_hopper();
        let l = t.layout();
        let (beta, eta) = (l.beta(5, 0), l.eta(5, 0));
        report.x[beta.start] = -1e-8;
        report.x[eta.start] = 1e6;
        report.x[beta.start + 1] = 0.1;
        report.x[eta.start + 1] = 0.1;
        let mut g = vec![0.0; l.num_constraints()];
        t.constraints(&report.x, &mut g);
        let row = l.rows_of("Complementarity", 5).start;
        assert!(
            g[row] >= -1e-6,
            "the row's sum hides the product: {:e}",
            g[row]
        );
        let s = Solution::read_off(&t, &spec, &report);
        assert!((s.max_slack - 0.01).abs() <= 1e-6, "{:e}", s.max_slack);
        let peak = s.slack_peak.clone().expect("a peak");
        assert_eq!(peak.interval, 5);
        assert_eq!(
            peak.contact.as_deref(),
            Some(spec.contacts[0].name.as_str())
        );
        // The slack variables do not hold it: a higher weight would not close it.
        assert!(peak.hidden);
        assert_eq!(s.verdict(), SolveVerdict::RelaxedContact);
        assert!(solved.max_slack <= 1e-6, "{:e}", solved.max_slack);
        assert!(!solved.slack_peak.expect("a peak").hidden);
    }

    #[test]
    fn multi_start_keeps_the_best_solved_start_and_records_every_start() {
        let spec = hopper_spec(&[]);
        let options = SolveOptions {
            multi_start: Some(MultiStart {
                starts: 3,
                seed: 5,
                only: None,
            }),
            ..SolveOptions::default()
        };
        let s = solve(&spec, &options);
        assert_eq!(s.starts.len(), 3);
        let seeds: Vec<Option<u64>> = s.starts.iter().map(|r| r.seed).collect();
        assert_eq!(seeds, [None, Some(6), Some(7)]);
        let best = s
            .starts
            .iter()
            .enumerate()
            .filter_map(|(k, r)| match &r.outcome {
                StartOutcome::Ended(e) if e.verdict.is_solved() => Some((k, e.objective)),
                _ => None,
            })
            .min_by(|a, b| a.1.total_cmp(&b.1));
        assert_eq!(best, Some((s.best_start, s.objective)));
        // Each start solved on its own and merged gives the same answer.
        let alone: Vec<(usize, Solution)> = (0..3)
            .map(|k| {
                let only = SolveOptions {
                    multi_start: Some(MultiStart {
                        starts: 3,
                        seed: 5,
                        only: Some(k),
                    }),
                    ..SolveOptions::default()
                };
                (k, solve(&spec, &only))
            })
            .collect();
        let merged = best_of(alone.clone(), Vec::new()).expect("three starts");
        assert_eq!(merged.best_start, s.best_start);
        assert_eq!(merged.objective.to_bits(), s.objective.to_bits());
        assert_eq!(merged.starts.len(), 3);
        // A start whose process was lost keeps its place: the best is still found by number.
        let lost = StartRecord {
            seed: Some(6),
            outcome: StartOutcome::Lost(LostStart {
                signal: Some(9),
                how: "killed by signal 9 (SIGKILL)".into(),
            }),
        };
        let kept: Vec<(usize, Solution)> = alone.into_iter().filter(|(k, _)| *k != 1).collect();
        let merged = best_of(kept, vec![(1, lost.clone())]).expect("two starts");
        assert_eq!(merged.starts.len(), 3);
        assert_eq!(merged.starts[1], lost);
        assert_eq!(merged.starts[0].seed, None);
        assert_eq!(merged.starts[2].seed, Some(7));
    }

    #[test]
    fn the_continuation_raises_the_weight_until_the_slack_is_below_its_target() {
        let spec = hopper_spec(&["slack.weight=1e-3", "slack.target=1e-6", "slack.rounds=6"]);
        let s = solve(&spec, &SolveOptions::default());
        assert!(
            s.solves > 1,
            "the first solve at α = 1e-3 already met the target"
        );
        let weight = 1e-3 * 10f64.powi(s.solves as i32 - 1);
        assert!((s.slack_weight - weight).abs() <= 1e-12 * weight);
        assert!(s.max_slack <= 1e-6, "{}", s.max_slack);
    }

    #[test]
    fn only_optima_and_limits_restart_the_continuation() {
        use ipopt::Status::*;
        assert!(restartable(SolveSucceeded) && restartable(MaximumIterationsExceeded));
        assert!(!restartable(UserRequestedStop) && !restartable(InfeasibleProblemDetected));
    }
}
