//! Robot mechanics from URDF, generic over the scalar type.

mod scalar;

pub use scalar::Scalar;

/// How the robot's root link is attached to the world.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BaseType {
    /// Root link welded to the world.
    #[default]
    Fixed,
    /// Trans(base_x, 0, base_z)·Ry(base_pitch): coordinates `base_x`, `base_z`, `base_pitch`.
    Planar,
    /// Trans(x, y, z)·Rz(yaw)·Ry(pitch)·Rx(roll): `base_x`, `base_y`, `base_z`, `base_roll`,
    /// `base_pitch`, `base_yaw`.
    Floating,
}
