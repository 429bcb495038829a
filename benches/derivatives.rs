//! Cost of one DEL segment's derivatives for planar chains (n = 9, 19, 38), per tile size.
//!
//! Run: `cargo bench --bench derivatives` (release build, one thread). Prints µs per call of
//! - `hess+third`: gradient, Hessian and third derivative contracted with a multiplier
//!   direction of Ld(qa, qb, h) (dim 2n+1): what the NLP needs per segment;
//! - `hess`: gradient and Hessian only (the DEL Jacobian blocks);
//! - `grad`: gradient only (the DEL residual).
//!
//! Inputs are seeded (a fixed LCG), so runs are comparable.

use std::hint::black_box;
use std::time::{Duration, Instant};
use vito::autodiff::{
    ThirdOrder, gradient_hessian_into, gradient_hessian_third_into, gradient_into,
};
use vito::discrete::MidpointSegment;
use vito::model::{BaseType, Model, sample};

/// Mean time per call of `f`, in µs, over at least 3 calls and about `budget`.
fn time_us(budget: Duration, mut f: impl FnMut()) -> f64 {
    f();
    let start = Instant::now();
    let mut calls = 0u32;
    while calls < 3 || start.elapsed() < budget {
        f();
        calls += 1;
    }
    start.elapsed().as_secs_f64() * 1e6 / f64::from(calls)
}

fn seeded(n: usize, seed: &mut u64) -> Vec<f64> {
    (0..n)
        .map(|_| {
            *seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect()
}

fn bench_tile<const T: usize>(name: &str, model: &Model, z: &[f64], dir: &[f64], budget: Duration) {
    let seg = MidpointSegment { model };
    let dim = z.len();
    let mut third = ThirdOrder::zeros(dim);
    let mut grad = vec![0.0; dim];
    let mut hess = nalgebra::DMatrix::zeros(dim, dim);
    let t3 = time_us(budget, || {
        gradient_hessian_third_into::<T, _>(&seg, black_box(z), dir, &mut third);
    });
    let t2 = time_us(budget, || {
        gradient_hessian_into::<T, _>(&seg, black_box(z), &mut grad, &mut hess);
    });
    let t1 = time_us(budget, || {
        black_box(gradient_into::<T, _>(&seg, black_box(z), &mut grad));
    });
    println!(
        "{name:<16} T={T:<3} hess+third {t3:>10.1} µs   hess {t2:>10.1} µs   grad {t1:>9.1} µs"
    );
}

fn main() {
    let budget = Duration::from_millis(
        std::env::var("VITO_BENCH_MS")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(1000),
    );
    let mut seed = 42;
    for n in [9, 19, 38] {
        let model = match Model::from_urdf_str(&sample::planar_chain(n), BaseType::Fixed) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("planar_chain({n}) failed to load: {e}");
                return;
            }
        };
        let qa = seeded(n, &mut seed);
        let qb: Vec<f64> = qa
            .iter()
            .zip(seeded(n, &mut seed))
            .map(|(a, d)| a + 0.05 * d)
            .collect();
        let z: Vec<f64> = qa.iter().chain(&qb).copied().chain([0.03]).collect();
        let dir = seeded(2 * n + 1, &mut seed);
        let name = format!("del_segment_n{n}");
        bench_tile::<4>(&name, &model, &z, &dir, budget);
        bench_tile::<8>(&name, &model, &z, &dir, budget);
        bench_tile::<12>(&name, &model, &z, &dir, budget);
        bench_tile::<16>(&name, &model, &z, &dir, budget);
    }
}
