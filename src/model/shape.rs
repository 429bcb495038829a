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
    /// Origins of the joints whose parent is this link, in the link frame.
    pub child_joints: Vec<[f64; 3]>,
}
