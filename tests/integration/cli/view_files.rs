//! `vito view`'s reads and writes: FIFOs refused without blocking, a link planted at any
//! name never written through, a user's file that quotes vito's markers never replaced, a
//! missing directory and an oversized strip refused (exit 2), a long sweep value printed;
//! values a page cannot draw refused (exit 2), a full disk exit 2 with nothing lost, the
//! problem's copy found whatever bytes names hold, no silent fallback.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::cli::util::{TestDir, hopper_text};

/// Runs `vito args` in `dir`; a run still going after 5 min is killed and fails the test (a
/// hang is a failure, never a stuck suite; the bound decides no outcome: a view takes
/// seconds on a loaded machine). Returns (exit code, stderr).
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
        if start.elapsed() > Duration::from_secs(300) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("vito {args:?} hung (killed after 5 min)");
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
    view_from_the_copy(&t, &moved, &elsewhere.path().join("view.html"));
}

/// `vito view dir --out page` (run in `t`) draws the hopper from the copy of its problem that
/// `dir` carries, and says so.
fn view_from_the_copy(t: &TestDir, dir: &Path, page: &Path) {
    let run = t
        .vito()
        .args([
            "view".as_ref(),
            dir.as_os_str(),
            "--out".as_ref(),
            page.as_os_str(),
        ])
        .assert_exit(0);
    assert!(run.stderr.contains("drawn from the copy"), "{}", run.stderr);
    let page = std::fs::read_to_string(page).unwrap();
    assert!(
        page.contains("foot_contact"),
        "the hopper's contact on the page"
    );
}

/// A copy of the result `r` under `t` as `name`, its `trajectory.csv` with `column`'s value
/// on data row `k` (0 is the first knot) set by `value(k, old)`.
fn edited_result(t: &TestDir, name: &str, column: &str, value: impl Fn(usize, f64) -> f64) {
    let dir = t.path().join(name);
    std::fs::create_dir(&dir).unwrap();
    for file in ["summary.json", "trajectory.csv"] {
        std::fs::copy(t.path().join("r").join(file), dir.join(file)).unwrap();
    }
    let csv = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let mut lines: Vec<String> = csv.lines().map(str::to_owned).collect();
    let c = lines[0]
        .split(',')
        .position(|h| h.split(" [").next() == Some(column))
        .unwrap_or_else(|| panic!("no column {column}"));
    for (k, line) in lines.iter_mut().skip(1).enumerate() {
        let mut cells: Vec<String> = line.split(',').map(str::to_owned).collect();
        cells[c] = format!("{:e}", value(k, cells[c].parse().unwrap()));
        *line = cells.join(",");
    }
    std::fs::write(dir.join("trajectory.csv"), lines.join("\n") + "\n").unwrap();
}

/// The page a simulation (or a solve) writes beside its results checks what it draws as
/// `vito view` does: a hopper simulated 100 km from the origin keeps its results (exit 0) and
/// its `animation.html` says why it shows no motion, naming the row, the column and the
/// value; `vito view` of it refuses the same value.
#[test]
fn a_results_page_does_not_draw_what_view_refuses() {
    let t = TestDir::with_hopper("a_results_page_does_not_draw_what_view_refuses");
    t.write("p.toml", &hopper_text());
    let (code, stderr) = run_within(
        t.path(),
        &[
            "simulate",
            "p.toml",
            "--set",
            "initial.q.x=1e5",
            "--duration",
            "0.2",
            "--out",
            "far",
            "--quiet",
        ],
    );
    assert_eq!(code, 0, "{stderr}");
    assert!(t.path().join("far/trajectory.csv").exists());
    let page = std::fs::read_to_string(t.path().join("far/animation.html")).unwrap();
    assert!(
        page.contains("vito did not draw this motion: row 2, column `x`: 100000 m is beyond"),
        "{page}"
    );
    assert!(!page.contains("<script"), "{page}");
    let (code, stderr) = run_within(t.path(), &["view", "far", "--out", "p.html"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("row 2, column `x`: 100000 m is beyond"),
        "{stderr}"
    );
}

/// A trajectory or terrain `vito view` cannot draw (a page a browser never finishes, poses
/// lost to rounding) is refused, exit 2, naming the file, the row, the column and the value,
/// with nothing written: a coordinate of 1e15 m on one row (the page and the world strip), an
/// angle of 1e9 rad, times 1e12 s from zero for a motion of 0.2 s, a terrain 1e9 m high. A
/// motion of 4 km (8000 times the hopper's size) is drawn.
#[test]
fn view_refuses_values_it_cannot_draw() {
    let t = simulated("view_refuses_values_it_cannot_draw");
    edited_result(&t, "far", "x", |k, x| if k == 2 { 1e15 } else { x });
    edited_result(&t, "spun", "theta", |k, a| if k == 1 { 1e9 } else { a });
    edited_result(&t, "late", "time", |_, s| s + 1e12);
    for (args, says) in [
        (
            &["view", "far", "--out", "p.html"][..],
            &["far/trajectory.csv: row 4, column `x`: 1000000000000000 m is beyond"][..],
        ),
        (
            &["view", "far", "--strip", "3", "--svg", "s.svg", "--world"][..],
            &["far/trajectory.csv: row 4, column `x`: 1000000000000000 m"][..],
        ),
        (
            &["view", "spun", "--out", "p.html"][..],
            &["spun/trajectory.csv: row 3, column `theta`: 1000000000 rad is beyond"][..],
        ),
        (
            &["view", "late", "--out", "p.html"][..],
            &[
                "late/trajectory.csv: row 2, column `time`: 1000000000000 s",
                "run together",
            ][..],
        ),
    ] {
        let (code, stderr) = run_within(t.path(), args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        for s in says {
            assert!(stderr.contains(s), "{args:?}: {stderr}");
        }
    }
    // The terrain, from the problem.
    t.write(
        "high.toml",
        &format!("{}\n[terrain]\nground_height = 1e9\n", hopper_text()),
    );
    let (code, stderr) = run_within(
        t.path(),
        &["view", "r", "--problem", "high.toml", "--out", "p.html"],
    );
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("high.toml: the terrain's height at x = ")
            && stderr.contains("1000000000 m is beyond"),
        "{stderr}"
    );
    assert!(!t.path().join("p.html").exists() && !t.path().join("s.svg").exists());
    // Large but sane: 4 km.
    edited_result(&t, "long", "x", |k, _| 1000.0 * k as f64);
    let (code, stderr) = run_within(t.path(), &["view", "long", "--out", "p.html"]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stderr) = run_within(
        t.path(),
        &["view", "long", "--strip", "3", "--svg", "s.svg", "--world"],
    );
    assert_eq!(code, 0, "{stderr}");
}

/// Runs `vito args` in `dir` with files limited to 2 KiB (a write beyond fails, as on a full
/// disk); returns (exit code, stderr).
fn run_with_small_files(dir: &Path, args: &[&str]) -> (i32, String) {
    let mut sh_args = vec![
        "-c",
        "ulimit -f 4; trap '' XFSZ; exec \"$0\" \"$@\"",
        env!("CARGO_BIN_EXE_vito"),
    ];
    sh_args.extend(args);
    let out = Command::new("sh")
        .current_dir(dir)
        .args(&sh_args)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A page or strip that cannot be written (the disk full, the file too large) is unwritable
/// output, not an internal error: exit 4 naming the file and why, the file already there
/// kept as it was, no temporary file left.
#[test]
fn view_on_a_full_disk_exits_4_and_keeps_what_was_there() {
    let t = simulated("view_on_a_full_disk_exits_4_and_keeps_what_was_there");
    let (code, stderr) = run_within(t.path(), &["view", "r", "--strip", "3", "--svg", "s.svg"]);
    assert_eq!(code, 0, "{stderr}");
    let before = |p: &str| std::fs::read(t.path().join(p)).unwrap();
    let (page, strip) = (before("r/animation.html"), before("s.svg"));
    assert!(page.len() > 4096 && strip.len() > 4096);
    for (args, file) in [
        (&["view", "r"][..], "r/animation.html"),
        (
            &["view", "r", "--out", "r/animation.html"][..],
            "r/animation.html",
        ),
        (
            &["view", "r", "--strip", "3", "--svg", "s.svg"][..],
            "s.svg",
        ),
    ] {
        let (code, stderr) = run_with_small_files(t.path(), args);
        assert_eq!(code, 4, "{args:?}: {stderr}");
        assert!(
            stderr.contains(&format!("cannot write {file}")) && stderr.contains("file too large"),
            "{args:?}: {stderr}"
        );
    }
    assert_eq!(before("r/animation.html"), page);
    assert_eq!(before("s.svg"), strip);
    for dir in [t.path().to_owned(), t.path().join("r")] {
        for entry in std::fs::read_dir(dir).unwrap() {
            let name = entry.unwrap().file_name();
            assert!(!name.to_string_lossy().ends_with(".tmp"), "{name:?} left");
        }
    }
}

/// A problem file whose name is not UTF-8, in a result folder whose name is not UTF-8
/// either: the copy is stored under the name `summary.json` records, so that the folder
/// moved elsewhere (the problem file gone) is drawn from it.
#[test]
fn a_problem_named_in_bytes_that_are_not_utf8_is_viewed_from_its_copy() {
    use std::ffi::OsStr;
    use std::os::unix::ffi::OsStrExt;
    let t =
        TestDir::with_hopper("a_problem_named_in_bytes_that_are_not_utf8_is_viewed_from_its_copy");
    let problem = t.path().join(OsStr::from_bytes(b"p\xff.toml"));
    std::fs::write(&problem, hopper_text()).unwrap();
    let out = t.path().join(OsStr::from_bytes(b"r\xfe"));
    t.vito()
        .args(["simulate".as_ref(), problem.as_os_str()])
        .args(["--duration", "0.2", "--quiet", "--out"])
        .args([&out])
        .assert_exit(0);
    let summary = crate::cli::util::summary(&out);
    let copy = summary["problem_copy"]["file"].as_str().unwrap();
    assert_eq!(copy, "problem/p\u{fffd}.toml");
    assert_eq!(
        std::fs::read_to_string(out.join(copy)).unwrap(),
        hopper_text()
    );
    std::fs::remove_file(&problem).unwrap();
    let elsewhere = tempfile::tempdir().unwrap();
    let moved = elsewhere.path().join(OsStr::from_bytes(b"moved\xfd"));
    std::fs::rename(&out, &moved).unwrap();
    view_from_the_copy(&t, &moved, &elsewhere.path().join("view.html"));
}

/// No silent fallback: an explicit `--problem` that cannot be read (a FIFO, never blocked
/// on; a missing file) is an error naming it; a summary naming a device says so when the
/// copy is drawn instead; a directory that a strip would leave out is refused.
#[test]
fn view_never_falls_back_silently() {
    let t = simulated("view_never_falls_back_silently");
    mkfifo(&t.path().join("fifo.toml"));
    for (problem, says) in [("fifo.toml", "FIFO"), ("missing.toml", "missing.toml")] {
        let (code, stderr) = run_within(
            t.path(),
            &["view", "r", "--problem", problem, "--out", "p.html"],
        );
        assert_eq!(code, 2, "{problem}: {stderr}");
        assert!(
            stderr.contains(problem) && stderr.contains(says) && !stderr.contains("copy"),
            "{stderr}"
        );
    }
    assert!(!t.path().join("p.html").exists());
    // The summary names a device: drawn from the copy, saying why.
    let summary_path = t.path().join("r/summary.json");
    let mut summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary_path).unwrap()).unwrap();
    summary["problem_file"] = "/dev/zero".into();
    std::fs::write(&summary_path, summary.to_string()).unwrap();
    let (code, stderr) = run_within(t.path(), &["view", "r", "--out", "p.html"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("/dev/zero cannot be read (it is a character device")
            && stderr.contains("drawn from the copy"),
        "{stderr}"
    );
    // Two results, one strip.
    std::fs::create_dir(t.path().join("r2")).unwrap();
    for file in ["summary.json", "trajectory.csv"] {
        std::fs::copy(
            t.path().join("r").join(file),
            t.path().join("r2").join(file),
        )
        .unwrap();
    }
    let (code, stderr) = run_within(
        t.path(),
        &[
            "view", "r", "r2", "--strip", "4", "--svg", "s.svg", "--world",
        ],
    );
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("`r2` would not be in it"), "{stderr}");
    assert!(!t.path().join("s.svg").exists());
}
