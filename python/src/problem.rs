//! `vito.Problem`: a loaded and checked problem file with its overrides; `check()` and
//! `solve()` as the command runs them; pickled as its file and overrides.

use std::path::PathBuf;
use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use vito::pipeline;
use vito::problem::{InitialGuess, LoadedProblem};
use vito::report;
use vito::transcription::MultiStart;

use crate::convert::{PathArg, check_progress, python_path, set_args, set_literal};
use crate::errors::{VitoError, vito_error};
use crate::load::{load_problem, reload_pickled};
use crate::solution::Solution;
use crate::solve::solve_loaded;

/// A loaded problem file: what `vito check` and `vito solve` read.
#[pyclass(module = "vito", frozen)]
pub(crate) struct Problem {
    /// The file as given.
    pub(crate) path: PathBuf,
    /// `--set` arguments applied, in order.
    pub(crate) sets: Vec<String>,
    pub(crate) loaded: Arc<LoadedProblem>,
}

impl Problem {
    pub(crate) fn open(py: Python<'_>, path: PathBuf, sets: Vec<String>) -> PyResult<Problem> {
        let loaded = load_problem(py, &path, &sets)?;
        Ok(Problem {
            path,
            sets,
            loaded: Arc::new(loaded),
        })
    }

    /// The file as an absolute path (what a pickle carries to another process).
    pub(crate) fn absolute_path(&self) -> PyResult<PathBuf> {
        std::path::absolute(&self.path)
            .map_err(|e| VitoError::new_err(format!("{}: {e}", self.path.display())))
    }
}

/// Rebuilds a pickled `Problem`: the file must still be where it was, with the overrides
/// still valid, and unchanged (its SHA-256 `sha256`).
#[pyfunction]
#[pyo3(signature = (path, sets, sha256 = None))]
pub(crate) fn _restore_problem(
    py: Python<'_>,
    path: PathArg,
    sets: Vec<String>,
    sha256: Option<String>,
) -> PyResult<Problem> {
    let path = path.0;
    let loaded = reload_pickled(py, "Problem", &path, &sets, sha256.as_deref())?;
    Ok(Problem {
        path,
        sets,
        loaded: Arc::new(loaded),
    })
}

#[pymethods]
impl Problem {
    /// Problem(path, set=None)
    ///
    /// Loads and checks a problem file (`path`: a str, bytes or os.PathLike), with `set` (a
    /// dict `{"key.path": value}`) applied as `vito solve FILE --set key.path=value` applies
    /// it: a str value is taken as the command line takes it (TOML, a bare word a string),
    /// bool, int, float and lists as TOML (values nest at most 64 deep and take at most
    /// 128 KiB as TOML; ValueError beyond). Raises `FileNotFoundError` (as
    /// `ProblemFileNotFoundError`, also a `ProblemError`) when the file does not exist,
    /// `ProblemError` (file, line, field, message) when the file, an override or a
    /// `[solver.ipopt]` option cannot be used.
    #[new]
    #[pyo3(signature = (path, set = None))]
    fn new(py: Python<'_>, path: PathArg, set: Option<&Bound<'_, PyAny>>) -> PyResult<Problem> {
        Problem::open(py, path.0, set_args(set)?)
    }

    /// The problem's name (`name` in the file).
    #[getter]
    fn name(&self) -> String {
        self.loaded.spec.name.clone()
    }

    /// The problem file as given.
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    /// The overrides applied, as `key.path=value` strings (the command line's `--set`).
    #[getter]
    fn sets(&self) -> Vec<String> {
        self.sets.clone()
    }

    /// A family's `[parameters]`: name → value with the overrides applied (empty when the
    /// file declares none).
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, value) in &self.loaded.family_parameters {
            d.set_item(name, value)?;
        }
        Ok(d)
    }

    /// with_set(set) -> Problem
    ///
    /// A copy of this problem with more overrides (a dict as for `Problem`) applied after
    /// this one's; the file is read and checked again.
    fn with_set(&self, py: Python<'_>, set: &Bound<'_, PyAny>) -> PyResult<Problem> {
        let mut sets = self.sets.clone();
        sets.extend(set_args(Some(set))?);
        Problem::open(py, self.path.clone(), sets)
    }

    /// check() -> dict
    ///
    /// What `vito check` reports: the names (coordinates, inputs, contacts), the horizon,
    /// the NLP's size as the solver builds it, each contact's distance to the terrain at the
    /// first and last knot of the initial guess, and the warnings.
    fn check<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let p = &self.loaded;
        let s = &p.spec;
        let report = py
            .detach(|| pipeline::check_report(s))
            .map_err(|e| vito_error(&e))?;
        let d = PyDict::new(py);
        d.set_item("name", &s.name)?;
        d.set_item("file", p.file.display().to_string())?;
        d.set_item("knots", s.knots)?;
        d.set_item("coordinates", &p.robot.coordinates)?;
        d.set_item("inputs", &p.robot.inputs)?;
        let contacts: Vec<&str> = s.contacts.iter().map(|c| c.name.as_str()).collect();
        d.set_item("contacts", contacts)?;
        d.set_item("friction_directions", report.friction_directions)?;
        d.set_item("n_variables", report.size.n_variables)?;
        d.set_item("n_constraints", report.size.n_constraints)?;
        d.set_item("nnz_jacobian", report.size.nnz_jacobian)?;
        d.set_item("nnz_hessian", report.size.nnz_hessian)?;
        let clearances = PyDict::new(py);
        for c in &report.feasibility.clearances {
            clearances.set_item(&c.name, (c.first, c.last))?;
        }
        d.set_item("clearances", clearances)?;
        d.set_item("warnings", &report.feasibility.warnings)?;
        d.set_item("robot_warnings", &p.robot.warnings)?;
        Ok(d)
    }

    /// solve(out=None, starts=1, seed=0, warm_start=None, progress=None) -> Solution
    ///
    /// Solves the problem as `vito solve` does and returns the `Solution`. With `out`, also
    /// writes what `vito solve --out OUT` writes (checked before solving: only vito's own
    /// results or an empty directory are replaced, atomically). `starts`/`seed`: the
    /// command's `--starts`/`--seed`. `warm_start`: a `Solution` or the path of a
    /// `trajectory.csv` to start from (as `initial_guess.warm_start`). `progress`: called
    /// with a dict (iteration, objective, inf_pr, inf_du, max_slack) at each iteration.
    ///
    /// Releases the GIL while solving; a second solve (another thread) waits for the first.
    /// Ctrl-C (SIGINT) stops the solve after the current iteration and raises
    /// `KeyboardInterrupt` whose `solution` attribute holds the iterate reached (written to
    /// `out` first, like the command); an exception raised by `progress` stops it likewise
    /// and is re-raised with the same attribute.
    #[pyo3(signature = (out = None, starts = 1, seed = 0, warm_start = None, progress = None))]
    fn solve(
        &self,
        py: Python<'_>,
        out: Option<PathArg>,
        starts: usize,
        seed: u64,
        warm_start: Option<&Bound<'_, PyAny>>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Py<Solution>> {
        let starts = crate::convert::count("starts", starts, vito::transcription::MAX_STARTS)?;
        check_progress(py, progress.as_ref())?;
        let problem = match warm_start {
            None => self.loaded.clone(),
            Some(w) => {
                if let Ok(solution) = w.cast::<Solution>() {
                    let mut problem = (*self.loaded).clone();
                    let warm = solution
                        .get()
                        .solution
                        .warm_start(PathBuf::from("Solution"));
                    problem.spec.initial_guess = InitialGuess::WarmStart(warm);
                    Arc::new(problem)
                } else {
                    let path = w.extract::<PathArg>()?.0;
                    let path = std::path::absolute(&path)
                        .map_err(|e| VitoError::new_err(format!("{}: {e}", path.display())))?;
                    // Given to the problem as `initial_guess.warm_start`, a TOML string.
                    let text = path.to_str().ok_or_else(|| {
                        pyo3::exceptions::PyValueError::new_err(format!(
                            "warm_start={}: the path is not UTF-8, so it cannot be a problem's \
                             `initial_guess.warm_start`; rename the file, or pass the Solution",
                            python_path(&path)
                        ))
                    })?;
                    let value = toml::Value::String(text.to_owned());
                    let mut sets = self.sets.clone();
                    sets.push(format!("initial_guess.warm_start={value}"));
                    Arc::new(load_problem(py, &self.path, &sets)?)
                }
            }
        };
        let target = match out.as_ref().map(|dir| &dir.0) {
            Some(dir) => Some(
                pipeline::output::checked_output_dir(&problem, Some(dir))
                    .map_err(|e| vito_error(&report::ReportError::from(e)))?,
            ),
            None => None,
        };
        let solved = solve_loaded(
            py,
            &problem,
            MultiStart {
                starts,
                seed,
                only: None,
            },
            progress,
            None,
            Arc::default(),
        )?;
        let solution = Solution {
            source: (self.path.clone(), self.sets.clone()),
            problem: problem.clone(),
            solution: solved.solution,
        };
        if let Some(target) = target {
            py.detach(|| solution.write_to(target))?;
        }
        let solution = solution.into_py(py)?;
        match solved.error {
            None => Ok(solution),
            Some(e) => {
                e.value(py).setattr("solution", solution)?;
                Err(e)
            }
        }
    }

    /// Pickled as its file (absolute), overrides and the file's SHA-256: unpickling loads
    /// the file again, and refuses it when it has changed.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let restore = py.import("vito._vito")?.getattr("_restore_problem")?;
        let args = (
            self.absolute_path()?,
            self.sets.clone(),
            self.loaded.sha256.clone(),
        )
            .into_pyobject(py)?;
        PyTuple::new(py, [restore, args.into_any()])
    }

    fn __repr__(&self) -> String {
        let path = python_path(&self.path);
        if self.sets.is_empty() {
            format!("vito.Problem({path})")
        } else {
            format!("vito.Problem({path}, set={})", set_literal(&self.sets))
        }
    }
}
