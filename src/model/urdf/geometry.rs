//! What a link looks like: its `<visual>` and `<collision>` shapes and where its child joints
//! sit, as the URDF states them (for drawing; the mechanics use none of it). Numbers no
//! drawing can use (NaN, ±∞, negative or absurd sizes and mesh scales) are refused by
//! element and link name before the model is built.

use super::extensions::bad;
use crate::model::ModelError;
use crate::model::{ChildJoint, LinkGeometry, Shape, ShapeKind};

/// Largest magnitude of a size, a radius or a mesh scale factor: far beyond any robot in
/// any unit, small enough that products of a few of them stay finite.
pub(crate) const MAX_GEOMETRY_VALUE: f64 = 1e9;

/// The shape of one `<visual>` or `<collision>` element, checked.
fn shape(
    link: &str,
    element: &str,
    origin: &urdf_rs::Pose,
    geometry: &urdf_rs::Geometry,
    rgba: Option<[f64; 4]>,
) -> Result<Shape, ModelError> {
    let check = |what: &str, values: &[f64], lowest: f64| -> Result<(), ModelError> {
        let fine = values
            .iter()
            .all(|v| v.is_finite() && *v >= lowest && v.abs() <= MAX_GEOMETRY_VALUE);
        if fine {
            return Ok(());
        }
        Err(bad(
            "link",
            link,
            format!(
                "<{element}> {what} {values:?}: each must be a finite number in [{lowest}, \
                 {MAX_GEOMETRY_VALUE:e}] (fix or remove the element)"
            ),
        ))
    };
    check("<origin xyz>", &origin.xyz[..], -MAX_GEOMETRY_VALUE)?;
    check("<origin rpy>", &origin.rpy[..], -MAX_GEOMETRY_VALUE)?;
    let kind = match geometry {
        urdf_rs::Geometry::Box { size } => {
            check("<box size>", &size[..], 0.0)?;
            ShapeKind::Box { size: **size }
        }
        urdf_rs::Geometry::Cylinder { radius, length } => {
            check("<cylinder radius length>", &[*radius, *length], 0.0)?;
            ShapeKind::Cylinder {
                radius: *radius,
                length: *length,
            }
        }
        urdf_rs::Geometry::Capsule { radius, length } => {
            check("<capsule radius length>", &[*radius, *length], 0.0)?;
            ShapeKind::Capsule {
                radius: *radius,
                length: *length,
            }
        }
        urdf_rs::Geometry::Sphere { radius } => {
            check("<sphere radius>", &[*radius], 0.0)?;
            ShapeKind::Sphere { radius: *radius }
        }
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let scale = scale.map_or([1.0; 3], |s| *s);
            check("<mesh scale>", &scale, -MAX_GEOMETRY_VALUE)?;
            if scale.iter().any(|s| s.abs() < 1.0 / MAX_GEOMETRY_VALUE) {
                return Err(bad(
                    "link",
                    link,
                    format!(
                        "<{element}> <mesh filename=\"{filename}\" scale=\"{scale:?}\">: a \
                         scale factor is zero or nearly so; give the mesh's real scale"
                    ),
                ));
            }
            ShapeKind::Mesh {
                filename: filename.clone(),
                scale,
            }
        }
    };
    Ok(Shape {
        xyz: *origin.xyz,
        rpy: *origin.rpy,
        kind,
        rgba,
    })
}

/// Every link's geometry, in the URDF's link order.
pub(super) fn read(robot: &urdf_rs::Robot) -> Result<Vec<(String, LinkGeometry)>, ModelError> {
    // The first material of each name, looked up by name (linear in visuals and materials).
    let mut materials = std::collections::HashMap::with_capacity(robot.materials.len());
    for m in &robot.materials {
        materials.entry(m.name.as_str()).or_insert(m);
    }
    let named_colour = |name: &str| {
        materials
            .get(name)
            .and_then(|m| m.color.as_ref())
            .map(|c| *c.rgba)
    };
    let mut out = Vec::with_capacity(robot.links.len());
    for link in &robot.links {
        let mut geometry = LinkGeometry::default();
        for visual in &link.visual {
            let rgba = visual.material.as_ref().and_then(|m| {
                m.color
                    .as_ref()
                    .map(|c| *c.rgba)
                    .or_else(|| named_colour(&m.name))
            });
            let rgba = rgba.filter(|c| c.iter().all(|v| v.is_finite()));
            geometry.visual.push(shape(
                &link.name,
                "visual",
                &visual.origin,
                &visual.geometry,
                rgba,
            )?);
        }
        for collision in &link.collision {
            geometry.collision.push(shape(
                &link.name,
                "collision",
                &collision.origin,
                &collision.geometry,
                None,
            )?);
        }
        let finite = |v: &[f64; 3]| v.iter().all(|x| x.is_finite());
        geometry.children = robot
            .joints
            .iter()
            .filter(|j| j.parent.link == link.name)
            .filter(|j| finite(&j.origin.xyz) && finite(&j.origin.rpy))
            .map(|j| ChildJoint {
                joint: j.name.clone(),
                link: j.child.link.clone(),
                xyz: *j.origin.xyz,
                rpy: *j.origin.rpy,
                slide: (j.joint_type == urdf_rs::JointType::Prismatic)
                    .then_some(*j.axis.xyz)
                    .filter(finite),
            })
            .collect();
        geometry.mass = Some(link.inertial.mass.value)
            .filter(|m| m.is_finite() && *m > 0.0)
            .unwrap_or(0.0);
        out.push((link.name.clone(), geometry));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use crate::model::{BaseType, Model, ModelError, ShapeKind};

    fn link(body: &str) -> String {
        format!(
            r#"<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>{body}</link></robot>"#
        )
    }

    #[test]
    fn shapes_are_kept_with_origin_and_colour() {
        let xml = link(
            r#"<visual><origin xyz="0 0 0.5" rpy="0 0 0"/><geometry><box size="0.1 0.2 0.3"/></geometry><material name="m"><color rgba="1 0 0 1"/></material></visual>
               <visual><geometry><mesh filename="m.stl" scale="2"/></geometry></visual>
               <collision><geometry><cylinder radius="0.1" length="1"/></geometry></collision>"#,
        );
        let model = Model::from_urdf_str(&xml, BaseType::Fixed).unwrap();
        let g = &model.link_geometry()[0];
        assert_eq!(g.visual.len(), 2);
        assert_eq!(g.visual[0].xyz, [0.0, 0.0, 0.5]);
        assert_eq!(g.visual[0].rgba, Some([1.0, 0.0, 0.0, 1.0]));
        assert_eq!(
            g.visual[0].kind,
            ShapeKind::Box {
                size: [0.1, 0.2, 0.3]
            }
        );
        assert_eq!(
            g.visual[1].kind,
            ShapeKind::Mesh {
                filename: "m.stl".into(),
                scale: [2.0; 3]
            }
        );
        assert_eq!(g.collision.len(), 1);
    }

    #[test]
    fn absurd_or_non_finite_geometry_is_refused_by_link() {
        for body in [
            r#"<visual><geometry><box size="NaN 1 1"/></geometry></visual>"#,
            r#"<visual><geometry><sphere radius="-1"/></geometry></visual>"#,
            r#"<visual><geometry><mesh filename="m.stl" scale="1e30 1 1"/></geometry></visual>"#,
            r#"<visual><geometry><mesh filename="m.stl" scale="0 1 1"/></geometry></visual>"#,
            r#"<visual><origin xyz="inf 0 0"/><geometry><sphere radius="1"/></geometry></visual>"#,
        ] {
            let err = Model::from_urdf_str(&link(body), BaseType::Fixed).unwrap_err();
            assert!(
                matches!(err, ModelError::BadExtension { .. }),
                "{body}: {err}"
            );
            let text = err.to_string();
            assert!(text.contains("'a'") || text.contains("a"), "{text}");
            assert!(text.contains("<visual>"), "{text}");
        }
    }
}
