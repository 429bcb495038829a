//! `vito bench`: sizes and timings of problems (by default the reference problems),
//! beside the independent CasADi implementation where it can run.

use std::path::PathBuf;

use vito::pipeline;
use vito::problem::load;

use super::args::parse_overrides;
use super::error::CliError;
use vito::regress::reference;

/// Prints one `pipeline::bench` row per problem (sizes, solve and derivative times),
/// then, where `casadi` asks for it and can, the same problems solved by the independent
/// CasADi implementation, side by side (each CasADi solve runs right after vito's, so both
/// see the same machine load).
pub(super) fn bench(files: &[PathBuf], set: &[String], casadi: bool) -> Result<u8, CliError> {
    let overrides = parse_overrides(set)?;
    let files: Vec<PathBuf> = if files.is_empty() {
        reference::NAMES.map(reference::file).to_vec()
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
    // The CasADi script implements the reference problems as they are: not with `--set`.
    let independent = match (casadi, set.is_empty()) {
        (false, _) => Err("left out (--no-casadi)".to_owned()),
        (true, false) => {
            Err("left out: --set changes the NLP the CasADi script implements".to_owned())
        }
        (true, true) => vito::regress::independent::Independent::locate(),
    };
    let mut side_by_side = Vec::new();
    for p in &problems {
        let r = pipeline::bench(&p.spec).map_err(CliError::Transcription)?;
        if let Ok(ind) = &independent
            && reference::is_reference(&p.spec.name)
        {
            side_by_side.push((r.clone(), ind.bench(&p.spec.name)));
        }
        out!(
            "{:<24} {:>5} {:>6} {:>6} {:>7} {:>7} {:>28} {:>15.8e} {:>9.2e} {:>6} {:>9.3} {:>9.3} {:>9.3} {:>10.2e}",
            r.name,
            p.spec.knots,
            r.size.n_variables,
            r.size.n_constraints,
            r.size.nnz_jacobian,
            r.size.nnz_hessian,
            r.verdict.name(),
            r.objective,
            r.max_slack,
            r.iterations,
            r.wall_time_s,
            r.callback_time_s,
            r.ipopt_time_s,
            r.derivative_eval_s
        );
        out!("  callbacks: {}", r.callback_split.describe());
    }
    match independent {
        Err(why) => out!("CasADi column: {why}"),
        Ok(_) => print_side_by_side(&side_by_side)?,
    }
    Ok(0)
}

/// vito's and CasADi's solves of the same problems, wall time split into the callbacks (the
/// NLP functions and derivatives) and Ipopt, per solve and per iteration.
fn print_side_by_side(
    rows: &[(
        vito::transcription::BenchRow,
        Result<vito::regress::independent::IndependentRow, String>,
    )],
) -> Result<(), CliError> {
    out!(
        "\n{:<22} {:>6} {:>24} {:>18} {:>6} {:>24} {:>18} {:>8} {:>8}",
        "side by side",
        "iter",
        "vito wall (callb./ipopt)",
        "per iter ms",
        "iter",
        "CasADi wall (func/ipopt)",
        "per iter ms",
        "wall x",
        "/iter x"
    );
    let split = |w: f64, c: f64, i: f64| format!("{w:.3} ({c:.3}/{i:.3}) s");
    let per_iter = |c: f64, i: f64, n: usize| {
        let n = n.max(1) as f64;
        format!("{:.3}/{:.3}", 1e3 * c / n, 1e3 * i / n)
    };
    for (v, c) in rows {
        let c = match c {
            // Where h is fixed (hopper, brick) the script makes it a constant, vito a fixed
            // variable that Ipopt removes: the variable counts differ by the N − 1 steps.
            Ok(c) if c.constraints == v.size.n_constraints => c,
            Ok(c) => {
                out!(
                    "{:<22} CasADi's NLP has {} constraints, vito's {}: not the same problem",
                    v.name,
                    c.constraints,
                    v.size.n_constraints
                );
                continue;
            }
            Err(e) => {
                out!("{:<22} CasADi: {e}", v.name);
                continue;
            }
        };
        let per = |wall: f64, n: usize| wall / n.max(1) as f64;
        out!(
            "{:<22} {:>6} {:>24} {:>18} {:>6} {:>24} {:>18} {:>8.2} {:>8.2}",
            v.name,
            v.iterations,
            split(v.wall_time_s, v.callback_time_s, v.ipopt_time_s),
            per_iter(v.callback_time_s, v.ipopt_time_s, v.iterations),
            c.iterations,
            split(c.wall_s, c.functions_s, c.ipopt_s),
            per_iter(c.functions_s, c.ipopt_s, c.iterations),
            c.wall_s / v.wall_time_s,
            per(c.wall_s, c.iterations) / per(v.wall_time_s, v.iterations)
        );
        out!(
            "{:<22} vito objective {:.10e} ({}), CasADi {:.10e} ({}, max slack {:.1e}; {})",
            "",
            v.objective,
            v.verdict.name(),
            c.objective,
            c.status,
            c.max_slack,
            c.implementation
        );
    }
    out!("wall x, /iter x: CasADi's time over vito's (above 1: vito is faster)");
    Ok(())
}
