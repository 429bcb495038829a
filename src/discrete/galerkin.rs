//! Galerkin variational integrators (Marsden and West 2001, §2.2.6; Ober-Blöbaum and Saake
//! 2015): on each interval [t_k, t_k + h] the configuration is the polynomial of degree s
//! through s + 1 control points q^0 = q_k, q^1 … q^{s−1} (interior), q^s = q_{k+1} at the
//! times t_k + d_ν h (d_ν the Gauss–Lobatto nodes on [0, 1]),
//!
//!   q_d(t_k + τh) = Σ_ν q^ν ℓ_ν(τ),   q̇_d(t_k + τh) = (1/h) Σ_ν q^ν ℓ̇_ν(τ),
//!
//! with ℓ_ν the Lagrange polynomials on the d_ν. The interval's action is the s-point
//! Gauss–Legendre quadrature (b_i, c_i) of the Lagrangian along it,
//!
//!   A(q^0 … q^s, h) = h Σ_i b_i L(q_d(c_i), q̇_d(c_i)),
//!
//! and the input u_k held over the interval does the virtual work of one discrete force per
//! control point, f^ν = h Σ_i b_i ℓ_ν(c_i) f(q_d(c_i), q̇_d(c_i), u_k). With degree s and s
//! Gauss points the method has order 2s (it is the symplectic Gauss collocation method;
//! Hairer, Lubich and Wanner §VI.6). The s = 1 member is the midpoint rule: one Gauss point at
//! τ = ½ with weight 1 gives A = h·L((q^0 + q^1)/2, (q^1 − q^0)/h).
//!
//! The continuous Lagrangian and force come from any [`Mechanics`] through its midpoint
//! pieces, which are exact for them: L(q, v) = Ld(q − hv/2, q + hv/2, h)/h and
//! h·(B(q)u − diag(d)v) = Fd(q − hv/2, q + hv/2, u, h).
//!
//! The interior points are stationary, ∂A/∂q^ν + f^ν = 0 for ν = 1 … s − 1, and the DEL row
//! of knot k adds ∂A_{k−1}/∂q^s + f^s_{k−1} (the momentum p_k⁻ arriving) and ∂A_k/∂q^0 + f^0_k
//! (= −p_k⁺): `super::galerkin_interval` solves an interval's interior points and gives these
//! end momenta with their derivatives.

use nalgebra::{DMatrix, DVector};

use super::{Mechanics, MechanicsDerivatives};
use crate::autodiff::Scalar;
use crate::autodiff::{ScalarFunction, ThirdOrder, VectorFunction};

/// The nodes, quadrature and Lagrange basis values of the Galerkin member of degree s.
#[derive(Debug, Clone, PartialEq)]
pub struct GalerkinRule {
    /// Control-point times d_0 = 0 < … < d_s = 1 (Gauss–Lobatto nodes on [0, 1]).
    nodes: Vec<f64>,
    /// Quadrature weights b_i (Gauss–Legendre, s points on [0, 1], summing to 1).
    weights: Vec<f64>,
    /// Quadrature points c_i in (0, 1).
    points: Vec<f64>,
    /// ℓ_ν(c_i), row i, column ν.
    basis: Vec<Vec<f64>>,
    /// ℓ̇_ν(c_i) = dℓ_ν/dτ at c_i, row i, column ν.
    basis_rate: Vec<Vec<f64>>,
}

impl GalerkinRule {
    /// The highest degree with tabulated nodes and quadrature.
    pub const MAX_DEGREE: usize = 3;

    /// The member of degree `s` (1 = the midpoint rule, 2 = fourth order, 3 = sixth order),
    /// or `None` for another degree.
    pub fn of_degree(s: usize) -> Option<GalerkinRule> {
        // Gauss–Lobatto nodes on [0, 1]: the ends and the roots of P'_s mapped from [−1, 1].
        let r5 = 0.5 / 5.0_f64.sqrt();
        let nodes = match s {
            1 => vec![0.0, 1.0],
            2 => vec![0.0, 0.5, 1.0],
            3 => vec![0.0, 0.5 - r5, 0.5 + r5, 1.0],
            _ => return None,
        };
        // Gauss–Legendre on [0, 1]: the roots of P_s mapped from [−1, 1], weights halved.
        let r3 = 0.5 / 3.0_f64.sqrt();
        let r15 = 0.5 * (3.0_f64 / 5.0).sqrt();
        let (points, weights) = match s {
            1 => (vec![0.5], vec![1.0]),
            2 => (vec![0.5 - r3, 0.5 + r3], vec![0.5, 0.5]),
            _ => (
                vec![0.5 - r15, 0.5, 0.5 + r15],
                vec![5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0],
            ),
        };
        let basis = points
            .iter()
            .map(|&c| (0..=s).map(|nu| lagrange(&nodes, nu, c)).collect())
            .collect();
        let basis_rate = points
            .iter()
            .map(|&c| (0..=s).map(|nu| lagrange_rate(&nodes, nu, c)).collect())
            .collect();
        Some(GalerkinRule {
            nodes,
            weights,
            points,
            basis,
            basis_rate,
        })
    }

    /// The degree s (control points s + 1, interior points s − 1).
    pub fn degree(&self) -> usize {
        self.nodes.len() - 1
    }

    /// The control-point times d_ν on [0, 1].
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }

    /// The quadrature points c_i on [0, 1].
    pub fn quadrature_points(&self) -> &[f64] {
        &self.points
    }

    /// The quadrature weights b_i.
    pub fn quadrature_weights(&self) -> &[f64] {
        &self.weights
    }

    /// The interior points interpolated on the chord from `qa` to `qb` (length (s − 1)·n,
    /// point ν at (1 − d_ν)qa + d_ν qb): a starting guess.
    pub fn chord_interior(&self, qa: &[f64], qb: &[f64]) -> Vec<f64> {
        self.nodes[1..self.degree()]
            .iter()
            .flat_map(|&d| qa.iter().zip(qb).map(move |(&a, &b)| (1.0 - d) * a + d * b))
            .collect()
    }

    /// Configuration and velocity of the path through `control` (the s + 1 control points
    /// q^0 … q^s, each length n, concatenated) at quadrature point i, for a step `h`.
    pub fn path_at<D: Scalar>(&self, control: &[D], h: D, i: usize) -> (Vec<D>, Vec<D>) {
        let n = control.len() / self.nodes.len();
        let (mut q, mut v) = (vec![D::zero(); n], vec![D::zero(); n]);
        for (nu, point) in control.chunks_exact(n).enumerate() {
            let (l, dl) = (self.basis[i][nu], self.basis_rate[i][nu]);
            for j in 0..n {
                q[j] += point[j] * l;
                v[j] += point[j] * dl;
            }
        }
        for vj in &mut v {
            *vj /= h;
        }
        (q, v)
    }

    /// The interval's action A = h Σ_i b_i L(q_d(c_i), q̇_d(c_i)) of the path through
    /// `control` (length (s + 1)·n), with L(q, v) = Ld(q − hv/2, q + hv/2, h)/h.
    pub fn action<D: Scalar, M: Mechanics>(&self, mech: &M, control: &[D], h: D) -> D {
        let mut total = D::zero();
        for (i, &b) in self.weights.iter().enumerate() {
            let (qa, qb) = self.midpoint_ends(control, h, i);
            // h·b_i·L = b_i·Ld(q − hv/2, q + hv/2, h).
            total += mech.discrete_lagrangian(&qa, &qb, h) * b;
        }
        total
    }

    /// The discrete forces f^ν = h Σ_i b_i ℓ_ν(c_i) f(q_d(c_i), q̇_d(c_i), u) into `out`
    /// (length (s + 1)·n, point ν at ν·n), with h·f(q, v, u) = Fd(q − hv/2, q + hv/2, u, h).
    pub fn forces<D: Scalar, M: Mechanics>(
        &self,
        mech: &M,
        control: &[D],
        u: &[D],
        h: D,
        out: &mut [D],
    ) {
        let n = mech.nq();
        out.iter_mut().for_each(|o| *o = D::zero());
        let mut force = vec![D::zero(); n];
        for (i, &b) in self.weights.iter().enumerate() {
            let (qa, qb) = self.midpoint_ends(control, h, i);
            mech.discrete_force(&qa, &qb, u, h, &mut force);
            for (nu, chunk) in out.chunks_exact_mut(n).enumerate() {
                let w = b * self.basis[i][nu];
                for (o, &f) in chunk.iter_mut().zip(&force) {
                    *o += f * w;
                }
            }
        }
    }

    /// The weights of control point ν in the ends of quadrature point i's midpoint segment
    /// (see [`GalerkinRule::action`]): qa_i = Σ_ν wa_ν q^ν, qb_i = Σ_ν wb_ν q^ν with
    /// wa_ν = ℓ_ν(c_i) − ℓ̇_ν(c_i)/2 and wb_ν = ℓ_ν(c_i) + ℓ̇_ν(c_i)/2: linear in the control
    /// points and free of h, so derivatives of A and f^ν chain from the segment's.
    pub fn segment_weights(&self, i: usize) -> Vec<(f64, f64)> {
        self.basis[i]
            .iter()
            .zip(&self.basis_rate[i])
            .map(|(&l, &dl)| (l - 0.5 * dl, l + 0.5 * dl))
            .collect()
    }

    /// The midpoint segment (q − hv/2, q + hv/2) whose Ld and Fd are h·L and h·f at the path's
    /// state (q, v) at quadrature point i.
    fn midpoint_ends<D: Scalar>(&self, control: &[D], h: D, i: usize) -> (Vec<D>, Vec<D>) {
        let (q, v) = self.path_at(control, h, i);
        let half: Vec<D> = v.iter().map(|&vj| vj * h * 0.5).collect();
        let qa = q.iter().zip(&half).map(|(&a, &d)| a - d).collect();
        let qb = q.iter().zip(&half).map(|(&a, &d)| a + d).collect();
        (qa, qb)
    }
}

impl GalerkinRule {
    /// The linear map P_i from x = [q^0; …; q^s; h] to quadrature point i's midpoint segment
    /// z_i = [qa_i; qb_i; h] ([`GalerkinRule::segment_weights`]), for n coordinates: the
    /// action is A(x) = Σ_i b_i Ld(P_i x), so its derivatives are the segment's pulled back,
    /// ∇A = Σ_i b_i P_iᵀ∇Ld, ∇²A = Σ_i b_i P_iᵀ∇²Ld P_i and likewise the third derivative
    /// contracted with d, with ∇³Ld contracted with P_i d.
    pub fn segment_map(&self, i: usize, n: usize) -> DMatrix<f64> {
        let points = self.nodes.len();
        let mut p = DMatrix::zeros(2 * n + 1, points * n + 1);
        for (nu, (wa, wb)) in self.segment_weights(i).into_iter().enumerate() {
            for r in 0..n {
                p[(r, nu * n + r)] = wa;
                p[(n + r, nu * n + r)] = wb;
            }
        }
        p[(2 * n, points * n)] = 1.0;
        p
    }
}

/// ∇A at x = [q^0; …; q^s; h] (the rows' values: ∂A/∂q^ν per control point, then ∂A/∂h),
/// chained from the mechanics' own segment gradient through [`GalerkinRule::segment_map`].
pub fn action_gradient<M: MechanicsDerivatives>(
    mech: &M,
    rule: &GalerkinRule,
    x: &[f64],
) -> Vec<f64> {
    let mut out = DVector::zeros(x.len());
    for_each_segment(mech, rule, x, |b, p, z| {
        out += p.tr_mul(&DVector::from_vec(mech.segment_gradient(z))) * b;
    });
    out.as_slice().to_vec()
}

/// ∇A and ∇²A at x = [q^0; …; q^s; h], chained from the mechanics' own segment derivatives
/// (for a URDF model, its adjoint) through [`GalerkinRule::segment_map`].
pub fn action_gradient_hessian<M: MechanicsDerivatives>(
    mech: &M,
    rule: &GalerkinRule,
    x: &[f64],
) -> (Vec<f64>, DMatrix<f64>) {
    let mut gradient = DVector::zeros(x.len());
    let mut hessian = DMatrix::zeros(x.len(), x.len());
    for_each_segment(mech, rule, x, |b, p, z| {
        let (g, h) = mech.segment_gradient_hessian(z);
        gradient += p.tr_mul(&DVector::from_vec(g)) * b;
        hessian += p.tr_mul(&h) * p * b;
    });
    (gradient.as_slice().to_vec(), hessian)
}

/// A, ∇A, ∇²A and the third derivative contracted with `dir` at x = [q^0; …; q^s; h], chained
/// from [`MechanicsDerivatives::segment_third_order`] with the segment's direction P_i·dir.
pub fn action_third_order<M: MechanicsDerivatives>(
    mech: &M,
    rule: &GalerkinRule,
    x: &[f64],
    dir: &[f64],
) -> ThirdOrder {
    let mut out = ThirdOrder::zeros(x.len());
    let mut gradient = DVector::zeros(x.len());
    let dir = DVector::from_column_slice(dir);
    for_each_segment(mech, rule, x, |b, p, z| {
        let pd = p * &dir;
        let t = mech.segment_third_order(z, pd.as_slice(), None);
        out.value += b * t.value;
        gradient += p.tr_mul(&DVector::from_vec(t.gradient)) * b;
        out.hessian += p.tr_mul(&t.hessian) * p * b;
        out.contracted += p.tr_mul(&t.contracted) * p * b;
    });
    out.gradient = gradient.as_slice().to_vec();
    out
}

/// Calls `f(b_i, P_i, z_i)` for every quadrature point i of the action at x.
fn for_each_segment<M: Mechanics>(
    mech: &M,
    rule: &GalerkinRule,
    x: &[f64],
    mut f: impl FnMut(f64, &DMatrix<f64>, &[f64]),
) {
    let x = DVector::from_column_slice(x);
    for (i, &b) in rule.quadrature_weights().iter().enumerate() {
        let p = rule.segment_map(i, mech.nq());
        let z = &p * &x;
        f(b, &p, z.as_slice());
    }
}

/// ℓ_ν(τ) = Π_{j≠ν} (τ − d_j)/(d_ν − d_j).
fn lagrange(nodes: &[f64], nu: usize, tau: f64) -> f64 {
    nodes
        .iter()
        .enumerate()
        .filter(|&(j, _)| j != nu)
        .map(|(_, &d)| (tau - d) / (nodes[nu] - d))
        .product()
}

/// ℓ̇_ν(τ) = Σ_{m≠ν} 1/(d_ν − d_m) Π_{j≠ν,m} (τ − d_j)/(d_ν − d_j).
fn lagrange_rate(nodes: &[f64], nu: usize, tau: f64) -> f64 {
    (0..nodes.len())
        .filter(|&m| m != nu)
        .map(|m| {
            let rest: f64 = (0..nodes.len())
                .filter(|&j| j != nu && j != m)
                .map(|j| (tau - nodes[j]) / (nodes[nu] - nodes[j]))
                .product();
            rest / (nodes[nu] - nodes[m])
        })
        .sum()
}

/// The action A as a [`ScalarFunction`] of z = [q^0; …; q^s; h] (dim (s + 1)·n + 1). Its
/// gradient holds ∂A/∂q^ν per control point and ∂A/∂h.
#[derive(Debug, Clone, Copy)]
pub struct GalerkinAction<'a, M> {
    /// The robot.
    pub mech: &'a M,
    /// The member.
    pub rule: &'a GalerkinRule,
}

impl<M: Mechanics> ScalarFunction for GalerkinAction<'_, M> {
    fn dim(&self) -> usize {
        self.rule.nodes.len() * self.mech.nq() + 1
    }
    fn eval<D: Scalar>(&self, z: &[D]) -> D {
        let (control, h) = z.split_at(z.len() - 1);
        self.rule.action(self.mech, control, h[0])
    }
}

/// The discrete forces f^0 … f^s as a [`VectorFunction`] of z = [q^0; …; q^s; u; h]
/// (dim (s + 1)·n + m + 1) → R^{(s+1)·n}.
#[derive(Debug, Clone, Copy)]
pub struct GalerkinForce<'a, M> {
    /// The robot.
    pub mech: &'a M,
    /// The member.
    pub rule: &'a GalerkinRule,
}

impl<M: Mechanics> VectorFunction for GalerkinForce<'_, M> {
    fn dim_in(&self) -> usize {
        self.dim_out() + self.mech.nu() + 1
    }
    fn dim_out(&self) -> usize {
        self.rule.nodes.len() * self.mech.nq()
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        let points = self.dim_out();
        let (control, rest) = z.split_at(points);
        let (u, h) = rest.split_at(rest.len() - 1);
        self.rule.forces(self.mech, control, u, h[0], out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::finite_differences::central;

    /// The quadrature integrates polynomials of degree 2s − 1 exactly (order 2s), the basis
    /// interpolates (ℓ_ν(d_μ) = δ_νμ) and ℓ̇ is the derivative of ℓ.
    #[test]
    fn quadrature_has_order_2s_and_the_basis_interpolates() {
        for s in 1..=GalerkinRule::MAX_DEGREE {
            let rule = GalerkinRule::of_degree(s).expect("tabulated");
            assert_eq!(rule.degree(), s);
            for p in 0..2 * s {
                let q: f64 = rule
                    .weights
                    .iter()
                    .zip(&rule.points)
                    .map(|(b, c)| b * c.powi(p as i32))
                    .sum();
                assert!((q - 1.0 / (p as f64 + 1.0)).abs() < 1e-15, "s {s}, τ^{p}");
            }
            // Degree 2s is not integrated exactly: the order is 2s, not more.
            let q: f64 = rule
                .weights
                .iter()
                .zip(&rule.points)
                .map(|(b, c)| b * c.powi(2 * s as i32))
                .sum();
            assert!((q - 1.0 / (2.0 * s as f64 + 1.0)).abs() > 1e-6);
            for nu in 0..=s {
                for (mu, &d) in rule.nodes.iter().enumerate() {
                    let expected = if nu == mu { 1.0 } else { 0.0 };
                    assert!((lagrange(&rule.nodes, nu, d) - expected).abs() < 1e-14);
                }
                let tau = 0.37;
                let fd = central(|t| lagrange(&rule.nodes, nu, tau + t), 1e-6);
                assert!((lagrange_rate(&rule.nodes, nu, tau) - fd).abs() < 1e-8);
            }
        }
        assert!(GalerkinRule::of_degree(0).is_none());
        assert!(GalerkinRule::of_degree(4).is_none());
    }

    /// The interior Lobatto nodes of s = 3 are the roots of P'_3 on [0, 1]: P'_3(x) ∝ 5x² − 1
    /// on [−1, 1].
    #[test]
    fn lobatto_nodes_are_the_roots_of_the_legendre_derivative() {
        let rule = GalerkinRule::of_degree(3).expect("tabulated");
        for &d in &rule.nodes[1..3] {
            let x = 2.0 * d - 1.0;
            assert!((5.0 * x * x - 1.0).abs() < 1e-14);
        }
    }
}
