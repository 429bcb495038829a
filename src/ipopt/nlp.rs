//! The sparse nonlinear program that the solver wrapper hands to Ipopt.
//!
//! minimise f(x) subject to x_L ≤ x ≤ x_U and g_L ≤ g(x) ≤ g_U.
//! Structure (sizes, sparsity) is asked once; values are asked every iteration with `new_x`
//! telling whether `x` changed since the last call, so a problem may cache per point.
//! Sparse matrices are triplets (row, col), zero-based; the Hessian of the Lagrangian is
//! given in its lower triangle (row ≥ col). Duplicate triplets are summed by Ipopt.
//! A NaN or Inf written by any value method makes the wrapper report an evaluation failure
//! to Ipopt, which then backtracks.

/// Numbers Ipopt reports at the end of each iteration (the intermediate callback).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationInfo {
    /// Iteration count (0 is the starting point).
    pub iteration: usize,
    /// Unscaled objective value at the current iterate.
    pub objective: f64,
    /// Primal infeasibility (max constraint violation, scaled).
    pub inf_pr: f64,
    /// Dual infeasibility.
    pub inf_du: f64,
    /// Barrier parameter.
    pub mu: f64,
    /// Norm of the last step.
    pub d_norm: f64,
    /// Step size taken for the primal variables.
    pub alpha_pr: f64,
    /// Number of line-search trials.
    pub ls_trials: usize,
    /// 0 for the regular algorithm, 1 in the restoration phase.
    pub mode: i32,
}

/// A sparse NLP with exact first derivatives and, optionally, an exact Lagrangian Hessian.
pub trait Nlp {
    /// Number of variables n.
    fn num_variables(&self) -> usize;
    /// Number of constraints m.
    fn num_constraints(&self) -> usize;
    /// Fill the variable bounds (length n each); use ±f64::INFINITY for none.
    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]);
    /// Fill the constraint bounds (length m each); equal bounds make an equality.
    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]);
    /// Fill the starting point (length n).
    fn initial_point(&self, x: &mut [f64]);

    /// Objective f(x).
    fn objective(&mut self, x: &[f64], new_x: bool) -> f64;
    /// Gradient of f (length n).
    fn gradient(&mut self, x: &[f64], new_x: bool, grad: &mut [f64]);
    /// Constraint values g(x) (length m).
    fn constraints(&mut self, x: &[f64], new_x: bool, g: &mut [f64]);

    /// Number of nonzeros in the constraint Jacobian.
    fn jacobian_nnz(&self) -> usize;
    /// Fill the Jacobian sparsity (length `jacobian_nnz` each).
    fn jacobian_structure(&self, rows: &mut [usize], cols: &mut [usize]);
    /// Fill the Jacobian values in the order of `jacobian_structure`.
    fn jacobian_values(&mut self, x: &[f64], new_x: bool, values: &mut [f64]);

    /// Number of nonzeros in the lower triangle of the Lagrangian Hessian, or `None` when
    /// the problem has no exact Hessian (the solver then uses L-BFGS).
    fn hessian_nnz(&self) -> Option<usize> {
        None
    }
    /// Fill the Hessian sparsity (lower triangle, length `hessian_nnz` each).
    fn hessian_structure(&self, _rows: &mut [usize], _cols: &mut [usize]) {}
    /// Fill the values of ∇²(obj_factor·f + Σ λ_i g_i) in the order of `hessian_structure`.
    fn hessian_values(
        &mut self,
        _x: &[f64],
        _new_x: bool,
        _obj_factor: f64,
        _lambda: &[f64],
        _new_lambda: bool,
        _values: &mut [f64],
    ) {
    }

    /// Scaling factors for Ipopt ([`super::Scaling`]), asked once per solve after the
    /// starting point; `None` (the default) leaves the scaling to Ipopt's options. When given,
    /// the solve sets `nlp_scaling_method user-scaling` unless the options set that name.
    fn scaling(&self) -> Option<super::Scaling> {
        None
    }

    /// Called once per iteration; return `false` to stop the solve (status
    /// `UserRequestedStop`, the current iterate is still returned).
    fn intermediate(&mut self, _info: &IterationInfo) -> bool {
        true
    }
}
