//! `vito._vito`: the Python binding of the `vito` library (the package `vito` re-exports it).
//!
//! Nothing here solves, writes or checks anything itself: each call runs the library
//! functions the `vito` command runs (problem loading, `pipeline`, `report`, `sweep`), and
//! turns their results into Python objects (numpy arrays, dicts) and their errors into
//! Python exceptions. Long calls release the GIL.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use vito::pipeline;
use vito::problem::{InitialGuess, LoadedProblem, Override};
use vito::report;
use vito::transcription::{MultiStart, SolveOptions};

pyo3::create_exception!(
    vito,
    VitoError,
    PyException,
    "An error of vito: the message is the one the `vito` command prints."
);
pyo3::create_exception!(
    vito,
    ProblemError,
    VitoError,
    "A problem file (or an override, or a file it names) that vito cannot use, found before \
     any solving. Attributes: `file`, `line` (1-based, or None), `field` (the TOML path, or \
     ''), `message` (what the `vito` command prints after `error:`)."
);

/// A library error as a Python exception: a [`ProblemError`] with its location, or a
/// [`VitoError`] with the command's message.
fn problem_error(py: Python<'_>, e: &vito::problem::ProblemError) -> PyErr {
    let message = e.to_string();
    let err = ProblemError::new_err(message.clone());
    let value = err.value(py);
    let location = e.location();
    let set = |name: &str, v: Bound<'_, PyAny>| value.setattr(name, v);
    let result = (|| -> PyResult<()> {
        set(
            "file",
            match location {
                Some(l) => l.file.display().to_string().into_pyobject(py)?.into_any(),
                None => py.None().into_bound(py),
            },
        )?;
        set(
            "line",
            match location.and_then(|l| l.line) {
                Some(line) => line.into_pyobject(py)?.into_any(),
                None => py.None().into_bound(py),
            },
        )?;
        set(
            "field",
            location
                .map_or(String::new(), |l| l.field.clone())
                .into_pyobject(py)?
                .into_any(),
        )?;
        set("message", message.into_pyobject(py)?.into_any())
    })();
    match result {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// Any other library error, with its chain of causes as the command prints it.
fn vito_error(e: &dyn std::error::Error) -> PyErr {
    let mut message = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        let text = s.to_string();
        if !message.contains(&text) {
            message.push_str(&format!("\n  caused by: {text}"));
        }
        source = s.source();
    }
    VitoError::new_err(message)
}

/// A Python value of `set={...}` as the text of a `--set` value (TOML): strings as given
/// (like the command line), booleans, numbers and lists as TOML.
fn set_value_text(value: &Bound<'_, PyAny>) -> PyResult<String> {
    if value.is_instance_of::<PyString>() {
        return value.extract::<String>();
    }
    if value.is_instance_of::<PyBool>() {
        return Ok(if value.extract::<bool>()? {
            "true"
        } else {
            "false"
        }
        .to_owned());
    }
    if value.is_instance_of::<PyInt>() {
        return Ok(value.extract::<i64>()?.to_string());
    }
    if value.is_instance_of::<PyFloat>() {
        let x = value.extract::<f64>()?;
        // TOML spells the non-finite values inf and nan; Rust's `{:?}` keeps a `.0`.
        return Ok(if x.is_nan() {
            "nan".into()
        } else if x.is_infinite() {
            if x > 0.0 { "inf" } else { "-inf" }.into()
        } else {
            format!("{x:?}")
        });
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items: Vec<String> = value
            .try_iter()?
            .map(|item| set_value_text(&item?))
            .collect::<PyResult<_>>()?;
        return Ok(format!("[{}]", items.join(", ")));
    }
    Ok(value.str()?.to_string())
}

/// `set={key: value}` as `--set key=value` arguments (in the dict's order).
fn set_args(set: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<String>> {
    let Some(set) = set else {
        return Ok(Vec::new());
    };
    set.iter()
        .map(|(k, v)| {
            Ok(format!(
                "{}={}",
                k.extract::<String>()?,
                set_value_text(&v)?
            ))
        })
        .collect()
}

/// A `serde_json` value as Python objects (through Python's `json`).
fn json_to_py<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(|e| VitoError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// Rows of equal length as a 2-D array of shape (rows, width).
fn matrix<'py>(py: Python<'py>, rows: &[Vec<f64>], width: usize) -> Bound<'py, PyAny> {
    let flat: Vec<f64> = rows.iter().flat_map(|r| r.iter().copied()).collect();
    match Array2::from_shape_vec((rows.len(), width), flat) {
        Ok(a) => a.into_pyarray(py).into_any(),
        Err(_) => PyArray1::<f64>::zeros(py, 0, false).into_any(),
    }
}

/// The columns of a trajectory CSV (the text vito writes) as `(header, values)`: the header
/// cells as written (`x [m]`), the values as the library reads them back (blank cells NaN).
fn csv_columns(csv: &str) -> PyResult<Vec<(String, Vec<f64>)>> {
    let headers: Vec<String> = csv
        .lines()
        .next()
        .unwrap_or_default()
        .split(',')
        .map(str::to_owned)
        .collect();
    let table = report::read_csv(csv).map_err(VitoError::new_err)?;
    Ok(headers.into_iter().zip(table.columns).collect())
}

/// A DataFrame of a trajectory CSV's columns, in its order, under its header.
fn csv_dataframe<'py>(py: Python<'py>, csv: &str) -> PyResult<Bound<'py, PyAny>> {
    let pandas = py.import("pandas")?;
    let data = PyDict::new(py);
    let mut order = Vec::new();
    for (header, values) in csv_columns(csv)? {
        data.set_item(&header, Array1::from(values).into_pyarray(py))?;
        order.push(header);
    }
    let kwargs = PyDict::new(py);
    kwargs.set_item("columns", order)?;
    pandas.call_method("DataFrame", (data,), Some(&kwargs))
}

/// What a solve or a simulation writes as `trajectory.csv`, kept as its text: the base class
/// of `Solution` and `Simulation`.
#[pyclass(module = "vito", frozen, subclass)]
struct Trajectory {
    csv: String,
}

#[pymethods]
impl Trajectory {
    /// The header of `trajectory.csv` (names with `[unit]`), in order.
    #[getter]
    fn columns(&self) -> PyResult<Vec<String>> {
        Ok(csv_columns(&self.csv)?
            .into_iter()
            .map(|(h, _)| h)
            .collect())
    }

    /// trajectory_csv() -> str
    ///
    /// The text of `trajectory.csv` exactly as the command (`vito solve`, `vito simulate`)
    /// writes it.
    fn trajectory_csv(&self) -> String {
        self.csv.clone()
    }

    /// to_pandas() -> pandas.DataFrame
    ///
    /// The trajectory as `trajectory.csv` holds it: one row per knot, its columns (names
    /// with units) in its order, blank cells NaN. Needs pandas.
    fn to_pandas<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        csv_dataframe(py, &self.csv)
    }
}

/// A loaded problem file: what `vito check` and `vito solve` read.
#[pyclass(module = "vito", frozen)]
struct Problem {
    /// The file as given.
    path: PathBuf,
    /// `--set` arguments applied, in order.
    sets: Vec<String>,
    loaded: Arc<LoadedProblem>,
}

/// Loads `path` with `sets` as `vito solve FILE --set ...` does.
fn load_problem(py: Python<'_>, path: &Path, sets: &[String]) -> PyResult<LoadedProblem> {
    let overrides: Vec<Override> = sets
        .iter()
        .map(|s| Override::parse(s))
        .collect::<Result<_, _>>()
        .map_err(|e| problem_error(py, &e))?;
    let loaded = vito::problem::load(path, &overrides).map_err(|e| problem_error(py, &e))?;
    pipeline::check_solver_options(&loaded).map_err(|e| problem_error(py, &e))?;
    Ok(loaded)
}

impl Problem {
    fn open(py: Python<'_>, path: PathBuf, sets: Vec<String>) -> PyResult<Problem> {
        let loaded = load_problem(py, &path, &sets)?;
        Ok(Problem {
            path,
            sets,
            loaded: Arc::new(loaded),
        })
    }
}

/// How a solve reports to Python: the user's progress callable and the signals, checked at
/// each Ipopt iteration with the GIL held briefly; the first exception stops the solve.
struct PythonHooks {
    progress: Option<Py<PyAny>>,
    cancel: Arc<AtomicBool>,
    error: Mutex<Option<PyErr>>,
}

impl PythonHooks {
    fn at_iteration(&self, p: &vito::transcription::Progress) {
        Python::attach(|py| {
            let outcome = py.check_signals().and_then(|()| match &self.progress {
                None => Ok(()),
                Some(callable) => {
                    let info = PyDict::new(py);
                    info.set_item("iteration", p.iteration)?;
                    info.set_item("objective", p.objective)?;
                    info.set_item("inf_pr", p.inf_pr)?;
                    info.set_item("inf_du", p.inf_du)?;
                    info.set_item("max_slack", p.max_slack)?;
                    callable.call1(py, (info,)).map(drop)
                }
            });
            if let Err(e) = outcome {
                self.cancel.store(true, Ordering::SeqCst);
                let mut slot = self.error.lock().unwrap_or_else(|p| p.into_inner());
                slot.get_or_insert(e);
            }
        });
    }
}

#[pymethods]
impl Problem {
    /// Problem(path, set=None)
    ///
    /// Loads and checks a problem file, with `set` (a dict `{"key.path": value}`) applied as
    /// `vito solve FILE --set key.path=value` applies it: a string value is taken as the
    /// command line takes it (TOML, a bare word a string), numbers, booleans and lists as
    /// TOML. Raises `ProblemError` (file, line, field, message) when the file, an override or
    /// a `[solver.ipopt]` option cannot be used.
    #[new]
    #[pyo3(signature = (path, set = None))]
    fn new(py: Python<'_>, path: PathBuf, set: Option<&Bound<'_, PyDict>>) -> PyResult<Problem> {
        Problem::open(py, path, set_args(set)?)
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
    fn with_set(&self, py: Python<'_>, set: &Bound<'_, PyDict>) -> PyResult<Problem> {
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
        let (size, nd, feasibility) = py
            .detach(|| {
                let nlp = pipeline::build_nlp(s)?;
                Ok::<_, vito::transcription::TranscriptionError>((
                    nlp.size(),
                    nlp.layout().nd,
                    pipeline::feasibility::feasibility(s, &nlp),
                ))
            })
            .map_err(|e| vito_error(&e))?;
        let d = PyDict::new(py);
        d.set_item("name", &s.name)?;
        d.set_item("file", p.file.display().to_string())?;
        d.set_item("knots", s.knots)?;
        d.set_item("coordinates", &p.robot.coordinates)?;
        d.set_item("inputs", &p.robot.inputs)?;
        let contacts: Vec<&str> = s.contacts.iter().map(|c| c.name.as_str()).collect();
        d.set_item("contacts", contacts)?;
        d.set_item("friction_directions", nd)?;
        d.set_item("n_variables", size.n_variables)?;
        d.set_item("n_constraints", size.n_constraints)?;
        d.set_item("nnz_jacobian", size.nnz_jacobian)?;
        d.set_item("nnz_hessian", size.nnz_hessian)?;
        let clearances = PyDict::new(py);
        for c in &feasibility.clearances {
            clearances.set_item(&c.name, (c.first, c.last))?;
        }
        d.set_item("clearances", clearances)?;
        d.set_item("warnings", &feasibility.warnings)?;
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
        out: Option<PathBuf>,
        starts: usize,
        seed: u64,
        warm_start: Option<&Bound<'_, PyAny>>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Py<Solution>> {
        if starts == 0 {
            return Err(VitoError::new_err("starts=0: give at least 1"));
        }
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
                    let path: PathBuf = w.extract()?;
                    let path = std::path::absolute(&path)
                        .map_err(|e| VitoError::new_err(format!("{}: {e}", path.display())))?;
                    let value = toml::Value::String(path.display().to_string());
                    let mut sets = self.sets.clone();
                    sets.push(format!("initial_guess.warm_start={value}"));
                    Arc::new(load_problem(py, &self.path, &sets)?)
                }
            }
        };
        let target = match &out {
            Some(dir) => Some(
                pipeline::output::checked_output_dir(&problem, Some(dir))
                    .map_err(|e| vito_error(&report::ReportError::from(e)))?,
            ),
            None => None,
        };
        let cancel = Arc::new(AtomicBool::new(false));
        let hooks = Arc::new(PythonHooks {
            progress,
            cancel: cancel.clone(),
            error: Mutex::new(None),
        });
        let options = SolveOptions {
            progress: Some(Box::new({
                let hooks = hooks.clone();
                move |p: &vito::transcription::Progress| hooks.at_iteration(p)
            })),
            cancel: Some(cancel),
            ipopt_options: Vec::new(),
            multi_start: Some(MultiStart { starts, seed }),
            deadline: None,
        };
        let solved = py.detach(|| pipeline::solve(&problem.spec, &options));
        drop(options);
        let solution = Solution {
            problem: problem.clone(),
            solution: solved.map_err(|e| vito_error(&e))?,
        };
        if let Some(target) = target {
            py.detach(|| solution.write_to(target))?;
        }
        let solution = solution.into_py(py)?;
        let error = hooks.error.lock().unwrap_or_else(|p| p.into_inner()).take();
        match error {
            None => Ok(solution),
            Some(e) => {
                e.value(py).setattr("solution", solution)?;
                Err(e)
            }
        }
    }

    fn __repr__(&self) -> String {
        format!(
            "vito.Problem({:?}, set={:?})",
            self.path.display().to_string(),
            self.sets
        )
    }
}

/// A solve's result: the verdict, the numbers of `summary.json`, and the trajectory as
/// arrays with named axes.
#[pyclass(module = "vito", frozen, extends = Trajectory)]
struct Solution {
    problem: Arc<LoadedProblem>,
    solution: vito::transcription::Solution,
}

impl Solution {
    /// The Python object, with its `trajectory.csv` text in the base class.
    fn into_py(self, py: Python<'_>) -> PyResult<Py<Solution>> {
        let units = report::column_units(&self.problem.robot, &self.problem.units);
        let csv = report::trajectory_csv(&self.solution, &units);
        Py::new(
            py,
            PyClassInitializer::from(Trajectory { csv }).add_subclass(self),
        )
    }

    /// Rows of one value per contact as an (rows, nc) array.
    fn per_contact<'py>(&self, py: Python<'py>, rows: &[Vec<f64>]) -> Bound<'py, PyAny> {
        matrix(py, rows, self.solution.contact_names.len())
    }

    /// Writes into a checked target as `vito solve` does (staged, then committed).
    fn write_to(&self, target: report::OutputTarget) -> PyResult<PathBuf> {
        target
            .stage()
            .map_err(report::ReportError::from)
            .and_then(|staged| report::write_outputs(staged, &self.problem, &self.solution))
            .map_err(|e| vito_error(&e))
    }
}

#[pymethods]
impl Solution {
    /// The verdict, as `summary.json`'s `status` (e.g. `solve_succeeded`).
    #[getter]
    fn status(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let summary = report::summary_json(&self.problem, &self.solution);
        Ok(json_to_py(py, &summary["status"])?.unbind())
    }

    /// Whether the verdict counts as solved (the command's exit code 0).
    #[getter]
    fn solved(&self) -> bool {
        self.solution.verdict().is_solved()
    }

    /// Total objective (problem cost + slack penalty).
    #[getter]
    fn objective(&self) -> f64 {
        self.solution.objective
    }

    /// The objective by term (e.g. `state_tracking`, `input`, `slack_penalty`), in order.
    #[getter]
    fn objective_terms<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, value) in &self.solution.objective_terms {
            d.set_item(name, value)?;
        }
        Ok(d)
    }

    /// Ipopt iterations (summed over the solves of a slack continuation).
    #[getter]
    fn iterations(&self) -> usize {
        self.solution.iterations
    }

    /// The largest slack of the complementarity rows.
    #[getter]
    fn max_slack(&self) -> f64 {
        self.solution.max_slack
    }

    /// `summary.json` as a dict (what `vito solve` writes).
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &report::summary_json(&self.problem, &self.solution))
    }

    /// Knot times, shape (N,).
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        Array1::from(self.solution.times.clone())
            .into_pyarray(py)
            .into_any()
    }

    /// Configurations at the knots, shape (N, n); columns `coordinate_names`.
    #[getter]
    fn q<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        matrix(py, &self.solution.q, self.solution.coordinate_names.len())
    }

    /// Velocities at the knots, shape (N, n); columns `coordinate_names`.
    #[getter]
    fn v<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        matrix(py, &self.solution.v, self.solution.coordinate_names.len())
    }

    /// Inputs per interval, shape (N−1, m); columns `input_names`.
    #[getter]
    fn u<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        matrix(py, &self.solution.u, self.solution.input_names.len())
    }

    /// Normal contact impulses per interval, shape (N−1, nc); columns `contact_names`.
    #[getter]
    fn normal_impulse<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        self.per_contact(py, &self.solution.normal_impulse)
    }

    /// Friction impulses per interval, shape (N−1, nc, nd); axes `contact_names`,
    /// `friction_directions`.
    #[getter]
    fn friction_impulse<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let s = &self.solution;
        let (nc, nd) = (s.contact_names.len(), s.friction_directions);
        let flat: Vec<f64> = s
            .friction_impulse
            .iter()
            .flatten()
            .flatten()
            .copied()
            .collect();
        match Array3::from_shape_vec((s.friction_impulse.len(), nc, nd), flat) {
            Ok(a) => a.into_pyarray(py).into_any(),
            Err(_) => PyArray1::<f64>::zeros(py, 0, false).into_any(),
        }
    }

    /// Signed distance of each contact to the terrain at every knot, shape (N, nc); columns
    /// `contact_names`. The normal impulse of interval k is complementary to row k + 1.
    #[getter]
    fn signed_distance<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        self.per_contact(py, &self.solution.signed_distance)
    }

    /// Slacks per interval, shape (N−1, slacks per interval).
    #[getter]
    fn slack<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let width = self.solution.slack.first().map_or(0, Vec::len);
        matrix(py, &self.solution.slack, width)
    }

    /// Names of the coordinates (the columns of `q` and `v`).
    #[getter]
    fn coordinate_names(&self) -> Vec<String> {
        self.solution.coordinate_names.clone()
    }

    /// Names of the inputs (the columns of `u`).
    #[getter]
    fn input_names(&self) -> Vec<String> {
        self.solution.input_names.clone()
    }

    /// Names of the contacts (the columns of the impulses and distances).
    #[getter]
    fn contact_names(&self) -> Vec<String> {
        self.solution.contact_names.clone()
    }

    /// Names of the friction directions (the last axis of `friction_impulse`).
    #[getter]
    fn friction_directions(&self) -> Vec<String> {
        report::friction_direction_names(self.solution.friction_directions)
    }

    /// Units of each array: a dict from `time`, `q`, `v`, `u`, `normal_impulse`,
    /// `friction_impulse`, `signed_distance` to a unit (a list of units, one per column,
    /// where they differ by column).
    #[getter]
    fn units<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let u = report::column_units(&self.problem.robot, &self.problem.units);
        let d = PyDict::new(py);
        d.set_item("time", &u.time)?;
        d.set_item("q", &u.coordinates)?;
        let rates: Vec<String> = u
            .coordinates
            .iter()
            .map(|c| format!("{c}/{}", u.time))
            .collect();
        d.set_item("v", rates)?;
        d.set_item("u", &u.inputs)?;
        d.set_item("normal_impulse", &u.impulse)?;
        d.set_item("friction_impulse", &u.impulse)?;
        d.set_item("signed_distance", &u.length)?;
        Ok(d)
    }

    /// write(dir) -> str
    ///
    /// Writes what `vito solve --out DIR` writes (trajectory.csv, summary.json, the plots),
    /// atomically; only vito's own results or an empty directory are replaced. Returns the
    /// directory.
    fn write(&self, py: Python<'_>, dir: PathBuf) -> PyResult<PathBuf> {
        let target = pipeline::output::checked_output_dir(&self.problem, Some(&dir))
            .map_err(|e| vito_error(&report::ReportError::from(e)))?;
        py.detach(|| self.write_to(target))
    }

    fn __repr__(&self) -> String {
        format!(
            "<vito.Solution {} {}: objective {:e}, {} iterations, max slack {:.3e}>",
            self.problem.spec.name,
            report::status_name(self.solution.status),
            self.solution.objective,
            self.solution.iterations,
            self.solution.max_slack
        )
    }
}

/// A forward simulation's result (`vito simulate`): its summary and trajectory.
#[pyclass(module = "vito", frozen, extends = Trajectory)]
struct Simulation {
    problem: Arc<LoadedProblem>,
    sim: vito::sim::Simulation,
    columns: report::SimulationColumns,
    summary: serde_json::Value,
    /// Files the output directory must not be (the problem, its robot, the CSVs read).
    inputs: Vec<PathBuf>,
}

impl Simulation {
    /// The Python object, with its `trajectory.csv` text in the base class.
    fn into_py(self, py: Python<'_>) -> PyResult<Py<Simulation>> {
        let units = report::column_units(&self.problem.robot, &self.problem.units);
        let csv = vito::files::trajectory_csv::write_trajectory(
            &self.columns.trajectory(&self.sim),
            &units,
        );
        Py::new(
            py,
            PyClassInitializer::from(Trajectory { csv }).add_subclass(self),
        )
    }

    /// Writes into a checked target as `vito simulate` does (staged, then committed).
    fn write_to(&self, target: report::OutputTarget) -> PyResult<PathBuf> {
        target
            .stage()
            .map_err(report::ReportError::from)
            .and_then(|staged| {
                report::write_trajectory_outputs(
                    staged,
                    &self.problem,
                    &self.columns.trajectory(&self.sim),
                    &self.summary,
                )
            })
            .map_err(|e| vito_error(&e))
    }
}

#[pymethods]
impl Simulation {
    /// `summary.json` of the simulation as a dict (what `vito simulate` writes).
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &self.summary)
    }

    /// Knot times, shape (N + 1,).
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        Array1::from(self.sim.times.clone())
            .into_pyarray(py)
            .into_any()
    }

    /// Configurations, shape (N + 1, n); columns `coordinate_names`.
    #[getter]
    fn q<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        matrix(py, &self.sim.q, self.problem.robot.coordinates.len())
    }

    /// Velocities, shape (N + 1, n); columns `coordinate_names`.
    #[getter]
    fn v<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        matrix(py, &self.sim.v, self.problem.robot.coordinates.len())
    }

    /// Inputs per step, shape (N, m); columns `input_names`.
    #[getter]
    fn u<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        matrix(py, &self.sim.u, self.problem.robot.inputs.len())
    }

    /// Names of the coordinates.
    #[getter]
    fn coordinate_names(&self) -> Vec<String> {
        self.problem.robot.coordinates.clone()
    }

    /// Names of the inputs.
    #[getter]
    fn input_names(&self) -> Vec<String> {
        self.problem.robot.inputs.clone()
    }

    /// write(dir) -> str
    ///
    /// Writes what `vito simulate --out DIR` writes, atomically, with the command's rules
    /// for the directory. Returns the directory.
    fn write(&self, py: Python<'_>, dir: PathBuf) -> PyResult<PathBuf> {
        let target = output_target(&dir, &self.inputs)?;
        py.detach(|| self.write_to(target))
    }
}

/// `dir` checked as `vito simulate --out DIR` checks it (never one of `inputs`, only vito's
/// own results or an empty directory replaced).
fn output_target(dir: &Path, inputs: &[PathBuf]) -> PyResult<report::OutputTarget> {
    let protected: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    report::OutputTarget::check(dir, &protected)
        .map_err(|e| vito_error(&report::ReportError::from(e)))
}

/// A trajectory argument of `simulate`: a path, or a `Solution` (its `trajectory.csv` in a
/// temporary file, read as the command reads a file).
fn trajectory_path(
    value: Option<&Bound<'_, PyAny>>,
    scratch: &mut Option<tempfile::TempDir>,
    name: &str,
) -> PyResult<Option<PathBuf>> {
    let Some(value) = value else {
        return Ok(None);
    };
    if let Ok(solution) = value.cast::<Solution>() {
        let dir = match scratch {
            Some(dir) => dir,
            None => {
                scratch.insert(tempfile::tempdir().map_err(|e| VitoError::new_err(e.to_string()))?)
            }
        };
        let path = dir.path().join(format!("{name}.csv"));
        std::fs::write(&path, &solution.as_super().get().csv)
            .map_err(|e| VitoError::new_err(format!("{}: {e}", path.display())))?;
        return Ok(Some(path));
    }
    Ok(Some(value.extract()?))
}

/// simulate(problem, inputs=None, track=None, gains=None, feedback=None, duration=None,
///          rate=None, integrator=None, out=None) -> Simulation
///
/// Simulates the problem's robot forward as `vito simulate` does: zero inputs, or the inputs
/// of `inputs` replayed, or `track` followed with PD feedback (`gains`: a dict
/// `{input or "all": (kp, kd)}` on top of the file's `[tracking] gains`; `feedback`:
/// "explicit" or "implicit"). `inputs` and `track` are a `Solution` or the path of a
/// `trajectory.csv`. `duration`, `rate` (steps per time unit) and `integrator` ("midpoint",
/// "euler", "galerkin4" or "galerkin6") as the command's options. With `out`, also writes what the command writes.
/// Releases the GIL while simulating.
#[pyfunction]
#[pyo3(signature = (problem, inputs = None, track = None, gains = None, feedback = None,
                    duration = None, rate = None, integrator = None, out = None))]
#[allow(clippy::too_many_arguments)]
fn simulate(
    py: Python<'_>,
    problem: &Problem,
    inputs: Option<&Bound<'_, PyAny>>,
    track: Option<&Bound<'_, PyAny>>,
    gains: Option<&Bound<'_, PyDict>>,
    feedback: Option<String>,
    duration: Option<f64>,
    rate: Option<f64>,
    integrator: Option<String>,
    out: Option<PathBuf>,
) -> PyResult<Py<Simulation>> {
    let mut scratch = None;
    let gains: Vec<String> = match gains {
        None => Vec::new(),
        Some(g) => g
            .iter()
            .map(|(k, v)| {
                let (kp, kd): (f64, f64) = v.extract()?;
                Ok(format!("{}={kp:?},{kd:?}", k.extract::<String>()?))
            })
            .collect::<PyResult<_>>()?,
    };
    let feedback = match feedback.as_deref() {
        None => None,
        Some("explicit") => Some(vito::sim::Feedback::Explicit),
        Some("implicit") => Some(vito::sim::Feedback::Implicit),
        Some(other) => {
            return Err(VitoError::new_err(format!(
                "feedback={other:?}: give \"explicit\" or \"implicit\""
            )));
        }
    };
    let integrator = match integrator.as_deref() {
        None => None,
        Some(name) => Some(
            name.parse::<vito::discrete::Integrator>()
                .map_err(|e| VitoError::new_err(format!("integrator={name:?}: {e}")))?,
        ),
    };
    let request = pipeline::simulation::SimulateRequest {
        inputs: trajectory_path(inputs, &mut scratch, "inputs")?,
        track: trajectory_path(track, &mut scratch, "track")?,
        gains,
        feedback,
        duration,
        rate,
        integrator,
    };
    let loaded = problem.loaded.clone();
    let prepared =
        pipeline::simulation::prepare_simulation(&loaded, &request).map_err(|e| vito_error(&e))?;
    let target = match &out {
        Some(dir) => Some(output_target(dir, &prepared.inputs)?),
        None => None,
    };
    let (sim, wall) = py
        .detach(|| {
            let start = std::time::Instant::now();
            let sim = pipeline::simulation::run_simulation(&prepared, |_| {})?;
            Ok::<_, vito::sim::SimulationError>((sim, start.elapsed().as_secs_f64()))
        })
        .map_err(|e| vito_error(&e))?;
    let energies = pipeline::simulation::conservative_energies(&prepared, &sim);
    let summary = pipeline::simulation::simulation_summary(
        &loaded,
        &prepared,
        &sim,
        energies.as_deref(),
        wall,
    );
    let columns = report::SimulationColumns::new(&loaded, &sim, prepared.contact.nd());
    // The temporary CSVs are gone once this returns; the output rules need only the
    // problem's own files then.
    let inputs: Vec<PathBuf> = prepared
        .inputs
        .iter()
        .filter(|p| scratch.as_ref().is_none_or(|d| !p.starts_with(d.path())))
        .cloned()
        .collect();
    let simulation = Simulation {
        problem: loaded,
        sim,
        columns,
        summary,
        inputs,
    };
    if let Some(target) = target {
        py.detach(|| simulation.write_to(target))?;
    }
    simulation.into_py(py)
}

/// _sweep(problem, axes, exe, out, jobs, time_limit, warm_start) -> str
///
/// Runs `vito sweep` (the library's sweep runner: one `exe solve` process per point) and
/// returns the path of the table (`sweep.csv`). `vito.sweep` is the public function.
#[pyfunction]
#[pyo3(signature = (problem, axes, exe, out, jobs, time_limit = None, neighbour = false))]
#[allow(clippy::too_many_arguments)]
fn _sweep(
    py: Python<'_>,
    problem: &Problem,
    axes: Vec<String>,
    exe: PathBuf,
    out: PathBuf,
    jobs: usize,
    time_limit: Option<f64>,
    neighbour: bool,
) -> PyResult<PathBuf> {
    use vito::sweep::{Axis, Grid, Shard, SweepOptions, WarmStart};
    let usage = |e: vito::sweep::SweepError| vito_error(&e);
    let grid = Grid::new(
        axes.iter()
            .map(|a| Axis::parse(a))
            .collect::<Result<_, _>>()
            .map_err(usage)?,
    )
    .map_err(usage)?;
    if jobs == 0 {
        return Err(VitoError::new_err("jobs=0: give at least 1"));
    }
    let time_limit = match time_limit {
        Some(t) if !(t.is_finite() && t > 0.0) => {
            return Err(VitoError::new_err(format!(
                "time_limit={t}: give a positive number of seconds"
            )));
        }
        t => t.map(std::time::Duration::from_secs_f64),
    };
    let overrides: Vec<Override> = problem
        .sets
        .iter()
        .map(|s| Override::parse(s))
        .collect::<Result<_, _>>()
        .map_err(|e| problem_error(py, &e))?;
    vito::sweep::check_grid(&problem.path, &overrides, &grid).map_err(usage)?;
    let options = SweepOptions {
        exe,
        problem: std::path::absolute(&problem.path)
            .map_err(|e| VitoError::new_err(e.to_string()))?,
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
        stop: None,
    };
    let sha = problem.loaded.sha256.clone();
    py.detach(|| vito::sweep::run_sweep(&options, &sha, |_| {}))
        .map_err(usage)?;
    Ok(out.join(vito::sweep::TABLE_CSV))
}

/// The OpenBLAS core type the `vito` command pins on this CPU (None: it pins none), which
/// the package sets before it loads the library.
#[pyfunction]
fn pinned_coretype() -> Option<&'static str> {
    vito::ipopt::blas_kernels::coretype()
}

/// The native module `vito._vito`; the package `vito` re-exports it.
#[pymodule]
fn _vito(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("VitoError", py.get_type::<VitoError>())?;
    m.add("ProblemError", py.get_type::<ProblemError>())?;
    m.add_class::<Problem>()?;
    m.add_class::<Trajectory>()?;
    m.add_class::<Solution>()?;
    m.add_class::<Simulation>()?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(pinned_coretype, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("IPOPT_VERSION", vito::ipopt::VERSION)?;
    Ok(())
}
