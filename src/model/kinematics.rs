//! Forward kinematics over the tree: world poses, velocities and accelerations of frames,
//! and world positions of points.

use super::spatial::{
    Mat3, Vec3, add, axis_angle, cross, identity, mat_mul, mat_mul_const, mat_vec_const, scale, sub,
};
use super::tree::{Frame, Motion};
use super::{LinkId, Model};
use crate::autodiff::Scalar;

/// World pose of one frame: `rotation` maps frame axes to world axes, `origin` is the frame
/// origin in the world; `axis` is the joint axis in world axes (zero for fixed joints).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Pose<D> {
    pub rotation: Mat3<D>,
    pub origin: Vec3<D>,
    pub axis: Vec3<D>,
}

impl<D: Scalar> Pose<D> {
    /// The world frame.
    pub(crate) fn world() -> Self {
        let z = D::from(0.0);
        Pose {
            rotation: identity(),
            origin: [z; 3],
            axis: [z; 3],
        }
    }
}

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// R ← R·Rot(axis, angle); for a coordinate axis ±e_k only two columns of R change.
fn rotate_about<D: Scalar>(r: &mut Mat3<D>, axis: &[f64; 3], angle: D) {
    let Some(k) = (0..3).find(|&k| axis[k].abs() == 1.0) else {
        *r = mat_mul(r, &axis_angle(axis, angle));
        return;
    };
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    let (s, c) = (angle.sin() * axis[k], angle.cos());
    for row in r.iter_mut() {
        let (ri, rj) = (row[i], row[j]);
        row[i] = ri * c + rj * s;
        row[j] = rj * c - ri * s;
    }
}

/// Pose of `frame` given the pose of its parent (`parent` = world if the frame has none).
pub(crate) fn child_pose<D: Scalar>(frame: &Frame, parent: &Pose<D>, q: &[D]) -> Pose<D> {
    let mut pose = Pose::world();
    child_pose_into(frame, parent, q, &mut pose);
    pose
}

/// [`child_pose`] written into `out` (every field), so that a sweep over stored poses moves
/// no pose.
pub(crate) fn child_pose_into<D: Scalar>(
    frame: &Frame,
    parent: &Pose<D>,
    q: &[D],
    out: &mut Pose<D>,
) {
    // The joint rotation J first, turned in place for a revolute joint.
    if frame.rotation == IDENTITY {
        out.rotation = parent.rotation;
    } else {
        out.rotation = mat_mul_const(&parent.rotation, &frame.rotation);
    }
    let joint_origin = add(
        parent.origin,
        mat_vec_const(&parent.rotation, &frame.translation),
    );
    match frame.motion {
        Motion::Fixed => {
            out.origin = joint_origin;
            out.axis = [D::from(0.0); 3];
        }
        Motion::Revolute => {
            let angle = frame.joint_value(q);
            out.axis = mat_vec_const(&out.rotation, &frame.axis);
            rotate_about(&mut out.rotation, &frame.axis, angle);
            out.origin = joint_origin;
        }
        Motion::Prismatic => {
            let axis = mat_vec_const(&out.rotation, &frame.axis);
            out.origin = add(joint_origin, scale(frame.joint_value(q), axis));
            out.axis = axis;
        }
    }
}

/// World poses of all frames (topological order), `q` of length `nq`.
pub(crate) fn frame_poses<D: Scalar>(model: &Model, q: &[D]) -> Vec<Pose<D>> {
    let mut poses: Vec<Pose<D>> = Vec::with_capacity(model.frames.len());
    for frame in &model.frames {
        let parent = frame.parent.map_or_else(Pose::world, |p| poses[p]);
        poses.push(child_pose(frame, &parent, q));
    }
    poses
}

/// World pose of one frame, composed along its ancestor path only.
pub(crate) fn frame_pose<D: Scalar>(model: &Model, frame: usize, q: &[D]) -> Pose<D> {
    let mut path = Vec::with_capacity(16);
    let mut cursor = Some(frame);
    while let Some(i) = cursor {
        path.push(i);
        cursor = model.frames[i].parent;
    }
    let mut pose = Pose::world();
    for &i in path.iter().rev() {
        pose = child_pose(&model.frames[i], &pose, q);
    }
    pose
}

/// World pose of a link: (rotation R mapping link axes to world axes, row-major; origin).
pub fn link_pose<D: Scalar>(model: &Model, link: LinkId, q: &[D]) -> ([[D; 3]; 3], [D; 3]) {
    check_len(model, q.len(), "q");
    let placement = &model.link_frame[link.0];
    let pose = frame_pose(model, placement.frame, q);
    (
        mat_mul_const(&pose.rotation, &placement.rotation),
        add(
            pose.origin,
            mat_vec_const(&pose.rotation, &placement.translation),
        ),
    )
}

/// The Z-Y-X angles (roll, pitch, yaw) of a rotation R = Rz(yaw)·Ry(pitch)·Rx(roll)
/// (row-major): roll = atan2(R₃₂, R₃₃), pitch = atan2(−R₃₁, √(R₃₂² + R₃₃²)),
/// yaw = atan2(R₂₁, R₁₁); pitch in [−π/2, π/2].
pub fn roll_pitch_yaw<D: Scalar>(r: &[[D; 3]; 3]) -> [D; 3] {
    [
        r[2][1].atan2(r[2][2]),
        (-r[2][0]).atan2((r[2][1] * r[2][1] + r[2][2] * r[2][2]).sqrt()),
        r[1][0].atan2(r[0][0]),
    ]
}

/// World angular velocity of `link` per unit rate of the coordinates: one (coordinate,
/// ∂ω/∂q̇_coordinate) pair per revolute joint on the link's path (its world axis, times the
/// multiplier of a mimic joint, whose coordinate is its leader's), root to leaf; a coordinate
/// can appear more than once (add the pairs). ω = Σ pairs·q̇[coordinate]: the rotation of
/// the link at q moving with q̇ (prismatic and fixed joints do not turn it).
pub fn link_angular_jacobian<D: Scalar>(
    model: &Model,
    link: LinkId,
    q: &[D],
) -> Vec<(usize, [D; 3])> {
    check_len(model, q.len(), "q");
    let mut path = Vec::with_capacity(16);
    let mut cursor = Some(model.link_frame[link.0].frame);
    while let Some(i) = cursor {
        path.push(i);
        cursor = model.frames[i].parent;
    }
    let mut pose = Pose::world();
    let mut columns = Vec::with_capacity(path.len());
    for &i in path.iter().rev() {
        let frame = &model.frames[i];
        pose = child_pose(frame, &pose, q);
        if frame.motion == Motion::Revolute {
            let rate = frame.mimic.map_or(1.0, |m| m.multiplier);
            columns.push((frame.coordinate, scale(D::from(rate), pose.axis)));
        }
    }
    columns
}

/// World position of `point` (given in the `link` frame) at configuration `q` (length `nq`).
pub fn point_position<D: Scalar>(model: &Model, link: LinkId, point: &[f64; 3], q: &[D]) -> [D; 3] {
    check_len(model, q.len(), "q");
    let placement = &model.link_frame[link.0];
    let pose = frame_pose(model, placement.frame, q);
    add(
        pose.origin,
        mat_vec_const(&pose.rotation, &placement.point_in_frame(point)),
    )
}

/// World angular velocity ω and origin velocity v of each frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Twist<D> {
    pub angular: Vec3<D>,
    pub linear: Vec3<D>,
}

/// Velocity of `frame` from its parent's (ω_p, v_p) and parent origin `parent_origin`.
pub(crate) fn child_twist<D: Scalar>(
    frame: &Frame,
    pose: &Pose<D>,
    parent_origin: Vec3<D>,
    parent: &Twist<D>,
    qdot: &[D],
) -> Twist<D> {
    let lever = sub(pose.origin, parent_origin);
    let mut angular = parent.angular;
    let mut linear = add(parent.linear, cross(parent.angular, lever));
    match frame.motion {
        Motion::Fixed => {}
        Motion::Revolute => angular = add(angular, scale(frame.joint_rate(qdot), pose.axis)),
        Motion::Prismatic => linear = add(linear, scale(frame.joint_rate(qdot), pose.axis)),
    }
    Twist { angular, linear }
}

/// Poses and twists of all frames.
pub(crate) fn frame_twists<D: Scalar>(
    model: &Model,
    q: &[D],
    qdot: &[D],
) -> (Vec<Pose<D>>, Vec<Twist<D>>) {
    let n = model.frames.len();
    let mut poses: Vec<Pose<D>> = Vec::with_capacity(n);
    let mut twists: Vec<Twist<D>> = Vec::with_capacity(n);
    let rest = Twist {
        angular: [D::from(0.0); 3],
        linear: [D::from(0.0); 3],
    };
    for frame in &model.frames {
        let (parent_pose, parent_twist) = match frame.parent {
            Some(p) => (poses[p], twists[p]),
            None => (Pose::world(), rest),
        };
        let pose = child_pose(frame, &parent_pose, q);
        let twist = child_twist(frame, &pose, parent_pose.origin, &parent_twist, qdot);
        poses.push(pose);
        twists.push(twist);
    }
    (poses, twists)
}

/// Panics with a clear message when a caller passes a slice of the wrong length: a
/// programming error of the caller, never user input.
pub(crate) fn check_len(model: &Model, len: usize, what: &str) {
    assert_eq!(
        len,
        model.nq(),
        "{what} has length {len}, but the model has nq = {}",
        model.nq()
    );
}
