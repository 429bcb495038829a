//! A tilted ground (`[terrain.slope]`) with the plane's own contact frame: the brick of
//! `problems/brick_incline.toml` released at rest on it obeys Coulomb's law of the plane, in
//! the simulator and the planner, whichever way the plane falls.

use crate::cli::util::{TestDir, column_named, csv_columns, problems_dir, summary};

/// Base position columns (x, y, z) of a trajectory CSV, per knot.
fn base_positions(dir: &std::path::Path) -> Vec<[f64; 3]> {
    let columns = csv_columns(&std::fs::read_to_string(dir.join("trajectory.csv")).unwrap());
    let column = |name: &str| column_named(&columns, name);
    let (x, y, z) = (column("base_x"), column("base_y"), column("base_z"));
    (0..x.len()).map(|k| [x[k], y[k], z[k]]).collect()
}

/// Simulates the incline with `sets` (`--set` values) into `out`; its base positions.
fn simulate(t: &TestDir, out: &str, sets: &[&str]) -> Vec<[f64; 3]> {
    let file = problems_dir().join("brick_incline.toml");
    let mut cmd = t
        .vito()
        .args([std::ffi::OsStr::new("simulate"), file.as_os_str()])
        .args(["-q", "--out", out]);
    for s in sets {
        cmd = cmd.args(["--set", s]);
    }
    cmd.assert_exit(0);
    base_positions(&t.path().join(out))
}

/// μ = 0.5 > tan 20°: the brick stays where it was released (drift ≤ 1e-9 m over 1 s).
/// μ = 0.3 < tan 30°: it slides down the fall line with acceleration g (sin θ − μ cos θ)
/// (2.3563 m/s²), the midpoint rule's second differences within 1e-6 of it, the same for a
/// plane falling along +x and one falling along +y.
#[test]
fn a_brick_on_an_incline_stays_or_slides_as_coulomb_says() {
    let t = TestDir::new("a_brick_on_an_incline_stays_or_slides_as_coulomb_says");
    let rest = simulate(&t, "rest", &["angle=20", "mu=0.5"]);
    let first = rest[0];
    let drift = rest
        .iter()
        .flat_map(|p| (0..3).map(move |i| (p[i] - first[i]).abs()))
        .fold(0.0, f64::max);
    assert!(drift <= 1e-9, "drift {drift} m");

    let (angle, mu, g) = (30f64.to_radians(), 0.3, 9.81);
    let expected = g * (angle.sin() - mu * angle.cos());
    for (heading, fall) in [("0", [1.0, 0.0]), ("90", [0.0, 1.0])] {
        let sets = ["angle=30", "mu=0.3"];
        let heading_set = format!("heading={heading}");
        let p = simulate(
            &t,
            &format!("slide{heading}"),
            &[sets[0], sets[1], &heading_set],
        );
        let h = 0.025;
        for k in [10, 20, 39] {
            let a: Vec<f64> = (0..3)
                .map(|i| (p[k + 1][i] - 2.0 * p[k][i] + p[k - 1][i]) / (h * h))
                .collect();
            // Down the fall line: horizontal part a cos θ along the fall direction, the
            // vertical part −a sin θ, nothing across.
            let along = [
                expected * angle.cos() * fall[0],
                expected * angle.cos() * fall[1],
                -expected * angle.sin(),
            ];
            for i in 0..3 {
                assert!(
                    (a[i] - along[i]).abs() <= 1e-6 * expected,
                    "heading {heading}, knot {k}: acceleration {a:?}, expected {along:?}"
                );
            }
        }
    }
}

/// The planner solves the sliding brick (a problem without inputs) to the simulated motion,
/// with no slack, and its derivatives pass the finite-difference check at a plane falling
/// neither along x nor along y.
#[test]
fn the_planner_slides_the_brick_down_the_incline_as_the_simulator_does() {
    let t = TestDir::new("the_planner_slides_the_brick_down_the_incline_as_the_simulator_does");
    let file = problems_dir().join("brick_incline.toml");
    let sets = ["angle=30", "mu=0.3", "heading=90"];
    let simulated = simulate(&t, "sim", &sets);
    let mut cmd = t
        .vito()
        .args([std::ffi::OsStr::new("solve"), file.as_os_str()])
        .args(["-q", "--out", "plan"]);
    for s in sets {
        cmd = cmd.args(["--set", s]);
    }
    cmd.assert_exit(0);
    let s = summary(&t.path().join("plan"));
    assert_eq!(s["status"], "solve_succeeded", "{s}");
    assert_eq!(s["max_slack"].as_f64(), Some(0.0), "{s}");
    let planned = base_positions(&t.path().join("plan"));
    assert_eq!(planned.len(), simulated.len());
    for (k, (a, b)) in planned.iter().zip(&simulated).enumerate() {
        for i in 0..3 {
            assert!(
                (a[i] - b[i]).abs() < 1e-6,
                "knot {k}: plan {a:?}, simulation {b:?}"
            );
        }
    }
    // It slid: 0.5 a T² ≈ 1.18 m down the fall line over 1 s (y), nothing along x.
    let last = planned[planned.len() - 1];
    assert!(last[1] - planned[0][1] > 1.0, "{last:?}");
    assert!((last[0] - planned[0][0]).abs() < 1e-9, "{last:?}");

    let mut cmd = t
        .vito()
        .args([std::ffi::OsStr::new("check"), file.as_os_str()]);
    for s in ["angle=30", "mu=0.3", "heading=37"] {
        cmd = cmd.args(["--set", s]);
    }
    let run = cmd.args(["--derivatives"]).assert_exit(0);
    assert!(run.stdout.contains("passed"), "{}", run.stdout);
}

/// What a slope cannot carry is refused before anything runs, naming the field: a planar
/// robot on a plane falling across its x–z plane, steps on a slope, a tilt beyond 80°.
#[test]
fn a_slope_the_problem_cannot_carry_is_an_input_error() {
    let t = TestDir::with_hopper("a_slope_the_problem_cannot_carry_is_an_input_error");
    let hopper = crate::cli::util::hopper_text();
    for (name, terrain, field) in [
        (
            "across.toml",
            "[terrain.slope]\nangle = 10\nheading = 90\n",
            "terrain.slope.heading",
        ),
        (
            "steps.toml",
            "[terrain.slope]\nangle = 10\n[[terrain.step]]\nedge_x = 0.2\nrise = 0.1\nwidth = 0.01\n",
            "terrain.slope",
        ),
        (
            "steep.toml",
            "[terrain.slope]\nangle = 85\n",
            "terrain.slope.angle",
        ),
    ] {
        t.write(name, &format!("{hopper}\n{terrain}"));
        let run = t.vito().args(["check", name]).assert_exit(2);
        assert!(run.stderr.contains(field), "{name}: {}", run.stderr);
    }
    // Along x the hopper may stand on it.
    t.write(
        "along.toml",
        &format!("{hopper}\n[terrain.slope]\nangle = 10\nheading = 180\n"),
    );
    t.vito().args(["check", "along.toml"]).assert_exit(0);
}
