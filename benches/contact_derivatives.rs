//! Contact-block derivative timings and agreement (prints numbers; asserts only agreement):
//! per block kind, one Jacobian plus one Lagrangian Hessian on the URDF reference problems,
//! with the contact blocks by the chain rule over q and by generic AD over the block. Run:
//! `cargo bench --bench contact_derivatives`.

#[path = "../tests/integration/common/mod.rs"]
mod common;

use std::time::Instant;

use common::reference::{brick_3d, hopper_2d};
use vito::discrete::{MechanicsDerivatives, ModelMechanics};
use vito::transcription::Transcription;

fn jh<M: MechanicsDerivatives>(
    t: &Transcription<M>,
    x: &[f64],
    lambda: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let mut jac = vec![0.0; t.jacobian_pattern().nnz()];
    let mut hess = vec![0.0; t.hessian_pattern().nnz()];
    t.jacobian_values(x, &mut jac);
    t.hessian_values(x, 1.0, lambda, &mut hess);
    (jac, hess)
}

fn max_relative_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / (1.0 + x.abs().max(y.abs())))
        .fold(0.0, f64::max)
}

fn contact_derivative_times_and_agreement() {
    for spec in [hopper_2d(), brick_3d()] {
        let mut t = Transcription::new(ModelMechanics::load(&spec).unwrap(), &spec).unwrap();
        t.set_parallel(false);
        let x0 = t.initial_point().to_vec();
        let rows = t.layout().num_constraints();
        let lambda: Vec<f64> = (0..rows).map(|r| 0.3 + 0.1 * (r % 7) as f64).collect();
        for chain_rule in [false, true] {
            t.set_contact_chain_rule(chain_rule);
            let mut best: Vec<(String, f64)> = Vec::new();
            for _ in 0..5 {
                let times = t.derivative_time_by_kind(&x0, &lambda);
                if best.is_empty() {
                    best = times;
                } else {
                    for (b, (_, s)) in best.iter_mut().zip(times) {
                        b.1 = b.1.min(s);
                    }
                }
            }
            let start = Instant::now();
            for _ in 0..5 {
                std::hint::black_box(jh(&t, &x0, &lambda));
            }
            let total = start.elapsed().as_secs_f64() / 5.0;
            let kinds: Vec<String> = best
                .iter()
                .map(|(k, s)| format!("{k} {:.2} ms", s * 1e3))
                .collect();
            println!(
                "{} chain rule {chain_rule}: J+H {:.2} ms (serial); per kind: {}",
                spec.name,
                total * 1e3,
                kinds.join(", ")
            );
        }
        // Entry-by-entry agreement at the initial point and at perturbed points.
        for k in 0..3 {
            let x: Vec<f64> = x0
                .iter()
                .enumerate()
                .map(|(i, &v)| v + 0.01 * k as f64 * (((i * 37 + k * 11) % 19) as f64 / 19.0 - 0.5))
                .collect();
            t.set_contact_chain_rule(false);
            let (ja, ha) = jh(&t, &x, &lambda);
            t.set_contact_chain_rule(true);
            let (jc, hc) = jh(&t, &x, &lambda);
            let (dj, dh) = (
                max_relative_difference(&ja, &jc),
                max_relative_difference(&ha, &hc),
            );
            println!(
                "{} point {k}: max relative |ΔJ| {dj:.2e}, |ΔH| {dh:.2e}",
                spec.name
            );
            assert!(dj < 1e-10 && dh < 1e-10);
        }
    }
}

/// Ipopt's own timing split (`print_timing_statistics yes`) for the URDF reference solves;
/// read the "LinearSystemFactorization" line against the factorisation count. Run:
/// `cargo bench --bench contact_derivatives`.
fn ipopt_timing_statistics() {
    use vito::ipopt::OptionValue;
    use vito::pipeline::solve;
    use vito::transcription::SolveOptions;
    for spec in [hopper_2d(), brick_3d()] {
        let options = SolveOptions {
            ipopt_options: vec![
                ("print_level".into(), OptionValue::Int(3)),
                (
                    "print_timing_statistics".into(),
                    OptionValue::Str("yes".into()),
                ),
            ],
            ..SolveOptions::default()
        };
        let s = solve(&spec, &options).unwrap();
        println!(
            "{}: {:?}, objective {:.9}, {} iterations, wall {:.3} s, callbacks {:.3} s, \
             ipopt {:.3} s, max slack {:.2e}",
            spec.name,
            s.status,
            s.objective,
            s.iterations,
            s.wall_time_s,
            s.callback_time_s,
            s.ipopt_time_s,
            s.max_slack
        );
    }
}

fn main() {
    contact_derivative_times_and_agreement();
    ipopt_timing_statistics();
}
