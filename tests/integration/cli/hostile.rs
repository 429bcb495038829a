//! Issue 11, items 5–17: hostile or careless input ends in one clear error (exit 2) naming
//! the file and field, before any solving, with nothing written; one test per item at least.

use crate::cli::errors::solve_fails;
use crate::cli::util::{TestDir, hopper_text};

/// `vito check` on `text` (as `bad.toml` next to the hopper's URDF) fails with exit 2 and
/// one error line, which it returns.
fn check_fails(name: &str, text: &str, extra: &[&str]) -> String {
    let t = TestDir::with_hopper(name);
    t.write("bad.toml", text);
    let run = t
        .vito()
        .args(["check", "bad.toml"])
        .args(extra)
        .assert_exit(2);
    let errors = run
        .stderr
        .lines()
        .filter(|l| l.starts_with("error:"))
        .count();
    assert_eq!(errors, 1, "one error expected:\n{}", run.stderr);
    run.stderr
}

/// Item 5: options that read or write files are refused in `check` and `solve`, naming the
/// option; the file named is neither created nor read.
#[test]
fn ipopt_options_outside_the_allow_list_are_refused() {
    let victim = std::env::temp_dir().join("vito-hostile-victim-output-file");
    let _ = std::fs::remove_file(&victim);
    for (key, value) in [
        ("output_file", format!("\"{}\"", victim.display())),
        ("option_file_name", "\"/etc/passwd\"".to_owned()),
        ("file_print_level", "12".to_owned()),
        ("linear_solver", "\"ma97\"".to_owned()),
        ("nlp_scaling_method", "\"equilibration-based\"".to_owned()),
    ] {
        let text = hopper_text()
            .replace("linear_solver = \"mumps\"\n", "")
            .replace("max_iter = 3000", &format!("{key} = {value}"));
        let err = check_fails(&format!("ipopt_allow_{key}"), &text, &[]);
        assert!(
            err.contains(&format!("field `solver.ipopt.{key}`")),
            "{err}"
        );
        assert!(err.contains("refused"), "{err}");
        let err = solve_fails(&format!("ipopt_allow_solve_{key}"), &text);
        assert!(err.contains(&format!("`solver.ipopt.{key}`")), "{err}");
        assert!(!victim.exists());
    }
    // Through --set as well.
    let err = check_fails(
        "ipopt_allow_set",
        &hopper_text(),
        &["--set", "solver.ipopt.output_file=\"x.log\""],
    );
    assert!(
        err.contains("solver.ipopt.output_file") && err.contains("--set"),
        "{err}"
    );
}

/// Item 5: Ipopt never reads an `ipopt.opt` from the working directory (one that would stop
/// the solve after one iteration changes nothing), and `--ipopt-log` writes Ipopt's log into
/// the output directory.
#[test]
fn ipopt_log_goes_into_the_output_directory_and_cwd_ipopt_opt_is_ignored() {
    let t = TestDir::with_hopper("ipopt_log");
    t.write("p.toml", &hopper_text());
    t.write("ipopt.opt", "max_iter 1\nlinear_solver ma97\n");
    let run = t
        .vito()
        .args(["solve", "p.toml", "--quiet", "--ipopt-log", "--out", "res"])
        .assert_exit(0);
    assert!(run.stdout.contains("solve_succeeded"), "{}", run.stdout);
    let log = std::fs::read_to_string(t.path().join("res/ipopt.log")).unwrap();
    assert!(log.contains("EXIT: Optimal Solution Found"), "{log}");
    assert!(log.contains("iter    objective"), "{log}");
    // Without the flag there is no log.
    t.vito()
        .args(["solve", "p.toml", "--quiet", "--out", "res"])
        .assert_exit(0);
    assert!(!t.path().join("res/ipopt.log").exists());
}

/// Item 9: non-finite numeric Ipopt options are input errors (`tol = nan` hung in MUMPS).
#[test]
fn non_finite_ipopt_options_are_input_errors() {
    for value in ["nan", "inf", "-inf"] {
        let text = hopper_text().replace("tol = 1e-6", &format!("tol = {value}"));
        let err = check_fails(
            &format!("ipopt_nonfinite_{}", value.replace('-', "m")),
            &text,
            &[],
        );
        assert!(err.contains("field `solver.ipopt.tol`"), "{err}");
        assert!(err.contains("finite"), "{err}");
    }
}
