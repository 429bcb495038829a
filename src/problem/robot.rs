//! What problem validation needs to know about a robot: its names, limits and contact points.
//!
//! [`RobotInfo::read`] loads the robot with `model::Model::from_urdf_file` (the authority on
//! names, limits, inputs and contact points) and adds what outputs need for units: whether
//! each coordinate is a length or an angle, read from the joint types with roxmltree.
//! [`RobotInfo::parse`] is that plain XML pass alone (SPEC.md's URDF conventions), kept for
//! tests and for files the model rejects.

#![warn(missing_docs)]

use std::path::{Path, PathBuf};

use crate::model::BaseType;
use crate::problem::Interval;

/// A contact point declared in the URDF (a zero-radius collision sphere).
#[derive(Debug, Clone, PartialEq)]
pub struct UrdfContact {
    /// Collision `name` attribute, else `<link>_contact<k>` (k-th point on the link, from 0),
    /// as `model::ContactPoint` names it.
    pub name: String,
    /// Link it is fixed to.
    pub link: String,
    /// Point in the link frame [length].
    pub point: [f64; 3],
}

/// Whether a coordinate is a length or an angle (for units in outputs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoordinateKind {
    /// A length (prismatic joint, base translation).
    Linear,
    /// An angle (revolute or continuous joint, base rotation).
    Angular,
}

/// Names and limits of a robot in the model's coordinate and input order.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotInfo {
    /// URDF file read.
    pub urdf: PathBuf,
    /// Coordinate names (length n): `base_*` first, then non-fixed joints.
    pub coordinates: Vec<String>,
    /// Linear or angular, per coordinate (length n).
    pub coordinate_kinds: Vec<CoordinateKind>,
    /// Joint limits per coordinate (length n), ±∞ where the URDF has none.
    pub coordinate_limits: Vec<Interval>,
    /// Input names (length m): the transmission joints.
    pub inputs: Vec<String>,
    /// Linear (force) or angular (torque) input, per input (length m).
    pub input_kinds: Vec<CoordinateKind>,
    /// Effort limit per input (length m), +∞ for none.
    pub effort_limits: Vec<f64>,
    /// Every link name, in document order.
    pub links: Vec<String>,
    /// Contact points the URDF declares.
    pub contacts: Vec<UrdfContact>,
}

/// Why a URDF could not be read.
#[derive(Debug, thiserror::Error)]
pub enum RobotError {
    /// The file could not be read.
    #[error("cannot read URDF {path}: {source}")]
    Io {
        /// The URDF.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The file is not well-formed XML.
    #[error("URDF {path} is not valid XML: {message}")]
    Xml {
        /// The URDF.
        path: PathBuf,
        /// The XML parser's message.
        message: String,
    },
    /// The XML is not a URDF vito reads.
    #[error("URDF {path}: {what}")]
    Content {
        /// The URDF.
        path: PathBuf,
        /// What is wrong.
        what: String,
    },
    /// The model loader rejected it.
    #[error(transparent)]
    Model(#[from] crate::model::ModelError),
}

fn parse_triple(text: Option<&str>) -> Option<[f64; 3]> {
    let Some(text) = text else {
        return Some([0.0; 3]);
    };
    let v: Vec<f64> = text
        .split_whitespace()
        .map(|s| s.parse().ok())
        .collect::<Option<_>>()?;
    (v.len() == 3).then(|| [v[0], v[1], v[2]])
}

fn parse_number(text: Option<&str>, default: f64) -> Option<f64> {
    match text {
        None => Some(default),
        Some(t) => match t.trim() {
            "inf" | "+inf" | "Inf" => Some(f64::INFINITY),
            "-inf" | "-Inf" => Some(f64::NEG_INFINITY),
            t => t.parse().ok(),
        },
    }
}

impl RobotInfo {
    /// Reads a URDF and lists its coordinates for the given base (names, limits, inputs and
    /// contacts as `model::Model` has them).
    pub fn read(path: &Path, base: BaseType) -> Result<RobotInfo, RobotError> {
        let text = std::fs::read_to_string(path).map_err(|source| RobotError::Io {
            path: path.to_owned(),
            source,
        })?;
        let model = crate::model::Model::from_urdf_str(&text, base)?;
        let xml = Self::parse(path, &text, base)?;
        let kind_of = |name: &str| {
            xml.coordinate_index(name)
                .map_or(CoordinateKind::Angular, |i| xml.coordinate_kinds[i])
        };
        let coordinates = model.coordinate_names().to_vec();
        let coordinate_kinds: Vec<CoordinateKind> =
            coordinates.iter().map(|c| kind_of(c)).collect();
        Ok(RobotInfo {
            urdf: path.to_owned(),
            coordinate_limits: model
                .coordinate_limits()
                .iter()
                .map(|&(lower, upper)| Interval { lower, upper })
                .collect(),
            inputs: model.input_names().to_vec(),
            input_kinds: model
                .input_coordinates()
                .iter()
                .map(|&c| {
                    coordinate_kinds
                        .get(c)
                        .copied()
                        .unwrap_or(CoordinateKind::Angular)
                })
                .collect(),
            effort_limits: model.effort_limits().to_vec(),
            links: model.link_names().to_vec(),
            contacts: model
                .contact_points()
                .iter()
                .map(|c| UrdfContact {
                    name: c.name.clone(),
                    link: c.link.clone(),
                    point: c.point,
                })
                .collect(),
            coordinates,
            coordinate_kinds,
        })
    }

    /// Parses URDF text (`path` only names it in errors).
    pub fn parse(path: &Path, text: &str, base: BaseType) -> Result<RobotInfo, RobotError> {
        let content = |what: String| RobotError::Content {
            path: path.to_owned(),
            what,
        };
        let doc = roxmltree::Document::parse(text).map_err(|e| RobotError::Xml {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
        let robot = doc.root_element();
        let (base_names, base_kinds): (&[&str], &[CoordinateKind]) = {
            use CoordinateKind::{Angular as A, Linear as L};
            match base {
                BaseType::Fixed => (&[], &[]),
                BaseType::Planar => (&["base_x", "base_z", "base_pitch"], &[L, L, A]),
                BaseType::Floating => (
                    &[
                        "base_x",
                        "base_y",
                        "base_z",
                        "base_roll",
                        "base_pitch",
                        "base_yaw",
                    ],
                    &[L, L, L, A, A, A],
                ),
            }
        };
        let mut info = RobotInfo {
            urdf: path.to_owned(),
            coordinates: base_names.iter().map(|s| s.to_string()).collect(),
            coordinate_kinds: base_kinds.to_vec(),
            coordinate_limits: vec![Interval::FREE; base_names.len()],
            inputs: Vec::new(),
            input_kinds: Vec::new(),
            effort_limits: Vec::new(),
            links: Vec::new(),
            contacts: Vec::new(),
        };
        let mut efforts = Vec::new();
        for node in robot.children().filter(|n| n.is_element()) {
            match node.tag_name().name() {
                "link" => {
                    let name = node
                        .attribute("name")
                        .ok_or_else(|| content("a <link> has no name".into()))?;
                    info.links.push(name.to_owned());
                    let mut on_link = 0;
                    for collision in node.children().filter(|c| c.has_tag_name("collision")) {
                        let is_point = collision
                            .descendants()
                            .find(|d| d.has_tag_name("sphere"))
                            .and_then(|s| parse_number(s.attribute("radius"), 1.0))
                            == Some(0.0);
                        if !is_point {
                            continue;
                        }
                        let origin = collision.children().find(|c| c.has_tag_name("origin"));
                        let point = parse_triple(origin.and_then(|o| o.attribute("xyz")))
                            .ok_or_else(|| {
                                content(format!("link `{name}`: bad collision origin xyz"))
                            })?;
                        let contact_name = match collision.attribute("name") {
                            Some(n) => n.to_owned(),
                            None => format!("{name}_contact{on_link}"),
                        };
                        on_link += 1;
                        info.contacts.push(UrdfContact {
                            name: contact_name,
                            link: name.to_owned(),
                            point,
                        });
                    }
                }
                "joint" => {
                    let name = node
                        .attribute("name")
                        .ok_or_else(|| content("a <joint> has no name".into()))?;
                    let kind = match node.attribute("type") {
                        Some("revolute" | "continuous") => CoordinateKind::Angular,
                        Some("prismatic") => CoordinateKind::Linear,
                        Some("fixed") => continue,
                        other => {
                            return Err(content(format!(
                                "joint `{name}` has type {other:?}; vito reads fixed, revolute, continuous and prismatic joints"
                            )));
                        }
                    };
                    let limit = node.children().find(|c| c.has_tag_name("limit"));
                    let bad = || content(format!("joint `{name}`: bad <limit> number"));
                    let (lower, upper, effort) = match limit {
                        Some(l)
                            if l.attribute("lower").is_some() || l.attribute("upper").is_some() =>
                        {
                            (
                                parse_number(l.attribute("lower"), 0.0).ok_or_else(bad)?,
                                parse_number(l.attribute("upper"), 0.0).ok_or_else(bad)?,
                                parse_number(l.attribute("effort"), f64::INFINITY)
                                    .ok_or_else(bad)?,
                            )
                        }
                        Some(l) => (
                            f64::NEG_INFINITY,
                            f64::INFINITY,
                            parse_number(l.attribute("effort"), f64::INFINITY).ok_or_else(bad)?,
                        ),
                        None => (f64::NEG_INFINITY, f64::INFINITY, f64::INFINITY),
                    };
                    info.coordinates.push(name.to_owned());
                    info.coordinate_kinds.push(kind);
                    info.coordinate_limits.push(Interval { lower, upper });
                    efforts.push((name.to_owned(), kind, effort));
                }
                "transmission" => {
                    let joint = node
                        .children()
                        .find(|c| c.has_tag_name("joint"))
                        .and_then(|j| j.attribute("name"))
                        .ok_or_else(|| content("a <transmission> names no joint".into()))?;
                    let (_, kind, effort) = efforts
                        .iter()
                        .find(|(n, _, _)| n == joint)
                        .cloned()
                        .ok_or_else(|| {
                            content(format!(
                                "transmission on `{joint}`, which is not a non-fixed joint declared before it"
                            ))
                        })?;
                    info.inputs.push(joint.to_owned());
                    info.input_kinds.push(kind);
                    info.effort_limits.push(effort);
                }
                _ => {}
            }
        }
        Ok(info)
    }

    /// Index of a coordinate by name.
    pub fn coordinate_index(&self, name: &str) -> Option<usize> {
        self.coordinates.iter().position(|c| c == name)
    }

    /// Index of an input by name.
    pub fn input_index(&self, name: &str) -> Option<usize> {
        self.inputs.iter().position(|c| c == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const URDF: &str = r#"<robot name="r">
      <link name="base"/>
      <link name="leg"><collision group="toe"><origin xyz="0 0 -0.5"/><geometry><sphere radius="0"/></geometry></collision></link>
      <joint name="hip" type="revolute"><parent link="base"/><child link="leg"/><axis xyz="0 1 0"/>
        <limit lower="-1" upper="2" effort="30" velocity="inf"/></joint>
      <joint name="slide" type="prismatic"><parent link="leg"/><child link="base"/></joint>
      <transmission name="t"><joint name="hip"/></transmission>
    </robot>"#;

    #[test]
    fn reads_names_limits_and_points_in_order() {
        let info = RobotInfo::parse(Path::new("r.urdf"), URDF, BaseType::Planar).unwrap();
        assert_eq!(
            info.coordinates,
            ["base_x", "base_z", "base_pitch", "hip", "slide"]
        );
        assert_eq!(
            info.coordinate_limits[3],
            Interval {
                lower: -1.0,
                upper: 2.0
            }
        );
        assert_eq!(info.coordinate_limits[4], Interval::FREE);
        assert_eq!(info.inputs, ["hip"]);
        assert_eq!(info.effort_limits, [30.0]);
        assert_eq!(info.contacts.len(), 1);
        assert_eq!(info.contacts[0].name, "leg_contact0");
        assert_eq!(info.contacts[0].point, [0.0, 0.0, -0.5]);
    }
}
