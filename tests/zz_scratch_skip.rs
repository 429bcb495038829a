use std::time::Instant;
use vito::problem::load;
use vito::transcription::{ModelMechanics, Transcription};
#[test]
fn skip_timing() {
    for f in ["problems/hopper_2d.toml", "problems/brick_3d.toml"] {
        let p = load(std::path::Path::new(f), &[]).unwrap();
        let mut t = Transcription::new(ModelMechanics::load(&p.spec).unwrap(), &p.spec).unwrap();
        let x = t.initial_point().to_vec();
        let lambda = vec![1.0; t.layout().num_constraints()];
        let mut h = vec![0.0; t.hessian_pattern().nnz()];
        let mut j = vec![0.0; t.jacobian_pattern().nnz()];
        let mut g = vec![0.0; t.layout().num_constraints()];
        for skip in [false, true, false, true] {
            t.set_skip_fixed_variables(skip);
            let s = Instant::now();
            for _ in 0..50 {
                t.hessian_values(&x, 1.0, &lambda, &mut h);
            }
            let th = s.elapsed().as_secs_f64() / 50.0;
            let s = Instant::now();
            for _ in 0..50 {
                t.jacobian_values(&x, &mut j);
            }
            let tj = s.elapsed().as_secs_f64() / 50.0;
            let s = Instant::now();
            for _ in 0..50 {
                t.constraints(&x, &mut g);
            }
            let tg = s.elapsed().as_secs_f64() / 50.0;
            println!(
                "{f} skip {skip}: H {:.3} ms, J {:.3} ms, g {:.3} ms",
                th * 1e3,
                tj * 1e3,
                tg * 1e3
            );
        }
    }
}
