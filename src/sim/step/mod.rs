//! One forward step with contact: the problem of eq. (32) of the paper, the NLP's own rows
//! solved for (q_{k+1}, λ_k) given the past, by a smoothed Fischer–Burmeister Newton method.
//!
//! Unknowns x = [q_{k+1} (n); per contact (c, β (nd), ψ); loop impulses ν (nl)]. Equations:
//! - the knot's discrete equations (midpoint DEL or Euler residual, `crate::discrete::del`;
//!   a Galerkin member's DEL with the interval's interior points solved inside it,
//!   `crate::discrete::galerkin_interval`)
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
//!
//! Where things are: this file holds the step's data, its active-set rounds and the order in
//! which the solvers are tried (`super::ncp`, one file per strategy); `system` holds the
//! step's equations as the smoothed complementarity system the solvers see.

mod system;

use nalgebra::{DMatrix, DVector};

use self::system::{StepEvaluation, StepSystem};
pub use super::ncp::StepFailure;
use super::ncp::{Damping, Limits, josephy_newton, newton, path_following};
use crate::contact::{ContactModel, distance_with_gradient};
use crate::discrete::{Integrator, Mechanics, MechanicsDerivatives};

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

/// What the knot's equation takes from before the step.
#[derive(Debug, Clone)]
pub enum Before<'a> {
    /// Midpoint and Galerkin: the momentum p_k⁻ arriving at knot k
    /// ([`crate::discrete::arriving_momentum`]; D2Ld(q_{k−1}, q_k) + ½Fd_{k−1} for the
    /// midpoint rule), or M(q_0)v_0 at the first step.
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
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
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
    /// All zero for the sizes of the robot `mech` with the contact model `contact`.
    pub fn zeros<M: Mechanics>(mech: &M, contact: &ContactModel) -> Impulses {
        let contacts = mech.num_contacts();
        Impulses {
            normal: vec![0.0; contacts],
            friction: vec![vec![0.0; contact.nd()]; contacts],
            slip: vec![0.0; contacts],
            loops: vec![0.0; mech.num_loop_constraints()],
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
    /// The contact model (the NLP's).
    pub contact: &'a ContactModel,
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

/// A failed [`ContactStep::attempt`]: the first failure, the first attempt's last iterate,
/// and the Levenberg–Marquardt attempt's last iterate.
struct AttemptFailure {
    failure: StepFailure,
    last: Vec<f64>,
    damped_last: Vec<f64>,
}

impl<M: MechanicsDerivatives> ContactStep<'_, M> {
    /// The solved step at x.
    fn outcome(
        &self,
        x: &[f64],
        e: StepEvaluation,
        iterations: usize,
        tolerance: f64,
    ) -> StepOutcome {
        let (n, nc, nd, stride) = (self.n(), self.nc(), self.contact.nd(), self.stride());
        let mut impulses = Impulses::zeros(self.mech, self.contact);
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
            residual: e.system.plain,
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
        let expected = match self.integrator {
            Integrator::Euler => "Euler",
            Integrator::Midpoint | Integrator::Galerkin4 | Integrator::Galerkin6 => "Momentum",
        };
        let given = match self.before {
            Before::Momentum(_) => "Momentum",
            Before::Euler { .. } => "Euler",
        };
        if given != expected {
            return Err(StepFailure::IntegratorMismatch {
                integrator: self.integrator.name(),
                expected,
            });
        }
        let (n, nc, nd, stride) = (self.n(), self.nc(), self.contact.nd(), self.stride());
        let nl = self.mech.num_loop_constraints();
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
            let (_, grad) = distance_with_gradient(self.mech, self.contact, i, q_guess);
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
                let (phi_guess, _) = distance_with_gradient(self.mech, self.contact, i, q_guess);
                let (phi_curr, _) = distance_with_gradient(self.mech, self.contact, i, self.q_curr);
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
                        if below || e.system.plain > options.acceptable_tolerance * momentum_scale {
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
    /// from far inside ([`path_following`]), which large, strongly nonlinear steps need; the
    /// pivoting Josephy–Newton method ([`josephy_newton`]), which finds the contact mode;
    /// last, Levenberg–Marquardt ([`Damping::LevenbergMarquardt`]). On failure, the first
    /// failure, the first attempt's last iterate and the damped attempt's.
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
        let system = StepSystem {
            step: self,
            active,
            scale,
        };
        let limits = Limits {
            tolerance,
            max_iterations: options.max_iterations,
        };
        let plain = Damping::Plain;
        let (first, last) = match newton(&system, x.to_vec(), limits, plain) {
            Ok(found) => return Ok(found),
            Err(failed) => failed,
        };
        let mut cold = x.to_vec();
        cold[..n].copy_from_slice(self.q_curr);
        cold[n..].iter_mut().for_each(|v| *v = 0.0);
        if let Ok(found) = newton(&system, cold, limits, plain) {
            return Ok(found);
        }
        if let Ok(found) = path_following(&system, x.to_vec(), limits, momentum_scale) {
            return Ok(found);
        }
        if let Ok(found) = josephy_newton(&system, x.to_vec(), limits) {
            return Ok(found);
        }
        // Last: Levenberg–Marquardt steps where Newton's are cut short, from where the first
        // attempt stopped; on failure its last iterate goes back (the caller may accept it at
        // `acceptable_tolerance`).
        let damped = Damping::LevenbergMarquardt {
            momentum: momentum_scale,
        };
        match newton(&system, last.clone(), limits, damped) {
            Ok(found) => Ok(found),
            Err((_, damped_last)) => Err(AttemptFailure {
                failure: first,
                last,
                damped_last,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::Terrain;
    use crate::discrete::{ContactSphere, ModelMechanics, incoming_momentum};
    use crate::model::{BaseType, Model, sample};

    pub(super) const H: f64 = 0.01;
    const G: f64 = 9.81;
    const MU: f64 = 0.5;

    /// The reference brick (1 kg, 0.2 m long, 0.05 m high) on a planar base [x, z, pitch], with
    /// point contacts at its two lower edges (heel and toe), friction `MU`, on flat ground.
    pub(super) fn brick() -> (ModelMechanics, ContactModel) {
        let model = Model::from_urdf_str(sample::brick(), BaseType::Planar).expect("loads");
        let link = model.link_index("brick").expect("has its link");
        let edges = [-0.1, 0.1].map(|x| ContactSphere::point(link, [x, 0.0, -0.025]));
        let mech = ModelMechanics::with_contacts(model, edges.to_vec());
        let contact = ContactModel::new(mech.moves_in_xz_plane(), vec![MU; 2], Terrain::flat());
        (mech, contact)
    }

    /// One midpoint step of the brick lying on the ground and moving along x at `speed`
    /// (q_{k−1} = (−h·speed, 0.025, 0), q_k = (0, 0.025, 0)), from the extrapolated guess.
    fn step_at_speed(speed: f64) -> StepOutcome {
        let (mech, contact) = brick();
        let q_prev = [-H * speed, 0.025, 0.0];
        let q_curr = [0.0, 0.025, 0.0];
        let u = StepInput::from(vec![0.0; mech.nu()]);
        let step = ContactStep {
            mech: &mech,
            contact: &contact,
            integrator: Integrator::Midpoint,
            before: Before::Momentum(incoming_momentum(&mech, &q_prev, &q_curr, &u.held, H)),
            q_curr: &q_curr,
            u: &u,
            h: H,
        };
        let guess = [H * speed, 0.025, 0.0];
        let warm = Impulses::zeros(&mech, &contact);
        step.solve(&guess, &warm, &StepOptions::default())
            .expect("solves")
    }

    /// A step whose `before` does not match its integrator is an error naming the pairing,
    /// not a panic: Euler given a momentum, the midpoint rule given Euler's velocity.
    #[test]
    fn a_mismatched_integrator_and_before_is_an_error() {
        let (mech, contact) = brick();
        let q = [0.0, 0.025, 0.0];
        let u = StepInput::from(vec![0.0; mech.nu()]);
        let momentum = incoming_momentum(&mech, &q, &q, &u.held, H);
        let v = [0.0; 3];
        for (integrator, before, expected) in [
            (Integrator::Euler, Before::Momentum(momentum), "Euler"),
            (
                Integrator::Midpoint,
                Before::Euler {
                    before: &v,
                    first_step: true,
                    h_prev: H,
                },
                "Momentum",
            ),
        ] {
            let step = ContactStep {
                mech: &mech,
                contact: &contact,
                integrator,
                before,
                q_curr: &q,
                u: &u,
                h: H,
            };
            let warm = Impulses::zeros(&mech, &contact);
            let err = step
                .solve(&q, &warm, &StepOptions::default())
                .expect_err("a mismatch is refused");
            assert!(
                matches!(err, StepFailure::IntegratorMismatch { expected: e, .. } if e == expected),
                "{err}"
            );
            assert!(err.to_string().contains(integrator.name()), "{err}");
        }
    }

    #[test]
    fn a_brick_at_rest_on_the_ground_stays_there_on_its_weight() {
        let s = step_at_speed(0.0);
        for (a, b) in s.q_next.iter().zip([0.0, 0.025, 0.0]) {
            assert!((a - b).abs() < 1e-12, "{:?}", s.q_next);
        }
        // The ground carries the weight over the step, m g h, shared by the two edges.
        let normal: f64 = s.impulses.normal.iter().sum();
        assert!((normal - G * H).abs() < 1e-9 * G * H, "{normal}");
        assert!((s.impulses.normal[0] - s.impulses.normal[1]).abs() < 1e-9 * G * H);
        // No net friction (the split between the two edges is not determined: they may
        // squeeze the brick between them).
        let net: f64 = s.impulses.friction.iter().map(|b| b[0] - b[1]).sum();
        assert!(net.abs() < 1e-9 * G * H, "{net}");
        assert!(s.residual <= s.tolerance);
    }

    #[test]
    fn a_sliding_brick_slows_by_coulomb_friction() {
        let speed = 1.0;
        let s = step_at_speed(speed);
        // m v_{k+1} = m v_k − μ Σc with Σc = m g h: the speed falls by μ g h.
        let v_next = s.q_next[0] / H;
        assert!((v_next - (speed - MU * G * H)).abs() < 1e-8, "{v_next}");
        assert!((s.q_next[1] - 0.025).abs() < 1e-12 && s.q_next[2].abs() < 1e-12);
        let normal: f64 = s.impulses.normal.iter().sum();
        assert!((normal - G * H).abs() < 1e-9 * G * H, "{normal}");
        // Friction against the motion (β⁻, the second direction) at the cone's edge; the
        // toe carries more than the heel against friction's pitching moment.
        let backward: f64 = s.impulses.friction.iter().map(|b| b[1] - b[0]).sum();
        assert!((backward - MU * G * H).abs() < 1e-9, "{backward}");
        assert!(s.impulses.normal[1] > s.impulses.normal[0]);
        assert!(
            (s.impulses.slip[0] - v_next).abs() < 1e-8,
            "{:?}",
            s.impulses.slip
        );
    }
}
