//! `type = "velocity"`: one world component of a point's velocity at knot k ≥ 1, the
//! difference over the interval ending there, (p(q_k) − p(q_{k−1}))/h_{k−1} [length/s].

use super::{FrameFunction, FramePoint, FrameReads};
use crate::autodiff::Scalar;
use crate::contact::Terrain;
use crate::discrete::Mechanics;

/// (p(q_k)[axis] − p(q_{k−1})[axis]) / h_{k−1}.
#[derive(Debug, Clone, PartialEq)]
pub struct Velocity {
    /// The point.
    pub point: FramePoint,
    /// 0, 1, 2 for x, y, z.
    pub axis: usize,
}

impl FrameFunction for Velocity {
    const NAME: &'static str = "velocity";
    const READS: FrameReads = FrameReads::IntervalEndingAt;
    const AXES: &'static [&'static str] = &["x", "y", "z"];
    fn new(point: FramePoint, axis: usize) -> Self {
        Velocity { point, axis }
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, _: &Terrain, n: usize, z: &[D]) -> D {
        let a = self.point.position(mech, &z[..n])[self.axis];
        let b = self.point.position(mech, &z[n..2 * n])[self.axis];
        (b - a) / z[2 * n]
    }
    fn point(&self) -> FramePoint {
        self.point
    }
}
