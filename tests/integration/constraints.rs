//! Problem-file constraint kinds (`problem::constraints`): `[[periodic]]` and its general
//! spelling `[[constraint]] type = "periodic"`, from the file to a solved trajectory.

use crate::common::reference::{appended, hopper_appended};
use vito::discrete::ModelMechanics;
use vito::pipeline::solve;
use vito::transcription::{SolveOptions, Transcription};

const SHORTHAND: &str = r#"
[[periodic]]
coordinate = "r"
position = false
velocity = true

[[periodic]]
coordinate = "theta"
position = false
velocity = true
"#;

const GENERAL: &str = r#"
[[constraint]]
type = "periodic"
coordinate = "r"
position = false
velocity = true

[[constraint]]
type = "periodic"
coordinate = "theta"
position = false
velocity = true
"#;

#[test]
fn both_spellings_build_the_same_nlp() {
    let a = hopper_appended(SHORTHAND).unwrap().spec;
    let b = hopper_appended(GENERAL).unwrap().spec;
    assert_eq!(a.constraints, b.constraints);
    let plain = hopper_appended("").unwrap().spec;
    let size = |spec| {
        let t = Transcription::new(ModelMechanics::load(spec).unwrap(), spec).unwrap();
        (t.size(), t.layout().constraint_rows.clone())
    };
    let (with, names) = size(&a);
    let (without, _) = size(&plain);
    assert_eq!(with.n_variables, without.n_variables);
    assert_eq!(with.n_constraints, without.n_constraints + 2);
    // Each velocity row reads q_1, q_2, h_1, q_{N−1}, q_N, h_{N−1} of its coordinate: 6
    // Jacobian entries; the hopper's steps are fixed, so Ipopt sees them all anyway.
    assert_eq!(with.nnz_jacobian, without.nnz_jacobian + 12);
    assert_eq!(names, ["periodic r velocity", "periodic theta velocity"]);
}

#[test]
fn a_solve_meets_the_periodic_rows() {
    let spec = hopper_appended(
        &(GENERAL.to_owned()
            + "\n[[constraint]]\ntype = \"periodic\"\ncoordinate = \"x\"\noffset = 0.5\n"),
    )
    .unwrap()
    .spec;
    let solution = solve(&spec, &SolveOptions::default()).unwrap();
    assert!(solution.status.is_success(), "{:?}", solution.status);
    let (q, h) = (&solution.q, &solution.time_steps);
    let last = q.len() - 1;
    let velocity = |k: usize, c: usize| (q[k + 1][c] - q[k][c]) / h[k];
    for c in [2, 3] {
        let gap = velocity(last - 1, c) - velocity(0, c);
        assert!(gap.abs() < 1e-7, "coordinate {c}: velocity gap {gap}");
    }
    assert!((q[last][0] - q[0][0] - 0.5).abs() < 1e-9);
    // The constraints change the optimum: the free hopper ends its hop with another leg
    // velocity than it starts with.
    let free = solve(&hopper_appended("").unwrap().spec, &SolveOptions::default()).unwrap();
    let (fq, fh) = (&free.q, &free.time_steps);
    let free_gap = (fq[last][3] - fq[last - 1][3]) / fh[last - 1] - (fq[1][3] - fq[0][3]) / fh[0];
    assert!(free_gap.abs() > 1e-3, "free leg-velocity gap {free_gap}");
}

#[test]
fn bad_constraint_entries_name_the_field() {
    let unknown = hopper_appended("\n[[constraint]]\ntype = \"periodic\"\ncoordinate = \"rr\"\n")
        .unwrap_err()
        .to_string();
    assert!(unknown.contains("constraint[0].coordinate"), "{unknown}");
    assert!(unknown.contains("`r`"), "{unknown}");
    let kind = hopper_appended("\n[[constraint]]\ntype = \"perodic\"\ncoordinate = \"r\"\n")
        .unwrap_err()
        .to_string();
    assert!(kind.contains("periodic"), "{kind}");
    let offset = hopper_appended("\n[[periodic]]\ncoordinate = \"x\"\noffset = nan\n")
        .unwrap_err()
        .to_string();
    assert!(offset.contains("periodic[0].offset"), "{offset}");
}

/// `periodic_momentum`'s rows take p_N⁻ from the last interval's DEL blocks and −M(q_1)v_0
/// from their own: at a random point they equal D2Ld + ½Fd − M(q_1)v_0 computed here
/// directly (D2Ld by dual numbers on the discrete Lagrangian), and Euler is refused.
#[test]
fn periodic_momentum_rows_are_the_end_momentum_minus_the_start_momentum() {
    use num_dual::Dual64;
    use vito::discrete::Mechanics;
    use vito::random::SeededRng;
    let spec = hopper_appended("\n[[constraint]]\ntype = \"periodic_momentum\"\n")
        .unwrap()
        .spec;
    let t = Transcription::new(ModelMechanics::load(&spec).unwrap(), &spec).unwrap();
    let (l, mech) = (t.layout(), t.mechanics());
    let (n, last) = (mech.nq(), l.knots - 1);
    let mut rng = SeededRng::new(17);
    let x: Vec<f64> = t
        .initial_point()
        .iter()
        .map(|&v| v + rng.symmetric(0.1))
        .collect();
    let mut g = vec![0.0; t.size().n_constraints];
    t.constraints(&x, &mut g);
    let (qa, qb, h) = (&x[l.q(last - 1)], &x[l.q(last)], x[l.h(last - 1)]);
    let mut force = vec![0.0; n];
    mech.discrete_force(qa, qb, &x[l.u(last - 1)], h, &mut force);
    let mut start = vec![0.0; n];
    mech.momentum(&x[l.q(0)], &x[l.v0()], &mut start);
    let lift = |q: &[f64]| q.iter().map(|&v| Dual64::from(v)).collect::<Vec<_>>();
    for c in 0..n {
        let mut qb_dual = lift(qb);
        qb_dual[c].eps = 1.0;
        let d2 = mech
            .discrete_lagrangian(&lift(qa), &qb_dual, Dual64::from(h))
            .eps;
        let expected = d2 + 0.5 * force[c] - start[c];
        let row = g[l.constraint_row(c)];
        assert!(
            (row - expected).abs() <= 1e-12 * expected.abs().max(1.0),
            "row {c}: {row} vs {expected}"
        );
    }
    let euler = appended(
        "hopper_2d",
        "robots/hopper_2d.urdf",
        "\n[[constraint]]\ntype = \"periodic_momentum\"\n",
        &["solver.integrator=\"euler\""],
    )
    .unwrap_err()
    .to_string();
    assert!(euler.contains("constraint[0].type"), "{euler}");
    assert!(euler.contains("midpoint"), "{euler}");
}
