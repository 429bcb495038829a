//! Errors of URDF loading: each names the file, link or joint and says how to fix it.

use std::path::PathBuf;

/// Why a URDF could not be turned into a [`crate::model::Model`].
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// The file could not be read.
    #[error("cannot read URDF file {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The text is not well-formed XML.
    #[error("{origin}: not well-formed XML: {message}; fix the XML syntax")]
    Xml {
        /// File path or `<string>`.
        origin: String,
        /// The parser's message (with line and column).
        message: String,
    },
    /// urdf-rs rejected the document.
    #[error("{origin}: not a valid URDF: {message}")]
    Urdf {
        /// File path or `<string>`.
        origin: String,
        /// urdf-rs's message.
        message: String,
    },
    /// A joint refers to a link that does not exist.
    #[error(
        "joint '{joint}' names {role} link '{link}', which is not defined; add <link name=\"{link}\"> or fix the name"
    )]
    MissingLink {
        /// The joint.
        joint: String,
        /// `parent` or `child`.
        role: &'static str,
        /// The missing link name.
        link: String,
    },
    /// Two links or two joints share a name.
    #[error("{kind} name '{name}' is used twice; names must be unique")]
    DuplicateName {
        /// `link` or `joint`.
        kind: &'static str,
        /// The repeated name.
        name: String,
    },
    /// A link is the child of more than one joint.
    #[error(
        "link '{link}' is the child of both joint '{first}' and joint '{second}'; a URDF is a tree, close loops with <loop_joint>"
    )]
    MultipleParents {
        /// The link.
        link: String,
        /// First joint.
        first: String,
        /// Second joint.
        second: String,
    },
    /// The joints form a cycle.
    #[error(
        "joints form a cycle through link '{link}'; a URDF is a tree, close loops with <loop_joint>"
    )]
    Cycle {
        /// A link on the cycle.
        link: String,
    },
    /// More than one link has no parent.
    #[error("the URDF has {} root links ({}); connect all but one with joints", roots.len(), roots.join(", "))]
    MultipleRoots {
        /// The parentless links.
        roots: Vec<String>,
    },
    /// No links at all.
    #[error("the URDF has no links")]
    NoLinks,
    /// Masses, inertias or mimic joints vito cannot use, all of a file's at once: each
    /// problem names the line and element and says how to fix it.
    #[error("{origin}: {} problem{} to fix:\n  - {}", problems.len(), if problems.len() == 1 { "" } else { "s" }, problems.join("\n  - "))]
    Invalid {
        /// File path or `<string>`.
        origin: String,
        /// One line per problem (`line N: <link name="x"> <inertial>: ...`).
        problems: Vec<String>,
    },
    /// A joint type vito does not model inside a URDF.
    #[error(
        "joint '{joint}' has type '{joint_type}', which vito does not support inside a URDF; use fixed, revolute, continuous or prismatic, and choose a planar/floating base with --base"
    )]
    UnsupportedJointType {
        /// The joint.
        joint: String,
        /// The type as written.
        joint_type: String,
    },
    /// A joint axis of zero length or with non-finite entries.
    #[error(
        "joint '{joint}' has axis {axis:?}, which has no direction; give a non-zero <axis xyz>"
    )]
    BadAxis {
        /// The joint (or loop joint).
        joint: String,
        /// The axis as read.
        axis: [f64; 3],
    },
    /// A base coordinate name collides with a joint name.
    #[error("joint '{joint}' has the same name as a base coordinate; rename the joint")]
    NameClash {
        /// The joint.
        joint: String,
    },
    /// The document is nested deeper, or has more links or joints, than vito reads.
    #[error("{origin}: {what}; vito reads URDFs up to {limit} ({fix})")]
    TooLarge {
        /// File path or `<string>`.
        origin: String,
        /// What was found (e.g. `elements nested 100000 deep`).
        what: String,
        /// The limit, as words.
        limit: String,
        /// How to fix it.
        fix: Box<str>,
    },
    /// An element is malformed: a Drake extension, or a value vito cannot use (a NaN
    /// origin, limits in the wrong order, a second transmission on a joint...).
    #[error("{element} '{name}': {problem}")]
    BadExtension {
        /// The element kind (`force_element`, `loop_joint`, `transmission`, `joint`, ...).
        element: &'static str,
        /// Its name attribute (or the joint it refers to).
        name: String,
        /// What is wrong and how to fix it.
        problem: String,
    },
}

/// `error` as a message that names the URDF `path` (errors about links and joints do not
/// carry the file; those about the text already start with it).
pub fn describe(path: &std::path::Path, error: &ModelError) -> String {
    let text = error.to_string();
    let shown = path.display().to_string();
    if text.contains(&shown) {
        text
    } else {
        format!("URDF {shown}: {text}")
    }
}
