//! URDF → [`Model`]: urdf-rs reads the standard elements, a roxmltree pass reads Drake's
//! extensions. The only file that imports `urdf_rs`.
//!
//! Read: links (`<inertial>`, zero-radius `<collision>` spheres as point contacts), joints
//! of type fixed, revolute, continuous and prismatic (origin, axis, `<limit>` lower/upper/effort,
//! `<dynamics damping>`), `<transmission>` joints (inputs), and Drake's `<force_element>`
//! (`<torsional_spring>`, `<prismatic_spring>`) and `<loop_joint>`.
//!
//! Repaired before parsing, each listed in [`Model::warnings`] (the original files of the
//! paper's robots need them): a `<limit>` without `velocity` or `effort` (both then mean "no
//! limit"), `pi`-expressions such as `-pi/4` in `<limit>`, commas in `xyz`/`rpy`, a one-value
//! mesh `scale`, capitalised joint types, and stray `/` text.
//!
//! Limitations (ignored): visual elements and meshes, non-zero-radius collision geometry,
//! `velocity` limits, `friction` in `<dynamics>`, `<mimic>`, `<calibration>`,
//! `<safety_controller>`, `mechanicalReduction` (must be 1), `<gazebo>`, Drake `<frame>`
//! (reported as a warning), collision groups.

use std::collections::{HashMap, HashSet};

use roxmltree::{Document, Node};

use super::spatial::{mat_mul, rpy_to_matrix};
use super::tree::{Frame, LinkPlacement, Motion};
use super::{BaseType, ContactPoint, LinkId, LoopClosure, Model, ModelError, Spring, SpringKind};

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

/// Parses, repairs, checks and converts a URDF document.
pub(crate) fn load(xml: &str, origin: &str, base: BaseType) -> Result<Model, ModelError> {
    let mut warnings = Vec::new();
    let repaired = repair(xml, origin, &mut warnings)?;
    let doc = Document::parse(&repaired).map_err(|e| xml_error(origin, e))?;
    let extensions = read_extensions(&doc, &mut warnings)?;
    let robot = urdf_rs::read_from_string(&repaired).map_err(|e| ModelError::Urdf {
        origin: origin.to_string(),
        message: e.to_string(),
    })?;
    build(&robot, &extensions, base, warnings)
}

fn xml_error(origin: &str, e: roxmltree::Error) -> ModelError {
    ModelError::Xml {
        origin: origin.to_string(),
        message: e.to_string(),
    }
}

/// A textual edit of the source: replace `range` by `text`.
struct Edit {
    range: std::ops::Range<usize>,
    text: String,
}

/// Makes the unambiguous repairs and returns the repaired text.
fn repair(xml: &str, origin: &str, warnings: &mut Vec<String>) -> Result<String, ModelError> {
    let doc = Document::parse(xml).map_err(|e| xml_error(origin, e))?;
    let mut edits: Vec<Edit> = Vec::new();
    let line = |pos: usize| doc.text_pos_at(pos).row;
    for node in doc.descendants() {
        if node.is_text() {
            let text = node.text().unwrap_or("");
            let parent_is_structural = node.parent_element().is_some_and(|p| {
                matches!(
                    p.tag_name().name(),
                    "robot" | "link" | "joint" | "visual" | "collision"
                )
            });
            if parent_is_structural && text.trim() == "/" {
                warnings.push(format!(
                    "line {}: removed stray text \"/\"",
                    line(node.range().start)
                ));
                edits.push(Edit {
                    range: node.range(),
                    text: String::new(),
                });
            }
            continue;
        }
        if !node.is_element() {
            continue;
        }
        let tag = node.tag_name().name();
        for attr in node.attributes() {
            let value = attr.value();
            let name = attr.name();
            if (name == "xyz" || name == "rpy") && value.contains(',') {
                warnings.push(format!(
                    "line {}: removed commas from {name}=\"{value}\"",
                    line(attr.range().start)
                ));
                edits.push(Edit {
                    range: attr.range_value(),
                    text: value.replace(',', " "),
                });
            }
            if tag == "limit"
                && (name == "lower" || name == "upper")
                && value.parse::<f64>().is_err()
                && let Some(v) = eval_pi_expression(value)
            {
                warnings.push(format!(
                    "line {}: evaluated limit {name}=\"{value}\" as {v:?}",
                    line(attr.range().start)
                ));
                edits.push(Edit {
                    range: attr.range_value(),
                    text: format!("{v:?}"),
                });
            }
            if tag == "mesh" && name == "scale" && value.split_whitespace().count() == 1 {
                edits.push(Edit {
                    range: attr.range_value(),
                    text: format!("{0} {0} {0}", value.trim()),
                });
            }
            if tag == "joint" && name == "type" && value != value.to_lowercase() {
                warnings.push(format!(
                    "line {}: joint type \"{value}\" read as \"{}\"",
                    line(attr.range().start),
                    value.to_lowercase()
                ));
                edits.push(Edit {
                    range: attr.range_value(),
                    text: value.to_lowercase(),
                });
            }
        }
        if tag == "limit" {
            let mut missing = Vec::new();
            for key in ["velocity", "effort"] {
                if node.attribute(key).is_none() {
                    missing.push(key);
                }
            }
            if !missing.is_empty() {
                let joint = node
                    .parent_element()
                    .and_then(|j| j.attribute("name"))
                    .unwrap_or("?");
                warnings.push(format!(
                    "joint '{joint}': <limit> has no {}; read as unbounded (inf)",
                    missing.join(" or ")
                ));
                let at = node.range().start + "<limit".len();
                edits.push(Edit {
                    range: at..at,
                    text: missing.iter().map(|k| format!(" {k}=\"inf\"")).collect(),
                });
            }
        }
    }
    edits.sort_by_key(|e| e.range.start);
    let mut out = String::with_capacity(xml.len() + 64 * edits.len());
    let mut cursor = 0;
    for edit in edits {
        if edit.range.start < cursor {
            continue; // overlapping edits cannot arise from distinct attributes; be safe
        }
        out.push_str(&xml[cursor..edit.range.start]);
        out.push_str(&edit.text);
        cursor = edit.range.end;
    }
    out.push_str(&xml[cursor..]);
    Ok(out)
}

/// Evaluates `[-][a*]pi[/b]` (spaces allowed), the form used in Drake-era URDF limits.
fn eval_pi_expression(text: &str) -> Option<f64> {
    let compact: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    let (sign, rest) = match compact.strip_prefix('-') {
        Some(r) => (-1.0, r),
        None => (1.0, compact.strip_prefix('+').unwrap_or(&compact)),
    };
    let (factor, rest) = match rest.split_once('*') {
        Some((a, r)) => (a.parse::<f64>().ok()?, r),
        None => (1.0, rest),
    };
    let rest = rest.strip_prefix("pi")?;
    let divisor = if rest.is_empty() {
        1.0
    } else {
        rest.strip_prefix('/')?.parse::<f64>().ok()?
    };
    Some(sign * factor * std::f64::consts::PI / divisor)
}

/// What the roxmltree pass collects.
#[derive(Default)]
struct Extensions {
    /// Links that have an `<inertial>`.
    has_inertial: HashSet<String>,
    /// Joint name → (has `<limit>`, has lower, has upper).
    limit_presence: HashMap<String, (bool, bool, bool)>,
    springs: Vec<RawSpring>,
    loops: Vec<RawLoop>,
    /// (transmission name, joint name, reduction).
    transmissions: Vec<(String, String, f64)>,
}

struct RawSpring {
    name: String,
    kind: SpringKind,
    joint: String,
    stiffness: f64,
    rest: f64,
}

struct RawLoop {
    name: String,
    axis: [f64; 3],
    link1: String,
    xyz1: [f64; 3],
    link2: String,
    xyz2: [f64; 3],
    rpy2: [f64; 3],
}

fn bad(element: &'static str, name: &str, problem: String) -> ModelError {
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

fn read_extensions(doc: &Document, warnings: &mut Vec<String>) -> Result<Extensions, ModelError> {
    let mut ext = Extensions::default();
    let root = doc.root_element();
    for node in root.children().filter(Node::is_element) {
        let tag = node.tag_name().name();
        let name = node.attribute("name").unwrap_or("").to_string();
        match tag {
            "link" => {
                if node.children().any(|c| c.has_tag_name("inertial")) {
                    ext.has_inertial.insert(name);
                }
            }
            "joint" => {
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
                let joint = node
                    .children()
                    .find(|c| c.has_tag_name("joint"))
                    .and_then(|j| j.attribute("name"))
                    .ok_or_else(|| {
                        bad(
                            "transmission",
                            &name,
                            "has no <joint name=\"...\"/>; name the actuated joint".into(),
                        )
                    })?;
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
                ext.transmissions.push((name, joint.to_string(), reduction));
            }
            _ if KNOWN_TOP_LEVEL.contains(&tag) => {}
            _ => warnings.push(format!(
                "line {}: element <{tag}{}> is not used by vito",
                doc.text_pos_at(node.range().start).row,
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

/// Unit vector, or `None` for a zero or non-finite vector.
fn normalized(v: [f64; 3]) -> Option<[f64; 3]> {
    let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (norm.is_finite() && norm > 1e-12).then(|| [v[0] / norm, v[1] / norm, v[2] / norm])
}

fn rpy(v: &[f64; 3]) -> [[f64; 3]; 3] {
    rpy_to_matrix(v[0], v[1], v[2])
}

/// Two unit vectors perpendicular to the unit `axis`: the other two coordinate axes when
/// `axis` is a coordinate axis, else an orthonormal pair.
fn perpendicular_pair(axis: [f64; 3]) -> [[f64; 3]; 2] {
    let unit = |k: usize| {
        let mut e = [0.0; 3];
        e[k] = 1.0;
        e
    };
    for (k, component) in axis.iter().enumerate() {
        if (component.abs() - 1.0).abs() < 1e-12 {
            let others: Vec<usize> = (0..3).filter(|&j| j != k).collect();
            return [unit(others[0]), unit(others[1])];
        }
    }
    let k = (0..3)
        .min_by(|&a, &b| axis[a].abs().total_cmp(&axis[b].abs()))
        .unwrap_or(0);
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let e1 = normalized(cross(axis, unit(k))).unwrap_or(unit(0));
    [e1, cross(axis, e1)]
}

/// Whether a symmetric 3×3 matrix is positive definite (Sylvester's criterion).
fn positive_definite(m: &[[f64; 3]; 3]) -> bool {
    let d1 = m[0][0];
    let d2 = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let d3 = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    d1 > 0.0 && d2 > 0.0 && d3 > 0.0 && m.iter().flatten().all(|x| x.is_finite())
}

fn transpose(m: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut t = [[0.0; 3]; 3];
    for (i, row) in m.iter().enumerate() {
        for (j, &x) in row.iter().enumerate() {
            t[j][i] = x;
        }
    }
    t
}

/// Mass, centre of mass, and inertia about the centre of mass (in the axes of the frame the
/// centre is given in).
type MassPiece = (f64, [f64; 3], [[f64; 3]; 3]);

/// A link's checked mass, centre of mass and inertia (about the centre of mass, in link
/// axes: the URDF inertia rotated by the inertial origin's rpy).
fn link_inertia(link: &urdf_rs::Link) -> Result<MassPiece, ModelError> {
    let inertial = &link.inertial;
    let mass = inertial.mass.value;
    if !(mass > 0.0 && mass.is_finite()) {
        return Err(ModelError::NonPositiveMass {
            link: link.name.clone(),
            mass,
        });
    }
    let i = &inertial.inertia;
    let urdf_inertia = [
        [i.ixx, i.ixy, i.ixz],
        [i.ixy, i.iyy, i.iyz],
        [i.ixz, i.iyz, i.izz],
    ];
    if !positive_definite(&urdf_inertia) {
        return Err(ModelError::InertiaNotPositiveDefinite {
            link: link.name.clone(),
            ixx: i.ixx,
            iyy: i.iyy,
            izz: i.izz,
            ixy: i.ixy,
            ixz: i.ixz,
            iyz: i.iyz,
        });
    }
    let r = rpy(&inertial.origin.rpy);
    let rotated = mat_mul(&mat_mul(&r, &urdf_inertia), &transpose(&r));
    Ok((mass, *inertial.origin.xyz, rotated))
}

/// Combines rigidly attached masses into one body: total mass, centre of mass, and the
/// inertia about it (parallel-axis theorem). Massless for no pieces.
fn lump(parts: &[MassPiece]) -> MassPiece {
    let mass: f64 = parts.iter().map(|p| p.0).sum();
    if mass == 0.0 {
        return (0.0, [0.0; 3], [[0.0; 3]; 3]);
    }
    if let [single] = parts {
        return *single;
    }
    let mut com = [0.0; 3];
    for (m, c, _) in parts {
        for k in 0..3 {
            com[k] += m * c[k] / mass;
        }
    }
    let mut inertia = [[0.0; 3]; 3];
    for (m, c, i) in parts {
        let d = [c[0] - com[0], c[1] - com[1], c[2] - com[2]];
        let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        for a in 0..3 {
            for b in 0..3 {
                let delta = if a == b { 1.0 } else { 0.0 };
                inertia[a][b] += i[a][b] + m * (d2 * delta - d[a] * d[b]);
            }
        }
    }
    (mass, com, inertia)
}

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

fn build(
    robot: &urdf_rs::Robot,
    ext: &Extensions,
    base: BaseType,
    mut warnings: Vec<String>,
) -> Result<Model, ModelError> {
    if robot.links.is_empty() {
        return Err(ModelError::NoLinks);
    }
    // Names.
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
    // Tree structure.
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
    // Coordinates: base, then non-fixed joints in document order.
    let base_names = base.coordinate_names();
    let base_frames = base_chain(base);
    let mut coordinate_names: Vec<String> = base_names.iter().map(|s| s.to_string()).collect();
    let mut coordinate_limits = vec![(f64::NEG_INFINITY, f64::INFINITY); base_names.len()];
    let mut damping = vec![0.0; base_names.len()];
    let mut joint_coordinate: Vec<Option<usize>> = vec![None; robot.joints.len()];
    for (j, joint) in robot.joints.iter().enumerate() {
        if joint.joint_type == urdf_rs::JointType::Fixed {
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
    // Frames: the virtual base chain, then the links in depth-first order.
    let mut frames: Vec<Frame> = Vec::with_capacity(base_frames.len() + robot.links.len());
    let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for (k, &(motion, axis, coordinate)) in base_frames.iter().enumerate() {
        frames.push(Frame::massless(
            k.checked_sub(1),
            identity,
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
    let mut total_mass = 0.0;
    for &l in &order {
        let link = &robot.links[l];
        let placement = match parent_joint[l] {
            None => {
                frames.push(Frame::massless(
                    frames.len().checked_sub(1),
                    identity,
                    [0.0; 3],
                    [1.0, 0.0, 0.0],
                    Motion::Fixed,
                    0,
                ));
                pieces.push(Vec::new());
                LinkPlacement {
                    frame: frames.len() - 1,
                    rotation: identity,
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
                    frames.push(Frame::massless(
                        Some(parent.frame),
                        rotation,
                        translation,
                        axis,
                        motion,
                        joint_coordinate[j].unwrap_or(0),
                    ));
                    pieces.push(Vec::new());
                    LinkPlacement {
                        frame: frames.len() - 1,
                        rotation: identity,
                        translation: [0.0; 3],
                    }
                }
            }
        };
        if ext.has_inertial.contains(&link.name) {
            let (mass, com, inertia) = link_inertia(link)?;
            total_mass += mass;
            let r = &placement.rotation;
            pieces[placement.frame].push((
                mass,
                placement.point_in_frame(&com),
                mat_mul(&mat_mul(r, &inertia), &transpose(r)),
            ));
        }
        placement_of[l] = Some(placement);
    }
    for (frame, parts) in frames.iter_mut().zip(&pieces) {
        (frame.mass, frame.com, frame.inertia) = lump(parts);
    }
    // Link ids follow the topological order.
    let link_names: Vec<String> = order.iter().map(|&l| robot.links[l].name.clone()).collect();
    let link_frame: Vec<LinkPlacement> = order
        .iter()
        .map(|&l| {
            placement_of[l].clone().ok_or(ModelError::Cycle {
                link: robot.links[l].name.clone(),
            })
        })
        .collect::<Result<_, _>>()?;
    let link_id = |name: &str| link_names.iter().position(|n| n == name).map(LinkId);
    // Contact points: zero-radius spheres, links in document order.
    let mut contact_points = Vec::new();
    for link in &robot.links {
        let is_point = |c: &&urdf_rs::Collision| matches!(c.geometry, urdf_rs::Geometry::Sphere { radius } if radius == 0.0);
        let n_points = link.collision.iter().filter(is_point).count();
        for (k, collision) in link.collision.iter().enumerate() {
            if !is_point(&collision) {
                continue;
            }
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
            });
        }
    }
    // Springs.
    let coordinate_of_joint = |element: &'static str, owner: &str, joint: &str| {
        let j = joint_of.get(joint).copied().ok_or_else(|| {
            bad(
                element,
                owner,
                format!("refers to joint '{joint}', which is not defined"),
            )
        })?;
        joint_coordinate[j].ok_or_else(|| {
            bad(
                element,
                owner,
                format!("acts on joint '{joint}', which is fixed and has no coordinate"),
            )
        })
    };
    let mut springs = Vec::with_capacity(ext.springs.len());
    for raw in &ext.springs {
        let coordinate = coordinate_of_joint("force_element", &raw.name, &raw.joint)?;
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
    // Loop closures.
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
    // Inputs.
    let mut input_names = Vec::new();
    let mut input_coordinates = Vec::new();
    let mut effort_limits = Vec::new();
    for (name, joint, reduction) in &ext.transmissions {
        let coordinate = coordinate_of_joint("transmission", name, joint)?;
        if *reduction != 1.0 {
            warnings.push(format!(
                "transmission '{name}': mechanicalReduction {reduction} ignored (vito uses 1)"
            ));
        }
        let j = joint_of[joint.as_str()];
        let has_limit = ext.limit_presence.get(joint).is_some_and(|p| p.0);
        let effort = if has_limit {
            robot.joints[j].limit.effort
        } else {
            f64::INFINITY
        };
        input_names.push(joint.clone());
        input_coordinates.push(coordinate);
        effort_limits.push(effort);
    }
    Ok(Model {
        frames,
        link_frame,
        link_names,
        coordinate_names,
        coordinate_limits,
        damping,
        input_names,
        input_coordinates,
        effort_limits,
        contact_points,
        springs,
        loop_closures,
        gravity: [0.0, 0.0, -9.81],
        total_mass,
        base,
        name: robot.name.clone(),
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pi_expressions() {
        let pi = std::f64::consts::PI;
        assert_eq!(eval_pi_expression("-pi/4"), Some(-pi / 4.0));
        assert_eq!(eval_pi_expression(" pi "), Some(pi));
        assert_eq!(eval_pi_expression("2*pi"), Some(2.0 * pi));
        assert_eq!(eval_pi_expression("-0.5*pi/2"), Some(-0.25 * pi));
        assert_eq!(eval_pi_expression("pie"), None);
        assert_eq!(eval_pi_expression("4/pi"), None);
    }

    #[test]
    fn perpendicular_pairs_are_orthonormal() {
        assert_eq!(
            perpendicular_pair([0.0, 1.0, 0.0]),
            [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
        );
        assert_eq!(
            perpendicular_pair([0.0, 0.0, -1.0]),
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        );
        let axis = normalized([1.0, 2.0, -0.5]).expect("non-zero");
        let [e1, e2] = perpendicular_pair(axis);
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        for (a, b, want) in [
            (e1, e1, 1.0),
            (e2, e2, 1.0),
            (e1, e2, 0.0),
            (e1, axis, 0.0),
            (e2, axis, 0.0),
        ] {
            assert!((dot(a, b) - want).abs() < 1e-15);
        }
    }

    #[test]
    fn lumping_two_point_masses() {
        // Two 1 kg points at x = ±1: mass 2, centre 0, Iyy = Izz = 2, Ixx = 0.
        let zero = [[0.0; 3]; 3];
        let (m, c, i) = lump(&[(1.0, [1.0, 0.0, 0.0], zero), (1.0, [-1.0, 0.0, 0.0], zero)]);
        assert_eq!((m, c), (2.0, [0.0; 3]));
        assert_eq!(i, [[0.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]]);
    }
}
