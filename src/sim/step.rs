//! One forward step with contact: the problem of eq. (32) of the paper, the NLP's own rows
//! solved for (q_{k+1}, λ_k) given the past, by a smoothed Fischer–Burmeister Newton method.
//!
//! Unknowns x = [q_{k+1} (n); per contact (c, β (nd), ψ); loop impulses ν (nl)]. Equations:
//! - the knot's discrete equations (midpoint DEL or Euler residual, `crate::discrete::del`)
//!   plus the contact impulses J(q_{k+1})ᵀλ (the NLP's contact-work gradient, and its spin
//!   friction for rolling spheres) and Gᵀν;
//! - per contact, with η = P(q_{k+1})(q_{k+1} − q_k)/h + ψe (the NLP's tangential-velocity
//!   rows solved for η): 0 ≤ c ⊥ φ(q_{k+1}) ≥ 0, 0 ≤ β ⊥ η ≥ 0, 0 ≤ ψ ⊥ μc − eᵀβ ≥ 0;
//! - the loop closures a(q_{k+1}) = 0.
//!
//! Each complementarity pair (a, b) becomes Φ_ε(a, b) = a + b − √(a² + b² + 2ε) = 0, i.e.
//! a, b > 0 with ab = ε, after scaling b to impulse units (φ by the contact's effective
//! mass over h, velocities by the effective mass). ε falls with the residual to a floor below
//! the tolerance; Newton steps are damped by an Armijo line search on ½‖Φ_ε‖².

use nalgebra::{DMatrix, DVector};

use crate::autodiff::{VectorFunction, jacobian, weighted_hessian};
use crate::discrete::{
    EulerKnotInNext, Integrator, MechanicsDerivatives, outgoing_momentum,
    outgoing_momentum_input_jacobian, outgoing_momentum_jacobian,
};
use crate::scalar::Scalar;
use crate::transcription::{
    Context, contact_work_gradient, contact_work_hessian, distance_with_gradient,
    spin_friction_jacobian, tangential_rate, tangential_rate_jacobian,
};

/// Settings of the per-step solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOptions {
    /// Residual tolerance relative to the step's momentum scale.
    pub relative_tolerance: f64,
    /// Newton iterations before the step fails.
    pub max_iterations: usize,
    /// Where every method fails to reach `relative_tolerance`, the step is accepted if its
    /// residual is below this (relative to the same scale); such steps are reported
    /// ([`StepOutcome::residual`], `relaxed_steps` in `summary.json`).
    pub acceptable_tolerance: f64,
    /// Gravity magnitude (the problem's length and time units), for the momentum scale of a
    /// body at rest.
    pub gravity: f64,
    /// A step ending with a coordinate faster than this (problem units per time unit) stops
    /// the run as diverged. No robot moves at a million m/s or rad/s, while an unstable law
    /// (explicit PD at stiff gains) gets there within a few dozen steps; the step solver's
    /// tolerance grows with the momentum and cannot tell.
    pub max_speed: f64,
}

impl Default for StepOptions {
    fn default() -> Self {
        StepOptions {
            relative_tolerance: 1e-10,
            max_iterations: 60,
            acceptable_tolerance: 1e-5,
            gravity: 9.81,
            max_speed: 1e6,
        }
    }
}

/// Why a step failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum StepFailure {
    /// A value became NaN or infinite.
    #[error("non-finite residual at Newton iteration {iteration}; reduce the time step")]
    NonFinite {
        /// Newton iteration.
        iteration: usize,
    },
    /// The Newton matrix could not be factorised.
    #[error("singular Newton matrix at iteration {iteration}")]
    Singular {
        /// Newton iteration.
        iteration: usize,
    },
    /// Newton did not reach the tolerance.
    #[error(
        "the contact problem did not converge in {iterations} Newton iterations (residual {residual:.3e}, tolerance {tolerance:.3e}); reduce the time step"
    )]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// Final max-norm residual (impulse units).
        residual: f64,
        /// The tolerance.
        tolerance: f64,
    },
}

/// What the knot's equation takes from before the step.
#[derive(Debug, Clone)]
pub enum Before<'a> {
    /// Midpoint: the momentum arriving at knot k, D2Ld(q_{k−1}, q_k) + ½Fd_{k−1}
    /// ([`crate::discrete::incoming_momentum`]), or M(q_0)v_0 at the first step.
    Momentum(Vec<f64>),
    /// Euler: v_0 at the first step (`first_step`), else q_{k−1} with h_{k−1}.
    Euler {
        /// v_0 or q_{k−1}.
        before: &'a [f64],
        /// Whether `before` is v_0.
        first_step: bool,
        /// h_{k−1}, s (unused at the first step).
        h_prev: f64,
    },
}

/// Contact and loop impulses of one interval.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Impulses {
    /// Normal impulse c per contact.
    pub normal: Vec<f64>,
    /// Friction impulses β per contact (nd each, the NLP's order).
    pub friction: Vec<Vec<f64>>,
    /// ψ per contact (the sliding speed).
    pub slip: Vec<f64>,
    /// Loop-closure impulses ν.
    pub loops: Vec<f64>,
}

impl Impulses {
    /// All zero for `ctx`'s sizes.
    pub fn zeros(ctx: &Context, contacts: usize) -> Impulses {
        Impulses {
            normal: vec![0.0; contacts],
            friction: vec![vec![0.0; ctx.nd()]; contacts],
            slip: vec![0.0; contacts],
            loops: vec![0.0; ctx.nl],
        }
    }
}

/// Feedback on one input evaluated at the step's end state (implicit feedback):
/// u_k[input] gains `stiffness`·(`target` − q_{k+1}[coordinate]) on top of the held input.
/// PD on q_{k+1} and v_{k+1} = (q_{k+1} − q_k)/h is this with stiffness kp + kd/h.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EndStateGain {
    /// Input index.
    pub input: usize,
    /// Coordinate index.
    pub coordinate: usize,
    /// Input units per coordinate unit.
    pub stiffness: f64,
    /// Where the feedback vanishes (coordinate units).
    pub target: f64,
}

/// A step's input: u_k = `held` plus the [`EndStateGain`]s at q_{k+1}.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StepInput {
    /// The part fixed before the step (length m).
    pub held: Vec<f64>,
    /// Feedback on the step's end state, solved with the step.
    pub feedback: Vec<EndStateGain>,
}

impl From<Vec<f64>> for StepInput {
    fn from(held: Vec<f64>) -> Self {
        StepInput {
            held,
            feedback: Vec::new(),
        }
    }
}

impl StepInput {
    /// u_k at q_{k+1} = `q_next`.
    pub fn at(&self, q_next: &[f64]) -> Vec<f64> {
        let mut u = self.held.clone();
        for g in &self.feedback {
            u[g.input] += g.stiffness * (g.target - q_next[g.coordinate]);
        }
        u
    }
}

/// A solved step.
#[derive(Debug, Clone, PartialEq)]
pub struct StepOutcome {
    /// q_{k+1}.
    pub q_next: Vec<f64>,
    /// u_k at q_{k+1} (the held input plus any end-state feedback).
    pub input: Vec<f64>,
    /// λ_k and ν_k.
    pub impulses: Impulses,
    /// Signed distance per contact at q_{k+1}.
    pub distance: Vec<f64>,
    /// Newton iterations.
    pub iterations: usize,
    /// Max-norm of the whole step system (discrete equations, complementarity pairs as
    /// Fischer–Burmeister values, loops; impulse units) at the solution.
    pub residual: f64,
    /// The tolerance on [`Self::residual`] (`relative_tolerance` times the step's momentum
    /// scale); a residual above it means the step was accepted at `acceptable_tolerance`.
    pub tolerance: f64,
    /// Max-norm of the discrete equations (impulse units) at the solution.
    pub dynamics_residual: f64,
    /// The NLP's complementarity products at the solution, max over contacts of c·φ, ηᵀβ and
    /// ψ(μc − eᵀβ): the slack the NLP would need for this step.
    pub complementarity: f64,
}

/// One step's problem: the robot, the contact constants, the integrator and the knot data.
pub struct ContactStep<'a, M> {
    /// The robot.
    pub mech: &'a M,
    /// Contact constants (the NLP's).
    pub ctx: &'a Context,
    /// Discrete mechanics.
    pub integrator: Integrator,
    /// What the knot equation takes from before the step.
    pub before: Before<'a>,
    /// q_k.
    pub q_curr: &'a [f64],
    /// u_k, held over the step (its feedback part evaluated at q_{k+1}).
    pub u: &'a StepInput,
    /// h_k, s.
    pub h: f64,
}

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

/// Φ_ε(a, b) and its partial derivatives, written without cancellation (far from the
/// kink, 1 − a/ρ is tiny and decides whether a variable is determined at all).
fn fischer_burmeister(a: f64, b: f64, eps: f64) -> (f64, f64, f64) {
    let root = (a * a + b * b + 2.0 * eps).sqrt();
    if root == 0.0 {
        let d = 1.0 - std::f64::consts::FRAC_1_SQRT_2;
        return (0.0, d, d);
    }
    // (a + b)² − ρ² = 2ab − 2ε.
    let value = if a + b > 0.0 {
        2.0 * (a * b - eps) / (a + b + root)
    } else {
        a + b - root
    };
    // 1 − x/ρ = (ρ² − x²)/(ρ(ρ + x)) for x > 0.
    let partial = |x: f64, y: f64| {
        if x > 0.0 {
            (y * y + 2.0 * eps) / (root * (root + x))
        } else {
            1.0 - x / root
        }
    };
    (value, partial(a, b), partial(b, a))
}

/// Proximal term on the impulse unknowns' diagonal (relative to the row's unit scale): keeps
/// the Newton matrix regular where the step leaves an impulse undetermined (ψ in flight, the
/// split of forces between redundant contacts at rest), at a linear rate of this size.
const PROXIMAL: f64 = 1e-10;

/// A failed [`ContactStep::attempt`]: the first failure, the first attempt's last iterate,
/// and the Levenberg–Marquardt attempt's last iterate.
struct AttemptFailure {
    failure: StepFailure,
    last: Vec<f64>,
    damped_last: Vec<f64>,
}

/// How [`ContactStep::newton`] continues where Newton's step is cut short.
#[derive(Debug, Clone, Copy)]
enum Damping {
    /// More smoothing.
    Plain,
    /// A Levenberg–Marquardt step first (momentum: the step's momentum scale).
    LevenbergMarquardt { momentum: f64 },
}

/// Residual, its Jacobian, and the quantities reported at a point.
struct Evaluation {
    residual: DVector<f64>,
    jacobian: DMatrix<f64>,
    /// Max-norm of the unsmoothed residual (ε = 0).
    plain: f64,
    dynamics: f64,
    complementarity: f64,
    distance: Vec<f64>,
}

impl<M: MechanicsDerivatives> ContactStep<'_, M> {
    fn n(&self) -> usize {
        self.mech.nq()
    }
    fn nc(&self) -> usize {
        self.mech.num_contacts()
    }
    fn stride(&self) -> usize {
        2 + self.ctx.nd()
    }

    /// The knot's discrete equations without impulses, and their Jacobian in q_{k+1} when
    /// `with_jacobian`.
    fn knot(&self, q_next: &[f64], with_jacobian: bool) -> (Vec<f64>, Option<DMatrix<f64>>) {
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
            (Before::Euler { .. }, Integrator::Euler) => self.euler_knot(u).input_jacobian(q_next),
            _ => outgoing_momentum_input_jacobian(self.mech, self.q_curr, q_next, u, self.h),
        }
    }

    /// The Euler knot equation as a function of q_{k+1} at input u_k = `u`.
    fn euler_knot<'s>(&'s self, u: &'s [f64]) -> EulerKnotInNext<'s, M> {
        let Before::Euler {
            before,
            first_step,
            h_prev,
        } = &self.before
        else {
            // The caller pairs them (see `super::run`); a mismatch is a programming error.
            panic!("ContactStep: `before` does not match the integrator")
        };
        EulerKnotInNext {
            mech: self.mech,
            first_step: *first_step,
            before,
            q_curr: self.q_curr,
            h_prev: *h_prev,
            h_curr: self.h,
            u_curr: u,
        }
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
            (Before::Euler { .. }, Integrator::Euler) => {
                let f = self.euler_knot(u);
                if with_jacobian {
                    let (v, j) = jacobian(&f, q_next);
                    (v, Some(j))
                } else {
                    let mut v = vec![0.0; q_next.len()];
                    f.eval(q_next, &mut v);
                    (v, None)
                }
            }
            // The caller pairs them (see `super::run`); a mismatch is a programming error.
            _ => panic!("ContactStep: `before` does not match the integrator"),
        }
    }

    /// Residual at x with smoothing ε and contact scales `scale`; the Jacobian only when
    /// `with_jacobian` (zeros otherwise: line-search trials need values alone).
    fn evaluate(
        &self,
        x: &[f64],
        eps: f64,
        scale: &[f64],
        active: &[bool],
        with_jacobian: bool,
    ) -> Evaluation {
        let (n, nc, nd, stride) = (self.n(), self.nc(), self.ctx.nd(), self.stride());
        let nl = self.ctx.nl;
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
            let work = contact_work_gradient(self.mech, self.ctx, i, &z);
            let work_hessian = if with_jacobian && active[i] {
                contact_work_hessian(self.mech, self.ctx, i, &z)
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
                let (spin, spin_jacobian) = spin_friction_jacobian(self.mech, self.ctx, i, &z);
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
            let mu = self.ctx.friction[i];
            // 0 ≤ c ⊥ φ ≥ 0.
            let (f, da, db) = fischer_burmeister(c, k_phi * phi, eps);
            residual[base] = f;
            plain = plain.max(fischer_burmeister(c, k_phi * phi, 0.0).0.abs());
            jac[(base, base)] = da;
            for col in 0..n {
                jac[(base, col)] = db * k_phi * work_hessian[(col, n)];
            }
            let mut cone = mu * c;
            let mut eta_beta = 0.0;
            if mu > 0.0 {
                // 0 ≤ β ⊥ η = P v + ψe ≥ 0.
                let mut rate = vec![0.0; nd];
                tangential_rate(self.mech, self.ctx, i, &segment, &mut rate);
                let rate_jac = if with_jacobian {
                    tangential_rate_jacobian(self.mech, self.ctx, i, &segment)
                } else {
                    DMatrix::zeros(nd, 2 * n + 1)
                };
                for d in 0..nd {
                    let eta = rate[d] + psi;
                    let row = base + 1 + d;
                    let (f, da, db) = fischer_burmeister(beta[d], k_v * eta, eps);
                    residual[row] = f;
                    plain = plain.max(fischer_burmeister(beta[d], k_v * eta, 0.0).0.abs());
                    jac[(row, row)] = da;
                    jac[(row, base + 1 + nd)] = db * k_v;
                    for col in 0..n {
                        jac[(row, col)] = db * k_v * rate_jac[(d, n + col)];
                    }
                    cone -= beta[d];
                    eta_beta += eta * beta[d];
                }
                // 0 ≤ ψ ⊥ μc − eᵀβ ≥ 0.
                let row = base + 1 + nd;
                let (f, da, db) = fischer_burmeister(k_v * psi, cone, eps);
                residual[row] = f;
                plain = plain.max(fischer_burmeister(k_v * psi, cone, 0.0).0.abs());
                jac[(row, row)] = da * k_v;
                jac[(row, base)] = db * mu;
                for d in 0..nd {
                    jac[(row, base + 1 + d)] = -db;
                }
            } else {
                // Frictionless: β = 0 and ψ = 0 (the cone μc − eᵀβ ≥ 0 leaves nothing else).
                for d in 0..=nd {
                    residual[base + 1 + d] = vars[1 + d];
                    jac[(base + 1 + d, base + 1 + d)] = 1.0;
                    plain = plain.max(vars[1 + d].abs());
                }
            }
            for r in 0..stride {
                let unit = if r == 1 + nd { k_v } else { 1.0 };
                jac[(base + r, base + r)] += PROXIMAL * unit;
            }
            complementarity = complementarity
                .max((c * phi).abs())
                .max(eta_beta.abs())
                .max((psi * cone).abs());
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
        Evaluation {
            residual,
            jacobian: jac,
            plain: plain.max(dynamics).max(loops),
            dynamics,
            complementarity,
            distance,
        }
    }

    /// The solved step at x.
    fn outcome(&self, x: &[f64], e: Evaluation, iterations: usize, tolerance: f64) -> StepOutcome {
        let (n, nc, nd, stride) = (self.n(), self.nc(), self.ctx.nd(), self.stride());
        let mut impulses = Impulses::zeros(self.ctx, nc);
        for i in 0..nc {
            let base = n + i * stride;
            impulses.normal[i] = x[base];
            impulses.friction[i] = x[base + 1..base + 1 + nd].to_vec();
            impulses.slip[i] = x[base + 1 + nd];
        }
        impulses.loops = x[n + nc * stride..].to_vec();
        StepOutcome {
            q_next: x[..n].to_vec(),
            input: self.u.at(&x[..n]),
            impulses,
            distance: e.distance,
            iterations,
            residual: e.plain,
            tolerance,
            dynamics_residual: e.dynamics,
            complementarity: e.complementarity,
        }
    }

    /// Solves the step from the guess `q_guess` for q_{k+1} and the warm start `warm` for the
    /// impulses.
    pub fn solve(
        &self,
        q_guess: &[f64],
        warm: &Impulses,
        options: &StepOptions,
    ) -> Result<StepOutcome, StepFailure> {
        let (n, nc, nd, stride) = (self.n(), self.nc(), self.ctx.nd(), self.stride());
        let nl = self.ctx.nl;
        let mut x = q_guess.to_vec();
        for i in 0..nc {
            x.push(warm.normal.get(i).copied().unwrap_or(0.0));
            for d in 0..nd {
                x.push(
                    warm.friction
                        .get(i)
                        .and_then(|b| b.get(d))
                        .copied()
                        .unwrap_or(0.0),
                );
            }
            x.push(warm.slip.get(i).copied().unwrap_or(0.0));
        }
        x.extend((0..nl).map(|l| warm.loops.get(l).copied().unwrap_or(0.0)));

        // Scales from the knot Jacobian A ≈ M/h at the guess: the momentum of the step's
        // motion (and of gravity over it), and each contact's effective mass 1/(∇φ A⁻¹ ∇φᵀ)·h.
        let a0 = self
            .knot(q_guess, true)
            .1
            .unwrap_or_else(|| DMatrix::identity(n, n));
        let motion = DVector::from_iterator(
            n,
            q_guess
                .iter()
                .zip(self.q_curr)
                .map(|(g, c)| (g - c).abs() + options.gravity * self.h * self.h),
        );
        let momentum_scale = (a0.abs() * motion).amax();
        let tolerance = options.relative_tolerance * momentum_scale.max(f64::MIN_POSITIVE);
        let a0_lu = a0.clone().lu();
        let mut scale = vec![1.0; nc];
        for (i, s) in scale.iter_mut().enumerate() {
            let (_, grad) = distance_with_gradient(self.mech, self.ctx, i, q_guess);
            if let Some(y) = a0_lu.solve(&grad) {
                let compliance = grad.dot(&y).abs();
                if compliance.is_finite() && compliance > 0.0 {
                    *s = self.h / compliance;
                }
            }
        }

        // Contacts clear of the ground at the guess and at q_k (by more than twice the
        // guess's approach) carry no impulse; one that ends up below the ground is added and
        // the step solved again.
        let mut active: Vec<bool> = (0..nc)
            .map(|i| {
                let (phi_guess, _) = distance_with_gradient(self.mech, self.ctx, i, q_guess);
                let (phi_curr, _) = distance_with_gradient(self.mech, self.ctx, i, self.q_curr);
                let margin = 2.0 * (phi_guess - phi_curr).abs() + options.gravity * self.h * self.h;
                phi_guess <= margin || phi_curr <= margin
            })
            .collect();
        let mut total = 0;
        // Each round may drop contacts a failed solve found clear of the ground, or add ones
        // that ended below it; bounded so that the two cannot alternate for ever.
        let mut rounds = 0;
        loop {
            rounds += 1;
            for i in (0..nc).filter(|&i| !active[i]) {
                let base = n + i * stride;
                x[base..base + stride].iter_mut().for_each(|v| *v = 0.0);
            }
            let attempt = self.attempt(&x, &active, &scale, tolerance, momentum_scale, options);
            let (solved, iterations) = match attempt {
                Ok(found) => found,
                Err(AttemptFailure {
                    failure,
                    last,
                    damped_last,
                }) => {
                    // A contact in flight carries no impulse, and its ψ (the sliding speed
                    // bound) is then undetermined: Newton can wander along it for ever (ψ of
                    // 1e9 with a singular matrix). Drop the contacts the failed solve ended
                    // clear of the ground, and solve again; the check below adds back any
                    // that end up below it.
                    let e = self.evaluate(&last, 0.0, &scale, &active, false);
                    let clearance = options.gravity * self.h * self.h * 1e-3;
                    let flying: Vec<usize> = (0..nc)
                        .filter(|&i| active[i] && e.distance[i] > clearance)
                        .collect();
                    if flying.is_empty() || rounds > 2 * nc + 2 {
                        // Nothing left to try: accept the last iterate if it is within the
                        // acceptable tolerance (reported as a relaxed step).
                        let e = self.evaluate(&damped_last, 0.0, &scale, &active, false);
                        let below = (0..nc).any(|i| !active[i] && e.distance[i] < 0.0);
                        if below || e.plain > options.acceptable_tolerance * momentum_scale {
                            return Err(failure);
                        }
                        total += options.max_iterations;
                        return Ok(self.outcome(&damped_last, e, total, tolerance));
                    }
                    for i in flying {
                        active[i] = false;
                    }
                    x = last;
                    continue;
                }
            };
            total += iterations;
            x = solved;
            let e = self.evaluate(&x, 0.0, &scale, &active, false);
            let missed: Vec<usize> = (0..nc)
                .filter(|&i| !active[i] && e.distance[i] < 0.0)
                .collect();
            if missed.is_empty() {
                return Ok(self.outcome(&x, e, total, tolerance));
            }
            if rounds > 2 * nc + 2 {
                return Err(StepFailure::NotConverged {
                    iterations: total,
                    residual: -e.distance.iter().cloned().fold(0.0, f64::min),
                    tolerance,
                });
            }
            for i in missed {
                active[i] = true;
            }
        }
    }

    /// Newton from x; once more from q_k at rest with no impulses (a long step's
    /// extrapolated guess can start Newton in the wrong contact mode); path following
    /// from far inside ([`Self::path_following`]), which large, strongly nonlinear steps
    /// need; the pivoting Josephy–Newton method ([`Self::josephy_newton`]), which finds the
    /// contact mode; last, Levenberg–Marquardt ([`Damping::LevenbergMarquardt`]). On failure, the
    /// first failure, the first attempt's last iterate and the damped attempt's.
    fn attempt(
        &self,
        x: &[f64],
        active: &[bool],
        scale: &[f64],
        tolerance: f64,
        momentum_scale: f64,
        options: &StepOptions,
    ) -> Result<(Vec<f64>, usize), AttemptFailure> {
        let n = self.n();
        let plain = Damping::Plain;
        let (first, last) = match self.newton(x.to_vec(), active, scale, tolerance, options, plain)
        {
            Ok(found) => return Ok(found),
            Err(failed) => failed,
        };
        let mut cold = x.to_vec();
        cold[..n].copy_from_slice(self.q_curr);
        cold[n..].iter_mut().for_each(|v| *v = 0.0);
        if let Ok(found) = self.newton(cold, active, scale, tolerance, options, plain) {
            return Ok(found);
        }
        if let Ok(found) = self.path_following(
            x.to_vec(),
            active,
            scale,
            tolerance,
            momentum_scale,
            options,
        ) {
            return Ok(found);
        }
        if let Ok(found) = self.josephy_newton(x.to_vec(), active, scale, tolerance, options) {
            return Ok(found);
        }
        // Last: Levenberg–Marquardt steps where Newton's are cut short, from where the first
        // attempt stopped; on failure its last iterate goes back (the caller may accept it at
        // `acceptable_tolerance`).
        let damped = Damping::LevenbergMarquardt {
            momentum: momentum_scale,
        };
        match self.newton(last.clone(), active, scale, tolerance, options, damped) {
            Ok(found) => Ok(found),
            Err((_, damped_last)) => Err(AttemptFailure {
                failure: first,
                last,
                damped_last,
            }),
        }
    }

    /// Josephy–Newton on the step's complementarity problem, each linearisation solved
    /// exactly by Lemke's pivoting method ([`super::lemke`]), then Newton's polish. At x the
    /// discrete equations and loop closures are linearised in q and ν (they are linear in the
    /// contact impulses), and solved for q and ν as affine functions of the impulses; the
    /// distances and tangential rates are linearised in q. What is left is a linear
    /// complementarity problem in (c, β, ψ) of the active contacts, the classical
    /// time-stepping LCP (Stewart–Trinkle, Anitescu–Potra) at the current iterate, whose
    /// solution is the next iterate.
    ///
    /// Why: where a contact pushes with its ψ far above its slip speed (LittleDog tracking its
    /// 20-knot variational plan at 2 kHz, step 52), Φ(ψ, μc − eᵀβ) is flat in ψ and the
    /// friction rows Φ(β, η) are flat in it too, so the ψ column of Newton's matrix vanishes
    /// and ½‖Φ‖² has a stationary point there that is no solution; no merit-descent method
    /// leaves it (the residual stayed at 1.2e-4, Levenberg–Marquardt at 2.2e-5). The LCP has
    /// no such point: its pivots set the mode (stick, slide, lift) of each contact, and ψ the
    /// slip speed, directly.
    fn josephy_newton(
        &self,
        mut x: Vec<f64>,
        active: &[bool],
        scale: &[f64],
        tolerance: f64,
        options: &StepOptions,
    ) -> Result<(Vec<f64>, usize), StepFailure> {
        let (n, nc, nd, stride) = (self.n(), self.nc(), self.ctx.nd(), self.stride());
        let nl = self.ctx.nl;
        let dim = n + nc * stride + nl;
        // The LCP's unknowns: every active contact's c, and β and ψ where it has friction.
        let mut complementary = Vec::new();
        for i in (0..nc).filter(|&i| active[i]) {
            let base = n + i * stride;
            let count = if self.ctx.friction[i] > 0.0 {
                stride
            } else {
                1
            };
            complementary.extend(base..base + count);
        }
        let free: Vec<usize> = (0..n).chain(n + nc * stride..dim).collect();
        let (nf, nz) = (free.len(), complementary.len());
        let mut best = (f64::INFINITY, x.clone());
        let mut iterations = 0;
        for _ in 0..options.max_iterations {
            let e = self.evaluate(&x, 0.0, scale, active, true);
            if !e.plain.is_finite() {
                break;
            }
            if e.plain < best.0 {
                best = (e.plain, x.clone());
            }
            if e.plain <= tolerance {
                return Ok((x, iterations));
            }
            iterations += 1;
            // The free rows: J_FF Δx_F + J_FZ (z − z_x) = −r_F, so Δx_F = a + B z.
            let j_ff = DMatrix::from_fn(nf, nf, |r, c| e.jacobian[(free[r], free[c])]);
            let j_fz = DMatrix::from_fn(nf, nz, |r, c| e.jacobian[(free[r], complementary[c])]);
            let z_x = DVector::from_iterator(nz, complementary.iter().map(|&i| x[i]));
            let r_f = DVector::from_iterator(nf, free.iter().map(|&r| e.residual[r]));
            let lu = j_ff.lu();
            let (Some(a), Some(b)) = (lu.solve(&(&j_fz * &z_x - r_f)), lu.solve(&(-&j_fz))) else {
                break;
            };
            // The complementary rows, w = M z + q, in the scaled units of `evaluate`.
            let mut m = DMatrix::zeros(nz, nz);
            let mut q = DVector::zeros(nz);
            let mut row = 0;
            let segment: Vec<f64> = [self.q_curr, &x[..n], &[self.h]].concat();
            for i in (0..nc).filter(|&i| active[i]) {
                let (phi, grad_phi) = distance_with_gradient(self.mech, self.ctx, i, &x[..n]);
                let (k_phi, k_v) = (scale[i] / self.h, scale[i]);
                // k_φ (φ + ∇φ·Δq).
                q[row] = k_phi * (phi + grad_phi.dot(&a.rows(0, n)));
                let coupling = grad_phi.transpose() * b.rows(0, n);
                for c in 0..nz {
                    m[(row, c)] = k_phi * coupling[c];
                }
                let mu = self.ctx.friction[i];
                if mu > 0.0 {
                    let mut rate = vec![0.0; nd];
                    tangential_rate(self.mech, self.ctx, i, &segment, &mut rate);
                    let rate_jac = tangential_rate_jacobian(self.mech, self.ctx, i, &segment)
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
            let Ok(z) = super::lemke::lemke(&m, &q, 50 * nz.max(1)) else {
                break;
            };
            let step = a + b * &z;
            for (k, &i) in free.iter().enumerate() {
                x[i] += step[k];
            }
            for (k, &i) in complementary.iter().enumerate() {
                x[i] = z[k];
            }
        }
        // Polish the best iterate (its mode found) with Newton on the smoothed system.
        self.newton(best.1, active, scale, tolerance, options, Damping::Plain)
            .map(|(x, k)| (x, iterations + k))
            .map_err(|(failure, _)| failure)
    }

    /// A Levenberg–Marquardt step on ½‖Φ_ε‖²: (JᵀJ + λ diag(JᵀJ)) d = −JᵀΦ with λ the
    /// residual relative to the step's momentum scale (×10 while the line search still cuts
    /// the step short, up to λ = 1).
    ///
    /// Why: redundant contacts (the toe and heel of Spring Flamingo's flat feet, both
    /// sticking) give Newton's matrix singular values of 1e-7–1e-10 against 3e4; Newton's
    /// directions then run along the undetermined directions (|d| ≫ 1) and the line search
    /// takes steps of 1e-6 (Spring Flamingo tracking its 30-knot plan with kd = 1 stalled at
    /// step 0 with a residual of 2.4e-5). The regularised direction is a descent direction of
    /// bounded length; there it reaches 3.6e-7 (the normal rows of the two feet, φ = ±1.9e-9 m
    /// in opposite signs: the all-stick mode is inconsistent at second order). Used only after
    /// the other attempts fail: as the first choice it led LittleDog's tracking to worse
    /// stalls.
    #[allow(clippy::too_many_arguments)]
    fn levenberg_marquardt(
        &self,
        x: &[f64],
        e: &Evaluation,
        merit: f64,
        eps: f64,
        scale: &[f64],
        active: &[bool],
        momentum: f64,
    ) -> Option<(Vec<f64>, f64, Evaluation)> {
        let normal = e.jacobian.tr_mul(&e.jacobian);
        let gradient = e.jacobian.tr_mul(&e.residual);
        let floor = normal.diagonal().amax() * f64::EPSILON;
        let mut lambda = (e.residual.amax() / momentum.max(f64::MIN_POSITIVE)).min(1.0);
        let mut best = None;
        while lambda <= 1.0 {
            let mut system = normal.clone();
            for r in 0..system.nrows() {
                system[(r, r)] += lambda * normal[(r, r)].max(floor);
            }
            let direction = system.cholesky()?.solve(&(-&gradient));
            if let Some(found) = self.armijo(x, &direction, merit, eps, scale, active, 30) {
                let long = found.1 >= 1e-2;
                best = Some(found);
                if long {
                    break;
                }
            }
            lambda *= 10.0;
        }
        best
    }

    /// Armijo backtracking on ½‖Φ_ε‖² from x along `direction` (halving up to `trials`
    /// times): the accepted point, its step length and its evaluation.
    #[allow(clippy::too_many_arguments)]
    fn armijo(
        &self,
        x: &[f64],
        direction: &DVector<f64>,
        merit: f64,
        eps: f64,
        scale: &[f64],
        active: &[bool],
        trials: usize,
    ) -> Option<(Vec<f64>, f64, Evaluation)> {
        let mut t = 1.0;
        for _ in 0..trials {
            let trial: Vec<f64> = x
                .iter()
                .zip(direction.iter())
                .map(|(a, d)| a + t * d)
                .collect();
            let e = self.evaluate(&trial, eps, scale, active, false);
            let value = 0.5 * e.residual.norm_squared();
            if value.is_finite() && value <= (1.0 - 1e-4 * t) * merit {
                return Some((trial, t, e));
            }
            t *= 0.5;
        }
        None
    }

    /// Path following on the smoothing: ε from the step's momentum scale squared (every
    /// complementarity pair far inside, ab = ε, where Φ_ε is smooth and Newton's basin wide)
    /// down to the floor, Newton converging each level to within its own smoothing before ε
    /// falls by 10; a level that fails restarts from the last solved one with a gentler
    /// decrease (down to 1.5). The interior-point central path of the step's NCP. Returns the
    /// solution and the iterations.
    fn path_following(
        &self,
        x0: Vec<f64>,
        active: &[bool],
        scale: &[f64],
        tolerance: f64,
        momentum_scale: f64,
        options: &StepOptions,
    ) -> Result<(Vec<f64>, usize), StepFailure> {
        let eps_floor = (0.01 * tolerance).powi(2);
        let budget = 10 * options.max_iterations;
        let mut eps = momentum_scale.powi(2).max(eps_floor);
        let mut factor = 0.1;
        let mut x = x0;
        let mut solved_x = x.clone();
        let mut solved_eps = f64::INFINITY;
        let mut iterations = 0;
        let mut last = f64::INFINITY;
        while iterations < budget {
            // Converge the level: smoothed residual below a small fraction of √ε (or the
            // tolerance at the floor).
            let target = if eps <= eps_floor {
                tolerance
            } else {
                (0.01 * eps.sqrt()).max(tolerance)
            };
            let mut converged = false;
            for _ in 0..options.max_iterations {
                let e = self.evaluate(&x, eps, scale, active, true);
                let size = e.residual.amax();
                last = e.plain;
                if eps <= eps_floor && e.plain <= tolerance {
                    return Ok((x, iterations));
                }
                if size <= target {
                    converged = true;
                    break;
                }
                if !e
                    .residual
                    .iter()
                    .chain(e.jacobian.iter())
                    .all(|v| v.is_finite())
                {
                    break;
                }
                iterations += 1;
                let Some(direction) = e.jacobian.clone().lu().solve(&(-&e.residual)) else {
                    break;
                };
                let merit = 0.5 * e.residual.norm_squared();
                let Some((trial, _, _)) =
                    self.armijo(&x, &direction, merit, eps, scale, active, 40)
                else {
                    break;
                };
                x = trial;
            }
            if converged {
                solved_x.clone_from(&x);
                solved_eps = eps;
                if eps <= eps_floor {
                    // Converged at the floor by the smoothed residual: polish with Newton.
                    return self
                        .newton(x, active, scale, tolerance, options, Damping::Plain)
                        .map(|(x, k)| (x, iterations + k))
                        .map_err(|(failure, _)| failure);
                }
                eps = (factor * eps).max(eps_floor);
            } else if solved_eps.is_finite() && factor < 0.66 {
                factor = factor.sqrt();
                x.clone_from(&solved_x);
                eps = (factor * solved_eps).max(eps_floor);
            } else {
                break;
            }
        }
        Err(StepFailure::NotConverged {
            iterations,
            residual: last,
            tolerance,
        })
    }

    /// Newton's method on the smoothed system from x with the contacts marked `active`;
    /// returns the solution and the iterations.
    fn newton(
        &self,
        mut x: Vec<f64>,
        active: &[bool],
        scale: &[f64],
        tolerance: f64,
        options: &StepOptions,
        damping: Damping,
    ) -> Result<(Vec<f64>, usize), (StepFailure, Vec<f64>)> {
        // Smoothing continuation: ε starts at the size of the residual, and falls (by 10, or
        // at once to the residual's size) whenever Newton is on the smoothed path, i.e. its
        // residual is below √(2ε); a failed or tiny line-search step raises it again.
        let eps_floor = (0.01 * tolerance).powi(2);
        let mut current = self.evaluate(&x, 0.0, scale, active, false);
        let mut eps = (0.1 * current.plain).powi(2).max(eps_floor);
        current = self.evaluate(&x, eps, scale, active, false);
        for iteration in 0..=options.max_iterations {
            if current.plain <= tolerance {
                return Ok((x, iteration));
            }
            if iteration == options.max_iterations {
                break;
            }
            if current.residual.amax() <= (2.0 * eps).sqrt() && eps > eps_floor {
                eps = (0.1 * eps)
                    .min((0.1 * current.plain).powi(2))
                    .max(eps_floor);
                current = self.evaluate(&x, eps, scale, active, false);
            }
            let e = self.evaluate(&x, eps, scale, active, true);
            let finite = e
                .residual
                .iter()
                .chain(e.jacobian.iter())
                .all(|v| v.is_finite());
            if !finite {
                return Err((StepFailure::NonFinite { iteration }, x));
            }
            let direction = e
                .jacobian
                .clone()
                .lu()
                .solve(&(-&e.residual))
                .ok_or(StepFailure::Singular { iteration });
            let direction = match direction {
                Ok(d) => d,
                Err(failure) => return Err((failure, x)),
            };
            let merit = 0.5 * e.residual.norm_squared();
            let mut step = self.armijo(&x, &direction, merit, eps, scale, active, 30);
            let mut short = step.as_ref().is_none_or(|(_, t, _)| *t < 1e-2);
            if let (true, Damping::LevenbergMarquardt { momentum }) = (short, damping)
                && let Some(found) =
                    self.levenberg_marquardt(&x, &e, merit, eps, scale, active, momentum)
            {
                short = found.1 < 1e-2;
                step = Some(found);
            }
            if let Some((trial, _, trial_eval)) = step {
                x = trial;
                current = trial_eval;
            }
            if short {
                // Stalled on a nonsmooth valley (or jammed at an impulse's bound): smooth
                // more and go on from here.
                eps = (100.0 * eps).max((0.1 * e.plain).powi(2));
                current = self.evaluate(&x, eps, scale, active, false);
            }
        }
        Err((
            StepFailure::NotConverged {
                iterations: options.max_iterations,
                residual: current.plain,
                tolerance,
            },
            x,
        ))
    }
}
