//! `vito check` on every problem file under `problems/`, and its size report.

use crate::cli::util::{TestDir, problems_dir};

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

/// The sizes `vito check` reports match SPEC.md for the two paper robots.
#[test]
fn check_reports_spec_sizes() {
    let t = TestDir::new("check_reports_spec_sizes");
    for (file, size) in [
        (
            "spring_flamingo_walk.toml",
            "954 variables, 695 constraints",
        ),
        ("littledog_step.toml", "2124 variables, 1333 constraints"),
    ] {
        let run = t
            .vito()
            .arg_path("check", &problems_dir().join(file))
            .assert_exit(0);
        assert!(run.stdout.contains(size), "{file}: {}", run.stdout);
    }
}

impl crate::cli::util::VitoCmd {
    /// `vito <command> <path>`.
    pub fn arg_path(self, command: &str, path: &std::path::Path) -> crate::cli::util::VitoCmd {
        self.args([std::ffi::OsStr::new(command), path.as_os_str()])
    }
}
