//! What acts on the joint coordinates, from the Drake extensions and `<transmission>`s:
//! springs, loop closures and actuators.

use std::collections::HashMap;

use super::extensions::{Extensions, bad};
use super::parts::{NameIndex, rpy};
use crate::model::actuation::Actuator;
use crate::model::spatial::{normalized, perpendicular_pair};
use crate::model::{LinkId, LoopClosure, ModelError, Spring, SpringKind};

/// Which coordinate a joint named by an extension moves.
pub(super) struct JointCoordinates<'a> {
    pub(super) robot: &'a urdf_rs::Robot,
    pub(super) joint_of: &'a NameIndex<'a>,
    pub(super) joint_coordinate: &'a [Option<usize>],
}

impl JointCoordinates<'_> {
    /// The coordinate of `joint`, or why it has none: not defined, fixed, or a mimic.
    fn coordinate(&self, joint: &str) -> Result<usize, String> {
        let j = self
            .joint_of
            .get(joint)
            .copied()
            .ok_or_else(|| format!("refers to joint '{joint}', which is not defined"))?;
        self.joint_coordinate[j].ok_or_else(|| {
            let why = match &self.robot.joints[j].mimic {
                Some(m) if self.robot.joints[j].joint_type != urdf_rs::JointType::Fixed => {
                    format!(
                        "mimics joint '{}' and has no coordinate of its own",
                        m.joint
                    )
                }
                _ => "is fixed and has no coordinate".to_string(),
            };
            format!("acts on joint '{joint}', which {why}")
        })
    }

    /// The coordinate of `joint`, named by `element` `owner`; an undefined or fixed joint is
    /// an error naming both.
    fn of(&self, element: &'static str, owner: &str, joint: &str) -> Result<usize, ModelError> {
        self.coordinate(joint)
            .map_err(|problem| bad(element, owner, problem))
    }
}

pub(super) fn springs(
    robot: &urdf_rs::Robot,
    ext: &Extensions,
    joints: &JointCoordinates,
) -> Result<Vec<Spring>, ModelError> {
    let mut springs = Vec::with_capacity(ext.springs.len());
    for raw in &ext.springs {
        let coordinate = joints.of("force_element", &raw.name, &raw.joint)?;
        let prismatic = robot.joints[joints.joint_of[raw.joint.as_str()]].joint_type
            == urdf_rs::JointType::Prismatic;
        if prismatic != (raw.kind == SpringKind::Prismatic) {
            let (spring, joint) = if prismatic {
                ("torsional", "prismatic")
            } else {
                ("prismatic", "revolute")
            };
            return Err(bad(
                "force_element",
                &raw.name,
                format!(
                    "a {spring} spring on the {joint} joint '{}'; use <{}_spring> there",
                    raw.joint,
                    if prismatic { "prismatic" } else { "torsional" }
                ),
            ));
        }
        if !raw.rest.is_finite() {
            return Err(bad(
                "force_element",
                &raw.name,
                format!("rest value {} must be a finite number", raw.rest),
            ));
        }
        if !(raw.stiffness.is_finite() && raw.stiffness >= 0.0) {
            return Err(bad(
                "force_element",
                &raw.name,
                format!("stiffness {} must be finite and ≥ 0", raw.stiffness),
            ));
        }
        springs.push(Spring {
            name: raw.name.clone(),
            kind: raw.kind,
            coordinate,
            stiffness: raw.stiffness,
            rest: raw.rest,
        });
    }
    Ok(springs)
}

pub(super) fn loop_closures(
    ext: &Extensions,
    link_names: &[String],
) -> Result<Vec<LoopClosure>, ModelError> {
    // Links by name, looked up once per loop joint (linear in loops and links).
    let mut ids: HashMap<&str, usize> = HashMap::with_capacity(link_names.len());
    for (i, n) in link_names.iter().enumerate() {
        ids.entry(n.as_str()).or_insert(i);
    }
    let link_id = |name: &str| ids.get(name).copied().map(LinkId);
    let mut loop_closures = Vec::with_capacity(ext.loops.len());
    for raw in &ext.loops {
        let find = |name: &str| {
            link_id(name).ok_or_else(|| {
                bad(
                    "loop_joint",
                    &raw.name,
                    format!("refers to link '{name}', which is not defined"),
                )
            })
        };
        if raw.link1 == raw.link2 {
            return Err(bad(
                "loop_joint",
                &raw.name,
                format!(
                    "joins link '{}' to itself, which closes no loop; name two links",
                    raw.link1
                ),
            ));
        }
        if !(raw.xyz1.iter().chain(&raw.xyz2).chain(&raw.rpy2)).all(|v| v.is_finite()) {
            return Err(bad(
                "loop_joint",
                &raw.name,
                "its link frames' xyz and rpy must hold finite numbers".to_string(),
            ));
        }
        let axis = normalized(raw.axis).ok_or(ModelError::BadAxis {
            joint: raw.name.clone(),
            axis: raw.axis,
        })?;
        loop_closures.push(LoopClosure {
            name: raw.name.clone(),
            link1: find(&raw.link1)?,
            point1: raw.xyz1,
            link2: find(&raw.link2)?,
            point2: raw.xyz2,
            rotation2: rpy(&raw.rpy2),
            axis,
            directions: perpendicular_pair(axis),
        });
    }
    Ok(loop_closures)
}

/// The joints that can take an input: every movable joint in coordinate order, with its
/// effort limit (∞ without `<limit>`) and its `<transmission>`, if one drives it.
pub(super) fn actuators(
    robot: &urdf_rs::Robot,
    ext: &Extensions,
    joints: &JointCoordinates,
    warnings: &mut Vec<String>,
) -> Result<Vec<Actuator>, ModelError> {
    let mut transmission_of: HashMap<usize, usize> = HashMap::new();
    for (t, raw) in ext.transmissions.iter().enumerate() {
        let (name, joint) = (&raw.name, &raw.joint);
        // A transmission on a joint that cannot take an input (one of another model, a
        // fixed joint, a mimic) is ignored, as ROS's parsers and Pinocchio ignore it.
        let coordinate = match joints.coordinate(joint) {
            Ok(c) => c,
            Err(problem) => {
                warnings.push(format!(
                    "line {}: transmission '{name}' {problem}; ignored (no input)",
                    raw.line
                ));
                continue;
            }
        };
        if raw.reduction != 1.0 {
            warnings.push(format!(
                "transmission '{name}': mechanicalReduction {} ignored (vito uses 1)",
                raw.reduction
            ));
        }
        let j = joints.joint_of[joint.as_str()];
        let has_limit = ext.limit_presence.get(joint).is_some_and(|p| p.0);
        let effort = if has_limit {
            robot.joints[j].limit.effort
        } else {
            f64::INFINITY
        };
        if effort.is_nan() || effort < 0.0 {
            return Err(bad(
                "joint",
                joint,
                format!(
                    "<limit effort=\"{effort}\"> on an actuated joint must be ≥ 0 (leave it \
                     out, or write inf, for no limit)"
                ),
            ));
        }
        transmission_of.entry(coordinate).or_insert(t);
    }
    let mut actuators: Vec<Actuator> = robot
        .joints
        .iter()
        .enumerate()
        .filter_map(|(j, joint)| {
            let coordinate = joints.joint_coordinate[j]?;
            let has_limit = ext.limit_presence.get(&joint.name).is_some_and(|p| p.0);
            let effort = if has_limit {
                joint.limit.effort
            } else {
                f64::INFINITY
            };
            // Transmission joints were checked above; any other joint with a meaningless
            // effort limit is left out of the joints an `actuated` rule may pick.
            if effort.is_nan() || effort < 0.0 {
                warnings.push(format!(
                    "joint '{}': <limit effort=\"{effort}\"> is not ≥ 0, so it cannot be actuated",
                    joint.name
                ));
                return None;
            }
            Some(Actuator {
                joint: joint.name.clone(),
                coordinate,
                effort,
                transmission: transmission_of.get(&coordinate).copied(),
            })
        })
        .collect();
    actuators.sort_by_key(|a| a.coordinate);
    Ok(actuators)
}
