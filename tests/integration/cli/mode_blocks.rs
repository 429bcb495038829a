//! `contacts.mode_block`: blocks of one interval are the reference NLP (the same solve as without
//! the key, at the independent optimum); blocks of two give a plan with one contact mode per
//! block, checked from the configurations and impulses of its trajectory CSV with the hand-written hopper's
//! kinematics; bad values are input errors.

use crate::cli::errors::solve_fails;
use crate::cli::util::{TestDir, hopper_text, problems_dir, summary};
use crate::common::analytic::Hopper;
use vito::discrete::Mechanics;

/// Solves the shipped hopper with `sets` into `out` and returns its summary.
fn solve_hopper(t: &TestDir, out: &str, sets: &[&str]) -> serde_json::Value {
    let file = problems_dir().join("hopper_2d.toml");
    let mut args = vec!["solve".to_owned(), file.display().to_string(), "-q".into()];
    for s in sets {
        args.push("--set".into());
        args.push((*s).into());
    }
    args.extend(["--out".into(), out.into()]);
    t.vito().args(&args).assert_exit(0);
    summary(&t.path().join(out))
}

#[test]
fn blocks_of_one_interval_are_the_spec_nlp() {
    let t = TestDir::new("mode_block_one");
    let default = solve_hopper(&t, "default", &[]);
    let one = solve_hopper(&t, "one", &["contacts.mode_block=1"]);
    // The same NLP gives the same solve, iterate for iterate, on whatever Ipopt runs it.
    for key in [
        "iterations",
        "objective",
        "nnz_jacobian",
        "nnz_hessian",
        "n_constraints",
    ] {
        assert_eq!(default[key], one[key], "{key}");
    }
    // The reference hopper: its pattern, and the independent CasADi optimum (relative 1e-6).
    assert_eq!(one["nnz_jacobian"], 2152);
    assert_eq!(one["nnz_hessian"], 1044);
    let objective = one["objective"].as_f64().unwrap();
    let casadi = 6.948567241208028;
    assert!(
        ((objective - casadi) / casadi).abs() < 1e-6,
        "objective {objective} against CasADi's {casadi}"
    );
}

/// Per block of `m` intervals: (whether some interval has a normal impulse above `tol`,
/// whether the foot is above `tol` at some knot an impulse of the block acts on), with the
/// foot height from q by the hand-written hopper, on flat ground.
fn block_modes(dir: &std::path::Path, m: usize, tol: f64) -> Vec<(bool, bool)> {
    let text = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let cols = crate::cli::util::csv_columns(&text);
    let col = |name: &str| &cols.iter().find(|c| c.0 == name).unwrap().1;
    let (x, z, theta, r) = (col("x"), col("z"), col("theta"), col("r"));
    let normal = col("foot_contact_normal");
    let intervals = x.len() - 1;
    let height = |k: usize| Hopper.contact_position(0, &[x[k], z[k], theta[k], r[k]])[2];
    (0..intervals)
        .step_by(m)
        .map(|start| {
            let block = start..(start + m).min(intervals);
            let pushes = block.clone().any(|j| normal[j] > tol);
            let apart = block.clone().any(|j| height(j + 1) > tol);
            (pushes, apart)
        })
        .collect()
}

#[test]
fn blocks_of_two_intervals_hold_one_contact_mode() {
    let t = TestDir::new("mode_block_two");
    let tol = 1e-6;
    let s = solve_hopper(&t, "two", &["contacts.mode_block=2"]);
    assert_eq!(s["status"], "solve_succeeded");
    assert!(
        s["max_slack"].as_f64().unwrap() <= 1e-8,
        "{}",
        s["max_slack"]
    );
    let modes = block_modes(&t.path().join("two"), 2, tol);
    assert_eq!(modes.len(), 10);
    for (b, &(pushes, apart)) in modes.iter().enumerate() {
        assert!(
            !(pushes && apart),
            "block {b} pushes and leaves the ground: {modes:?}"
        );
    }
    // The plan has stance and flight blocks, and the check has teeth: the plan with a mode
    // per interval pushes and flies within one pair of intervals.
    assert!(
        modes.iter().any(|m| m.0) && modes.iter().any(|m| m.1),
        "{modes:?}"
    );
    solve_hopper(&t, "one", &[]);
    let per_interval = block_modes(&t.path().join("one"), 2, tol);
    assert!(
        per_interval.iter().any(|&(pushes, apart)| pushes && apart),
        "{per_interval:?}"
    );
}

#[test]
fn mode_block_must_be_a_whole_number_of_intervals_in_the_horizon() {
    for (value, says) in [
        ("0", "got 0"),
        ("-2", "got -2"),
        ("21", "to the horizon's 20 intervals, got 21"),
    ] {
        let text = hopper_text().replace(
            "friction = 0.8",
            &format!("friction = 0.8\nmode_block = {value}"),
        );
        let err = solve_fails(&format!("mode_block_{value}"), &text);
        assert!(err.contains("field `contacts.mode_block`"), "{err}");
        assert!(err.contains(says), "{err}");
    }
    let text = hopper_text().replace("friction = 0.8", "friction = 0.8\nmode_block = 2.5");
    let err = solve_fails("mode_block_fraction", &text);
    assert!(err.contains("contacts.mode_block"), "{err}");
    // The largest block, the whole horizon, is accepted.
    let t = TestDir::with_hopper("mode_block_whole_horizon");
    t.write(
        "whole.toml",
        &hopper_text().replace("friction = 0.8", "friction = 0.8\nmode_block = 20"),
    );
    t.vito().args(["check", "whole.toml"]).assert_exit(0);
}
