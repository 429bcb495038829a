//! `vito check` on every problem file under `problems/`, and its size report.

use std::path::Path;

use crate::cli::util::{TestDir, problems_dir, summary};

/// Every problem file validates and prints its size (quick: no solve).
#[test]
fn every_problem_file_checks() {
    let t = TestDir::new("every_problem_file_checks");
    let mut seen = 0;
    for entry in std::fs::read_dir(problems_dir()).unwrap() {
        let path = entry.unwrap().path();
        // The regression records (golden.toml, golden-slow.toml) are not problems.
        let record = path
            .file_name()
            .and_then(|n| n.to_str())
            .is_some_and(|n| n.starts_with("golden"));
        if path.extension().and_then(|e| e.to_str()) != Some("toml") || record {
            continue;
        }
        let run = t.vito().arg_path("check", &path).assert_exit(0);
        assert!(run.stdout.contains(": ok ("), "{}", run.stdout);
        seen += 1;
    }
    assert!(
        seen >= 4,
        "expected the four reference problems, saw {seen}"
    );
}

/// The sizes `vito check` reports match docs/reference-problems.md for the two paper robots,
/// and it names the slack weights each file's continuation solves at: Spring Flamingo's
/// homotopy from a thousandth of its `slack.weight` 1e4, LittleDog's `slack.target` from 300.
#[test]
fn check_reports_spec_sizes() {
    let t = TestDir::new("check_reports_spec_sizes");
    for (file, size, weight) in [
        (
            "spring_flamingo_walk.toml",
            "954 variables, 695 constraints",
            "slack weight 10, then ×10 per solve while the largest slack exceeds 1e-5, \
             at most 6 more, Ipopt's tolerances tied to the relaxation\n",
        ),
        (
            "littledog_step.toml",
            "2124 variables, 1333 constraints",
            "slack weight 300, then ×10 per solve while the largest slack exceeds 1e-5, \
             at most 3 more\n",
        ),
    ] {
        let run = t
            .vito()
            .arg_path("check", &problems_dir().join(file))
            .assert_exit(0);
        assert!(run.stdout.contains(size), "{file}: {}", run.stdout);
        assert!(run.stdout.contains(weight), "{file}: {}", run.stdout);
    }
}

/// The problem files under `problems/` (the regression records excluded).
fn problem_files() -> Vec<std::path::PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir(problems_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension().and_then(|e| e.to_str()) == Some("toml")
                && !p
                    .file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.starts_with("golden"))
        })
        .collect();
    files.sort();
    files
}

/// (variables, constraints, nnz J, nnz H) from `vito check`'s `NLP size:` line.
fn checked_size(stdout: &str) -> [u64; 4] {
    let line = stdout
        .lines()
        .find_map(|l| l.trim().strip_prefix("NLP size:"))
        .unwrap_or_else(|| panic!("no NLP size line in\n{stdout}"));
    let numbers: Vec<u64> = line
        .split(|c: char| !c.is_ascii_digit())
        .filter(|w| !w.is_empty())
        .take(4)
        .map(|w| w.parse().unwrap())
        .collect();
    numbers
        .try_into()
        .unwrap_or_else(|_| panic!("four sizes in `{line}`"))
}

/// The sizes of the NLP that `vito solve` built, from its `summary.json`.
fn solved_size(dir: &Path) -> [u64; 4] {
    let s = summary(dir);
    [
        "n_variables",
        "n_constraints",
        "nnz_jacobian",
        "nnz_hessian",
    ]
    .map(|k| {
        s[k].as_u64()
            .unwrap_or_else(|| panic!("{k} in summary.json"))
    })
}

/// `vito check` and a `vito solve` stopped before its first iteration agree on the sizes.
fn assert_check_matches_solve(t: &TestDir, file: &Path, set: &[&str]) -> [u64; 4] {
    let mut check = t.vito().arg_path("check", file);
    let out = t.path().join(file.file_stem().unwrap());
    let mut solve = t
        .vito()
        .arg_path("solve", file)
        .args(["--quiet", "--set", "solver.ipopt.max_iter=0", "--out"])
        .args([&out]);
    for s in set {
        check = check.args(["--set", s]);
        solve = solve.args(["--set", s]);
    }
    let checked = checked_size(&check.assert_exit(0).stdout);
    // Not optimal after no iteration (exit 1), except a passive problem, solved at its
    // simulation in none (exit 0); the outputs written either way.
    let run = solve.run();
    assert!(
        run.code == 1 || run.code == 0,
        "{}\n{}",
        run.stdout,
        run.stderr
    );
    assert_eq!(checked, solved_size(&out), "{}", file.display());
    checked
}

/// What `vito check` prints is the NLP the solver builds, for every problem file.
#[test]
fn check_size_is_the_solvers_for_every_problem_file() {
    let t = TestDir::new("check_size_is_the_solvers");
    let files = problem_files();
    assert!(files.len() >= 4, "{files:?}");
    for file in &files {
        // Sizes do not depend on the guess: a simulated one (HAMR, minutes) is replaced by
        // q_1 held, which `check` also uses.
        let text = std::fs::read_to_string(file).unwrap();
        let held: &[&str] = if text.contains("[initial_guess.simulation]") {
            &["initial_guess.to=initial"]
        } else {
            &[]
        };
        let [variables, constraints, ..] = assert_check_matches_solve(&t, file, held);
        assert!(variables > 0 && constraints > 0, "{}", file.display());
    }
}

/// With loop closures (HAMR, 24 rows per interval) the sizes count the loop impulses and rows
/// that a size derived apart from the solver once left out (252 / 130 instead of 300 / 202).
#[test]
fn check_size_counts_loop_closures() {
    let t = TestDir::new("check_size_counts_loop_closures");
    let urdf = problems_dir().join("robots/hamr/HAMR_scaledV2.normalized.urdf");
    let file = t.write(
        "hamr_three_knots.toml",
        &format!(
            r#"name = "hamr_three_knots"
[robot]
urdf = {urdf:?}
base = "floating"
units = "mm g ms"
gravity = [0.0, 0.0, -9.81e-3]

[horizon]
knots = 3
time_step = 0.1

[initial.q]
default = 0.0
base_z = 20.0

[slack]
weight = 100.0
"#
        ),
    );
    let [variables, constraints, ..] = assert_check_matches_solve(&t, &file, &[]);
    assert_eq!((variables, constraints), (300, 202));
}

/// `vito check --derivatives` passes on every problem file at its initial guess, with its own
/// integrator and with galerkin4, and names where it checked and its tolerance rule.
#[test]
fn every_problem_passes_the_derivative_check_at_its_initial_guess() {
    let t = TestDir::new("derivative_check_initial_guess");
    for file in problem_files() {
        // HAMR's 38 coordinates and 24 loop rows make a 51-knot finite-difference sweep take
        // minutes; 5 knots hold every block kind it has (first, interior and last knots).
        let text = std::fs::read_to_string(&file).unwrap();
        let knots: &[&str] = if text.contains("robots/hamr/") {
            &["--set", "horizon.knots=5"]
        } else {
            &[]
        };
        // As the file says, and with galerkin4 (interior points, their stationarity and φ rows).
        for integrator in [None, Some("solver.integrator=galerkin4")] {
            let run = t
                .vito()
                .args([std::ffi::OsStr::new("check"), "--derivatives".as_ref()])
                .args(knots)
                .args(integrator.map(|set| ["--set", set]).into_iter().flatten())
                .args([file.as_os_str()])
                .assert_exit(0);
            assert!(
                run.stdout.contains("derivative check at the initial guess")
                    && run.stdout.contains("tolerance:")
                    && run.stdout.trim_end().ends_with("passed"),
                "{} {integrator:?}: {}",
                file.display(),
                run.stdout
            );
        }
    }
}

/// `--at` checks at a solved trajectory (the hopper's own solution); a trajectory with
/// another knot count is an input error naming the file and the fix.
#[test]
fn derivative_check_at_a_solved_trajectory() {
    let t = TestDir::with_hopper("derivative_check_at");
    let problem = t.write("hopper.toml", &crate::cli::util::hopper_text());
    t.vito()
        .args(["solve", "hopper.toml", "--quiet", "--out", "solved"])
        .assert_exit(0);
    let trajectory = t.path().join("solved/trajectory.csv");
    // `vito check --derivatives --set SETS… --at CSV hopper.toml`, exiting with `code`.
    let check_at = |sets: &[&str], csv: &std::path::Path, code: i32| {
        t.vito()
            .args(["check", "--derivatives"])
            .args(sets.iter().flat_map(|&set| ["--set", set]))
            .args(["--at".as_ref(), csv.as_os_str(), problem.as_os_str()])
            .assert_exit(code)
    };
    let run = check_at(&[], &trajectory, 0);
    assert!(run.stdout.contains("trajectory.csv ("), "{}", run.stdout);
    // A galerkin4 plan, checked at its trajectory (interior points on the chord between its
    // knots).
    t.vito()
        .args(["solve", "hopper.toml", "--quiet", "--out", "g4"])
        .args(["--set", "solver.integrator=galerkin4"])
        .assert_exit(0);
    let run = check_at(
        &["solver.integrator=galerkin4"],
        &t.path().join("g4/trajectory.csv"),
        0,
    );
    assert!(run.stdout.trim_end().ends_with("passed"), "{}", run.stdout);
    let run = check_at(&["horizon.knots=11"], &trajectory, 2);
    assert!(
        run.stderr
            .contains("trajectory.csv: it has 21 rows, the problem has 11 knots"),
        "{}",
        run.stderr
    );
}

impl crate::cli::util::VitoCmd {
    /// `vito <command> <path>`.
    pub fn arg_path(self, command: &str, path: &std::path::Path) -> crate::cli::util::VitoCmd {
        self.args([std::ffi::OsStr::new(command), path.as_os_str()])
    }
}

/// LittleDog gives its feet as `[[contacts.point]]`: the URDF's ignored capsules are still
/// named, without the advice to add sphere collisions.
#[test]
fn the_sphere_advice_is_left_out_when_the_problem_gives_its_contacts() {
    let t = TestDir::new("the_sphere_advice_is_left_out_when_the_problem_gives_its_contacts");
    let problem = problems_dir().join("littledog_step.toml");
    let run = t.vito().args(["check".as_ref(), problem.as_os_str()]).run();
    assert!(
        run.stderr
            .contains("collision shapes other than spheres are ignored"),
        "{}",
        run.stderr
    );
    assert!(!run.stderr.contains("add a <sphere>"), "{}", run.stderr);
}
