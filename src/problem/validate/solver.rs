//! `[solver]`: integrator, Hessian mode, scaling and the Ipopt options.

use super::context::Context;
use crate::ipopt;
use crate::ipopt::OptionValue;
use crate::problem::schema::ProblemFile;
use crate::problem::{HessianMode, Integrator, ProblemError, ScalingMode};

/// The checked `[solver]` section.
pub(super) struct CheckedSolver {
    pub(super) integrator: Integrator,
    pub(super) hessian: HessianMode,
    pub(super) scaling: ScalingMode,
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
    let scaling = check_scaling(ctx, raw.solver.scaling.as_deref(), &solver_options)?;
    Ok(CheckedSolver {
        integrator,
        hessian,
        scaling,
        solver_options,
    })
}

/// Ipopt options that `scaling = "units"` sets itself or does not reproduce: with
/// `nlp_scaling_method` other than `user-scaling` Ipopt would ignore the scaling; the rows'
/// gradient rule takes `nlp_scaling_max_gradient` and `nlp_scaling_min_value` only.
const UNITS_EXCLUDE: [&str; 3] = [
    "nlp_scaling_method",
    "nlp_scaling_obj_target_gradient",
    "nlp_scaling_constr_target_gradient",
];

fn check_scaling(
    ctx: &Context,
    name: Option<&str>,
    solver_options: &[(String, OptionValue)],
) -> Result<ScalingMode, ProblemError> {
    let scaling = match name {
        None | Some("ipopt") => ScalingMode::Ipopt,
        Some("units") => ScalingMode::Units,
        Some(other) => {
            let valid = ScalingMode::NAMES.map(String::from);
            return Err(ctx.unknown_name("solver.scaling", "scaling", other, &valid));
        }
    };
    if scaling == ScalingMode::Units {
        let user_scaling = OptionValue::Str("user-scaling".into());
        if let Some((key, _)) = solver_options.iter().find(|(key, value)| {
            UNITS_EXCLUDE.contains(&key.as_str())
                && !(key == "nlp_scaling_method" && *value == user_scaling)
        }) {
            return Err(ctx.invalid(
                &format!("solver.ipopt.{key}"),
                format!(
                    "`solver.scaling = \"units\"` hands Ipopt its own scaling (variables by \
                     their units, the objective and rows by the gradient rule with \
                     `nlp_scaling_max_gradient`), which `{key}` would override or Ipopt \
                     would ignore; remove `{key}`, or `scaling` for Ipopt's own scaling"
                ),
            ));
        }
    }
    Ok(scaling)
}
