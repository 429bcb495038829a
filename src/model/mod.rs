//! Robot mechanics from URDF, generic over the scalar type.
//!
//! Frame rule: `world_t_frame` maps frame coordinates into the world; a child frame is
//! parent · Trans(xyz) · R(rpy) · Rot(axis, q) with R(rpy) = Rz(y)·Ry(p)·Rx(r) (URDF).
//! The configuration is q = [base coordinates; non-fixed joints in `<joint>` document order].
//! The [`Model`] is immutable and all `f64`; the algorithms are free functions generic over
//! [`crate::autodiff::Scalar`], so plain floats and (nested) dual numbers flow through the same formulas.

mod actuation;
mod auto_base;
pub(crate) mod dynamics;
pub(crate) mod energy;
mod energy_adjoint;
mod error;
mod inspect;
pub(crate) mod kinematics;
mod loops;
mod point_jet;
pub mod sample;
mod shape;

pub(crate) mod spatial;
pub(crate) mod tree;
mod urdf;

pub use actuation::{Actuation, AppliedActuation, NotActuatable};
pub use auto_base::BaseChoice;
pub use dynamics::{
    generalized_damping_force, generalized_input_force, generalized_point_force, inverse_dynamics,
};
pub use energy::{
    generalized_gravity, generalized_momentum, kinetic_energy, mass_matrix, mass_matrix_entries,
    potential_energy,
};
pub use energy_adjoint::{
    SweepBuffers, kinetic_energy_gradient, lagrangian_gradient, potential_energy_gradient,
};
pub use error::{ModelError, describe};
pub use inspect::{
    ContactInfo, CoordinateInfo, Inspection, LoopInfo, SpringInfo, inspect, trimmed_decimal,
};
pub use kinematics::{link_angular_jacobian, link_pose, point_position, roll_pitch_yaw};
pub use loops::{LoopJet, loop_closure_jets, loop_residual};
pub use point_jet::{PointJet, point_jet, point_jet_into, vector_jet};
pub use shape::{
    ChildJoint, LinkGeometry, Shape, ShapeKind, base_link, coordinate_limbs, frames_only,
};

pub use tree::{ContactPoint, IgnoredCollision, LinkId, LoopClosure, Model, Spring, SpringKind};
pub use urdf::SPHERE_HINT;

/// How the robot's root link is attached to the world.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BaseType {
    /// Root link welded to the world.
    #[default]
    Fixed,
    /// Trans(base_x, 0, base_z)·Ry(base_pitch): coordinates [`PLANAR_BASE_COORDINATES`].
    Planar,
    /// Trans(x, y, z)·Rz(yaw)·Ry(pitch)·Rx(roll): coordinates [`FLOATING_BASE_COORDINATES`].
    Floating,
}

/// The planar base's coordinates, in the order they lead q.
pub const PLANAR_BASE_COORDINATES: [&str; 3] = ["base_x", "base_z", "base_pitch"];

/// The floating base's coordinates, in the order they lead q.
pub const FLOATING_BASE_COORDINATES: [&str; 6] = [
    "base_x",
    "base_y",
    "base_z",
    "base_roll",
    "base_pitch",
    "base_yaw",
];

impl BaseType {
    /// The base's name as problem files, `vito init --base` and messages write it.
    pub fn name(self) -> &'static str {
        match self {
            BaseType::Fixed => "fixed",
            BaseType::Planar => "planar",
            BaseType::Floating => "floating",
        }
    }

    /// Names of the base coordinates, which lead q (none for a fixed base).
    pub fn coordinate_names(self) -> &'static [&'static str] {
        match self {
            BaseType::Fixed => &[],
            BaseType::Planar => &PLANAR_BASE_COORDINATES,
            BaseType::Floating => &FLOATING_BASE_COORDINATES,
        }
    }
}

/// Whether a coordinate is a length or an angle (for units in outputs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoordinateKind {
    /// A length (prismatic joint, base translation).
    Linear,
    /// An angle (revolute or continuous joint, base rotation).
    Angular,
}
