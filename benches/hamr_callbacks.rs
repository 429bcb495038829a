//! HAMR's callbacks (prints numbers, asserts none): one Jacobian plus one Lagrangian Hessian
//! of the 51-knot standing problem `benches/hamr_standing.toml` (38 coordinates, 24
//! loop-closure rows per knot), serial per block kind and in all, and on rayon's pool.
//! `cargo bench --bench hamr_callbacks`; `-- --repeat N` loops the serial J + H N times
//! (for `perf record`), `-- --repeat N --hessian-only` the serial H alone; `-- --reps N`
//! takes the minimum over N evaluations instead of 5 (on a loaded machine).

use std::path::Path;
use std::time::Instant;

use vito::discrete::ModelMechanics;
use vito::transcription::Transcription;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let repeat = args
        .iter()
        .position(|a| a == "--repeat")
        .and_then(|i| args.get(i + 1))
        .and_then(|s| s.parse::<usize>().ok());
    let reps = args
        .iter()
        .position(|a| a == "--reps")
        .and_then(|i| args.get(i + 1))
        .and_then(|s| s.parse::<usize>().ok())
        .unwrap_or(5);
    let file = args
        .iter()
        .position(|a| a == "--file")
        .and_then(|i| args.get(i + 1))
        .map_or("benches/hamr_standing.toml", String::as_str);
    let problem = vito::problem::load(Path::new(file), &[]).expect("the bench problem loads");
    let spec = &problem.spec;
    let mut t = Transcription::new(ModelMechanics::load(spec).expect("robot"), spec)
        .expect("transcription");
    t.set_skip_fixed_variables(true);
    let x = t.initial_point().to_vec();
    let rows = t.layout().num_constraints();
    let lambda: Vec<f64> = (0..rows).map(|r| 0.3 + 0.1 * (r % 7) as f64).collect();
    let mut jac = vec![0.0; t.jacobian_pattern().nnz()];
    let mut hess = vec![0.0; t.hessian_pattern().nnz()];
    if let Some(n) = repeat {
        t.set_parallel(false);
        let hessian_only = args.iter().any(|a| a == "--hessian-only");
        for _ in 0..n {
            if !hessian_only {
                t.jacobian_values(&x, &mut jac);
            }
            t.hessian_values(&x, 1.0, &lambda, &mut hess);
        }
        return;
    }
    t.set_parallel(false);
    let mut best: Vec<(String, f64)> = Vec::new();
    for _ in 0..3 {
        let times = t.derivative_time_by_kind(&x, &lambda);
        if best.is_empty() {
            best = times;
        } else {
            for (b, (_, s)) in best.iter_mut().zip(times) {
                b.1 = b.1.min(s);
            }
        }
    }
    let kinds: Vec<String> = best
        .iter()
        .map(|(k, s)| format!("{k} {:.2} ms", s * 1e3))
        .collect();
    println!(
        "{}: per kind (serial, min of 3): {}",
        spec.name,
        kinds.join(", ")
    );
    for parallel in [false, true] {
        t.set_parallel(parallel);
        let (mut tg, mut tj, mut th) = (f64::MAX, f64::MAX, f64::MAX);
        let mut g = vec![0.0; rows];
        for _ in 0..reps {
            let s = Instant::now();
            t.constraints(&x, &mut g);
            tg = tg.min(s.elapsed().as_secs_f64());
            let s = Instant::now();
            t.jacobian_values(&x, &mut jac);
            tj = tj.min(s.elapsed().as_secs_f64());
            let s = Instant::now();
            t.hessian_values(&x, 1.0, &lambda, &mut hess);
            th = th.min(s.elapsed().as_secs_f64());
        }
        println!(
            "{} (parallel = {parallel}, min of {reps}): g {:.2} ms, J {:.2} ms, H {:.2} ms, J+H {:.2} ms; \
             {} variables, J nnz {}, H nnz {}",
            spec.name,
            tg * 1e3,
            tj * 1e3,
            th * 1e3,
            (tj + th) * 1e3,
            t.layout().num_variables(),
            jac.len(),
            hess.len()
        );
    }
}
