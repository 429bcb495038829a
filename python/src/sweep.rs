//! Sweeps from Python, both through the library's `vito::sweep`: `_sweep` runs
//! `run_sweep` (one `vito solve` process per point), `SweepJobs` hands the points to a
//! Python executor as jobs ([`vito::sweep::JobSweep`]: the same directories, table and
//! resume rules), and `_solve_point` is what such a job runs in its worker.

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use vito::pipeline;
use vito::problem::Override;
use vito::report;
use vito::sweep::{
    Axis, Event, Grid, JobOutcome, JobSweep, Progress, Shard, SweepError, SweepOptions, WarmStart,
};
use vito::transcription::MultiStart;

use crate::convert::{PathArg, value_text};
use crate::errors::{problem_error, vito_error};
use crate::load::{load_problem, same_file};
use crate::problem::Problem;
use crate::solution::Solution;
use crate::solve::solve_loaded;
use crate::watch::run_watched;

/// The jobs solving in this process (a thread executor's, or Dask's threads), by run
/// directory, and the run directories of stopped sweeps: `SweepJobs.stop()` stops such a job at
/// its next iteration, and one that starts after the stop at once. A job in another process
/// (a process pool's, Ray's, a cluster's) finishes on its own.
struct InProcess {
    running: Vec<(PathBuf, Arc<AtomicBool>)>,
    stopped: BTreeSet<PathBuf>,
}

static IN_PROCESS: Mutex<InProcess> = Mutex::new(InProcess {
    running: Vec::new(),
    stopped: BTreeSet::new(),
});

fn in_process() -> std::sync::MutexGuard<'static, InProcess> {
    IN_PROCESS.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A job's entry in [`IN_PROCESS`] while it solves; its stop flag is set at once when its
/// sweep has stopped. Removed on drop.
struct InProcessJob {
    run_dir: PathBuf,
    cancel: Arc<AtomicBool>,
}

impl InProcessJob {
    fn register(run_dir: &std::path::Path) -> InProcessJob {
        let cancel = Arc::new(AtomicBool::new(false));
        let mut jobs = in_process();
        if jobs.stopped.contains(run_dir) {
            cancel.store(true, Ordering::SeqCst);
        }
        jobs.running.push((run_dir.to_path_buf(), cancel.clone()));
        InProcessJob {
            run_dir: run_dir.to_path_buf(),
            cancel,
        }
    }
}

impl Drop for InProcessJob {
    fn drop(&mut self) {
        in_process()
            .running
            .retain(|(dir, flag)| !(dir == &self.run_dir && Arc::ptr_eq(flag, &self.cancel)));
    }
}

/// Stops the jobs of `run_dirs` that solve in this process, now or later.
fn stop_in_process(run_dirs: &[PathBuf]) {
    let mut jobs = in_process();
    for dir in run_dirs {
        for (running, flag) in &jobs.running {
            if running == dir {
                flag.store(true, Ordering::SeqCst);
            }
        }
        jobs.stopped.insert(dir.clone());
    }
}

fn usage(e: SweepError) -> PyErr {
    match e {
        SweepError::Usage(m) => PyValueError::new_err(crate::errors::python_words(&m)),
        e => vito_error(&e),
    }
}

/// `grid={key: [values]}` as the library's grid (a str value as given, others as TOML; a
/// single value stands for a list of one), each value checked against the problem.
fn grid_of(py: Python<'_>, problem: &Problem, grid: &Bound<'_, PyDict>) -> PyResult<Grid> {
    let mut axes = Vec::new();
    for (key, values) in grid.iter() {
        let key: String = key.extract()?;
        let single = values.is_instance_of::<pyo3::types::PyString>() || values.try_iter().is_err();
        let texts: Vec<String> = if single {
            vec![value_text(&key, &values)?]
        } else {
            values
                .try_iter()?
                .map(|v| value_text(&key, &v?))
                .collect::<PyResult<_>>()?
        };
        axes.push(
            Axis::new(&key, texts)
                .map_err(|e| usage(SweepError::Usage(format!("grid={{{key:?}: ...}}: {e}"))))?,
        );
    }
    let grid = Grid::new(axes).map_err(usage)?;
    let overrides = overrides_of(py, &problem.sets)?;
    let path = problem.path.clone();
    py.detach(|| vito::sweep::check_grid(&path, &overrides, &grid))
        .map_err(usage)?;
    Ok(grid)
}

fn overrides_of(py: Python<'_>, sets: &[String]) -> PyResult<Vec<Override>> {
    sets.iter()
        .map(|s| Override::parse(s))
        .collect::<Result<_, _>>()
        .map_err(|e| problem_error(py, &e))
}

/// A sweep directory `out` whose runs start from others' trajectories (`warm_starts`: the
/// neighbour warm starts or the neighbour pass): each is named in the problem's
/// `initial_guess.warm_start`, a TOML string, so the directory's absolute name must be UTF-8;
/// else a ValueError saying so (before anything runs).
fn check_out_name(out: &std::path::Path, warm_starts: bool) -> PyResult<()> {
    let Some(absolute) = vito::sweep::out_name_without_utf8(out, warm_starts) else {
        return Ok(());
    };
    Err(PyValueError::new_err(format!(
        "out={}: the directory's name is not UTF-8, and a sweep's neighbour warm starts and \
         neighbour pass give each run the trajectory it starts from as the problem's \
         `initial_guess.warm_start`, a TOML string (UTF-8 only); choose a directory whose \
         name is UTF-8, or give warm_start=None and neighbour_rounds=0",
        crate::convert::python_path(&absolute)
    )))
}

/// A per-run time limit as the command checks it (positive, at most 1e9 s): ValueError.
fn time_limit_of(time_limit: Option<f64>) -> PyResult<Option<f64>> {
    time_limit
        .map(|t| vito::files::input::checked_span("time_limit=", t))
        .transpose()
        .map_err(PyValueError::new_err)
}

fn counts_dict<'py>(py: Python<'py>, c: &Progress) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("done", c.done)?;
    d.set_item("failed", c.failed)?;
    d.set_item("interrupted", c.interrupted)?;
    d.set_item("running", c.running)?;
    d.set_item("total", c.total)?;
    d.set_item("skipped", c.skipped)?;
    d.set_item("attempts_done", c.attempts_done)?;
    d.set_item("attempts_total", c.attempts_total)?;
    Ok(d)
}

/// _sweep(problem, grid, exe, out, jobs, time_limit=None, neighbour=False, progress=None) -> str
///
/// `exe`: the `vito` command, or None for `vito.find_executable()`.
///
/// Runs the library's sweep runner (one `exe solve` process per point) and returns the path
/// of the table (`sweep.csv`); `progress(counts)` whenever the counts change. Ctrl-C asks
/// the runs to stop after their current iteration, starts no new run, and raises
/// `KeyboardInterrupt` once they have ended (the table says which points ran; a rerun
/// resumes). `vito.sweep` is the public function.
#[pyfunction]
#[pyo3(signature = (problem, grid, exe, out, jobs, time_limit = None, neighbour = false,
                    progress = None, starts = 1, seed = 0,
                    neighbour_rounds = vito::sweep::DEFAULT_ROUNDS))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn _sweep(
    py: Python<'_>,
    problem: &Problem,
    grid: &Bound<'_, PyDict>,
    exe: Option<PathArg>,
    out: PathArg,
    jobs: usize,
    time_limit: Option<f64>,
    neighbour: bool,
    progress: Option<Py<PyAny>>,
    starts: usize,
    seed: u64,
    neighbour_rounds: usize,
) -> PyResult<PathBuf> {
    let jobs = crate::convert::count("jobs", jobs, vito::sweep::MAX_JOBS)?;
    crate::convert::check_progress(py, progress.as_ref())?;
    let starts = crate::convert::count("starts", starts, vito::transcription::MAX_STARTS)?;
    let time_limit = time_limit_of(time_limit)?.map(Duration::from_secs_f64);
    let grid = grid_of(py, problem, grid)?;
    // Looked up once the arguments are known to be good.
    let out = out.0;
    check_out_name(&out, neighbour || neighbour_rounds > 0)?;
    let exe = match exe {
        Some(exe) => exe.0,
        None => {
            py.import("vito")?
                .getattr("find_executable")?
                .call0()?
                .extract::<PathArg>()?
                .0
        }
    };
    let stop = Arc::new(AtomicBool::new(false));
    let options = SweepOptions {
        exe,
        problem: problem.absolute_path()?,
        sets: problem.sets.clone(),
        grid,
        shard: Shard::ALL,
        jobs,
        time_limit,
        out: out.clone(),
        warm_start: if neighbour {
            WarmStart::Neighbour
        } else {
            WarmStart::None
        },
        stop: Some(stop.clone()),
        starts,
        seed,
        neighbour_rounds,
    };
    let sha = problem.loaded.sha256.clone();
    let (result, error) = run_watched(
        py,
        &stop,
        |messages| {
            vito::sweep::run_sweep(&options, &sha, |event| match event {
                Event::Progress(c) | Event::Ended(_, c) => messages.send(*c),
                Event::Stopping { .. } | Event::Round { .. } | Event::RoundEnded { .. } => {}
            })
        },
        |py, counts: Progress| match &progress {
            Some(callable) => callable.call1(py, (counts_dict(py, &counts)?,)).map(drop),
            None => Ok(()),
        },
    );
    let mut outcome = match result {
        Ok(outcome) => outcome,
        Err(e) => return Err(error.unwrap_or_else(|| usage(e))),
    };
    if outcome.interrupted {
        outcome.table.mark_not_run();
        outcome.table.write(&out).map_err(usage)?;
    }
    if let Some(e) = error {
        return Err(e);
    }
    Ok(out.join(vito::sweep::TABLE_CSV))
}

/// SweepJobs(problem, grid, out, neighbour=False, time_limit=None)
///
/// A sweep whose points run as jobs elsewhere (what `vito.sweep(..., executor=...)`
/// drives): opens or resumes the sweep directory `out` (its table rebuilt from the run
/// directories); `next_job()` hands out the next point, `record(...)` records it from its
/// run directory, `stop()` leaves the rest not run. The table is rewritten after each.
#[pyclass(module = "vito", frozen)]
pub(crate) struct SweepJobs {
    sweep: Mutex<JobSweep>,
    problem: PathBuf,
    /// The problem file's SHA-256 (each job carries it: its worker refuses a changed file).
    sha256: String,
    out: PathBuf,
    /// The per-run time limit [s], checked (each job carries it).
    time_limit: Option<f64>,
}

impl SweepJobs {
    fn with<T>(&self, f: impl FnOnce(&mut JobSweep) -> Result<T, SweepError>) -> PyResult<T> {
        let mut sweep = self.sweep.lock().unwrap_or_else(PoisonError::into_inner);
        f(&mut sweep).map_err(usage)
    }
}

#[pymethods]
impl SweepJobs {
    #[new]
    #[pyo3(signature = (problem, grid, out, neighbour = false, time_limit = None,
                        neighbour_rounds = 0))]
    fn new(
        py: Python<'_>,
        problem: &Problem,
        grid: &Bound<'_, PyDict>,
        out: PathArg,
        neighbour: bool,
        time_limit: Option<f64>,
        neighbour_rounds: usize,
    ) -> PyResult<SweepJobs> {
        if neighbour_rounds > 1000 {
            return Err(PyValueError::new_err(format!(
                "neighbour_rounds={neighbour_rounds}: give 0 to 1000"
            )));
        }
        let out = out.0;
        let time_limit = time_limit_of(time_limit)?;
        let grid = grid_of(py, problem, grid)?;
        check_out_name(&out, neighbour || neighbour_rounds > 0)?;
        let path = problem.absolute_path()?;
        let warm = if neighbour {
            WarmStart::Neighbour
        } else {
            WarmStart::None
        };
        let sweep = py
            .detach(|| {
                JobSweep::open(
                    &path,
                    &problem.loaded.sha256,
                    &problem.sets,
                    &grid,
                    &out,
                    warm,
                    neighbour_rounds,
                )
            })
            .map_err(usage)?;
        Ok(SweepJobs {
            sweep: Mutex::new(sweep),
            problem: path,
            sha256: problem.loaded.sha256.clone(),
            out,
            time_limit,
        })
    }

    /// next_job() -> dict | None
    ///
    /// The next point as a job: `index`, `problem` (the file, absolute), `problem_sha256`
    /// (its SHA-256 when the sweep opened), `sets` (the overrides to load it with),
    /// `run_dir` (absolute), `warm_start` (the trajectory it starts from, or None), `attempt`
    /// (a neighbour-pass attempt's directory, given back to `record`, or None for a point's
    /// own run); None when no job is ready (the jobs handed out must come back first) or the
    /// sweep is done.
    fn next_job<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(job) = self.with(|s| s.next_job())? else {
            return Ok(None);
        };
        // A run directory handed out again (a resumed sweep) may solve again.
        in_process().stopped.remove(&job.run_dir);
        let d = PyDict::new(py);
        d.set_item("index", job.index)?;
        d.set_item("problem", &self.problem)?;
        d.set_item("problem_sha256", &self.sha256)?;
        d.set_item("sets", job.sets)?;
        d.set_item("run_dir", job.run_dir)?;
        d.set_item("warm_start", job.warm_start)?;
        d.set_item("attempt", job.attempt)?;
        Ok(Some(d))
    }

    /// record(index, attempt=None, timed_out=None, error=None) -> dict
    ///
    /// Records point `index` from its run directory (or the neighbour-pass `attempt` the
    /// job was, folded in when its round is): `timed_out` (the time limit in s) when its
    /// job stopped at the limit, `error` (a message) when the job raised. Returns the row
    /// (`index`, `point`, `status`, `solver_status`, `objective`, `note`).
    #[pyo3(signature = (index, attempt = None, timed_out = None, error = None))]
    fn record<'py>(
        &self,
        py: Python<'py>,
        index: usize,
        attempt: Option<String>,
        timed_out: Option<f64>,
        error: Option<String>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let outcome = match (timed_out, error) {
            (_, Some(message)) => JobOutcome::Failed(message),
            (Some(limit_s), None) => JobOutcome::TimedOut { limit_s },
            (None, None) => JobOutcome::Returned,
        };
        let row =
            py.detach(|| self.with(|s| s.record(index, attempt.as_deref(), outcome).cloned()))?;
        let d = PyDict::new(py);
        d.set_item("index", row.index)?;
        d.set_item("point", row.point_label())?;
        d.set_item("status", row.status.name())?;
        d.set_item("solver_status", row.solver_status)?;
        d.set_item("objective", row.objective)?;
        d.set_item("note", row.note)?;
        Ok(d)
    }

    /// stop()
    ///
    /// Ends the sweep early: the points handed out and not recorded, and the rest, stay
    /// pending (not run; a rerun of the sweep runs them). The jobs handed out that solve in
    /// this process (a thread executor's) stop at their next iteration; those elsewhere
    /// finish on their own.
    fn stop(&self) -> PyResult<()> {
        self.with(|s| {
            stop_in_process(&s.running_dirs());
            s.stop()
        })
    }

    /// The counts: done, failed, interrupted, running, total, skipped.
    #[getter]
    fn counts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let counts = self.with(|s| Ok(s.counts()))?;
        counts_dict(py, &counts)
    }

    /// The per-run time limit [s], or None.
    #[getter]
    fn time_limit(&self) -> Option<f64> {
        self.time_limit
    }

    /// The table file (`sweep.csv`).
    #[getter]
    fn table_csv(&self) -> PathBuf {
        self.out.join(vito::sweep::TABLE_CSV)
    }
}

/// _solve_point(problem, sets, run_dir, time_limit=None, starts=1, seed=0, sha256=None)
///     -> float | None
///
/// One sweep point, as `vito solve PROBLEM --set ... --out RUN_DIR` solves it, in this
/// process: loads the problem with `sets` (refused when `sha256` is given and the file's
/// differs: it changed since the sweep opened), solves, writes the run directory (also the
/// iterate of a solve stopped at `time_limit` seconds, by Ctrl-C or by its sweep's `stop()`
/// when it runs in the sweep's process). Returns the time limit
/// when it stopped the solve, else None. Raises what loading or writing raises.
#[pyfunction]
#[pyo3(signature = (problem, sets, run_dir, time_limit = None, starts = 1, seed = 0,
                    sha256 = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn _solve_point(
    py: Python<'_>,
    problem: PathArg,
    sets: Vec<String>,
    run_dir: PathArg,
    time_limit: Option<f64>,
    starts: usize,
    seed: u64,
    sha256: Option<String>,
) -> PyResult<Option<f64>> {
    let (problem, run_dir) = (problem.0, run_dir.0);
    let time_limit = time_limit_of(time_limit)?;
    let starts = crate::convert::count("starts", starts, vito::transcription::MAX_STARTS)?;
    let loaded = Arc::new(load_problem(py, &problem, &sets)?);
    if let Some(sha256) = &sha256 {
        same_file(
            &loaded,
            sha256,
            "this sweep job cannot run",
            "its sweep opened",
            "rerun the sweep (the points solved with the file as it was are solved again)",
        )?;
    }
    let target = pipeline::output::checked_output_dir(&loaded, Some(&run_dir))
        .map_err(|e| vito_error(&report::ReportError::from(e)))?;
    let deadline = time_limit.map(|t| Instant::now() + Duration::from_secs_f64(t));
    let job = InProcessJob::register(&run_dir);
    let solved = solve_loaded(
        py,
        &loaded,
        MultiStart {
            starts,
            seed,
            only: None,
        },
        None,
        deadline,
        job.cancel.clone(),
    )?;
    drop(job);
    let solution = Solution {
        source: (problem, sets),
        problem: loaded,
        solution: solved.solution,
    };
    py.detach(|| solution.write_to(target))?;
    match solved.error {
        Some(e) => Err(e),
        None => Ok(time_limit.filter(|_| solved.timed_out)),
    }
}
