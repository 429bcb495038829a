//! The derivative check (`Transcription::check_derivatives`, `vito check --derivatives`) of
//! the problem files at hard points: LittleDog with each foot in turn on the step's edge,
//! where the tanh step's slope is large and, a few widths away, exactly 0.0 (a structure
//! probed from values lost these entries); hopper and brick at seeded random points.

use std::path::PathBuf;

use crate::common::reference::loaded;
use vito::discrete::Mechanics;
use vito::pipeline::build_nlp;
use vito::problem::{LoadedProblem, Override, load};
use vito::random::SeededRng;
use vito::transcription::{
    DerivativeCheck, DerivativeKind, EntryNames, ModelMechanics, Transcription,
};

/// Asserts the check passes at x, printing the failures (by name) when it does not.
fn assert_passes(
    p: &LoadedProblem,
    nlp: &Transcription<ModelMechanics>,
    x: &[f64],
    what: &str,
) -> DerivativeCheck {
    let check = nlp.check_derivatives(x, 7);
    let contacts: Vec<String> = p.spec.contacts.iter().map(|c| c.name.clone()).collect();
    let names = EntryNames {
        coordinates: &p.robot.coordinates,
        inputs: &p.robot.inputs,
        contacts: &contacts,
    };
    let failures: Vec<String> = check
        .failures()
        .take(20)
        .map(|e| nlp.describe_entry(e, names))
        .collect();
    assert!(
        failures.is_empty(),
        "{what}: {} entries fail, the first:\n{}",
        check.failures().count(),
        failures.join("\n")
    );
    for kind in [DerivativeKind::Jacobian, DerivativeKind::Hessian] {
        assert!(
            check.worst(kind).is_some(),
            "{what}: no {kind:?} entry compared"
        );
    }
    check
}

/// LittleDog's initial guess with foot `foot` moved onto the step edge at every free knot:
/// the base is shifted along x so that the foot's world x lies at edge + s·w, s running
/// over [−0.9, 0.9] across the knots (w = 5 mm, the smoothing width).
fn foot_on_edge(nlp: &Transcription<ModelMechanics>, foot: usize) -> Vec<f64> {
    let l = nlp.layout();
    let mut x = nlp.initial_point().to_vec();
    let (edge, width) = (0.25, 0.005);
    for k in 1..l.knots {
        let q = x[l.q(k)].to_vec();
        let foot_x = nlp.mechanics().contact_position::<f64>(foot, &q)[0];
        let s = -0.9 + 1.8 * (k - 1) as f64 / (l.knots - 2) as f64;
        x[l.q(k).start] += edge + s * width - foot_x;
    }
    // A Galerkin member's interior points on the chord between the moved knots: their foot
    // lies between the knots' feet, on the edge too.
    if let Some(rule) = &nlp.context().galerkin {
        for j in 0..l.intervals() {
            let chord = rule.chord_interior(&x[l.q(j)], &x[l.q(j + 1)]);
            x[l.interior_points(j)].copy_from_slice(&chord);
        }
    }
    x
}

#[test]
fn littledog_passes_with_each_foot_on_the_step_edge() {
    littledog_passes_on_the_step_edge(&[], &[0, 1, 2, 3]);
}

/// The same with galerkin4 (interior points on the edge as well, their φ rows checked):
/// a front and a hind foot.
#[test]
fn littledog_galerkin4_passes_with_a_foot_on_the_step_edge() {
    littledog_passes_on_the_step_edge(&["solver.integrator=galerkin4"], &[0, 3]);
}

fn littledog_passes_on_the_step_edge(overrides: &[&str], feet: &[usize]) {
    let p = loaded("littledog_step", overrides);
    let nlp = build_nlp(&p.spec).unwrap();
    let l = nlp.layout();
    for &foot in feet {
        let x = foot_on_edge(&nlp, foot);
        let check = assert_passes(&p, &nlp, &x, &format!("foot {foot} on the edge"));
        // The terrain slope is in play: ∂φ/∂base_x at a mid knot is the normal's x part,
        // −H′/√(1 + H′²) ≈ −0.996 there (H′ ≈ 11), where flat ground has 0.
        let k = l.knots / 2;
        let slope = check
            .entries
            .iter()
            .find(|e| {
                e.kind == DerivativeKind::Jacobian
                    && e.row == l.rows_of("Distance", k - 1).start + foot
                    && e.col == l.q(k).start
            })
            .unwrap();
        assert!(
            slope.declared && slope.finite_difference < -0.99,
            "{slope:?}"
        );
        // And at an interior point of the interval after that knot (a Galerkin member).
        if l.interior > 0 {
            let slope = check
                .entries
                .iter()
                .find(|e| {
                    e.kind == DerivativeKind::Jacobian
                        && e.row == l.rows_of("InteriorDistance", k).start + foot
                        && e.col == l.interior(k, 0).start
                })
                .unwrap();
            assert!(
                slope.declared && slope.finite_difference < -0.99,
                "{slope:?}"
            );
        }
    }
}

/// The initial guess moved by seeded noise of size `a` (time steps scaled, kept positive).
fn random_point(nlp: &Transcription<ModelMechanics>, seed: u64, a: f64) -> Vec<f64> {
    let mut rng = SeededRng::new(seed);
    let l = nlp.layout();
    let mut x: Vec<f64> = nlp
        .initial_point()
        .iter()
        .map(|&v| v + rng.symmetric(a))
        .collect();
    for j in 0..l.intervals() {
        let h = l.h(j);
        x[h] = nlp.initial_point()[h] * (1.0 + rng.symmetric(0.5));
    }
    x
}

#[test]
fn hopper_and_brick_pass_at_random_points() {
    for (file, overrides) in [
        ("hopper_2d", vec![]),
        ("brick_3d", vec!["horizon.knots=11"]),
    ] {
        let p = loaded(file, &overrides);
        let nlp = build_nlp(&p.spec).unwrap();
        for seed in 1..=3 {
            let x = random_point(&nlp, seed, 0.3);
            assert_passes(&p, &nlp, &x, &format!("{file} seed {seed}"));
        }
    }
}

/// HAMR (38 coordinates, 12 loop closures: the loop rows and the loop impulses in the DEL
/// rows come from the analytic loop jets) passes the check at seeded random points, and its
/// Jacobian and Hessian equal generic AD over every block to round-off there.
#[test]
fn hamr_passes_at_random_points_and_matches_generic_ad() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("benches/hamr_standing.toml");
    let overrides = [Override::parse("horizon.knots=4").unwrap()];
    let p = load(&path, &overrides).unwrap();
    let mut nlp = build_nlp(&p.spec).unwrap();
    assert!(nlp.mechanics().num_loop_constraints() == 24);
    let rows = nlp.layout().num_constraints();
    let lambda: Vec<f64> = (0..rows).map(|r| 0.3 + 0.1 * (r % 7) as f64).collect();
    for seed in 1..=2 {
        let x = random_point(&nlp, seed, 0.2);
        assert_passes(&p, &nlp, &x, &format!("hamr seed {seed}"));
        let mut values = Vec::new();
        for chain_rule in [true, false] {
            nlp.set_contact_chain_rule(chain_rule);
            let mut jac = vec![0.0; nlp.jacobian_pattern().nnz()];
            let mut hess = vec![0.0; nlp.hessian_pattern().nnz()];
            nlp.jacobian_values(&x, &mut jac);
            nlp.hessian_values(&x, 0.7, &lambda, &mut hess);
            values.push((jac, hess));
        }
        nlp.set_contact_chain_rule(true);
        for (what, ours, theirs) in [
            ("jacobian", &values[0].0, &values[1].0),
            ("hessian", &values[0].1, &values[1].1),
        ] {
            let worst = ours
                .iter()
                .zip(theirs)
                .map(|(a, b)| (a - b).abs() / (1.0 + a.abs().max(b.abs())))
                .fold(0.0, f64::max);
            assert!(
                worst < 1e-10,
                "hamr seed {seed}: {what} differs by {worst:e}"
            );
        }
    }
}
