//! One Galerkin interval with its ends fixed: the interior control points solved from their
//! stationarity ∂A/∂q^ν + f^ν = 0 (ν = 1 … s − 1) by Newton's method, and the end momenta the
//! DEL rows take from it, with their derivatives in q_{k+1} and u_k through the implicit
//! function theorem. This is the discrete Lagrangian of the interval, A at the stationary
//! interior, that a forward step or a simulation uses; the NLP keeps the interior points as
//! variables instead.

use nalgebra::DMatrix;

use super::{
    GalerkinRule, HalfForce, MechanicsDerivatives, StepError, action_gradient_hessian,
    incoming_momentum,
};
use crate::autodiff::jacobian;

/// Newton iterations before the interior solve gives up.
const MAX_ITERATIONS: usize = 30;

/// A Newton update this small relative to |q| is at the round-off floor.
const ROUND_OFF_STEP: f64 = 1e-15;

/// Relative stationarity residual accepted (of the end momenta's scale).
const TOLERANCE: f64 = 1e-11;

/// Relative residual below which a Newton iteration that no longer halves it has reached the
/// round-off floor of the stationarity's sums (whose terms, momenta over small steps, can be
/// far larger than the end momenta that scale [`TOLERANCE`]).
const FLOOR_TOLERANCE: f64 = 1e-8;

/// An interval at its stationary interior points.
#[derive(Debug, Clone, PartialEq)]
pub struct GalerkinInterval {
    /// The interior control points q^1 … q^{s−1} (length (s − 1)·n).
    pub interior: Vec<f64>,
    /// ∂A/∂q^0 + f^0 = −p_k⁺ (length n): the interval's share of knot k's DEL row.
    pub start: Vec<f64>,
    /// ∂A/∂q^s + f^s = p_{k+1}⁻ (length n): the interval's share of knot k + 1's DEL row.
    pub end: Vec<f64>,
    /// ∂start/∂q_{k+1} (n × n) along the stationary interior.
    pub start_by_end: DMatrix<f64>,
    /// ∂start/∂u_k (n × m) along the stationary interior.
    pub start_by_input: DMatrix<f64>,
}

/// The control points [qa; interior; qb] of an interval.
fn control(qa: &[f64], interior: &[f64], qb: &[f64]) -> Vec<f64> {
    [qa, interior, qb].concat()
}

/// Gradient of A plus the forces (length (s + 1)·n) and its Jacobian in the control points and
/// the input ((s + 1)·n × ((s + 1)·n + m)), at `points` with input `u` and step `h`.
///
/// Chained from the midpoint segments of the quadrature points, whose ends are linear in the
/// control points ([`GalerkinRule::segment_weights`]): ∇A = Σ_i b_i P_iᵀ∇Ld_i,
/// ∇²A = Σ_i b_i P_iᵀ∇²Ld_i P_i, f^ν = Σ_i 2 b_i ℓ_ν(c_i)·½Fd_i, so the mechanics' own segment
/// derivatives (the URDF model's adjoint) do the work.
pub fn galerkin_stationarity<M: MechanicsDerivatives>(
    mech: &M,
    rule: &GalerkinRule,
    points: &[f64],
    u: &[f64],
    h: f64,
) -> (Vec<f64>, DMatrix<f64>) {
    let (n, m) = (mech.nq(), mech.nu());
    let size = points.len();
    let mut value = vec![0.0; size];
    let mut jac = DMatrix::zeros(size, size + m);
    // ∇A and ∇²A over [control points; h], less the h row and column.
    let x: Vec<f64> = points.iter().copied().chain([h]).collect();
    let (gradient, hessian) = action_gradient_hessian(mech, rule, &x);
    value.copy_from_slice(&gradient[..size]);
    jac.view_mut((0, 0), (size, size))
        .copy_from(&hessian.view((0, 0), (size, size)));
    if !mech.has_discrete_force() {
        return (value, jac);
    }
    for (i, &b) in rule.quadrature_weights().iter().enumerate() {
        let weights = rule.segment_weights(i);
        let ends = |pick: fn(&(f64, f64)) -> f64| -> Vec<f64> {
            let mut q = vec![0.0; n];
            for (point, w) in points.chunks_exact(n).zip(&weights) {
                q.iter_mut().zip(point).for_each(|(a, p)| *a += pick(w) * p);
            }
            q
        };
        let (qa, qb) = (ends(|w| w.0), ends(|w| w.1));
        let zf: Vec<f64> = qa.iter().chain(&qb).chain(u).copied().chain([h]).collect();
        let (half, half_jac) = jacobian(&HalfForce { mech }, &zf);
        for (nu, &(wa, wb)) in weights.iter().enumerate() {
            // h·b_i·ℓ_ν(c_i)·f = 2 b_i ℓ_ν(c_i)·½Fd_i, ℓ_ν = (wa_ν + wb_ν)/2.
            let scale = b * (wa + wb);
            for r in 0..n {
                value[nu * n + r] += scale * half[r];
                for (mu, &(va, vb)) in weights.iter().enumerate() {
                    for c in 0..n {
                        jac[(nu * n + r, mu * n + c)] +=
                            scale * (va * half_jac[(r, c)] + vb * half_jac[(r, n + c)]);
                    }
                }
                for c in 0..m {
                    jac[(nu * n + r, size + c)] += scale * half_jac[(r, 2 * n + c)];
                }
            }
        }
    }
    (value, jac)
}

/// Solves the interior points of the interval from `qa` to `qb` (length n each) with input `u`
/// held and step `h`, starting from `guess` (length (s − 1)·n; the chord
/// [`GalerkinRule::chord_interior`] when `None`), and returns the interval there.
pub fn galerkin_interval<M: MechanicsDerivatives>(
    mech: &M,
    rule: &GalerkinRule,
    qa: &[f64],
    qb: &[f64],
    u: &[f64],
    h: f64,
    guess: Option<&[f64]>,
) -> Result<GalerkinInterval, StepError> {
    let n = mech.nq();
    let s = rule.degree();
    let inner = (s - 1) * n;
    let mut interior = guess.map_or_else(|| rule.chord_interior(qa, qb), <[f64]>::to_vec);
    let mut last = f64::INFINITY;
    for iteration in 0..=MAX_ITERATIONS {
        let previous = last;
        let points = control(qa, &interior, qb);
        let (value, jac) = galerkin_stationarity(mech, rule, &points, u, h);
        if !value.iter().chain(jac.iter()).all(|x| x.is_finite()) {
            return Err(StepError::NonFinite { iteration });
        }
        let scale = 1.0 + value.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let residual = nalgebra::DVector::from_column_slice(&value[n..n + inner]);
        last = residual.amax();
        let interior_jac = jac.view((n, n), (inner, inner)).into_owned();
        let lu = interior_jac.lu();
        let converged = last <= 1e-15 * scale;
        let delta = if inner == 0 || converged {
            None
        } else {
            Some(
                lu.solve(&residual)
                    .ok_or(StepError::SingularJacobian { iteration })?,
            )
        };
        let q_scale = 1.0 + points.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let small = delta
            .as_ref()
            .is_none_or(|d| d.amax() <= ROUND_OFF_STEP * q_scale);
        let stalled = last > 0.5 * previous && last <= FLOOR_TOLERANCE * scale;
        if inner == 0 || converged || (small && last <= TOLERANCE * scale) || stalled {
            return finish(rule, n, interior, &value, &jac, &lu, iteration);
        }
        if iteration == MAX_ITERATIONS {
            break;
        }
        if let Some(delta) = delta {
            interior.iter_mut().zip(&delta).for_each(|(x, d)| *x -= d);
        }
    }
    Err(StepError::NotConverged {
        iterations: MAX_ITERATIONS,
        residual: last,
    })
}

/// The interval at stationary `interior`: the end momenta from the stationarity `value` and
/// the start's derivatives by the implicit function theorem from its Jacobian `jac` (`lu` the
/// factorised interior block): d start/dy = ∂start/∂y − ∂start/∂x (∂r/∂x)⁻¹ ∂r/∂y for
/// y = q_{k+1} or u_k, x the interior points and r their stationarity.
fn finish(
    rule: &GalerkinRule,
    n: usize,
    interior: Vec<f64>,
    value: &[f64],
    jac: &DMatrix<f64>,
    lu: &nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
    iteration: usize,
) -> Result<GalerkinInterval, StepError> {
    let s = rule.degree();
    let inner = (s - 1) * n;
    let m = jac.ncols() - (s + 1) * n;
    let end_col = s * n;
    let mut by_end = jac.view((0, end_col), (n, n)).into_owned();
    let mut by_input = jac.view((0, end_col + n), (n, m)).into_owned();
    if inner > 0 {
        let start_by_interior = jac.view((0, n), (n, inner));
        let rhs_end = jac.view((n, end_col), (inner, n)).into_owned();
        let rhs_input = jac.view((n, end_col + n), (inner, m)).into_owned();
        let singular = StepError::SingularJacobian { iteration };
        by_end -= start_by_interior * lu.solve(&rhs_end).ok_or(singular.clone())?;
        by_input -= start_by_interior * lu.solve(&rhs_input).ok_or(singular)?;
    }
    Ok(GalerkinInterval {
        interior,
        start: value[..n].to_vec(),
        end: value[end_col..end_col + n].to_vec(),
        start_by_end: by_end,
        start_by_input: by_input,
    })
}

/// The momentum p_k⁻ arriving at knot k from the interval (q_{k−1}, q_k) with input u_{k−1}
/// and step h: for the midpoint rule (`rule` `None`) D2Ld + ½Fd ([`incoming_momentum`]), for
/// a Galerkin member ∂A/∂q^s + f^s at the stationary interior points.
pub fn arriving_momentum<M: MechanicsDerivatives>(
    mech: &M,
    rule: Option<&GalerkinRule>,
    q_prev: &[f64],
    q_curr: &[f64],
    u_prev: &[f64],
    h: f64,
) -> Result<Vec<f64>, StepError> {
    match rule {
        None => Ok(incoming_momentum(mech, q_prev, q_curr, u_prev, h)),
        Some(rule) => Ok(galerkin_interval(mech, rule, q_prev, q_curr, u_prev, h, None)?.end),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::finite_differences::{central, gradient as fd_gradient};
    use crate::autodiff::{ScalarFunction, gradient};
    use crate::discrete::{GalerkinAction, GalerkinForce, ModelMechanics};
    use crate::model::{BaseType, Model, sample};

    /// A 3-link chain on a planar base (n = 6, 3 inputs) with damping 0.3 on every hinge.
    fn damped_chain() -> ModelMechanics {
        let model =
            Model::from_urdf_str(&sample::damped_chain(3), BaseType::Planar).expect("chain loads");
        ModelMechanics::with_contacts(model, Vec::new())
    }

    const QA: [f64; 6] = [0.1, 0.2, -0.1, 0.4, -0.3, 0.2];
    const QB: [f64; 6] = [0.12, 0.17, -0.08, 0.45, -0.36, 0.26];
    const U: [f64; 3] = [0.7, -0.4, 1.1];
    const H: f64 = 0.03;

    /// The interior points are stationary (∂A/∂q^ν + f^ν = 0 by central differences of A),
    /// and the end momenta are the end gradients plus forces.
    #[test]
    fn interior_points_are_stationary_and_ends_are_gradients() {
        let mech = damped_chain();
        for s in [2, 3] {
            let rule = GalerkinRule::of_degree(s).expect("tabulated");
            let interval = galerkin_interval(&mech, &rule, &QA, &QB, &U, H, None).expect("solves");
            let points = control(&QA, &interval.interior, &QB);
            let z: Vec<f64> = points.iter().copied().chain([H]).collect();
            let action = GalerkinAction {
                mech: &mech,
                rule: &rule,
            };
            let (_, grad) = gradient(&action, &z);
            let mut force = vec![0.0; points.len()];
            rule.forces(&mech, &points, &U, H, &mut force);
            let n = 6;
            let differences = fd_gradient(|x| action.eval(x), &z, 1e-6);
            for j in 0..points.len() {
                let fd = differences[j];
                assert!(
                    (fd - grad[j]).abs() < 1e-7,
                    "s {s}, ∂A/∂z{j}: {fd} vs {}",
                    grad[j]
                );
                let total = grad[j] + force[j];
                if (n..s * n).contains(&j) {
                    assert!(total.abs() < 1e-12, "s {s}: interior residual {total:e}");
                } else if j < n {
                    assert!((total - interval.start[j]).abs() < 1e-12);
                } else {
                    assert!((total - interval.end[j - s * n]).abs() < 1e-12);
                }
            }
        }
    }

    /// The stationarity chained from the midpoint segments' adjoint derivatives equals forward
    /// AD through [`GalerkinAction`] and [`GalerkinForce`] (value and Jacobian).
    #[test]
    fn chained_stationarity_equals_forward_ad() {
        use crate::autodiff::gradient_hessian;

        let mech = damped_chain();
        for s in 1..=GalerkinRule::MAX_DEGREE {
            let rule = GalerkinRule::of_degree(s).expect("tabulated");
            let points = control(&QA, &rule.chord_interior(&QA, &QB), &QB);
            let points: Vec<f64> = points
                .iter()
                .enumerate()
                .map(|(i, p)| p + 0.01 * (i as f64).sin())
                .collect();
            let (value, jac) = galerkin_stationarity(&mech, &rule, &points, &U, H);
            let z: Vec<f64> = points.iter().copied().chain([H]).collect();
            let action = GalerkinAction {
                mech: &mech,
                rule: &rule,
            };
            let (_, grad, hess) = gradient_hessian(&action, &z);
            let zf: Vec<f64> = points.iter().chain(&U).copied().chain([H]).collect();
            let (force, force_jac) = jacobian(
                &GalerkinForce {
                    mech: &mech,
                    rule: &rule,
                },
                &zf,
            );
            let size = points.len();
            let scale = 1.0 + jac.amax();
            for r in 0..size {
                assert!(
                    (value[r] - grad[r] - force[r]).abs() < 1e-12 * scale,
                    "s {s} value {r}"
                );
                for c in 0..size + U.len() {
                    let ad = if c < size { hess[(r, c)] } else { 0.0 } + force_jac[(r, c)];
                    assert!(
                        (jac[(r, c)] - ad).abs() < 1e-11 * scale,
                        "s {s} ({r}, {c}): {} vs {ad}",
                        jac[(r, c)]
                    );
                }
            }
        }
    }

    /// ∂start/∂q_{k+1} and ∂start/∂u_k by the implicit function theorem equal central
    /// differences of the re-solved interval.
    #[test]
    fn start_derivatives_match_finite_differences() {
        let mech = damped_chain();
        for s in [2, 3] {
            let rule = GalerkinRule::of_degree(s).expect("tabulated");
            let at = |qb: &[f64], u: &[f64]| {
                galerkin_interval(&mech, &rule, &QA, qb, u, H, None).expect("solves")
            };
            let base = at(&QB, &U);
            let mut worst = 0.0_f64;
            for j in 0..QB.len() + U.len() {
                let shifted = |t: f64| {
                    let (mut qb, mut u) = (QB.to_vec(), U.to_vec());
                    if j < QB.len() {
                        qb[j] += t;
                    } else {
                        u[j - QB.len()] += t;
                    }
                    at(&qb, &u).start
                };
                let fd_column = central(shifted, 1e-6);
                for (r, &fd) in fd_column.iter().enumerate() {
                    let exact = if j < QB.len() {
                        base.start_by_end[(r, j)]
                    } else {
                        base.start_by_input[(r, j - QB.len())]
                    };
                    let error = (fd - exact).abs() / (1.0 + exact.abs());
                    worst = worst.max(error);
                }
            }
            assert!(worst < 1e-6, "s {s}: worst relative error {worst:e}");
        }
    }
}
