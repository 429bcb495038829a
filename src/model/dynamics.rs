//! Generalised forces: inputs, damping and inverse dynamics (RNEA in world coordinates).

use super::energy::{com_position, project_wrenches, world_inertia_times};
use super::kinematics::{Pose, Twist, check_len, child_pose, child_twist, frame_poses};
use super::spatial::{Vec3, add, cross, mat_vec_const, scale, sub};
use super::tree::Motion;
use super::{LinkId, Model};
use crate::autodiff::Scalar;

/// B(q)·u: input i adds `u[i]` to coordinate `model.input_coordinates()[i]` (length `nq`;
/// B is a constant selection matrix, `q` is accepted for the general signature).
pub fn generalized_input_force<D: Scalar>(model: &Model, q: &[D], u: &[D]) -> Vec<D> {
    check_len(model, q.len(), "q");
    assert_eq!(
        u.len(),
        model.input_coordinates.len(),
        "u has length {}, but the model has {} inputs",
        u.len(),
        model.input_coordinates.len()
    );
    let mut out = vec![D::from(0.0); model.nq()];
    for (&coordinate, &value) in model.input_coordinates.iter().zip(u) {
        out[coordinate] += value;
    }
    out
}

/// Generalised force Jᵀ(q)·f of a world-frame force `force` applied at `point` (given in the
/// `link` frame), length `nq`: for actuators or contact forces that act at a point.
pub fn generalized_point_force<D: Scalar>(
    model: &Model,
    link: LinkId,
    point: &[f64; 3],
    force: [D; 3],
    q: &[D],
) -> Vec<D> {
    check_len(model, q.len(), "q");
    let poses = frame_poses(model, q);
    let placement = &model.link_frame[link.0];
    let frame = placement.frame;
    let at = add(
        poses[frame].origin,
        mat_vec_const(&poses[frame].rotation, &placement.point_in_frame(point)),
    );
    let zero = [D::from(0.0); 3];
    let mut forces = vec![zero; model.frames.len()];
    let mut moments = vec![zero; model.frames.len()];
    forces[frame] = force;
    moments[frame] = cross(at, force);
    project_wrenches(model, &poses, forces, moments)
}

/// Viscous damping force −diag(d)·v (length `nq`; d from URDF `<dynamics damping>`).
pub fn generalized_damping_force<D: Scalar>(model: &Model, v: &[D]) -> Vec<D> {
    check_len(model, v.len(), "v");
    model
        .damping
        .iter()
        .zip(v)
        .map(|(&d, &vi)| vi * (-d))
        .collect()
}

/// Inverse dynamics M(q)a + C(q, v)v + ∂V/∂q (gravity and springs; no damping, no inputs),
/// length `nq`, by the recursive Newton–Euler algorithm in world coordinates.
pub fn inverse_dynamics<D: Scalar>(model: &Model, q: &[D], v: &[D], a: &[D]) -> Vec<D> {
    check_len(model, q.len(), "q");
    check_len(model, v.len(), "v");
    check_len(model, a.len(), "a");
    let n = model.frames.len();
    let zero = [D::from(0.0); 3];
    let mut poses: Vec<Pose<D>> = Vec::with_capacity(n);
    let mut twists: Vec<Twist<D>> = Vec::with_capacity(n);
    // World angular acceleration and origin acceleration of each frame.
    let mut accels: Vec<(Vec3<D>, Vec3<D>)> = Vec::with_capacity(n);
    let mut force = vec![zero; n];
    let mut moment = vec![zero; n];
    let gravity = [
        D::from(model.gravity[0]),
        D::from(model.gravity[1]),
        D::from(model.gravity[2]),
    ];
    for (i, frame) in model.frames.iter().enumerate() {
        let (parent_pose, parent_twist, (parent_alpha, parent_acc)) = match frame.parent {
            Some(p) => (poses[p], twists[p], accels[p]),
            None => (
                Pose::world(),
                Twist {
                    angular: zero,
                    linear: zero,
                },
                (zero, zero),
            ),
        };
        let pose = child_pose(frame, &parent_pose, q);
        let twist = child_twist(frame, &pose, parent_pose.origin, &parent_twist, v);
        let lever = sub(pose.origin, parent_pose.origin);
        let w = parent_twist.angular;
        let mut alpha = parent_alpha;
        let mut acc = add(
            parent_acc,
            add(cross(parent_alpha, lever), cross(w, cross(w, lever))),
        );
        match frame.motion {
            Motion::Fixed => {}
            Motion::Revolute => {
                let rate = scale(frame.joint_rate(v), pose.axis);
                alpha = add(
                    alpha,
                    add(scale(frame.joint_rate(a), pose.axis), cross(w, rate)),
                );
            }
            Motion::Prismatic => {
                let rate = scale(frame.joint_rate(v), pose.axis);
                let slide = add(
                    scale(frame.joint_rate(a), pose.axis),
                    scale(D::from(2.0), cross(w, rate)),
                );
                acc = add(acc, slide);
            }
        }
        if frame.mass > 0.0 {
            let omega = twist.angular;
            let lever_com = mat_vec_const(&pose.rotation, &frame.com);
            let acc_com = add(
                acc,
                add(
                    cross(alpha, lever_com),
                    cross(omega, cross(omega, lever_com)),
                ),
            );
            let f = scale(D::from(frame.mass), sub(acc_com, gravity));
            let h = world_inertia_times(frame, &pose, omega);
            let n_com = add(world_inertia_times(frame, &pose, alpha), cross(omega, h));
            force[i] = f;
            moment[i] = add(cross(com_position(frame, &pose), f), n_com);
        }
        poses.push(pose);
        twists.push(twist);
        accels.push((alpha, acc));
    }
    let mut out = project_wrenches(model, &poses, force, moment);
    for spring in &model.springs {
        out[spring.coordinate] += (q[spring.coordinate] - spring.rest) * spring.stiffness;
    }
    out
}
