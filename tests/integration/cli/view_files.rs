//! `vito view`'s reads and writes: FIFOs refused without blocking, a link planted at any
//! name never written through, a user's file that quotes vito's markers never replaced, a
//! missing directory and an oversized strip refused (exit 2), a long sweep value printed.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::cli::util::{TestDir, hopper_text};

/// Runs `vito args` in `dir`; a run still going after 60 s is killed and fails the test (a
/// hang is a failure, never a stuck suite). Returns (exit code, stderr).
fn run_within(dir: &Path, args: &[&str]) -> (i32, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_vito"))
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut stderr = String::new();
            std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
            return (status.code().unwrap_or(-1), stderr);
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("vito {args:?} hung (killed after 60 s)");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn mkfifo(path: &Path) {
    rustix::fs::mknodat(
        rustix::fs::CWD,
        path,
        rustix::fs::FileType::Fifo,
        rustix::fs::Mode::from_raw_mode(0o600),
        0,
    )
    .unwrap();
}

/// A directory with the hopper and a short simulation of it in `r/`.
fn simulated(name: &str) -> TestDir {
    let t = TestDir::with_hopper(name);
    t.write("p.toml", &hopper_text());
    let (code, stderr) = run_within(
        t.path(),
        &[
            "simulate",
            "p.toml",
            "--duration",
            "0.2",
            "--out",
            "r",
            "--quiet",
        ],
    );
    assert_eq!(code, 0, "{stderr}");
    t
}

#[test]
fn view_refuses_fifos_without_blocking() {
    let t = simulated("view_refuses_fifos_without_blocking");
    // --svg and --out naming a FIFO.
    mkfifo(&t.path().join("fifo.svg"));
    let (code, stderr) = run_within(
        t.path(),
        &["view", "r", "--strip", "3", "--svg", "fifo.svg"],
    );
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("FIFO"), "{stderr}");
    mkfifo(&t.path().join("fifo.html"));
    let (code, stderr) = run_within(t.path(), &["view", "r", "--out", "fifo.html"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("FIFO"), "{stderr}");
    // The result's own files as FIFOs.
    for name in ["summary.json", "trajectory.csv"] {
        let dir = t.path().join(format!("fifo-{name}"));
        std::fs::create_dir(&dir).unwrap();
        for other in ["summary.json", "trajectory.csv"] {
            if other != name {
                std::fs::copy(t.path().join("r").join(other), dir.join(other)).unwrap();
            }
        }
        mkfifo(&dir.join(name));
        let d = dir.file_name().unwrap().to_str().unwrap();
        let (code, stderr) = run_within(t.path(), &["view", d, "--out", "x.html"]);
        assert_eq!(code, 2, "{name}: {stderr}");
        assert!(stderr.contains("FIFO") && stderr.contains(name), "{stderr}");
    }
    assert!(!t.path().join("x.html").exists());
}

#[test]
fn view_writes_never_follow_links_nor_replace_users_files() {
    let t = simulated("view_writes_never_follow_links_nor_replace_users_files");
    let victim = t.write("victim.txt", "precious");
    // Links at the names older builds used for their temporary files, and at the target.
    for planted in [
        "r/.animation.html.tmp-1".to_owned(),
        ".s.svg.tmp".to_owned(),
        "link.html".to_owned(),
    ] {
        std::os::unix::fs::symlink(&victim, t.path().join(planted)).unwrap();
    }
    let (code, stderr) = run_within(t.path(), &["view", "r"]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stderr) = run_within(t.path(), &["view", "r", "--strip", "3", "--svg", "s.svg"]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    // A user's page that merely mentions vito's status element (or its marker, late in the
    // file) is not replaced.
    let notes = format!(
        "<!DOCTYPE html>\n<p>my notes about id=\"vito-status\"</p>{}\n<meta name=\"generator\" content=\"vito animation page\">",
        "x".repeat(2000)
    );
    t.write("notes.html", &notes);
    let (code, stderr) = run_within(t.path(), &["view", "r", "--out", "notes.html"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("vito did not write it"), "{stderr}");
    assert_eq!(
        std::fs::read_to_string(t.path().join("notes.html")).unwrap(),
        notes
    );
    // vito's own page is replaced.
    std::fs::copy(
        t.path().join("r/animation.html"),
        t.path().join("mine.html"),
    )
    .unwrap();
    let (code, stderr) = run_within(t.path(), &["view", "r", "--out", "mine.html"]);
    assert_eq!(code, 0, "{stderr}");
    // --svg and --out into a missing directory; --strip beyond its limit.
    for args in [
        &["view", "r", "--strip", "3", "--svg", "nowhere/s.svg"][..],
        &["view", "r", "--out", "nowhere/a.html"][..],
    ] {
        let (code, stderr) = run_within(t.path(), args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains("does not exist"), "{stderr}");
    }
    for n in ["18446744073709551615", "100000", "0"] {
        let (code, stderr) = run_within(t.path(), &["view", "r", "--strip", n, "--svg", "big.svg"]);
        assert_eq!(code, 2, "{n}: {stderr}");
        assert!(stderr.contains("--strip"), "{stderr}");
    }
    assert!(!t.path().join("big.svg").exists());
}

/// A result folder carries copies of its problem file and URDF (`problem/`, named in
/// `summary.json`'s `problem_copy`): moved to a folder where its problem file is not found,
/// `vito view` draws it from them, with the summary's overrides, and says so; the page
/// holds the hopper's links.
#[test]
fn a_result_folder_moved_elsewhere_is_viewed_from_its_copies() {
    let t = TestDir::with_hopper("a_result_folder_moved_elsewhere_is_viewed_from_its_copies");
    t.write("p.toml", &hopper_text());
    t.vito()
        .args([
            "solve",
            "p.toml",
            "--set",
            "contacts.friction=0.6",
            "--quiet",
            "--out",
            "res",
        ])
        .assert_exit(0);
    let summary = crate::cli::util::summary(&t.path().join("res"));
    assert_eq!(summary["problem_copy"]["file"], "problem/p.toml");
    assert_eq!(summary["problem_copy"]["urdf"], "problem/hopper_2d.urdf");
    assert_eq!(
        std::fs::read_to_string(t.path().join("res/problem/p.toml")).unwrap(),
        hopper_text()
    );
    let elsewhere = tempfile::tempdir().unwrap();
    let moved = elsewhere.path().join("res");
    std::fs::rename(t.path().join("res"), &moved).unwrap();
    std::fs::remove_file(t.path().join("p.toml")).unwrap();
    let out = elsewhere.path().join("view.html");
    let run = t
        .vito()
        .args([
            "view".as_ref(),
            moved.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ])
        .assert_exit(0);
    assert!(run.stderr.contains("drawn from the copy"), "{}", run.stderr);
    let page = std::fs::read_to_string(&out).unwrap();
    assert!(
        page.contains("foot_contact"),
        "the hopper's contact on the page"
    );
}
