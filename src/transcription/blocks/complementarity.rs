//! The relaxed products ηᵀβ and ψ(μc − eᵀβ) of the listed contacts with the slacks; z = [(c,
//! β, ψ, η) per contact; slacks (0: added by another block, 1 shared, or 3)], where c and β
//! may be another interval's of the same contact-mode block than ψ and η. Bilinear:
//! closed-form Jacobian and Hessian.

use nalgebra::DMatrix;

use super::place::range_vec;
use super::{Block, Context, Distance, Placement, RowBlock, Stage, VectorKind};
use crate::autodiff::Scalar;
use crate::contact::{self, complementarity_hessian, complementarity_jacobian};
use crate::discrete::{Mechanics, MechanicsDerivatives};
use crate::problem::SlackMode;
use crate::transcription::layout::{COMPLEMENTARITY_NAMES, Dims, EntryNames, IntervalRows, Layout};

/// The complementarity products of `contacts` with `slacks` slacks.
#[derive(Debug, Clone, PartialEq)]
pub struct Complementarity {
    /// The contacts, in z order.
    pub contacts: Vec<usize>,
    /// Slacks at the end of z.
    pub slacks: usize,
}

impl RowBlock for Complementarity {
    const NAME: &'static str = "Complementarity";
    fn interval_rows(dims: &Dims, slack_mode: SlackMode) -> Option<IntervalRows> {
        let count = match slack_mode {
            SlackMode::PerInterval => 3,
            SlackMode::PerContact => 3 * dims.nc,
            // The products are in the objective (`ComplementarityPenalty`).
            SlackMode::Penalty => return None,
        };
        let name: fn(&Layout, usize, usize, EntryNames) -> String = match slack_mode {
            SlackMode::PerInterval | SlackMode::Penalty => |_, local, j, _| {
                format!("s - sum {}, interval {j}", COMPLEMENTARITY_NAMES[local % 3])
            },
            SlackMode::PerContact => |_, local, j, names| {
                let contact = names.contact(local / 3);
                format!(
                    "s - {} {contact}, interval {j}",
                    COMPLEMENTARITY_NAMES[local % 3]
                )
            },
        };
        Some(IntervalRows {
            kind: Self::NAME,
            count,
            equality: false,
            name,
        })
    }
    fn place(p: &mut Placement<'_>, stage: Stage) {
        // Per contact, its −c·φ gap rows (`Distance` with `gap`) and its products; one block
        // per contact keeps the Hessian sparse (products of different contacts never meet).
        // In per-interval mode the shared slack rides on the first block and every block adds
        // into the same three rows.
        //
        // Interval j's rows pair its own c, ψ, η with the sums over its contact-mode block
        // B ∋ j (`contacts.mode_block`) of φ(q_{j'+1}), μc_{j'} − eᵀβ_{j'} and β_{j'}: one gap
        // block and one product block per j' ∈ B, whose z takes c and β from j' and ψ, η from
        // j (the products are bilinear, so the same functions and closed forms serve). With
        // blocks of one interval this is the reference NLP, block for block.
        let Stage::Complementarity(j) = stage else {
            return;
        };
        let l = p.layout;
        if l.slack_mode == SlackMode::Penalty {
            return;
        }
        let rows = range_vec(l.rows_of(Self::NAME, j));
        let slacks = range_vec(l.slack(j));
        let shared = slacks.len() == 1;
        let (groups, partners): (Vec<Vec<usize>>, Vec<usize>) = if l.nc == 0 {
            (vec![vec![]], vec![j])
        } else {
            (
                (0..l.nc).map(|i| vec![i]).collect(),
                p.ctx.mode_block_of(j, l.intervals()).collect(),
            )
        };
        for (g, contacts) in groups.into_iter().enumerate() {
            for &k in &partners {
                let mut vars = Vec::new();
                for &i in &contacts {
                    vars.push(l.c(k, i));
                    vars.extend(l.beta(k, i));
                    vars.push(l.psi(j, i));
                    vars.extend(l.eta(j, i));
                }
                let nonlinear = vars.len();
                let (own, block_rows) = if shared {
                    let own = if g == 0 && k == j {
                        vec![slacks[0]]
                    } else {
                        vec![]
                    };
                    (own, &rows[..3])
                } else {
                    let own = if k == j {
                        slacks[3 * g..3 * g + 3].to_vec()
                    } else {
                        vec![]
                    };
                    (own, &rows[3 * g..3 * g + 3])
                };
                for &i in &contacts {
                    let mut gap_vars = range_vec(l.q(k + 1));
                    gap_vars.push(l.c(j, i));
                    p.vector.push(Block::new(
                        VectorKind::Distance(Distance {
                            contact: i,
                            gap: true,
                        }),
                        gap_vars,
                        l.n + 1,
                        vec![vec![block_rows[1]]],
                    ));
                }
                let num_slacks = own.len();
                vars.extend(own);
                let targets = block_rows.iter().map(|&r| vec![r]).collect();
                p.vector.push(Block::new(
                    VectorKind::Complementarity(Complementarity {
                        contacts: contacts.clone(),
                        slacks: num_slacks,
                    }),
                    vars,
                    nonlinear,
                    targets,
                ));
            }
        }
    }
    fn value<D: Scalar, M: Mechanics>(&self, _: &M, ctx: &Context, z: &[D], out: &mut [D]) {
        contact::complementarity(&ctx.contact, &self.contacts, self.slacks, z, out)
    }
    fn jacobian<M: MechanicsDerivatives>(
        &self,
        _: &M,
        ctx: &Context,
        z: &[f64],
    ) -> Option<DMatrix<f64>> {
        Some(complementarity_jacobian(
            &ctx.contact,
            &self.contacts,
            self.slacks,
            z,
        ))
    }
    fn hessian<M: MechanicsDerivatives>(
        &self,
        _: &M,
        ctx: &Context,
        z: &[f64],
        w: &[f64],
    ) -> Option<DMatrix<f64>> {
        Some(complementarity_hessian(
            &ctx.contact,
            &self.contacts,
            z.len(),
            w,
        ))
    }
}
