//! One step's equations as a smoothed complementarity system: the knot's discrete equations
//! with the contact impulses and loop closures, and per active contact the Fischer–Burmeister
//! pairs 0 ≤ c ⊥ φ, 0 ≤ β ⊥ η, 0 ≤ ψ ⊥ μc − eᵀβ in impulse units; and their linearisation
//! for the pivoting method.

use nalgebra::{DMatrix, DVector};

use super::{Before, ContactStep};
use crate::autodiff::Scalar;
use crate::autodiff::{VectorFunction, jacobian, weighted_hessian};
use crate::contact::{
    Own, Partner, Products, cone, contact_work_gradient, contact_work_hessian,
    distance_with_gradient, gap_product, spin_friction_jacobian, tangential_rate,
    tangential_rate_jacobian,
};
use crate::discrete::{
    EulerKnotInNext, GalerkinInterval, Integrator, MechanicsDerivatives, galerkin_interval,
    outgoing_momentum, outgoing_momentum_input_jacobian, outgoing_momentum_jacobian,
};
use crate::sim::ncp::{Evaluation, LinearisedComplementarity, SmoothedSystem, fischer_burmeister};

/// Loop closures a(q) of any mechanics as an AD function of q.
struct Loops<'a, M>(&'a M);

impl<M: MechanicsDerivatives> VectorFunction for Loops<'_, M> {
    fn dim_in(&self) -> usize {
        self.0.nq()
    }
    fn dim_out(&self) -> usize {
        self.0.num_loop_constraints()
    }
    fn eval<D: Scalar>(&self, z: &[D], out: &mut [D]) {
        self.0.loop_residual(z, out);
    }
}

/// Proximal term on the impulse unknowns' diagonal (relative to the row's unit scale): keeps
/// the Newton matrix regular where the step leaves an impulse undetermined (ψ in flight, the
/// split of forces between redundant contacts at rest), at a linear rate of this size.
const PROXIMAL: f64 = 1e-10;

/// The step's system at a point, with what the step reports.
pub(super) struct StepEvaluation {
    /// Residual, Jacobian and unsmoothed size.
    pub system: Evaluation,
    /// Max-norm of the discrete equations (impulse units).
    pub dynamics: f64,
    /// The NLP's complementarity products ([`Products`]), max over contacts of |c·φ|, |ηᵀβ|
    /// and |ψ(μc − eᵀβ)|.
    pub complementarity: f64,
    /// Signed distance per contact.
    pub distance: Vec<f64>,
}

impl<M: MechanicsDerivatives> ContactStep<'_, M> {
    pub(super) fn n(&self) -> usize {
        self.mech.nq()
    }
    pub(super) fn nc(&self) -> usize {
        self.mech.num_contacts()
    }
    pub(super) fn stride(&self) -> usize {
        2 + self.contact.nd()
    }

    /// The knot's discrete equations without impulses, and their Jacobian in q_{k+1} when
    /// `with_jacobian`.
    pub(super) fn knot(
        &self,
        q_next: &[f64],
        with_jacobian: bool,
    ) -> (Vec<f64>, Option<DMatrix<f64>>) {
        let u = self.u.at(q_next);
        let (value, jac) = self.knot_with_input(q_next, &u, with_jacobian);
        let Some(mut jac) = jac else {
            return (value, None);
        };
        if !self.u.feedback.is_empty() {
            // The chain rule through u_k(q_{k+1}): ∂r/∂u_i · (−stiffness) in column c.
            let input_jacobian = self.knot_input_jacobian(q_next, &u);
            for g in &self.u.feedback {
                let column = input_jacobian.column(g.input) * g.stiffness;
                let mut target = jac.column_mut(g.coordinate);
                target -= column;
            }
        }
        (value, Some(jac))
    }

    /// The knot's equations' Jacobian in u_k (n × m).
    fn knot_input_jacobian(&self, q_next: &[f64], u: &[f64]) -> DMatrix<f64> {
        match (&self.before, self.integrator) {
            (Before::Euler { .. }, Integrator::Euler) => match self.euler_knot(u) {
                Some(f) => f.input_jacobian(q_next),
                None => DMatrix::from_element(self.n(), u.len(), f64::NAN),
            },
            (_, Integrator::Galerkin4 | Integrator::Galerkin6) => match self.interval(q_next, u) {
                Some(interval) => interval.start_by_input,
                None => DMatrix::from_element(self.n(), u.len(), f64::NAN),
            },
            _ => outgoing_momentum_input_jacobian(self.mech, self.q_curr, q_next, u, self.h),
        }
    }

    /// The Galerkin interval (q_k, q_{k+1}) at its stationary interior points, or `None`
    /// where they are not found (the caller's residual is then NaN, a failed step).
    fn interval(&self, q_next: &[f64], u: &[f64]) -> Option<GalerkinInterval> {
        let rule = self.integrator.galerkin_rule()?;
        galerkin_interval(self.mech, &rule, self.q_curr, q_next, u, self.h, None).ok()
    }

    /// The Euler knot equation as a function of q_{k+1} at input u_k = `u`, when `before` is
    /// Euler's (`ContactStep::solve` refuses any other pairing before it gets here).
    fn euler_knot<'s>(&'s self, u: &'s [f64]) -> Option<EulerKnotInNext<'s, M>> {
        let Before::Euler {
            before,
            first_step,
            h_prev,
        } = &self.before
        else {
            return None;
        };
        Some(EulerKnotInNext {
            mech: self.mech,
            first_step: *first_step,
            before,
            q_curr: self.q_curr,
            h_prev: *h_prev,
            h_curr: self.h,
            u_curr: u,
        })
    }

    /// The knot's discrete equations at input u_k = `u`, and their Jacobian in q_{k+1} with
    /// u_k held.
    fn knot_with_input(
        &self,
        q_next: &[f64],
        u: &[f64],
        with_jacobian: bool,
    ) -> (Vec<f64>, Option<DMatrix<f64>>) {
        match (&self.before, self.integrator) {
            (Before::Momentum(p), Integrator::Midpoint) => {
                let (mut value, jac) = if with_jacobian {
                    let (v, j) =
                        outgoing_momentum_jacobian(self.mech, self.q_curr, q_next, u, self.h);
                    (v, Some(j))
                } else {
                    let v = outgoing_momentum(self.mech, self.q_curr, q_next, u, self.h);
                    (v, None)
                };
                value.iter_mut().zip(p).for_each(|(v, p)| *v += p);
                (value, jac)
            }
            (Before::Momentum(p), Integrator::Galerkin4 | Integrator::Galerkin6) => {
                let n = self.n();
                let (mut value, jac) = match self.interval(q_next, u) {
                    Some(interval) => (interval.start, interval.start_by_end),
                    None => (vec![f64::NAN; n], DMatrix::from_element(n, n, f64::NAN)),
                };
                value.iter_mut().zip(p).for_each(|(v, p)| *v += p);
                (value, with_jacobian.then_some(jac))
            }
            (Before::Euler { .. }, Integrator::Euler) => {
                let Some(f) = self.euler_knot(u) else {
                    return self.failed_knot(with_jacobian);
                };
                if with_jacobian {
                    let (v, j) = jacobian(&f, q_next);
                    (v, Some(j))
                } else {
                    let mut v = vec![0.0; q_next.len()];
                    f.eval(q_next, &mut v);
                    (v, None)
                }
            }
            // `ContactStep::solve` refuses a mismatched pairing; should one get here, the
            // residual is NaN, a failed step.
            _ => self.failed_knot(with_jacobian),
        }
    }

    /// A knot equation that cannot be evaluated: NaN values (and Jacobian), a failed step.
    fn failed_knot(&self, with_jacobian: bool) -> (Vec<f64>, Option<DMatrix<f64>>) {
        let n = self.n();
        (
            vec![f64::NAN; n],
            with_jacobian.then(|| DMatrix::from_element(n, n, f64::NAN)),
        )
    }

    /// Residual at x with smoothing ε and contact scales `scale`; the Jacobian only when
    /// `with_jacobian` (zeros otherwise: line-search trials need values alone).
    pub(super) fn evaluate(
        &self,
        x: &[f64],
        eps: f64,
        scale: &[f64],
        active: &[bool],
        with_jacobian: bool,
    ) -> StepEvaluation {
        let (n, nc, nd, stride) = (self.n(), self.nc(), self.contact.nd(), self.stride());
        let nl = self.mech.num_loop_constraints();
        let dim = n + nc * stride + nl;
        let q = &x[..n];
        let (knot, knot_jac) = self.knot(q, with_jacobian);
        let mut residual = DVector::from_vec([knot, vec![0.0; dim - n]].concat());
        let mut jac = DMatrix::zeros(dim, dim);
        if let Some(knot_jac) = knot_jac {
            jac.view_mut((0, 0), (n, n)).copy_from(&knot_jac);
            // Proximal term on q as on the impulses: a coordinate chart singular at a
            // configuration (roll–pitch–yaw at pitch ±π/2, where a brick rests on its end
            // face) leaves a direction of q undetermined; the root is unchanged.
            for r in 0..n {
                let d = knot_jac[(r, r)].abs();
                jac[(r, r)] += PROXIMAL * d.max(f64::MIN_POSITIVE);
            }
        }
        let mut plain = 0.0_f64;
        let mut complementarity = 0.0_f64;
        let mut distance = vec![0.0; nc];
        let segment: Vec<f64> = [self.q_curr, q, &[self.h]].concat();
        for i in 0..nc {
            let base = n + i * stride;
            let vars = &x[base..base + stride];
            let (c, beta, psi) = (vars[0], &vars[1..1 + nd], vars[1 + nd]);
            let z: Vec<f64> = [q, &vars[..1 + nd]].concat();
            // Nᵀc + Pᵀβ into the knot rows, with its derivatives in q, c and β.
            let work = contact_work_gradient(self.mech, self.contact, i, &z);
            let work_hessian = if with_jacobian && active[i] {
                contact_work_hessian(self.mech, self.contact, i, &z)
            } else {
                DMatrix::zeros(n + 1 + nd, n + 1 + nd)
            };
            for r in 0..n {
                residual[r] += work[r];
                for col in 0..n + 1 + nd {
                    let target = if col < n { col } else { base + col - n };
                    jac[(r, target)] += work_hessian[(r, col)];
                }
            }
            if self.mech.contact_rolls(i) {
                // A rolling sphere's friction also turns it (the NLP's SpinFriction rows).
                let (spin, spin_jacobian) = spin_friction_jacobian(self.mech, self.contact, i, &z);
                for r in 0..n {
                    residual[r] += spin[r];
                    if with_jacobian && active[i] {
                        for col in 0..n + 1 + nd {
                            let target = if col < n { col } else { base + col - n };
                            jac[(r, target)] += spin_jacobian[(r, col)];
                        }
                    }
                }
            }
            let phi = work[n];
            distance[i] = phi;
            if !active[i] {
                // Clear of the ground this step: no impulse (the caller checks φ afterwards).
                for r in 0..stride {
                    residual[base + r] = vars[r];
                    jac[(base + r, base + r)] = 1.0;
                    plain = plain.max(vars[r].abs());
                }
                continue;
            }
            let (k_phi, k_v) = (scale[i] / self.h, scale[i]);
            let mu = self.contact.friction[i];
            // 0 ≤ c ⊥ φ ≥ 0.
            let (f, da, db) = fischer_burmeister(c, k_phi * phi, eps);
            residual[base] = f;
            plain = plain.max(fischer_burmeister(c, k_phi * phi, 0.0).0.abs());
            jac[(base, base)] = da;
            for col in 0..n {
                jac[(base, col)] = db * k_phi * work_hessian[(col, n)];
            }
            let products = if mu > 0.0 {
                // 0 ≤ β ⊥ η = P v + ψe ≥ 0.
                // The tangential rate P v, then η = P v + ψe in the same storage.
                let mut eta = vec![0.0; nd];
                tangential_rate(self.mech, self.contact, i, &segment, &mut eta);
                eta.iter_mut().for_each(|e| *e += psi);
                let rate_jac = if with_jacobian {
                    tangential_rate_jacobian(self.mech, self.contact, i, &segment)
                } else {
                    DMatrix::zeros(nd, 2 * n + 1)
                };
                for d in 0..nd {
                    let row = base + 1 + d;
                    let (f, da, db) = fischer_burmeister(beta[d], k_v * eta[d], eps);
                    residual[row] = f;
                    plain = plain.max(fischer_burmeister(beta[d], k_v * eta[d], 0.0).0.abs());
                    jac[(row, row)] = da;
                    jac[(row, base + 1 + nd)] = db * k_v;
                    for col in 0..n {
                        jac[(row, col)] = db * k_v * rate_jac[(d, n + col)];
                    }
                }
                // 0 ≤ ψ ⊥ μc − eᵀβ ≥ 0.
                let cone = cone(mu, c, beta);
                let row = base + 1 + nd;
                let (f, da, db) = fischer_burmeister(k_v * psi, cone, eps);
                residual[row] = f;
                plain = plain.max(fischer_burmeister(k_v * psi, cone, 0.0).0.abs());
                jac[(row, row)] = da * k_v;
                jac[(row, base)] = db * mu;
                for d in 0..nd {
                    jac[(row, base + 1 + d)] = -db;
                }
                Products::new(&Own { c, psi, eta: &eta }, &Partner { phi, beta, cone })
            } else {
                // Frictionless: β = 0 and ψ = 0 (the cone μc − eᵀβ ≥ 0 leaves nothing else),
                // so c·φ is the only product.
                for d in 0..=nd {
                    residual[base + 1 + d] = vars[1 + d];
                    jac[(base + 1 + d, base + 1 + d)] = 1.0;
                    plain = plain.max(vars[1 + d].abs());
                }
                Products {
                    eta_beta: 0.0,
                    gap: gap_product(c, phi),
                    cone: 0.0,
                }
            };
            for r in 0..stride {
                let unit = if r == 1 + nd { k_v } else { 1.0 };
                jac[(base + r, base + r)] += PROXIMAL * unit;
            }
            complementarity = complementarity
                .max(products.gap.abs())
                .max(products.eta_beta.abs())
                .max(products.cone.abs());
        }
        if nl > 0 {
            // Loop closures are few and small: always with derivatives.
            let loops = Loops(self.mech);
            let first = n + nc * stride;
            let nu = &x[first..];
            let (closure, g) = jacobian(&loops, q);
            let impulse = g.tr_mul(&DVector::from_column_slice(nu));
            let curvature = weighted_hessian(&loops, q, nu);
            for r in 0..n {
                residual[r] += impulse[r];
                for col in 0..n {
                    jac[(r, col)] += curvature[(r, col)];
                }
                for l in 0..nl {
                    jac[(r, first + l)] = g[(l, r)];
                }
            }
            for l in 0..nl {
                residual[first + l] = closure[l];
                for col in 0..n {
                    jac[(first + l, col)] = g[(l, col)];
                }
            }
        }
        let dynamics = residual.rows(0, n).amax();
        let loops = if nl > 0 {
            residual.rows(n + nc * stride, nl).amax()
        } else {
            0.0
        };
        StepEvaluation {
            system: Evaluation {
                residual,
                jacobian: jac,
                plain: plain.max(dynamics).max(loops),
            },
            dynamics,
            complementarity,
            distance,
        }
    }
}

/// The step's system with its contacts marked `active` and their scales `scale`, as the
/// complementarity solvers see it.
pub(super) struct StepSystem<'s, 'a, M> {
    /// The step.
    pub step: &'s ContactStep<'a, M>,
    /// Contacts that may carry impulses.
    pub active: &'s [bool],
    /// Each contact's effective mass over the step (impulse units per velocity).
    pub scale: &'s [f64],
}

impl<M: MechanicsDerivatives> SmoothedSystem for StepSystem<'_, '_, M> {
    fn evaluate(&self, x: &[f64], eps: f64, with_jacobian: bool) -> Evaluation {
        self.step
            .evaluate(x, eps, self.scale, self.active, with_jacobian)
            .system
    }
}

/// The classical time-stepping LCP (Stewart–Trinkle, Anitescu–Potra) at the current
/// iterate: the discrete equations and loop closures are linear in the contact impulses and
/// linearised in q and ν; the distances and tangential rates are linearised in q.
impl<M: MechanicsDerivatives> LinearisedComplementarity for StepSystem<'_, '_, M> {
    fn split(&self) -> (Vec<usize>, Vec<usize>) {
        let step = self.step;
        let (n, nc, stride) = (step.n(), step.nc(), step.stride());
        let nl = step.mech.num_loop_constraints();
        let dim = n + nc * stride + nl;
        // The LCP's unknowns: every active contact's c, and β and ψ where it has friction.
        let mut complementary = Vec::new();
        for i in (0..nc).filter(|&i| self.active[i]) {
            let base = n + i * stride;
            let count = if step.contact.friction[i] > 0.0 {
                stride
            } else {
                1
            };
            complementary.extend(base..base + count);
        }
        let free: Vec<usize> = (0..n).chain(n + nc * stride..dim).collect();
        (free, complementary)
    }

    /// The complementary rows, w = M z + q, in the scaled units of `evaluate`; the free
    /// unknowns start with q.
    fn linearised(
        &self,
        x: &[f64],
        a: &DVector<f64>,
        b: &DMatrix<f64>,
    ) -> (DMatrix<f64>, DVector<f64>) {
        let step = self.step;
        let (n, nc, nd, stride) = (step.n(), step.nc(), step.contact.nd(), step.stride());
        let nz = b.ncols();
        let mut m = DMatrix::zeros(nz, nz);
        let mut q = DVector::zeros(nz);
        let mut row = 0;
        let segment: Vec<f64> = [step.q_curr, &x[..n], &[step.h]].concat();
        for i in (0..nc).filter(|&i| self.active[i]) {
            let (phi, grad_phi) = distance_with_gradient(step.mech, step.contact, i, &x[..n]);
            let (k_phi, k_v) = (self.scale[i] / step.h, self.scale[i]);
            // k_φ (φ + ∇φ·Δq).
            q[row] = k_phi * (phi + grad_phi.dot(&a.rows(0, n)));
            let coupling = grad_phi.transpose() * b.rows(0, n);
            for c in 0..nz {
                m[(row, c)] = k_phi * coupling[c];
            }
            let mu = step.contact.friction[i];
            if mu > 0.0 {
                let mut rate = vec![0.0; nd];
                tangential_rate(step.mech, step.contact, i, &segment, &mut rate);
                let rate_jac = tangential_rate_jacobian(step.mech, step.contact, i, &segment)
                    .columns(n, n)
                    .into_owned();
                let rate_a = &rate_jac * a.rows(0, n);
                let rate_b = &rate_jac * b.rows(0, n);
                let psi = row + 1 + nd;
                for d in 0..nd {
                    // k_v (η_d + ∇η_d·Δq + ψ).
                    q[row + 1 + d] = k_v * (rate[d] + rate_a[d]);
                    for c in 0..nz {
                        m[(row + 1 + d, c)] = k_v * rate_b[(d, c)];
                    }
                    m[(row + 1 + d, psi)] += k_v;
                    // μc − eᵀβ.
                    m[(psi, row + 1 + d)] = -1.0;
                }
                m[(psi, row)] = mu;
                row += stride;
            } else {
                row += 1;
            }
        }
        (m, q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::autodiff::finite_differences::{central, moved};
    use crate::discrete::Mechanics;
    use crate::sim::step::StepInput;
    use crate::sim::step::tests::{H, brick};

    #[test]
    fn the_systems_jacobian_is_the_derivative_of_its_residual() {
        // The brick tilted, one edge below the ground and one above, both active, with
        // impulses inside every pair (away from Φ_ε's kink).
        let (mech, contact) = brick();
        let q_curr = [0.0, 0.026, 0.02];
        let u = StepInput::from(vec![0.0; mech.nu()]);
        let step = ContactStep {
            mech: &mech,
            contact: &contact,
            integrator: Integrator::Midpoint,
            before: Before::Momentum(vec![0.3, -0.1, 0.01]),
            q_curr: &q_curr,
            u: &u,
            h: H,
        };
        let system = StepSystem {
            step: &step,
            active: &[true, true],
            scale: &[0.5, 0.7],
        };
        let x = [
            0.011, 0.0255, 0.021, 0.04, 0.01, 0.02, 0.3, 0.05, 0.002, 0.01, 0.2,
        ];
        let eps = 1e-4;
        let e = system.evaluate(&x, eps, true);
        for j in 0..x.len() {
            let fd = central(
                |t| system.evaluate(&moved(&x, j, t), eps, false).residual,
                1e-7,
            );
            for r in 0..x.len() {
                let exact = e.jacobian[(r, j)];
                assert!(
                    (exact - fd[r]).abs() < 1e-5 * (1.0 + exact.abs()),
                    "∂r{r}/∂x{j}: {exact} vs {}",
                    fd[r]
                );
            }
        }
    }
}
