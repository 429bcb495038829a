//! Cost blocks: one interval's (or the last knot's) share of each `CostTerm`.

use super::Context;
use crate::discrete::midpoint_state;
use crate::problem::CostTerm;
use crate::scalar::Scalar;

/// ½ Σ w_i (a_i − b_i)² over paired slices.
fn half_weighted_square<D: Scalar>(w: &[f64], a: impl Iterator<Item = D>, b: &[f64]) -> D {
    a.zip(w.iter().zip(b))
        .fold(D::from(0.0), |acc, (ai, (&wi, &bi))| {
            let d = ai - D::from(bi);
            acc + d * d * D::from(0.5 * wi)
        })
}

/// The value of one cost block. z layouts: StateTracking [qa; qb; h], Input [u; h],
/// InputRate [u_prev; u], ConfigurationDifference [qa; qb], FinalState [q_N], Time [h].
pub fn cost<D: Scalar>(term: &CostTerm, ctx: &Context, z: &[D]) -> D {
    let (n, m) = (ctx.n, ctx.m);
    match term {
        CostTerm::StateTracking {
            q_target,
            v_target,
            q_weights,
            v_weights,
            time_weighted,
        } => {
            let (qa, qb, h) = (&z[..n], &z[n..2 * n], z[2 * n]);
            let (mid, vel) = midpoint_state(qa, qb, h);
            let value = half_weighted_square(q_weights, mid.into_iter(), q_target)
                + half_weighted_square(v_weights, vel.into_iter(), v_target);
            if *time_weighted { value * h } else { value }
        }
        CostTerm::Input {
            weights,
            time_weighted,
        } => {
            let zeros = vec![0.0; m];
            let value = half_weighted_square(weights, z[..m].iter().copied(), &zeros);
            if *time_weighted { value * z[m] } else { value }
        }
        CostTerm::InputRate { weights } => {
            let zeros = vec![0.0; m];
            let diff = z[..m].iter().zip(&z[m..2 * m]).map(|(&a, &b)| b - a);
            half_weighted_square(weights, diff, &zeros)
        }
        CostTerm::ConfigurationDifference { weights } => {
            let zeros = vec![0.0; n];
            let diff = z[..n].iter().zip(&z[n..2 * n]).map(|(&a, &b)| b - a);
            half_weighted_square(weights, diff, &zeros)
        }
        CostTerm::FinalState { q_target, weights } => {
            half_weighted_square(weights, z[..n].iter().copied(), q_target)
        }
        CostTerm::Time { weight } => z[0] * D::from(*weight),
    }
}

/// The name of a cost term in `Solution::objective_terms`.
pub fn term_name(term: &CostTerm) -> &'static str {
    match term {
        CostTerm::StateTracking { .. } => "state_tracking",
        CostTerm::Input { .. } => "input",
        CostTerm::InputRate { .. } => "input_rate",
        CostTerm::ConfigurationDifference { .. } => "configuration_difference",
        CostTerm::FinalState { .. } => "final_state",
        CostTerm::Time { .. } => "time",
    }
}
