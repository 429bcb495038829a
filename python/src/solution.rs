//! `vito.Solution` (a solve's result) and its base `vito.Trajectory` (the text of
//! `trajectory.csv`): arrays with named axes and units, the summary, writing, pickling and
//! notebook display.

use std::path::PathBuf;
use std::sync::Arc;

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use vito::pipeline;
use vito::problem::LoadedProblem;
use vito::report;

use crate::convert::{PathArg, csv_columns, csv_dataframe, json_to_py, matrix, vector};
use crate::errors::vito_error;
use crate::pickle::{check_trajectory, friction_directions, pickled, refused, unpickled};

/// What a solve or a simulation writes as `trajectory.csv`, kept as its text: the base class
/// of `Solution` and `Simulation`.
#[pyclass(module = "vito", frozen, subclass)]
pub(crate) struct Trajectory {
    pub(crate) csv: String,
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

/// A solve's result: the verdict, the numbers of `summary.json`, and the trajectory as
/// arrays with named axes.
#[pyclass(module = "vito", frozen, extends = Trajectory)]
pub(crate) struct Solution {
    /// The problem file and overrides it was solved from (what a pickle carries).
    pub(crate) source: (PathBuf, Vec<String>),
    pub(crate) problem: Arc<LoadedProblem>,
    pub(crate) solution: vito::transcription::Solution,
}

impl Solution {
    /// The Python object, with its `trajectory.csv` text in the base class.
    pub(crate) fn into_py(self, py: Python<'_>) -> PyResult<Py<Solution>> {
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
    pub(crate) fn write_to(&self, target: report::OutputTarget) -> PyResult<PathBuf> {
        target
            .stage()
            .map_err(report::ReportError::from)
            .and_then(|staged| report::write_outputs(staged, &self.problem, &self.solution))
            .map_err(|e| vito_error(&e))
    }

    fn summary_value(&self) -> serde_json::Value {
        report::summary_json(&self.problem, &self.solution)
    }
}

/// Rebuilds a pickled `Solution`: its problem file loaded again (unchanged: SHA-256
/// `sha256`), its numbers checked against it ([`check_solution`]).
#[pyfunction]
#[pyo3(signature = (path, sets, text, sha256 = None))]
pub(crate) fn _restore_solution(
    py: Python<'_>,
    path: PathArg,
    sets: Vec<String>,
    text: &str,
    sha256: Option<String>,
) -> PyResult<Py<Solution>> {
    let path = path.0;
    let (problem, solution): (_, vito::transcription::Solution) =
        unpickled(py, "Solution", &path, &sets, text, sha256.as_deref())?;
    check_solution(&problem, &solution)?;
    Solution {
        source: (path, sets),
        problem: Arc::new(problem),
        solution,
    }
    .into_py(py)
}

/// Whether `s` is a solution of `problem`: its trajectory one of the problem's
/// ([`check_trajectory`]), with the problem's knots and a finite, positive step between
/// each two.
fn check_solution(problem: &LoadedProblem, s: &vito::transcription::Solution) -> PyResult<()> {
    let nd = friction_directions(problem)?;
    let knots = problem.spec.knots;
    check_trajectory(problem, nd, &report::solution_trajectory(s))
        .and_then(|()| {
            if s.times.len() != knots {
                return Err(format!(
                    "it has {} knots, its problem {knots}",
                    s.times.len()
                ));
            }
            if s.time_steps.len() + 1 != knots
                || s.time_steps.iter().any(|h| !(h.is_finite() && *h > 0.0))
            {
                return Err(format!(
                    "its `time_steps` are not {} positive numbers",
                    knots - 1
                ));
            }
            Ok(())
        })
        .map_err(|why| refused("Solution", &why))
}

#[pymethods]
impl Solution {
    /// The verdict, as `summary.json`'s `status` (e.g. `solve_succeeded`).
    #[getter]
    fn status(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        Ok(json_to_py(py, &self.summary_value()["status"])?.unbind())
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
        json_to_py(py, &self.summary_value())
    }

    /// Knot times, shape (N,).
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        vector(py, &self.solution.times)
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
    /// Writes what `vito solve --out DIR` writes (trajectory.csv, summary.json, the plots,
    /// animation.html), atomically; only vito's own results or an empty directory are
    /// replaced. Returns the directory.
    fn write(&self, py: Python<'_>, dir: PathArg) -> PyResult<PathBuf> {
        let target = pipeline::output::checked_output_dir(&self.problem, Some(&dir.0))
            .map_err(|e| vito_error(&report::ReportError::from(e)))?;
        py.detach(|| self.write_to(target))
    }

    /// Pickled as its problem (file, overrides and the file's SHA-256; loaded again on
    /// unpickling, and refused when the file has changed or the numbers do not fit it) and
    /// its numbers: a round trip gives an equal solution.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        pickled(
            py,
            "_restore_solution",
            &self.source,
            &self.problem,
            &self.solution,
        )
    }

    /// A summary table and the motion, for Jupyter.
    fn _repr_html_(&self) -> String {
        let s = &self.solution;
        let summary = self.summary_value();
        let status = summary["status"].as_str().unwrap_or("unknown").to_owned();
        let rows = [
            ("status", status),
            ("objective", format!("{:.6e}", s.objective)),
            ("iterations", s.iterations.to_string()),
            ("max slack", format!("{:.3e}", s.max_slack)),
            ("knots", s.times.len().to_string()),
            ("wall time", format!("{:.3} s", s.wall_time_s)),
        ];
        crate::html::result_html(
            "solution",
            &self.problem,
            &rows,
            &report::solution_trajectory(s),
            &summary,
        )
    }

    fn __repr__(&self) -> String {
        format!(
            "<vito.Solution {} {}: objective {:e}, {} iterations, max slack {:.3e}>",
            self.problem.spec.name,
            self.solution.verdict().name(),
            self.solution.objective,
            self.solution.iterations,
            self.solution.max_slack
        )
    }
}
