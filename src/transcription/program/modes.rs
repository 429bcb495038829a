//! The contact modes of a point, and the NLP with them fixed: the bounds of the polish
//! (`[slack] polish`), a regular NLP in place of the relaxed complementarity.
//!
//! Each complementarity pair of interval j and contact i, c ⟂ φ(q_{j+1}), β_d ⟂ η_d and
//! ψ ⟂ μc − eᵀβ, has its smaller side fixed at zero: a variable by its upper bound, a row
//! (φ, the friction cone) by making it an equality. "Smaller" compares the values as they
//! are: at a complementary point one side is at zero (±1e-8) and the other is not, whatever
//! the units. Relative to each quantity's largest value instead, a foot in flight with η = 3.6
//! had its β of 1.5e-4 count as the larger side, because ψ and η, which nothing bounds in
//! flight, reach 1e6 elsewhere. The slacks are fixed at zero and the complementarity
//! rows, whose products are then zero on every feasible point, are freed.

use super::super::start::Bounds;
use super::Transcription;
use crate::discrete::MechanicsDerivatives;

/// How many pairs a mode-fixed NLP fixed on each side.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct FixedModes {
    /// Contact-intervals with the normal impulse fixed at zero (free of force).
    pub free: usize,
    /// Contact-intervals held in touch (φ = 0 at the interval's end).
    pub touching: usize,
    /// Friction directions with β fixed at zero.
    pub no_friction: usize,
    /// Friction directions with η fixed at zero (the direction opposing the slip).
    pub opposing: usize,
    /// Contact-intervals with ψ fixed at zero (sticking, or no force).
    pub sticking: usize,
    /// Contact-intervals on the friction cone's edge (μc = eᵀβ: sliding).
    pub sliding: usize,
}

/// One pair of a variable and a row, each at its value: the variable fixed at zero (its upper
/// bound) when it is the smaller side (ties: the variable), else the row made an equality at
/// its lower bound; whether the variable was fixed. `bounds`: the variables' upper bounds,
/// the rows' lower and upper bounds.
fn fix_variable_or_row(
    bounds: (&mut [f64], &[f64], &mut [f64]),
    (variable, x): (usize, f64),
    (row, g): (usize, f64),
) -> bool {
    let (x_upper, g_lower, g_upper) = bounds;
    if x <= g {
        x_upper[variable] = 0.0;
        true
    } else {
        g_upper[row] = g_lower[row];
        false
    }
}

impl<M: MechanicsDerivatives> Transcription<M> {
    /// Fix the contact modes of `x` (module docs): its bounds change, and the bounds it had
    /// are returned for [`Transcription::restore_bounds`]. Contact-mode blocks longer than
    /// one interval pair one interval's ψ, η and c with another's: validation refuses the
    /// polish with them, and this fixes nothing for them either.
    pub(crate) fn fix_contact_modes(&mut self, x: &[f64]) -> (Bounds, FixedModes) {
        let previous = self.bounds();
        let mut fixed = FixedModes::default();
        let l = &self.layout;
        let intervals = l.intervals();
        if l.nc == 0 || self.ctx.mode_block > 1 {
            return (previous, fixed);
        }
        let mut g = vec![0.0; l.num_constraints()];
        self.constraints(x, &mut g);
        let phi_row = |j: usize, i: usize| l.rows_of("Distance", j).start + i;
        let cone_row = |j: usize, i: usize| l.rows_of("FrictionCone", j).start + i;
        for i in 0..l.nc {
            for j in 0..intervals {
                let c = l.c(j, i);
                let phi = phi_row(j, i);
                let bounds = (
                    &mut self.x_upper[..],
                    &self.g_lower[..],
                    &mut self.g_upper[..],
                );
                if fix_variable_or_row(bounds, (c, x[c]), (phi, g[phi])) {
                    fixed.free += 1;
                } else {
                    fixed.touching += 1;
                }
                for (beta, eta) in l.beta(j, i).zip(l.eta(j, i)) {
                    if x[beta] <= x[eta] {
                        self.x_upper[beta] = 0.0;
                        fixed.no_friction += 1;
                    } else {
                        self.x_upper[eta] = 0.0;
                        fixed.opposing += 1;
                    }
                }
                let (psi, cone) = (l.psi(j, i), cone_row(j, i));
                let bounds = (
                    &mut self.x_upper[..],
                    &self.g_lower[..],
                    &mut self.g_upper[..],
                );
                if fix_variable_or_row(bounds, (psi, x[psi]), (cone, g[cone])) {
                    fixed.sticking += 1;
                } else {
                    fixed.sliding += 1;
                }
            }
        }
        for s in l.slacks() {
            self.x_upper[s] = 0.0;
        }
        let freed: Vec<usize> = self.freed_rows().collect();
        for r in freed {
            self.g_lower[r] = f64::NEG_INFINITY;
        }
        (previous, fixed)
    }

    /// The rows a mode-fixed NLP freed (module docs): the complementarity rows.
    pub(crate) fn freed_rows(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.layout.intervals()).flat_map(|j| self.layout.rows_of("Complementarity", j))
    }

    /// Put back the bounds [`Transcription::fix_contact_modes`] returned.
    pub(crate) fn restore_bounds(&mut self, bounds: Bounds) {
        self.x_lower = bounds.x_lower;
        self.x_upper = bounds.x_upper;
        self.g_lower = bounds.g_lower;
        self.g_upper = bounds.g_upper;
    }

    fn bounds(&self) -> Bounds {
        Bounds {
            x_lower: self.x_lower.clone(),
            x_upper: self.x_upper.clone(),
            g_lower: self.g_lower.clone(),
            g_upper: self.g_upper.clone(),
        }
    }
}
