//! Grid continuation: `vito solve` asked for a grid finer than its file's solves the file's
//! grid first and each doubling after it, every level started from the plan below.

use crate::cli::util::{TestDir, hopper_text, summary};

/// The hopper file as shipped (21 knots over 1 s) asked for at 41 knots: solved through the
/// 21-knot level, each level recorded (knots, verdict, objective, slack, iterations, how far
/// q moved from the level below), the total iterations their sum. Cold at 41 knots the same
/// NLP ended `relaxed_contact` (objective 88.0, slack 0.34). A grid not finer than the
/// file's, or `--no-refine`, is solved on its own.
#[test]
fn a_finer_grid_is_solved_through_the_files_grid() {
    let t = TestDir::with_hopper("a_finer_grid_is_solved_through_the_files_grid");
    t.write("p.toml", &hopper_text());
    let fine = [
        "--set",
        "horizon.knots=41",
        "--set",
        "horizon.time_step=0.025",
    ];
    let run = t
        .vito()
        .args(["solve", "p.toml", "--out", "fine"])
        .args(fine)
        .assert_exit(0);
    assert!(
        run.stderr
            .contains("grid continuation: 21 → 41 knots (the file's grid"),
        "{}",
        run.stderr
    );
    assert!(
        run.stderr.contains("level 1/2, 21 knots: solve_succeeded")
            && run.stderr.contains("level 2/2, 41 knots: solve_succeeded"),
        "{}",
        run.stderr
    );
    let s = summary(&t.path().join("fine"));
    assert_eq!(s["status"], "solve_succeeded", "{s}");
    assert_eq!(s["knots"], 41, "{s}");
    let levels = s["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 2, "{s}");
    assert_eq!(levels[0]["knots"], 21);
    assert_eq!(levels[1]["knots"], 41);
    for level in levels {
        assert_eq!(level["status"], "solve_succeeded", "{s}");
        assert!(level["max_slack"].as_f64().unwrap() <= 1e-6, "{s}");
    }
    assert!(levels[0]["max_q_difference"].is_null());
    // The finer level also solved the NLP with the 21-knot plan's contact modes fixed, and
    // kept the lower of that and the relaxed solve.
    assert!(levels[0]["carried_modes_kept"].is_null(), "{s}");
    let carried = &s["carried_modes"];
    assert_eq!(carried["status"], "solve_succeeded", "{s}");
    assert!(carried["fixed"]["touching"].as_u64().unwrap() > 0, "{s}");
    let kept = carried["kept"].as_bool().unwrap();
    assert_eq!(levels[1]["carried_modes_kept"], kept, "{s}");
    let carried_objective = carried["objective"].as_f64().unwrap();
    let objective = s["objective"].as_f64().unwrap();
    if kept {
        assert_eq!(objective, carried_objective, "{s}");
    } else {
        assert!(objective <= carried_objective, "{s}");
    }
    // The hopper's plan shifts by centimetres between 21 and 41 knots, not metres.
    let moved = levels[1]["max_q_difference"].as_f64().unwrap();
    assert!(moved > 0.0 && moved < 0.5, "{moved}");
    assert_eq!(
        s["iterations"].as_u64().unwrap(),
        levels
            .iter()
            .map(|l| l["iterations"].as_u64().unwrap())
            .sum::<u64>(),
        "{s}"
    );
    assert_eq!(s["objective"], levels[1]["objective"], "{s}");
    // The times are the levels' sums too, and vito's callbacks and Ipopt split them.
    let wall = s["wall_time_s"].as_f64().unwrap();
    let levels_wall: f64 = levels
        .iter()
        .map(|l| l["wall_time_s"].as_f64().unwrap())
        .sum();
    let split = s["callback_time_s"].as_f64().unwrap() + s["ipopt_time_s"].as_f64().unwrap();
    assert!((wall - levels_wall).abs() <= 1e-9 * wall, "{s}");
    assert!((wall - split).abs() <= 1e-6 * wall, "{s}");
    // The levels' plot: a panel per quantity, the knots along x.
    let svg = std::fs::read_to_string(t.path().join("fine/levels.svg")).unwrap();
    for panel in [
        "objective per level",
        "largest slack",
        "Ipopt iterations",
        "knots",
    ] {
        assert!(svg.contains(panel), "{panel}");
    }
    // The 21-knot level is the file's own solve: its optimum is the golden one.
    crate::cli::util::assert_recorded(
        "golden.toml",
        "hopper_2d.toml",
        levels[0]["objective"].as_f64().unwrap(),
    );

    // Starts explore the first level; the summary lists them, and the best is the plan the
    // level above refined.
    let run = t
        .vito()
        .args([
            "solve", "p.toml", "--out", "explored", "--starts", "3", "--jobs", "1",
        ])
        .args(fine)
        .run();
    assert!(run.code == 0 || run.code == 1, "{}", run.stderr);
    assert!(
        run.stdout.contains(
            "starts       on the first level (21 knots); the levels above refined the best"
        ),
        "{}",
        run.stdout
    );
    let s = summary(&t.path().join("explored"));
    let starts = s["starts"].as_array().unwrap();
    assert_eq!(starts.len(), 3, "{s}");
    let best = s["best_start"].as_u64().unwrap() as usize;
    assert_eq!(
        starts[best]["objective"], s["levels"][0]["objective"],
        "{s}"
    );

    for (name, extra) in [("own", &[][..]), ("alone", &["--no-refine"][..])] {
        let mut cmd = t.vito().args(["solve", "p.toml", "-q", "--out", name]);
        if name == "alone" {
            cmd = cmd.args(fine);
        }
        let run = cmd.args(extra).run();
        assert!(run.code == 0 || run.code == 1, "{}", run.stderr);
        assert!(!run.stderr.contains("grid continuation"), "{}", run.stderr);
        let s = summary(&t.path().join(name));
        assert!(s.get("levels").is_none(), "{s}");
        assert!(!t.path().join(name).join("levels.svg").exists());
    }
}

/// The hopper's ladder converges: asked for at 161 knots, its levels at 21, 41, 81 and 161
/// knots all solve, each optimum below the one before by less than the step before it
/// (measured: 6.9486, 6.3776, 6.0939, 5.9484; differences 0.571, 0.284, 0.146, first order as
/// the contact timing is). Cold at 161 knots the same NLP ended `relaxed_contact` at 30.55.
#[test]
fn the_hoppers_ladder_converges() {
    let t = TestDir::with_hopper("the_hoppers_ladder_converges");
    t.write("p.toml", &hopper_text());
    t.vito()
        .args(["solve", "p.toml", "-q", "--out", "fine"])
        .args([
            "--set",
            "horizon.knots=161",
            "--set",
            "horizon.time_step=0.00625",
        ])
        .assert_exit(0);
    let s = summary(&t.path().join("fine"));
    let levels = s["levels"].as_array().unwrap();
    let knots: Vec<u64> = levels
        .iter()
        .map(|l| l["knots"].as_u64().unwrap())
        .collect();
    assert_eq!(knots, [21, 41, 81, 161], "{s}");
    for level in levels {
        assert_eq!(level["status"], "solve_succeeded", "{s}");
        assert!(level["max_slack"].as_f64().unwrap() <= 1e-6, "{s}");
    }
    let optima: Vec<f64> = levels
        .iter()
        .map(|l| l["objective"].as_f64().unwrap())
        .collect();
    let steps: Vec<f64> = optima.windows(2).map(|w| w[0] - w[1]).collect();
    assert!(steps.iter().all(|&d| d > 0.0), "{optima:?}");
    assert!(
        steps.windows(2).all(|w| w[1] < 0.75 * w[0]),
        "successive differences do not shrink: {optima:?}"
    );
    // Within 3 % of the level before, and near the measured optimum.
    assert!(steps[2] < 0.03 * optima[2], "{optima:?}");
    assert!(optima[3] < 6.0, "{optima:?}");
}

/// A smooth problem's optimum converges at its integrator's order as the grid refines: the
/// double pendulum's swing (no contact; 11 knots over 1 s in its file) asked for at 21 to 161
/// knots, each solved through the levels below it. Once the grid resolves the swing, each
/// difference of successive optima is about a quarter of the one before it, the midpoint rule
/// being of second order (measured: 10.9309, 10.8365, 10.8132, 10.8074 from 21 to 161 knots,
/// ratios 4.07 and 3.96).
#[test]
fn a_smooth_optimum_converges_at_the_integrators_order() {
    let t = TestDir::new("a_smooth_optimum_converges_at_the_integrators_order");
    crate::common::swing::write_pendulum_swing(t.path());
    let (integrator, order) = ("midpoint", 2);
    let mut optima = Vec::new();
    for knots in [11_usize, 21, 41, 81, 161] {
        let out = format!("{integrator}{knots}");
        let step = format!("horizon.time_step={}", 1.0 / (knots - 1) as f64);
        let set_knots = format!("horizon.knots={knots}");
        let set_integrator = format!("solver.integrator=\"{integrator}\"");
        t.vito()
            .args(["solve", "swing.toml", "-q", "--out", &out])
            .args([
                "--set",
                &set_knots,
                "--set",
                &step,
                "--set",
                &set_integrator,
            ])
            .assert_exit(0);
        let s = summary(&t.path().join(&out));
        assert_eq!(s["status"], "solve_succeeded", "{s}");
        optima.push(s["objective"].as_f64().unwrap());
        if knots > 11 {
            let levels = s["levels"].as_array().unwrap();
            assert_eq!(levels.len(), 1 + (knots / 20).ilog2() as usize + 1, "{s}");
            assert_eq!(levels.last().unwrap()["knots"], knots, "{s}");
        }
    }
    let differences: Vec<f64> = optima.windows(2).map(|w| w[0] - w[1]).collect();
    let ratios: Vec<f64> = differences.windows(2).map(|w| w[0] / w[1]).collect();
    println!("{integrator}: optima {optima:?}, ratios {ratios:?}");
    let expected = f64::from(1 << order);
    for &ratio in &ratios[ratios.len() - 2..] {
        assert!(
            (ratio / expected - 1.0).abs() < 0.15,
            "{integrator}: ratio {ratio}, expected {expected}: {optima:?}"
        );
    }
}
