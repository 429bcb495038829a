//! `[solver]`: integrator, Hessian mode and the Ipopt options.

use super::context::Context;
use crate::ipopt;
use crate::ipopt::OptionValue;
use crate::problem::schema::ProblemFile;
use crate::problem::{HessianMode, Integrator, ProblemError};

/// The checked `[solver]` section.
pub(super) struct CheckedSolver {
    pub(super) integrator: Integrator,
    pub(super) hessian: HessianMode,
    pub(super) solver_options: Vec<(String, OptionValue)>,
}

pub(super) fn check_solver(
    ctx: &Context,
    raw: &ProblemFile,
) -> Result<CheckedSolver, ProblemError> {
    let integrator = match raw.solver.integrator.as_deref() {
        None => Integrator::default(),
        Some(name) => name.parse().map_err(|_| {
            let valid = Integrator::ALL.map(|i| i.name().to_owned());
            ctx.unknown_name("solver.integrator", "integrator", name, &valid)
        })?,
    };
    let hessian = match raw.solver.hessian.as_deref() {
        None | Some("exact") => HessianMode::Exact,
        Some("lbfgs") => HessianMode::Lbfgs,
        Some(other) => {
            let valid = ["exact", "lbfgs"].map(String::from);
            return Err(ctx.unknown_name("solver.hessian", "Hessian mode", other, &valid));
        }
    };
    let mut solver_options = Vec::new();
    for (key, value) in &raw.solver.ipopt {
        let field = format!("solver.ipopt.{key}");
        let v = match value {
            toml::Value::String(s) => OptionValue::Str(s.clone()),
            toml::Value::Integer(i) => OptionValue::Int(*i),
            toml::Value::Float(x) => OptionValue::Num(*x),
            _ => {
                return Err(ctx.invalid(
                    &field,
                    "an Ipopt option is a string, an integer or a number",
                ));
            }
        };
        ipopt::check_problem_option(key, &v).map_err(|e| ctx.invalid(&field, e.to_string()))?;
        solver_options.push((key.clone(), v));
    }
    Ok(CheckedSolver {
        integrator,
        hessian,
        solver_options,
    })
}
