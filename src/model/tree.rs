//! The immutable model: a kinematic tree of frames in topological order, plus names,
//! limits, springs, dampers, inputs, contact points and loop closures.

use super::{BaseType, CoordinateKind};
use crate::autodiff::Scalar;

/// Index of a URDF link in [`Model::link_names`].
#[repr(transparent)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LinkId(pub(crate) usize);

impl LinkId {
    /// The position of the link in [`Model::link_names`].
    pub fn index(self) -> usize {
        self.0
    }
}

/// A contact of the URDF: a collision sphere (radius 0: a point).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPoint {
    /// The collision element's `name`; when it has none, the link's name if this is the
    /// link's only point contact, else `<link>_contact<i>` (i = index among its collisions).
    pub name: String,
    /// The URDF link the point is fixed to.
    pub link: String,
    /// The sphere's centre in the link frame (the collision origin's xyz), in model length
    /// units.
    pub point: [f64; 3],
    /// The sphere's radius (0 for a point), in model length units.
    pub radius: f64,
}

/// A collision element that gives no contact (a box, cylinder, capsule or mesh).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct IgnoredCollision {
    /// The link it belongs to.
    pub link: String,
    /// `box`, `cylinder`, `capsule` or `mesh`.
    pub shape: String,
}

/// Whether a spring acts on an angle or a length.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SpringKind {
    /// Drake `<torsional_spring>`: stiffness in torque per radian.
    Torsional,
    /// Drake `<prismatic_spring>`: stiffness in force per length.
    Prismatic,
}

/// A linear joint spring with energy ½·stiffness·(`q[coordinate]` − rest)².
#[derive(Debug, Clone, PartialEq)]
pub struct Spring {
    /// The `<force_element>` name.
    pub name: String,
    /// Torsional or prismatic.
    pub kind: SpringKind,
    /// Index of the coordinate the spring acts on.
    pub coordinate: usize,
    /// Stiffness (N·m/rad or N/m in SI).
    pub stiffness: f64,
    /// Rest angle (rad) or rest length.
    pub rest: f64,
}

/// A holonomic loop closure (Drake `<loop_joint>`): the point `point1` of `link1` and the
/// point `point2` of `link2` coincide, in the plane perpendicular to `axis`.
///
/// Residual rows (2 per loop): d = R_Bᵀ(p1 − p2) with frame B = link2 · R(rpy2), projected on
/// two unit vectors perpendicular to `axis` (for a coordinate axis, the other two coordinate
/// axes in increasing order, as Drake's `HamrRBM` kept them).
#[derive(Debug, Clone, PartialEq)]
pub struct LoopClosure {
    /// The `<loop_joint>` name.
    pub name: String,
    /// First link.
    pub link1: LinkId,
    /// Point in `link1` frame.
    pub point1: [f64; 3],
    /// Second link.
    pub link2: LinkId,
    /// Point in `link2` frame.
    pub point2: [f64; 3],
    /// Rotation R(rpy2) of frame B in `link2`, row-major.
    pub(crate) rotation2: [[f64; 3]; 3],
    /// The pin axis, unit, in frame B.
    pub axis: [f64; 3],
    /// The two unit directions (in frame B) whose components are constrained.
    pub(crate) directions: [[f64; 3]; 2],
}

/// How a frame moves relative to its parent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Motion {
    /// Welded.
    Fixed,
    /// Rotation about `axis` by q.
    Revolute,
    /// Translation along `axis` by q.
    Prismatic,
}

/// One frame of the tree: a rigid body (a URDF link with everything welded to it by fixed
/// joints, masses lumped), or a massless virtual frame of the base chain.
#[derive(Debug, Clone)]
pub(crate) struct Frame {
    /// Parent frame (index < own index), `None` for the world.
    pub parent: Option<usize>,
    /// Joint origin rotation R(rpy), row-major.
    pub rotation: [[f64; 3]; 3],
    /// Joint origin translation, in the parent frame.
    pub translation: [f64; 3],
    /// Joint axis, unit, in the joint frame (after R(rpy)).
    pub axis: [f64; 3],
    /// Joint motion.
    pub motion: Motion,
    /// Coordinate index (meaningless for `Fixed`).
    pub coordinate: usize,
    /// Mass (0 for massless frames).
    pub mass: f64,
    /// Centre of mass in this frame.
    pub com: [f64; 3],
    /// Inertia about the centre of mass, in this frame's axes.
    pub inertia: [[f64; 3]; 3],
    /// For a `<mimic>` joint: its value is multiplier·q[`coordinate`] + offset (the leader's
    /// coordinate); `None` when the joint has a coordinate of its own.
    pub mimic: Option<Mimic>,
}

/// A `<mimic>` joint's map from its leader's coordinate: θ = multiplier·q_leader + offset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Mimic {
    pub multiplier: f64,
    pub offset: f64,
}

impl Frame {
    /// A frame without mass yet (masses are lumped in after all frames exist).
    pub fn massless(
        parent: Option<usize>,
        rotation: [[f64; 3]; 3],
        translation: [f64; 3],
        axis: [f64; 3],
        motion: Motion,
        coordinate: usize,
    ) -> Frame {
        Frame {
            parent,
            rotation,
            translation,
            axis,
            motion,
            coordinate,
            mass: 0.0,
            com: [0.0; 3],
            inertia: [[0.0; 3]; 3],
            mimic: None,
        }
    }

    /// The joint's value θ (angle or length): q[`coordinate`], or a mimic's map of it.
    pub(crate) fn joint_value<D: Scalar>(&self, q: &[D]) -> D {
        match self.mimic {
            None => q[self.coordinate],
            Some(m) => q[self.coordinate] * m.multiplier + D::from(m.offset),
        }
    }

    /// The joint's rate θ̇ (or acceleration) from the coordinates' rates `v`.
    pub(crate) fn joint_rate<D: Scalar>(&self, v: &[D]) -> D {
        match self.mimic {
            None => v[self.coordinate],
            Some(m) => v[self.coordinate] * m.multiplier,
        }
    }

    /// A generalised force on θ as a force on q[`coordinate`]: times ∂θ/∂q = multiplier.
    pub(crate) fn to_coordinate<D: Scalar>(&self, force: D) -> D {
        match self.mimic {
            None => force,
            Some(m) => force * m.multiplier,
        }
    }
}

/// Where a URDF link sits: rigidly attached to tree frame `frame` at (rotation, translation).
/// Links behind fixed joints share their moving ancestor's frame, so the recursions visit
/// one frame per rigid body, not per URDF link.
#[derive(Debug, Clone)]
pub(crate) struct LinkPlacement {
    /// The tree frame.
    pub frame: usize,
    /// Link axes in frame axes, row-major.
    pub rotation: [[f64; 3]; 3],
    /// Link origin in the frame.
    pub translation: [f64; 3],
}

impl LinkPlacement {
    /// A link-frame point expressed in the tree frame.
    pub(crate) fn point_in_frame(&self, point: &[f64; 3]) -> [f64; 3] {
        let r = &self.rotation;
        let t = &self.translation;
        [
            t[0] + r[0][0] * point[0] + r[0][1] * point[1] + r[0][2] * point[2],
            t[1] + r[1][0] * point[0] + r[1][1] * point[1] + r[1][2] * point[2],
            t[2] + r[2][0] * point[0] + r[2][1] * point[1] + r[2][2] * point[2],
        ]
    }
}

/// A robot model loaded from URDF: immutable, `f64`, frames in topological order.
#[derive(Debug, Clone)]
pub struct Model {
    pub(crate) frames: Vec<Frame>,
    pub(crate) link_frame: Vec<LinkPlacement>,
    pub(crate) link_names: Vec<String>,
    pub(crate) coordinate_names: Vec<String>,
    pub(crate) coordinate_limits: Vec<(f64, f64)>,
    pub(crate) damping: Vec<f64>,
    pub(crate) input_names: Vec<String>,
    pub(crate) input_coordinates: Vec<usize>,
    pub(crate) effort_limits: Vec<f64>,
    /// Every joint that can take an input; the inputs are those the actuation rule chose.
    pub(crate) actuators: Vec<super::actuation::Actuator>,
    pub(crate) actuation: super::actuation::AppliedActuation,
    pub(crate) contact_points: Vec<ContactPoint>,
    pub(crate) ignored_collisions: Vec<IgnoredCollision>,
    pub(crate) springs: Vec<Spring>,
    pub(crate) loop_closures: Vec<LoopClosure>,
    pub(crate) gravity: [f64; 3],
    pub(crate) total_mass: f64,
    pub(crate) base: BaseType,
    pub(crate) name: String,
    pub(crate) warnings: Vec<String>,
    pub(crate) leaf_links: Vec<String>,
    /// Per link (in [`Model::link_names`] order): what it looks like, for drawing only.
    pub(crate) geometry: Vec<super::LinkGeometry>,
}

impl Model {
    /// Whether every point of the robot stays in a plane y = const for every q: each
    /// revolute joint turns about world ±y and each prismatic joint (base coordinates
    /// included) slides within x–z, read from the joint axes at q = 0. Rotations about y
    /// keep y-axes and x–z directions as they are, so what holds at q = 0 holds at every q.
    /// A rule on structure, never on sampled values (a point whose y-rate merely vanishes
    /// at a sample is still spatial).
    pub fn moves_in_xz_plane(&self) -> bool {
        const TOLERANCE: f64 = 1e-9;
        let mut world_rotation: Vec<[[f64; 3]; 3]> = Vec::with_capacity(self.frames.len());
        for frame in &self.frames {
            let rotation = match frame.parent {
                Some(p) => super::spatial::mat_mul_const(&world_rotation[p], &frame.rotation),
                None => frame.rotation,
            };
            let axis = super::spatial::mat_vec_const(&rotation, &frame.axis);
            let in_plane = match frame.motion {
                Motion::Revolute => axis[0].abs() < TOLERANCE && axis[2].abs() < TOLERANCE,
                Motion::Prismatic => axis[1].abs() < TOLERANCE,
                Motion::Fixed => true,
            };
            if !in_plane {
                return false;
            }
            world_rotation.push(rotation);
        }
        true
    }

    /// The robot's name (URDF `<robot name>`).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The base the model was loaded with.
    pub fn base(&self) -> BaseType {
        self.base
    }

    /// Number of generalised coordinates.
    pub fn nq(&self) -> usize {
        self.coordinate_names.len()
    }

    /// Coordinate names, length `nq`: base coordinates, then joints in document order.
    pub fn coordinate_names(&self) -> &[String] {
        &self.coordinate_names
    }

    /// Per coordinate, whether it is a length (prismatic joint, base translation) or an angle.
    pub fn coordinate_kinds(&self) -> Vec<CoordinateKind> {
        let mut kinds = vec![CoordinateKind::Angular; self.nq()];
        for frame in &self.frames {
            if frame.motion == Motion::Prismatic && frame.mimic.is_none() {
                kinds[frame.coordinate] = CoordinateKind::Linear;
            }
        }
        kinds
    }

    /// Index of the coordinate with this name.
    pub fn coordinate_index(&self, name: &str) -> Option<usize> {
        self.coordinate_names.iter().position(|n| n == name)
    }

    /// (lower, upper) per coordinate, ±inf where the URDF gives none (base coordinates: none).
    pub fn coordinate_limits(&self) -> &[(f64, f64)] {
        &self.coordinate_limits
    }

    /// Per coordinate, whether changing it translates a subtree rigidly along a fixed world
    /// axis: a prismatic joint (the only frame of its coordinate, no mimic, no spring on it)
    /// whose ancestors are all prismatic or fixed (a floating or planar base's x, y, z). The
    /// Lagrangian depends on such a coordinate at most linearly: the translated bodies keep
    /// their velocities (their ancestors do not turn) and the potential changes by their
    /// weight times the shift. Read from the structure, never from values.
    pub fn translation_coordinates(&self) -> Vec<bool> {
        let n = self.nq();
        let mut frames_of = vec![0usize; n];
        for frame in self.frames.iter().filter(|f| f.motion != Motion::Fixed) {
            frames_of[frame.coordinate] += 1;
        }
        let mut out = vec![false; n];
        // Whether a frame and all its ancestors are prismatic or fixed.
        let mut translating: Vec<bool> = Vec::with_capacity(self.frames.len());
        for frame in &self.frames {
            let above = frame.parent.is_none_or(|p| translating[p]);
            translating.push(above && frame.motion != Motion::Revolute);
            if above && frame.motion == Motion::Prismatic && frame.mimic.is_none() {
                out[frame.coordinate] = frames_of[frame.coordinate] == 1;
            }
        }
        for spring in &self.springs {
            out[spring.coordinate] = false;
        }
        out
    }

    /// Whether the URDF moves its root link itself: some coordinate translates the robot
    /// along a world axis ([`Model::translation_coordinates`]: a prismatic joint with only
    /// prismatic or fixed joints above it, as a planar hopper's `x` and `z` sliders). Such a
    /// URDF needs no free base (one would add coordinates it already has); a URDF whose root
    /// link is the torso does.
    pub fn slides_its_root(&self) -> bool {
        let base = self.base.coordinate_names().len();
        self.translation_coordinates().iter().skip(base).any(|&t| t)
    }

    /// Viscous damping per coordinate (URDF `<dynamics damping>`), 0 where none.
    pub fn damping(&self) -> &[f64] {
        &self.damping
    }

    /// Input names: the `<transmission>` joints, in document order.
    pub fn input_names(&self) -> &[String] {
        &self.input_names
    }

    /// Input i acts on coordinate `input_coordinates()[i]` (B is a selection matrix).
    pub fn input_coordinates(&self) -> &[usize] {
        &self.input_coordinates
    }

    /// Effort limit per input (URDF `<limit effort>`), +inf where none.
    pub fn effort_limits(&self) -> &[f64] {
        &self.effort_limits
    }

    /// What each link looks like (in [`Model::link_names`] order), for drawing only.
    pub fn link_geometry(&self) -> &[super::LinkGeometry] {
        &self.geometry
    }

    /// URDF link names, in topological order (parents before children).
    pub fn link_names(&self) -> &[String] {
        &self.link_names
    }

    /// The link with this name.
    pub fn link_index(&self, name: &str) -> Option<LinkId> {
        self.link_names.iter().position(|n| n == name).map(LinkId)
    }

    /// Collision spheres (radius 0: points), in document order.
    pub fn contact_points(&self) -> &[ContactPoint] {
        &self.contact_points
    }

    /// Collision elements that are not spheres, so give no contact, in document order.
    pub fn ignored_collisions(&self) -> &[IgnoredCollision] {
        &self.ignored_collisions
    }

    /// Sum of the link masses.
    pub fn total_mass(&self) -> f64 {
        self.total_mass
    }

    /// Gravity acceleration in the world frame; default [0, 0, −9.81].
    pub fn gravity(&self) -> [f64; 3] {
        self.gravity
    }

    /// Sets gravity (e.g. [0, 0, −9.81e-3] for HAMR's mm/g/ms units).
    pub fn set_gravity(&mut self, g: [f64; 3]) {
        self.gravity = g;
    }

    /// Joint springs (torsional and prismatic).
    pub fn springs(&self) -> &[Spring] {
        &self.springs
    }

    /// Loop closures, in document order.
    pub fn loop_closures(&self) -> &[LoopClosure] {
        &self.loop_closures
    }

    /// Number of loop-closure residual rows (2 per loop).
    pub fn num_loop_constraints(&self) -> usize {
        2 * self.loop_closures.len()
    }

    /// Links without children (the ends of the tree: feet, hands, sensor frames), in
    /// document order.
    pub fn leaf_links(&self) -> &[String] {
        &self.leaf_links
    }

    /// What the loader repaired or ignored (unknown elements, inserted limits, ...).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }
}
