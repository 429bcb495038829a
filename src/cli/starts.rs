//! `vito solve --starts K --jobs J`: the starts run in parallel, each in a `vito solve`
//! process of its own (Ipopt solves one problem at a time per process), which writes its
//! solution to a private temporary directory; the best is chosen as a one-process
//! multi-start chooses it ([`vito::transcription::best_of`]), so the result is the same.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use vito::transcription::{LostStart, MultiStart, Solution, StartOutcome, StartRecord};

use super::error::CliError;

/// The hidden option that makes `vito solve` solve one start and write its solution (JSON)
/// to a file instead of an output directory.
pub(super) const START_RESULT_FLAG: &str = "--start-result";

/// Writes the solution of one start for the process that runs the starts in parallel.
pub(super) fn write_start_result(path: &Path, solution: &Solution) -> Result<(), CliError> {
    let text = serde_json::to_string(solution).map_err(|e| CliError::Internal(e.to_string()))?;
    vito::files::output::write_atomic(path, text.as_bytes()).map_err(CliError::io(path))
}

struct Running {
    start: usize,
    child: Child,
    started: Instant,
}

/// Solves the starts of `multi` in `jobs` processes at a time and returns the best, with
/// every start's record: a start whose process ended without a result (killed, or failing)
/// is recorded as lost, and said so on the terminal. A stop request (`cancel`) is passed on
/// to the running starts (they stop after their current iteration and report their
/// iterates); no new start begins.
pub(super) fn solve_in_parallel(
    file: &Path,
    set: &[String],
    multi: MultiStart,
    jobs: usize,
    cancel: &Arc<AtomicBool>,
    quiet: bool,
) -> Result<Solution, CliError> {
    let exe = std::env::current_exe().map_err(|e| CliError::Internal(e.to_string()))?;
    let scratch = tempfile::Builder::new()
        .prefix("vito-starts-")
        .tempdir()
        .map_err(|e| {
            CliError::Input(format!(
                "cannot make a temporary directory for the parallel starts ({e}): set TMPDIR to \
                 a writable directory, or give --jobs 1"
            ))
        })?;
    let result_path = |k: usize| scratch.path().join(format!("start-{k}.json"));
    let log_path = |k: usize| scratch.path().join(format!("start-{k}.log"));
    let mut next = 0;
    let mut running: Vec<Running> = Vec::new();
    let mut results: Vec<(usize, Solution)> = Vec::new();
    let mut lost: Vec<(usize, StartRecord)> = Vec::new();
    let began = Instant::now();
    let mut stopping = false;
    while (next < multi.starts && !stopping) || !running.is_empty() {
        if !stopping && cancel.load(Ordering::SeqCst) {
            stopping = true;
            for r in &mut running {
                vito::sweep::ask_to_stop(&mut r.child);
            }
        }
        while running.len() < jobs && next < multi.starts && !stopping {
            let k = next;
            next += 1;
            let child = spawn(&exe, file, set, multi, k, &result_path(k), &log_path(k))?;
            if !quiet {
                note!(
                    "start {k}/{}: running as process {}",
                    multi.starts,
                    child.id()
                );
            }
            running.push(Running {
                start: k,
                child,
                started: Instant::now(),
            });
        }
        std::thread::sleep(Duration::from_millis(20));
        let mut i = 0;
        while i < running.len() {
            let status = match running[i].child.try_wait() {
                Ok(Some(status)) => status,
                Ok(None) => {
                    i += 1;
                    continue;
                }
                Err(e) => return Err(CliError::Internal(format!("waiting for a start: {e}"))),
            };
            let r = running.swap_remove(i);
            let read = std::fs::read_to_string(result_path(r.start))
                .ok()
                .and_then(|t| serde_json::from_str::<Solution>(&t).ok());
            let Some(s) = read else {
                let ended = lost_start(status, &log_path(r.start));
                note!("start {}/{}: {}", r.start, multi.starts, ended.how);
                lost.push((
                    r.start,
                    StartRecord {
                        seed: multi.seed_of(r.start),
                        outcome: StartOutcome::Lost(ended),
                    },
                ));
                continue;
            };
            if !quiet {
                let ended = results.len() + lost.len() + 1;
                let left = multi.starts - ended;
                let eta = if left > 0 && !stopping {
                    let per = began.elapsed().as_secs_f64() / ended as f64;
                    format!(", ETA {:.0} s", per * left as f64)
                } else {
                    String::new()
                };
                note!(
                    "start {}/{}: {}, objective {:.6e}, max slack {:.1e}, {} iterations, {:.1} s{eta}",
                    r.start,
                    multi.starts,
                    s.verdict().name(),
                    s.objective,
                    s.max_slack,
                    s.iterations,
                    r.started.elapsed().as_secs_f64()
                );
            }
            results.push((r.start, s));
        }
    }
    let why: Vec<String> = lost
        .iter()
        .map(|(k, r)| match &r.outcome {
            StartOutcome::Lost(l) => format!("start {k}: {}", l.how),
            StartOutcome::Ended(_) => format!("start {k}"),
        })
        .collect();
    vito::transcription::best_of(results, lost).ok_or_else(|| {
        CliError::NoResult(format!(
            "no start returned a result ({}); nothing was written",
            if why.is_empty() {
                "stopped before any ended".to_owned()
            } else {
                why.join("; ")
            }
        ))
    })
}

/// How the process of a start that wrote no result ended: the signal that killed it, or its
/// exit code and the last error line of its log.
fn lost_start(status: std::process::ExitStatus, log: &Path) -> LostStart {
    use std::os::unix::process::ExitStatusExt;
    if let Some(signal) = status.signal() {
        use rustix::process::Signal;
        let names = [
            (Signal::HUP, "SIGHUP"),
            (Signal::INT, "SIGINT"),
            (Signal::ABORT, "SIGABRT"),
            (Signal::KILL, "SIGKILL"),
            (Signal::SEGV, "SIGSEGV"),
            (Signal::TERM, "SIGTERM"),
        ];
        let name = names
            .iter()
            .find(|(s, _)| s.as_raw() == signal)
            .map_or(String::new(), |(_, n)| format!(" ({n})"));
        return LostStart {
            signal: Some(signal),
            how: format!("killed by signal {signal}{name}"),
        };
    }
    let code = status.code().unwrap_or(-1);
    let log = std::fs::read_to_string(log).unwrap_or_default();
    let how = match log.lines().rev().find(|l| l.starts_with("error:")) {
        Some(error) => format!("failed (exit {code}): {error}"),
        None => format!("failed (exit {code}) without a result"),
    };
    LostStart { signal: None, how }
}

fn spawn(
    exe: &Path,
    file: &Path,
    set: &[String],
    multi: MultiStart,
    k: usize,
    result: &PathBuf,
    log: &PathBuf,
) -> Result<Child, CliError> {
    let log_file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(log)
        .map_err(CliError::io(log))?;
    let log_err = log_file.try_clone().map_err(CliError::io(log))?;
    let mut cmd = Command::new(exe);
    cmd.arg("solve").arg(file).arg("--quiet");
    for s in set {
        cmd.arg("--set").arg(s);
    }
    cmd.args(["--starts", &multi.starts.to_string()])
        .args(["--seed", &multi.seed.to_string()])
        .args(["--jobs", "1", "--only-start", &k.to_string()])
        .arg(START_RESULT_FLAG)
        .arg(result)
        .arg(vito::sweep::PARENT_FLAG)
        .arg(std::process::id().to_string());
    // One BLAS thread per start: the parallelism is the starts'.
    if std::env::var_os("OPENBLAS_NUM_THREADS").is_none() {
        cmd.env("OPENBLAS_NUM_THREADS", "1");
    }
    // The starts run in a process group of their own, so that a terminal's Ctrl-C reaches
    // this process alone, which passes it on through the pipe each start listens to.
    std::os::unix::process::CommandExt::process_group(&mut cmd, 0);
    cmd.stdin(Stdio::piped())
        .stdout(log_file)
        .stderr(log_err)
        .spawn()
        .map_err(|source| CliError::Io {
            what: format!("cannot run {}", exe.display()),
            source,
        })
}
