//! The checked [`Model`] from a parsed URDF and its Drake extensions: names, the tree's
//! order, coordinates, frames with lumped masses, contact points, springs, loop closures and
//! inputs, each step a function.

use std::collections::{HashMap, HashSet};

use super::extensions::{Extensions, bad};
use super::inertia::{MassPiece, check_body, link_inertia, lump};
use crate::model::actuation::{Actuator, AppliedActuation};
use crate::model::spatial::{mat_mul, normalized, perpendicular_pair, rpy_to_matrix, transpose};
use crate::model::tree::{Frame, LinkPlacement, Mimic, Motion};
use crate::model::{
    BaseType, ContactPoint, IgnoredCollision, LinkId, LoopClosure, Model, ModelError, Spring,
    SpringKind,
};

fn rpy(v: &[f64; 3]) -> [[f64; 3]; 3] {
    rpy_to_matrix(v[0], v[1], v[2])
}

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// One virtual base frame: its motion, axis and coordinate index (into
/// [`BaseType::coordinate_names`]).
type BaseFrame = (Motion, [f64; 3], usize);

fn base_chain(base: BaseType) -> Vec<BaseFrame> {
    const X: [f64; 3] = [1.0, 0.0, 0.0];
    const Y: [f64; 3] = [0.0, 1.0, 0.0];
    const Z: [f64; 3] = [0.0, 0.0, 1.0];
    match base {
        BaseType::Fixed => vec![],
        BaseType::Planar => vec![
            (Motion::Prismatic, X, 0),
            (Motion::Prismatic, Z, 1),
            (Motion::Revolute, Y, 2),
        ],
        // Trans(x, y, z)·Rz(yaw)·Ry(pitch)·Rx(roll), q_base = [x, y, z, roll, pitch, yaw].
        BaseType::Floating => vec![
            (Motion::Prismatic, X, 0),
            (Motion::Prismatic, Y, 1),
            (Motion::Prismatic, Z, 2),
            (Motion::Revolute, Z, 5),
            (Motion::Revolute, Y, 4),
            (Motion::Revolute, X, 3),
        ],
    }
}

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
    let mut findings = Findings { problems, warnings };
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
    Ok(model)
}

/// Index of a link or joint by name.
type NameIndex<'a> = HashMap<&'a str, usize>;

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

/// The tree's shape: each link's parent joint, and the links parents first.
struct Tree {
    parent_joint: Vec<Option<usize>>,
    /// Links without children, in document order.
    leaves: Vec<usize>,
    /// Depth-first from the root.
    order: Vec<usize>,
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

/// The coordinates: base, then non-fixed joints in document order (except `<mimic>`
/// joints, which follow their leader and have no coordinate of their own).
struct Coordinates {
    names: Vec<String>,
    limits: Vec<(f64, f64)>,
    damping: Vec<f64>,
    /// Per joint, its coordinate (`None` for fixed and mimic joints).
    joint_coordinate: Vec<Option<usize>>,
    /// Per mimic joint, its leader's coordinate and the map from it.
    mimic: Vec<Option<(usize, Mimic)>>,
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

/// What loading found so far: problems (reported together, as one error) and warnings.
struct Findings {
    problems: Vec<String>,
    warnings: Vec<String>,
}

/// The rigid bodies: tree frames with their lumped masses, and where each link sits.
struct Bodies {
    frames: Vec<Frame>,
    /// Per link, in topological order.
    link_frame: Vec<LinkPlacement>,
    /// Link names in topological order (the link ids).
    link_names: Vec<String>,
    total_mass: f64,
}

/// Frames: the virtual base chain, then one per moving joint (links behind fixed joints
/// share their parent's frame), masses lumped per frame.
fn bodies(
    robot: &urdf_rs::Robot,
    ext: &Extensions,
    base: BaseType,
    link_of: &NameIndex,
    tree: &Tree,
    coordinates: &Coordinates,
    findings: &mut Findings,
) -> Result<Bodies, ModelError> {
    let Findings { problems, warnings } = findings;
    let base_frames = base_chain(base);
    let mut frames: Vec<Frame> = Vec::with_capacity(base_frames.len() + robot.links.len());
    for (k, &(motion, axis, coordinate)) in base_frames.iter().enumerate() {
        frames.push(Frame::massless(
            k.checked_sub(1),
            IDENTITY,
            [0.0; 3],
            axis,
            motion,
            coordinate,
        ));
    }
    // Each link's placement; a link behind a fixed joint shares its parent's frame.
    let mut placement_of: Vec<Option<LinkPlacement>> = vec![None; robot.links.len()];
    // Mass pieces per frame: (mass, com in frame, inertia about com in frame axes).
    let mut pieces: Vec<Vec<MassPiece>> = vec![Vec::new(); frames.len()];
    // Per frame, its links with mass ("line N: ", name), for messages about the lumped body.
    let mut body_links: Vec<Vec<(String, String)>> = vec![Vec::new(); frames.len()];
    let mut total_mass = 0.0;
    for &l in &tree.order {
        let link = &robot.links[l];
        let placement = match tree.parent_joint[l] {
            None => {
                frames.push(Frame::massless(
                    frames.len().checked_sub(1),
                    IDENTITY,
                    [0.0; 3],
                    [1.0, 0.0, 0.0],
                    Motion::Fixed,
                    0,
                ));
                pieces.push(Vec::new());
                body_links.push(Vec::new());
                LinkPlacement {
                    frame: frames.len() - 1,
                    rotation: IDENTITY,
                    translation: [0.0; 3],
                }
            }
            Some(j) => {
                let joint = &robot.joints[j];
                let parent = placement_of[link_of[joint.parent.link.as_str()]]
                    .clone()
                    .ok_or_else(|| ModelError::Cycle {
                        link: link.name.clone(),
                    })?;
                // Joint frame in the parent's tree frame: parent placement ∘ Trans(xyz)·R(rpy).
                let rotation = mat_mul(&parent.rotation, &rpy(&joint.origin.rpy));
                let translation = parent.point_in_frame(&joint.origin.xyz);
                let motion = match joint.joint_type {
                    urdf_rs::JointType::Prismatic => Motion::Prismatic,
                    urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                        Motion::Revolute
                    }
                    _ => Motion::Fixed,
                };
                if motion == Motion::Fixed {
                    LinkPlacement {
                        frame: parent.frame,
                        rotation,
                        translation,
                    }
                } else {
                    let axis = normalized(*joint.axis.xyz).ok_or(ModelError::BadAxis {
                        joint: joint.name.clone(),
                        axis: *joint.axis.xyz,
                    })?;
                    let (coordinate, mimic) = match coordinates.mimic[j] {
                        Some((leader, map)) => (leader, Some(map)),
                        None => (coordinates.joint_coordinate[j].unwrap_or(0), None),
                    };
                    let mut frame = Frame::massless(
                        Some(parent.frame),
                        rotation,
                        translation,
                        axis,
                        motion,
                        coordinate,
                    );
                    frame.mimic = mimic;
                    frames.push(frame);
                    pieces.push(Vec::new());
                    body_links.push(Vec::new());
                    LinkPlacement {
                        frame: frames.len() - 1,
                        rotation: IDENTITY,
                        translation: [0.0; 3],
                    }
                }
            }
        };
        let at = ext.at("link", &link.name);
        if ext.has_inertial.contains(&link.name)
            && let Some((mass, com, inertia)) = link_inertia(link, &at, problems, warnings)
        {
            total_mass += mass;
            body_links[placement.frame].push((at, link.name.clone()));
            let r = &placement.rotation;
            pieces[placement.frame].push((
                mass,
                placement.point_in_frame(&com),
                mat_mul(&mat_mul(r, &inertia), &transpose(r)),
            ));
        }
        placement_of[l] = Some(placement);
    }
    // A body welded to the world never moves, so its inertia plays no part.
    let mut moves: Vec<bool> = Vec::with_capacity(frames.len());
    for (i, (frame, parts)) in frames.iter_mut().zip(&pieces).enumerate() {
        (frame.mass, frame.com, frame.inertia) = lump(parts);
        let moving = frame.motion != Motion::Fixed || frame.parent.is_some_and(|p| moves[p]);
        if moving {
            check_body(
                &(frame.mass, frame.com, frame.inertia),
                &body_links[i],
                problems,
            );
        }
        moves.push(moving);
    }
    // Link ids follow the topological order.
    let link_names: Vec<String> = tree
        .order
        .iter()
        .map(|&l| robot.links[l].name.clone())
        .collect();
    let link_frame: Vec<LinkPlacement> = tree
        .order
        .iter()
        .map(|&l| {
            placement_of[l].clone().ok_or(ModelError::Cycle {
                link: robot.links[l].name.clone(),
            })
        })
        .collect::<Result<_, _>>()?;
    Ok(Bodies {
        frames,
        link_frame,
        link_names,
        total_mass,
    })
}

/// Contacts: collision spheres of any radius (0: a point), links in document order. Other
/// collision shapes are returned and listed, by link, in one warning.
fn contact_points(
    robot: &urdf_rs::Robot,
    ext: &Extensions,
    warnings: &mut Vec<String>,
) -> (Vec<ContactPoint>, Vec<IgnoredCollision>) {
    let mut contact_points = Vec::new();
    let mut ignored = Vec::new();
    let mut ignored_collisions = Vec::new();
    for link in &robot.links {
        let sphere = |c: &urdf_rs::Collision| match c.geometry {
            urdf_rs::Geometry::Sphere { radius } => Some(radius),
            _ => None,
        };
        let n_points = link
            .collision
            .iter()
            .filter(|c| sphere(c).is_some())
            .count();
        for (k, collision) in link.collision.iter().enumerate() {
            let Some(radius) = sphere(collision) else {
                let shape = match collision.geometry {
                    urdf_rs::Geometry::Box { .. } => "box",
                    urdf_rs::Geometry::Cylinder { .. } => "cylinder",
                    urdf_rs::Geometry::Capsule { .. } => "capsule",
                    _ => "mesh",
                };
                ignored.push(format!(
                    "{}'{}' ({shape})",
                    ext.at("link", &link.name),
                    link.name
                ));
                ignored_collisions.push(IgnoredCollision {
                    link: link.name.clone(),
                    shape: shape.into(),
                });
                continue;
            };
            // Unnamed: the link's name when it is the link's only point.
            let fallback = if n_points == 1 {
                link.name.clone()
            } else {
                format!("{}_contact{k}", link.name)
            };
            contact_points.push(ContactPoint {
                name: collision.name.clone().unwrap_or(fallback),
                link: link.name.clone(),
                point: *collision.origin.xyz,
                radius,
            });
        }
    }
    if !ignored.is_empty() {
        warnings.push(format!(
            "collision shapes other than spheres are ignored (no contact from them): {}; \
             add a <sphere> collision or a [[contacts.point]] with a radius for each foot",
            ignored.join(", ")
        ));
    }
    (contact_points, ignored_collisions)
}

/// Which coordinate a joint named by an extension moves.
struct JointCoordinates<'a> {
    robot: &'a urdf_rs::Robot,
    joint_of: &'a NameIndex<'a>,
    joint_coordinate: &'a [Option<usize>],
}

impl JointCoordinates<'_> {
    /// The coordinate of `joint`, named by `element` `owner`; an undefined or fixed joint is
    /// an error naming both.
    fn of(&self, element: &'static str, owner: &str, joint: &str) -> Result<usize, ModelError> {
        let j = self.joint_of.get(joint).copied().ok_or_else(|| {
            bad(
                element,
                owner,
                format!("refers to joint '{joint}', which is not defined"),
            )
        })?;
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
            bad(
                element,
                owner,
                format!("acts on joint '{joint}', which {why}"),
            )
        })
    }
}

fn springs(
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

fn loop_closures(ext: &Extensions, link_names: &[String]) -> Result<Vec<LoopClosure>, ModelError> {
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
fn actuators(
    robot: &urdf_rs::Robot,
    ext: &Extensions,
    joints: &JointCoordinates,
    warnings: &mut Vec<String>,
) -> Result<Vec<Actuator>, ModelError> {
    let mut transmission_of: HashMap<usize, usize> = HashMap::new();
    for (t, (name, joint, reduction)) in ext.transmissions.iter().enumerate() {
        let coordinate = joints.of("transmission", name, joint)?;
        if *reduction != 1.0 {
            warnings.push(format!(
                "transmission '{name}': mechanicalReduction {reduction} ignored (vito uses 1)"
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
