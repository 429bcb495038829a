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

/// A problem that cannot be set up (an input error of its solve) is an input error of
/// `regress` (exit 2, naming the file and field), never a `FAIL`; the record is untouched.
#[test]
fn regress_setup_error_is_an_input_error_not_a_failure() {
    let t = TestDir::with_hopper("regress_setup_error_is_an_input_error_not_a_failure");
    t.write(
        "broken.toml",
        &hopper_text().replace("knots = 21", "knots = 1"),
    );
    let record = "[[problem]]\nfile = \"broken.toml\"\nobjective = 1.0\ntolerance = 1e-6\nstatus = \"solve_succeeded\"\niterations = 3\nmax_slack = 0.0\n";
    t.write("golden.toml", record);
    let run = t
        .vito()
        .args(["regress", "--record", "golden.toml"])
        .assert_exit(2);
    assert!(
        run.stderr.contains("broken.toml") && run.stderr.contains("field `horizon.knots`"),
        "{}",
        run.stderr
    );
    assert!(!run.stdout.contains("FAIL"), "{}", run.stdout);
    assert_eq!(
        std::fs::read_to_string(t.path().join("golden.toml")).unwrap(),
        record
    );
}

/// A user's own problem, in their own directory: `--bless FILE` makes the record beside it
/// (with the file's hash and the platform); a difference shows the terms, iterations and
/// slack beside the record and keeps the new solution; blessing through a symbolic link
/// is refused and writes nothing.
#[test]
fn regress_blesses_and_checks_a_users_own_problem() {
    let t = TestDir::with_hopper("regress_blesses_and_checks_a_users_own_problem");
    t.write("hop_up.toml", &hopper_text());
    let run = t
        .vito()
        .args(["regress", "--bless", "hop_up.toml"])
        .assert_exit(0);
    assert!(
        run.stdout
            .contains("blessed 1 of 1 problem(s) into golden.toml"),
        "{}",
        run.stdout
    );
    let text = std::fs::read_to_string(t.path().join("golden.toml")).unwrap();
    let record: toml::Table = toml::from_str(&text).unwrap();
    let e = &record["problem"].as_array().unwrap()[0];
    assert_eq!(e["file"].as_str(), Some("hop_up.toml"));
    let summary_hash = {
        use sha2::Digest;
        let bytes = std::fs::read(t.path().join("hop_up.toml")).unwrap();
        sha2::Sha256::digest(&bytes)
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect::<String>()
    };
    assert_eq!(e["problem_sha256"].as_str(), Some(summary_hash.as_str()));
    assert!(
        e["platform"]
            .as_str()
            .unwrap()
            .contains(std::env::consts::ARCH)
    );
    let objective = e["objective"].as_float().unwrap();

    // The record named through a link: read and compared.
    std::os::unix::fs::symlink("golden.toml", t.path().join("link.toml")).unwrap();
    let shifted = text.replace(
        &format!("objective = {objective:?}"),
        &format!("objective = {:?}", objective + 0.5),
    );
    assert_ne!(shifted, text);
    std::fs::write(t.path().join("golden.toml"), &shifted).unwrap();
    let run = t
        .vito()
        .args(["regress", "--record", "link.toml"])
        .assert_exit(1);
    assert!(run.stdout.contains("DIFF"), "{}", run.stdout);
    for shown in ["hop_up.toml (DIFF):", "input", "iterations", "max slack"] {
        assert!(run.stdout.contains(shown), "{shown}: {}", run.stdout);
    }
    // Each term now and as recorded: the bless recorded them, so no `-`.
    let recorded_terms = record_terms(&text);
    assert!(recorded_terms.contains_key("input"), "{text}");
    for (name, value) in &recorded_terms {
        let line = run
            .stdout
            .lines()
            .find(|l| l.trim_start().starts_with(&format!("{name} ")))
            .unwrap_or_else(|| panic!("a line for `{name}` in {}", run.stdout));
        let numbers: Vec<f64> = line
            .split_whitespace()
            .skip(1)
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(numbers.len(), 2, "{line}");
        assert!(
            (numbers[1] - value).abs() <= 1e-9 * value.abs().max(1.0),
            "{line}"
        );
    }
    let kept = run
        .stdout
        .lines()
        .find_map(|l| l.trim().strip_prefix("new solution kept in "))
        .expect("the kept solution's path");
    let kept = std::path::Path::new(kept);
    assert!(kept.join("summary.json").is_file() && kept.join("trajectory.csv").is_file());
    std::fs::remove_dir_all(kept.parent().unwrap()).unwrap();
    // Blessing through the link is refused before any solve: neither the link nor the
    // record it names is written.
    let run = t
        .vito()
        .args(["regress", "--bless", "--record", "link.toml"])
        .assert_exit(2);
    assert!(run.stderr.contains("symbolic link"), "{}", run.stderr);
    assert!(
        std::fs::symlink_metadata(t.path().join("link.toml"))
            .unwrap()
            .is_symlink()
    );
    assert_eq!(
        std::fs::read_to_string(t.path().join("golden.toml")).unwrap(),
        shifted
    );
    t.vito()
        .args(["regress", "--bless", "--record", "golden.toml"])
        .assert_exit(0);
    let blessed = std::fs::read_to_string(t.path().join("golden.toml")).unwrap();
    assert!(
        blessed.contains(&format!("objective = {objective:?}")),
        "{blessed}"
    );

    // A plain `vito regress` in the directory checks its golden.toml.
    let run = t.vito().args(["regress"]).assert_exit(0);
    assert!(
        run.stdout
            .lines()
            .any(|l| l.starts_with("hop_up.toml") && l.ends_with("ok")),
        "{}",
        run.stdout
    );
    // Naming a file checks that file only; blessing a problem that does not solve (the hop
    // onto the platform ends relaxed_contact) records nothing, says so and exits 1.
    let relaxed = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/problems/hop_up.toml"),
    )
    .unwrap()
    .replace("../../../problems/robots/", "robots/");
    t.write("relaxed.toml", &relaxed);
    let run = t
        .vito()
        .args(["regress", "--bless", "relaxed.toml"])
        .assert_exit(1);
    assert!(!run.stdout.contains("hop_up.toml"), "{}", run.stdout);
    assert!(run.stdout.contains("relaxed_contact"), "{}", run.stdout);
    assert!(
        run.stderr
            .contains("nothing blessed: none of the 1 problem(s) solved; golden.toml is unchanged"),
        "{}",
        run.stderr
    );
    assert_eq!(
        std::fs::read_to_string(t.path().join("golden.toml")).unwrap(),
        blessed
    );
}

/// The objective terms of a record's first entry.
fn record_terms(text: &str) -> std::collections::BTreeMap<String, f64> {
    let record: toml::Table = toml::from_str(text).unwrap();
    record["problem"].as_array().unwrap()[0]
        .get("terms")
        .and_then(|t| t.as_table())
        .map(|t| {
            t.iter()
                .map(|(k, v)| (k.clone(), v.as_float().unwrap()))
                .collect()
        })
        .unwrap_or_default()
}

/// The solves' scratch directory is a fresh private one: a directory planted at the old
/// predictable name (`$TMPDIR/vito-regress-<pid>-<record stem>`) is neither used nor emptied.
#[test]
fn regress_scratch_is_a_fresh_private_directory() {
    let t = TestDir::with_hopper("regress_scratch_is_a_fresh_private_directory");
    t.write("hop_up.toml", &hopper_text());
    let tmp = t.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    // `exec` keeps the shell's pid, so the shell knows the name vito would have used.
    let script = format!(
        "mkdir \"$TMPDIR/vito-regress-$$-golden\" && echo mine > \"$TMPDIR/vito-regress-$$-golden/keep.txt\" && exec '{}' regress --bless hop_up.toml",
        env!("CARGO_BIN_EXE_vito")
    );
    let output = std::process::Command::new("sh")
        .args(["-c", &script])
        .current_dir(t.path())
        .env("TMPDIR", &tmp)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("NEW"), "{stdout}");
    // Nothing of vito's left behind after a pass, and the planted directory untouched
    // (other libraries may leave their own: Debian 13's Open MPI writes `ompi.*` there).
    let left: Vec<String> = std::fs::read_dir(&tmp)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|name| name.starts_with("vito") || name.starts_with(".tmp"))
        .collect();
    assert_eq!(left.len(), 1, "{left:?}");
    let planted = tmp.join(&left[0]);
    assert_eq!(
        std::fs::read_dir(&planted).unwrap().count(),
        1,
        "{planted:?} was used"
    );
    assert_eq!(
        std::fs::read_to_string(planted.join("keep.txt")).unwrap(),
        "mine\n"
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

/// `TMPDIR` naming a directory that cannot exist (its parent is a regular file): a clear input
/// error (exit 2) before any solve. A merely missing directory is no test: on Debian 13 a
/// library that libipopt loads (OpenMPI, under MUMPS) creates `$TMPDIR` before `main` runs.
#[test]
fn regress_with_an_unusable_tmpdir_is_an_input_error() {
    let t = TestDir::with_hopper("regress_with_an_unusable_tmpdir_is_an_input_error");
    t.write("hop_up.toml", &hopper_text());
    let file = t.write("a-file", "not a directory");
    let run = t
        .vito()
        .args(["regress", "--bless", "hop_up.toml"])
        .env("TMPDIR", &file.join("tmp").to_string_lossy())
        .assert_exit(2);
    assert!(run.stderr.contains("TMPDIR"), "{}", run.stderr);
    assert!(!t.path().join("golden.toml").exists());
}
