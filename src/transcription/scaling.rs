//! `[solver] scaling = "units"`: Ipopt's user scaling from the problem's physical units.
//!
//! Each variable is measured in a unit of its kind, from the problem's data and never from
//! the values of a guess, and Ipopt iterates on x/unit:
//!
//! | variables | unit |
//! | --- | --- |
//! | q_k, v_0, interior control points | 1 (one length unit, one radian; per time unit) |
//! | h_j | the nominal step: the middle of h's bounds (the fixed step where it is fixed) |
//! | u_j | the actuator bound max(\|lower\|, \|upper\|) where finite, else the weight W (a force, or a torque per length unit) |
//! | c, β, γ (impulses) | W·h: the weight's impulse over one nominal step |
//! | ψ, η (sliding speeds) | 1 (one length unit per time unit) |
//! | slacks | W·h (an impulse times one length unit, or times one speed unit) |
//!
//! W = m·\|g\| is the robot's weight from the URDF's total mass and the problem's gravity
//! ([`crate::discrete::Mechanics::weight`]); without it (or with no gravity) the impulse and
//! input units fall back to 1. The objective and the rows are scaled by Ipopt's own
//! gradient-based rule at the starting point, applied to the derivatives in the scaled
//! variables ([`ipopt::Scaling::with_gradient_rule`]), so that this scaling differs from
//! Ipopt's default only in the variables.

use super::Transcription;
use crate::discrete::MechanicsDerivatives;
use crate::ipopt::{self, GradientRule, JacobianEntries, OptionValue};

/// The unit of every variable of `t` under `[solver] scaling = "units"` (see the module):
/// Ipopt's variable scaling factor is its reciprocal.
pub fn variable_units<M: MechanicsDerivatives>(t: &Transcription<M>) -> Vec<f64> {
    let l = t.layout();
    let (x_lower, x_upper) = t.variable_bounds();
    let mut units = vec![1.0; l.num_variables()];
    if l.intervals() == 0 {
        return units;
    }
    let step = {
        let (lo, hi) = (x_lower[l.h(0)], x_upper[l.h(0)]);
        let middle = 0.5 * (lo + hi);
        if middle.is_finite() && middle > 0.0 {
            middle
        } else {
            1.0
        }
    };
    let weight = t
        .mechanics()
        .weight()
        .filter(|w| w.is_finite() && *w > 0.0)
        .unwrap_or(1.0);
    let impulse = weight * step;
    for j in 0..l.intervals() {
        units[l.h(j)] = step;
        for v in l.u(j) {
            let bound = x_lower[v].abs().max(x_upper[v].abs());
            units[v] = if bound.is_finite() && bound > 0.0 {
                bound
            } else {
                weight
            };
        }
        for i in 0..l.nc {
            units[l.c(j, i)] = impulse;
            units[l.beta(j, i)].fill(impulse);
        }
        units[l.gamma(j)].fill(impulse);
        units[l.slack(j)].fill(impulse);
    }
    units
}

/// Ipopt's scaling of `t` under `[solver] scaling = "units"` at its current starting point:
/// the variables by [`variable_units`], the objective and rows by Ipopt's gradient rule with
/// `options`' `nlp_scaling_max_gradient` and `nlp_scaling_min_value` (Ipopt's defaults
/// otherwise), leaving out the fixed variables when Ipopt takes them out of the problem
/// (`drops_fixed`).
pub fn units_scaling<M: MechanicsDerivatives>(
    t: &Transcription<M>,
    options: &[(String, OptionValue)],
    drops_fixed: bool,
) -> ipopt::Scaling {
    let mut rule = GradientRule::default();
    for (name, value) in options {
        let number = match value {
            OptionValue::Num(x) => *x,
            OptionValue::Int(i) => *i as f64,
            OptionValue::Str(_) => continue,
        };
        match name.as_str() {
            "nlp_scaling_max_gradient" => rule.max_gradient = number,
            "nlp_scaling_min_value" => rule.min_value = number,
            _ => {}
        }
    }
    let x = t.initial_point();
    let (x_lower, x_upper) = t.variable_bounds();
    let pattern = t.jacobian_pattern();
    let mut gradient = vec![0.0; x.len()];
    t.gradient(x, &mut gradient);
    let mut values = vec![0.0; pattern.nnz()];
    t.jacobian_values(x, &mut values);
    let skip: Vec<bool> = x_lower
        .iter()
        .zip(x_upper)
        .map(|(lo, hi)| drops_fixed && lo == hi)
        .collect();
    let scales = variable_units(t).iter().map(|u| 1.0 / u).collect();
    ipopt::Scaling::with_gradient_rule(
        scales,
        &gradient,
        JacobianEntries {
            rows: &pattern.rows,
            cols: &pattern.cols,
            values: &values,
        },
        t.layout().num_constraints(),
        &skip,
        rule,
    )
}
