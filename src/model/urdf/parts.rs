//! The pieces the URDF's conversion steps share: rotations, the virtual base's frames, name
//! indices, the tree's order and the coordinate table.

use std::collections::HashMap;

use crate::model::BaseType;
use crate::model::spatial::rpy_to_matrix;
use crate::model::tree::{Mimic, Motion};

/// The rotation of URDF roll, pitch, yaw angles.
pub(super) fn rpy(v: &[f64; 3]) -> [[f64; 3]; 3] {
    rpy_to_matrix(v[0], v[1], v[2])
}

pub(super) const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// One virtual base frame: its motion, axis and coordinate index (into
/// [`BaseType::coordinate_names`]).
pub(super) type BaseFrame = (Motion, [f64; 3], usize);

pub(super) fn base_chain(base: BaseType) -> Vec<BaseFrame> {
    const X: [f64; 3] = [1.0, 0.0, 0.0];
    const Y: [f64; 3] = [0.0, 1.0, 0.0];
    const Z: [f64; 3] = [0.0, 0.0, 1.0];
    match base {
        BaseType::Fixed => vec![],
        BaseType::Planar => vec![
            (Motion::Prismatic, X, 0),
            (Motion::Prismatic, Z, 1),
            (Motion::Revolute, Y, 2),
        ],
        // Trans(x, y, z)·Rz(yaw)·Ry(pitch)·Rx(roll), q_base = [x, y, z, roll, pitch, yaw].
        BaseType::Floating => vec![
            (Motion::Prismatic, X, 0),
            (Motion::Prismatic, Y, 1),
            (Motion::Prismatic, Z, 2),
            (Motion::Revolute, Z, 5),
            (Motion::Revolute, Y, 4),
            (Motion::Revolute, X, 3),
        ],
    }
}

/// Index of a link or joint by name.
pub(super) type NameIndex<'a> = HashMap<&'a str, usize>;

/// The tree's shape: each link's parent joint, and the links parents first.
pub(super) struct Tree {
    pub(super) parent_joint: Vec<Option<usize>>,
    /// Links without children, in document order.
    pub(super) leaves: Vec<usize>,
    /// Depth-first from the root.
    pub(super) order: Vec<usize>,
}

/// The coordinates: base, then non-fixed joints in document order (except `<mimic>`
/// joints, which follow their leader and have no coordinate of their own).
pub(super) struct Coordinates {
    pub(super) names: Vec<String>,
    pub(super) limits: Vec<(f64, f64)>,
    pub(super) damping: Vec<f64>,
    /// Per joint, its coordinate (`None` for fixed and mimic joints).
    pub(super) joint_coordinate: Vec<Option<usize>>,
    /// Per mimic joint, its leader's coordinate and the map from it.
    pub(super) mimic: Vec<Option<(usize, Mimic)>>,
}
