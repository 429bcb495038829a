//! The transcription on robots loaded from URDF: the sizes and values at the initial
//! guess for all four reference problems, and agreement of the URDF hopper and brick with
//! the closed-form mechanics at random points.

use crate::common;

use common::analytic::{Brick, Hopper};
use common::reference::{brick_3d, hopper_2d, littledog_step, spring_flamingo_walk};
use vito::discrete::{MechanicsDerivatives, ModelMechanics};
use vito::problem::{Integrator, ProblemSpec};
use vito::random::SeededRng;
use vito::transcription::{InitialGuessReport, Transcription};

fn report(spec: &ProblemSpec) -> (Transcription<ModelMechanics>, InitialGuessReport) {
    let t = Transcription::new(ModelMechanics::load(spec).unwrap(), spec).unwrap();
    let r = t.initial_guess_report();
    println!(
        "{}: {r:?}; {} variables, {} constraints, J nnz {}, H nnz {}",
        spec.name,
        t.layout().num_variables(),
        t.layout().num_constraints(),
        t.jacobian_pattern().nnz(),
        t.hessian_pattern().nnz()
    );
    (t, r)
}

fn close(found: f64, expected: f64, rel: f64) -> bool {
    (found - expected).abs() <= rel * expected.abs().max(1.0)
}

#[test]
fn hopper_and_brick_from_urdf_match_spec_initial_values() {
    let (_, r) = report(&hopper_2d());
    assert!(close(r.objective, 20.041640625, 1e-12), "{r:?}");
    assert!(close(r.max_constraint_violation, 1.65, 1e-12), "{r:?}");
    assert!(
        close(r.equality_residual_norm, 7.930688569805903, 1e-10),
        "{r:?}"
    );
    let (_, r) = report(&brick_3d());
    assert!(close(r.objective, 400.0, 1e-12), "{r:?}");
    assert!(close(r.max_constraint_violation, 1.0, 1e-12), "{r:?}");
    assert!(
        close(r.equality_residual_norm, 1.4376470914219122, 1e-10),
        "{r:?}"
    );
}

#[test]
fn spring_flamingo_matches_spec_sizes_and_initial_values() {
    // The spec's values are at the slack weight α = 1e4. The file's homotopy starts its first
    // solve at α / 1000, where the slack term, 2400 of the 2400.1, is a thousandth as large.
    let one_solve = ["slack.homotopy=false", "slack.tied_tolerances=false"];
    let (t, r) = report(&common::reference::loaded("spring_flamingo_walk", &one_solve).spec);
    let (_, first) = report(&spring_flamingo_walk());
    assert!(close(first.objective, 2.499870703125, 1e-10), "{first:?}");
    assert_eq!(t.layout().num_variables(), 954);
    assert_eq!(t.layout().num_constraints(), 695);
    // Counted by hand: 10881 and 4760. The structure by dependencies holds 142 and 89 more:
    // entries that are zero by algebraic cancellation (sin² + cos² = 1 in a rotated velocity's
    // norm), which dependencies cannot see; none is left out (the derivative check).
    assert_eq!(t.jacobian_pattern().nnz(), 11023);
    assert_eq!(t.hessian_pattern().nnz(), 4849);
    assert!(close(r.objective, 2400.099870703126, 1e-10), "{r:?}");
    assert!(close(r.max_constraint_violation, 14.4959675, 1e-8), "{r:?}");
    assert!(
        close(r.equality_residual_norm, 70.2622742619474, 1e-10),
        "{r:?}"
    );
}

#[test]
fn littledog_matches_spec_sizes_and_initial_values() {
    let (t, r) = report(&littledog_step());
    assert_eq!(t.layout().num_variables(), 2124);
    assert_eq!(t.layout().num_constraints(), 1333);
    // The structure comes from dependencies (entries zero by cancellation, as for Spring
    // Flamingo): on the step's profile the tangential coordinate up the step depends on the
    // foot's height as well as its x (τ = S(x) + H′/σ·(z − H), the surface's frame), so a
    // foot's tangential rows depend on every coordinate that moves the foot in x or z. A
    // structure probed from values would lose the step's entries wherever a foot was far
    // from the edge.
    assert_eq!(t.jacobian_pattern().nnz(), 37138);
    assert_eq!(t.hessian_pattern().nnz(), 16976);
    assert!(close(r.objective, 87.026825, 1e-8), "{r:?}");
    // The guess's feet cross the edge: the distance along the unit normal, (z − H)/σ.
    assert!(
        close(r.max_constraint_violation, 3.693678427727354, 1e-8),
        "{r:?}"
    );
    assert!(
        close(r.equality_residual_norm, 19.696784004023183, 1e-10),
        "{r:?}"
    );
}

/// Constraint values of the URDF and closed-form transcriptions at the same random points.
fn compare<A: MechanicsDerivatives, B: MechanicsDerivatives>(
    spec: &ProblemSpec,
    a: A,
    b: B,
) -> f64 {
    let ta = Transcription::new(a, spec).unwrap();
    let tb = Transcription::new(b, spec).unwrap();
    let mut rng = SeededRng::new(12345);
    let mut worst = 0.0_f64;
    for _ in 0..3 {
        let x: Vec<f64> = ta
            .initial_point()
            .iter()
            .map(|&v| v + 0.1 * (rng.unit() - 0.5))
            .collect();
        let m = ta.layout().num_constraints();
        let (mut ga, mut gb) = (vec![0.0; m], vec![0.0; m]);
        ta.constraints(&x, &mut ga);
        tb.constraints(&x, &mut gb);
        for (u, v) in ga.iter().zip(&gb) {
            worst = worst.max((u - v).abs() / v.abs().max(1.0));
        }
        assert!((ta.objective(&x) - tb.objective(&x)).abs() < 1e-10);
    }
    worst
}

/// Both integrators; with Euler the URDF rows come from the model's inverse dynamics and
/// the closed-form rows from the trait's default (Ld, momentum and Fd), so the Euler case
/// checks two independent derivations of eq. (1).
#[test]
fn urdf_and_closed_form_mechanics_agree() {
    for integrator in [Integrator::Midpoint, Integrator::Euler] {
        let mut spec = hopper_2d();
        spec.integrator = integrator;
        let worst = compare(&spec, ModelMechanics::load(&spec).unwrap(), Hopper);
        println!("hopper {integrator:?}: largest relative difference of g {worst:.1e}");
        assert!(worst < 1e-10);
        let mut spec = brick_3d();
        spec.integrator = integrator;
        let worst = compare(&spec, ModelMechanics::load(&spec).unwrap(), Brick);
        println!("brick {integrator:?}: largest relative difference of g {worst:.1e}");
        assert!(worst < 1e-10);
    }
}

/// A Galerkin member of degree s adds (s − 1)·n interior-point variables per interval, with
/// (s − 1)·n stationarity rows and (s − 1)·nc non-penetration rows; the midpoint rule's
/// variables and rows are all still there (hopper: n = 4, nc = 1, 20 intervals).
#[test]
fn galerkin_transcription_adds_interior_points_and_their_rows() {
    let midpoint = hopper_2d();
    let base = Transcription::new(ModelMechanics::load(&midpoint).unwrap(), &midpoint).unwrap();
    let (v, r) = (
        base.layout().num_variables(),
        base.layout().num_constraints(),
    );
    assert_eq!((v, r), (288, 220));
    for (integrator, s) in [(Integrator::Galerkin4, 2), (Integrator::Galerkin6, 3)] {
        let mut spec = hopper_2d();
        spec.integrator = integrator;
        let t = Transcription::new(ModelMechanics::load(&spec).unwrap(), &spec).unwrap();
        let l = t.layout();
        assert_eq!(l.num_variables(), v + 20 * (s - 1) * 4, "{integrator:?}");
        assert_eq!(
            l.num_constraints(),
            r + 20 * (s - 1) * (4 + 1),
            "{integrator:?}"
        );
        // The interior points start on the chord between their knots.
        let x = t.initial_point();
        let d = integrator.galerkin_rule().unwrap().nodes()[1];
        for c in 0..4 {
            let (a, b) = (x[l.q(3).start + c], x[l.q(4).start + c]);
            let interior = x[l.interior(3, 0).start + c];
            assert!((interior - ((1.0 - d) * a + d * b)).abs() < 1e-15);
        }
    }
}

/// A galerkin4 plan read back from its `trajectory.csv` as an NLP point (`vito check --at`):
/// the interior points, not in the file, are put where the intervals' dynamics put them, so
/// their stationarity rows hold there to the solver's tolerance (on the chord between the
/// knots they would be off by the interval's curvature).
#[test]
fn galerkin_plan_read_back_has_its_interior_points() {
    use vito::ipopt::OptionValue;
    use vito::transcription::SolveOptions;
    let load = crate::common::reference::loaded("hopper_2d", &["solver.integrator=galerkin4"]);
    let options = SolveOptions {
        ipopt_options: vec![("print_level".into(), OptionValue::Int(0))],
        ..SolveOptions::default()
    };
    let plan = vito::pipeline::solve(&load.spec, &options).expect("solves");
    assert!(plan.verdict().is_solved());
    let units = vito::report::column_units(&load.robot, &load.units);
    let text = vito::report::trajectory_csv(&plan, &units);
    let nlp = vito::pipeline::build_nlp(&load.spec).unwrap();
    let contacts: Vec<String> = load.spec.contacts.iter().map(|c| c.name.clone()).collect();
    let mut x = vito::pipeline::trajectory_point::point_from_trajectory(
        &nlp,
        &load.robot,
        &contacts,
        &text,
    )
    .unwrap();
    let l = nlp.layout();
    let stationarity = |x: &[f64]| {
        let mut g = vec![0.0; l.num_constraints()];
        nlp.constraints(x, &mut g);
        (0..l.intervals())
            .flat_map(|j| l.rows_of("GalerkinForce", j))
            .fold(0.0_f64, |a, r| a.max(g[r].abs()))
    };
    let restored = stationarity(&x);
    nlp.set_interior_points(&mut x, false);
    let chord = stationarity(&x);
    println!("interior stationarity: restored {restored:.3e}, on the chord {chord:.3e}");
    assert!(restored < 1e-8, "{restored}");
    assert!(chord > 1e3 * restored.max(1e-12), "{chord}");
}
