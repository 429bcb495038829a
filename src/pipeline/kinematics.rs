//! Forward kinematics of a problem's robot by name: a contact point's or a link point's
//! world position and a link's world orientation at a configuration q, the quantities the
//! frame terms (`problem::frames`) and the trajectory file's `<contact>_x/_y/_z` columns use.

use crate::discrete::{Mechanics, ModelMechanics};
use crate::model::roll_pitch_yaw;
use crate::problem::ProblemSpec;
use crate::transcription::TranscriptionError;

/// Why a kinematics query was refused.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum KinematicsError {
    /// A name that is not a contact or link of the robot.
    #[error("no {kind} `{name}`; the {kind}s are: {}", valid.join(", "))]
    UnknownName {
        /// `contact` or `link`.
        kind: &'static str,
        /// The name given.
        name: String,
        /// The valid names.
        valid: Vec<String>,
    },
    /// A configuration of the wrong length.
    #[error("q has {found} values; the robot has {expected} coordinates")]
    Length {
        /// n.
        expected: usize,
        /// The length given.
        found: usize,
    },
}

/// A link's world pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkPose {
    /// Rotation (row-major) mapping link axes to world axes.
    pub rotation: [[f64; 3]; 3],
    /// The link origin in the world [length].
    pub position: [f64; 3],
    /// Its Z-Y-X angles [roll, pitch, yaw] [rad] ([`roll_pitch_yaw`]).
    pub roll_pitch_yaw: [f64; 3],
}

/// The robot of a problem, for forward kinematics.
#[derive(Debug)]
pub struct Kinematics {
    mech: ModelMechanics,
    contacts: Vec<String>,
    links: Vec<String>,
}

impl Kinematics {
    /// The robot of `spec` (URDF, base, contacts) as the transcription loads it.
    pub fn new(spec: &ProblemSpec) -> Result<Kinematics, TranscriptionError> {
        let mech = ModelMechanics::load(spec)?;
        let links = mech.model().link_names().to_vec();
        Ok(Kinematics {
            mech,
            contacts: spec.contacts.iter().map(|c| c.name.clone()).collect(),
            links,
        })
    }

    /// The problem's contact names, in order.
    pub fn contact_names(&self) -> &[String] {
        &self.contacts
    }

    /// The URDF's link names.
    pub fn link_names(&self) -> &[String] {
        &self.links
    }

    /// Contact `name`'s point at q (a sphere's lowest point, as its distance sees it).
    pub fn contact_position(&self, name: &str, q: &[f64]) -> Result<[f64; 3], KinematicsError> {
        self.check_len(q)?;
        let i = find("contact", name, &self.contacts)?;
        Ok(self.mech.contact_position(i, q))
    }

    /// The world position of `point` (in `link`'s frame) at q.
    pub fn point_position(
        &self,
        link: &str,
        point: [f64; 3],
        q: &[f64],
    ) -> Result<[f64; 3], KinematicsError> {
        let pose = self.link_pose(link, q)?;
        let mut p = pose.position;
        for (a, row) in p.iter_mut().zip(&pose.rotation) {
            *a += row.iter().zip(point).map(|(r, x)| r * x).sum::<f64>();
        }
        Ok(p)
    }

    /// `link`'s world pose at q.
    pub fn link_pose(&self, link: &str, q: &[f64]) -> Result<LinkPose, KinematicsError> {
        self.check_len(q)?;
        let i = find("link", link, &self.links)?;
        let (rotation, position) =
            self.mech
                .link_pose(i, q)
                .ok_or_else(|| KinematicsError::UnknownName {
                    kind: "link",
                    name: link.to_owned(),
                    valid: self.links.clone(),
                })?;
        Ok(LinkPose {
            rotation,
            position,
            roll_pitch_yaw: roll_pitch_yaw(&rotation),
        })
    }

    fn check_len(&self, q: &[f64]) -> Result<(), KinematicsError> {
        let expected = self.mech.nq();
        if q.len() == expected {
            Ok(())
        } else {
            Err(KinematicsError::Length {
                expected,
                found: q.len(),
            })
        }
    }
}

fn find(kind: &'static str, name: &str, names: &[String]) -> Result<usize, KinematicsError> {
    names
        .iter()
        .position(|n| n == name)
        .ok_or_else(|| KinematicsError::UnknownName {
            kind,
            name: name.to_owned(),
            valid: names.to_vec(),
        })
}
