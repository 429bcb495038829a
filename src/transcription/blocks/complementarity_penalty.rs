//! The penalty form of the complementarity (`[slack] mode = "penalty"`, Leyffer, López-Calva
//! & Nocedal 2006): no slacks and no complementarity rows; the objective gets α times the
//! products ηᵀβ, c·φ and ψ(μc − eᵀβ) of every contact and interval, whose factors the bounds
//! and the distance and friction-cone rows keep ≥ 0. A cost block per contact and pair of
//! intervals (j, k ∈ j's contact-mode block, as the elastic rows pair them): the gap term
//! α c_j φ(q_{k+1}), z = [q_{k+1}; c_j] (`gap`), or the bilinear terms α(η_jᵀβ_k +
//! ψ_j(μc_k − eᵀβ_k)), z = [c_k, β_k, ψ_j, η_j]. Values generic over the scalar (generic AD
//! differentiates them under `set_contact_chain_rule(false)`); by default the closed forms of
//! the elastic rows the terms replace, weighted by −α: the bilinear rows' and the gap row's
//! chain rule through the contact point's jet.

use nalgebra::DMatrix;

use super::place::range_vec;
use super::{Block, Context, Eval, GradientBlock, Placement, ScalarKind, Stage};
use crate::autodiff::Scalar;
use crate::contact::{
    self, Own, Partner, Products, complementarity_hessian, complementarity_jacobian,
    distance_hessian, distance_jacobian,
};
use crate::discrete::{Mechanics, MechanicsDerivatives};
use crate::problem::SlackMode;
use crate::transcription::layout::Layout;

/// The name of the penalty in the objective's split (`Solution::objective_terms`).
pub const PENALTY_TERM: &str = "complementarity_penalty";

/// One contact's weighted complementarity products over one pair of intervals.
#[derive(Debug, Clone, PartialEq)]
pub struct ComplementarityPenalty {
    /// The contact.
    pub contact: usize,
    /// Whether the term is α c·φ(q) (z = [q; c]) rather than α(ηᵀβ + ψ(μc − eᵀβ))
    /// (z = [c, β (nd), ψ, η (nd)]).
    pub gap: bool,
}

impl GradientBlock for ComplementarityPenalty {
    const NAME: &'static str = "ComplementarityPenalty";
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // Where the elastic form places interval j's complementarity rows, one gap block and
        // one product block per contact and partner interval k of j's contact-mode block
        // (`Complementarity::place` pairs the same variables).
        let Stage::Complementarity(j) = stage else {
            return;
        };
        let l = p.layout;
        if l.slack_mode != SlackMode::Penalty {
            return;
        }
        for i in 0..l.nc {
            for k in p.ctx.mode_block_of(j, l.intervals()) {
                let mut gap_vars = range_vec(l.q(k + 1));
                gap_vars.push(l.c(j, i));
                let gap = ComplementarityPenalty {
                    contact: i,
                    gap: true,
                };
                p.cost
                    .push(Block::new(ScalarKind::from(gap), gap_vars, l.n + 1, vec![]));
                let mut vars = vec![l.c(k, i)];
                vars.extend(l.beta(k, i));
                vars.push(l.psi(j, i));
                vars.extend(l.eta(j, i));
                let products = ComplementarityPenalty {
                    contact: i,
                    gap: false,
                };
                let nonlinear = vars.len();
                p.cost.push(Block::new(
                    ScalarKind::from(products),
                    vars,
                    nonlinear,
                    vec![],
                ));
            }
        }
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, ctx: &Context, z: &[D]) -> D {
        let weight = D::from(ctx.slack_weight);
        if self.gap {
            // `contact_gap` is the row's −cφ.
            -weight * contact::contact_gap(mech, &ctx.contact, self.contact, z)
        } else {
            // The elastic rows' −ηᵀβ and −ψ(μc − eᵀβ) with no slack (its row 1 stays 0).
            let mut rows = [D::from(0.0); 3];
            contact::complementarity(&ctx.contact, &[self.contact], 0, z, &mut rows);
            -weight * (rows[0] + rows[2])
        }
    }
    fn gradient<M: MechanicsDerivatives>(&self, at: &Eval<M>, z: &[f64]) -> Option<Vec<f64>> {
        let (ctx, w) = (at.ctx, -at.ctx.slack_weight);
        if self.gap {
            // The gap row's chain rule (`Distance` with `gap`: −cφ) weighted by −α.
            let row = distance_jacobian(at.mech, &ctx.contact, self.contact, z, true);
            return Some(row.iter().map(|v| w * v).collect());
        }
        // The elastic rows' closed form: −α (row 0 + row 2).
        let rows = complementarity_jacobian(&ctx.contact, &[self.contact], 0, z);
        Some(
            (0..z.len())
                .map(|c| w * (rows[(0, c)] + rows[(2, c)]))
                .collect(),
        )
    }
    fn hessian<M: MechanicsDerivatives>(&self, at: &Eval<M>, z: &[f64]) -> Option<DMatrix<f64>> {
        let (ctx, w) = (at.ctx, -at.ctx.slack_weight);
        if self.gap {
            // Generic AD of φ's kinematics doubled LittleDog's Hessian call (13.7 against
            // 6.5 ms); the gap row's chain rule weighted by −α.
            return Some(distance_hessian(
                at.mech,
                &ctx.contact,
                self.contact,
                z,
                w,
                true,
            ));
        }
        // Constant: the elastic rows' closed form weighted by −α on the two product rows.
        Some(complementarity_hessian(
            &ctx.contact,
            &[self.contact],
            z.len(),
            &[w, 0.0, w],
        ))
    }
}

/// Per interval j and contact i, the complementarity products [η_jᵀΣβ_k, c_j·Σφ(q_{k+1}),
/// ψ_j·Σ(μc_k − eᵀβ_k)] over j's contact-mode block (the pairs of the elastic rows), each
/// factor clipped at 0 ([`Products::clipped`]); `phi[k][i]` is φ_i(q_k).
pub fn interval_products(
    l: &Layout,
    ctx: &Context,
    x: &[f64],
    phi: &[Vec<f64>],
) -> Vec<Vec<[f64; 3]>> {
    (0..l.intervals())
        .map(|j| {
            (0..l.nc)
                .map(|i| {
                    let own = Own {
                        c: x[l.c(j, i)],
                        psi: x[l.psi(j, i)],
                        eta: &x[l.eta(j, i)],
                    };
                    let partners = ctx.mode_block_of(j, l.intervals()).map(|k| {
                        let beta = &x[l.beta(k, i)];
                        Partner {
                            phi: phi[k + 1][i],
                            beta,
                            cone: contact::cone(ctx.contact.friction[i], x[l.c(k, i)], beta),
                        }
                    });
                    Products::clipped(&own, partners).into()
                })
                .collect()
        })
        .collect()
}

/// The slack the elastic per-interval form would hold at interval j for these products: the
/// largest of the three sums over the contacts.
pub fn interval_slack(products: &[[f64; 3]]) -> f64 {
    (0..3)
        .map(|p| products.iter().map(|c| c[p]).sum::<f64>())
        .fold(0.0_f64, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interval_slack_is_the_largest_sum_over_contacts() {
        let products = [[1.0, 0.5, 0.0], [0.25, 2.0, 0.1]];
        assert_eq!(interval_slack(&products), 2.5);
        assert_eq!(interval_slack(&[]), 0.0);
    }
}
