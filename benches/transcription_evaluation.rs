//! Derivative-evaluation timings (prints numbers, asserts none): one Jacobian plus one
//! Lagrangian Hessian at the initial point, serial and on rayon's pool, for the reference
//! problems on the closed-form mechanics. Run:
//! `cargo bench --bench transcription_evaluation`.

#[path = "../tests/integration/common/mod.rs"]
mod common;

use std::time::Instant;

use common::analytic::{Brick, Hopper};
use common::reference::{brick_3d, hopper_2d};
use vito::discrete::MechanicsDerivatives;
use vito::transcription::Transcription;

fn median_eval<M: MechanicsDerivatives>(t: &Transcription<M>, repeats: usize) -> (f64, f64, f64) {
    let x = t.initial_point().to_vec();
    let mut g = vec![0.0; t.layout().num_constraints()];
    let mut jac = vec![0.0; t.jacobian_pattern().nnz()];
    let mut hess = vec![0.0; t.hessian_pattern().nnz()];
    let lambda = vec![0.5; t.layout().num_constraints()];
    let (mut tg, mut tj, mut th) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..repeats {
        let s = Instant::now();
        t.constraints(&x, &mut g);
        tg.push(s.elapsed().as_secs_f64());
        let s = Instant::now();
        t.jacobian_values(&x, &mut jac);
        tj.push(s.elapsed().as_secs_f64());
        let s = Instant::now();
        t.hessian_values(&x, 1.0, &lambda, &mut hess);
        th.push(s.elapsed().as_secs_f64());
    }
    let med = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    (med(tg), med(tj), med(th))
}

fn report<M: MechanicsDerivatives>(name: &str, mut t: Transcription<M>) {
    for parallel in [false, true] {
        t.set_parallel(parallel);
        let (g, j, h) = median_eval(&t, 21);
        println!(
            "{name} ({} threads max, parallel = {parallel}): g {:.3} ms, J {:.3} ms, H {:.3} ms; \
             {} variables, {} rows, J nnz {}, H nnz {}",
            rayon::current_num_threads(),
            g * 1e3,
            j * 1e3,
            h * 1e3,
            t.layout().num_variables(),
            t.layout().num_constraints(),
            t.jacobian_pattern().nnz(),
            t.hessian_pattern().nnz()
        );
    }
}

fn derivative_evaluation_times() {
    report(
        "hopper-2d",
        Transcription::new(Hopper, &hopper_2d()).unwrap(),
    );
    report("brick-3d", Transcription::new(Brick, &brick_3d()).unwrap());
}

/// `vito bench` rows for the reference problems loaded from URDF.
fn bench_rows_from_urdf() {
    for spec in [
        common::reference::hopper_2d(),
        common::reference::brick_3d(),
    ] {
        let row = vito::pipeline::bench(&spec).unwrap();
        println!(
            "{}: {} variables, {} constraints, J nnz {}, H nnz {}, {:?}, objective {:.9}, \
             {} iterations, wall {:.3} s, callbacks {:.3} s ({:.0} %), ipopt {:.3} s, \
             one J+H evaluation {:.3} ms",
            row.name,
            row.size.n_variables,
            row.size.n_constraints,
            row.size.nnz_jacobian,
            row.size.nnz_hessian,
            row.status,
            row.objective,
            row.iterations,
            row.wall_time_s,
            row.callback_time_s,
            100.0 * row.callback_time_s / row.wall_time_s,
            row.ipopt_time_s,
            row.derivative_eval_s * 1e3
        );
    }
}

fn main() {
    derivative_evaluation_times();
    bench_rows_from_urdf();
}
