//! Forward simulation without contact: solve one knot's discrete equations (with loop
//! closures imposed at the new knot) for q_{k+1} by Newton's method with the exact Jacobian.

use super::{
    DiscreteForce, EulerKnotResidual, GalerkinRule, Integrator, LoopClosure, MidpointSegment,
    ModelMechanics, arriving_momentum, galerkin_interval, momentum_after,
};
use crate::autodiff::{gradient_hessian, jacobian, weighted_hessian};
use crate::model::Model;
use nalgebra::{DMatrix, DVector};

/// Newton iterations before [`step`] gives up.
const MAX_NEWTON_ITERATIONS: usize = 30;

/// Relative residual at which Newton stops: a few hundred ulps of the momentum scale.
const RELATIVE_TOLERANCE: f64 = 1e-13;

/// A Newton update this small (relative to |q|) is at the round-off floor of the residual.
const ROUND_OFF_STEP: f64 = 1e-14;

/// Relative residual still accepted once the update is at the round-off floor.
const STALL_TOLERANCE: f64 = 1e-9;

/// Why a forward step failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum StepError {
    /// A slice argument has the wrong length.
    #[error("step: `{what}` has length {found}, but the model needs {expected}")]
    Dimension {
        /// Argument name.
        what: &'static str,
        /// Required length (`model.nq()` or the number of inputs).
        expected: usize,
        /// Length given.
        found: usize,
    },
    /// The time step is not a positive finite number.
    #[error("step: time step h = {h} s must be positive and finite")]
    InvalidTimeStep {
        /// The step given, s.
        h: f64,
    },
    /// The residual or its Jacobian became NaN or infinite.
    #[error(
        "step: non-finite residual at Newton iteration {iteration}; reduce h or check the state"
    )]
    NonFinite {
        /// Newton iteration (0 = the starting guess).
        iteration: usize,
    },
    /// The Newton matrix could not be factorised (e.g. redundant loop closures).
    #[error(
        "step: singular Newton matrix at iteration {iteration}; check for redundant loop closures"
    )]
    SingularJacobian {
        /// Newton iteration.
        iteration: usize,
    },
    /// Newton did not reach the tolerance.
    #[error(
        "step: Newton did not converge in {iterations} iterations (residual {residual:e}); reduce h"
    )]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// Final max-norm residual (impulse units, and length units for loop rows).
        residual: f64,
    },
}

fn check_len(what: &'static str, found: usize, expected: usize) -> Result<(), StepError> {
    if found == expected {
        Ok(())
    } else {
        Err(StepError::Dimension {
            what,
            expected,
            found,
        })
    }
}

/// One forward step without contact: given q_{k−1} = `q_prev`, q_k = `q_curr` (length
/// `model.nq()`), inputs `u` (one per input, held over both intervals) and a step `h` (s) used
/// for both intervals, returns q_{k+1} solving the discrete equations of `integrator` together
/// with the loop closures (impulses Gᵀ(q_{k+1})ν, residual imposed at q_{k+1}).
///
/// Newton starts from the linear extrapolation 2q_k − q_{k−1} with the exact Jacobian from
/// [`crate::autodiff`], and stops at a max-norm residual of 1e-13 relative to the momentum scale (or below 1e-9
/// once the update is at the round-off floor).
pub fn step(
    model: &Model,
    integrator: Integrator,
    q_prev: &[f64],
    q_curr: &[f64],
    u: &[f64],
    h: f64,
) -> Result<Vec<f64>, StepError> {
    let n = model.nq();
    check_len("q_prev", q_prev.len(), n)?;
    check_inputs(model, q_curr, u, h)?;
    let before = match integrator.galerkin_rule() {
        Some(rule) => Before::galerkin(model, rule, |mech, rule| {
            arriving_momentum(mech, Some(rule), q_prev, q_curr, u, h)
        })?,
        None if integrator == Integrator::Euler => Before::PreviousConfiguration(q_prev.to_vec()),
        // The knot's incoming momentum D2Ld(q_{k−1}, q_k) + ½Fd_{k−1} does not change.
        None => Before::Momentum(momentum_after(model, q_prev, q_curr, u, h)),
    };
    let guess = q_curr
        .iter()
        .zip(q_prev)
        .map(|(&c, &p)| 2.0 * c - p)
        .collect();
    solve_knot(model, &before, q_curr, guess, u, h)
}

/// The first step from a configuration and a velocity: given q_1 = `q_first` and v_0 =
/// `v_first` (length `model.nq()`, m/s or rad/s per coordinate), returns q_2 solving the first
/// step equations (midpoint: M(q_1)v_0 + D1Ld(q_1, q_2, h) + ½Fd = 0; Euler: its residual with
/// v_k = v_0), with loop closures imposed at q_2. Newton starts from q_1 + h·v_0.
pub fn first_step(
    model: &Model,
    integrator: Integrator,
    q_first: &[f64],
    v_first: &[f64],
    u: &[f64],
    h: f64,
) -> Result<Vec<f64>, StepError> {
    let n = model.nq();
    check_len("v_first", v_first.len(), n)?;
    check_inputs(model, q_first, u, h)?;
    let before = match integrator.galerkin_rule() {
        Some(rule) => Before::galerkin(model, rule, |_, _| {
            Ok(crate::model::generalized_momentum(model, q_first, v_first))
        })?,
        None if integrator == Integrator::Euler => Before::Velocity(v_first.to_vec()),
        None => Before::Momentum(crate::model::generalized_momentum(model, q_first, v_first)),
    };
    let guess = q_first
        .iter()
        .zip(v_first)
        .map(|(&q, &v)| q + h * v)
        .collect();
    solve_knot(model, &before, q_first, guess, u, h)
}

fn check_inputs(model: &Model, q_curr: &[f64], u: &[f64], h: f64) -> Result<(), StepError> {
    check_len("q_curr", q_curr.len(), model.nq())?;
    check_len("u", u.len(), model.input_coordinates().len())?;
    if !(h.is_finite() && h > 0.0) {
        return Err(StepError::InvalidTimeStep { h });
    }
    Ok(())
}

/// What the knot equation needs from before the knot.
enum Before {
    /// Midpoint: the incoming momentum p_k⁻ (or M(q_1)v_0 at the first step).
    Momentum(Vec<f64>),
    /// Galerkin: the incoming momentum p_k⁻ (or M(q_1)v_0), with the model as [`Mechanics`]
    /// and the member, for the interval after the knot.
    Galerkin {
        p_minus: Vec<f64>,
        mech: Box<ModelMechanics>,
        rule: GalerkinRule,
    },
    /// Euler: q_{k−1}, so that v_k = (q_k − q_{k−1})/h.
    PreviousConfiguration(Vec<f64>),
    /// Euler first step: v_k = v_0.
    Velocity(Vec<f64>),
}

impl Before {
    /// The Galerkin member `rule` of `model` (a copy, without contacts) with the incoming
    /// momentum `p_minus` computes from it.
    fn galerkin(
        model: &Model,
        rule: GalerkinRule,
        p_minus: impl FnOnce(&ModelMechanics, &GalerkinRule) -> Result<Vec<f64>, StepError>,
    ) -> Result<Before, StepError> {
        let mech = Box::new(ModelMechanics::with_contacts(model.clone(), Vec::new()));
        Ok(Before::Galerkin {
            p_minus: p_minus(&mech, &rule)?,
            mech,
            rule,
        })
    }
}

/// Newton on [q_{k+1}; ν] for the knot equation plus loop closures.
fn solve_knot(
    model: &Model,
    before: &Before,
    q_curr: &[f64],
    mut q_next: Vec<f64>,
    u: &[f64],
    h: f64,
) -> Result<Vec<f64>, StepError> {
    let n = model.nq();
    let n_loop = model.num_loop_constraints();
    let mut nu = vec![0.0; n_loop];
    let before_scale = match before {
        Before::Momentum(p) | Before::Galerkin { p_minus: p, .. } => {
            p.iter().fold(0.0f64, |a, &b| a.max(b.abs()))
        }
        Before::PreviousConfiguration(q) => q
            .iter()
            .zip(q_curr)
            .fold(0.0f64, |a, (&p, &c)| a.max((c - p).abs())),
        Before::Velocity(v) => h * v.iter().fold(0.0f64, |a, &b| a.max(b.abs())),
    };
    let tolerance = RELATIVE_TOLERANCE * (1.0 + before_scale);

    let size = n + n_loop;
    let mut residual = DVector::zeros(size);
    let mut newton = DMatrix::zeros(size, size);
    let mut last_norm = f64::INFINITY;
    for iteration in 0..=MAX_NEWTON_ITERATIONS {
        newton.fill(0.0);
        let (del, del_partial_q_next) = knot_residual(model, before, q_curr, &q_next, u, h)?;
        for i in 0..n {
            residual[i] = del[i];
            for j in 0..n {
                newton[(i, j)] = del_partial_q_next[(i, j)];
            }
        }
        if n_loop > 0 {
            let (closure, g) = jacobian(&LoopClosure { model }, &q_next);
            let impulse = g.tr_mul(&DVector::from_column_slice(&nu));
            let curvature = weighted_hessian(&LoopClosure { model }, &q_next, &nu);
            for i in 0..n {
                residual[i] += impulse[i];
                for j in 0..n {
                    newton[(i, j)] += curvature[(i, j)];
                }
            }
            for r in 0..n_loop {
                residual[n + r] = closure[r];
                for j in 0..n {
                    newton[(n + r, j)] = g[(r, j)];
                    newton[(j, n + r)] = g[(r, j)];
                }
            }
        }
        if !residual.iter().chain(newton.iter()).all(|x| x.is_finite()) {
            return Err(StepError::NonFinite { iteration });
        }
        last_norm = residual.amax();
        if last_norm <= tolerance {
            return Ok(q_next);
        }
        if iteration == MAX_NEWTON_ITERATIONS {
            break;
        }
        let delta = newton
            .clone()
            .lu()
            .solve(&residual)
            .ok_or(StepError::SingularJacobian { iteration })?;
        for i in 0..n {
            q_next[i] -= delta[i];
        }
        for r in 0..n_loop {
            nu[r] -= delta[n + r];
        }
        // At the round-off floor the update no longer moves q: accept if the residual is small.
        let q_scale = 1.0 + q_next.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
        if delta.rows(0, n).amax() <= ROUND_OFF_STEP * q_scale
            && last_norm <= STALL_TOLERANCE * (1.0 + before_scale)
        {
            return Ok(q_next);
        }
    }
    Err(StepError::NotConverged {
        iterations: MAX_NEWTON_ITERATIONS,
        residual: last_norm,
    })
}

/// The knot's residual (without loop impulses) and its Jacobian with respect to q_{k+1} (n × n).
fn knot_residual(
    model: &Model,
    before: &Before,
    q_curr: &[f64],
    q_next: &[f64],
    u: &[f64],
    h: f64,
) -> Result<(Vec<f64>, DMatrix<f64>), StepError> {
    let n = model.nq();
    let euler = |x: &[f64], first_step: bool| {
        let z: Vec<f64> = x
            .iter()
            .chain(q_curr)
            .chain(q_next)
            .copied()
            .chain([h, h])
            .chain(u.iter().copied())
            .collect();
        let (residual, jac) = jacobian(&EulerKnotResidual { model, first_step }, &z);
        (residual, jac.columns(2 * n, n).into_owned())
    };
    Ok(match before {
        Before::Galerkin {
            p_minus,
            mech,
            rule,
        } => {
            // −p_k⁺ and its q_{k+1} derivative along the interval's stationary interior.
            let interval = galerkin_interval(mech.as_ref(), rule, q_curr, q_next, u, h, None)?;
            let residual = p_minus.iter().zip(&interval.start).map(|(p, s)| p + s);
            (residual.collect(), interval.start_by_end)
        }
        Before::Momentum(p_minus) => {
            // D1Ld(q_k, q_{k+1}) and its q_{k+1} block from the Hessian of the segment.
            let z: Vec<f64> = q_curr.iter().chain(q_next).copied().chain([h]).collect();
            let (_, grad, hess) = gradient_hessian(&MidpointSegment { model }, &z);
            let mut residual: Vec<f64> = (0..n).map(|i| p_minus[i] + grad[i]).collect();
            let mut jac = DMatrix::from_fn(n, n, |i, j| hess[(i, n + j)]);
            // Fd vanishes identically without inputs and damping: skip its derivative pass.
            if !u.is_empty() || model.damping().iter().any(|&d| d != 0.0) {
                let zf: Vec<f64> = q_curr
                    .iter()
                    .chain(q_next)
                    .chain(u)
                    .copied()
                    .chain([h])
                    .collect();
                let (fd, fd_jac) = jacobian(&DiscreteForce { model }, &zf);
                for i in 0..n {
                    residual[i] += 0.5 * fd[i];
                    for j in 0..n {
                        jac[(i, j)] += 0.5 * fd_jac[(i, n + j)];
                    }
                }
            }
            (residual, jac)
        }
        Before::PreviousConfiguration(q_prev) => euler(q_prev, false),
        Before::Velocity(v_first) => euler(v_first, true),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{BaseType, sample};

    fn pendulum() -> Model {
        Model::from_urdf_str(&sample::pendulum(), BaseType::Fixed).expect("loads")
    }

    #[test]
    fn bad_arguments_are_reported_not_panicked() {
        let model = pendulum();
        let mid = Integrator::Midpoint;
        assert_eq!(
            step(&model, mid, &[0.0, 1.0], &[0.0], &[0.0], 0.01),
            Err(StepError::Dimension {
                what: "q_prev",
                expected: 1,
                found: 2
            })
        );
        assert_eq!(
            step(&model, mid, &[0.0], &[0.0], &[], 0.01),
            Err(StepError::Dimension {
                what: "u",
                expected: 1,
                found: 0
            })
        );
        assert_eq!(
            first_step(&model, mid, &[0.0], &[0.0], &[0.0], -0.1),
            Err(StepError::InvalidTimeStep { h: -0.1 })
        );
        assert!(matches!(
            step(&model, mid, &[0.0], &[f64::NAN], &[0.0], 0.01),
            Err(StepError::NonFinite { .. })
        ));
    }

    /// The returned q_{k+1} satisfies the DEL equation (p_k⁻ = p_k⁺) to the Newton tolerance.
    #[test]
    fn midpoint_step_solves_the_del_equation() {
        let model = pendulum();
        let (q0, q1, u, h) = ([0.4], [0.43], [0.7], 0.02);
        let q2 = step(&model, Integrator::Midpoint, &q0, &q1, &u, h).expect("converges");
        let p_minus = super::super::momentum_after(&model, &q0, &q1, &u, h);
        let p_plus = super::super::momentum_before(&model, &q1, &q2, &u, h);
        assert!((p_minus[0] - p_plus[0]).abs() < 1e-12);
    }
}
