//! Test helpers: a temp dir per test (named after it) and a `VitoCmd` around the binary.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub use crate::common::problems_dir;

/// A temp directory for one test, removed at the end.
pub struct TestDir {
    dir: tempfile::TempDir,
}

impl TestDir {
    /// A fresh directory whose name starts with the test's name.
    pub fn new(name: &str) -> TestDir {
        let dir = tempfile::Builder::new()
            .prefix(&format!("vito-{name}-"))
            .tempdir()
            .expect("create a temp dir");
        TestDir { dir }
    }

    /// A fresh directory holding a copy of `problems/robots/hopper_2d.urdf` in `robots/`.
    pub fn with_hopper(name: &str) -> TestDir {
        let t = TestDir::new(name);
        std::fs::create_dir(t.path().join("robots")).unwrap();
        std::fs::copy(
            problems_dir().join("robots/hopper_2d.urdf"),
            t.path().join("robots/hopper_2d.urdf"),
        )
        .unwrap();
        t
    }

    pub fn path(&self) -> &Path {
        self.dir.path()
    }

    /// Writes a file relative to the directory.
    pub fn write(&self, name: &str, text: &str) -> PathBuf {
        let path = self.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    /// A `vito` command running in this directory.
    pub fn vito(&self) -> VitoCmd {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_vito"));
        cmd.current_dir(self.path());
        VitoCmd { cmd }
    }

    /// A `vito` command running in this directory after the shell commands `limits`
    /// (`ulimit …`, `trap …`).
    fn vito_after(&self, limits: &str) -> VitoCmd {
        let mut cmd = Command::new("sh");
        cmd.current_dir(self.path())
            .args(["-c", &format!("{limits} && exec \"$0\" \"$@\"")])
            .arg(env!("CARGO_BIN_EXE_vito"));
        VitoCmd { cmd }
    }

    /// A `vito` command running in this directory on what behaves as a full disk: a file-size
    /// limit of one block (`ulimit -f 1`, with SIGXFSZ ignored), so that every write past it
    /// fails with "File too large" as a write to a full disk fails with "No space left".
    pub fn vito_on_a_full_disk(&self) -> VitoCmd {
        self.vito_after("ulimit -f 1 && trap '' XFSZ")
    }

    /// A `vito` command running in this directory with an address space of `kib` KiB
    /// (`ulimit -v`): an allocation past it fails.
    pub fn vito_with_address_space(&self, kib: u64) -> VitoCmd {
        self.vito_after(&format!("ulimit -v {kib}"))
    }
}

/// The hopper problem file's text (to be edited into bad inputs).
pub fn hopper_text() -> String {
    std::fs::read_to_string(problems_dir().join("hopper_2d.toml")).unwrap()
}

/// A `vito` invocation.
pub struct VitoCmd {
    cmd: Command,
}

/// What a finished run printed.
pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

impl VitoCmd {
    pub fn args<I, S>(mut self, args: I) -> VitoCmd
    where
        I: IntoIterator<Item = S>,
        S: AsRef<std::ffi::OsStr>,
    {
        self.cmd.args(args);
        self
    }

    /// Sets an environment variable of the command.
    pub fn env(mut self, key: &str, value: &str) -> VitoCmd {
        self.cmd.env(key, value);
        self
    }

    /// Removes an environment variable from the command's environment.
    pub fn env_remove(mut self, key: &str) -> VitoCmd {
        self.cmd.env_remove(key);
        self
    }

    pub fn run(mut self) -> Run {
        let Output {
            status,
            stdout,
            stderr,
        } = self.cmd.output().expect("run vito");
        Run {
            code: status.code().unwrap_or(-1),
            stdout: String::from_utf8_lossy(&stdout).into_owned(),
            stderr: String::from_utf8_lossy(&stderr).into_owned(),
        }
    }

    /// Runs and checks the exit code, printing both streams when it differs.
    pub fn assert_exit(self, code: i32) -> Run {
        let run = self.run();
        assert_eq!(
            run.code, code,
            "exit code\n--- stdout\n{}\n--- stderr\n{}",
            run.stdout, run.stderr
        );
        run
    }
}

/// Reads `summary.json` of an output directory.
pub fn summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    serde_json::from_str(&text).expect("summary.json is JSON")
}

/// Runs `vito ARGS` in `t`, checks the exit code and that stdout or stderr says `text`.
pub fn says(t: &TestDir, args: &[&str], code: i32, text: &str) -> Run {
    let run = t.vito().args(args).assert_exit(code);
    assert!(
        run.stdout.contains(text) || run.stderr.contains(text),
        "{args:?} should say {text:?}\n--- stdout\n{}\n--- stderr\n{}",
        run.stdout,
        run.stderr
    );
    run
}

/// Asserts that `objective` is `file`'s in the regression record `problems/<record>` within
/// the record's tolerance (relative, at least absolute).
pub fn assert_recorded(record: &str, file: &str, objective: f64) {
    let text = std::fs::read_to_string(problems_dir().join(record)).unwrap();
    let table: toml::Table = toml::from_str(&text).unwrap();
    let entry = table["problem"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["file"].as_str() == Some(file))
        .unwrap_or_else(|| {
            panic!("{file} is not in problems/{record}; run `vito regress --bless {file}`")
        });
    let recorded = entry["objective"].as_float().unwrap();
    let tolerance = entry["tolerance"].as_float().unwrap();
    assert!(
        (objective - recorded).abs() <= tolerance * recorded.abs().max(1.0),
        "objective {objective} vs recorded {recorded} (tolerance {tolerance})"
    );
}

/// `--set` arguments under which a solve never ends by itself: Ipopt's tolerances far below
/// what any iterate reaches, its acceptable-point and tiny-step exits off (a failed line
/// search at an acceptable point ends a solve too, so `acceptable_tol` goes down as well), and
/// an iteration limit no test reaches (measured: the brick ran 914 iterations and the hopper
/// 8,726 in 60 s without ending). A test that stops such a
/// solve (a signal, a time limit) decides its outcome by that stop alone, whatever the
/// machine's speed.
pub const ENDLESS_SOLVE: [&str; 16] = [
    "--set",
    "solver.ipopt.max_iter=100000000",
    "--set",
    "solver.ipopt.tol=1e-300",
    "--set",
    "solver.ipopt.dual_inf_tol=1e-300",
    "--set",
    "solver.ipopt.constr_viol_tol=1e-300",
    "--set",
    "solver.ipopt.compl_inf_tol=1e-300",
    "--set",
    "solver.ipopt.acceptable_iter=0",
    "--set",
    "solver.ipopt.acceptable_tol=1e-300",
    "--set",
    "solver.ipopt.tiny_step_tol=0",
];

/// Whether a progress line is an iteration's (it starts with the iteration number).
pub fn is_iteration_line(line: &str) -> bool {
    line.trim_start().starts_with(|c: char| c.is_ascii_digit())
}

/// Waits for a child that was asked to stop; one still running after 10 min is killed and
/// fails the test (a broken stop is a failure, never a stuck suite). The bound decides no
/// outcome: a stop takes one iteration. The wait itself blocks on the child's exit, no
/// polling.
pub fn wait_after_stop(mut child: std::process::Child) -> std::process::ExitStatus {
    let pid = rustix::process::Pid::from_child(&child);
    let (sent, exited) = std::sync::mpsc::channel();
    std::thread::spawn(move || sent.send(child.wait()));
    match exited.recv_timeout(std::time::Duration::from_secs(600)) {
        Ok(status) => status.unwrap(),
        Err(_) => {
            let _ = rustix::process::kill_process(pid, rustix::process::Signal::KILL);
            panic!("the process did not stop within 10 min of the stop request");
        }
    }
}

/// A CSV's columns by name (units stripped), parsed here rather than by vito's reader; a
/// cell that is not a number is NaN.
/// The column `name` of [`csv_columns`]' output (panics naming it when missing).
pub fn column_named(columns: &[(String, Vec<f64>)], name: &str) -> Vec<f64> {
    columns
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no column {name}"))
        .1
        .clone()
}

pub fn csv_columns(text: &str) -> Vec<(String, Vec<f64>)> {
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default();
    let mut cols: Vec<(String, Vec<f64>)> = header
        .split(',')
        .map(|h| (h.split(" [").next().unwrap_or(h).to_owned(), Vec::new()))
        .collect();
    for line in lines {
        for (cell, col) in line.split(',').zip(cols.iter_mut()) {
            col.1.push(cell.parse().unwrap_or(f64::NAN));
        }
    }
    cols
}
