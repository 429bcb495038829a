use vito::problem::load;
use vito::transcription::{ModelMechanics, Transcription};
#[test]
fn h_loop() {
    let p = load(std::path::Path::new("problems/hopper_2d.toml"), &[]).unwrap();
    let mut t = Transcription::new(ModelMechanics::load(&p.spec).unwrap(), &p.spec).unwrap();
    t.set_skip_fixed_variables(true);
    let x = t.initial_point().to_vec();
    let lambda = vec![1.0; t.layout().num_constraints()];
    let mut h = vec![0.0; t.hessian_pattern().nnz()];
    let mut j = vec![0.0; t.jacobian_pattern().nnz()];
    let mut g = vec![0.0; t.layout().num_constraints()];
    for _ in 0..3000 {
        t.hessian_values(&x, 1.0, &lambda, &mut h);
        t.jacobian_values(&x, &mut j);
        t.constraints(&x, &mut g);
    }
}
