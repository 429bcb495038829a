//! `[[cost]]`: the cost terms, with weights and targets by name.

use super::context::Context;
use super::values::{nonnegative, resolve};
use crate::problem::schema::{CostEntry, NamedVector, ProblemFile};
use crate::problem::{CostTerm, ProblemError, RobotInfo};

pub(super) fn check_costs(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
    goal: &[f64],
) -> Result<Vec<CostTerm>, ProblemError> {
    let n = robot.coordinates.len();
    let coords = &robot.coordinates;
    let goal = goal.to_vec();
    // Costs.
    let mut costs = Vec::new();
    let zeros_n = vec![0.0; n];
    for (i, c) in raw.cost.iter().enumerate() {
        let f = |k: &str| format!("cost[{i}].{k}");
        let term = match c {
            CostEntry::StateTracking {
                q_target,
                v_target,
                q_weights,
                v_weights,
                time_weighted,
            } => CostTerm::StateTracking {
                q_target: match q_target {
                    Some(t) => resolve(ctx, &f("q_target"), "coordinate", coords, t, Some(&goal))?,
                    None => goal.clone(),
                },
                v_target: match v_target {
                    Some(t) => {
                        resolve(ctx, &f("v_target"), "coordinate", coords, t, Some(&zeros_n))?
                    }
                    None => zeros_n.clone(),
                },
                q_weights: weights(ctx, &f("q_weights"), coords, "coordinate", q_weights)?,
                v_weights: match v_weights {
                    Some(w) => weights(ctx, &f("v_weights"), coords, "coordinate", w)?,
                    None => zeros_n.clone(),
                },
                time_weighted: time_weighted.unwrap_or(true),
            },
            CostEntry::Input {
                weights: w,
                time_weighted,
            } => CostTerm::Input {
                weights: weights(ctx, &f("weights"), &robot.inputs, "input", w)?,
                time_weighted: time_weighted.unwrap_or(true),
            },
            CostEntry::InputRate { weights: w } => CostTerm::InputRate {
                weights: weights(ctx, &f("weights"), &robot.inputs, "input", w)?,
            },
            CostEntry::ConfigurationDifference { weights: w } => {
                CostTerm::ConfigurationDifference {
                    weights: weights(ctx, &f("weights"), coords, "coordinate", w)?,
                }
            }
            CostEntry::FinalState {
                q_target,
                weights: w,
            } => CostTerm::FinalState {
                q_target: match q_target {
                    Some(t) => resolve(ctx, &f("q_target"), "coordinate", coords, t, Some(&goal))?,
                    None => goal.clone(),
                },
                weights: weights(ctx, &f("weights"), coords, "coordinate", w)?,
            },
            CostEntry::Time { weight } => CostTerm::Time {
                weight: nonnegative(ctx, &f("weight"), *weight)?,
            },
        };
        costs.push(term);
    }
    Ok(costs)
}

fn weights(
    ctx: &Context,
    field: &str,
    names: &[String],
    kind: &'static str,
    w: &NamedVector,
) -> Result<Vec<f64>, ProblemError> {
    let values = resolve(ctx, field, kind, names, w, None)?;
    if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| **v < 0.0) {
        return Err(ctx.invalid(
            field,
            format!("weight of `{}` is {v}; weights must be ≥ 0", names[i]),
        ));
    }
    Ok(values)
}
