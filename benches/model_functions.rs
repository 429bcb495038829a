//! Prints evaluation times of the model functions on the paper's robots (no assertions on
//! time). Run with `cargo bench --bench model_functions`.

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use num_dual::{Derivative, Dual64, DualSVec64};
use vito::model::{
    BaseType, Model, inverse_dynamics, kinetic_energy, mass_matrix, potential_energy,
};

fn robot(rel: &str, base: BaseType) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems/robots")
        .join(rel);
    Model::from_urdf_file(&path, base).unwrap_or_else(|e| panic!("{e}"))
}

/// Prints the minimum over 10 batches of the mean time per call (the minimum filters out
/// the time the shared machine spends on other processes).
fn time<F: FnMut()>(label: &str, reps: usize, mut f: F) {
    f();
    let mut best = f64::INFINITY;
    for _ in 0..10 {
        let start = Instant::now();
        for _ in 0..reps.div_ceil(10) {
            f();
        }
        best = best.min(start.elapsed().as_secs_f64() / reps.div_ceil(10) as f64);
    }
    println!("{label:<48} {:>10.2} µs", best * 1e6);
}

fn run<const N2: usize>(name: &str, model: &Model) {
    let n = model.nq();
    assert_eq!(2 * n, N2);
    let q: Vec<f64> = (0..n).map(|i| 0.01 * i as f64).collect();
    let v: Vec<f64> = (0..n).map(|i| 0.02 * i as f64 - 0.1).collect();
    time(&format!("{name} (n={n}) kinetic_energy f64"), 2000, || {
        black_box(kinetic_energy(model, black_box(&q), black_box(&v)));
    });
    time(
        &format!("{name} (n={n}) potential_energy f64"),
        2000,
        || {
            black_box(potential_energy(model, black_box(&q)));
        },
    );
    time(
        &format!("{name} (n={n}) inverse_dynamics f64"),
        2000,
        || {
            black_box(inverse_dynamics(model, black_box(&q), &v, &v));
        },
    );
    time(&format!("{name} (n={n}) mass_matrix f64"), 200, || {
        black_box(mass_matrix(model, black_box(&q)));
    });
    // Gradient of T in (q, v) in one pass: a DualSVec of size 2n.
    let qd: Vec<DualSVec64<N2>> = (0..n)
        .map(|i| {
            DualSVec64::new(
                q[i],
                Derivative::derivative_generic(nalgebra::Const::<N2>, nalgebra::U1, i),
            )
        })
        .collect();
    let vd: Vec<DualSVec64<N2>> = (0..n)
        .map(|i| {
            DualSVec64::new(
                v[i],
                Derivative::derivative_generic(nalgebra::Const::<N2>, nalgebra::U1, n + i),
            )
        })
        .collect();
    time(
        &format!("{name} (n={n}) kinetic_energy DualSVec64<2n>"),
        100,
        || {
            black_box(kinetic_energy(model, black_box(&qd), black_box(&vd)));
        },
    );
    let qe: Vec<Dual64> = q.iter().map(|&x| Dual64::new(x, 1.0)).collect();
    let ve: Vec<Dual64> = v.iter().map(|&x| Dual64::from(x)).collect();
    time(
        &format!("{name} (n={n}) kinetic_energy Dual64"),
        1000,
        || {
            black_box(kinetic_energy(model, black_box(&qe), black_box(&ve)));
        },
    );
}

fn print_model_timings() {
    run::<18>(
        "spring_flamingo",
        &robot(
            "spring_flamingo/spring_flamingo_passive_ankle.normalized.urdf",
            BaseType::Planar,
        ),
    );
    run::<36>(
        "littledog",
        &robot("littledog/LittleDog.normalized.urdf", BaseType::Floating),
    );
    run::<76>(
        "hamr",
        &robot("hamr/HAMR_scaledV2.normalized.urdf", BaseType::Floating),
    );
}

fn main() {
    print_model_timings();
}
