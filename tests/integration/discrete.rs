//! Discrete mechanics: energy behaviour, convergence orders, loop closure, and AD
//! derivatives against central differences.

use nalgebra::{DMatrix, DVector};
use vito::autodiff::finite_differences::{self as fd, relative_step};
use vito::autodiff::{ScalarFunction, gradient, gradient_hessian, jacobian};
use vito::discrete::{
    DiscreteForce, EulerKnotResidual, InitialMomentum, Integrator, KnotWindow, LoopClosure,
    MidpointKnotResidual, MidpointSegment, ModelMechanics, d1_ld, d2_ld, del_residual, first_step,
    knot_residual, knot_residual_jacobian_next, ld, step,
};
use vito::model::{self, BaseType, Model, sample};
use vito::random::SeededRng;

fn double_pendulum() -> Model {
    Model::from_urdf_str(&sample::double_pendulum(), BaseType::Fixed).expect("sample loads")
}

/// A 3-link chain (3 inputs) with damping 0.3 N·m·s/rad on every hinge, so that inputs and
/// damping enter the derivatives; on a planar base (n = 6) base coordinates enter too.
fn damped_chain(base: BaseType) -> Model {
    let m = Model::from_urdf_str(&sample::damped_chain(3), base).expect("chain loads");
    assert_eq!(m.input_coordinates().len(), 3);
    assert!(m.damping().iter().filter(|&&d| d == 0.3).count() == 3);
    m
}

/// Total energy at a knot from a configuration and a velocity.
fn energy(model: &Model, q: &[f64], v: &[f64]) -> f64 {
    model::kinetic_energy(model, q, v) + model::potential_energy(model, q)
}

/// Simulates from (q0, v0) for `steps` steps and returns the configurations q_1..q_{steps+1}.
fn simulate(
    model: &Model,
    method: Integrator,
    q0: &[f64],
    v0: &[f64],
    h: f64,
    steps: usize,
) -> Vec<Vec<f64>> {
    let u = vec![0.0; model.input_coordinates().len()];
    let mut qs = vec![
        q0.to_vec(),
        first_step(model, method, q0, v0, &u, h).expect("first step"),
    ];
    for k in 1..steps {
        let next = step(model, method, &qs[k - 1], &qs[k], &u, h).expect("step converges");
        qs.push(next);
    }
    qs
}

/// Energy along a simulated trajectory. Midpoint: from the discrete Legendre transform
/// p_k⁻ = D2Ld(q_{k−1}, q_k), v_k = M(q_k)⁻¹p_k. Euler: from its own velocity
/// v_k = (q_k − q_{k−1})/h at q_k.
fn energies(model: &Model, method: Integrator, qs: &[Vec<f64>], h: f64) -> Vec<f64> {
    (1..qs.len())
        .map(|k| {
            let v: Vec<f64> = match method {
                Integrator::Midpoint => {
                    let p = d2_ld(model, &qs[k - 1], &qs[k], h);
                    let m = model::mass_matrix(model, &qs[k]);
                    m.lu()
                        .solve(&DVector::from_vec(p))
                        .expect("M invertible")
                        .as_slice()
                        .to_vec()
                }
                Integrator::Euler => qs[k]
                    .iter()
                    .zip(&qs[k - 1])
                    .map(|(a, b)| (a - b) / h)
                    .collect(),
                Integrator::Galerkin4 | Integrator::Galerkin6 => {
                    panic!("the Galerkin members' energies are `vito::sim::knot_energies`")
                }
            };
            energy(model, &qs[k], &v)
        })
        .collect()
}

/// A conservative double pendulum released from rest at (1.0, −0.5) rad, stepped 10,000 times
/// at h = 0.01 s (100 s, chaotic): the midpoint energy error stays bounded, shows no drift, and is
/// smaller than the first-order method's at the same step.
#[test]
fn midpoint_energy_error_is_bounded_and_below_first_order() {
    let model = double_pendulum();
    let (q0, v0, h, steps) = ([1.0, -0.5], [0.0, 0.0], 0.01, 10_000);
    let e0 = energy(&model, &q0, &v0);
    // Energy scale: the potential energy swing between hanging and released, m g l ≈ 10 J.
    let scale = e0 - model::potential_energy(&model, &[0.0, 0.0]);
    let qs = simulate(&model, Integrator::Midpoint, &q0, &v0, h, steps);
    let errors: Vec<f64> = energies(&model, Integrator::Midpoint, &qs, h)
        .iter()
        .map(|e| (e - e0).abs())
        .collect();
    let first_half = errors[..steps / 2].iter().cloned().fold(0.0, f64::max);
    let second_half = errors[steps / 2..].iter().cloned().fold(0.0, f64::max);
    let midpoint_max = first_half.max(second_half);
    println!(
        "Midpoint: energy scale {scale:.3} J, max |E − E0| first half {first_half:.3e} J, second half {second_half:.3e} J"
    );
    // Bounded: a second-order symplectic method keeps |ΔE| = O(h²)·scale for exponentially
    // long times; measured 8.1e-4 J = 1.7e-4·scale, so 1e-3·scale leaves a factor ~6.
    assert!(
        midpoint_max < 1e-3 * scale,
        "midpoint energy error {midpoint_max:.3e}"
    );
    // No drift: the second half's error is of the size of the first half's.
    assert!(
        second_half < 2.0 * first_half,
        "energy drifts: {first_half:.3e} → {second_half:.3e}"
    );

    // Euler at the same h over its first 2,000 steps (20 s; it is O(h) off from the first step
    // on, and over 10,000 steps its energy grows until a Newton step fails near step 6,500),
    // stopping early if a step fails.
    // Unforced: the sample pendulum has no transmissions, so both joints take an input.
    let u = vec![0.0; model.input_names().len()];
    let mut q_prev = q0.to_vec();
    let mut q_curr = first_step(&model, Integrator::Euler, &q0, &v0, &u, h).expect("first step");
    let mut euler_max = 0.0f64;
    let euler_steps = 2000;
    for k in 1..=euler_steps {
        let v: Vec<f64> = q_curr
            .iter()
            .zip(&q_prev)
            .map(|(a, b)| (a - b) / h)
            .collect();
        euler_max = euler_max.max((energy(&model, &q_curr, &v) - e0).abs());
        if k == euler_steps {
            println!("Euler: max |E − E0| {euler_max:.3e} J after {k} steps");
            break;
        }
        match step(&model, Integrator::Euler, &q_prev, &q_curr, &u, h) {
            Ok(next) => q_prev = std::mem::replace(&mut q_curr, next),
            Err(e) => {
                println!("Euler: step {k} failed ({e}); max |E − E0| {euler_max:.3e} J");
                break;
            }
        }
    }
    assert!(
        midpoint_max < euler_max,
        "midpoint {midpoint_max:.3e} J vs Euler {euler_max:.3e} J"
    );
}

/// Global error at T = 1 s estimated from successive halvings (e(h) ≈ |q_h − q_{h/2}|, which
/// has the order of the method), for h = 0.02, 0.01, 0.005, 0.0025: the observed orders
/// log2(e(h)/e(h/2)) are 2 ± 0.3 for midpoint and 1 ± 0.3 for Euler.
#[test]
fn convergence_orders_are_two_and_one() {
    let model = double_pendulum();
    let (q0, v0, t_end) = ([0.6, -0.4], [0.3, 0.5], 1.0_f64);
    for (method, expected) in [(Integrator::Midpoint, 2.0), (Integrator::Euler, 1.0)] {
        let finals: Vec<Vec<f64>> = [0.02, 0.01, 0.005, 0.0025]
            .iter()
            .map(|&h| {
                let steps = (t_end / h).round() as usize;
                simulate(&model, method, &q0, &v0, h, steps)
                    .pop()
                    .expect("nonempty")
            })
            .collect();
        let errors: Vec<f64> = finals
            .windows(2)
            .map(|w| {
                w[0].iter()
                    .zip(&w[1])
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max)
            })
            .collect();
        for pair in errors.windows(2) {
            let order = (pair[0] / pair[1]).log2();
            println!(
                "{method:?}: errors {:.3e} → {:.3e}, order {order:.3}",
                pair[0], pair[1]
            );
            assert!(
                (order - expected).abs() < 0.3,
                "{method:?} order {order} (expected {expected})"
            );
        }
    }
}

/// A closed four-bar started in its closed pose q = 0 with the crank turning at 1 rad/s moves
/// under gravity for 1,000 steps of 0.01 s (both methods); the closure residual stays below 1e-9 m at every knot.
#[test]
fn four_bar_stays_closed() {
    let model = Model::from_urdf_str(&sample::four_bar(), BaseType::Fixed).expect("four-bar loads");
    assert_eq!(model.num_loop_constraints(), 2);
    // Start with 1 rad/s on the crank along the null space of G = ∂ loop_residual/∂q (the
    // cross product of its two rows), so that v_0 is admissible.
    let (_, g) = jacobian(&LoopClosure { model: &model }, &[0.0; 3]);
    let null = g.row(0).transpose().cross(&g.row(1).transpose());
    let v0: Vec<f64> = null.iter().map(|x| x / null[0]).collect();
    for method in [Integrator::Midpoint, Integrator::Euler] {
        let qs = simulate(&model, method, &[0.0; 3], &v0, 0.01, 1000);
        let worst = qs
            .iter()
            .flat_map(|q| model::loop_residual(&model, q))
            .fold(0.0f64, |a, r: f64| a.max(r.abs()));
        let travel = qs.iter().map(|q| q[0].abs()).fold(0.0, f64::max);
        println!("{method:?}: max closure residual {worst:.3e} m, max crank angle {travel:.3} rad");
        assert!(worst < 1e-9, "{method:?} closure residual {worst:e}");
        assert!(
            travel > 0.1,
            "the linkage should move (crank swung {travel} rad)"
        );
    }
}

/// Agreement to 1e-6 relative to the size of the matrix (max entry, at least 1).
fn assert_close(ad: &DMatrix<f64>, fd: &DMatrix<f64>, what: &str) {
    let scale = ad.amax().max(1.0);
    let diff = (ad - fd).amax();
    assert!(
        diff < 1e-6 * scale,
        "{what}: max |AD − FD| = {diff:e} (scale {scale:e})"
    );
}

/// A random state: configurations within ±0.8 rad of 0, steps in [0.01, 0.05] s.
fn random_segment(n: usize, rng: &mut SeededRng) -> (Vec<f64>, Vec<f64>, f64) {
    let qa = rng.symmetric_vec(n, 0.8);
    let dq = rng.symmetric_vec(n, 0.05);
    let h = 0.03 + rng.symmetric_vec(1, 0.02)[0];
    let qb = qa.iter().zip(&dq).map(|(a, d)| a + d).collect();
    (qa, qb, h)
}

#[test]
fn gradient_of_ld_matches_central_differences() {
    let mut rng = SeededRng::new(1);
    for model in [double_pendulum(), damped_chain(BaseType::Planar)] {
        let n = model.nq();
        let seg = MidpointSegment { model: &model };
        for _ in 0..5 {
            let (qa, qb, h) = random_segment(n, &mut rng);
            let z: Vec<f64> = qa.iter().chain(&qb).copied().chain([h]).collect();
            let (value, grad) = gradient(&seg, &z);
            assert_eq!(value, ld(&model, &qa, &qb, h));
            let fd = fd::gradient(|x| seg.eval(x), &z, 1e-6);
            assert_close(
                &DMatrix::from_row_slice(1, 2 * n + 1, &grad),
                &DMatrix::from_row_slice(1, 2 * n + 1, &fd),
                "∇Ld",
            );
            // The generic slot derivatives (the NLP's adjoint path) are the same numbers.
            let d1 = d1_ld(&model, &qa, &qb, h);
            let d2 = d2_ld(&model, &qa, &qb, h);
            for i in 0..n {
                assert!((d1[i] - grad[i]).abs() < 1e-12 * (1.0 + grad[i].abs()));
                assert!((d2[i] - grad[n + i]).abs() < 1e-12 * (1.0 + grad[n + i].abs()));
            }
        }
    }
}

#[test]
fn jacobians_of_knot_residuals_match_central_differences() {
    let mut rng = SeededRng::new(7);
    for model in [double_pendulum(), damped_chain(BaseType::Planar)] {
        let n = model.nq();
        let m = model.input_coordinates().len();
        for _ in 0..3 {
            let (q0, q1, h0) = random_segment(n, &mut rng);
            let (_, dq, h1) = random_segment(n, &mut rng);
            let q2: Vec<f64> = q1.iter().zip(&dq).map(|(a, d)| a + d * 0.05).collect();
            let (u0, u1) = (rng.symmetric_vec(m, 2.0), rng.symmetric_vec(m, 2.0));
            let z: Vec<f64> = [&q0[..], &q1, &q2, &[h0, h1], &u0, &u1].concat();
            let del = MidpointKnotResidual { model: &model };
            let (values, jac) = jacobian(&del, &z);
            let window = KnotWindow {
                q_prev: &q0,
                q_curr: &q1,
                q_next: &q2,
                h_prev: h0,
                h_curr: h1,
                u_prev: &u0,
                u_curr: &u1,
            };
            // Same formula; the dual pass and the f64 pass round differently (measured ~1 ulp).
            let direct = del_residual(&model, &window);
            for (a, b) in values.iter().zip(&direct) {
                assert!(
                    (a - b).abs() <= 1e-14 * (1.0 + b.abs()),
                    "{values:?} vs {direct:?}"
                );
            }
            assert_close(
                &jac,
                &fd::jacobian(|x| fd::values(&del, x), &z, relative_step),
                "midpoint DEL Jacobian",
            );

            // The NLP's route: the same Jacobian from segment Hessians and force Jacobians.
            let seg = MidpointSegment { model: &model };
            let (_, _, h_prev_seg) = gradient_hessian(&seg, &[&q0[..], &q1, &[h0]].concat());
            let (_, _, h_next_seg) = gradient_hessian(&seg, &[&q1[..], &q2, &[h1]].concat());
            let force = DiscreteForce { model: &model };
            let (_, f_prev) = jacobian(&force, &[&q0[..], &q1, &u0, &[h0]].concat());
            let (_, f_next) = jacobian(&force, &[&q1[..], &q2, &u1, &[h1]].concat());
            let mut assembled = DMatrix::zeros(n, 3 * n + 2 + 2 * m);
            for i in 0..n {
                for j in 0..2 * n {
                    assembled[(i, j)] += h_prev_seg[(n + i, j)] + 0.5 * f_prev[(i, j)];
                    assembled[(i, n + j)] += h_next_seg[(i, j)] + 0.5 * f_next[(i, j)];
                }
                assembled[(i, 3 * n)] = h_prev_seg[(n + i, 2 * n)] + 0.5 * f_prev[(i, 2 * n + m)];
                assembled[(i, 3 * n + 1)] = h_next_seg[(i, 2 * n)] + 0.5 * f_next[(i, 2 * n + m)];
                for j in 0..m {
                    assembled[(i, 3 * n + 2 + j)] = 0.5 * f_prev[(i, 2 * n + j)];
                    assembled[(i, 3 * n + 2 + m + j)] = 0.5 * f_next[(i, 2 * n + j)];
                }
            }
            assert!(
                (&assembled - &jac).amax() < 1e-10 * jac.amax().max(1.0),
                "assembled DEL Jacobian"
            );

            // The DEL of the mechanics trait (the NLP's pieces: the adjoint segment gradient,
            // ½Fd) is the model's DEL, and its Jacobian in q_{k+1} is that block of the
            // one-piece Jacobian; an impulse adds as it is.
            let mech = ModelMechanics::with_contacts(model.clone(), Vec::new());
            let impulse = rng.symmetric_vec(n, 0.3);
            let residual = knot_residual(&mech, &window, &impulse);
            for i in 0..n {
                let expected = values[i] + impulse[i];
                assert!(
                    (residual[i] - expected).abs() < 1e-12 * (1.0 + expected.abs()),
                    "knot residual {i}: {} vs {expected}",
                    residual[i]
                );
            }
            let next = knot_residual_jacobian_next(&mech, &window);
            let reference = jac.columns(2 * n, n).into_owned();
            assert!(
                (&next - &reference).amax() < 1e-10 * reference.amax().max(1.0),
                "DEL Jacobian in q_next: {next} vs {reference}"
            );

            for first_step in [false, true] {
                let euler = EulerKnotResidual {
                    model: &model,
                    first_step,
                };
                let ze: Vec<f64> = [&q0[..], &q1, &q2, &[h0, h1], &u1].concat();
                let (_, jac) = jacobian(&euler, &ze);
                assert_close(
                    &jac,
                    &fd::jacobian(|x| fd::values(&euler, x), &ze, relative_step),
                    "Euler residual Jacobian",
                );
            }
            let momentum = InitialMomentum { model: &model };
            let zm: Vec<f64> = [&q1[..], &dq].concat();
            let (p, jac) = jacobian(&momentum, &zm);
            let mv = model::mass_matrix(&model, &q1) * DVector::from_column_slice(&dq);
            assert!(
                (DVector::from_vec(p) - mv).amax()
                    < 1e-12 * (1.0 + dq.iter().map(|x| x.abs()).sum::<f64>())
            );
            assert_close(
                &jac,
                &fd::jacobian(|x| fd::values(&momentum, x), &zm, relative_step),
                "initial momentum Jacobian",
            );
        }
    }
}

/// Damping removes energy: a damped chain released from rest loses energy every step (and the
/// residual sign convention makes Fd dissipative, not a source).
#[test]
fn damping_dissipates_energy() {
    let model = damped_chain(BaseType::Fixed);
    let q0 = [0.8, -0.6, 0.3];
    let h = 0.01;
    for method in [Integrator::Midpoint, Integrator::Euler] {
        let qs = simulate(&model, method, &q0, &[0.0; 3], h, 300);
        let e = energies(&model, method, &qs, h);
        let e_start = energy(&model, &q0, &[0.0; 3]);
        println!(
            "{method:?}: energy {e_start:.4} J → {:.4} J",
            e[e.len() - 1]
        );
        let e_end = e[e.len() - 1];
        assert!(
            e_end < e_start - 1e-2,
            "{method:?}: energy {e_start} J → {e_end} J"
        );
    }
}
