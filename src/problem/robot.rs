//! What problem validation needs to know about a robot: its names, limits and contact points.
//!
//! [`RobotInfo::read`] loads the robot with `model::Model` (the one URDF reader: names,
//! limits, inputs, contact points and whether each coordinate is a length or an angle) and
//! keeps what validation and outputs need.

#![warn(missing_docs)]

use std::path::{Path, PathBuf};

use crate::model::{Actuation, AppliedActuation, BaseType, CoordinateKind, Model};
use crate::problem::Interval;

/// A contact declared in the URDF (a collision sphere; radius 0: a point).
#[derive(Debug, Clone, PartialEq)]
pub struct UrdfContact {
    /// The name `model::ContactPoint` gives it (the collision's `name`, else the link's or
    /// `<link>_contact<k>`).
    pub name: String,
    /// Link it is fixed to.
    pub link: String,
    /// Point in the link frame [length] (a sphere's centre).
    pub point: [f64; 3],
    /// The sphere's radius [length] (0: a point).
    pub radius: f64,
}

/// Names and limits of a robot in the model's coordinate and input order.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotInfo {
    /// URDF file read.
    pub urdf: PathBuf,
    /// Coordinate names (length n): `base_*` first, then non-fixed joints.
    pub coordinates: Vec<String>,
    /// Linear or angular, per coordinate (length n).
    pub coordinate_kinds: Vec<CoordinateKind>,
    /// Joint limits per coordinate (length n), ±∞ where the URDF has none.
    pub coordinate_limits: Vec<Interval>,
    /// Input names (length m): the actuated joints.
    pub inputs: Vec<String>,
    /// The rule that chose the inputs.
    pub actuation: AppliedActuation,
    /// Every joint that could take an input (movable, not a base coordinate).
    pub actuatable_joints: Vec<String>,
    /// Linear (force) or angular (torque) input, per input (length m).
    pub input_kinds: Vec<CoordinateKind>,
    /// Effort limit per input (length m), +∞ for none.
    pub effort_limits: Vec<f64>,
    /// Every link name, in document order.
    pub links: Vec<String>,
    /// Contact points the URDF declares.
    pub contacts: Vec<UrdfContact>,
    /// What the URDF reader repaired or ignored (`Model::warnings`), for `check` and
    /// `solve` to show.
    pub warnings: Vec<String>,
    /// Whether every point of the robot moves in the x–z plane (friction along x alone,
    /// [`crate::contact::FrictionBasis::for_robot`]).
    pub moves_in_xz_plane: bool,
}

/// Why a URDF could not be read.
#[derive(Debug, thiserror::Error)]
pub enum RobotError {
    /// The file could not be read.
    #[error("cannot read URDF {path}: {source}")]
    Io {
        /// The URDF.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The model loader rejected it.
    #[error("{}", crate::model::describe(path, source))]
    Model {
        /// The URDF.
        path: PathBuf,
        /// Why.
        source: crate::model::ModelError,
    },
    /// A joint named to be actuated is not a movable joint.
    #[error("joint `{joint}` cannot be actuated; the movable joints are: {}", actuatable.join(", "))]
    NotActuatable {
        /// The name given.
        joint: String,
        /// The movable joints.
        actuatable: Vec<String>,
    },
}

impl RobotInfo {
    /// Reads a URDF and lists its coordinates for the given base, and its inputs by the
    /// actuation rule.
    pub fn read(
        path: &Path,
        base: BaseType,
        actuation: &Actuation,
    ) -> Result<RobotInfo, RobotError> {
        let model = Model::from_urdf_file(path, base).map_err(|source| match source {
            crate::model::ModelError::Io { path, source } => RobotError::Io { path, source },
            source => RobotError::Model {
                path: path.to_owned(),
                source,
            },
        })?;
        RobotInfo::actuated(path, model, actuation)
    }

    /// [`RobotInfo::read`] for a URDF's text in memory (`path` names it in messages).
    pub fn from_text(
        path: &Path,
        text: &str,
        base: BaseType,
        actuation: &Actuation,
    ) -> Result<RobotInfo, RobotError> {
        let model =
            Model::from_urdf_named(text, &path.display().to_string(), base).map_err(|source| {
                RobotError::Model {
                    path: path.to_owned(),
                    source,
                }
            })?;
        RobotInfo::actuated(path, model, actuation)
    }

    /// The robot's info once `actuation` chose its inputs.
    fn actuated(
        path: &Path,
        mut model: Model,
        actuation: &Actuation,
    ) -> Result<RobotInfo, RobotError> {
        model
            .actuate(actuation)
            .map_err(|e| RobotError::NotActuatable {
                joint: e.joint,
                actuatable: model.actuatable_joints(),
            })?;
        Ok(RobotInfo::from_model(path, &model))
    }

    /// What a loaded model says about names, limits, inputs and contacts (`path` names the
    /// URDF it came from).
    pub fn from_model(path: &Path, model: &Model) -> RobotInfo {
        let coordinate_kinds = model.coordinate_kinds();
        RobotInfo {
            urdf: path.to_owned(),
            coordinates: model.coordinate_names().to_vec(),
            coordinate_limits: model
                .coordinate_limits()
                .iter()
                .map(|&(lower, upper)| Interval { lower, upper })
                .collect(),
            inputs: model.input_names().to_vec(),
            actuation: model.actuation(),
            actuatable_joints: model.actuatable_joints(),
            input_kinds: model
                .input_coordinates()
                .iter()
                .map(|&c| coordinate_kinds[c])
                .collect(),
            effort_limits: model.effort_limits().to_vec(),
            links: model.link_names().to_vec(),
            contacts: model
                .contact_points()
                .iter()
                .map(|c| UrdfContact {
                    name: c.name.clone(),
                    link: c.link.clone(),
                    point: c.point,
                    radius: c.radius,
                })
                .collect(),
            coordinate_kinds,
            warnings: model.warnings().to_vec(),
            moves_in_xz_plane: model.moves_in_xz_plane(),
        }
    }

    /// Index of a coordinate by name.
    pub fn coordinate_index(&self, name: &str) -> Option<usize> {
        self.coordinates.iter().position(|c| c == name)
    }

    /// Index of an input by name.
    pub fn input_index(&self, name: &str) -> Option<usize> {
        self.inputs.iter().position(|c| c == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const URDF: &str = r#"<robot name="r">
      <link name="base"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="leg"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>
        <collision><origin xyz="0 0 -0.5"/><geometry><sphere radius="0"/></geometry></collision></link>
      <link name="foot"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="hip" type="revolute"><parent link="base"/><child link="leg"/><axis xyz="0 1 0"/>
        <limit lower="-1" upper="2" effort="30" velocity="1"/></joint>
      <joint name="slide" type="prismatic"><parent link="leg"/><child link="foot"/><axis xyz="0 0 1"/></joint>
      <transmission name="t"><joint name="hip"/></transmission>
      <transmission name="s"><joint name="slide"/></transmission>
    </robot>"#;

    #[test]
    fn reads_names_limits_kinds_and_points_in_order() {
        let model = Model::from_urdf_str(URDF, BaseType::Planar).unwrap();
        let info = RobotInfo::from_model(Path::new("r.urdf"), &model);
        assert_eq!(
            info.coordinates,
            ["base_x", "base_z", "base_pitch", "hip", "slide"]
        );
        use CoordinateKind::{Angular as A, Linear as L};
        assert_eq!(info.coordinate_kinds, [L, L, A, A, L]);
        assert_eq!(
            info.coordinate_limits[3],
            Interval {
                lower: -1.0,
                upper: 2.0
            }
        );
        assert_eq!(info.coordinate_limits[4], Interval::FREE);
        assert_eq!(info.inputs, ["hip", "slide"]);
        assert_eq!(info.input_kinds, [A, L]);
        assert_eq!(info.effort_limits[0], 30.0);
        assert_eq!(info.contacts.len(), 1);
        // The link's only point contact, unnamed: named after the link (`model::ContactPoint`).
        assert_eq!(info.contacts[0].name, "leg");
        assert_eq!(info.contacts[0].point, [0.0, 0.0, -0.5]);
    }
}
