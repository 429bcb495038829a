//! Solving a problem's NLP: build the transcription, run Ipopt (multi-start, slack
//! continuation), fill a [`Solution`]; plus the benchmark row. The entry point is
//! [`crate::pipeline::solve`], which loads the robot and resolves the initial guess first.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use super::blocks::complementarity_penalty::{interval_products, interval_slack};
use super::nlp::{ProgressFn, TranscriptionNlp};
use super::{
    MechanicsDerivatives, NlpSize, Solution, SolveVerdict, Transcription, TranscriptionError,
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
    fn stopped(&self) -> bool {
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

/// Relative size of a multi-start perturbation.
pub const PERTURBATION: f64 = 0.1;

/// One start of a multi-start solve, as `summary.json` lists it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StartRecord {
    /// 0 for the problem's own guess, else the perturbation's seed.
    pub seed: Option<u64>,
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
    let given = |name: &str| {
        spec.solver_options
            .iter()
            .chain(&options.ipopt_options)
            .any(|(n, _)| n == name)
    };
    if spec.slack_mode == SlackMode::Penalty && !given(PENALTY_BOUND_RELAX.0) {
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
        let (start, seed) = if k == 0 {
            (guess, None)
        } else {
            let seed = multi.seed.wrapping_add(k as u64);
            (perturbed(&transcription, &guess, seed), Some(seed))
        };
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
        let seed = multi.seed.wrapping_add(k as u64);
        let start = perturbed(&transcription, &guess, seed);
        let solution = solve_from(
            &mut transcription,
            spec,
            options,
            &start,
            Some(seed),
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
        status: solution.status,
        verdict: solution.verdict(),
        objective: solution.objective,
        objective_terms: solution.objective_terms.clone(),
        max_slack: solution.max_slack,
        max_constraint_violation: solution.max_constraint_violation,
        iterations: solution.iterations,
        wall_time_s: solution.wall_time_s,
    });
    Ok(solution)
}

/// The best of starts solved one by one (each with `only` set, listing its own record): all
/// their records in start order and the best solution, as one multi-start solve of them all
/// returns it (ties go to the earlier start). None when `solutions` is empty.
pub fn best_of(mut solutions: Vec<(usize, Solution)>) -> Option<Solution> {
    solutions.sort_by_key(|(k, _)| *k);
    let records: Vec<StartRecord> = solutions
        .iter()
        .flat_map(|(_, s)| s.starts.iter().cloned())
        .collect();
    let mut best: Option<(usize, Solution)> = None;
    for (i, (_, s)) in solutions.into_iter().enumerate() {
        if best.as_ref().is_none_or(|(_, b)| better(&s, b)) {
            best = Some((i, s));
        }
    }
    best.map(|(i, mut s)| {
        s.starts = records;
        s.best_start = i;
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

/// Solve, then continue with a growing slack weight while `[slack] target` asks for it.
fn solve_transcription<M: MechanicsDerivatives>(
    transcription: &mut Transcription<M>,
    spec: &ProblemSpec,
    options: &SolveOptions,
) -> Result<Solution, TranscriptionError> {
    transcription.set_skip_fixed_variables(ipopt_drops_fixed_variables(spec, options));
    let mut solver = configure(spec, options)?;
    let mut nlp = adapter(transcription, spec, options);
    let report = solver.solve(&mut nlp)?;
    let mut solution = fill_solution(transcription, spec, &report);
    let Some(continuation) = spec.slack_continuation else {
        return Ok(solution);
    };
    // Exact-penalty continuation: a finite α can leave the solve at a relaxed point;
    // raise α and restart from that point, near the central path (small μ and bound push, unless
    // the problem file or the caller sets them), so that the complementarity pattern found is
    // kept. A solve stopped by a limit is no such point (LittleDog with L-BFGS, stopped after
    // 1500 iterations at violation 4: the α = 3000 solve from there was still at violation 4
    // after 1100 more): the raised-α solve then starts afresh from the guess.
    let guess = transcription.initial_point().to_vec();
    let mut report = report;
    let mut weight = spec.slack_weight;
    for _ in 0..continuation.rounds {
        if solution.max_slack <= continuation.target
            || !restartable(solution.status)
            || options.stopped()
        {
            break;
        }
        weight *= continuation.growth;
        transcription.set_slack_weight(weight);
        let restart = if solution.status.is_success() {
            continuation.restart
        } else {
            SlackRestart::InitialGuess
        };
        let warm = restart != SlackRestart::InitialGuess;
        transcription.set_initial_point(if warm { &report.x } else { &guess })?;
        let mut solver = configure(spec, options)?;
        let mut warm_options = vec![
            ("bound_push", ipopt::OptionValue::Num(1e-6)),
            ("bound_frac", ipopt::OptionValue::Num(1e-6)),
        ];
        match restart {
            SlackRestart::InitialGuess => warm_options.clear(),
            SlackRestart::Primal => warm_options.push(("mu_init", ipopt::OptionValue::Num(1e-4))),
            SlackRestart::PrimalDual => {
                // The last optimum's multipliers, and a barrier parameter near its own
                // complementarity; bound multipliers pushed off zero like the bounds.
                warm_options.extend([
                    (
                        "warm_start_init_point",
                        ipopt::OptionValue::Str("yes".into()),
                    ),
                    ("mu_init", ipopt::OptionValue::Num(1e-6)),
                    ("warm_start_bound_push", ipopt::OptionValue::Num(1e-6)),
                    ("warm_start_bound_frac", ipopt::OptionValue::Num(1e-6)),
                    ("warm_start_slack_bound_push", ipopt::OptionValue::Num(1e-6)),
                    ("warm_start_slack_bound_frac", ipopt::OptionValue::Num(1e-6)),
                    ("warm_start_mult_bound_push", ipopt::OptionValue::Num(1e-6)),
                ]);
                solver.set_starting_multipliers(Multipliers {
                    g: report.mult_g.clone(),
                    x_lower: report.mult_x_lower.clone(),
                    x_upper: report.mult_x_upper.clone(),
                });
            }
        }
        for (name, value) in warm_options {
            let given = spec
                .solver_options
                .iter()
                .chain(&options.ipopt_options)
                .any(|(n, _)| n == name);
            if !given {
                solver.set_option(name, value)?;
            }
        }
        let mut nlp = adapter(transcription, spec, options);
        let next_report = solver.solve(&mut nlp)?;
        let mut next = fill_solution(transcription, spec, &next_report);
        next.iterations += solution.iterations;
        next.wall_time_s += solution.wall_time_s;
        next.callback_time_s += solution.callback_time_s;
        next.callback_split = next.callback_split.plus(&solution.callback_split);
        next.ipopt_time_s += solution.ipopt_time_s;
        next.solves = solution.solves + 1;
        solution = next;
        report = next_report;
    }
    Ok(solution)
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
            Some(transcription.units_scaling(&given, ipopt_drops_fixed_variables(spec, options)))
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
    !spec
        .solver_options
        .iter()
        .chain(&options.ipopt_options)
        .any(|(name, value)| {
            name == "fixed_variable_treatment"
                && !matches!(value, OptionValue::Str(s) if s == "make_parameter")
        })
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

/// Signed distance φ_i(q) of every contact at q.
fn distances<M: MechanicsDerivatives>(t: &Transcription<M>, q: &[f64]) -> Vec<f64> {
    (0..t.layout().nc)
        .map(|i| crate::contact::distance(t.mechanics(), &t.context().contact, i, q))
        .collect()
}

fn fill_solution<M: MechanicsDerivatives>(
    t: &Transcription<M>,
    spec: &ProblemSpec,
    report: &ipopt::SolveReport,
) -> Solution {
    let l = t.layout();
    let x = &report.x;
    let q: Vec<Vec<f64>> = (0..l.knots).map(|k| x[l.q(k)].to_vec()).collect();
    let time_steps: Vec<f64> = (0..l.intervals()).map(|j| x[l.h(j)]).collect();
    let times: Vec<f64> = match time_steps.first() {
        // Equal steps (fixed, or free steps that ended equal): t_k = k·h, in decimal.
        Some(&h) if time_steps.iter().all(|&s| s == h) => (0..l.knots)
            .map(|k| crate::files::trajectory_csv::knot_time(k, h))
            .collect(),
        _ => {
            let mut times = vec![0.0];
            for h in &time_steps {
                times.push(times.last().copied().unwrap_or(0.0) + h);
            }
            times
        }
    };
    let mut v = vec![x[l.v0()].to_vec()];
    for j in 0..l.intervals() {
        v.push(
            q[j + 1]
                .iter()
                .zip(&q[j])
                .map(|(b, a)| (b - a) / time_steps[j])
                .collect(),
        );
    }
    let mut normal_impulse = Vec::new();
    let mut friction_impulse = Vec::new();
    let mut slack = Vec::new();
    let mut max_complementarity = 0.0_f64;
    // φ at every knot; the impulses of interval j are complementary to φ at knot j + 1.
    let signed_distance: Vec<Vec<f64>> = q.iter().map(|qk| distances(t, qk)).collect();
    for j in 0..l.intervals() {
        let phi = &signed_distance[j + 1];
        let c: Vec<f64> = (0..l.nc).map(|i| x[l.c(j, i)]).collect();
        let beta: Vec<Vec<f64>> = (0..l.nc).map(|i| x[l.beta(j, i)].to_vec()).collect();
        // Report the slack and the clipped c·φ. The other two products (ηᵀβ and
        // ψ(μc − eᵀβ)) are not meaningful per contact: ψ and η are undetermined in flight
        // and stick and drift to 1e5–1e8, where Ipopt's 1e-8 bound relaxation shows as
        // O(1e-2) terms that cancel within a row.
        let contact_gap: f64 = (0..l.nc).map(|i| c[i].max(0.0) * phi[i].max(0.0)).sum();
        max_complementarity = max_complementarity.max(contact_gap);
        normal_impulse.push(c);
        friction_impulse.push(beta);
        // A slack is ≥ 0; Ipopt's bound relaxation leaves it at −1e-8 where it is 0.
        slack.push(x[l.slack(j)].iter().map(|s| s.max(0.0)).collect());
    }
    let contact_names: Vec<String> = spec.contacts.iter().map(|c| c.name.clone()).collect();
    let (max_slack, slack_peak) = if l.slack_mode == SlackMode::Penalty {
        // No slack variables: an interval's slack is the one the elastic form would hold
        // there, the largest sum of its products (so a plan whose products exceed the
        // tolerance is still `relaxed_contact`).
        let products = interval_products(l, t.context(), x, &signed_distance);
        slack = products.iter().map(|p| vec![interval_slack(p)]).collect();
        let peak = penalty_slack_peak(&products, &contact_names);
        (peak.as_ref().map_or(0.0, |p| p.slack), peak)
    } else {
        let max_slack = x[l.slacks()].iter().fold(0.0_f64, |a, &b| a.max(b));
        (
            max_slack,
            slack_peak(t, x, &signed_distance, &contact_names),
        )
    };
    let contact_positions = q
        .iter()
        .map(|qk| {
            (0..l.nc)
                .map(|i| t.mechanics().contact_position(i, qk))
                .collect()
        })
        .collect();
    let (row_violations, _) = t.row_violations(x);
    let max_constraint_violation = row_violations.iter().fold(0.0_f64, |a, &b| a.max(b));
    let coordinate_names = t.mechanics().coordinate_names();
    let input_names = t.mechanics().input_names();
    let worst_rows = worst_rows(
        l,
        &row_violations,
        crate::transcription::EntryNames {
            coordinates: &coordinate_names,
            inputs: &input_names,
            contacts: &contact_names,
        },
    );
    Solution {
        status: report.status,
        objective: report.objective,
        objective_terms: t.objective_terms(x),
        iterations: report.iterations,
        wall_time_s: report.wall_time_s,
        callback_time_s: report.callback_time_s,
        ipopt_time_s: report.ipopt_time_s,
        callback_split: report.callback_split,
        size: t.size(),
        coordinate_names,
        input_names,
        contact_names,
        friction_directions: l.nd,
        times,
        time_steps,
        u: (0..l.intervals()).map(|j| x[l.u(j)].to_vec()).collect(),
        q,
        v,
        normal_impulse,
        friction_impulse,
        signed_distance,
        contact_positions,
        slack,
        max_slack,
        slack_peak,
        slack_tolerance: spec.slack_tolerance,
        max_complementarity,
        max_constraint_violation,
        worst_rows,
        slack_weight: t.slack_weight(),
        solves: 1,
        starts: Vec::new(),
        best_start: 0,
    }
}

/// Where the largest slack of x sits: its interval, and the contact it relaxes (its own in
/// per-contact mode; else the contact with the largest clipped product c·φ, ηᵀβ or
/// ψ(μc − eᵀβ) in that interval).
fn slack_peak<M: MechanicsDerivatives>(
    t: &Transcription<M>,
    x: &[f64],
    distance: &[Vec<f64>],
    contacts: &[String],
) -> Option<crate::transcription::SlackPeak> {
    let l = t.layout();
    let per = l.slacks_per_interval();
    let (index, slack) = x[l.slacks()].iter().copied().enumerate().fold(
        None,
        |best: Option<(usize, f64)>, (i, s)| match best {
            Some((_, b)) if s <= b || s.is_nan() => best,
            _ => Some((i, s)),
        },
    )?;
    let interval = index / per;
    let contact = if per > 1 {
        // Per-contact mode: three slacks per contact, in contact order.
        Some((index % per) / 3)
    } else {
        use crate::contact::{Own, Partner, Products};
        let j = interval;
        // c·φ of the clipped factors (c and φ both at Ipopt's relaxed bound −1e-8 would make
        // a positive product); ηᵀβ and ψ(μc − eᵀβ) raw, as the slack's rows have them, so an
        // interval where they are ≤ 0 names no contact.
        let product = |i: usize| {
            let own = Own {
                c: x[l.c(j, i)],
                psi: x[l.psi(j, i)],
                eta: &x[l.eta(j, i)],
            };
            let beta = &x[l.beta(j, i)];
            let mu = t.context().contact.friction[i];
            let partner = Partner {
                phi: distance[j + 1][i],
                beta,
                cone: crate::contact::cone(mu, own.c, beta),
            };
            let raw = Products::new(&own, &partner);
            let clipped = Products::clipped(&own, [partner]);
            clipped.gap.max(raw.eta_beta).max(raw.cone)
        };
        (0..l.nc)
            .map(|i| (i, product(i)))
            .filter(|&(_, p)| p > 0.0)
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    };
    Some(crate::transcription::SlackPeak {
        interval,
        contact: contact.and_then(|i| contacts.get(i).cloned()),
        slack: slack.max(0.0),
    })
}

/// Where the largest interval slack of penalty mode sits ([`interval_slack`] of each
/// interval's products): its interval and the contact with the largest product there (None
/// when no product is positive).
fn penalty_slack_peak(
    products: &[Vec<[f64; 3]>],
    contacts: &[String],
) -> Option<crate::transcription::SlackPeak> {
    let (interval, slack) = products
        .iter()
        .map(|p| interval_slack(p))
        .enumerate()
        .fold(None, |best: Option<(usize, f64)>, (j, s)| match best {
            Some((_, b)) if s <= b || s.is_nan() => best,
            _ => Some((j, s)),
        })?;
    let contact = products[interval]
        .iter()
        .map(|p| p.iter().copied().fold(0.0_f64, f64::max))
        .enumerate()
        .filter(|&(_, p)| p > 0.0)
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .and_then(|(i, _)| contacts.get(i).cloned());
    Some(crate::transcription::SlackPeak {
        interval,
        contact,
        slack,
    })
}

/// A row violated by at most this much is not listed among the worst rows: Ipopt relaxes
/// bounds by 1e-8 (`bound_relax_factor`), so solved points show violations of that order.
const LISTED_VIOLATION: f64 = 1e-6;

/// The most violated rows (at most [`Solution::WORST_ROWS`], each by more than
/// [`LISTED_VIOLATION`]), worst first, named as `vito check --derivatives` names them.
fn worst_rows(
    l: &crate::transcription::Layout,
    violations: &[f64],
    names: crate::transcription::EntryNames,
) -> Vec<crate::transcription::RowViolation> {
    let mut rows: Vec<usize> = (0..violations.len())
        .filter(|&r| violations[r] > LISTED_VIOLATION)
        .collect();
    rows.sort_by(|&a, &b| violations[b].total_cmp(&violations[a]).then(a.cmp(&b)));
    rows.truncate(Solution::WORST_ROWS);
    rows.into_iter()
        .map(|r| crate::transcription::RowViolation {
            row: l.row_name(r, names),
            violation: violations[r],
        })
        .collect()
}
