//! The golden record `problems/golden.toml` and `vito regress`.

use crate::cli::util::{TestDir, hopper_text, problems_dir};

/// Every quick problem (hopper, brick) has an entry with a positive tolerance, so the solve
/// tests and `vito regress` check its objective.
#[test]
fn golden_record_lists_the_quick_problems() {
    let text = std::fs::read_to_string(problems_dir().join("golden.toml")).unwrap();
    let record: toml::Table = toml::from_str(&text).unwrap();
    let entries = record["problem"].as_array().unwrap();
    for file in ["hopper_2d.toml", "brick_3d.toml"] {
        let e = entries
            .iter()
            .find(|e| e["file"].as_str() == Some(file))
            .unwrap_or_else(|| panic!("{file} missing from golden.toml"));
        assert!(e["objective"].as_float().unwrap().is_finite());
        let tol = e["tolerance"].as_float().unwrap();
        assert!(tol > 0.0 && tol <= 1e-4, "{file}: tolerance {tol}");
        assert!(problems_dir().join(file).is_file());
    }
}

/// A problem that cannot be solved shows as FAIL in the table and the exit code is 1; the
/// record is not rewritten without --bless.
#[test]
fn regress_reports_a_failing_problem() {
    let t = TestDir::with_hopper("regress_reports_a_failing_problem");
    t.write(
        "broken.toml",
        &hopper_text().replace("knots = 21", "knots = 1"),
    );
    let record = "[[problem]]\nfile = \"broken.toml\"\nobjective = 1.0\ntolerance = 1e-6\nstatus = \"solve_succeeded\"\niterations = 3\nmax_slack = 0.0\n";
    t.write("golden.toml", record);
    let run = t
        .vito()
        .args(["regress", "--record", "golden.toml"])
        .assert_exit(1);
    let row = run
        .stdout
        .lines()
        .find(|l| l.starts_with("broken.toml"))
        .unwrap_or_default();
    assert!(
        row.contains("no result (exit 2)") && row.ends_with("FAIL"),
        "{}",
        run.stdout
    );
    assert_eq!(
        std::fs::read_to_string(t.path().join("golden.toml")).unwrap(),
        record
    );
}

/// An empty record with no files named is a usage error.
#[test]
fn regress_without_problems_is_an_input_error() {
    let t = TestDir::new("regress_without_problems_is_an_input_error");
    let run = t
        .vito()
        .args(["regress", "--record", "none.toml"])
        .assert_exit(2);
    assert!(
        run.stderr.contains("none.toml does not exist"),
        "{}",
        run.stderr
    );
}
