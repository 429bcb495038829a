//! A one-variable test problem for the wrapper, shared by its unit tests and the integration
//! tests: min (x − 1)² over x ∈ [−10, 10] from x = −1, whose callbacks can misbehave on
//! purpose.

use super::Nlp;

/// min (x − 1)², exact Hessian unless `curvature` says otherwise.
#[derive(Debug, Clone)]
pub struct Quadratic {
    /// Panic in `gradient` on this call (1-based).
    pub panic_on_gradient_call: Option<usize>,
    /// Calls of `gradient` so far.
    pub gradient_calls: usize,
    /// The objective is NaN for x above this.
    pub nan_above: f64,
    /// Hessian value used (2 is exact; smaller overshoots).
    pub curvature: f64,
}

impl Default for Quadratic {
    fn default() -> Self {
        Quadratic {
            panic_on_gradient_call: None,
            gradient_calls: 0,
            nan_above: f64::INFINITY,
            curvature: 2.0,
        }
    }
}

impl Nlp for Quadratic {
    fn num_variables(&self) -> usize {
        1
    }
    fn num_constraints(&self) -> usize {
        0
    }
    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        lower[0] = -10.0;
        upper[0] = 10.0;
    }
    fn constraint_bounds(&self, _: &mut [f64], _: &mut [f64]) {}
    fn initial_point(&self, x: &mut [f64]) {
        x[0] = -1.0;
    }
    fn objective(&mut self, x: &[f64], _: bool) -> f64 {
        if x[0] > self.nan_above {
            f64::NAN
        } else {
            (x[0] - 1.0).powi(2)
        }
    }
    fn gradient(&mut self, x: &[f64], _: bool, g: &mut [f64]) {
        self.gradient_calls += 1;
        if self.panic_on_gradient_call == Some(self.gradient_calls) {
            panic!("gradient blew up on purpose");
        }
        g[0] = 2.0 * (x[0] - 1.0);
    }
    fn constraints(&mut self, _: &[f64], _: bool, _: &mut [f64]) {}
    fn jacobian_nnz(&self) -> usize {
        0
    }
    fn jacobian_structure(&self, _: &mut [usize], _: &mut [usize]) {}
    fn jacobian_values(&mut self, _: &[f64], _: bool, _: &mut [f64]) {}
    fn hessian_nnz(&self) -> Option<usize> {
        Some(1)
    }
    fn hessian_structure(&self, rows: &mut [usize], cols: &mut [usize]) {
        rows[0] = 0;
        cols[0] = 0;
    }
    fn hessian_values(&mut self, _: &[f64], _: bool, s: f64, _: &[f64], _: bool, v: &mut [f64]) {
        v[0] = s * self.curvature;
    }
}
