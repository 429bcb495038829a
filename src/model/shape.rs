//! A link's drawable geometry as the URDF states it (`<visual>`, `<collision>`, child joint
//! origins). Only drawing reads it; the mechanics never do.

/// One geometric primitive or mesh, placed in its link's frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// `<origin xyz>` in the link frame.
    pub xyz: [f64; 3],
    /// `<origin rpy>` (R = Rz(y)·Ry(p)·Rx(r)).
    pub rpy: [f64; 3],
    /// What it is.
    pub kind: ShapeKind,
    /// `<material>` colour (red, green, blue, alpha in [0, 1]), when a visual names one.
    pub rgba: Option<[f64; 4]>,
}

/// The geometry of a [`Shape`] (URDF conventions: a cylinder's and capsule's axis is local z,
/// centred on the origin).
#[derive(Debug, Clone, PartialEq)]
pub enum ShapeKind {
    /// `<box size>`: full edge lengths.
    Box {
        /// Edge lengths along x, y, z.
        size: [f64; 3],
    },
    /// `<cylinder>`.
    Cylinder {
        /// Radius.
        radius: f64,
        /// Length along z.
        length: f64,
    },
    /// `<capsule>`: a cylinder with hemispherical caps beyond its length.
    Capsule {
        /// Radius.
        radius: f64,
        /// Length of the cylindrical part along z.
        length: f64,
    },
    /// `<sphere>`.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// `<mesh>`: a file named as the URDF names it (not resolved or read here).
    Mesh {
        /// The `filename` attribute as written.
        filename: String,
        /// Scale factors along x, y, z.
        scale: [f64; 3],
    },
}

/// What a link looks like.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LinkGeometry {
    /// `<visual>` shapes.
    pub visual: Vec<Shape>,
    /// `<collision>` shapes.
    pub collision: Vec<Shape>,
    /// The joints whose parent is this link.
    pub children: Vec<ChildJoint>,
    /// `<inertial><mass>` (0 without one): a link with neither mass nor shapes is a
    /// coordinate frame (such as a planar base's sliders), not a body.
    pub mass: f64,
}

/// A joint whose parent is the link that lists it.
#[derive(Debug, Clone, PartialEq)]
pub struct ChildJoint {
    /// The joint's name.
    pub joint: String,
    /// The child link's name.
    pub link: String,
    /// `<origin xyz>` in the parent link's frame.
    pub xyz: [f64; 3],
    /// `<origin rpy>` (R = Rz(y)·Ry(p)·Rx(r)).
    pub rpy: [f64; 3],
    /// For a prismatic joint, its axis in the joint frame (the child's origin slides along
    /// it, away from `xyz`); `None` for joints that keep the child's origin at `xyz`.
    pub slide: Option<[f64; 3]>,
}

/// Whether each link is a coordinate frame rather than a body: no mass, no shapes, and its
/// parent (if any) is one too, such as the world link and a planar base's sliders.
pub fn frames_only(model: &super::Model) -> Vec<bool> {
    let geometry = model.link_geometry();
    let parent = parents(model);
    // Link ids are in topological order: a parent's verdict is known before its children's.
    let mut frame = vec![false; geometry.len()];
    for (l, g) in geometry.iter().enumerate() {
        frame[l] = g.mass == 0.0
            && g.visual.is_empty()
            && g.collision.is_empty()
            && parent[l].is_none_or(|p| p < l && frame[p]);
    }
    frame
}

/// Each link's parent link (by the joints the URDF states).
fn parents(model: &super::Model) -> Vec<Option<usize>> {
    let names = model.link_names();
    let mut parent = vec![None; names.len()];
    for (l, g) in model.link_geometry().iter().enumerate() {
        for child in &g.children {
            if let Some(c) = names.iter().position(|n| *n == child.link) {
                parent[c] = Some(l);
            }
        }
    }
    parent
}

/// The robot's base: its first link that is a body (see [`frames_only`]).
pub fn base_link(model: &super::Model) -> usize {
    frames_only(model).iter().position(|f| !f).unwrap_or(0)
}

/// Per coordinate, the limb it moves: `None` for the base's own coordinates (a free base's,
/// and joints that move coordinate frames or the base link itself, such as a planar base's
/// sliders and pitch), else the name of the base's child link whose subtree holds the joint.
pub fn coordinate_limbs(model: &super::Model) -> Vec<Option<String>> {
    let names = model.link_names();
    let frames = frames_only(model);
    let base = base_link(model);
    let parent = parents(model);
    let joint_child = |joint: &str| {
        model.link_geometry().iter().find_map(|g| {
            g.children
                .iter()
                .find(|c| c.joint == joint)
                .and_then(|c| names.iter().position(|n| *n == c.link))
        })
    };
    model
        .coordinate_names()
        .iter()
        .map(|coordinate| {
            let child = joint_child(coordinate)?;
            if frames[child] || child == base {
                return None;
            }
            let mut limb = child;
            while let Some(p) = parent[limb] {
                if p == base || frames[p] {
                    break;
                }
                limb = p;
            }
            Some(names[limb].clone())
        })
        .collect()
}
