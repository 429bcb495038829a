//! A URDF's rigid-body dynamics by name, as vito reads the robot: the mass matrix, the
//! generalised gravity, inverse dynamics and link poses at a configuration, the quantities an
//! independent library (Pinocchio, MuJoCo) computes too, so that each can be checked against
//! the other (the Python `vito.Dynamics`). Every number comes from `model`'s own functions, the
//! ones the planner's discrete Lagrangian is made of.

use std::path::Path;

use crate::model::{self, BaseType, Model, ModelError};

/// Why a dynamics query was refused.
#[derive(Debug, thiserror::Error)]
pub enum DynamicsError {
    /// The URDF could not be loaded.
    #[error("{0}")]
    Model(#[from] ModelError),
    /// A base name other than `fixed`, `planar`, `floating`.
    #[error("no base `{0}`; the bases are: fixed, planar, floating")]
    UnknownBase(String),
    /// A link name the URDF does not have.
    #[error("no link `{name}`; the links are: {}", valid.join(", "))]
    UnknownLink {
        /// The name given.
        name: String,
        /// The URDF's links.
        valid: Vec<String>,
    },
    /// A vector of the wrong length.
    #[error("{what} has {found} values; the robot has {expected} coordinates")]
    Length {
        /// `q`, `v` or `a`.
        what: &'static str,
        /// n.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// A gravity vector with a value that is not finite.
    #[error("gravity must be 3 finite numbers, got {0:?}")]
    Gravity([f64; 3]),
}

/// The base named as problem files name it (`fixed`, `planar`, `floating`).
pub fn base_type(name: &str) -> Result<BaseType, DynamicsError> {
    [BaseType::Fixed, BaseType::Planar, BaseType::Floating]
        .into_iter()
        .find(|b| b.name() == name)
        .ok_or_else(|| DynamicsError::UnknownBase(name.to_owned()))
}

/// A robot's dynamics, loaded from its URDF on a base.
#[derive(Debug, Clone)]
pub struct Dynamics {
    model: Model,
}

impl Dynamics {
    /// The URDF at `path` on `base`, under `gravity` (world frame, the URDF's units).
    pub fn load(path: &Path, base: BaseType, gravity: [f64; 3]) -> Result<Dynamics, DynamicsError> {
        if gravity.iter().any(|g| !g.is_finite()) {
            return Err(DynamicsError::Gravity(gravity));
        }
        let mut model = Model::from_urdf_file(path, base)?;
        model.set_gravity(gravity);
        Ok(Dynamics { model })
    }

    /// The model itself.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The coordinates' names: the base's (`base_x`, ...), then the joints in document order.
    pub fn coordinate_names(&self) -> &[String] {
        self.model.coordinate_names()
    }

    /// The URDF's link names, parents first.
    pub fn link_names(&self) -> &[String] {
        self.model.link_names()
    }

    /// M(q), row-major (`nq × nq`).
    pub fn mass_matrix(&self, q: &[f64]) -> Result<Vec<Vec<f64>>, DynamicsError> {
        self.check("q", q)?;
        let m = model::mass_matrix(&self.model, q);
        Ok(m.row_iter().map(|r| r.iter().copied().collect()).collect())
    }

    /// The generalised gravity g(q) = ∂V_g/∂q ([`model::generalized_gravity`]).
    pub fn gravity(&self, q: &[f64]) -> Result<Vec<f64>, DynamicsError> {
        self.check("q", q)?;
        Ok(model::generalized_gravity(&self.model, q))
    }

    /// M(q)a + C(q, v)v + ∂V/∂q, springs included ([`model::inverse_dynamics`]).
    pub fn inverse_dynamics(
        &self,
        q: &[f64],
        v: &[f64],
        a: &[f64],
    ) -> Result<Vec<f64>, DynamicsError> {
        self.check("q", q)?;
        self.check("v", v)?;
        self.check("a", a)?;
        Ok(model::inverse_dynamics(&self.model, q, v, a))
    }

    /// The kinetic energy T(q, v) ([`model::kinetic_energy`]).
    pub fn kinetic_energy(&self, q: &[f64], v: &[f64]) -> Result<f64, DynamicsError> {
        self.check("q", q)?;
        self.check("v", v)?;
        Ok(model::kinetic_energy(&self.model, q, v))
    }

    /// `link`'s world pose at q: (rotation, link axes to world axes, row-major; origin).
    pub fn link_pose(
        &self,
        link: &str,
        q: &[f64],
    ) -> Result<([[f64; 3]; 3], [f64; 3]), DynamicsError> {
        self.check("q", q)?;
        let id = self.link(link)?;
        Ok(model::link_pose(&self.model, id, q))
    }

    /// The world position of `point` (in `link`'s frame) at q.
    pub fn point_position(
        &self,
        link: &str,
        point: [f64; 3],
        q: &[f64],
    ) -> Result<[f64; 3], DynamicsError> {
        self.check("q", q)?;
        let id = self.link(link)?;
        Ok(model::point_position(&self.model, id, &point, q))
    }

    fn link(&self, name: &str) -> Result<model::LinkId, DynamicsError> {
        self.model
            .link_index(name)
            .ok_or_else(|| DynamicsError::UnknownLink {
                name: name.to_owned(),
                valid: self.model.link_names().to_vec(),
            })
    }

    fn check(&self, what: &'static str, x: &[f64]) -> Result<(), DynamicsError> {
        let expected = self.model.nq();
        if x.len() == expected {
            Ok(())
        } else {
            Err(DynamicsError::Length {
                what,
                expected,
                found: x.len(),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::sample;

    fn pendulum() -> Dynamics {
        let path = std::env::temp_dir().join(format!("vito-dynamics-{}.urdf", std::process::id()));
        std::fs::write(&path, sample::pendulum()).unwrap();
        let d = Dynamics::load(&path, BaseType::Fixed, [0.0, 0.0, -9.81]).unwrap();
        std::fs::remove_file(&path).unwrap();
        d
    }

    #[test]
    fn a_uniform_rod_about_its_end() {
        // 1 kg, 1 m, about its end: M = m l²/3. The rod hangs along −z at θ = 0 and turns about
        // +y, so its centre is at (−½ sin θ, 0, −½ cos θ), V = −m g ½ cos θ and g(θ) = m g ½ sin θ.
        let d = pendulum();
        let q = [0.4];
        let m = d.mass_matrix(&q).unwrap();
        assert!((m[0][0] - 1.0 / 3.0).abs() < 1e-14);
        let g = d.gravity(&q).unwrap();
        assert!(
            (g[0].abs() - 9.81 * 0.5 * 0.4_f64.sin()).abs() < 1e-12,
            "{g:?}"
        );
        // Gravity is what inverse dynamics returns at rest.
        let at_rest = d.inverse_dynamics(&q, &[0.0], &[0.0]).unwrap();
        assert!((at_rest[0] - g[0]).abs() < 1e-14);
        // M a adds to it when accelerating.
        let moving = d.inverse_dynamics(&q, &[0.0], &[2.0]).unwrap();
        assert!((moving[0] - g[0] - 2.0 / 3.0).abs() < 1e-13);
    }

    #[test]
    fn names_lengths_and_bases_are_checked() {
        let d = pendulum();
        assert!(matches!(
            d.gravity(&[0.0, 1.0]),
            Err(DynamicsError::Length {
                what: "q",
                expected: 1,
                found: 2
            })
        ));
        let e = d.link_pose("nope", &[0.0]).unwrap_err();
        assert!(
            e.to_string().starts_with("no link `nope`; the links are: "),
            "{e}"
        );
        assert!(matches!(
            base_type("free"),
            Err(DynamicsError::UnknownBase(_))
        ));
        assert_eq!(base_type("planar").unwrap(), BaseType::Planar);
        let missing = Dynamics::load(Path::new("/nonexistent.urdf"), BaseType::Fixed, [0.0; 3]);
        assert!(matches!(
            missing,
            Err(DynamicsError::Model(ModelError::Io { .. }))
        ));
        let nan = Dynamics::load(
            Path::new("/nonexistent.urdf"),
            BaseType::Fixed,
            [f64::NAN; 3],
        );
        assert!(matches!(nan, Err(DynamicsError::Gravity(_))));
    }
}
