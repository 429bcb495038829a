//! Galerkin variational integrators: the s = 1 member is the midpoint rule, the
//! measured orders of accuracy without contact, bounded energy error, and resting contact.

use nalgebra::DVector;
use vito::autodiff::{VectorFunction, gradient};
use vito::discrete::{
    GalerkinAction, GalerkinRule, HalfForce, Integrator, Mechanics, MechanicsDerivatives,
    ModelMechanics, arriving_momentum, first_step, step,
};
use vito::model::{self, BaseType, Model, sample};
use vito::random::SeededRng;

/// The s = 1 Galerkin member (one Gauss point) is the midpoint rule: on the hopper, its
/// ∂A/∂q^0, ∂A/∂q^1, ∂A/∂h equal the midpoint segment gradient (D1Ld, D2Ld, ∂Ld/∂h) and its
/// forces f^0, f^1 equal ½Fd each, to round-off.
#[test]
fn galerkin_degree_one_is_the_midpoint_rule_on_the_hopper() {
    let spec = crate::common::reference::hopper_2d();
    let mech = vito::pipeline::mechanics(&spec).expect("hopper loads");
    let (n, m) = (mech.nq(), mech.nu());
    let rule = GalerkinRule::of_degree(1).expect("tabulated");
    let mut rng = SeededRng::new(30);
    for _ in 0..5 {
        let qa: Vec<f64> = (0..n).map(|_| rng.range(-0.5, 0.5)).collect();
        let qb: Vec<f64> = qa.iter().map(|q| q + rng.range(-0.05, 0.05)).collect();
        let u: Vec<f64> = (0..m).map(|_| rng.range(-20.0, 20.0)).collect();
        let h = rng.range(0.01, 0.1);
        let z: Vec<f64> = qa.iter().chain(&qb).copied().chain([h]).collect();
        let midpoint = mech.segment_gradient(&z);
        let (value, galerkin) = gradient(
            &GalerkinAction {
                mech: &mech,
                rule: &rule,
            },
            &z,
        );
        assert!(
            (value - mech.discrete_lagrangian(&qa, &qb, h)).abs() < 1e-13 * (1.0 + value.abs())
        );
        let scale = 1.0 + midpoint.iter().fold(0.0_f64, |a, g| a.max(g.abs()));
        for (a, b) in midpoint.iter().zip(&galerkin) {
            assert!((a - b).abs() < 1e-13 * scale, "{a} vs {b}");
        }
        let zf: Vec<f64> = qa.iter().chain(&qb).chain(&u).copied().chain([h]).collect();
        let mut half = vec![0.0; n];
        HalfForce { mech: &mech }.eval(&zf, &mut half);
        let mut forces = vec![0.0; 2 * n];
        rule.forces(
            &mech,
            &[qa.clone(), qb.clone()].concat(),
            &u,
            h,
            &mut forces,
        );
        for i in 0..n {
            assert!((forces[i] - half[i]).abs() < 1e-13 * (1.0 + half[i].abs()));
            assert!((forces[n + i] - half[i]).abs() < 1e-13 * (1.0 + half[i].abs()));
        }
    }
}

/// Least-squares slope of log(error) against log(h).
fn fitted_slope(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points.iter().map(|(h, e)| (h.ln(), e.ln())).collect();
    let k = logs.len() as f64;
    let (mx, my) = logs
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / k, b + y / k));
    let (sxy, sxx) = logs.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    sxy / sxx
}

/// The double pendulum of `sample::double_pendulum` from rest at q = (1, −0.5) rad.
const Q0: [f64; 2] = [1.0, -0.5];

/// Knots q_0..q_N of `integrator` over [0, T] with N = `steps` (`discrete::step`, Newton to
/// round-off) and the energy T + V at each knot from the integrator's own momentum
/// (v_k = M(q_k)⁻¹p_k⁻, v_0 at the first knot).
fn pendulum_run(
    mech: &ModelMechanics,
    integrator: Integrator,
    horizon: f64,
    steps: usize,
) -> (Vec<Vec<f64>>, Vec<f64>) {
    let model = mech.model();
    let h = horizon / steps as f64;
    let u: Vec<f64> = vec![0.0; mech.nu()];
    let mut qs = vec![
        Q0.to_vec(),
        first_step(model, integrator, &Q0, &[0.0; 2], &u, h).expect("first step"),
    ];
    for k in 1..steps {
        let next = step(model, integrator, &qs[k - 1], &qs[k], &u, h).expect("step");
        qs.push(next);
    }
    let rule = integrator.galerkin_rule();
    let energies = (0..qs.len())
        .map(|k| {
            let v = if k == 0 {
                vec![0.0; 2]
            } else {
                let p = arriving_momentum(mech, rule.as_ref(), &qs[k - 1], &qs[k], &u, h)
                    .expect("interval solves");
                let mass = model::mass_matrix(model, &qs[k]);
                mass.lu()
                    .solve(&DVector::from_vec(p))
                    .expect("M invertible")
                    .as_slice()
                    .to_vec()
            };
            model::kinetic_energy(model, &qs[k], &v) + model::potential_energy(model, &qs[k])
        })
        .collect();
    (qs, energies)
}

/// Convergence without contact on the double pendulum over T = 1 s: the state error at the
/// knots t = 0.1 s, 0.2 s, …, 1 s against a reference (galerkin6 at N = 1920) and the largest
/// energy error |E_k − E_0|, at 10 step counts per integrator. Fitted log-log slopes: midpoint
/// ≈ 2, galerkin4 ≥ 3.8, galerkin6 ≥ 5.6 (state and energy).
#[test]
fn galerkin_orders_on_the_double_pendulum() {
    let model = Model::from_urdf_str(&sample::double_pendulum(), BaseType::Fixed).unwrap();
    let mech = ModelMechanics::with_contacts(model, Vec::new());
    let horizon = 1.0;
    // The reference's own error is ~1e-11 rad (N = 960 and 1920 differ by 8e-12); finer
    // steps gain nothing, round-off of (1/h)·Σ q^ν ℓ̇_ν grows like 1/h.
    let reference_steps = 1920;
    let (reference, _) = pendulum_run(&mech, Integrator::Galerkin6, horizon, reference_steps);
    // Step counts within each member's asymptotic range and above the reference's error:
    // h = 0.1 … 0.003 s for orders 2 and 4, h = 0.05 … 0.008 s for order 6.
    let steps: [usize; 10] = [10, 20, 30, 40, 60, 80, 120, 160, 240, 320];
    let sixth: [usize; 10] = [20, 30, 40, 50, 60, 70, 80, 90, 100, 120];
    let cases = [
        (Integrator::Midpoint, &steps[..], 1.9, 2.1),
        (Integrator::Galerkin4, &steps[..], 3.8, 4.3),
        (Integrator::Galerkin6, &sixth[..], 5.6, 6.5),
    ];
    for (integrator, counts, low, high) in cases {
        let (mut state, mut energy) = (Vec::new(), Vec::new());
        for &n in counts {
            let (qs, energies) = pendulum_run(&mech, integrator, horizon, n);
            let error = (1..=10)
                .map(|i| {
                    let (k, r) = (i * n / 10, i * reference_steps / 10);
                    qs[k]
                        .iter()
                        .zip(&reference[r])
                        .fold(0.0_f64, |a, (x, y)| a.max((x - y).abs()))
                })
                .fold(0.0_f64, f64::max);
            let drift = energies
                .iter()
                .fold(0.0_f64, |a, e| a.max((e - energies[0]).abs()));
            let h = horizon / n as f64;
            println!("{integrator:?} h {h:.5}: state {error:.3e} rad, energy {drift:.3e} J");
            state.push((h, error));
            energy.push((h, drift));
        }
        let (s, e) = (fitted_slope(&state), fitted_slope(&energy));
        println!("{integrator:?}: state slope {s:.3}, energy slope {e:.3}");
        assert!((low..high).contains(&s), "{integrator:?} state slope {s}");
        assert!((low..high).contains(&e), "{integrator:?} energy slope {e}");
    }
}
