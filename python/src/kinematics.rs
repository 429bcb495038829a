//! `vito.Kinematics`: forward kinematics of a problem's robot by name (the library's
//! `pipeline::kinematics`): a contact's or a link point's world position and a link's world
//! orientation, for one configuration q (shape (n,)) or one per row (shape (N, n), e.g. a
//! Solution's `q`).

use numpy::IntoPyArray;
use numpy::ndarray::{Array1, Array2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use vito::pipeline::kinematics::{Kinematics as Robot, KinematicsError};

/// Forward kinematics of the robot of a problem file.
#[pyclass(module = "vito._vito", frozen)]
struct Kinematics {
    robot: Robot,
}

/// q as rows: one row for a 1-D array, its rows for a 2-D one.
fn rows(q: &Bound<'_, PyAny>) -> PyResult<(Vec<Vec<f64>>, bool)> {
    let numpy = q.py().import("numpy")?;
    let array = numpy.call_method1("asarray", (q, "float64"))?;
    let ndim: usize = array.getattr("ndim")?.extract()?;
    match ndim {
        1 => Ok((vec![array.call_method0("tolist")?.extract()?], false)),
        2 => Ok((array.call_method0("tolist")?.extract()?, true)),
        _ => Err(PyValueError::new_err(format!(
            "q must have shape (n,) or (N, n), got {ndim} dimensions"
        ))),
    }
}

fn error(e: KinematicsError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Positions of one point per row of q: shape (3,) for one q, (N, 3) for N.
fn positions<'py>(
    py: Python<'py>,
    q: &Bound<'py, PyAny>,
    at: impl Fn(&[f64]) -> Result<[f64; 3], KinematicsError>,
) -> PyResult<Bound<'py, PyAny>> {
    let (rows, many) = rows(q)?;
    let points: Vec<[f64; 3]> = rows
        .iter()
        .map(|r| at(r))
        .collect::<Result<_, _>>()
        .map_err(error)?;
    if many {
        let flat: Vec<f64> = points.iter().flatten().copied().collect();
        let array = Array2::from_shape_vec((points.len(), 3), flat)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(array.into_pyarray(py).into_any())
    } else {
        Ok(Array1::from(points[0].to_vec()).into_pyarray(py).into_any())
    }
}

#[pymethods]
impl Kinematics {
    /// The robot of the problem file `path` (its URDF, base and contacts).
    #[new]
    fn new(py: Python<'_>, path: crate::convert::PathArg) -> PyResult<Kinematics> {
        let path = path.0;
        let loaded =
            vito::problem::load(&path, &[]).map_err(|e| crate::errors::problem_error(py, &e))?;
        let robot = Robot::new(&loaded.spec)
            .map_err(|e| crate::errors::VitoError::new_err(e.to_string()))?;
        Ok(Kinematics { robot })
    }

    /// The problem's contact names, in order.
    #[getter]
    fn contact_names(&self) -> Vec<String> {
        self.robot.contact_names().to_vec()
    }

    /// The URDF's link names.
    #[getter]
    fn link_names(&self) -> Vec<String> {
        self.robot.link_names().to_vec()
    }

    /// Contact `name`'s world position [m] (a sphere's lowest point): shape (3,) for one q,
    /// (N, 3) for q of shape (N, n).
    fn contact_position<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        positions(py, q, |q| self.robot.contact_position(name, q))
    }

    /// The world position [m] of `point` (in `link`'s frame, default its origin).
    #[pyo3(signature = (link, q, point = [0.0, 0.0, 0.0]))]
    fn point_position<'py>(
        &self,
        py: Python<'py>,
        link: &str,
        q: &Bound<'py, PyAny>,
        point: [f64; 3],
    ) -> PyResult<Bound<'py, PyAny>> {
        positions(py, q, |q| self.robot.point_position(link, point, q))
    }

    /// `link`'s world pose at one q: a dict of `rotation` (3×3, link axes to world axes),
    /// `position` [m] (3,) and `roll_pitch_yaw` [rad] (3,), the Z-Y-X angles.
    fn link_pose<'py>(
        &self,
        py: Python<'py>,
        link: &str,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (rows, many) = rows(q)?;
        if many {
            return Err(PyValueError::new_err(
                "link_pose takes one q, of shape (n,)",
            ));
        }
        let pose = self.robot.link_pose(link, &rows[0]).map_err(error)?;
        let dict = PyDict::new(py);
        let flat: Vec<f64> = pose.rotation.iter().flatten().copied().collect();
        let rotation = Array2::from_shape_vec((3, 3), flat)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        dict.set_item("rotation", rotation.into_pyarray(py))?;
        dict.set_item(
            "position",
            Array1::from(pose.position.to_vec()).into_pyarray(py),
        )?;
        dict.set_item(
            "roll_pitch_yaw",
            Array1::from(pose.roll_pitch_yaw.to_vec()).into_pyarray(py),
        )?;
        Ok(dict)
    }
}

/// Adds `Kinematics` to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Kinematics>()
}
