//! `vito._vito.mujoco_model`: a problem's world as MJCF text (the library's
//! `pipeline::mujoco`), which `vito.mujoco` (pure Python, over the `mujoco` package) loads
//! and runs.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use vito::pipeline::mujoco::{MujocoError, mujoco_model as build};

use crate::errors::VitoError;
use crate::problem::Problem;

/// The MuJoCo model of `problem`'s world (robot, contacts, terrain, gravity, one motor per
/// input) stepped every `timestep` seconds: a dict of `xml` (MJCF text),
/// `translation_coordinates` (the coordinates that move the robot along world axes) and
/// `timestep` (in the problem's time unit).
#[pyfunction]
#[pyo3(signature = (problem, timestep = 0.001))]
pub(crate) fn mujoco_model<'py>(
    py: Python<'py>,
    problem: &Bound<'py, Problem>,
    timestep: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let loaded = problem.get().loaded.clone();
    let model = py
        .detach(|| build(&loaded, timestep))
        .map_err(|e| match e {
            MujocoError::TimeStep(_) => PyValueError::new_err(e.to_string()),
            _ => VitoError::new_err(e.to_string()),
        })?;
    let dict = PyDict::new(py);
    dict.set_item("xml", model.xml)?;
    dict.set_item("translation_coordinates", model.translation_coordinates)?;
    dict.set_item("timestep", model.timestep)?;
    Ok(dict)
}
