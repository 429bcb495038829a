//! `type = "clearance"`: a point's height above the terrain under it at a knot, the
//! terrain's signed distance φ = p_z − H(p_x) (steps included) [length]. On a contact it is
//! the contact's own distance (a sphere's lowest point).

use super::{FrameFunction, FramePoint, FrameReads};
use crate::autodiff::Scalar;
use crate::contact::{Terrain, signed_distance};
use crate::discrete::Mechanics;

/// φ(p(q_k)).
#[derive(Debug, Clone, PartialEq)]
pub struct Clearance {
    /// The point.
    pub point: FramePoint,
}

impl FrameFunction for Clearance {
    const NAME: &'static str = "clearance";
    const READS: FrameReads = FrameReads::Knot;
    const AXES: &'static [&'static str] = &[];
    fn new(point: FramePoint, _: usize) -> Self {
        Clearance { point }
    }
    fn value<D: Scalar, M: Mechanics>(&self, mech: &M, terrain: &Terrain, _: usize, z: &[D]) -> D {
        signed_distance(terrain, &self.point.position(mech, z))
    }
    fn point(&self) -> FramePoint {
        self.point
    }
}
