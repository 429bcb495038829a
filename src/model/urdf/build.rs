//! The checked [`Model`] from a parsed URDF and its Drake extensions: names, the tree's
//! order, coordinates, frames with lumped masses, contact points, springs, loop closures and
//! inputs, each step a function.

use std::collections::{HashMap, HashSet};

use super::bodies::{Findings, bodies, contact_points};
use super::extensions::Extensions;
use super::inertia::{MassMatrixDefect, mass_matrix_defect};
use super::joint_elements::{JointCoordinates, actuators, loop_closures, springs};
use super::parts::{Coordinates, NameIndex, Tree};
use crate::model::actuation::AppliedActuation;
use crate::model::tree::Mimic;
use crate::model::{BaseType, Model, ModelError};

/// Converts a parsed URDF with its extensions into a model with the given base.
pub(super) fn build(
    robot: &urdf_rs::Robot,
    ext: &Extensions,
    base: BaseType,
    origin: &str,
    mut warnings: Vec<String>,
) -> Result<Model, ModelError> {
    if robot.links.is_empty() {
        return Err(ModelError::NoLinks);
    }
    let (link_of, joint_of) = index_names(robot)?;
    let tree = tree_order(robot, &link_of)?;
    // Problems of masses and mimic joints, reported together.
    let mut problems = Vec::new();
    let coordinates = coordinates(robot, ext, base, &joint_of, &mut problems, &mut warnings)?;
    let joints = JointCoordinates {
        robot,
        joint_of: &joint_of,
        joint_coordinate: &coordinates.joint_coordinate,
    };
    let mut findings = Findings {
        problems,
        warnings,
        inertias: Vec::new(),
    };
    let bodies = bodies(
        robot,
        ext,
        base,
        &link_of,
        &tree,
        &coordinates,
        &mut findings,
    )?;
    let Findings {
        problems,
        mut warnings,
        inertias,
    } = findings;
    if !problems.is_empty() {
        return Err(ModelError::Invalid {
            origin: origin.to_string(),
            problems,
        });
    }
    let (contact_points, ignored_collisions) = contact_points(robot, ext, &mut warnings);
    let springs = springs(robot, ext, &joints)?;
    let loop_closures = loop_closures(ext, &bodies.link_names)?;
    let actuators = actuators(robot, ext, &joints, &mut warnings)?;
    let mut model = Model {
        frames: bodies.frames,
        link_frame: bodies.link_frame,
        link_names: bodies.link_names,
        coordinate_names: coordinates.names,
        coordinate_limits: coordinates.limits,
        damping: coordinates.damping,
        input_names: Vec::new(),
        input_coordinates: Vec::new(),
        effort_limits: Vec::new(),
        actuators,
        actuation: AppliedActuation::default(),
        contact_points,
        ignored_collisions,
        springs,
        loop_closures,
        gravity: [0.0, 0.0, -9.81],
        total_mass: bodies.total_mass,
        base,
        name: robot.name.clone(),
        warnings,
        leaf_links: tree
            .leaves
            .iter()
            .map(|&l| robot.links[l].name.clone())
            .collect(),
        geometry: Vec::new(),
    };
    model.actuate_by_default();
    if !inertias.is_empty() {
        // Kept as written, as ROS's parsers and Pinocchio keep them (iCub's point masses,
        // Romeo's hips), unless they make kinetic energy negative.
        match mass_matrix_defect(&model) {
            Some(MassMatrixDefect {
                coordinates,
                negative: Some(eigenvalue),
            }) => {
                return Err(ModelError::Invalid {
                    origin: origin.to_string(),
                    problems: inertias
                        .into_iter()
                        .map(|p| {
                            format!(
                                "{p}{FIX_INERTIA}: the mass matrix has a negative eigenvalue \
                                 ({eigenvalue:e}) along {} at the nominal pose",
                                crate::files::names::list_names(&coordinates, 8)
                            )
                        })
                        .collect(),
                });
            }
            defect => {
                model.warnings.extend(
                    inertias
                        .into_iter()
                        .map(|p| format!("{p}; kept as written")),
                );
                if let Some(MassMatrixDefect { coordinates, .. }) = defect {
                    model.warnings.push(format!(
                        "the mass matrix is singular at the nominal pose along {}: nothing \
                         with inertia moves with them, so a plan may move them at no \
                         cost{FIX_INERTIA}, or make their joints fixed",
                        crate::files::names::list_names(&coordinates, 8)
                    ));
                }
            }
        }
    }
    Ok(model)
}

/// The fix named with an inertia that is not positive definite.
const FIX_INERTIA: &str = "; give the links positive-definite <inertia> values (a body that \
                           turns needs rotational inertia about every axis)";

/// Link and joint indices by name; a name used twice is an error.
fn index_names(robot: &urdf_rs::Robot) -> Result<(NameIndex<'_>, NameIndex<'_>), ModelError> {
    let mut link_of: HashMap<&str, usize> = HashMap::new();
    for (i, link) in robot.links.iter().enumerate() {
        if link_of.insert(link.name.as_str(), i).is_some() {
            return Err(ModelError::DuplicateName {
                kind: "link",
                name: link.name.clone(),
            });
        }
    }
    let mut joint_of: HashMap<&str, usize> = HashMap::new();
    for (j, joint) in robot.joints.iter().enumerate() {
        if joint_of.insert(joint.name.as_str(), j).is_some() {
            return Err(ModelError::DuplicateName {
                kind: "joint",
                name: joint.name.clone(),
            });
        }
    }
    Ok((link_of, joint_of))
}

/// Checks that the joints form one tree of supported joints and orders its links.
fn tree_order(robot: &urdf_rs::Robot, link_of: &NameIndex) -> Result<Tree, ModelError> {
    let mut parent_joint: Vec<Option<usize>> = vec![None; robot.links.len()];
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); robot.links.len()];
    for (j, joint) in robot.joints.iter().enumerate() {
        use urdf_rs::JointType as T;
        if !matches!(
            joint.joint_type,
            T::Fixed | T::Revolute | T::Continuous | T::Prismatic
        ) {
            return Err(ModelError::UnsupportedJointType {
                joint: joint.name.clone(),
                joint_type: format!("{:?}", joint.joint_type).to_lowercase(),
            });
        }
        let lookup = |name: &str, role: &'static str| {
            link_of
                .get(name)
                .copied()
                .ok_or_else(|| ModelError::MissingLink {
                    joint: joint.name.clone(),
                    role,
                    link: name.to_string(),
                })
        };
        let parent = lookup(&joint.parent.link, "parent")?;
        let child = lookup(&joint.child.link, "child")?;
        if let Some(first) = parent_joint[child] {
            return Err(ModelError::MultipleParents {
                link: joint.child.link.clone(),
                first: robot.joints[first].name.clone(),
                second: joint.name.clone(),
            });
        }
        parent_joint[child] = Some(j);
        children[parent].push(child);
    }
    let roots: Vec<usize> = (0..robot.links.len())
        .filter(|&i| parent_joint[i].is_none())
        .collect();
    let root = match roots.as_slice() {
        [] => {
            return Err(ModelError::Cycle {
                link: robot.links[0].name.clone(),
            });
        }
        [r] => *r,
        many => {
            return Err(ModelError::MultipleRoots {
                roots: many.iter().map(|&i| robot.links[i].name.clone()).collect(),
            });
        }
    };
    // Depth-first order from the root: parents before children.
    let mut order = Vec::with_capacity(robot.links.len());
    let mut stack = vec![root];
    while let Some(l) = stack.pop() {
        order.push(l);
        stack.extend(children[l].iter().rev());
    }
    if order.len() < robot.links.len() {
        let visited: HashSet<usize> = order.iter().copied().collect();
        let stray = (0..robot.links.len())
            .find(|i| !visited.contains(i))
            .unwrap_or(0);
        return Err(ModelError::Cycle {
            link: robot.links[stray].name.clone(),
        });
    }
    let leaves = (0..robot.links.len())
        .filter(|&l| children[l].is_empty())
        .collect();
    Ok(Tree {
        parent_joint,
        leaves,
        order,
    })
}

fn coordinates(
    robot: &urdf_rs::Robot,
    ext: &Extensions,
    base: BaseType,
    joint_of: &NameIndex,
    problems: &mut Vec<String>,
    warnings: &mut Vec<String>,
) -> Result<Coordinates, ModelError> {
    let base_names = base.coordinate_names();
    let mut coordinate_names: Vec<String> = base_names.iter().map(|s| s.to_string()).collect();
    let mut coordinate_limits = vec![(f64::NEG_INFINITY, f64::INFINITY); base_names.len()];
    let mut damping = vec![0.0; base_names.len()];
    let mut joint_coordinate: Vec<Option<usize>> = vec![None; robot.joints.len()];
    let moves = |joint: &urdf_rs::Joint| joint.joint_type != urdf_rs::JointType::Fixed;
    for (j, joint) in robot.joints.iter().enumerate() {
        if !moves(joint) || joint.mimic.is_some() {
            continue;
        }
        if base_names.contains(&joint.name.as_str()) {
            return Err(ModelError::NameClash {
                joint: joint.name.clone(),
            });
        }
        joint_coordinate[j] = Some(coordinate_names.len());
        coordinate_names.push(joint.name.clone());
        let (_, has_lower, has_upper) = ext
            .limit_presence
            .get(&joint.name)
            .copied()
            .unwrap_or((false, false, false));
        let continuous_unlimited =
            joint.joint_type == urdf_rs::JointType::Continuous && !has_lower && !has_upper;
        if !continuous_unlimited && (!has_lower || !has_upper) {
            warnings.push(format!(
                "joint '{}': no lower/upper limit given; left unbounded",
                joint.name
            ));
        }
        let lower = if has_lower {
            joint.limit.lower
        } else {
            f64::NEG_INFINITY
        };
        let upper = if has_upper {
            joint.limit.upper
        } else {
            f64::INFINITY
        };
        coordinate_limits.push((lower, upper));
        damping.push(joint.dynamics.as_ref().map_or(0.0, |d| d.damping));
    }
    let mut mimic = vec![None; robot.joints.len()];
    for (j, joint) in robot.joints.iter().enumerate() {
        if !moves(joint) || joint.mimic.is_none() {
            continue;
        }
        let at = ext.at("joint", &joint.name);
        match follow_mimics(robot, j, joint_of, &joint_coordinate) {
            Ok((coordinate, map)) => {
                // Viscous damping d on θ = m·q + o is d·m² on q (the same dissipation).
                if let Some(d) = &joint.dynamics {
                    damping[coordinate] += d.damping * map.multiplier * map.multiplier;
                }
                let presence = ext.limit_presence.get(&joint.name).copied();
                let (_, has_lower, has_upper) = presence.unwrap_or((false, false, false));
                let own = (
                    if has_lower {
                        joint.limit.lower
                    } else {
                        f64::NEG_INFINITY
                    },
                    if has_upper {
                        joint.limit.upper
                    } else {
                        f64::INFINITY
                    },
                );
                let leader = &coordinate_names[coordinate];
                match mimic_limits(own, map, coordinate_limits[coordinate]) {
                    Ok((limits, narrowed)) => {
                        if narrowed {
                            warnings.push(format!(
                                "joint '{}' (mimic of '{leader}'): its <limit> [{}, {}] narrows \
                                 '{leader}' from [{}, {}] to [{}, {}]",
                                joint.name,
                                own.0,
                                own.1,
                                coordinate_limits[coordinate].0,
                                coordinate_limits[coordinate].1,
                                limits.0,
                                limits.1
                            ));
                        }
                        coordinate_limits[coordinate] = limits;
                    }
                    Err(problem) => problems.push(format!(
                        "{at}<joint name=\"{}\"> <limit> (mimic of '{leader}'): {problem}",
                        joint.name
                    )),
                }
                mimic[j] = Some((coordinate, map));
            }
            Err(problem) => problems.push(format!(
                "{at}<joint name=\"{}\"> <mimic>: {problem}",
                joint.name
            )),
        }
    }
    Ok(Coordinates {
        names: coordinate_names,
        limits: coordinate_limits,
        damping,
        joint_coordinate,
        mimic,
    })
}

/// The leader's coordinate limits with a mimic joint's own `<limit>` `own` on θ =
/// multiplier·q + offset applied: q within (own − offset)/multiplier, intersected with
/// `leader`. Returns the limits and whether the mimic's narrowed them; an error when they
/// leave no value (or when a multiplier of 0 holds θ at an offset outside `own`).
fn mimic_limits(
    own: (f64, f64),
    map: Mimic,
    leader: (f64, f64),
) -> Result<((f64, f64), bool), String> {
    let (lower, upper) = own;
    if lower == f64::NEG_INFINITY && upper == f64::INFINITY {
        return Ok((leader, false));
    }
    let (m, o) = (map.multiplier, map.offset);
    if m == 0.0 {
        return if (lower..=upper).contains(&o) {
            Ok((leader, false))
        } else {
            Err(format!(
                "multiplier 0 holds the joint at {o}, outside its limit [{lower}, {upper}]"
            ))
        };
    }
    let (a, b) = ((lower - o) / m, (upper - o) / m);
    let (implied_lower, implied_upper) = if m > 0.0 { (a, b) } else { (b, a) };
    let limits = (leader.0.max(implied_lower), leader.1.min(implied_upper));
    if limits.0 > limits.1 {
        return Err(format!(
            "[{lower}, {upper}] needs the leader's coordinate within [{implied_lower}, \
             {implied_upper}], which its own limits [{}, {}] exclude; make them agree",
            leader.0, leader.1
        ));
    }
    Ok((limits, limits != leader))
}

/// The coordinate a mimic joint follows and θ = multiplier·q + offset, composed along a
/// chain of mimics (a mimic of a mimic).
fn follow_mimics(
    robot: &urdf_rs::Robot,
    joint: usize,
    joint_of: &NameIndex,
    joint_coordinate: &[Option<usize>],
) -> Result<(usize, Mimic), String> {
    let mut map = Mimic {
        multiplier: 1.0,
        offset: 0.0,
    };
    let mut current = joint;
    for _ in 0..=robot.joints.len() {
        let Some(m) = &robot.joints[current].mimic else {
            return match joint_coordinate[current] {
                Some(c) => Ok((c, map)),
                None => Err(format!(
                    "follows joint '{}', which is fixed; name a moving joint",
                    robot.joints[current].name
                )),
            };
        };
        let (multiplier, offset) = (m.multiplier.unwrap_or(1.0), m.offset.unwrap_or(0.0));
        if !(multiplier.is_finite() && offset.is_finite()) {
            return Err(format!(
                "multiplier {multiplier} and offset {offset} must be finite numbers"
            ));
        }
        // θ = c·θ_current + d with θ_current = a·θ_leader + b: θ = c·a·θ_leader + (c·b + d).
        map = Mimic {
            multiplier: map.multiplier * multiplier,
            offset: map.multiplier * offset + map.offset,
        };
        current = *joint_of.get(m.joint.as_str()).ok_or_else(|| {
            format!(
                "follows joint '{}', which is not defined; name a joint of this URDF",
                m.joint
            )
        })?;
    }
    Err(
        "mimic joints follow each other in a circle; one of them must have its own coordinate"
            .into(),
    )
}
