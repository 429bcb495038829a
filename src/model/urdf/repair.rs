//! Textual repairs made before parsing, each listed as a warning: the original files of the
//! paper's robots need them.

use roxmltree::Document;

use super::xml_error;
use crate::model::ModelError;

/// A textual edit of the source: replace `range` by `text`.
struct Edit {
    range: std::ops::Range<usize>,
    text: String,
}

/// Makes the unambiguous repairs and returns the repaired text.
pub(super) fn repair(
    xml: &str,
    origin: &str,
    warnings: &mut Vec<String>,
) -> Result<String, ModelError> {
    let doc = Document::parse(xml).map_err(|e| xml_error(origin, e))?;
    let mut edits: Vec<Edit> = Vec::new();
    let lines = super::Lines::new(xml);
    let line = |pos: usize| lines.row(pos);
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
        // A visual material's `<texture/>` without a file (iCub's and Romeo's URDFs have
        // them): vito draws no textures, and the URDF reader refuses one without a file.
        if tag == "texture" && node.attribute("filename").is_none() {
            let material = node
                .parent_element()
                .filter(|p| p.has_tag_name("material"))
                .and_then(|p| p.attribute("name"))
                .map_or_else(String::new, |m| format!(" in <material name=\"{m}\">"));
            warnings.push(format!(
                "line {}: <texture>{material} has no filename and is not used by vito; ignored",
                line(node.range().start)
            ));
            edits.push(Edit {
                range: node.range(),
                text: String::new(),
            });
            continue;
        }
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
}
