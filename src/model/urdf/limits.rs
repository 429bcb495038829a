//! How deep and how large a URDF vito reads, checked before any parser sees the text: the
//! parsers recurse per nesting level (100,000 levels overflowed the stack), and the model's
//! memory and loading time grow with the links.

use roxmltree::Document;

use crate::model::ModelError;

/// Deepest element nesting read (a URDF needs about 6: robot, link, collision, geometry...).
pub(super) const MAX_DEPTH: usize = 64;

/// Most attributes on one element (a URDF's take at most 4 or so: `<inertia>` has 6).
pub(super) const MAX_ATTRIBUTES: usize = 64;

/// Most coordinates (degrees of freedom, base included) of a model. A block's sparsity
/// structure is discovered by tracing its function with dependency sets whose second-order
/// part is dense in the block's inputs, so checking a problem grows as about the cube of the
/// coordinates of a chain: measured on a serial chain, 0.26 s at 25, 2.4 s at 50 and
/// 18–86 s at 100 (quiet and loaded 2-core machine), over 300 s at 200, and an allocation of
/// 4 GB aborted at 1,000. Real legged robots have 10–60.
pub(super) const MAX_COORDINATES: usize = 100;

/// Most links, and most joints, read.
pub(super) const MAX_LINKS: usize = 10_000;

/// Most elements read: 20 per link at [`MAX_LINKS`] (a link with its inertial, a contact,
/// a visual and its joint is about 15; the project's largest robot has about 1,100 in all).
/// The URDF reader takes about 20 µs per element on a loaded 2-core machine (200,000
/// `<visual>` parts in one link, 800,000 elements, took 15.8 s).
pub(super) const MAX_ELEMENTS: usize = 200_000;

/// The byte offset just past the first `end` at or after `from` (the text's end if none).
fn skip_past(bytes: &[u8], from: usize, end: &[u8]) -> usize {
    bytes[from.min(bytes.len())..]
        .windows(end.len())
        .position(|w| w == end)
        .map_or(bytes.len(), |p| from + p + end.len())
}

/// Refuses text with more than [`MAX_ELEMENTS`] elements, whose elements nest deeper than
/// [`MAX_DEPTH`] or carry more than [`MAX_ATTRIBUTES`] attributes (the parsers check attribute names pairwise), or with an element or
/// attribute name that starts with `:` (XML allows it, roxmltree takes it, and urdf-rs's XML
/// library then panics on the empty namespace prefix), naming the line, by a scan that keeps
/// no stack (comments, CDATA, declarations and quoted attributes are skipped).
pub(super) fn check_nesting(xml: &str, origin: &str) -> Result<(), ModelError> {
    let bytes = xml.as_bytes();
    let mut depth = 0usize;
    let mut elements = 0usize;
    let mut i = 0;
    while let Some(p) = bytes[i..].iter().position(|&b| b == b'<') {
        let start = i + p;
        let rest = &bytes[start..];
        i = if rest.starts_with(b"<!--") {
            skip_past(bytes, start + 4, b"-->")
        } else if rest.starts_with(b"<![CDATA[") {
            skip_past(bytes, start + 9, b"]]>")
        } else if rest.starts_with(b"<?") {
            skip_past(bytes, start + 2, b"?>")
        } else if rest.starts_with(b"<!") || rest.starts_with(b"</") {
            if rest.starts_with(b"</") {
                depth = depth.saturating_sub(1);
            }
            skip_past(bytes, start + 2, b">")
        } else {
            // An opening tag: find its `>` outside quoted attribute values.
            elements += 1;
            if elements > MAX_ELEMENTS {
                let line = bytes[..start].iter().filter(|&&b| b == b'\n').count() + 1;
                return Err(ModelError::TooLarge {
                    origin: origin.to_owned(),
                    what: format!("it has more than {MAX_ELEMENTS} elements (line {line})"),
                    limit: format!("{MAX_ELEMENTS} elements"),
                    fix: "remove the visuals, collisions and elements vito does not read, or \
                          merge rigidly connected links"
                        .into(),
                });
            }
            let mut j = start + 1;
            let mut quote = None;
            let mut attributes = 0usize;
            while j < bytes.len() {
                match (quote, bytes[j]) {
                    (None, b'=') => {
                        attributes += 1;
                        if attributes > MAX_ATTRIBUTES {
                            let line = bytes[..start].iter().filter(|&&b| b == b'\n').count() + 1;
                            return Err(ModelError::TooLarge {
                                origin: origin.to_owned(),
                                what: format!(
                                    "an element at line {line} has more than {MAX_ATTRIBUTES} attributes"
                                ),
                                limit: format!("{MAX_ATTRIBUTES} attributes per element"),
                                fix: "a URDF element has a few attributes (name, xyz, rpy, …); \
                                      remove the others"
                                    .into(),
                            });
                        }
                    }
                    (None, b'"' | b'\'') => quote = Some(bytes[j]),
                    (Some(q), b) if b == q => quote = None,
                    (None, b'>') => break,
                    (None, b':') if bytes[j - 1] == b'<' || bytes[j - 1].is_ascii_whitespace() => {
                        let line = bytes[..j].iter().filter(|&&b| b == b'\n').count() + 1;
                        return Err(ModelError::Xml {
                            origin: origin.to_owned(),
                            message: format!(
                                "a name starts with `:` (an empty namespace prefix) at line {line}"
                            ),
                        });
                    }
                    _ => {}
                }
                j += 1;
            }
            if j > start + 1 && bytes.get(j - 1) != Some(&b'/') {
                depth += 1;
                if depth > MAX_DEPTH {
                    let line = bytes[..start].iter().filter(|&&b| b == b'\n').count() + 1;
                    return Err(ModelError::TooLarge {
                        origin: origin.to_owned(),
                        what: format!("elements nest more than {MAX_DEPTH} deep at line {line}"),
                        limit: format!("{MAX_DEPTH} levels deep"),
                        fix: "a URDF's elements sit a few levels below <robot>; close the open \
                              elements"
                            .into(),
                    });
                }
            }
            j + 1
        };
        if i >= bytes.len() {
            break;
        }
    }
    Ok(())
}

/// Refuses a document with more than [`MAX_LINKS`] links or joints.
pub(super) fn check_counts(doc: &Document, origin: &str) -> Result<(), ModelError> {
    for kind in ["link", "joint"] {
        let count = doc
            .root_element()
            .children()
            .filter(|n| n.has_tag_name(kind))
            .count();
        if count > MAX_LINKS {
            return Err(ModelError::TooLarge {
                origin: origin.to_owned(),
                what: format!("it has {count} <{kind}> elements"),
                limit: format!("{MAX_LINKS} links and {MAX_LINKS} joints"),
                fix: "merge rigidly connected links, or split the model".into(),
            });
        }
    }
    Ok(())
}

/// Refuses a model with more than [`MAX_COORDINATES`] coordinates, naming joints whose
/// fixing would bring it within the limit ([`joints_to_fix`]).
pub(super) fn check_coordinates(
    model: &crate::model::Model,
    robot: &urdf_rs::Robot,
    origin: &str,
) -> Result<(), ModelError> {
    let n = model.nq();
    if n > MAX_COORDINATES {
        let base = model.base().coordinate_names().len();
        let mut fix = String::from("make joints that need not move `fixed`");
        if let Some(hint) = joints_to_fix(robot, n - MAX_COORDINATES) {
            fix.push_str(&format!(", {hint}"));
        }
        if base > 0 && n - base <= MAX_COORDINATES {
            fix.push_str(&format!(
                "; or load it with `--base fixed` ({} coordinates)",
                n - base
            ));
        }
        fix.push_str("; or model fewer links");
        return Err(ModelError::TooLarge {
            origin: origin.to_owned(),
            what: format!("it has {n} coordinates (moving joints and base)"),
            limit: format!("{MAX_COORDINATES} coordinates"),
            fix: fix.into(),
        });
    }
    Ok(())
}

/// Which joints to make fixed to drop at least `excess` coordinates: the moving joints
/// below the branching links nearest the ends of the tree (a hand's palm, whose fingers
/// branch from it), largest first, as many as it takes. `None` when no such link holds
/// `excess` of them.
fn joints_to_fix(robot: &urdf_rs::Robot, excess: usize) -> Option<String> {
    use std::collections::HashMap;
    let index: HashMap<&str, usize> = robot
        .links
        .iter()
        .enumerate()
        .map(|(i, l)| (l.name.as_str(), i))
        .collect();
    let mut children: Vec<Vec<(usize, bool)>> = vec![Vec::new(); robot.links.len()];
    let mut has_parent = vec![false; robot.links.len()];
    for joint in &robot.joints {
        let (Some(&p), Some(&c)) = (
            index.get(joint.parent.link.as_str()),
            index.get(joint.child.link.as_str()),
        ) else {
            continue;
        };
        let moves = joint.joint_type != urdf_rs::JointType::Fixed && joint.mimic.is_none();
        children[p].push((c, moves));
        has_parent[c] = true;
    }
    // Coordinates below each link, and whether a branching link lies below it, by one
    // pass children first (a depth-first order; the tree was checked when the model was
    // built).
    let root = has_parent.iter().position(|&h| !h)?;
    let mut order = Vec::with_capacity(robot.links.len());
    let mut stack = vec![root];
    while let Some(l) = stack.pop() {
        order.push(l);
        stack.extend(children[l].iter().map(|&(c, _)| c));
    }
    let mut below = vec![0usize; robot.links.len()];
    let mut branching_below = vec![false; robot.links.len()];
    let mut ends: Vec<usize> = Vec::new();
    for &l in order.iter().rev() {
        let moving_branches = children[l]
            .iter()
            .filter(|&&(c, moves)| moves || below[c] > 0)
            .count();
        below[l] = children[l]
            .iter()
            .map(|&(c, moves)| below[c] + usize::from(moves))
            .sum();
        let deeper = children[l].iter().any(|&(c, _)| branching_below[c]);
        let branches = moving_branches >= 2;
        if branches && !deeper && l != root {
            ends.push(l);
        }
        branching_below[l] = branches || deeper;
    }
    ends.sort_by_key(|&l| std::cmp::Reverse(below[l]));
    let mut dropped = 0;
    let mut named = Vec::new();
    for &l in &ends {
        if dropped >= excess {
            break;
        }
        dropped += below[l];
        named.push(format!(
            "the {} below link `{}`",
            below[l], robot.links[l].name
        ));
    }
    (dropped >= excess).then(|| format!("e.g. {}", named.join(" and ")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nesting_is_measured_without_recursion() {
        let ok = "<?xml version=\"1.0\"?><!-- <a><a><a> --><robot name=\"a>b\"><link name=\"x\"/>\
                  <link name=\"y\"><![CDATA[<a><a>]]></link></robot>";
        assert!(check_nesting(ok, "t").is_ok());
        let deep = format!(
            "<robot>\n{}{}</robot>",
            "<a>".repeat(100_000),
            "</a>".repeat(100_000)
        );
        let err = check_nesting(&deep, "t.urdf").unwrap_err().to_string();
        assert!(err.contains("t.urdf") && err.contains("line 2"), "{err}");
        let flat = format!("<robot>{}</robot>", "<a></a>".repeat(100_000));
        assert!(check_nesting(&flat, "t").is_ok());
        let err = check_nesting("<robot>\n<joint :ame=\"x\"/></robot>", "t").unwrap_err();
        assert!(
            err.to_string()
                .contains("`:` (an empty namespace prefix) at line 2"),
            "{err}"
        );
        assert!(check_nesting("<robot a=\"x :y\"/>", "t").is_ok());
    }

    /// Elements are counted (not comments or closing tags): the limit is refused with
    /// the file and the fix, before any parser reads the text.
    #[test]
    fn elements_are_counted_up_to_the_limit() {
        let doc = |n: usize| format!("<robot>\n{}<!-- c --></robot>", "<link/>".repeat(n));
        assert!(check_nesting(&doc(MAX_ELEMENTS - 1), "t").is_ok());
        let err = check_nesting(&doc(MAX_ELEMENTS), "t.urdf")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("t.urdf") && err.contains("more than 200000 elements"),
            "{err}"
        );
    }
}
