//! Reverse-mode (adjoint) gradients of the energies of [`super::energy`]; the midpoint Ld's
//! fast derivatives are built on them in `crate::discrete::midpoint_derivatives`.
//!
//! One forward sweep over the tree (parents first) computes the poses and twists exactly as
//! [`kinetic_energy`](super::kinetic_energy) does; one reverse sweep (children first) carries
//! the adjoints R̄, ō (of each frame's world rotation and origin), ω̄, v̄ (of its twist) back to
//! the coordinates. The sweep is generic over [`Scalar`], so forward duals run through it.

use super::Model;
use super::energy::{com_position, spring_energy};
use super::kinematics::{Pose, Twist, check_len, child_pose_into, child_twist};
use super::spatial::{
    Mat3, Vec3, add, axis_angle, const_mat_vec, cross, dot, mat_t_vec, mat_vec, mat_vec_const,
    scale, sub,
};
use super::tree::{Frame, Motion};
use crate::autodiff::Scalar;

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// Kinetic energy T(q, q̇) and its gradient by one forward and one reverse sweep.
///
/// `q`, `qdot`, `dq` (∂T/∂q) and `dqdot` (∂T/∂q̇) have length `nq`; `dq` and `dqdot` are
/// overwritten. Returns T (the same number as [`kinetic_energy`](super::kinetic_energy)).
pub fn kinetic_energy_gradient<D: Scalar>(
    model: &Model,
    q: &[D],
    qdot: &[D],
    dq: &mut [D],
    dqdot: &mut [D],
) -> D {
    check_len(model, qdot.len(), "qdot");
    check_len(model, dqdot.len(), "dqdot");
    energy_sweep(
        model,
        q,
        Some(qdot),
        0.0,
        dq,
        dqdot,
        &mut SweepBuffers::default(),
    )
    .0
}

/// Potential energy V(q) (gravity and springs) and its gradient ∂V/∂q.
///
/// `q` and `dq` have length `nq`; `dq` is overwritten. Returns V (the same number as
/// [`potential_energy`](super::potential_energy)).
pub fn potential_energy_gradient<D: Scalar>(model: &Model, q: &[D], dq: &mut [D]) -> D {
    energy_sweep(
        model,
        q,
        None,
        1.0,
        dq,
        &mut [],
        &mut SweepBuffers::default(),
    )
    .1
}

/// Lagrangian L(q, v) = T − V and its gradient, in one forward and one reverse sweep.
///
/// `q`, `v`, `dq` (∂L/∂q) and `dv` (∂L/∂v) have length `nq`; `dq` and `dv` are overwritten.
/// `buffers` holds the sweep's per-frame storage: a caller evaluating many passes (the 2n+1
/// dual passes of a DEL segment's derivatives) keeps one, so that no pass allocates.
/// Returns L in J (model units).
pub fn lagrangian_gradient<D: Scalar>(
    model: &Model,
    q: &[D],
    v: &[D],
    dq: &mut [D],
    dv: &mut [D],
    buffers: &mut SweepBuffers<D>,
) -> D {
    check_len(model, v.len(), "v");
    check_len(model, dv.len(), "dv");
    let (kinetic, potential) = energy_sweep(model, q, Some(v), -1.0, dq, dv, buffers);
    kinetic - potential
}

/// The per-frame poses, twists and adjoints of one energy sweep, kept between sweeps
/// (contents are overwritten by each sweep; only the allocations are reused).
#[derive(Debug)]
pub struct SweepBuffers<D> {
    poses: Vec<Pose<D>>,
    twists: Vec<Twist<D>>,
    adjoints: Vec<FrameAdjoint<D>>,
}

impl<D> Default for SweepBuffers<D> {
    fn default() -> Self {
        SweepBuffers {
            poses: Vec::new(),
            twists: Vec::new(),
            adjoints: Vec::new(),
        }
    }
}

/// Adjoints of one frame's forward quantities: ∂E/∂(world rotation, world origin, angular
/// and linear velocity) for the energy E being differentiated.
#[derive(Debug, Clone, Copy)]
struct FrameAdjoint<D> {
    rotation: Mat3<D>,
    origin: Vec3<D>,
    angular: Vec3<D>,
    linear: Vec3<D>,
}

impl<D: Scalar> FrameAdjoint<D> {
    fn zero() -> Self {
        let z = D::from(0.0);
        FrameAdjoint {
            rotation: [[z; 3]; 3],
            origin: [z; 3],
            angular: [z; 3],
            linear: [z; 3],
        }
    }
}

/// R̄ += a·bᵀ with a constant b.
fn add_outer_const<D: Scalar>(m: &mut Mat3<D>, a: Vec3<D>, b: &[f64; 3]) {
    for (row, &ai) in m.iter_mut().zip(&a) {
        for (entry, &bj) in row.iter_mut().zip(b) {
            *entry += ai * bj;
        }
    }
}

/// R̄ += a·bᵀ.
fn add_outer<D: Scalar>(m: &mut Mat3<D>, a: Vec3<D>, b: Vec3<D>) {
    for (row, &ai) in m.iter_mut().zip(&a) {
        for (entry, &bj) in row.iter_mut().zip(&b) {
            *entry += ai * bj;
        }
    }
}

/// Column k of M.
fn column<D: Scalar>(m: &Mat3<D>, k: usize) -> Vec3<D> {
    [m[0][k], m[1][k], m[2][k]]
}

/// The forward sweep (poses, and twists when `qdot` is given) and the reverse sweep of
/// E = T + `potential_weight`·V, where T counts only when `qdot` is given and V only when
/// `potential_weight` ≠ 0. Writes ∂E/∂q into `dq` and ∂E/∂q̇ into `dqdot` (ignored, may be
/// empty, without `qdot`). Returns (T, V), each 0 when not counted.
/// Parents precede children in `model.frames`, so a frame's parent is read in place (no copy
/// of the parent's pose, twist or adjoint); the per-frame storage is `buffers`'.
fn energy_sweep<D: Scalar>(
    model: &Model,
    q: &[D],
    qdot: Option<&[D]>,
    potential_weight: f64,
    dq: &mut [D],
    dqdot: &mut [D],
    buffers: &mut SweepBuffers<D>,
) -> (D, D) {
    check_len(model, q.len(), "q");
    check_len(model, dq.len(), "dq");
    let zero = D::from(0.0);
    let n = model.frames.len();
    let SweepBuffers {
        poses,
        twists,
        adjoints,
    } = buffers;
    let world = Pose::world();
    // Each pose is written in place (every field), so the storage is kept as it is.
    poses.resize(n, world);
    twists.clear();
    twists.reserve(n);
    let rest = Twist {
        angular: [zero; 3],
        linear: [zero; 3],
    };
    for (i, frame) in model.frames.iter().enumerate() {
        let (done, todo) = poses.split_at_mut(i);
        let parent_pose = frame.parent.map_or(&world, |p| &done[p]);
        let pose = &mut todo[0];
        child_pose_into(frame, parent_pose, q, pose);
        if let Some(qdot) = qdot {
            let parent_twist = frame.parent.map_or(&rest, |p| &twists[p]);
            let twist = child_twist(frame, pose, parent_pose.origin, parent_twist, qdot);
            twists.push(twist);
        }
    }

    dq.fill(zero);
    if qdot.is_some() {
        dqdot.fill(zero);
    }
    adjoints.clear();
    adjoints.resize(n, FrameAdjoint::<D>::zero());
    let mut twice_kinetic = zero;
    let mut potential = zero;
    let g = model.gravity;
    // The adjoint of a moving joint's rotation, reused from frame to frame.
    let mut joint_bar = [[zero; 3]; 3];
    for i in (0..n).rev() {
        let frame = &model.frames[i];
        let pose = &poses[i];
        let (earlier, rest_of) = adjoints.split_at_mut(i);
        let bar = &mut rest_of[0];
        if frame.mass > 0.0 {
            if qdot.is_some() {
                twice_kinetic += kinetic_adjoint(frame, pose, &twists[i], bar);
            }
            if potential_weight != 0.0 {
                // V_i = −m g·(o + R c): ō = −w m g, R̄ = −w m g cᵀ.
                potential -= dot(com_position(frame, pose), g.map(D::from)) * frame.mass;
                let force = g.map(|gk| D::from(-potential_weight * frame.mass * gk));
                bar.origin = add(bar.origin, force);
                add_outer_const(&mut bar.rotation, force, &frame.com);
            }
        }
        let mut axis_bar = [zero; 3];
        if let Some(qdot) = qdot {
            twist_adjoint(model, i, poses, qdot, bar, &mut axis_bar, dqdot);
            if let Some(p) = frame.parent {
                earlier[p].angular = add(earlier[p].angular, bar.angular);
                earlier[p].linear = add(earlier[p].linear, bar.linear);
                // v_i = v_p + ω_p × (o_i − o_p): the lever's adjoint v̄ × ω_p.
                let lever = sub(pose.origin, poses[p].origin);
                earlier[p].angular = add(earlier[p].angular, cross(lever, bar.linear));
                let lever_bar = cross(bar.linear, twists[p].angular);
                bar.origin = add(bar.origin, lever_bar);
                earlier[p].origin = sub(earlier[p].origin, lever_bar);
            }
        }
        let joint_rotation_bar = pose_adjoint(frame, pose, q, bar, axis_bar, dq, &mut joint_bar);
        if let Some(p) = frame.parent {
            let parent = &mut earlier[p];
            // J = R_p·C and o_joint = o_p + R_p·t.
            if frame.rotation == IDENTITY {
                for (row, bar_row) in parent.rotation.iter_mut().zip(joint_rotation_bar) {
                    for (entry, &b) in row.iter_mut().zip(bar_row) {
                        *entry += b;
                    }
                }
            } else {
                for (row, bar_row) in parent.rotation.iter_mut().zip(joint_rotation_bar) {
                    // (J̄·Cᵀ)_row = C·J̄_row.
                    let contribution = const_mat_vec(&frame.rotation, *bar_row);
                    for (entry, c) in row.iter_mut().zip(contribution) {
                        *entry += c;
                    }
                }
            }
            add_outer_const(&mut parent.rotation, bar.origin, &frame.translation);
            parent.origin = add(parent.origin, bar.origin);
        }
    }
    if potential_weight != 0.0 {
        potential += spring_energy(model, q);
        for spring in &model.springs {
            let stretch = q[spring.coordinate] - spring.rest;
            dq[spring.coordinate] += stretch * (potential_weight * spring.stiffness);
        }
    }
    (twice_kinetic * 0.5, potential)
}

/// Adds the adjoint of T_i = ½ m |v + ω × R c|² + ½ (Rᵀω)ᵀ I (Rᵀω) into `bar`; returns 2 T_i.
fn kinetic_adjoint<D: Scalar>(
    frame: &Frame,
    pose: &Pose<D>,
    twist: &Twist<D>,
    bar: &mut FrameAdjoint<D>,
) -> D {
    let lever = mat_vec_const(&pose.rotation, &frame.com);
    let v = add(twist.linear, cross(twist.angular, lever));
    let momentum = scale(D::from(frame.mass), v);
    bar.linear = add(bar.linear, momentum);
    bar.angular = add(bar.angular, cross(lever, momentum));
    add_outer_const(
        &mut bar.rotation,
        cross(momentum, twist.angular),
        &frame.com,
    );
    let omega_body = mat_t_vec(&pose.rotation, twist.angular);
    let spin_body = const_mat_vec(&frame.inertia, omega_body);
    bar.angular = add(bar.angular, mat_vec(&pose.rotation, spin_body));
    add_outer(&mut bar.rotation, twist.angular, spin_body);
    dot(v, momentum) + dot(omega_body, spin_body)
}

/// Reverse of `child_twist` for frame `i`: the joint rate's adjoint into `dqdot`, the world
/// axis's adjoint into `axis_bar`. The parent's share is added by the caller.
fn twist_adjoint<D: Scalar>(
    model: &Model,
    i: usize,
    poses: &[Pose<D>],
    qdot: &[D],
    bar: &mut FrameAdjoint<D>,
    axis_bar: &mut Vec3<D>,
    dqdot: &mut [D],
) {
    let frame = &model.frames[i];
    let axis = poses[i].axis;
    match frame.motion {
        Motion::Fixed => {}
        Motion::Revolute => {
            dqdot[frame.coordinate] += frame.to_coordinate(dot(axis, bar.angular));
            *axis_bar = add(*axis_bar, scale(frame.joint_rate(qdot), bar.angular));
        }
        Motion::Prismatic => {
            dqdot[frame.coordinate] += frame.to_coordinate(dot(axis, bar.linear));
            *axis_bar = add(*axis_bar, scale(frame.joint_rate(qdot), bar.linear));
        }
    }
}

/// Reverse of `child_pose`: adds the joint coordinate's adjoint into `dq` and returns the
/// adjoint J̄ of the joint rotation J = R_parent·C (the origin's adjoint passes unchanged):
/// R̄ itself for a fixed joint, else written into `joint_bar`.
fn pose_adjoint<'b, D: Scalar>(
    frame: &Frame,
    pose: &Pose<D>,
    q: &[D],
    bar: &'b FrameAdjoint<D>,
    mut axis_bar: Vec3<D>,
    dq: &mut [D],
    joint_bar: &'b mut Mat3<D>,
) -> &'b Mat3<D> {
    let r_bar = &bar.rotation;
    match frame.motion {
        Motion::Fixed => return r_bar,
        Motion::Revolute => {
            // R = J·Rot(axis, q), dR/dq = [a]×·R with a = J·axis the world axis, so
            // q̄ = Σ_k R̄_k·(a × R_k) = a·Σ_k R_k × R̄_k over the columns k.
            let r = &pose.rotation;
            let mut torque = [D::from(0.0); 3];
            for k in 0..3 {
                torque = add(torque, cross(column(r, k), column(r_bar, k)));
            }
            dq[frame.coordinate] += frame.to_coordinate(dot(pose.axis, torque));
            rotation_adjoint(r_bar, &frame.axis, frame.joint_value(q), joint_bar);
        }
        Motion::Prismatic => {
            dq[frame.coordinate] += frame.to_coordinate(dot(pose.axis, bar.origin));
            axis_bar = add(axis_bar, scale(frame.joint_value(q), bar.origin));
            *joint_bar = *r_bar;
        }
    }
    // a = J·axis.
    add_outer_const(joint_bar, axis_bar, &frame.axis);
    joint_bar
}

/// R̄·Rot(axis, angle)ᵀ, the adjoint of J in R = J·Rot(axis, angle), into `out`; for a
/// coordinate axis ±e_k only two columns mix (as in `kinematics::rotate_about`).
fn rotation_adjoint<D: Scalar>(r_bar: &Mat3<D>, axis: &[f64; 3], angle: D, out: &mut Mat3<D>) {
    let Some(k) = (0..3).find(|&k| axis[k].abs() == 1.0) else {
        let rot = axis_angle(axis, angle);
        for (out_row, bar_row) in out.iter_mut().zip(r_bar) {
            // (R̄·Rotᵀ)_row,j = Σ_l R̄_row,l Rot_j,l.
            for (entry, rot_row) in out_row.iter_mut().zip(&rot) {
                *entry = dot(*bar_row, *rot_row);
            }
        }
        return;
    };
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    let (s, c) = (angle.sin() * axis[k], angle.cos());
    for (out_row, bar_row) in out.iter_mut().zip(r_bar) {
        out_row[k] = bar_row[k];
        out_row[i] = bar_row[i] * c - bar_row[j] * s;
        out_row[j] = bar_row[i] * s + bar_row[j] * c;
    }
}
