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
    // The 21-knot level is the file's own solve: its optimum is the golden one.
    crate::cli::util::assert_recorded(
        "golden.toml",
        "hopper_2d.toml",
        levels[0]["objective"].as_f64().unwrap(),
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
    }
}
