//! User scaling of a problem (Ipopt's `get_scaling_parameters`, the C interface's
//! `SetIpoptProblemScaling`): Ipopt iterates on x̃ = d_x ∘ x, minimises d_f·f and holds the
//! rows d_g ∘ g. Its bound push, Hessian regularisation and convergence tests then act on the
//! scaled quantities; every number it returns (x, g, f, the multipliers) and the objective in
//! the intermediate callback are unscaled.

/// Scaling factors a problem supplies ([`super::Nlp::scaling`]); the solve then uses them
/// under `nlp_scaling_method user-scaling`, unless the options set another method.
#[derive(Debug, Clone, PartialEq)]
pub struct Scaling {
    /// d_f > 0: Ipopt minimises d_f·f (times its option `obj_scaling_factor`).
    pub objective: f64,
    /// d_x (length n, each > 0): Ipopt's i-th variable is d_x,i·x_i; `None` leaves x as it is.
    pub variables: Option<Vec<f64>>,
    /// d_g (length m, each > 0): Ipopt's i-th row is d_g,i·g_i; `None` leaves the rows as
    /// they are.
    pub constraints: Option<Vec<f64>>,
}

/// The limits of Ipopt's gradient-based scaling (options `nlp_scaling_max_gradient` and
/// `nlp_scaling_min_value`, Ipopt's defaults 100 and 1e-8).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GradientRule {
    /// A function whose gradient's largest entry exceeds this is scaled down to it.
    pub max_gradient: f64,
    /// No factor is below this.
    pub min_value: f64,
}

impl Default for GradientRule {
    fn default() -> Self {
        GradientRule {
            max_gradient: 100.0,
            min_value: 1e-8,
        }
    }
}

impl GradientRule {
    /// The factor of a function whose gradient's largest magnitude is `largest`:
    /// max(min_value, min(1, max_gradient/largest)).
    pub fn factor(&self, largest: f64) -> f64 {
        if largest > self.max_gradient {
            (self.max_gradient / largest).max(self.min_value)
        } else {
            1.0
        }
    }
}

/// A sparse Jacobian's entries at one point: (row, column, value) triplets, duplicates
/// allowed.
#[derive(Debug, Clone, Copy)]
pub struct JacobianEntries<'a> {
    /// Rows (length nnz).
    pub rows: &'a [usize],
    /// Columns (length nnz).
    pub cols: &'a [usize],
    /// Values (length nnz).
    pub values: &'a [f64],
}

impl Scaling {
    /// Variables scaled by `variables`, and the objective and rows by Ipopt's own
    /// gradient-based rule at a point, applied to the derivatives with respect to the scaled
    /// variables (∂/∂x̃_j = (∂/∂x_j)/d_x,j): with these factors `user-scaling` differs from
    /// Ipopt's `gradient-based` by the variable scaling alone. `gradient` is ∇f (length n),
    /// `jacobian` the m rows' entries at that point; columns with `skip[j]` (the fixed
    /// variables Ipopt takes out of the problem) count for nothing, as in Ipopt.
    pub fn with_gradient_rule(
        variables: Vec<f64>,
        gradient: &[f64],
        jacobian: JacobianEntries<'_>,
        m: usize,
        skip: &[bool],
        rule: GradientRule,
    ) -> Scaling {
        let scaled = |j: usize, value: f64| {
            if skip.get(j).copied().unwrap_or(false) {
                0.0
            } else {
                (value / variables[j]).abs()
            }
        };
        let objective_largest = gradient
            .iter()
            .enumerate()
            .fold(0.0_f64, |a, (j, &g)| a.max(scaled(j, g)));
        let mut row_largest = vec![0.0_f64; m];
        for ((&r, &c), &v) in jacobian.rows.iter().zip(jacobian.cols).zip(jacobian.values) {
            row_largest[r] = row_largest[r].max(scaled(c, v));
        }
        Scaling {
            objective: rule.factor(objective_largest),
            constraints: Some(row_largest.iter().map(|&a| rule.factor(a)).collect()),
            variables: Some(variables),
        }
    }

    /// Checks the sizes (n variables, m rows) and that every factor is finite and positive.
    pub(super) fn check(&self, n: usize, m: usize) -> Result<(), String> {
        let check_factor = |what: String, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(format!(
                    "{what} = {value}; a scaling factor is finite and positive"
                ))
            }
        };
        check_factor("the objective's scaling".to_string(), self.objective)?;
        for (kind, factors, len) in [
            ("variable", &self.variables, n),
            ("constraint", &self.constraints, m),
        ] {
            let Some(factors) = factors else { continue };
            if factors.len() != len {
                return Err(format!(
                    "{} {kind} scaling factors for {len} {kind}s",
                    factors.len()
                ));
            }
            for (i, &d) in factors.iter().enumerate() {
                check_factor(format!("{kind} {i}'s scaling"), d)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule on a small problem: the scaled derivatives decide, fixed columns do not.
    #[test]
    fn gradient_rule_in_scaled_variables() {
        // Row 0: entries 500 (x0) and 3 (x1); row 1: 50 (x1) and 1e12 (x2, fixed).
        let jacobian = JacobianEntries {
            rows: &[0, 0, 1, 1],
            cols: &[0, 1, 1, 2],
            values: &[500.0, 3.0, 50.0, 1e12],
        };
        let skip = [false, false, true];
        let rule = GradientRule::default();
        // Unscaled variables: row 0 has 500 > 100, so 0.2; row 1 has 50: 1.
        let plain =
            Scaling::with_gradient_rule(vec![1.0; 3], &[1e3, 0.0, 0.0], jacobian, 2, &skip, rule);
        assert_eq!(plain.objective, 0.1);
        assert_eq!(plain.constraints, Some(vec![0.2, 1.0]));
        // x0 scaled by 10 (x̃0 = 10·x0): row 0's entry becomes 50 and the objective's 100;
        // x1 scaled by 0.1: its entries become 30 and 500 (row 1 scaled to 0.2).
        let scaled = Scaling::with_gradient_rule(
            vec![10.0, 0.1, 1.0],
            &[1e3, 0.0, 0.0],
            jacobian,
            2,
            &skip,
            rule,
        );
        assert_eq!(scaled.objective, 1.0);
        assert_eq!(scaled.constraints, Some(vec![1.0, 0.2]));
        assert_eq!(rule.factor(1e20), 1e-8);
        assert!(scaled.check(3, 2).is_ok());
        assert!(scaled.check(3, 3).is_err());
        let zero = Scaling {
            variables: Some(vec![1.0, 0.0, 1.0]),
            ..scaled
        };
        let err = zero.check(3, 2).unwrap_err();
        assert!(err.contains("variable 1's scaling = 0"), "{err}");
    }
}
