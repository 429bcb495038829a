//! `[[bounds]]` and whether every knot of every coordinate keeps a non-empty box.

use super::context::Context;
use super::values::bound;
use crate::problem::schema::{KnotsName, ProblemFile};
use crate::problem::{CoordinateBound, Interval, KnotSet, ProblemError, RobotInfo};

pub(super) fn check_bounds(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
    knots: usize,
) -> Result<Vec<CoordinateBound>, ProblemError> {
    let coords = &robot.coordinates;
    let mut bounds = Vec::new();
    for (i, b) in raw.bounds.iter().enumerate() {
        let field = format!("bounds[{i}]");
        let coordinate = robot.coordinate_index(&b.coordinate).ok_or_else(|| {
            ctx.unknown_name(
                &format!("{field}.coordinate"),
                "coordinate",
                &b.coordinate,
                coords,
            )
        })?;
        let knots_set = match &b.knots {
            None => KnotSet::All,
            Some(KnotsName::Named(s)) => match s.as_str() {
                "all" => KnotSet::All,
                "interior" => KnotSet::Interior,
                "first" => KnotSet::First,
                "last" => KnotSet::Last,
                other => {
                    let valid = ["all", "interior", "first", "last"].map(String::from);
                    return Err(ctx.unknown_name(
                        &format!("{field}.knots"),
                        "knot set",
                        other,
                        &valid,
                    ));
                }
            },
            Some(KnotsName::List(list)) => {
                if list.is_empty() {
                    return Err(ctx.invalid(
                        &format!("{field}.knots"),
                        "lists no knot, so the bound would apply nowhere: list 0-based knots, \
                         or use \"all\", \"interior\", \"first\" or \"last\"",
                    ));
                }
                let mut out = Vec::new();
                for &k in list {
                    if k < 0 || k as usize >= knots {
                        return Err(ctx.invalid(
                            &format!("{field}.knots"),
                            format!("knot {k} is outside 0..{} (knots are 0-based)", knots - 1),
                        ));
                    }
                    out.push(k as usize);
                }
                KnotSet::List(out)
            }
        };
        if b.lower.is_none() && b.upper.is_none() {
            return Err(ctx.invalid(&field, "give `lower`, `upper` or both"));
        }
        let end_field = if b.lower.is_some_and(|l| l.is_nan() || l == f64::INFINITY) {
            format!("{field}.lower")
        } else if b
            .upper
            .is_some_and(|u| u.is_nan() || u == f64::NEG_INFINITY)
        {
            format!("{field}.upper")
        } else {
            field.clone()
        };
        let Interval { lower, upper } = bound(
            ctx,
            &end_field,
            b.lower.unwrap_or(f64::NEG_INFINITY),
            b.upper.unwrap_or(f64::INFINITY),
        )?;
        bounds.push(CoordinateBound {
            coordinate,
            knots: knots_set,
            bound: Interval { lower, upper },
        });
    }
    Ok(bounds)
}

/// Whether a knot set holds knot `k` of `knots`.
fn knot_in(set: &KnotSet, k: usize, knots: usize) -> bool {
    match set {
        KnotSet::All => true,
        KnotSet::Interior => k > 0 && k + 1 < knots,
        KnotSet::First => k == 0,
        KnotSet::Last => k + 1 == knots,
        KnotSet::List(list) => list.contains(&k),
    }
}

/// Every knot of every coordinate must have a non-empty box (joint limits ∩ bounds ∩ the
/// fixed q_1 ∩ the q_N goal box), or Ipopt would be handed an infeasible problem.
#[allow(clippy::too_many_arguments)]
pub(super) fn check_bounds_feasible(
    ctx: &Context,
    robot: &RobotInfo,
    knots: usize,
    joint_limits: bool,
    bounds: &[CoordinateBound],
    q_initial: &[f64],
    q_final: &[Interval],
) -> Result<(), ProblemError> {
    const SLACK: f64 = 1e-12;
    for (j, name) in robot.coordinates.iter().enumerate() {
        for k in [0, knots - 1].into_iter().chain(1..knots.saturating_sub(1)) {
            let mut lower = f64::NEG_INFINITY;
            let mut upper = f64::INFINITY;
            let mut parts = Vec::new();
            let mut culprit = None;
            if joint_limits {
                let l = robot.coordinate_limits[j];
                if l.lower.is_finite() || l.upper.is_finite() {
                    lower = lower.max(l.lower);
                    upper = upper.min(l.upper);
                    parts.push(format!("URDF limits [{}, {}]", l.lower, l.upper));
                }
            }
            for (i, b) in bounds.iter().enumerate() {
                if b.coordinate == j && knot_in(&b.knots, k, knots) {
                    lower = lower.max(b.bound.lower);
                    upper = upper.min(b.bound.upper);
                    parts.push(format!(
                        "bounds[{i}] [{}, {}]",
                        b.bound.lower, b.bound.upper
                    ));
                    culprit = Some(format!("bounds[{i}]"));
                }
            }
            let field = if k == 0 {
                if q_initial[j] < lower - SLACK || q_initial[j] > upper + SLACK {
                    return Err(ctx.invalid(
                        &format!("initial.q.{name}"),
                        format!(
                            "q_1 {name} = {} is outside {} (set joint_limits = false or change the pose)",
                            q_initial[j],
                            parts.join(" ∩ ")
                        ),
                    ));
                }
                continue;
            } else if k + 1 == knots {
                let f = q_final[j];
                if f.lower.is_finite() || f.upper.is_finite() {
                    lower = lower.max(f.lower);
                    upper = upper.min(f.upper);
                    parts.push(format!("final [{}, {}]", f.lower, f.upper));
                    format!("final.q.{name}")
                } else {
                    culprit
                        .clone()
                        .unwrap_or_else(|| "robot.joint_limits".into())
                }
            } else {
                culprit
                    .clone()
                    .unwrap_or_else(|| "robot.joint_limits".into())
            };
            if lower > upper + SLACK {
                return Err(ctx.invalid(
                    &field,
                    format!(
                        "coordinate `{name}` has no feasible value at knot {k}: {} is empty",
                        parts.join(" ∩ ")
                    ),
                ));
            }
        }
    }
    Ok(())
}
