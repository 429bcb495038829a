//! The rigid bodies of a URDF: tree frames with their lumped masses (and the checks on the
//! lumped bodies), where each link sits, and the contact points.

use super::extensions::Extensions;
use super::inertia::{MassPiece, check_body, link_inertia, lump};
use super::parts::{Coordinates, IDENTITY, NameIndex, Tree, base_chain, rpy};
use crate::model::spatial::{mat_mul, normalized, transpose};
use crate::model::tree::{Frame, LinkPlacement, Motion};
use crate::model::{BaseType, ContactPoint, IgnoredCollision, ModelError};

/// What loading found so far: problems (reported together, as one error) and warnings.
pub(super) struct Findings {
    pub(super) problems: Vec<String>,
    pub(super) warnings: Vec<String>,
    /// Moving bodies whose inertia is not positive definite: problems when the mass matrix
    /// is not positive definite either, else warnings (the bodies beyond them carry the
    /// inertia the coordinates need, as in iCub's and Romeo's URDFs).
    pub(super) inertias: Vec<String>,
}

/// The rigid bodies: tree frames with their lumped masses, and where each link sits.
pub(super) struct Bodies {
    pub(super) frames: Vec<Frame>,
    /// Per link, in topological order.
    pub(super) link_frame: Vec<LinkPlacement>,
    /// Link names in topological order (the link ids).
    pub(super) link_names: Vec<String>,
    pub(super) total_mass: f64,
}

/// Frames: the virtual base chain, then one per moving joint (links behind fixed joints
/// share their parent's frame), masses lumped per frame.
pub(super) fn bodies(
    robot: &urdf_rs::Robot,
    ext: &Extensions,
    base: BaseType,
    link_of: &NameIndex,
    tree: &Tree,
    coordinates: &Coordinates,
    findings: &mut Findings,
) -> Result<Bodies, ModelError> {
    let Findings {
        problems,
        warnings,
        inertias,
    } = findings;
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
                let root = Frame::massless(
                    frames.len().checked_sub(1),
                    IDENTITY,
                    [0.0; 3],
                    [1.0, 0.0, 0.0],
                    Motion::Fixed,
                    0,
                );
                push_frame(&mut frames, &mut pieces, &mut body_links, root)
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
                    push_frame(&mut frames, &mut pieces, &mut body_links, frame)
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
                inertias,
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
pub(super) fn contact_points(
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
            "collision shapes other than spheres are ignored (no contact from them): {}{SPHERE_HINT}",
            ignored.join(", ")
        ));
    }
    (contact_points, ignored_collisions)
}

/// The advice ending the warning about ignored collision shapes; a problem that gives its
/// contacts itself (`[[contacts.point]]`) has no use for it, and the commands leave it out.
pub const SPHERE_HINT: &str =
    "; add a <sphere> collision or a [[contacts.point]] with a radius for each foot";
/// Appends `frame` with no pieces and no links yet; the placement of a link at its origin.
fn push_frame<P, L>(
    frames: &mut Vec<Frame>,
    pieces: &mut Vec<Vec<P>>,
    body_links: &mut Vec<Vec<L>>,
    frame: Frame,
) -> LinkPlacement {
    frames.push(frame);
    pieces.push(Vec::new());
    body_links.push(Vec::new());
    LinkPlacement {
        frame: frames.len() - 1,
        rotation: IDENTITY,
        translation: [0.0; 3],
    }
}
