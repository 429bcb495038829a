//! Exact sparse derivatives against central differences, over every block type.
//!
//! For each problem variant, at seeded random points: every Jacobian entry agrees with the
//! central difference of the constraint residuals, and every lower-triangle Hessian entry of
//! the Lagrangian σf + λᵀg with the central difference of its gradient σ∇f + Jᵀλ (whose
//! Jacobian part is checked first), to 1e-6 relative; and no finite-difference entry that is
//! nonzero falls outside the declared pattern.
//!
//! Variants cover: midpoint and Euler mechanics, fixed and free equal steps, per-interval
//! and per-contact slacks, every cost term, periodicity of position and velocity, a
//! smoothed step in the terrain, a loop closure (with its impulses in the DEL rows), and
//! rolling sphere contacts (friction at the lowest material point: spin rows by generic AD).

use crate::common;

use common::analytic::{Brick, Hopper};
use common::reference::{brick_3d, hopper_2d, littledog_step, spring_flamingo_walk};
use vito::autodiff::Scalar;
use vito::autodiff::finite_differences::{central, moved};
use vito::contact::Step;
use vito::discrete::{Mechanics, MechanicsDerivatives, ModelMechanics};
use vito::problem::constraints::{Periodic, PeriodicMomentum};
use vito::problem::costs::{
    ConfigurationDifference, CostSizes, FinalState, FinalVelocity, ImpulseRate, Input, InputRate,
    StateTracking, Time, VelocityDifference, cost_value,
};
use vito::problem::{
    Constraint, CostTerm, Integrator, Interval, ProblemSpec, SlackMode, TimeSteps,
};
use vito::random::SeededRng;
use vito::transcription::Transcription;

/// Any mechanics plus one made-up smooth loop closure, so loop blocks are exercised.
struct WithLoop<M>(M);
impl<M: Mechanics> Mechanics for WithLoop<M> {
    fn nq(&self) -> usize {
        self.0.nq()
    }
    fn nu(&self) -> usize {
        self.0.nu()
    }
    fn num_loop_constraints(&self) -> usize {
        1
    }
    fn num_contacts(&self) -> usize {
        self.0.num_contacts()
    }
    fn has_discrete_force(&self) -> bool {
        self.0.has_discrete_force()
    }
    fn moves_in_xz_plane(&self) -> bool {
        self.0.moves_in_xz_plane()
    }
    fn discrete_lagrangian<D: Scalar>(&self, qa: &[D], qb: &[D], h: D) -> D {
        self.0.discrete_lagrangian(qa, qb, h)
    }
    fn discrete_force<D: Scalar>(&self, qa: &[D], qb: &[D], u: &[D], h: D, out: &mut [D]) {
        self.0.discrete_force(qa, qb, u, h, out)
    }
    fn euler_residual<D: Scalar>(
        &self,
        v_k: &[D],
        q_k: &[D],
        q_next: &[D],
        h: D,
        u: &[D],
        out: &mut [D],
    ) {
        self.0.euler_residual(v_k, q_k, q_next, h, u, out)
    }
    fn momentum<D: Scalar>(&self, q: &[D], v: &[D], out: &mut [D]) {
        self.0.momentum(q, v, out)
    }
    fn contact_position<D: Scalar>(&self, c: usize, q: &[D]) -> [D; 3] {
        self.0.contact_position(c, q)
    }
    fn loop_residual<D: Scalar>(&self, q: &[D], out: &mut [D]) {
        out[0] = q[0].sin() * q[1] + q[3] * q[3] - D::from(0.25);
    }
}

impl<M: MechanicsDerivatives> MechanicsDerivatives for WithLoop<M> {}

/// The hopper with every optional feature switched on and a short horizon.
fn hopper_everything(integrator: Integrator, slack_mode: SlackMode) -> ProblemSpec {
    let mut spec = hopper_2d();
    spec.knots = 5;
    spec.integrator = integrator;
    spec.slack_mode = slack_mode;
    spec.time_steps = TimeSteps::FreeEqual {
        t_min: 0.1,
        t_max: 0.4,
    };
    spec.terrain.steps.push(Step::along_x(0.2, 0.05, 0.05));
    spec.q_final = vec![Interval::FREE; 4];
    spec.costs.push(CostTerm::StateTracking(StateTracking {
        q_target: vec![0.5, 0.5, 0.1, 0.5],
        v_target: vec![0.3, 0.0, 0.0, 0.1],
        q_weights: vec![1.0, 2.0, 0.5, 1.0],
        v_weights: vec![0.5, 1.0, 0.2, 0.3],
        time_weighted: false,
    }));
    spec.costs.push(CostTerm::Input(Input {
        weights: vec![0.3, 0.2],
        time_weighted: false,
    }));
    spec.costs.push(CostTerm::InputRate(InputRate {
        weights: vec![1.0, 0.5],
    }));
    spec.costs
        .push(CostTerm::ConfigurationDifference(ConfigurationDifference {
            weights: vec![1.0, 0.5, 2.0, 1.0],
        }));
    spec.costs.push(CostTerm::FinalState(FinalState {
        q_target: vec![0.5, 0.6, 0.0, 0.5],
        weights: vec![3.0, 1.0, 1.0, 2.0],
    }));
    spec.costs.push(CostTerm::FinalVelocity(FinalVelocity {
        v_target: vec![0.4, -0.2, 0.0, 0.1],
        weights: vec![1.5, 0.5, 2.0, 0.0],
    }));
    spec.costs.push(CostTerm::Time(Time { weight: 2.0 }));
    spec.costs
        .push(CostTerm::VelocityDifference(VelocityDifference {
            weights: vec![0.5, 1.0, 2.0, 0.3],
        }));
    spec.costs
        .push(CostTerm::ImpulseRate(ImpulseRate { weights: vec![0.7] }));
    spec.constraints = vec![
        Constraint::Periodic(Periodic {
            coordinate: 1,
            name: "z".into(),
            offset: Some(0.1),
            velocity: true,
        }),
        Constraint::Periodic(Periodic {
            coordinate: 3,
            name: "r".into(),
            offset: None,
            velocity: true,
        }),
    ];
    // The momentum arriving at q_N is the variational integrators' DLT; Euler refuses it
    // (below).
    if integrator != Integrator::Euler {
        spec.constraints
            .push(Constraint::PeriodicMomentum(PeriodicMomentum {
                names: ["x", "z", "theta", "r"].map(String::from).to_vec(),
            }));
    }
    spec
}

/// A random point: configurations near the guess, positive steps, contact variables in
/// [0, 1]; plus random multipliers and objective factor.
fn random_point<M: MechanicsDerivatives>(
    t: &Transcription<M>,
    rng: &mut SeededRng,
) -> (Vec<f64>, Vec<f64>, f64) {
    let l = t.layout();
    let mut x: Vec<f64> = t
        .initial_point()
        .iter()
        .map(|&v| v + rng.range(-0.2, 0.2))
        .collect();
    for j in 0..l.intervals() {
        x[l.h(j)] = rng.range(0.03, 0.08);
        for i in l.contact_vars(j) {
            x[i] = rng.range(0.0, 1.0);
        }
    }
    let lambda = (0..l.num_constraints())
        .map(|_| rng.range(-1.0, 1.0))
        .collect();
    (x, lambda, rng.range(0.5, 2.0))
}

fn dense_jacobian<M: MechanicsDerivatives>(t: &Transcription<M>, x: &[f64]) -> Vec<Vec<f64>> {
    let p = t.jacobian_pattern();
    let mut values = vec![0.0; p.nnz()];
    t.jacobian_values(x, &mut values);
    let mut j = vec![vec![0.0; x.len()]; t.layout().num_constraints()];
    for k in 0..p.nnz() {
        j[p.rows[k]][p.cols[k]] += values[k];
    }
    j
}

fn lagrangian_gradient<M: MechanicsDerivatives>(
    t: &Transcription<M>,
    x: &[f64],
    lambda: &[f64],
    sigma: f64,
) -> Vec<f64> {
    let mut grad = vec![0.0; x.len()];
    t.gradient(x, &mut grad);
    for g in grad.iter_mut() {
        *g *= sigma;
    }
    let j = dense_jacobian(t, x);
    for (row, &l) in j.iter().zip(lambda) {
        for (g, &jv) in grad.iter_mut().zip(row) {
            *g += l * jv;
        }
    }
    grad
}

fn agree(exact: f64, fd: f64, tol: f64) -> bool {
    (exact - fd).abs() <= tol * exact.abs().max(1.0)
}

fn check_derivatives<M: MechanicsDerivatives>(name: &str, t: &Transcription<M>, seed: u64) {
    let mut rng = SeededRng::new(seed);
    let (x, lambda, sigma) = random_point(t, &mut rng);
    let nv = x.len();
    let nr = t.layout().num_constraints();
    let eps = 1e-6;
    let tol = 1e-6;

    // Objective gradient against central differences of the objective.
    let objective = t.objective(&x);
    let mut grad = vec![0.0; nv];
    t.gradient(&x, &mut grad);
    let jac = dense_jacobian(t, &x);
    let mut declared = vec![vec![false; nv]; nr];
    let p = t.jacobian_pattern();
    for k in 0..p.nnz() {
        declared[p.rows[k]][p.cols[k]] = true;
    }
    let (mut worst_j, mut checked) = (0.0_f64, 0);
    for i in 0..nv {
        let fd_f = central(|d| t.objective(&moved(&x, i, d)), eps);
        // Central differences of f carry its rounding, about ε·|f|/eps.
        let rounding = 4.0 * f64::EPSILON * objective.abs() / eps;
        assert!(
            (grad[i] - fd_f).abs() <= tol * grad[i].abs().max(1.0) + rounding,
            "{name}: ∂f/∂x[{i}] exact {} fd {fd_f}",
            grad[i]
        );
        let fd_g = central(
            |d| {
                let mut g = vec![0.0; nr];
                t.constraints(&moved(&x, i, d), &mut g);
                g
            },
            eps,
        );
        for r in 0..nr {
            let fd = fd_g[r];
            if !declared[r][i] {
                assert!(
                    fd.abs() < 1e-8,
                    "{name}: ∂g[{r}]/∂x[{i}] = {fd} lies outside the Jacobian pattern"
                );
                continue;
            }
            checked += 1;
            let err = (jac[r][i] - fd).abs() / jac[r][i].abs().max(1.0);
            worst_j = worst_j.max(err);
            assert!(
                agree(jac[r][i], fd, tol),
                "{name}: ∂g[{r}]/∂x[{i}] exact {} fd {fd}",
                jac[r][i]
            );
        }
    }

    // Lagrangian Hessian against central differences of the Lagrangian gradient.
    let hp = t.hessian_pattern();
    let mut hv = vec![0.0; hp.nnz()];
    t.hessian_values(&x, sigma, &lambda, &mut hv);
    let mut hess = vec![vec![0.0; nv]; nv];
    let mut hdecl = vec![vec![false; nv]; nv];
    for k in 0..hp.nnz() {
        assert!(
            hp.rows[k] >= hp.cols[k],
            "{name}: Hessian entry above the diagonal"
        );
        hess[hp.rows[k]][hp.cols[k]] += hv[k];
        hdecl[hp.rows[k]][hp.cols[k]] = true;
    }
    // Central differences of ∇L carry its rounding, about ε·|∇L|/eps.
    let gradient_scale = lagrangian_gradient(t, &x, &lambda, sigma)
        .iter()
        .fold(0.0_f64, |m, g| m.max(g.abs()));
    let rounding = 4.0 * f64::EPSILON * gradient_scale / eps;
    let mut worst_h = 0.0_f64;
    for i in 0..nv {
        let fd_l = central(
            |d| lagrangian_gradient(t, &moved(&x, i, d), &lambda, sigma),
            eps,
        );
        for r in i..nv {
            let fd = fd_l[r];
            if !hdecl[r][i] {
                assert!(
                    fd.abs() < 1e-7,
                    "{name}: ∂²L/∂x[{r}]∂x[{i}] = {fd} lies outside the Hessian pattern"
                );
                continue;
            }
            let err = (hess[r][i] - fd).abs() / hess[r][i].abs().max(1.0);
            worst_h = worst_h.max(err);
            assert!(
                (hess[r][i] - fd).abs() <= tol * hess[r][i].abs().max(1.0) + rounding,
                "{name}: ∂²L/∂x[{r}]∂x[{i}] exact {} fd {fd} (rounding {rounding:.1e})",
                hess[r][i]
            );
        }
    }
    println!(
        "{name}: {nv} variables, {nr} rows, J nnz {} ({checked} checked, worst rel err {worst_j:.1e}), \
         H nnz {} (worst rel err {worst_h:.1e})",
        p.nnz(),
        hp.nnz()
    );
}

#[test]
fn hopper_midpoint_every_feature() {
    let spec = hopper_everything(Integrator::Midpoint, SlackMode::PerInterval);
    let t = Transcription::new(Hopper, &spec).unwrap();
    check_derivatives("hopper midpoint per-interval", &t, 1);
}

/// The Galerkin members (interior points as variables, their stationarity rows, φ ≥ 0 at
/// them, the end momentum into `periodic_momentum`) with every other feature, both slack
/// modes, and with a loop closure.
#[test]
fn hopper_galerkin_every_feature() {
    for (seed, integrator, mode) in [
        (21, Integrator::Galerkin4, SlackMode::PerInterval),
        (22, Integrator::Galerkin6, SlackMode::PerContact),
    ] {
        let spec = hopper_everything(integrator, mode);
        let t = Transcription::new(Hopper, &spec).unwrap();
        check_derivatives(&format!("hopper {integrator:?} {mode:?}"), &t, seed);
    }
    let spec = hopper_everything(Integrator::Galerkin4, SlackMode::PerInterval);
    let t = Transcription::new(WithLoop(Hopper), &spec).unwrap();
    check_derivatives("hopper galerkin4 loop", &t, 23);
}

#[test]
fn hopper_euler_per_interval_slack() {
    let mut spec = hopper_everything(Integrator::Euler, SlackMode::PerInterval);
    let t = Transcription::new(Hopper, &spec).unwrap();
    check_derivatives("hopper euler per-interval", &t, 8);
    spec.constraints
        .push(Constraint::PeriodicMomentum(PeriodicMomentum {
            names: ["x", "z", "theta", "r"].map(String::from).to_vec(),
        }));
    let Err(e) = Transcription::new(Hopper, &spec) else {
        panic!("Euler with periodic_momentum was accepted")
    };
    assert!(e.to_string().contains("midpoint"), "{e}");
}

#[test]
fn hopper_euler_per_contact_slack_with_loop() {
    let spec = hopper_everything(Integrator::Euler, SlackMode::PerContact);
    let t = Transcription::new(WithLoop(Hopper), &spec).unwrap();
    check_derivatives("hopper euler per-contact loop", &t, 2);
}

#[test]
fn brick_short_horizon_both_slack_modes_and_integrators() {
    for (seed, mode, integrator) in [
        (3, SlackMode::PerInterval, Integrator::Midpoint),
        (4, SlackMode::PerContact, Integrator::Midpoint),
        (6, SlackMode::PerInterval, Integrator::Euler),
        (24, SlackMode::PerContact, Integrator::Galerkin4),
    ] {
        let mut spec = brick_3d();
        spec.knots = 3;
        spec.costs.push(CostTerm::ImpulseRate(ImpulseRate {
            weights: (0..8).map(|i| 0.25 * i as f64).collect(),
        }));
        spec.slack_mode = mode;
        spec.integrator = integrator;
        spec.terrain.steps.push(Step::along_x(0.05, 0.02, 0.1));
        let t = Transcription::new(Brick, &spec).unwrap();
        check_derivatives(&format!("brick {mode:?} {integrator:?}"), &t, seed);
    }
}

/// Spring Flamingo from URDF (damping in Fd, springs in V, joint limits, free steps), with
/// the midpoint rule, Euler (through the model's inverse dynamics) and galerkin4 (the
/// discrete forces at its interior point).
#[test]
fn spring_flamingo_from_urdf_short_horizon() {
    for (seed, integrator) in [
        (5, Integrator::Midpoint),
        (7, Integrator::Euler),
        (25, Integrator::Galerkin4),
    ] {
        let mut spec = spring_flamingo_walk();
        spec.knots = 3;
        spec.q_final = vec![Interval::FREE; 9];
        spec.integrator = integrator;
        spec.costs.push(CostTerm::ImpulseRate(ImpulseRate {
            weights: vec![0.5, 1.0, 2.0, 0.0],
        }));
        let t = Transcription::new(ModelMechanics::load(&spec).unwrap(), &spec).unwrap();
        check_derivatives(&format!("spring flamingo (URDF) {integrator:?}"), &t, seed);
    }
}

/// Sphere contacts of radius > 0 roll: their friction directions add the spin columns
/// (no gradient of a potential), in the SpinFriction rows and the tangential rates. On a
/// floating brick whose corners are balls, on the planar Spring Flamingo with ball feet
/// (the spin from base pitch and three joints), and on LittleDog's 3-D legs, both integrators.
#[test]
fn rolling_sphere_contacts_have_exact_derivatives() {
    let with_radius = |mut spec: ProblemSpec, r: f64| {
        spec.knots = 3;
        for c in &mut spec.contacts {
            c.radius = r;
        }
        spec
    };
    // On flat ground: a sphere's contact point is taken straight below its centre, so
    // validation keeps spheres off any other terrain.
    let brick = with_radius(brick_3d(), 0.01);
    let mut flamingo = with_radius(spring_flamingo_walk(), 0.02);
    flamingo.q_final = vec![Interval::FREE; 9];
    let mut dog = with_radius(littledog_step(), 0.0175);
    dog.q_final = vec![Interval::FREE; dog.q_initial.len()];
    dog.terrain = vito::contact::Terrain::flat();
    for (seed, spec, integrator) in [
        (11, brick.clone(), Integrator::Midpoint),
        (12, brick, Integrator::Euler),
        (13, flamingo, Integrator::Midpoint),
        (14, dog, Integrator::Euler),
    ] {
        let mut spec = spec;
        spec.integrator = integrator;
        let mech = ModelMechanics::load(&spec).unwrap();
        assert!((0..mech.num_contacts()).all(|i| mech.contact_rolls(i)));
        let t = Transcription::new(mech, &spec).unwrap();
        check_derivatives(&format!("rolling {} {integrator:?}", spec.name), &t, seed);
    }
}

/// With fixed variables skipped (what the solve does), the Lagrangian Hessian is unchanged on
/// every pair of free variables and zero on pairs with a fixed one (Ipopt drops those).
#[test]
fn skipping_fixed_variables_keeps_every_free_entry() {
    let spec = hopper_everything(Integrator::Midpoint, SlackMode::PerInterval);
    let mut t = Transcription::new(Hopper, &spec).unwrap();
    let (lo, hi) = t.variable_bounds();
    let fixed: Vec<bool> = lo.iter().zip(hi).map(|(a, b)| a == b).collect();
    assert!(
        fixed.iter().filter(|&&f| f).count() >= 4,
        "the test needs fixed variables"
    );
    let x = t.initial_point().to_vec();
    let lambda: Vec<f64> = (0..t.layout().num_constraints())
        .map(|r| 0.5 + (r as f64 * 0.37).sin())
        .collect();
    let nnz = t.hessian_pattern().nnz();
    let (mut full, mut skipped) = (vec![0.0; nnz], vec![0.0; nnz]);
    t.hessian_values(&x, 0.7, &lambda, &mut full);
    t.set_skip_fixed_variables(true);
    t.hessian_values(&x, 0.7, &lambda, &mut skipped);
    let p = t.hessian_pattern();
    let mut compared = 0;
    for k in 0..nnz {
        let (r, c) = (p.rows[k], p.cols[k]);
        if fixed[r] || fixed[c] {
            continue;
        }
        compared += 1;
        assert!(
            (full[k] - skipped[k]).abs() <= 1e-12 * full[k].abs().max(1.0),
            "entry ({r}, {c}): {} vs {}",
            full[k],
            skipped[k]
        );
    }
    assert!(compared > nnz / 2, "{compared} of {nnz} entries compared");
    assert_ne!(
        full, skipped,
        "skipping changed nothing: the test proves nothing"
    );
}

/// The Jacobian and Hessian blocks (and the contact geometries they share) on rayon's pool
/// (`set_parallel(true)`, the default from `PARALLEL_FROM_JACOBIAN_NNZ` nonzeros) and on one
/// thread give the same bits: results are collected in block order and scattered serially
/// either way.
#[test]
fn parallel_and_serial_evaluation_agree_to_the_bit() {
    let spec = brick_3d();
    let mut t = Transcription::new(Brick, &spec).unwrap();
    let (x, lambda, sigma) = random_point(&t, &mut SeededRng::new(16));
    let evaluate = |t: &Transcription<Brick>| {
        let mut jac = vec![0.0; t.jacobian_pattern().nnz()];
        let mut hess = vec![0.0; t.hessian_pattern().nnz()];
        let mut g = vec![0.0; t.layout().num_constraints()];
        t.jacobian_values(&x, &mut jac);
        t.hessian_values(&x, sigma, &lambda, &mut hess);
        t.constraints(&x, &mut g);
        (jac, hess, g)
    };
    t.set_parallel(true);
    let parallel = evaluate(&t);
    t.set_parallel(false);
    let serial = evaluate(&t);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&parallel.0), bits(&serial.0), "Jacobian");
    assert_eq!(bits(&parallel.1), bits(&serial.1), "Hessian");
    assert_eq!(bits(&parallel.2), bits(&serial.2), "constraints");
    assert!(parallel.1.iter().any(|&v| v != 0.0));
}

/// `final_velocity` on z = [q_{N−1}; q_N; h_{N−1}]: ½ Σ w_i ((q_N − q_{N−1})_i / h − v_i)², by
/// hand; and placed on the last interval of a transcription, where its term in the objective
/// is the same formula on the solver's variables.
#[test]
fn final_velocity_value_matches_hand_computation() {
    let term = CostTerm::FinalVelocity(FinalVelocity {
        v_target: vec![1.0, 0.0, 0.5, 0.0],
        weights: vec![1.0, 2.0, 4.0, 0.0],
    });
    let sizes = CostSizes { n: 4, m: 2, nc: 1 };
    // v = ([0.1, 0.2, 0.0, 0.3] − [0, 0, 0.05, 0]) / 0.05 = [2, 4, −1, 6]:
    // ½ (1·(2 − 1)² + 2·4² + 4·(−1 − 0.5)² + 0·6²) = ½ (1 + 32 + 9) = 21.
    let z: [f64; 9] = [0.0, 0.0, 0.05, 0.0, 0.1, 0.2, 0.0, 0.3, 0.05];
    assert!((cost_value(&term, sizes, &z) - 21.0).abs() < 1e-12);

    let mut spec = hopper_everything(Integrator::Midpoint, SlackMode::PerInterval);
    spec.costs = vec![term];
    let t = Transcription::new(Hopper, &spec).unwrap();
    let (x, _, _) = random_point(&t, &mut SeededRng::new(21));
    let l = t.layout();
    let last = l.intervals() - 1;
    let (before, after, h) = (l.q(last), l.q(last + 1), x[l.h(last)]);
    let hand: f64 = [(1.0, 1.0), (2.0, 0.0), (4.0, 0.5), (0.0, 0.0)]
        .iter()
        .enumerate()
        .map(|(c, &(w, target))| {
            let v = (x[after.start + c] - x[before.start + c]) / h;
            0.5 * w * (v - target) * (v - target)
        })
        .sum();
    assert!(hand > 0.1, "the point tests nothing: {hand}");
    assert_term_value(&t, &x, "final_velocity", hand);
}

/// The term `name` of `t`'s objective at x equals `hand` to 1e-12 (relative).
fn assert_term_value<M: MechanicsDerivatives>(
    t: &Transcription<M>,
    x: &[f64],
    name: &str,
    hand: f64,
) {
    let terms = t.objective_terms(x);
    let Some((_, value)) = terms.iter().find(|(n, _)| n == name) else {
        panic!("{name} not in objective_terms: {terms:?}")
    };
    assert!(
        (value - hand).abs() <= 1e-12 * hand.abs(),
        "{name}: {value} vs {hand}"
    );
}

/// `impulse_rate` on z = [c_{k−1}; c_k]: ½ Σ_i w_i (c_{k,i} − c_{k−1,i})², by hand; placed on
/// the brick's eight contacts over every pair of adjacent intervals, its term in the objective
/// is that sum over the solver's impulses, and its objective Hessian is the constant
/// second-difference matrix: w_i on (c_{k,i}, c_{k,i}) at the first and last interval, 2 w_i
/// between, −w_i on (c_{k+1,i}, c_{k,i}), at two different points.
#[test]
fn impulse_rate_value_and_hessian_match_hand_computation() {
    let term = CostTerm::ImpulseRate(ImpulseRate {
        weights: vec![2.0, 0.5],
    });
    let sizes = CostSizes { n: 4, m: 2, nc: 2 };
    // ½ (2·(0.3 − 0.1)² + 0.5·(0 − 0.4)²) = ½ (0.08 + 0.08) = 0.08.
    let z: [f64; 4] = [0.1, 0.4, 0.3, 0.0];
    assert!((cost_value(&term, sizes, &z) - 0.08).abs() < 1e-15);

    let weights: Vec<f64> = (0..8).map(|i| 0.5 + 0.25 * i as f64).collect();
    let mut spec = brick_3d();
    spec.knots = 6;
    spec.costs = vec![CostTerm::ImpulseRate(ImpulseRate {
        weights: weights.clone(),
    })];
    let t = Transcription::new(Brick, &spec).unwrap();
    let l = t.layout();
    let intervals = l.intervals();
    let p = t.hessian_pattern();
    let lambda = vec![0.0; l.num_constraints()];
    for seed in [41, 42] {
        let (x, _, _) = random_point(&t, &mut SeededRng::new(seed));
        let hand: f64 = (1..intervals)
            .flat_map(|k| (0..8).map(move |i| (k, i)))
            .map(|(k, i)| {
                let d = x[l.c(k, i)] - x[l.c(k - 1, i)];
                0.5 * weights[i] * d * d
            })
            .sum();
        assert!(hand > 1e-3, "the point tests nothing: {hand}");
        assert_term_value(&t, &x, "impulse_rate", hand);

        let mut values = vec![0.0; p.nnz()];
        t.hessian_values(&x, 1.0, &lambda, &mut values);
        let at = |r: usize, c: usize| {
            let (r, c) = (r.max(c), r.min(c));
            (0..p.nnz())
                .filter(|&k| p.rows[k] == r && p.cols[k] == c)
                .map(|k| values[k])
                .sum::<f64>()
        };
        for (i, &w) in weights.iter().enumerate() {
            for k in 0..intervals {
                let pairs = if k == 0 || k + 1 == intervals {
                    1.0
                } else {
                    2.0
                };
                let (diagonal, expected) = (at(l.c(k, i), l.c(k, i)), pairs * w);
                assert!(
                    (diagonal - expected).abs() < 1e-12,
                    "c[{k},{i}]: {diagonal}"
                );
                if k + 1 < intervals {
                    let off = at(l.c(k + 1, i), l.c(k, i));
                    assert!((off + w).abs() < 1e-12, "c[{k},{i}] off-diagonal: {off}");
                }
            }
            // No coupling between contacts or with the friction impulses.
            let other = l.c(1, (i + 1) % 8);
            assert_eq!(at(l.c(1, i), other), 0.0);
            assert_eq!(at(l.c(1, i), l.beta(1, i).start), 0.0);
        }
    }
}

/// The Hessian pattern holds the term's step–configuration entries from its inputs, not from
/// values: at a point that stands still (q_N = q_{N−1}) those entries of the objective's Hessian
/// are exactly zero, yet declared; moved, they equal the hand-computed
/// ∂²f/∂q_N∂h = −2wΔ/h³, ∂²f/∂q_{N−1}∂h = 2wΔ/h³, ∂²f/∂h² = 3Σ wΔ²/h⁴, ∂²f/∂q_N² = w/h².
#[test]
fn final_velocity_hessian_pattern_comes_from_its_inputs() {
    let weights = vec![1.0, 2.0, 0.5, 3.0];
    let mut spec = hopper_everything(Integrator::Midpoint, SlackMode::PerInterval);
    spec.costs = vec![CostTerm::FinalVelocity(FinalVelocity {
        v_target: vec![0.0; 4],
        weights: weights.clone(),
    })];
    let t = Transcription::new(Hopper, &spec).unwrap();
    let l = t.layout();
    let last = l.intervals() - 1;
    let (before, after, hv) = (l.q(last), l.q(last + 1), l.h(last));
    let p = t.hessian_pattern();
    let entry = |r: usize, c: usize| {
        let (r, c) = (r.max(c), r.min(c));
        (0..p.nnz()).filter(move |&k| p.rows[k] == r && p.cols[k] == c)
    };
    let objective_hessian = |x: &[f64]| {
        let mut values = vec![0.0; p.nnz()];
        let lambda = vec![0.0; l.num_constraints()];
        t.hessian_values(x, 1.0, &lambda, &mut values);
        move |r: usize, c: usize| entry(r, c).map(|k| values[k]).sum::<f64>()
    };

    let mut still = t.initial_point().to_vec();
    still.copy_within(before.clone(), after.start);
    let at_still = objective_hessian(&still);
    for c in 0..4 {
        for var in [before.start + c, after.start + c] {
            assert_eq!(entry(hv, var).count(), 1, "(h, q[{var}]) not declared");
            assert_eq!(at_still(hv, var), 0.0);
        }
    }
    assert_eq!(at_still(hv, hv), 0.0);

    let mut moved = still.clone();
    let h = moved[hv];
    let deltas = [0.03, -0.02, 0.05, 0.01];
    for (c, d) in deltas.iter().enumerate() {
        moved[after.start + c] += d;
    }
    let at_moved = objective_hessian(&moved);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-10 * b.abs().max(1.0);
    let mut hh = 0.0;
    for c in 0..4 {
        let (w, d) = (weights[c], deltas[c]);
        let (qa, qb) = (before.start + c, after.start + c);
        assert!(close(at_moved(hv, qb), -2.0 * w * d / h.powi(3)), "c {c}");
        assert!(close(at_moved(hv, qa), 2.0 * w * d / h.powi(3)), "c {c}");
        assert!(close(at_moved(qb, qb), w / (h * h)), "c {c}");
        assert!(close(at_moved(qb, qa), -w / (h * h)), "c {c}");
        hh += 3.0 * w * d * d / h.powi(4);
    }
    assert!(close(at_moved(hv, hv), hh));
}

/// `contacts.mode_block`: the complementarity rows of each interval read the impulses,
/// cones and distances of its whole contact-mode block. Blocks of 2 over 5 intervals and of
/// 3 over 4 (each with a shorter last block), both slack modes, the midpoint rule and
/// galerkin4 on the hopper; blocks of 2 over 3 intervals on the brick (eight contacts).
#[test]
fn contact_mode_blocks_have_exact_derivatives() {
    for (seed, m, knots, integrator, mode) in [
        (31, 2, 6, Integrator::Midpoint, SlackMode::PerInterval),
        (32, 2, 6, Integrator::Galerkin4, SlackMode::PerContact),
        (33, 3, 5, Integrator::Midpoint, SlackMode::PerContact),
        (34, 3, 5, Integrator::Galerkin4, SlackMode::PerInterval),
    ] {
        let mut spec = hopper_everything(integrator, mode);
        spec.knots = knots;
        spec.mode_block = m;
        let t = Transcription::new(Hopper, &spec).unwrap();
        check_derivatives(
            &format!("hopper blocks of {m} {integrator:?} {mode:?}"),
            &t,
            seed,
        );
    }
    for (seed, mode) in [(35, SlackMode::PerInterval), (36, SlackMode::PerContact)] {
        let mut spec = brick_3d();
        spec.knots = 4;
        spec.slack_mode = mode;
        spec.mode_block = 2;
        let t = Transcription::new(Brick, &spec).unwrap();
        check_derivatives(&format!("brick blocks of 2 {mode:?}"), &t, seed);
    }
}

/// Blocks of 2 add to interval j's rows exactly the partners' terms: at a point, the
/// complementarity rows of the blocked NLP are those of the per-interval NLP plus the
/// cross terms, computed here by hand from the variables.
#[test]
fn contact_mode_block_rows_pair_each_interval_with_its_block() {
    let mut spec = hopper_2d();
    spec.knots = 6;
    let one = Transcription::new(Hopper, &spec).unwrap();
    spec.mode_block = 2;
    let two = Transcription::new(Hopper, &spec).unwrap();
    let l = one.layout();
    let mut rng = SeededRng::new(37);
    let (x, _, _) = random_point(&one, &mut rng);
    let (mut g1, mut g2) = (
        vec![0.0; l.num_constraints()],
        vec![0.0; l.num_constraints()],
    );
    one.constraints(&x, &mut g1);
    two.constraints(&x, &mut g2);
    let mu = spec.contacts[0].friction;
    let foot_z = |k: usize| Hopper.contact_position(0, &x[l.q(k)])[2];
    let beta = |j: usize| l.beta(j, 0).map(|i| x[i]).collect::<Vec<_>>();
    let cone = |j: usize| mu * x[l.c(j, 0)] - beta(j).iter().sum::<f64>();
    let blocks = [0..2, 0..2, 2..4, 2..4, 4..5];
    for (j, block) in blocks.iter().enumerate() {
        let rows = l.rows_of("Complementarity", j);
        let eta: Vec<f64> = l.eta(j, 0).map(|i| x[i]).collect();
        for k in block.clone().filter(|&k| k != j) {
            let eta_beta: f64 = eta.iter().zip(beta(k)).map(|(e, b)| e * b).sum();
            let expected = [
                eta_beta,
                x[l.c(j, 0)] * foot_z(k + 1),
                x[l.psi(j, 0)] * cone(k),
            ];
            for (p, e) in expected.iter().enumerate() {
                let r = rows.start + p;
                let got = g1[r] - g2[r];
                assert!(
                    (got - e).abs() <= 1e-12 * e.abs().max(1.0),
                    "interval {j} row {p}: {got} vs {e}"
                );
            }
        }
        if block.len() == 1 {
            for r in rows {
                assert_eq!(g1[r], g2[r], "interval {j}: a block of one adds nothing");
            }
        }
    }
    for r in 0..l.num_constraints() {
        if !(0..5).any(|j| l.rows_of("Complementarity", j).contains(&r)) {
            assert_eq!(g1[r], g2[r], "row {r} is no complementarity row");
        }
    }
}

/// `[slack] mode = "penalty"`: no slacks, no complementarity rows, the weighted products in
/// the objective (cost blocks with closed-form gradient and Hessian). Every feature on the
/// hopper with the midpoint rule, galerkin4 and Euler (with a loop), the brick's eight
/// contacts on a step, and contact-mode blocks of 2 and 3 (shorter last blocks).
#[test]
fn penalty_mode_has_exact_derivatives() {
    for (seed, integrator) in [
        (41, Integrator::Midpoint),
        (42, Integrator::Galerkin4),
        (43, Integrator::Euler),
    ] {
        let spec = hopper_everything(integrator, SlackMode::Penalty);
        let t = Transcription::new(WithLoop(Hopper), &spec).unwrap();
        check_derivatives(&format!("hopper penalty {integrator:?}"), &t, seed);
    }
    for (seed, m, knots) in [(44, 2, 6), (45, 3, 5)] {
        let mut spec = hopper_everything(Integrator::Midpoint, SlackMode::Penalty);
        spec.knots = knots;
        spec.mode_block = m;
        let t = Transcription::new(Hopper, &spec).unwrap();
        check_derivatives(&format!("hopper penalty blocks of {m}"), &t, seed);
    }
    let mut spec = brick_3d();
    spec.knots = 4;
    spec.slack_mode = SlackMode::Penalty;
    spec.mode_block = 2;
    spec.terrain.steps.push(Step::along_x(0.05, 0.02, 0.1));
    let t = Transcription::new(Brick, &spec).unwrap();
    check_derivatives("brick penalty blocks of 2", &t, 46);
}

/// The penalty's closed forms (the elastic rows' bilinear forms and the gap row's chain
/// rule, weighted by −α) equal generic AD of the blocks' values: objective gradient and
/// Lagrangian Hessian at random points, the hopper and LittleDog's 3-D legs.
#[test]
fn penalty_closed_forms_match_generic_ad() {
    fn compare<M: MechanicsDerivatives>(name: &str, mut t: Transcription<M>, seed: u64) {
        let mut rng = SeededRng::new(seed);
        let (x, lambda, sigma) = random_point(&t, &mut rng);
        let nnz = t.hessian_pattern().nnz();
        let mut values = Vec::new();
        for chain_rule in [true, false] {
            t.set_contact_chain_rule(chain_rule);
            let mut grad = vec![0.0; x.len()];
            t.gradient(&x, &mut grad);
            let mut hess = vec![0.0; nnz];
            t.hessian_values(&x, sigma, &lambda, &mut hess);
            values.push((grad, hess));
        }
        let close = |a: &[f64], b: &[f64]| {
            a.iter()
                .zip(b)
                .all(|(p, q)| (p - q).abs() <= 1e-10 * p.abs().max(1.0))
        };
        assert!(close(&values[0].0, &values[1].0), "{name}: gradient");
        assert!(close(&values[0].1, &values[1].1), "{name}: Hessian");
        // The check has teeth: the penalty moves the gradient at this point.
        assert!(values[0].0.iter().any(|g| g.abs() > 1e-3), "{name}");
    }
    let mut spec = hopper_everything(Integrator::Midpoint, SlackMode::Penalty);
    spec.mode_block = 2;
    compare("hopper", Transcription::new(Hopper, &spec).unwrap(), 47);
    let mut spec = littledog_step();
    spec.knots = 3;
    spec.slack_mode = SlackMode::Penalty;
    // A 5 cm edge rather than the file's 5 mm: the surface frame's terms of a sharp edge
    // (H⁗ ~ 1e8) cancel in another order in each form, past the tolerance.
    spec.terrain.steps[0].width = 0.05;
    let mech = ModelMechanics::load(&spec).unwrap();
    compare("littledog", Transcription::new(mech, &spec).unwrap(), 48);
}

/// The penalty is the elastic rows' products weighted by α: at a point, the objective's
/// `complementarity_penalty` term equals −α times the sum of the elastic NLP's
/// complementarity rows with every slack at 0 (per-interval slacks, blocks of 1 and 2), the
/// penalty NLP has neither those rows nor slacks, and its cost terms are the elastic ones.
#[test]
fn penalty_term_is_the_weighted_elastic_products() {
    for m in [1, 2] {
        let mut spec = hopper_2d();
        spec.knots = 6;
        spec.mode_block = m;
        let elastic = Transcription::new(Hopper, &spec).unwrap();
        spec.slack_mode = SlackMode::Penalty;
        let penalty = Transcription::new(Hopper, &spec).unwrap();
        let (le, lp) = (elastic.layout(), penalty.layout());
        assert_eq!(lp.slacks().len(), 0);
        assert_eq!(
            le.num_constraints() - lp.num_constraints(),
            3 * le.intervals()
        );
        assert_eq!(le.num_variables() - lp.num_variables(), le.intervals());
        let mut rng = SeededRng::new(49 + m as u64);
        let (xp, _, _) = random_point(&penalty, &mut rng);
        // The elastic point: the same variables, its slacks (the last ones, midpoint) at 0.
        let mut xe = xp.clone();
        xe.extend(std::iter::repeat_n(0.0, le.intervals()));
        assert_eq!(le.slacks(), lp.num_variables()..le.num_variables());
        let mut g = vec![0.0; le.num_constraints()];
        elastic.constraints(&xe, &mut g);
        let rows: f64 = (0..le.intervals())
            .flat_map(|j| le.rows_of("Complementarity", j))
            .map(|r| g[r])
            .sum();
        let term = |t: &Transcription<Hopper>, x: &[f64], name: &str| {
            t.objective_terms(x)
                .into_iter()
                .find(|(n, _)| n == name)
                .map(|(_, v)| v)
        };
        let weighted = term(&penalty, &xp, "complementarity_penalty").unwrap();
        let expected = -spec.slack_weight * rows;
        assert!(
            (weighted - expected).abs() <= 1e-12 * expected.abs().max(1.0),
            "blocks of {m}: penalty {weighted} against −α Σ rows {expected}"
        );
        assert!(expected > 1.0, "blocks of {m}: {expected}");
        assert_eq!(term(&penalty, &xp, "slack_penalty"), None);
        let objective = penalty.objective(&xp);
        assert!(
            (objective - (elastic.objective(&xe) + weighted)).abs() <= 1e-12 * objective.abs(),
            "blocks of {m}"
        );
    }
}
