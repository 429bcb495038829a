//! Prints the time per DEL segment of the midpoint Ld's derivatives, the Hessian alone (the
//! constraint Jacobian callback) and the Hessian plus the contracted third derivative (the
//! Lagrangian Hessian callback), by
//! (a) tiled forward duals through Ld: `gradient_hessian(_third)` on `MidpointSegment`;
//! (b) the autodiff drivers on the adjoint gradient: `jacobian` (+ `weighted_hessian`) on
//!     `MidpointGradient`;
//! (c) `midpoint_gradient_hessian` / `midpoint_third_order`: the Jacobian of the adjoint
//!     gradient, one column per pass, a nested `Dual64` carrying the multipliers;
//! and, to justify (c)'s layout, the same Jacobian by tiles of `num-dual` vector duals.
//! No assertions on time; the results are checked against each other.
//!
//! Run with `cargo bench --bench del_segment_paths`.

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use num_dual::{Dual, Dual64, DualSVec, DualSVec64};
use vito::autodiff::Scalar;
use vito::autodiff::{
    ThirdOrder, gradient_hessian, gradient_hessian_third, jacobian, weighted_hessian,
};
use vito::discrete::{
    LdBuffers, MidpointGradient, MidpointSegment, ld, midpoint_gradient_hessian,
    midpoint_ld_gradient, midpoint_third_order_into,
};
use vito::model::{BaseType, Model, sample};
use vito::random::SeededRng;

fn robot(rel: &str, base: BaseType) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems/robots")
        .join(rel);
    Model::from_urdf_file(&path, base).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Mean seconds per call: the minimum over 5 batches of about 40 ms each (the minimum filters
/// out time the shared machine spends elsewhere).
fn time<F: FnMut()>(mut f: F) -> f64 {
    let start = Instant::now();
    f();
    let once = start.elapsed().as_secs_f64();
    let reps = ((0.04 / once.max(1e-9)) as usize).clamp(1, 1_000_000);
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let start = Instant::now();
        for _ in 0..reps {
            f();
        }
        best = best.min(start.elapsed().as_secs_f64() / reps as f64);
    }
    best
}

/// The Jacobian of the adjoint gradient of Ld by tiles of `T` columns per pass, with the
/// scalar `S` built by `lift(i, tile slot or None)`; `read(y, k)` gives (H, W) entries of
/// output y for tile slot k, or None when y has no derivative part.
fn tiled<const T: usize, S: Scalar>(
    model: &Model,
    lift: impl Fn(usize, Option<usize>) -> S,
    read: impl Fn(&S, usize) -> Option<(f64, f64)>,
    out: &mut ThirdOrder,
) {
    let n = model.nq();
    let dim = 2 * n + 1;
    let mut zd: Vec<S> = (0..dim).map(|i| lift(i, None)).collect();
    let mut d1 = vec![S::from(0.0); n];
    let mut d2 = d1.clone();
    let mut buffers = LdBuffers::default();
    for start in (0..dim).step_by(T) {
        let cols = start..(start + T).min(dim);
        for (i, d) in zd.iter_mut().enumerate() {
            *d = lift(i, cols.contains(&i).then(|| i - start));
        }
        let (qa, qb, h) = (&zd[..n], &zd[n..2 * n], zd[2 * n]);
        let (_, dh) = midpoint_ld_gradient(model, qa, qb, h, &mut d1, &mut d2, &mut buffers);
        for (row, y) in d1.iter().chain(&d2).chain(std::iter::once(&dh)).enumerate() {
            for (k, col) in cols.clone().enumerate() {
                let (h, w) = read(y, k).unwrap_or((0.0, 0.0));
                out.hessian[(row, col)] = h;
                out.contracted[(row, col)] = w;
            }
        }
    }
}

/// Tiles of `DualSVec<Dual64, T>`: the tile outside, the direction inside.
fn tiled_direction_inside<const T: usize>(
    model: &Model,
    z: &[f64],
    dir: &[f64],
    out: &mut ThirdOrder,
) {
    tiled::<T, DualSVec<Dual64, T>>(
        model,
        |i, slot| {
            let d = DualSVec::<Dual64, T>::from_re(Dual64::new(z[i], dir[i]));
            slot.map_or(d, |k| d.derivative(k))
        },
        |y, k| y.eps.0.as_ref().map(|e| (e[k].re, e[k].eps)),
        out,
    );
}

/// Tiles of `Dual<DualSVec64<T>>`: the direction outside, the tile inside.
fn tiled_direction_outside<const T: usize>(
    model: &Model,
    z: &[f64],
    dir: &[f64],
    out: &mut ThirdOrder,
) {
    tiled::<T, Dual<DualSVec64<T>>>(
        model,
        |i, slot| {
            let re = DualSVec64::<T>::from_re(z[i]);
            let re = slot.map_or(re, |k| re.derivative(k));
            Dual::new(re, DualSVec64::from_re(dir[i]))
        },
        |y, k| {
            let h = y.re.eps.0.as_ref().map_or(0.0, |e| e[k]);
            let w = y.eps.eps.0.as_ref().map_or(0.0, |e| e[k]);
            Some((h, w))
        },
        out,
    );
}

fn run(name: &str, model: &Model, h: f64) {
    let n = model.nq();
    let mut rng = SeededRng::new(17);
    let qa = rng.symmetric_vec(n, 0.5);
    let step = rng.symmetric_vec(n, 0.01);
    let mut z = qa.clone();
    z.extend(qa.iter().zip(&step).map(|(a, d)| a + d));
    z.push(h);
    let mut dir = rng.symmetric_vec(2 * n, 1.0);
    dir.push(0.0);

    let segment = MidpointSegment { model };
    let grad_fn = MidpointGradient { model };
    let (mut d1, mut d2) = (vec![0.0; n], vec![0.0; n]);
    let us = |t: f64| t * 1e6;
    let t_ld = time(|| {
        black_box(ld(model, black_box(&z[..n]), &z[n..2 * n], z[2 * n]));
    });
    let t_grad = time(|| {
        black_box(midpoint_ld_gradient(
            model,
            black_box(&z[..n]),
            &z[n..2 * n],
            z[2 * n],
            &mut d1,
            &mut d2,
            &mut LdBuffers::default(),
        ));
    });
    println!(
        "{name} (n = {n}): Ld {:.2} µs, its adjoint gradient {:.2} µs",
        us(t_ld),
        us(t_grad)
    );

    // Hessian only.
    let h_a = time(|| {
        black_box(gradient_hessian(&segment, black_box(&z)));
    });
    let h_b = time(|| {
        black_box(jacobian(&grad_fn, black_box(&z)));
    });
    let h_c = time(|| {
        black_box(midpoint_gradient_hessian(model, black_box(&z)));
    });
    println!(
        "  Hessian            (a) {:>9.1} µs  (b) {:>9.1} µs ({:>5.1}×)  (c) {:>9.1} µs ({:>5.1}×)",
        us(h_a),
        us(h_b),
        h_a / h_b,
        us(h_c),
        h_a / h_c
    );

    // Hessian and contracted third derivative.
    let mut out = ThirdOrder::zeros(2 * n + 1);
    let t_a = time(|| {
        black_box(gradient_hessian_third(&segment, black_box(&z), &dir));
    });
    let t_b = time(|| {
        black_box(jacobian(&grad_fn, black_box(&z)));
        black_box(weighted_hessian(&grad_fn, black_box(&z), &dir));
    });
    let t_c = time(|| midpoint_third_order_into(model, black_box(&z), &dir, &mut out));
    println!(
        "  Hessian + third    (a) {:>9.1} µs  (b) {:>9.1} µs ({:>5.2}×)  (c) {:>9.1} µs ({:>5.1}×)",
        us(t_a),
        us(t_b),
        t_a / t_b,
        us(t_c),
        t_a / t_c
    );
    let mut tiles = ThirdOrder::zeros(2 * n + 1);
    let layouts = [
        time(|| tiled_direction_inside::<4>(model, black_box(&z), &dir, &mut tiles)),
        time(|| tiled_direction_inside::<8>(model, black_box(&z), &dir, &mut tiles)),
        time(|| tiled_direction_outside::<4>(model, black_box(&z), &dir, &mut tiles)),
        time(|| tiled_direction_outside::<8>(model, black_box(&z), &dir, &mut tiles)),
    ];
    println!(
        "  (c) by tiles: DualSVec<Dual64, 4> {:.1} µs, <8> {:.1} µs; Dual<DualSVec64<4>> {:.1} µs, <8> {:.1} µs",
        us(layouts[0]),
        us(layouts[1]),
        us(layouts[2]),
        us(layouts[3])
    );

    // All paths agree, so that the timings compare equal work.
    let reference = gradient_hessian_third(&segment, &z, &dir);
    let scale = reference.contracted.amax();
    let checks = [
        ("b", weighted_hessian(&grad_fn, &z, &dir)),
        ("c", out.contracted.clone()),
        ("tiles inside", {
            tiled_direction_inside::<8>(model, &z, &dir, &mut tiles);
            tiles.contracted.clone()
        }),
        ("tiles outside", {
            tiled_direction_outside::<8>(model, &z, &dir, &mut tiles);
            tiles.contracted.clone()
        }),
    ];
    for (label, w) in checks {
        let err = (&w - &reference.contracted).amax() / scale;
        assert!(err < 1e-9, "{name} {label}: relative difference {err:e}");
    }
    let err = (&midpoint_gradient_hessian(model, &z).2 - &reference.hessian).amax()
        / reference.hessian.amax();
    assert!(err < 1e-9, "{name} Hessian: relative difference {err:e}");
}

fn print_derivative_speed() {
    for n in [9, 19, 38] {
        let model = Model::from_urdf_str(&sample::planar_chain(n), BaseType::Fixed)
            .expect("planar chain loads");
        run(&format!("planar_chain({n})"), &model, 0.02);
    }
    run(
        "spring_flamingo",
        &robot(
            "spring_flamingo/spring_flamingo_passive_ankle.normalized.urdf",
            BaseType::Planar,
        ),
        0.02,
    );
    run(
        "littledog",
        &robot("littledog/LittleDog.normalized.urdf", BaseType::Floating),
        0.02,
    );
    let mut hamr = robot("hamr/HAMR_scaledV2.normalized.urdf", BaseType::Floating);
    hamr.set_gravity([0.0, 0.0, -9.81e-3]);
    run("hamr", &hamr, 0.3);
}

fn main() {
    print_derivative_speed();
}
