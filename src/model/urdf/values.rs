//! The numbers and references of a parsed URDF that vito cannot use, refused by element and
//! name before the model is built: non-finite origins (joints, collisions, inertials), NaN
//! or crossed joint limits, negative damping, two transmissions on one joint.

use super::extensions::{Extensions, bad};
use crate::model::ModelError;

/// A joint limit of this magnitude or more is no limit: Ipopt's infinity
/// (`nlp_upper_bound_inf`), which a portable URDF writes (e.g. `1e20`) where `inf` would do,
/// since urdfdom, ROS's and Pinocchio's reader, refuses `inf`.
pub(super) const NO_LIMIT: f64 = 1e19;

/// Reads every `<limit>` value of magnitude [`NO_LIMIT`] or more as infinite (lower
/// −∞; upper, effort and velocity +∞), so a file that writes `1e20` plans exactly as one
/// that writes `inf`.
pub(super) fn open_limits(robot: &mut urdf_rs::Robot) {
    for joint in &mut robot.joints {
        let limit = &mut joint.limit;
        if limit.lower <= -NO_LIMIT {
            limit.lower = f64::NEG_INFINITY;
        }
        for value in [&mut limit.upper, &mut limit.effort, &mut limit.velocity] {
            if *value >= NO_LIMIT {
                *value = f64::INFINITY;
            }
        }
    }
}

/// Whether every entry is a finite number.
fn finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

/// `<origin>` of `element` `name` must have finite `xyz` and `rpy`.
fn origin(element: &'static str, name: &str, pose: &urdf_rs::Pose) -> Result<(), ModelError> {
    if finite(&pose.xyz[..]) && finite(&pose.rpy[..]) {
        return Ok(());
    }
    Err(bad(
        element,
        name,
        format!(
            "<origin xyz=\"{:?}\" rpy=\"{:?}\"> must hold finite numbers",
            *pose.xyz, *pose.rpy
        ),
    ))
}

pub(super) fn check_values(robot: &urdf_rs::Robot, ext: &Extensions) -> Result<(), ModelError> {
    for link in &robot.links {
        origin("link", &link.name, &link.inertial.origin)?;
        for collision in &link.collision {
            origin("link", &link.name, &collision.origin)?;
            if let urdf_rs::Geometry::Sphere { radius } = collision.geometry
                && !(radius.is_finite() && radius >= 0.0)
            {
                return Err(bad(
                    "link",
                    &link.name,
                    format!(
                        "<collision> <sphere radius=\"{radius}\">: the radius must be a finite number ≥ 0"
                    ),
                ));
            }
        }
    }
    for joint in &robot.joints {
        origin("joint", &joint.name, &joint.origin)?;
        let (_, has_lower, has_upper) = ext
            .limit_presence
            .get(&joint.name)
            .copied()
            .unwrap_or_default();
        let (lower, upper) = (joint.limit.lower, joint.limit.upper);
        if (has_lower && lower.is_nan()) || (has_upper && upper.is_nan()) {
            return Err(bad(
                "joint",
                &joint.name,
                format!(
                    "<limit lower=\"{lower}\" upper=\"{upper}\">: a limit is not a number; give numbers or leave the attribute out"
                ),
            ));
        }
        if has_lower && has_upper && lower > upper {
            return Err(bad(
                "joint",
                &joint.name,
                format!(
                    "<limit lower=\"{lower}\" upper=\"{upper}\">: lower exceeds upper; swap them"
                ),
            ));
        }
        if let Some(d) = &joint.dynamics
            && !(d.damping.is_finite() && d.damping >= 0.0)
        {
            return Err(bad(
                "joint",
                &joint.name,
                format!(
                    "<dynamics damping=\"{}\"> must be a finite number ≥ 0",
                    d.damping
                ),
            ));
        }
    }
    // The first transmission on each joint, by joint name (a scan of the earlier ones per
    // transmission was quadratic in them).
    let mut first_on: std::collections::HashMap<&str, &str> = std::collections::HashMap::new();
    for t in &ext.transmissions {
        let (name, joint) = (&t.name, &t.joint);
        if let Some(first) = first_on.insert(joint.as_str(), name.as_str())
            && first != name
        {
            return Err(bad(
                "transmission",
                name,
                format!(
                    "acts on joint '{joint}' like transmission '{first}'; give each joint one transmission"
                ),
            ));
        }
    }
    Ok(())
}
