//! `vito.Dynamics`: a URDF's rigid-body dynamics as vito reads the robot (the library's
//! `pipeline::dynamics`): the mass matrix, the generalised gravity, inverse dynamics, the
//! kinetic energy and link poses at one configuration, as numpy arrays.

use std::path::Path;

use numpy::IntoPyArray;
use numpy::ndarray::{Array1, Array2};
use pyo3::exceptions::{PyFileNotFoundError, PyValueError};
use pyo3::prelude::*;

use vito::model::ModelError;
use vito::pipeline::dynamics::{Dynamics as Robot, DynamicsError, base_type};

use crate::errors::VitoError;

/// The rigid-body dynamics of a URDF on a base, with vito's coordinates.
#[pyclass(module = "vito._vito", frozen)]
struct Dynamics {
    robot: Robot,
    base: &'static str,
}

fn error(e: DynamicsError) -> PyErr {
    match e {
        DynamicsError::Model(ModelError::Io { ref source, .. })
            if source.kind() == std::io::ErrorKind::NotFound =>
        {
            PyFileNotFoundError::new_err(e.to_string())
        }
        DynamicsError::Model(_) => VitoError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// A 1-D float vector (any array-like numpy takes).
fn vector(x: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    let numpy = x.py().import("numpy")?;
    let array = numpy.call_method1("asarray", (x, "float64"))?;
    let ndim: usize = array.getattr("ndim")?.extract()?;
    if ndim != 1 {
        return Err(PyValueError::new_err(format!(
            "{what} must have shape (n,), got {ndim} dimensions"
        )));
    }
    array.call_method0("tolist")?.extract()
}

fn matrix(py: Python<'_>, rows: Vec<Vec<f64>>) -> PyResult<Bound<'_, PyAny>> {
    let (n, m) = (rows.len(), rows.first().map_or(0, Vec::len));
    let flat: Vec<f64> = rows.into_iter().flatten().collect();
    let array =
        Array2::from_shape_vec((n, m), flat).map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(array.into_pyarray(py).into_any())
}

fn array(py: Python<'_>, v: Vec<f64>) -> Bound<'_, PyAny> {
    Array1::from(v).into_pyarray(py).into_any()
}

#[pymethods]
impl Dynamics {
    /// The URDF at `urdf` on `base` (`"fixed"`, `"planar"`: base_x, base_z, base_pitch, or
    /// `"floating"`: base_x, base_y, base_z, base_roll, base_pitch, base_yaw, the pose
    /// Trans(x, y, z)·Rz(yaw)·Ry(pitch)·Rx(roll)), under `gravity` (world frame, the URDF's
    /// units). Raises `FileNotFoundError` for a missing file, `vito.VitoError` for a URDF vito
    /// cannot read (the message says why), `ValueError` for an unknown base.
    #[new]
    #[pyo3(signature = (urdf, base = "fixed", gravity = [0.0, 0.0, -9.81]))]
    fn new(
        py: Python<'_>,
        urdf: crate::convert::PathArg,
        base: &str,
        gravity: [f64; 3],
    ) -> PyResult<Dynamics> {
        let base = base_type(base).map_err(error)?;
        let path = urdf.0;
        let robot = py
            .detach(|| Robot::load(Path::new(&path), base, gravity))
            .map_err(error)?;
        Ok(Dynamics {
            robot,
            base: base.name(),
        })
    }

    /// The base: `"fixed"`, `"planar"` or `"floating"`.
    #[getter]
    fn base(&self) -> &'static str {
        self.base
    }

    /// The coordinates' names, the order of q: the base's, then the URDF's moving joints in
    /// document order (a `<mimic>` joint has none: it follows its leader).
    #[getter]
    fn coordinate_names(&self) -> Vec<String> {
        self.robot.coordinate_names().to_vec()
    }

    /// The URDF's link names, parents first.
    #[getter]
    fn link_names(&self) -> Vec<String> {
        self.robot.link_names().to_vec()
    }

    /// The number of coordinates n.
    #[getter]
    fn nq(&self) -> usize {
        self.robot.coordinate_names().len()
    }

    /// The sum of the link masses.
    #[getter]
    fn total_mass(&self) -> f64 {
        self.robot.model().total_mass()
    }

    /// The mass matrix M(q), shape (n, n), symmetric: the kinetic energy is ½ q̇ᵀ M(q) q̇.
    fn mass_matrix<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let q = vector(q, "q")?;
        matrix(py, self.robot.mass_matrix(&q).map_err(error)?)
    }

    /// The generalised gravity g(q) = ∂V/∂q of the gravitational potential V (springs not
    /// included), shape (n,): the joint torques and base forces that hold q against gravity.
    fn gravity<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let q = vector(q, "q")?;
        Ok(array(py, self.robot.gravity(&q).map_err(error)?))
    }

    /// Inverse dynamics M(q)a + C(q, v)v + ∂V/∂q (gravity and the URDF's springs; no
    /// damping, no inputs), shape (n,).
    fn inverse_dynamics<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        a: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (q, v, a) = (vector(q, "q")?, vector(v, "v")?, vector(a, "a")?);
        Ok(array(
            py,
            self.robot.inverse_dynamics(&q, &v, &a).map_err(error)?,
        ))
    }

    /// The kinetic energy T(q, v) = ½ vᵀ M(q) v.
    fn kinetic_energy(&self, q: &Bound<'_, PyAny>, v: &Bound<'_, PyAny>) -> PyResult<f64> {
        let (q, v) = (vector(q, "q")?, vector(v, "v")?);
        self.robot.kinetic_energy(&q, &v).map_err(error)
    }

    /// The world position of `point` (in `link`'s frame, default its origin) at q, shape (3,).
    #[pyo3(signature = (link, q, point = [0.0, 0.0, 0.0]))]
    fn frame_position<'py>(
        &self,
        py: Python<'py>,
        link: &str,
        q: &Bound<'py, PyAny>,
        point: [f64; 3],
    ) -> PyResult<Bound<'py, PyAny>> {
        let q = vector(q, "q")?;
        let p = self.robot.point_position(link, point, &q).map_err(error)?;
        Ok(array(py, p.to_vec()))
    }

    /// `link`'s world rotation at q, shape (3, 3): link axes to world axes.
    fn frame_rotation<'py>(
        &self,
        py: Python<'py>,
        link: &str,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let q = vector(q, "q")?;
        let (rotation, _) = self.robot.link_pose(link, &q).map_err(error)?;
        matrix(py, rotation.iter().map(|r| r.to_vec()).collect())
    }

    fn __repr__(&self) -> String {
        format!(
            "<vito.Dynamics {} on a {} base: {} coordinates>",
            self.robot.model().name(),
            self.base,
            self.robot.coordinate_names().len()
        )
    }
}

/// Adds `Dynamics` to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Dynamics>()
}
