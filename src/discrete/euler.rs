//! First-order semi-implicit Euler time stepping (Stewart–Trinkle; Posa et al. 2014; eq. 1 of
//! the paper): M(q_k)(v_{k+1} − v_k) = h_k(B(q_k)u_k − C(q_k, v_{k+1})v_{k+1} − ∂V/∂q(q_k)
//! − diag(d)v_{k+1}) + J(q_{k+1})ᵀλ_k, with q_{k+1} = q_k + h_k v_{k+1}.

use super::difference_velocity;
use crate::autodiff::Scalar;
use crate::autodiff::VectorFunction;
use crate::model::{self, Model};

/// Euler residual at knot k (length `nq`, impulse units, same sign convention as the midpoint
/// DEL: momentum before − momentum after + impulses):
/// −h_k·inverse_dynamics(q_k, v_{k+1}, (v_{k+1} − v_k)/h_k) + h_k·B(q_k)u_k − h_k·diag(d)·v_{k+1},
/// with v_{k+1} = (q_{k+1} − q_k)/h_k. `v_k` is the velocity at knot k (m/s or rad/s per
/// coordinate): (q_k − q_{k−1})/h_{k−1}, or v_0 at the first step.
pub fn euler_residual<D: Scalar>(
    model: &Model,
    v_k: &[D],
    q_k: &[D],
    q_next: &[D],
    h: D,
    u: &[D],
) -> Vec<D> {
    let v_next = difference_velocity(q_k, q_next, h);
    let accel = difference_velocity(v_k, &v_next, h);
    let id = model::inverse_dynamics(model, q_k, &v_next, &accel);
    let input = model::generalized_input_force(model, q_k, u);
    id.iter()
        .zip(&input)
        .zip(model.damping().iter().zip(&v_next))
        .map(|((&t, &b), (&d, &v))| (b - t - v * d) * h)
        .collect()
}

/// Euler residual at knot k as a [`VectorFunction`] → R^n of
/// z = [x; q_k; q_{k+1}; h_{k−1}; h_k; u_k] (dim 3n + 2 + m), where x = q_{k−1} and
/// v_k = (q_k − q_{k−1})/h_{k−1}, or, when `first_step`, x = v_0 and the h_{k−1} entry is
/// ignored (its derivative is zero), so that both cases share one layout.
#[derive(Debug, Clone, Copy)]
pub struct EulerKnotResidual<'a> {
    /// The robot.
    pub model: &'a Model,
    /// Whether the first block of z is v_0 (first step) rather than q_{k−1}.
    pub first_step: bool,
}

impl VectorFunction for EulerKnotResidual<'_> {
    fn dim_in(&self) -> usize {
        3 * self.model.nq() + 2 + self.model.input_coordinates().len()
    }
    fn dim_out(&self) -> usize {
        self.model.nq()
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        let n = self.model.nq();
        let (x, q_k, q_next) = (&z[..n], &z[n..2 * n], &z[2 * n..3 * n]);
        let (h_prev, h) = (z[3 * n], z[3 * n + 1]);
        let u = &z[3 * n + 2..];
        let v_k: Vec<D> = if self.first_step {
            x.to_vec()
        } else {
            difference_velocity(x, q_k, h_prev)
        };
        out.copy_from_slice(&euler_residual(self.model, &v_k, q_k, q_next, h, u));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{BaseType, sample};

    /// Pendulum (I = 1/3 kg·m² about the pivot, gravity torque (m g l/2) sin q) with damping d:
    /// r = −(I(v₁ − v₀) + h (m g l/2) sin q_k) + h u − h d v₁.
    #[test]
    fn residual_matches_closed_form_for_pendulum() {
        let xml = sample::pendulum().replace(
            "<axis xyz=\"0 1 0\"/>",
            "<axis xyz=\"0 1 0\"/>\n    <dynamics damping=\"0.4\"/>",
        );
        let model = Model::from_urdf_str(&xml, BaseType::Fixed).expect("loads");
        let g = -model.gravity()[2];
        let (v0, q, q_next, h, u) = (0.7, 0.3, 0.32, 0.02, 1.5);
        let v1 = (q_next - q) / h;
        let expected = -((v1 - v0) / 3.0 + h * 0.5 * g * f64::sin(q)) + h * u - h * 0.4 * v1;
        let r = euler_residual(&model, &[v0], &[q], &[q_next], h, &[u])[0];
        assert!((r - expected).abs() < 1e-12, "{r} vs {expected}");
        // The first-step flag reads v_0 from the first slot; otherwise it is q_{k−1}.
        let f = EulerKnotResidual {
            model: &model,
            first_step: true,
        };
        let mut out = [0.0];
        f.eval(&[v0, q, q_next, 99.0, h, u], &mut out);
        assert_eq!(out[0], r);
        let f = EulerKnotResidual {
            model: &model,
            first_step: false,
        };
        f.eval(&[q - v0 * 0.01, q, q_next, 0.01, h, u], &mut out);
        assert!((out[0] - r).abs() < 1e-12);
    }
}
