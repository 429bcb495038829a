//! Output directories never cost a user a file: every refused target
//! ends in exit 2 before solving, and what was there is left as it was.

use crate::cli::util::{TestDir, hopper_text};

/// A directory holding the hopper problem, its robot and some of the user's own files.
fn workspace(name: &str) -> TestDir {
    let t = TestDir::with_hopper(name);
    t.write("prob.toml", &hopper_text());
    t.write("notes.txt", "my notes");
    std::fs::create_dir(t.path().join("work")).unwrap();
    t.write("work/thesis.tex", "my thesis");
    t
}

fn untouched(t: &TestDir) {
    let read = |p: &str| std::fs::read_to_string(t.path().join(p)).unwrap();
    assert_eq!(read("prob.toml"), hopper_text());
    assert_eq!(read("notes.txt"), "my notes");
    assert_eq!(read("work/thesis.tex"), "my thesis");
    assert!(t.path().join("robots/hopper_2d.urdf").is_file());
}

#[test]
fn targets_vito_did_not_write_are_refused_before_solving() {
    let t = workspace("outdirs");
    let abs = t.path().display().to_string();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["--out".into(), ".".into()], "names no directory"),
        (vec!["--out".into(), abs.clone()], "the current directory"),
        (
            vec!["--out".into(), format!("{abs}/")],
            "the current directory",
        ),
        (vec!["--out".into(), "robots".into()], "holding the input"),
        (
            vec!["--out".into(), format!("{abs}/..")],
            "names no directory",
        ),
        (
            vec![
                "--out".into(),
                t.path().parent().unwrap().display().to_string(),
            ],
            "an ancestor",
        ),
        (vec!["--out".into(), "prob.toml".into()], "is a file"),
        (vec!["--out".into(), "notes.txt".into()], "is a file"),
        (vec!["--out".into(), "work".into()], "vito did not write"),
        (
            vec!["--set".into(), "output.dir=\"\"".into()],
            "names no directory",
        ),
    ];
    for (extra, expected) in cases {
        let run = t
            .vito()
            .args(["solve", "prob.toml", "--quiet"])
            .args(&extra)
            .assert_exit(2);
        assert!(run.stderr.contains(expected), "{extra:?}: {}", run.stderr);
        assert!(
            !run.stderr.contains("iter"),
            "solved before refusing: {}",
            run.stderr
        );
        untouched(&t);
    }
    untouched(&t);
}

/// The problem file's own directory is protected even when it is marked as vito's.
#[test]
fn the_problem_files_directory_is_never_replaced() {
    let t = workspace("outdirs-input");
    std::fs::create_dir(t.path().join("b")).unwrap();
    t.write(
        "b/prob.toml",
        &hopper_text().replace("robots/", "../robots/"),
    );
    t.write("b/.vito-output", "");
    let run = t
        .vito()
        .args(["solve", "b/prob.toml", "--quiet", "--out", "b"])
        .assert_exit(2);
    assert!(run.stderr.contains("the input"), "{}", run.stderr);
    assert!(t.path().join("b/prob.toml").is_file());
}

/// vito's own results are replaced whole, atomically, with nothing left beside them.
#[test]
fn vitos_own_results_are_replaced() {
    let t = workspace("outdirs-own");
    for _ in 0..2 {
        t.vito()
            .args(["solve", "prob.toml", "--quiet", "--out", "res"])
            .assert_exit(0);
        assert!(t.path().join("res/.vito-output").is_file());
        assert!(t.path().join("res/trajectory.csv").is_file());
    }
    let leftovers: Vec<_> = std::fs::read_dir(t.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".res."))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    untouched(&t);
}

/// A file a user adds to vito's results is never deleted by the next run: the directory is
/// refused, naming it; and a directory with only a `summary.json` naming `vito_version` and a
/// `trajectory.csv` (no marker) is not taken as vito's.
#[test]
fn files_added_to_vitos_results_are_kept() {
    let t = workspace("outdirs-added");
    t.vito()
        .args(["solve", "prob.toml", "--quiet", "--out", "res"])
        .assert_exit(0);
    let marker = std::fs::read_to_string(t.path().join("res/.vito-output")).unwrap();
    assert!(marker.contains("wrote: summary.json\n"), "{marker}");
    t.write("res/notes.txt", "mine");
    let run = t
        .vito()
        .args(["solve", "prob.toml", "--quiet", "--out", "res"])
        .assert_exit(2);
    assert!(run.stderr.contains("`notes.txt`"), "{}", run.stderr);
    assert_eq!(
        std::fs::read_to_string(t.path().join("res/notes.txt")).unwrap(),
        "mine"
    );
    std::fs::create_dir(t.path().join("look")).unwrap();
    t.write("look/summary.json", "{\"vito_version\": \"0.1.0\"}");
    t.write("look/trajectory.csv", "mine");
    t.vito()
        .args(["solve", "prob.toml", "--quiet", "--out", "look"])
        .assert_exit(2);
    assert_eq!(
        std::fs::read_to_string(t.path().join("look/trajectory.csv")).unwrap(),
        "mine"
    );
}
