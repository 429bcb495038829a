//! `summary.json`: the numbers scripts and CI read after a solve.

use serde_json::{Map, Value, json};

use crate::ipopt::Status;
use crate::problem::LoadedProblem;
use crate::report::modes::{FLIGHT_RELATIVE, SLIDE_CONE_FRACTION};
use crate::transcription::{Solution, SolveVerdict, StartOutcome};

/// Ipopt's return status in snake case, e.g. `solve_succeeded`.
pub fn status_name(status: Status) -> &'static str {
    status.as_snake_case()
}

/// The verdict a `summary.json` records ([`SolveVerdict::of_summary`]).
pub fn summary_verdict(summary: &Value) -> Option<SolveVerdict> {
    SolveVerdict::of_summary(summary)
}

/// The threads a solve's arithmetic ran on: the linear algebra's (one, set before every
/// solve by [`crate::ipopt::pin_one_thread`]; null for a library that is not loaded) and
/// rayon's (the derivatives' blocks, whose results do not depend on it).
fn threads_json() -> Value {
    let blas = crate::ipopt::pin_one_thread();
    json!({
        "openblas": blas.openblas_threads,
        "openblas_config": blas.openblas_config,
        "openblas_core": blas.openblas_core,
        "blis": blas.blis.then_some(1),
        "openmp": blas.omp_threads,
        "rayon": rayon::current_num_threads(),
    })
}

/// JSON-safe number: NaN and ±∞ become null.
fn num(x: f64) -> Value {
    if x.is_finite() { json!(x) } else { Value::Null }
}

/// Objective terms as a JSON object by name.
fn terms_json(terms: &[(String, f64)]) -> Value {
    let mut map = Map::new();
    for (name, value) in terms {
        map.insert(name.clone(), num(*value));
    }
    Value::Object(map)
}

/// Builds the summary object.
pub fn summary_json(problem: &LoadedProblem, solution: &Solution) -> Value {
    let s = solution;
    let terms = terms_json(&s.objective_terms);
    let mut parameters = Map::new();
    for (path, value) in &problem.parameters {
        let parsed: Value = toml::from_str::<toml::Table>(&format!("v = {value}"))
            .ok()
            .and_then(|t| t.get("v").cloned())
            .and_then(|v| serde_json::to_value(v).ok())
            .unwrap_or_else(|| json!(value));
        parameters.insert(path.clone(), parsed);
    }
    let mut final_q = Map::new();
    if let Some(q) = s.q.last() {
        for (name, v) in s.coordinate_names.iter().zip(q) {
            final_q.insert(name.clone(), num(*v));
        }
    }
    let verdict = s.verdict();
    let worst_rows: Vec<Value> = s
        .worst_rows
        .iter()
        .map(|r| json!({"row": r.row, "violation": num(r.violation)}))
        .collect();
    let mut summary = json!({
        "kind": "plan",
        "status": verdict.name(),
        "solved": verdict.is_solved(),
        "ipopt_status": status_name(s.status),
        "objective": num(s.objective),
        "objective_terms": terms,
        "iterations": s.iterations,
        "wall_time_s": num(s.wall_time_s),
        "callback_time_s": num(s.callback_time_s),
        "ipopt_time_s": num(s.ipopt_time_s),
        "callbacks": s
            .callback_split
            .entries()
            .iter()
            .map(|(name, stat)| (name.to_string(), json!({"calls": stat.calls, "seconds": num(stat.seconds)})))
            .collect::<Map<String, Value>>(),
        "max_slack": num(s.max_slack),
        "max_slack_at": s.slack_peak.as_ref().map(|p| json!({
            "interval": p.interval,
            "contact": p.contact,
            "hidden": p.hidden,
        })),
        "slack_tolerance": num(s.slack_tolerance),
        "max_complementarity": num(s.max_complementarity),
        "max_constraint_violation": num(s.max_constraint_violation),
        "worst_rows": worst_rows,
        "slack_weight": num(s.slack_weight),
        "solves": s.solves,
        "n_variables": s.size.n_variables,
        "n_constraints": s.size.n_constraints,
        "nnz_jacobian": s.size.nnz_jacobian,
        "nnz_hessian": s.size.nnz_hessian,
        "knots": s.times.len(),
        "integrator": problem.spec.integrator.name(),
        "total_time": num(s.times.last().copied().unwrap_or(0.0)),
        "final_q": final_q,
        "problem": problem.spec.name,
        "problem_file": problem.file.display().to_string(),
        "problem_sha256": problem.sha256,
        "parameters": parameters,
        "vito_version": env!("CARGO_PKG_VERSION"),
        "ipopt_version": crate::ipopt::VERSION,
        // The BLAS kernels (the `vito` binary pins them; see `ipopt::blas_kernels`).
        "openblas_coretype": std::env::var("OPENBLAS_CORETYPE").ok(),
        "threads": threads_json(),
        "units": {
            "length": problem.units.length,
            "mass": problem.units.mass,
            "time": problem.units.time,
        },
        "contact_mode_thresholds": {
            "flight_below_fraction_of_max_normal_impulse": FLIGHT_RELATIVE,
            "slide_at_fraction_of_friction_cone": SLIDE_CONE_FRACTION,
        },
    });
    let (metrics, metric_units) = super::metrics_json(
        &problem.spec.metrics,
        &problem.units,
        &super::MetricInputs {
            times: &s.times,
            q: &s.q,
            contact_positions: &s.contact_positions,
        },
    );
    if let Some(p) = &s.polish {
        summary["polish"] = polish_json(p);
    }
    if let Some(c) = &s.carried_modes {
        summary["carried_modes"] = json!({
            "status": c.verdict.name(),
            "objective": num(c.objective),
            "iterations": c.iterations,
            "wall_time_s": num(c.wall_time_s),
            "kept": c.kept,
            "fixed": c.fixed,
        });
    }
    if !s.continuation.is_empty() {
        summary["continuation"] = continuation_json(&s.continuation);
    }
    if !s.levels.is_empty() {
        summary["levels"] = Value::Array(
            s.levels
                .iter()
                .map(|l| {
                    json!({
                        "knots": l.knots,
                        "status": l.verdict.name(),
                        "objective": num(l.objective),
                        "max_slack": num(l.max_slack),
                        "iterations": l.iterations,
                        "wall_time_s": num(l.wall_time_s),
                        "max_q_difference": l.max_q_difference.map(num),
                        "carried_modes_kept": l.carried_modes_kept,
                    })
                })
                .collect(),
        );
    }
    if let Some(start) = &s.simulation_start {
        summary["simulation_start"] = json!({
            "steps": start.steps,
            "simulation_time_s": num(start.simulation_time_s),
            "simulation_residual": num(start.simulation_residual),
            "status": start.verdict.name(),
            "iterations": start.iterations,
            "max_q_difference": num(start.max_q_difference),
            "kept": start.kept,
        });
    }
    summary["metrics"] = metrics;
    summary["metric_units"] = metric_units;
    if !s.starts.is_empty() {
        // A multi-start solve: every start, and which one this summary describes.
        let starts: Vec<Value> = s
            .starts
            .iter()
            .map(|r| match &r.outcome {
                StartOutcome::Ended(e) => json!({
                    "seed": r.seed,
                    "status": e.verdict.name(),
                    "ipopt_status": status_name(e.status),
                    "objective": num(e.objective),
                    "objective_terms": terms_json(&e.objective_terms),
                    "max_slack": num(e.max_slack),
                    "max_constraint_violation": num(e.max_constraint_violation),
                    "iterations": e.iterations,
                    "wall_time_s": num(e.wall_time_s),
                    "polish": e.polish.as_ref().map(polish_json),
                    "continuation": continuation_json(&e.continuation),
                }),
                StartOutcome::Lost(lost) => json!({
                    "seed": r.seed,
                    "status": lost.status(),
                    "ended": lost.how,
                }),
            })
            .collect();
        summary["starts"] = Value::Array(starts);
        summary["best_start"] = json!(s.best_start);
    }
    summary
}

/// The slack continuation's solves as summary.json lists them, in order.
fn continuation_json(solves: &[crate::transcription::ContinuationSolve]) -> Value {
    solves
        .iter()
        .map(|c| {
            json!({
                "slack_weight": num(c.slack_weight),
                "tied_tol": c.tied_tol.map(num),
                "ipopt_status": status_name(c.status),
                "objective": num(c.objective),
                "max_slack": num(c.max_slack),
                "iterations": c.iterations,
                "wall_time_s": num(c.wall_time_s),
            })
        })
        .collect()
}

/// The mode-fixed re-solve of `[slack] polish` as summary.json lists it.
fn polish_json(p: &crate::transcription::PolishRecord) -> Value {
    json!({
        "status": p.verdict.name(),
        "ipopt_status": status_name(p.status),
        "ipopt_status_before": status_name(p.status_before),
        "objective_before": num(p.objective_before),
        "max_slack_before": num(p.max_slack_before),
        "objective": num(p.objective),
        "iterations": p.iterations,
        "wall_time_s": num(p.wall_time_s),
        "kept": p.kept,
        "fixed": p.fixed,
    })
}
