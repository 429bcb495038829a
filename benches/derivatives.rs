//! Cost of one DEL segment's derivatives for planar chains (n = 9, 19, 38), per tile size.
//!
//! Run: `cargo bench --bench derivatives` (release build, one thread). Prints µs per call of
//! - `hess+third`: gradient, Hessian and third derivative contracted with a multiplier
//!   direction of Ld(qa, qb, h) (dim 2n+1): what the NLP needs per segment;
//! - `hess`: gradient and Hessian only (the DEL Jacobian blocks);
//! - `grad`: gradient only (the DEL residual);
//!
//! and, for scale, one plain `f64` evaluation of Ld.
//!
//! Inputs come from `vito::random::SeededRng`, so runs are comparable.
//!
//! Measured 2026-11-22 on the 2-core shared development VM (other sessions running, so ±50 %),
//! `VITO_BENCH_MS=700`, µs per call (hess+third / hess / grad; plain f64 Ld):
//!
//! | n  | Ld f64 | T = 4                  | T = 8                  | T = 12                 |
//! |----|--------|------------------------|------------------------|------------------------|
//! | 9  | 2.1    | 2,816 / 1,312 / 65     | 4,389 / 2,261 / 76     | 5,805 / 1,757 / 52     |
//! | 19 | 3.3    | 15,819 / 7,396 / 150   | 16,741 / 7,642 / 175   | 30,165 / 10,993 / 190  |
//! | 38 | 9.3    | 153,634 / 72,271 / 797 | 142,395 / 72,125 / 974 | 163,309 / 53,343 / 977 |
//!
//! (A first run gave T = 8: 13,742 µs at n = 19 and 95,333 µs at n = 38.) T = 16 was 2–3×
//! slower throughout. Forward duals through the recursion took 142 µs / 1.4 ms /
//! 13 ms and its adjoint route 11 / 44 / 146 µs: the hyper-dual tiles are 10–30× slower than
//! the former, so large robots need the adjoint gradient with
//! `autodiff::jacobian_directional` on top.

use std::hint::black_box;
use std::time::{Duration, Instant};
use vito::autodiff::{
    ScalarFunction, ThirdOrder, gradient_hessian_into, gradient_hessian_third_into, gradient_into,
};
use vito::discrete::MidpointSegment;
use vito::model::{BaseType, Model, sample};
use vito::random::SeededRng;

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
    let mut rng = SeededRng::new(42);
    for n in [9, 19, 38] {
        let model = match Model::from_urdf_str(&sample::planar_chain(n), BaseType::Fixed) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("planar_chain({n}) failed to load: {e}");
                return;
            }
        };
        let qa = rng.symmetric_vec(n, 0.5);
        let qb: Vec<f64> = qa
            .iter()
            .zip(rng.symmetric_vec(n, 0.5))
            .map(|(a, d)| a + 0.05 * d)
            .collect();
        let z: Vec<f64> = qa.iter().chain(&qb).copied().chain([0.03]).collect();
        let dir = rng.symmetric_vec(2 * n + 1, 0.5);
        let name = format!("del_segment_n{n}");
        let seg = MidpointSegment { model: &model };
        let plain = time_us(budget, || {
            black_box(seg.eval(black_box(&z[..])));
        });
        println!("{name:<16} plain f64 Ld {plain:.2} µs");
        bench_tile::<4>(&name, &model, &z, &dir, budget);
        bench_tile::<8>(&name, &model, &z, &dir, budget);
        bench_tile::<12>(&name, &model, &z, &dir, budget);
        bench_tile::<16>(&name, &model, &z, &dir, budget);
    }
}
