//! `vito.simulate` and `vito.Simulation`: a forward simulation as `vito simulate` runs it
//! (`pipeline::simulation::prepare_simulation`, then `simulate_prepared`), stopped by
//! Ctrl-C; its result with arrays, writing, pickling and notebook display.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use vito::pipeline;
use vito::problem::LoadedProblem;
use vito::report;

use crate::convert::{PathArg, json_to_py, matrix, vector};
use crate::errors::{VitoError, vito_error};
use crate::pickle::{check_trajectory, friction_directions, pickled, refused, unpickled};
use crate::problem::Problem;
use crate::solution::{Solution, Trajectory};
use crate::watch::run_watched;

/// A forward simulation's result (`vito simulate`): its summary and trajectory.
#[pyclass(module = "vito", frozen, extends = Trajectory)]
pub(crate) struct Simulation {
    source: (PathBuf, Vec<String>),
    problem: Arc<LoadedProblem>,
    sim: vito::sim::Simulation,
    /// Friction directions per contact (the trajectory's impulse columns).
    nd: usize,
    summary: serde_json::Value,
    /// Files the output directory must not be (the problem, its robot, the CSVs read).
    inputs: Vec<PathBuf>,
}

impl Simulation {
    fn columns(&self) -> report::SimulationColumns {
        report::SimulationColumns::new(&self.problem, &self.sim, self.nd)
    }

    /// The Python object, with its `trajectory.csv` text in the base class.
    fn into_py(self, py: Python<'_>) -> PyResult<Py<Simulation>> {
        let units = report::column_units(&self.problem.robot, &self.problem.units);
        let csv = vito::files::trajectory_csv::write_trajectory(
            &self.columns().trajectory(&self.sim),
            &units,
        );
        Py::new(
            py,
            PyClassInitializer::from(Trajectory { csv }).add_subclass(self),
        )
    }

    /// Whether the simulation fits its problem: its trajectory one of the problem's (with the
    /// problem's friction directions), with one record per step in each per-step list (what
    /// a restored simulation is checked with).
    fn check(&self) -> PyResult<()> {
        let nd = friction_directions(&self.problem)?;
        if self.nd != nd {
            return Err(refused(
                "Simulation",
                &format!(
                    "it has {} friction directions per contact, its problem {nd}",
                    self.nd
                ),
            ));
        }
        let steps = self.sim.times.len().saturating_sub(1);
        let s = &self.sim;
        let counts = [
            ("impulses", s.impulses.len()),
            ("iterations", s.iterations.len()),
            ("complementarity", s.complementarity.len()),
            ("dynamics_residual", s.dynamics_residual.len()),
            ("residual", s.residual.len()),
        ];
        let per_step = counts
            .iter()
            .find(|(_, len)| *len != steps)
            .map(|(name, len)| format!("`{name}` has {len} records, for {steps} steps"));
        let relaxed = s
            .relaxed_steps
            .iter()
            .find(|&&k| k >= steps)
            .map(|k| format!("`relaxed_steps` names step {k} of {steps}"));
        match per_step.or(relaxed) {
            Some(why) => Err(refused("Simulation", &why)),
            None => check_trajectory(&self.problem, nd, &self.columns().trajectory(&self.sim))
                .map_err(|why| refused("Simulation", &why)),
        }
    }

    /// Writes into a checked target as `vito simulate` does (staged, then committed).
    fn write_to(&self, target: report::OutputTarget) -> PyResult<PathBuf> {
        let columns = self.columns();
        target
            .stage()
            .map_err(report::ReportError::from)
            .and_then(|staged| {
                report::write_trajectory_outputs(
                    staged,
                    &self.problem,
                    &columns.trajectory(&self.sim),
                    &self.summary,
                )
            })
            .map_err(|e| vito_error(&e))
    }
}

/// What a pickled `Simulation` carries besides its problem and trajectory.
#[derive(serde::Serialize, serde::Deserialize)]
struct SimulationState {
    sim: vito::sim::Simulation,
    nd: usize,
    /// `summary.json` as JSON text.
    summary: String,
    inputs: Vec<PathBuf>,
}

/// Rebuilds a pickled `Simulation`: its problem file loaded again (unchanged: SHA-256
/// `sha256`), its numbers checked against it.
#[pyfunction]
#[pyo3(signature = (path, sets, text, sha256 = None))]
pub(crate) fn _restore_simulation(
    py: Python<'_>,
    path: PathArg,
    sets: Vec<String>,
    text: &str,
    sha256: Option<String>,
) -> PyResult<Py<Simulation>> {
    let path = path.0;
    let (problem, state): (_, SimulationState) =
        unpickled(py, "Simulation", &path, &sets, text, sha256.as_deref())?;
    let summary: serde_json::Value = serde_json::from_str(&state.summary)
        .map_err(|e| refused("Simulation", &format!("its summary is not JSON text: {e}")))?;
    if !summary.is_object() {
        return Err(refused("Simulation", "its summary is not a JSON object"));
    }
    let simulation = Simulation {
        source: (path, sets),
        problem: Arc::new(problem),
        sim: state.sim,
        nd: state.nd,
        summary,
        inputs: state.inputs,
    };
    simulation.check()?;
    simulation.into_py(py)
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
        vector(py, &self.sim.times)
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
    fn write(&self, py: Python<'_>, dir: PathArg) -> PyResult<PathBuf> {
        let target = output_target(&dir.0, &self.inputs)?;
        py.detach(|| self.write_to(target))
    }

    /// Pickled as its problem (file, overrides and the file's SHA-256; loaded again on
    /// unpickling, and refused when the file has changed or the numbers do not fit it) and
    /// its numbers.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let state = SimulationState {
            sim: self.sim.clone(),
            nd: self.nd,
            summary: self.summary.to_string(),
            inputs: self.inputs.clone(),
        };
        pickled(
            py,
            "_restore_simulation",
            &self.source,
            &self.problem,
            &state,
        )
    }

    /// A summary table and the motion, for Jupyter.
    fn _repr_html_(&self) -> String {
        let s = &self.summary;
        let text = |key: &str| match &s[key] {
            serde_json::Value::String(v) => v.clone(),
            serde_json::Value::Null => "-".to_owned(),
            v => v.to_string(),
        };
        let rows = [
            ("integrator", text("integrator")),
            ("steps", self.sim.iterations.len().to_string()),
            (
                "duration",
                format!(
                    "{} {}",
                    self.sim.times.last().copied().unwrap_or(0.0),
                    self.problem.units.time
                ),
            ),
            (
                "max penetration",
                format!(
                    "{:.3e} {}",
                    self.sim.max_penetration(),
                    self.problem.units.length
                ),
            ),
            ("relaxed steps", self.sim.relaxed_steps.len().to_string()),
        ];
        let columns = self.columns();
        crate::html::result_html(
            "simulation",
            &self.problem,
            &rows,
            &columns.trajectory(&self.sim),
            s,
        )
    }

    fn __repr__(&self) -> String {
        format!(
            "<vito.Simulation {}: {} steps to t = {}>",
            self.problem.spec.name,
            self.sim.iterations.len(),
            self.sim.times.last().copied().unwrap_or(0.0)
        )
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
    Ok(Some(value.extract::<PathArg>()?.0))
}

/// A duration or rate as the command checks it (positive, at most 1e9): ValueError.
fn span(name: &str, value: Option<f64>) -> PyResult<Option<f64>> {
    value
        .map(|v| vito::files::input::checked_span(&format!("{name}="), v))
        .transpose()
        .map_err(PyValueError::new_err)
}

/// simulate(problem, inputs=None, track=None, gains=None, feedback=None, duration=None,
///          rate=None, integrator=None, out=None, set=None) -> Simulation
///
/// Simulates the problem's robot forward as `vito simulate` does: zero inputs, or the inputs
/// of `inputs` replayed, or `track` followed with PD feedback (`gains`: a dict
/// `{input or "all": (kp, kd)}` on top of the file's `[tracking] gains`; `feedback`:
/// "explicit" or "implicit"). `problem` is a `Problem` or the path of a problem file (with
/// `set` as for `Problem`). `inputs` and `track` are a `Solution` or the path of a
/// `trajectory.csv`. `duration`, `rate` (steps per time unit) and `integrator`
/// ("midpoint", "euler", "galerkin4" or "galerkin6") as the command's options. With `out`,
/// also writes what the command writes. Releases the GIL while simulating; Ctrl-C stops it
/// after the current step (KeyboardInterrupt).
#[pyfunction]
#[pyo3(signature = (problem, inputs = None, track = None, gains = None, feedback = None,
                    duration = None, rate = None, integrator = None, out = None, set = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn simulate(
    py: Python<'_>,
    problem: &Bound<'_, PyAny>,
    inputs: Option<&Bound<'_, PyAny>>,
    track: Option<&Bound<'_, PyAny>>,
    gains: Option<&Bound<'_, PyDict>>,
    feedback: Option<String>,
    duration: Option<f64>,
    rate: Option<f64>,
    integrator: Option<String>,
    out: Option<PathArg>,
    set: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<Simulation>> {
    let opened;
    let problem: &Problem = match problem.cast::<Problem>() {
        Ok(p) => p.get(),
        Err(_) => {
            let path = problem.extract::<PathArg>()?.0;
            opened = Problem::open(py, path, crate::convert::set_args(set)?)?;
            &opened
        }
    };
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
    let feedback = feedback
        .map(|name| name.parse::<vito::sim::Feedback>())
        .transpose()
        .map_err(|e| PyValueError::new_err(format!("feedback={e}")))?;
    let integrator = match integrator.as_deref() {
        None => None,
        Some(name) => Some(
            name.parse::<vito::discrete::Integrator>()
                .map_err(|e| PyValueError::new_err(format!("integrator={name:?}: {e}")))?,
        ),
    };
    let request = pipeline::simulation::SimulateRequest {
        inputs: trajectory_path(inputs, &mut scratch, "inputs")?,
        track: trajectory_path(track, &mut scratch, "track")?,
        gains,
        feedback,
        duration: span("duration", duration)?,
        rate: span("rate", rate)?,
        integrator,
    };
    let loaded = problem.loaded.clone();
    let prepared = py
        .detach(|| pipeline::simulation::prepare_simulation(&loaded, &request))
        .map_err(|e| vito_error(&e))?;
    let target = match &out {
        Some(dir) => Some(output_target(&dir.0, &prepared.inputs)?),
        None => None,
    };
    let stop = Arc::new(AtomicBool::new(false));
    let (run, error) = run_watched(
        py,
        &stop,
        |_messages: crate::watch::Messages<()>| {
            pipeline::simulation::simulate_prepared(&loaded, &prepared, |_| {
                if stop.load(Ordering::SeqCst) {
                    std::ops::ControlFlow::Break(())
                } else {
                    std::ops::ControlFlow::Continue(())
                }
            })
        },
        |_, ()| Ok(()),
    );
    if let Some(e) = error {
        return Err(e);
    }
    let run = run.map_err(|e| vito_error(&e))?;
    // The temporary CSVs are gone once this returns; the output rules need only the
    // problem's own files then.
    let inputs: Vec<PathBuf> = prepared
        .inputs
        .iter()
        .filter(|p| scratch.as_ref().is_none_or(|d| !p.starts_with(d.path())))
        .cloned()
        .collect();
    let simulation = Simulation {
        source: (problem.path.clone(), problem.sets.clone()),
        problem: loaded,
        sim: run.sim,
        nd: prepared.contact.nd(),
        summary: run.summary,
        inputs,
    };
    if let Some(target) = target {
        py.detach(|| simulation.write_to(target))?;
    }
    simulation.into_py(py)
}
