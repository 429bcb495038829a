//! Derivatives of a point's world position in the coordinates of its kinematic chain, up to
//! third order, from the joints' world axes and origins (no dual numbers).
//!
//! Why: the contact blocks need ∂p, ∂²p and ∂³p contracted with multipliers at every knot and
//! contact, and forward AD through the frame chain with nested duals was most of the solve
//! time (profiled on Spring Flamingo: `child_pose` on `HyperDualVec`s and their copies).
//!
//! For the joints on the point's path, in root-to-leaf order, let G_k(p) be the velocity of
//! the point per unit q̇_k (revolute: a_k × (p − o_k); prismatic: a_k) and R_i(v) the rate of
//! a free vector carried by the bodies below joint i (revolute: a_i × v; prismatic: 0). Every
//! vector in G_k and in R_j(G_k), j ≤ k, is carried by the bodies below the joints above it,
//! so for chain positions i ≤ j ≤ k
//!   ∂p/∂q_k = G_k,   ∂²p/∂q_j∂q_k = R_j(G_k),   ∂³p/∂q_i∂q_j∂q_k = R_i(R_j(G_k)),
//! and the other orders follow by symmetry. A free vector v fixed in a body (a loop closure's
//! direction) has the same jet with G_k replaced by R_k(v). `tests/integration/model_point_jet.rs` checks every entry
//! against forward AD through [`super::point_position`].

use super::kinematics::{Pose, check_len, child_pose};
use super::spatial::{add, cross, mat_vec_const, sub};
use super::tree::Motion;
use super::{LinkId, Model};

/// A point's world position and its derivatives in the coordinates `coords` it depends on
/// (every other coordinate has zero derivatives). Local index a stands for q[`coords[a]`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PointJet {
    /// Coordinates the point depends on.
    pub coords: Vec<usize>,
    /// World position (length units of the model).
    pub position: [f64; 3],
    /// ∂p/∂q_a at `[a]`.
    pub first: Vec<[f64; 3]>,
    /// ∂²p/∂q_a∂q_b at `[a * c + b]`, c = `coords.len()`; empty below order 2.
    pub second: Vec<[f64; 3]>,
    /// ∂³p/∂q_a∂q_b∂q_e at `[(a * c + b) * c + e]`; empty below order 3.
    pub third: Vec<[f64; 3]>,
}

impl PointJet {
    /// Number of coordinates the point depends on.
    pub fn len(&self) -> usize {
        self.coords.len()
    }

    /// Whether the point is fixed in the world (depends on no coordinate).
    pub fn is_empty(&self) -> bool {
        self.coords.is_empty()
    }
}

/// Position of `point` (in the `link` frame) and its derivatives in q up to `order` (1 to 3;
/// higher orders are clamped to 3).
pub fn point_jet(
    model: &Model,
    link: LinkId,
    point: &[f64; 3],
    q: &[f64],
    order: usize,
) -> PointJet {
    let mut jet = PointJet::default();
    point_jet_into(model, link, point, q, order, &mut jet);
    jet
}

/// [`point_jet`] written into `jet`, reusing its storage: a jet of the same chain and order
/// (the last call's at another q) is overwritten entry by entry, without allocating or
/// zero-filling its second and third derivatives.
pub fn point_jet_into(
    model: &Model,
    link: LinkId,
    point: &[f64; 3],
    q: &[f64],
    order: usize,
    jet: &mut PointJet,
) {
    let chain = Chain::to_link(model, link, q);
    let placement = &model.link_frame[link.0];
    let position = add(
        chain.pose.origin,
        mat_vec_const(&chain.pose.rotation, &placement.point_in_frame(point)),
    );
    jet.first.clear();
    jet.first.extend(
        chain
            .joints
            .iter()
            .map(|&(_, motion, axis, origin)| match motion {
                Motion::Revolute => cross(axis, sub(position, origin)),
                _ => axis,
            }),
    );
    chain.jet_into(position, order, jet);
}

/// World components of a free vector fixed in `link` (`vector` in the link frame, e.g. a
/// direction) and their derivatives in q up to `order` (1 to 3): the same jet as a point's,
/// with every joint's first derivative R_k(v) (a free vector does not translate).
pub fn vector_jet(
    model: &Model,
    link: LinkId,
    vector: &[f64; 3],
    q: &[f64],
    order: usize,
) -> PointJet {
    let chain = Chain::to_link(model, link, q);
    let placement = &model.link_frame[link.0];
    let value = mat_vec_const(
        &chain.pose.rotation,
        &mat_vec_const(&placement.rotation, vector),
    );
    let first = (0..chain.joints.len())
        .map(|k| chain.rotate(k, value))
        .collect();
    chain.jet(value, first, order)
}

/// The moving joints on the path from the world to a link, at q.
struct Chain {
    /// The link's tree-frame pose.
    pose: Pose<f64>,
    /// (coordinate, motion, world axis, world origin) of each moving joint, root to leaf.
    joints: Vec<(usize, Motion, [f64; 3], [f64; 3])>,
}

impl Chain {
    fn to_link(model: &Model, link: LinkId, q: &[f64]) -> Chain {
        check_len(model, q.len(), "q");
        let placement = &model.link_frame[link.0];
        let mut path = Vec::with_capacity(16);
        let mut cursor = Some(placement.frame);
        while let Some(i) = cursor {
            path.push(i);
            cursor = model.frames[i].parent;
        }
        let mut pose: Pose<f64> = Pose::world();
        let mut joints = Vec::with_capacity(path.len());
        for &i in path.iter().rev() {
            let frame = &model.frames[i];
            pose = child_pose(frame, &pose, q);
            if frame.motion != Motion::Fixed {
                // Per unit rate of the coordinate: a mimic joint turns `multiplier` times as fast.
                let axis = pose.axis.map(|a| frame.to_coordinate(a));
                joints.push((frame.coordinate, frame.motion, axis, pose.origin));
            }
        }
        Chain { pose, joints }
    }

    /// R_i(v): the rate of a free vector carried by the bodies below joint i.
    fn rotate(&self, i: usize, v: [f64; 3]) -> [f64; 3] {
        match self.joints[i].1 {
            Motion::Revolute => cross(self.joints[i].2, v),
            _ => [0.0; 3],
        }
    }

    /// The jet whose first derivatives are `first` (one per joint, carried by the bodies
    /// below it): higher orders by R_j and R_i (module comment).
    fn jet(&self, position: [f64; 3], first: Vec<[f64; 3]>, order: usize) -> PointJet {
        let mut jet = PointJet {
            first,
            ..PointJet::default()
        };
        self.jet_into(position, order, &mut jet);
        jet
    }

    /// Completes `jet`, whose `first` holds the first derivatives, with the coordinates, the
    /// position and the higher orders; every entry of `second` and `third` is written, so
    /// storage of the right length is reused as it is.
    fn jet_into(&self, position: [f64; 3], order: usize, jet: &mut PointJet) {
        let c = self.joints.len();
        let PointJet {
            coords,
            position: jet_position,
            first,
            second,
            third,
        } = jet;
        coords.clear();
        coords.extend(self.joints.iter().map(|j| j.0));
        *jet_position = position;
        if order >= 2 {
            second.resize(c * c, [0.0; 3]);
            for k in 0..c {
                for j in 0..=k {
                    let s = self.rotate(j, first[k]);
                    second[j * c + k] = s;
                    second[k * c + j] = s;
                }
            }
        } else {
            second.clear();
        }
        if order >= 3 {
            third.resize(c * c * c, [0.0; 3]);
            for k in 0..c {
                for j in 0..=k {
                    for i in 0..=j {
                        let t = self.rotate(i, second[j * c + k]);
                        for (a, b, e) in [
                            (i, j, k),
                            (i, k, j),
                            (j, i, k),
                            (j, k, i),
                            (k, i, j),
                            (k, j, i),
                        ] {
                            third[(a * c + b) * c + e] = t;
                        }
                    }
                }
            }
        } else {
            third.clear();
        }
    }
}
