//! `type = "orientation"`: a link's roll, pitch or yaw at a knot [rad], the Z-Y-X (yaw,
//! pitch, roll) angles of its world rotation R = Rz(yaw)·Ry(pitch)·Rx(roll). On a contact,
//! the link the contact is fixed to.

use super::{FrameFunction, FramePoint, FrameReads};
use crate::autodiff::Scalar;
use crate::contact::Terrain;
use crate::discrete::Mechanics;
use crate::model::roll_pitch_yaw;

/// One of the link's [`roll_pitch_yaw`] angles.
#[derive(Debug, Clone, PartialEq)]
pub struct Orientation {
    /// The link (its point is unused).
    pub point: FramePoint,
    /// 0, 1, 2 for roll, pitch, yaw.
    pub axis: usize,
}

impl FrameFunction for Orientation {
    const NAME: &'static str = "orientation";
    const READS: FrameReads = FrameReads::Knot;
    const AXES: &'static [&'static str] = &["roll", "pitch", "yaw"];
    const OF_LINK: bool = true;
    fn new(point: FramePoint, axis: usize) -> Self {
        Orientation { point, axis }
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, _: &Terrain, _: usize, z: &[D]) -> D {
        let FramePoint::Link { link, .. } = self.point else {
            return D::from(0.0);
        };
        let Some((r, _)) = mech.link_pose(link, z) else {
            return D::from(0.0);
        };
        roll_pitch_yaw(&r)[self.axis]
    }
    fn point(&self) -> FramePoint {
        self.point
    }
}
