//! `vito solve --starts K --jobs J`: the starts run in parallel, each in a `vito solve`
//! process of its own (Ipopt solves one problem at a time per process), which writes its
//! solution to a private temporary directory; the best is chosen as a one-process
//! multi-start chooses it ([`vito::transcription::best_of`]), so the result is the same.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use vito::transcription::{MultiStart, Solution};

use super::error::CliError;

/// The hidden option that makes `vito solve` solve one start and write its solution (JSON)
/// to a file instead of an output directory.
pub(super) const START_RESULT_FLAG: &str = "--start-result";

/// Writes the solution of one start for the process that runs the starts in parallel.
pub(super) fn write_start_result(path: &Path, solution: &Solution) -> Result<(), CliError> {
    let text = serde_json::to_string(solution).map_err(|e| CliError::Internal(e.to_string()))?;
    vito::files::output::write_atomic(path, text.as_bytes())
        .map_err(|e| CliError::Internal(format!("{}: {e}", path.display())))
}

struct Running {
    start: usize,
    child: Child,
    started: Instant,
}

/// Solves the starts of `multi` in `jobs` processes at a time and returns the best, with
/// every start's record. A stop request (`cancel`) is passed on to the running starts (they
/// stop after their current iteration and report their iterates); no new start begins.
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
    let mut queue: Vec<usize> = (0..multi.starts).rev().collect();
    let mut running: Vec<Running> = Vec::new();
    let mut results: Vec<(usize, Solution)> = Vec::new();
    let mut failures: Vec<String> = Vec::new();
    let began = Instant::now();
    let mut stopping = false;
    while (!queue.is_empty() && !stopping) || !running.is_empty() {
        if !stopping && cancel.load(Ordering::SeqCst) {
            stopping = true;
            for r in &running {
                let _ = rustix::process::kill_process(
                    rustix::process::Pid::from_child(&r.child),
                    rustix::process::Signal::TERM,
                );
            }
        }
        while running.len() < jobs && !stopping {
            let Some(k) = queue.pop() else { break };
            let child = spawn(&exe, file, set, multi, k, &result_path(k), &log_path(k))?;
            running.push(Running {
                start: k,
                child,
                started: Instant::now(),
            });
        }
        std::thread::sleep(Duration::from_millis(20));
        let mut i = 0;
        while i < running.len() {
            let done = match running[i].child.try_wait() {
                Ok(Some(_)) => true,
                Ok(None) => false,
                Err(e) => return Err(CliError::Internal(format!("waiting for a start: {e}"))),
            };
            if !done {
                i += 1;
                continue;
            }
            let r = running.swap_remove(i);
            let read = std::fs::read_to_string(result_path(r.start))
                .ok()
                .and_then(|t| serde_json::from_str::<Solution>(&t).ok());
            match read {
                Some(s) => {
                    if !quiet {
                        let ended = results.len() + failures.len() + 1;
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
                None => {
                    let log = std::fs::read_to_string(log_path(r.start)).unwrap_or_default();
                    let why = log
                        .lines()
                        .rev()
                        .find(|l| l.starts_with("error:"))
                        .unwrap_or("it ended without a result")
                        .to_owned();
                    note!("start {}/{}: failed: {why}", r.start, multi.starts);
                    failures.push(why);
                }
            }
        }
    }
    vito::transcription::best_of(results).ok_or_else(|| {
        CliError::Internal(format!(
            "no start returned a result: {}",
            failures.first().map_or("stopped before any ended", |s| s)
        ))
    })
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
        .map_err(|e| CliError::Internal(format!("{}: {e}", log.display())))?;
    let log_err = log_file
        .try_clone()
        .map_err(|e| CliError::Internal(e.to_string()))?;
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
    cmd.stdin(Stdio::null())
        .stdout(log_file)
        .stderr(log_err)
        .spawn()
        .map_err(|e| CliError::Internal(format!("cannot run {}: {e}", exe.display())))
}
