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
//! and the other orders follow by symmetry. `tests/integration/model_point_jet.rs` checks every entry
//! against forward AD through [`super::point_position`].

use super::kinematics::{Pose, check_len, child_pose};
use super::spatial::{add, cross, mat_vec_const, sub};
use super::tree::Motion;
use super::{LinkId, Model};

/// A point's world position and its derivatives in the coordinates `coords` it depends on
/// (every other coordinate has zero derivatives). Local index a stands for q[`coords[a]`].
#[derive(Debug, Clone, PartialEq)]
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
    check_len(model, q.len(), "q");
    let placement = &model.link_frame[link.0];
    let mut path = Vec::with_capacity(16);
    let mut cursor = Some(placement.frame);
    while let Some(i) = cursor {
        path.push(i);
        cursor = model.frames[i].parent;
    }
    let mut pose: Pose<f64> = Pose::world();
    // (coordinate, motion, world axis, world origin) of each moving joint, root to leaf.
    let mut joints: Vec<(usize, Motion, [f64; 3], [f64; 3])> = Vec::with_capacity(path.len());
    for &i in path.iter().rev() {
        let frame = &model.frames[i];
        pose = child_pose(frame, &pose, q);
        if frame.motion != Motion::Fixed {
            // Per unit rate of the coordinate: a mimic joint turns `multiplier` times as fast.
            let axis = pose.axis.map(|a| frame.to_coordinate(a));
            joints.push((frame.coordinate, frame.motion, axis, pose.origin));
        }
    }
    let position = add(
        pose.origin,
        mat_vec_const(&pose.rotation, &placement.point_in_frame(point)),
    );
    let c = joints.len();
    let rotate = |i: usize, v: [f64; 3]| match joints[i].1 {
        Motion::Revolute => cross(joints[i].2, v),
        _ => [0.0; 3],
    };
    let first: Vec<[f64; 3]> = joints
        .iter()
        .map(|&(_, motion, axis, origin)| match motion {
            Motion::Revolute => cross(axis, sub(position, origin)),
            _ => axis,
        })
        .collect();
    let mut second = Vec::new();
    if order >= 2 {
        second = vec![[0.0; 3]; c * c];
        for k in 0..c {
            for j in 0..=k {
                let s = rotate(j, first[k]);
                second[j * c + k] = s;
                second[k * c + j] = s;
            }
        }
    }
    let mut third = Vec::new();
    if order >= 3 {
        third = vec![[0.0; 3]; c * c * c];
        for k in 0..c {
            for j in 0..=k {
                for i in 0..=j {
                    let t = rotate(i, second[j * c + k]);
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
    }
    PointJet {
        coords: joints.iter().map(|j| j.0).collect(),
        position,
        first,
        second,
        third,
    }
}
