//! Drake's URDF extensions and what urdf-rs does not keep, read with roxmltree: which links
//! have an `<inertial>`, which limits are given, `<force_element>` springs, `<loop_joint>`
//! closures and `<transmission>` joints.

use std::collections::{HashMap, HashSet};

use roxmltree::{Document, Node};

use crate::model::{ModelError, SpringKind};

/// Top-level elements vito knows (read or deliberately ignored without a warning).
const KNOWN_TOP_LEVEL: &[&str] = &[
    "link",
    "joint",
    "material",
    "transmission",
    "gazebo",
    "force_element",
    "loop_joint",
];

/// What the roxmltree pass collects.
#[derive(Default)]
pub(super) struct Extensions {
    /// Links that have an `<inertial>`.
    pub(super) has_inertial: HashSet<String>,
    /// Source line of each `<link>` (of its `<inertial>` when it has one) and `<joint>`,
    /// for messages that name where to look.
    pub(super) lines: HashMap<(&'static str, String), u32>,
    /// Joint name → (has `<limit>`, has lower, has upper).
    pub(super) limit_presence: HashMap<String, (bool, bool, bool)>,
    pub(super) springs: Vec<RawSpring>,
    pub(super) loops: Vec<RawLoop>,
    /// The joints the `<transmission>`s drive, one entry per joint, in document order.
    pub(super) transmissions: Vec<RawTransmission>,
}

/// One joint a `<transmission>` drives.
pub(super) struct RawTransmission {
    /// The transmission's name.
    pub(super) name: String,
    /// The joint it names.
    pub(super) joint: String,
    /// Its `<mechanicalReduction>` (1 when absent).
    pub(super) reduction: f64,
    /// The transmission's line.
    pub(super) line: u32,
}

/// Where transmissions name the joints they drive: `<joint name>` (ROS's
/// SimpleTransmission, and every joint of a differential or four-bar transmission, whatever
/// its `<role>`), a PR2 wrist's `<flexJoint>` and `<rollJoint>` and a PR2 gripper's
/// `<gap_joint>` (its `<passive_joint>`s follow and are not driven).
const DRIVEN_JOINT_TAGS: &[&str] = &["joint", "flexJoint", "rollJoint", "gap_joint"];

/// The joints a `<transmission>` drives, in document order.
fn transmission_joints<'a>(node: Node<'a, '_>) -> Vec<&'a str> {
    node.children()
        .filter(|c| DRIVEN_JOINT_TAGS.contains(&c.tag_name().name()))
        .filter_map(|c| c.attribute("name"))
        .collect()
}

pub(super) struct RawSpring {
    pub(super) name: String,
    pub(super) kind: SpringKind,
    pub(super) joint: String,
    pub(super) stiffness: f64,
    pub(super) rest: f64,
}

pub(super) struct RawLoop {
    pub(super) name: String,
    pub(super) axis: [f64; 3],
    pub(super) link1: String,
    pub(super) xyz1: [f64; 3],
    pub(super) link2: String,
    pub(super) xyz2: [f64; 3],
    pub(super) rpy2: [f64; 3],
}

impl Extensions {
    /// "line N: " for the named link or joint (empty when unknown).
    pub(super) fn at(&self, element: &'static str, name: &str) -> String {
        self.lines
            .get(&(element, name.to_string()))
            .map_or_else(String::new, |line| format!("line {line}: "))
    }
}

pub(super) fn bad(element: &'static str, name: &str, problem: String) -> ModelError {
    ModelError::BadExtension {
        element,
        name: name.to_string(),
        problem,
    }
}

/// Parses "a b c" (commas tolerated) into three numbers.
fn parse_vec3(text: &str) -> Option<[f64; 3]> {
    let values: Vec<f64> = text
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|s| !s.is_empty())
        .map(str::parse)
        .collect::<Result<_, _>>()
        .ok()?;
    <[f64; 3]>::try_from(values).ok()
}

fn number_attr(
    node: Node,
    key: &str,
    element: &'static str,
    name: &str,
) -> Result<Option<f64>, ModelError> {
    match node.attribute(key) {
        None => Ok(None),
        Some(text) => text.trim().parse::<f64>().map(Some).map_err(|_| {
            bad(
                element,
                name,
                format!("attribute {key}=\"{text}\" is not a number; write a decimal number"),
            )
        }),
    }
}

fn vec3_attr(
    node: Node,
    key: &str,
    element: &'static str,
    name: &str,
) -> Result<[f64; 3], ModelError> {
    match node.attribute(key) {
        None => Ok([0.0; 3]),
        Some(text) => parse_vec3(text).ok_or_else(|| {
            bad(
                element,
                name,
                format!(
                    "attribute {key}=\"{text}\" is not three numbers; write e.g. {key}=\"0 0 1\""
                ),
            )
        }),
    }
}

pub(super) fn read_extensions(
    doc: &Document,
    warnings: &mut Vec<String>,
) -> Result<Extensions, ModelError> {
    let mut ext = Extensions::default();
    let root = doc.root_element();
    let lines = super::Lines::new(doc.input_text());
    for node in root.children().filter(Node::is_element) {
        let tag = node.tag_name().name();
        let name = node.attribute("name").unwrap_or("").to_string();
        let line = |n: Node| lines.row(n.range().start);
        match tag {
            "link" => {
                let inertial = node.children().find(|c| c.has_tag_name("inertial"));
                ext.lines
                    .insert(("link", name.clone()), line(inertial.unwrap_or(node)));
                if inertial.is_some() {
                    ext.has_inertial.insert(name);
                }
            }
            "joint" => {
                ext.lines.insert(("joint", name.clone()), line(node));
                let limit = node.children().find(|c| c.has_tag_name("limit"));
                let presence = match limit {
                    Some(l) => (true, l.has_attribute("lower"), l.has_attribute("upper")),
                    None => (false, false, false),
                };
                ext.limit_presence.insert(name, presence);
            }
            "force_element" => read_force_element(node, &name, &mut ext, warnings)?,
            "loop_joint" => ext.loops.push(read_loop_joint(node, &name)?),
            "transmission" => {
                let at = line(node);
                let joints = transmission_joints(node);
                if joints.is_empty() {
                    warnings.push(format!(
                        "line {at}: transmission '{name}' names no joint (<joint name=\"...\"/>, \
                         or a PR2 transmission's <flexJoint>, <rollJoint> or <gap_joint>); ignored"
                    ));
                    continue;
                }
                let reduction = match node
                    .children()
                    .find(|c| c.has_tag_name("mechanicalReduction"))
                {
                    Some(r) => r.text().unwrap_or("1").trim().parse::<f64>().map_err(|_| {
                        bad(
                            "transmission",
                            &name,
                            "mechanicalReduction is not a number".into(),
                        )
                    })?,
                    None => 1.0,
                };
                if !reduction.is_finite() || reduction == 0.0 {
                    return Err(bad(
                        "transmission",
                        &name,
                        format!(
                            "mechanicalReduction {reduction}: give a finite, nonzero ratio \
                             (vito uses 1 and warns about others)"
                        ),
                    ));
                }
                for joint in joints {
                    ext.transmissions.push(RawTransmission {
                        name: name.clone(),
                        joint: joint.to_string(),
                        reduction,
                        line: at,
                    });
                }
            }
            _ if KNOWN_TOP_LEVEL.contains(&tag) => {}
            _ => warnings.push(format!(
                "line {}: element <{tag}{}> is not used by vito",
                lines.row(node.range().start),
                if name.is_empty() {
                    String::new()
                } else {
                    format!(" name=\"{name}\"")
                }
            )),
        }
    }
    Ok(ext)
}

fn read_force_element(
    node: Node,
    name: &str,
    ext: &mut Extensions,
    warnings: &mut Vec<String>,
) -> Result<(), ModelError> {
    for child in node.children().filter(Node::is_element) {
        let (kind, rest_key) = match child.tag_name().name() {
            "torsional_spring" => (SpringKind::Torsional, "rest_angle"),
            "prismatic_spring" => (SpringKind::Prismatic, "rest_length"),
            other => {
                warnings.push(format!(
                    "force_element '{name}': <{other}> is not supported and is ignored"
                ));
                continue;
            }
        };
        let stiffness =
            number_attr(child, "stiffness", "force_element", name)?.ok_or_else(|| {
                bad(
                    "force_element",
                    name,
                    "spring has no stiffness attribute; add stiffness=\"...\"".into(),
                )
            })?;
        let rest = number_attr(child, rest_key, "force_element", name)?.unwrap_or(0.0);
        let joint = child
            .children()
            .find(|c| c.has_tag_name("joint"))
            .and_then(|j| j.attribute("name"))
            .ok_or_else(|| {
                bad(
                    "force_element",
                    name,
                    "spring has no <joint name=\"...\"/>".into(),
                )
            })?;
        ext.springs.push(RawSpring {
            name: name.to_string(),
            kind,
            joint: joint.to_string(),
            stiffness,
            rest,
        });
    }
    Ok(())
}

fn read_loop_joint(node: Node, name: &str) -> Result<RawLoop, ModelError> {
    let kind = node.attribute("type").unwrap_or("continuous");
    if !matches!(kind, "continuous" | "revolute") {
        return Err(bad(
            "loop_joint",
            name,
            format!(
                "type \"{kind}\" is not supported; vito closes loops with pins (type=\"continuous\" or \"revolute\")"
            ),
        ));
    }
    let axis = match node.children().find(|c| c.has_tag_name("axis")) {
        Some(a) => vec3_attr(a, "xyz", "loop_joint", name)?,
        None => [1.0, 0.0, 0.0],
    };
    let end = |tag: &str| -> Result<(String, [f64; 3], [f64; 3]), ModelError> {
        let n = node
            .children()
            .find(|c| c.has_tag_name(tag))
            .ok_or_else(|| {
                bad(
                    "loop_joint",
                    name,
                    format!("has no <{tag} link=\"...\" xyz=\"...\"/>"),
                )
            })?;
        let link = n
            .attribute("link")
            .ok_or_else(|| bad("loop_joint", name, format!("<{tag}> has no link attribute")))?;
        Ok((
            link.to_string(),
            vec3_attr(n, "xyz", "loop_joint", name)?,
            vec3_attr(n, "rpy", "loop_joint", name)?,
        ))
    };
    let (link1, xyz1, _) = end("link1")?;
    let (link2, xyz2, rpy2) = end("link2")?;
    Ok(RawLoop {
        name: name.to_string(),
        axis,
        link1,
        xyz1,
        link2,
        xyz2,
        rpy2,
    })
}
