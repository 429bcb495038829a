//! `type = "position"`: one world coordinate (x, y or z) of a point at a knot [length].

use super::{FrameFunction, FramePoint, FrameReads};
use crate::autodiff::Scalar;
use crate::contact::Terrain;
use crate::discrete::Mechanics;

/// p(q_k)[axis]: the point's world position along one axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Position {
    /// The point.
    pub point: FramePoint,
    /// 0, 1, 2 for x, y, z.
    pub axis: usize,
}

impl FrameFunction for Position {
    const NAME: &'static str = "position";
    const READS: FrameReads = FrameReads::Knot;
    const AXES: &'static [&'static str] = &["x", "y", "z"];
    fn new(point: FramePoint, axis: usize) -> Self {
        Position { point, axis }
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, _: &Terrain, _: usize, z: &[D]) -> D {
        self.point.position(mech, z)[self.axis]
    }
    fn point(&self) -> FramePoint {
        self.point
    }
}
