//! Kinetic and potential energy, mass matrix and generalised momentum.

use nalgebra::DMatrix;

use super::Model;
use super::kinematics::{Pose, Twist, check_len, frame_poses, frame_twists};
use super::spatial::{
    Vec3, add, const_mat_vec, cross, dot, mat_t_vec, mat_vec, mat_vec_const, scale, sub,
};
use super::tree::{Frame, Motion};
use crate::autodiff::Scalar;

/// World position of a frame's centre of mass.
pub(crate) fn com_position<D: Scalar>(frame: &Frame, pose: &Pose<D>) -> Vec3<D> {
    add(pose.origin, mat_vec_const(&pose.rotation, &frame.com))
}

/// World velocity of a frame's centre of mass.
fn com_velocity<D: Scalar>(frame: &Frame, pose: &Pose<D>, twist: &Twist<D>) -> Vec3<D> {
    let lever = mat_vec_const(&pose.rotation, &frame.com);
    add(twist.linear, cross(twist.angular, lever))
}

/// World inertia (about the centre of mass) times a world vector: R·I_c·Rᵀ·w.
pub(crate) fn world_inertia_times<D: Scalar>(frame: &Frame, pose: &Pose<D>, w: Vec3<D>) -> Vec3<D> {
    let body = mat_t_vec(&pose.rotation, w);
    mat_vec(&pose.rotation, const_mat_vec(&frame.inertia, body))
}

/// Kinetic energy T(q, q̇) = Σ ½ m |ṗ_com|² + ½ ω_bᵀ I_c ω_b, by a recursion over the tree
/// (body velocities from parent to child; M is never assembled). Slices of length `nq`.
pub fn kinetic_energy<D: Scalar>(model: &Model, q: &[D], qdot: &[D]) -> D {
    check_len(model, q.len(), "q");
    check_len(model, qdot.len(), "qdot");
    let (poses, twists) = frame_twists(model, q, qdot);
    let mut twice_energy = D::from(0.0);
    for ((frame, pose), twist) in model.frames.iter().zip(&poses).zip(&twists) {
        if frame.mass == 0.0 {
            continue;
        }
        let v = com_velocity(frame, pose, twist);
        let omega_body = mat_t_vec(&pose.rotation, twist.angular);
        twice_energy +=
            dot(v, v) * frame.mass + dot(omega_body, const_mat_vec(&frame.inertia, omega_body));
    }
    twice_energy * 0.5
}

/// Potential energy V(q) = −Σ m gravity·p_com + Σ ½ k (q − rest)² (`q` of length `nq`).
pub fn potential_energy<D: Scalar>(model: &Model, q: &[D]) -> D {
    check_len(model, q.len(), "q");
    let poses = frame_poses(model, q);
    let g = model.gravity;
    let mut energy = D::from(0.0);
    for (frame, pose) in model.frames.iter().zip(&poses) {
        if frame.mass == 0.0 {
            continue;
        }
        let c = com_position(frame, pose);
        energy -= (c[0] * g[0] + c[1] * g[1] + c[2] * g[2]) * frame.mass;
    }
    energy + spring_energy(model, q)
}

/// Generalised gravity g(q) = ∂V_g/∂q (length `nq`), V_g = −Σ m gravity·p_com: the gradient of
/// [`potential_energy`] without its springs' share, the joint torques and base forces that
/// hold the robot still against gravity (Pinocchio's `computeGeneralizedGravity`).
pub fn generalized_gravity<D: Scalar>(model: &Model, q: &[D]) -> Vec<D> {
    check_len(model, q.len(), "q");
    let mut dq = vec![D::from(0.0); model.nq()];
    super::potential_energy_gradient(model, q, &mut dq);
    for spring in &model.springs {
        dq[spring.coordinate] -= (q[spring.coordinate] - spring.rest) * spring.stiffness;
    }
    dq
}

/// Σ ½ k (q − rest)².
pub(crate) fn spring_energy<D: Scalar>(model: &Model, q: &[D]) -> D {
    let mut energy = D::from(0.0);
    for spring in &model.springs {
        let stretch = q[spring.coordinate] - spring.rest;
        energy += stretch * stretch * (0.5 * spring.stiffness);
    }
    energy
}

/// Projects per-frame wrenches onto the joint coordinates: `force[i]` and `moment[i]` (about
/// the world origin) act on frame i; returns Jᵀ·wrench (length `nq`), accumulating subtree
/// sums from the leaves to the root.
pub(crate) fn project_wrenches<D: Scalar>(
    model: &Model,
    poses: &[Pose<D>],
    mut force: Vec<Vec3<D>>,
    mut moment: Vec<Vec3<D>>,
) -> Vec<D> {
    let mut out = vec![D::from(0.0); model.nq()];
    for i in (0..model.frames.len()).rev() {
        let frame = &model.frames[i];
        let pose = &poses[i];
        match frame.motion {
            Motion::Fixed => {}
            Motion::Revolute => {
                // Moment about the joint axis line through the frame origin.
                let about_joint = sub(moment[i], cross(pose.origin, force[i]));
                out[frame.coordinate] += frame.to_coordinate(dot(pose.axis, about_joint));
            }
            Motion::Prismatic => {
                out[frame.coordinate] += frame.to_coordinate(dot(pose.axis, force[i]))
            }
        }
        if let Some(p) = frame.parent {
            force[p] = add(force[p], force[i]);
            moment[p] = add(moment[p], moment[i]);
        }
    }
    out
}

/// Generalised momentum M(q)·v (length `nq`), without assembling M: the Jacobian transpose
/// of each link's linear and angular momentum.
pub fn generalized_momentum<D: Scalar>(model: &Model, q: &[D], v: &[D]) -> Vec<D> {
    check_len(model, q.len(), "q");
    check_len(model, v.len(), "v");
    let (poses, twists) = frame_twists(model, q, v);
    let n = model.frames.len();
    let mut linear = vec![[D::from(0.0); 3]; n];
    let mut angular = vec![[D::from(0.0); 3]; n];
    for i in 0..n {
        let frame = &model.frames[i];
        if frame.mass == 0.0 {
            continue;
        }
        let (pose, twist) = (&poses[i], &twists[i]);
        let p = scale(D::from(frame.mass), com_velocity(frame, pose, twist));
        let c = com_position(frame, pose);
        linear[i] = p;
        angular[i] = add(cross(c, p), world_inertia_times(frame, pose, twist.angular));
    }
    project_wrenches(model, &poses, linear, angular)
}

/// The mass matrix M(q) (`nq × nq`, symmetric), from [`mass_matrix_entries`].
pub fn mass_matrix(model: &Model, q: &[f64]) -> DMatrix<f64> {
    let n = model.nq();
    let mut entries = Vec::new();
    mass_matrix_entries(model, q, &mut entries);
    DMatrix::from_row_slice(n, n, &entries)
}

/// The mass matrix M(q) = ∂²T/∂q̇² into `out` (`nq × nq`, row-major, exactly symmetric;
/// resized and overwritten): Σ over bodies of m·J_vᵀJ_v + J_ωᵀ·(R I_c Rᵀ)·J_ω, with J_v and
/// J_ω the Jacobians of the body's centre-of-mass velocity and angular velocity (the
/// columns of its moving ancestors, times the mimic multiplier). Generic over the scalar so
/// that its derivative along q comes from duals (the midpoint segment's qa–qa block needs
/// M and its directional derivative).
pub fn mass_matrix_entries<D: Scalar>(model: &Model, q: &[D], out: &mut Vec<D>) {
    check_len(model, q.len(), "q");
    let n = model.nq();
    out.clear();
    out.resize(n * n, D::from(0.0));
    let poses = frame_poses(model, q);
    // The moving ancestors of the current body: (coordinate, J_v column, J_ω column).
    let mut columns: Vec<(usize, Vec3<D>, Vec3<D>)> = Vec::new();
    let zero = [D::from(0.0); 3];
    for (i, frame) in model.frames.iter().enumerate() {
        if frame.mass == 0.0 {
            continue;
        }
        let c = com_position(frame, &poses[i]);
        columns.clear();
        let mut k = Some(i);
        while let Some(a) = k {
            let (ancestor, pose) = (&model.frames[a], &poses[a]);
            let rate = |v: Vec3<D>| scale(ancestor.to_coordinate(D::from(1.0)), v);
            match ancestor.motion {
                Motion::Fixed => {}
                Motion::Revolute => columns.push((
                    ancestor.coordinate,
                    rate(cross(pose.axis, sub(c, pose.origin))),
                    rate(pose.axis),
                )),
                Motion::Prismatic => columns.push((ancestor.coordinate, rate(pose.axis), zero)),
            }
            k = ancestor.parent;
        }
        for (a, &(ca, va, wa)) in columns.iter().enumerate() {
            let inertia_wa = world_inertia_times(frame, &poses[i], wa);
            for (b, &(cb, vb, wb)) in columns[..=a].iter().enumerate() {
                let term = dot(va, vb) * frame.mass + dot(wb, inertia_wa);
                out[ca * n + cb] += term;
                // Each unordered pair once: its mirror gets the same number.
                if b != a {
                    out[cb * n + ca] += term;
                }
            }
        }
    }
}
