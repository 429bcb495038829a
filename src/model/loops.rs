//! Loop-closure residuals.

use super::Model;
use super::kinematics::{check_len, frame_pose};
use super::spatial::{add, mat_mul, mat_mul_const, mat_t_vec, mat_vec_const, sub};
use crate::scalar::Scalar;

/// Loop-closure residual, length `model.num_loop_constraints()`: for each loop (document
/// order) the two components of R_Bᵀ(p1 − p2) perpendicular to the pin axis (see
/// [`super::LoopClosure`]); zero when every loop is closed. Length units of the model.
pub fn loop_residual<D: Scalar>(model: &Model, q: &[D]) -> Vec<D> {
    check_len(model, q.len(), "q");
    let mut out = Vec::with_capacity(model.num_loop_constraints());
    for closure in &model.loop_closures {
        let place1 = &model.link_frame[closure.link1.0];
        let place2 = &model.link_frame[closure.link2.0];
        let pose1 = frame_pose(model, place1.frame, q);
        let pose2 = frame_pose(model, place2.frame, q);
        let in_frame1 = place1.point_in_frame(&closure.point1);
        let in_frame2 = place2.point_in_frame(&closure.point2);
        let p1 = add(pose1.origin, mat_vec_const(&pose1.rotation, &in_frame1));
        let p2 = add(pose2.origin, mat_vec_const(&pose2.rotation, &in_frame2));
        // Frame B's axes in the tree frame of link2, then in the world.
        let b_in_frame2: [[f64; 3]; 3] = mat_mul(&place2.rotation, &closure.rotation2);
        let frame_b = mat_mul_const(&pose2.rotation, &b_in_frame2);
        let gap = mat_t_vec(&frame_b, sub(p1, p2));
        for direction in &closure.directions {
            out.push(gap[0] * direction[0] + gap[1] * direction[1] + gap[2] * direction[2]);
        }
    }
    out
}
