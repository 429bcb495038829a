//! A problem with no inputs is a simulation: `vito solve` returns the motion `vito simulate`
//! computes from the same file with the same step.

use crate::cli::util::{TestDir, csv_columns, problems_dir, summary};

/// The thrown brick at 81 knots, its file's 41 knots over 1 s doubled: it solves with no
/// slack, and its configurations at every knot are the ones `vito simulate` steps to at the
/// same rate (within the file's tolerance, 1e-6 m or rad), as is its final rest. Solved
/// cold, it ended at Ipopt's iteration limit with a slack of 3.2 after 300 s.
#[test]
fn a_passive_brick_at_81_knots_solves_to_its_simulation() {
    let t = TestDir::new("a_passive_brick_at_81_knots_solves_to_its_simulation");
    let file = problems_dir().join("brick_3d.toml");
    for knots in [81usize] {
        let steps = knots - 1;
        let plan = t.path().join(format!("plan-{knots}"));
        let sim = t.path().join(format!("sim-{knots}"));
        t.vito()
            .args([std::ffi::OsStr::new("solve"), file.as_os_str()])
            .args(["--quiet".as_ref(), "--out".as_ref(), plan.as_os_str()])
            .args(["--set", &format!("horizon.knots={knots}")])
            .args([
                "--set",
                &format!("horizon.time_step={}", 1.0 / steps as f64),
            ])
            .assert_exit(0);
        let s = summary(&plan);
        assert_eq!(s["status"], "solve_succeeded", "{s}");
        assert_eq!(s["max_slack"].as_f64(), Some(0.0), "{s}");
        assert_eq!(s["simulation_start"]["kept"], true, "{s}");
        assert_eq!(s["simulation_start"]["steps"], steps, "{s}");
        t.vito()
            .args([std::ffi::OsStr::new("simulate"), file.as_os_str()])
            .args(["--quiet".as_ref(), "--out".as_ref(), sim.as_os_str()])
            .args(["--rate", &steps.to_string(), "--duration", "1"])
            .assert_exit(0);
        let planned = csv_columns(&std::fs::read_to_string(plan.join("trajectory.csv")).unwrap());
        let simulated = csv_columns(&std::fs::read_to_string(sim.join("trajectory.csv")).unwrap());
        let mut compared = 0;
        for (name, values) in planned.iter().filter(|(n, _)| n.starts_with("base_")) {
            if name.ends_with("_dot") {
                continue;
            }
            let (_, other) = simulated
                .iter()
                .find(|(n, _)| n == name)
                .unwrap_or_else(|| panic!("no column {name} in the simulation"));
            assert_eq!(values.len(), knots, "{name}");
            assert_eq!(other.len(), knots, "{name}");
            for (k, (a, b)) in values.iter().zip(other).enumerate() {
                // Within the file's Ipopt tol (1e-6): Ipopt 3.11 takes the simulated point
                // as it is (0 iterations), Ipopt 3.14 moves it by 1e-8.
                assert!(
                    (a - b).abs() < 1e-6,
                    "{knots} knots: {name} at knot {k}: plan {a}, simulation {b}"
                );
            }
            compared += 1;
        }
        assert_eq!(compared, 6);
        // Thrown at 1 m/s, the brick has landed and stopped well before 1 s: at rest, a
        // little downstream of where it was thrown, on the ground.
        let col = |name: &str| &planned.iter().find(|(n, _)| n == name).unwrap().1;
        let x = col("base_x");
        let z = col("base_z");
        assert!(
            x[steps] > 0.05 && (x[steps] - x[steps - 1]).abs() < 1e-6,
            "{x:?}"
        );
        assert!(
            z[steps] < 0.1 && (z[steps] - z[steps - 1]).abs() < 1e-6,
            "{z:?}"
        );
    }
}
