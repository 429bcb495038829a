//! The reference problems' "values at the initial guess" (no solver involved): objective, largest
//! constraint violation and ‖equality residuals‖₂, for hopper-2d and brick-3d, on the
//! closed-form mechanics of docs/reference-problems.md. Also the problem sizes.

use crate::common;

use common::analytic::{Brick, Hopper};
use common::reference::{brick_3d, hopper_2d};
use vito::transcription::Transcription;

fn close(found: f64, expected: f64, tol: f64) -> bool {
    (found - expected).abs() <= tol
}

#[test]
fn hopper_initial_guess_matches_spec() {
    let t = Transcription::new(Hopper, &hopper_2d()).unwrap();
    let r = t.initial_guess_report();
    println!("hopper-2d initial guess: {r:?}");
    assert!(close(r.objective, 20.041640625, 1e-9), "{r:?}");
    assert!(close(r.max_constraint_violation, 1.65, 1e-9), "{r:?}");
    assert!(close(r.equality_residual_norm, 7.93069, 5e-6), "{r:?}");
    // Independent CasADi value to all digits it printed.
    assert!(
        close(r.equality_residual_norm, 7.930688569805903, 1e-9),
        "{r:?}"
    );
}

#[test]
fn brick_initial_guess_matches_spec() {
    let t = Transcription::new(Brick, &brick_3d()).unwrap();
    let r = t.initial_guess_report();
    println!("brick-3d initial guess: {r:?}");
    assert!(close(r.objective, 400.0, 1e-9), "{r:?}");
    assert!(close(r.max_constraint_violation, 1.0, 1e-9), "{r:?}");
    assert!(close(r.equality_residual_norm, 1.43765, 5e-6), "{r:?}");
    assert!(
        close(r.equality_residual_norm, 1.4376470914219122, 1e-9),
        "{r:?}"
    );
}

#[test]
fn reference_problem_sizes() {
    let hopper = Transcription::new(Hopper, &hopper_2d()).unwrap();
    let l = hopper.layout();
    // 21·4 q + 4 v0 + 20 h + 20·2 u + 20·(1 + 2 + 1 + 2) contact + 20 s.
    assert_eq!(l.num_variables(), 84 + 4 + 20 + 40 + 120 + 20);
    // per interval: 4 DEL + 2 tangential + 1 φ + 1 cone + 3 complementarity.
    assert_eq!(l.num_constraints(), 20 * 11);
    assert_eq!(l.nd, 2, "the hopper is planar: one friction direction pair");
    let brick = Transcription::new(Brick, &brick_3d()).unwrap();
    let l = brick.layout();
    assert_eq!(l.nd, 4);
    assert_eq!(l.num_variables(), 41 * 6 + 6 + 40 + 40 * 8 * 10 + 40);
    assert_eq!(l.num_constraints(), 40 * (6 + 32 + 8 + 8 + 3));
}

/// A warm start into free equal steps keeps the previous solution's duration (within the
/// window) and resamples it over the knots by normalised time, so that a solution of the
/// same problem comes back knot for knot (at 0.8 s, not stretched to the guess T_max = 2.5 s).
#[test]
fn warm_start_into_free_steps_keeps_the_previous_duration() {
    use vito::problem::{InitialGuess, WarmStart};
    use vito::transcription::ModelMechanics;
    let mut spec = common::reference::spring_flamingo_walk();
    let (n, knots) = (spec.q_initial.len(), spec.knots);
    let duration = 0.8;
    let times: Vec<f64> = (0..knots)
        .map(|k| duration * k as f64 / (knots - 1) as f64)
        .collect();
    let q: Vec<Vec<f64>> = times
        .iter()
        .map(|&t| (0..n).map(|c| (3.0 * t + c as f64).sin()).collect())
        .collect();
    spec.initial_guess = InitialGuess::WarmStart(WarmStart {
        source: "memory".into(),
        times,
        q: q.clone(),
        u: Vec::new(),
        forces: Vec::new(),
    });
    let t = Transcription::new(ModelMechanics::load(&spec).unwrap(), &spec).unwrap();
    let (x, l) = (t.initial_point(), t.layout());
    let h = x[l.h(0)];
    assert!(
        (h * (knots - 1) as f64 - duration).abs() < 1e-12,
        "h = {h}: duration {} instead of {duration}",
        h * (knots - 1) as f64
    );
    // Interior knots carry the warm start (the first and last are fixed by the problem).
    for (k, qk) in q.iter().enumerate().take(knots - 1).skip(1) {
        for (c, i) in l.q(k).enumerate() {
            let (lo, hi) = (t.variable_bounds().0[i], t.variable_bounds().1[i]);
            if lo < hi && qk[c] > lo && qk[c] < hi {
                assert!((x[i] - qk[c]).abs() < 1e-12, "knot {k}, coordinate {c}");
            }
        }
    }
}

/// A warm start carrying contact forces (a coarser level's plan) gives each interval of the
/// finer grid the forces of the coarse interval holding its middle, times its own step, and
/// the sliding speeds, their duals and the slacks that meet the rows: tangential rows at
/// zero, complementarity rows satisfied, every ψ, η and slack at least zero.
#[test]
fn a_warm_start_carries_its_forces_to_a_finer_grid() {
    use vito::problem::{InitialGuess, TimeSteps, WarmStart};
    let mut spec = hopper_2d();
    let coarse: Vec<f64> = (0..21).map(|k| 0.05 * k as f64).collect();
    let q: Vec<Vec<f64>> = coarse
        .iter()
        .map(|&t| vec![0.5 * t, 0.5 - 0.1 * (3.0 * t).sin(), 0.2 * t, 0.5])
        .collect();
    let forces: Vec<Vec<Vec<f64>>> = (0..20)
        .map(|j| vec![vec![10.0 + j as f64, 2.0, 0.5 * j as f64]])
        .collect();
    spec.initial_guess = InitialGuess::WarmStart(WarmStart {
        source: "memory".into(),
        times: coarse,
        q,
        u: vec![vec![0.0, 0.0]; 20],
        forces,
    });
    spec.knots = 41;
    spec.time_steps = TimeSteps::Fixed(0.025);
    let t = Transcription::new(Hopper, &spec).unwrap();
    let (x, l) = (t.initial_point(), t.layout());
    assert_eq!(l.intervals(), 40);
    for j in 0..40 {
        let coarse = (j / 2) as f64;
        assert!(
            close(x[l.c(j, 0)], (10.0 + coarse) * 0.025, 1e-12),
            "c at {j}"
        );
        let beta = &x[l.beta(j, 0)];
        assert!(close(beta[0], 2.0 * 0.025, 1e-12), "β at {j}");
        assert!(close(beta[1], 0.5 * coarse * 0.025, 1e-12), "β at {j}");
    }
    let mut g = vec![0.0; l.num_constraints()];
    t.constraints(x, &mut g);
    let mut sliding = 0;
    for j in 0..40 {
        for r in l.rows_of("TangentialRate", j) {
            assert!(g[r].abs() < 1e-12, "tangential row {r}: {}", g[r]);
        }
        for r in l.rows_of("Complementarity", j) {
            assert!(g[r] > -1e-12, "complementarity row {r}: {}", g[r]);
        }
        assert!(x[l.psi(j, 0)] >= 0.0 && x[l.eta(j, 0)].iter().all(|&e| e >= 0.0));
        assert!(x[l.slack(j)].iter().all(|&s| s >= 0.0));
        sliding += usize::from(x[l.psi(j, 0)] > 0.0);
    }
    // The body moves forward at 0.5 m/s, so the foot slides wherever it is: ψ > 0.
    assert!(sliding > 30, "{sliding} sliding intervals");
}

/// `contacts.max_slip_speed` bounds every ψ from above and nothing else.
#[test]
fn max_slip_speed_bounds_every_psi() {
    let mut spec = hopper_2d();
    let free = Transcription::new(Hopper, &spec).unwrap();
    spec.max_slip_speed = Some(7.5);
    let bounded = Transcription::new(Hopper, &spec).unwrap();
    let l = bounded.layout();
    let mut psi = Vec::new();
    for j in 0..l.intervals() {
        for i in 0..l.nc {
            psi.push(l.psi(j, i));
        }
    }
    assert!(!psi.is_empty());
    let (upper_free, upper) = (free.variable_bounds().1, bounded.variable_bounds().1);
    for (v, (&a, &b)) in upper_free.iter().zip(upper).enumerate() {
        if psi.contains(&v) {
            assert_eq!((a, b), (f64::INFINITY, 7.5), "psi variable {v}");
        } else {
            assert_eq!(a, b, "variable {v} changed");
        }
    }
}
