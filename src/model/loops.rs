//! Loop-closure residuals.

use super::kinematics::{check_len, frame_pose};
use super::spatial::{add, mat_mul_const, mat_t_vec, mat_vec_const, sub};
use super::{Model, Scalar};

/// Loop-closure residual, length `model.num_loop_constraints()`: for each loop (document
/// order) the two components of R_Bᵀ(p1 − p2) perpendicular to the pin axis (see
/// [`super::LoopClosure`]); zero when every loop is closed. Length units of the model.
pub fn loop_residual<D: Scalar>(model: &Model, q: &[D]) -> Vec<D> {
    check_len(model, q.len(), "q");
    let mut out = Vec::with_capacity(model.num_loop_constraints());
    for closure in &model.loop_closures {
        let pose1 = frame_pose(model, model.link_frame[closure.link1.0], q);
        let pose2 = frame_pose(model, model.link_frame[closure.link2.0], q);
        let p1 = add(
            pose1.origin,
            mat_vec_const(&pose1.rotation, &closure.point1),
        );
        let p2 = add(
            pose2.origin,
            mat_vec_const(&pose2.rotation, &closure.point2),
        );
        let frame_b = mat_mul_const(&pose2.rotation, &closure.rotation2);
        let gap = mat_t_vec(&frame_b, sub(p1, p2));
        for direction in &closure.directions {
            out.push(gap[0] * direction[0] + gap[1] * direction[1] + gap[2] * direction[2]);
        }
    }
    out
}
