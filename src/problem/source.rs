//! Where a field lives in a problem file: TOML paths ↔ lines, and nearest-name suggestions.

#![warn(missing_docs)]

use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// 1-based line of a byte offset in `text`.
pub fn line_of_offset(text: &str, offset: usize) -> usize {
    let end = offset.min(text.len());
    text.as_bytes()[..end]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// A TOML parser's or schema's error on `text` as `line N: message`, without the quote of the
/// text around it that its `Display` shows (the file may not be what it was named as: a link
/// to another file must not be shown).
pub fn toml_error_message(text: &str, e: &toml::de::Error) -> String {
    match e.span() {
        Some(span) => format!(
            "line {}: {}",
            line_of_offset(text, span.start),
            e.message().trim()
        ),
        None => e.message().trim().to_owned(),
    }
}

/// One step of a TOML path: a key or an array index.
#[derive(Debug, Clone, PartialEq)]
enum Segment {
    Key(String),
    Index(usize),
}

/// Splits `cost[2].weights.knee` into keys and indices.
fn segments(path: &str) -> Vec<Segment> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let mut rest = part;
        if let Some(open) = rest.find('[') {
            if open > 0 {
                out.push(Segment::Key(rest[..open].to_owned()));
            }
            rest = &rest[open..];
            while let Some(stripped) = rest.strip_prefix('[') {
                let Some(close) = stripped.find(']') else {
                    break;
                };
                if let Ok(i) = stripped[..close].parse() {
                    out.push(Segment::Index(i));
                }
                rest = &stripped[close + 1..];
            }
        } else if !rest.is_empty() {
            out.push(Segment::Key(rest.to_owned()));
        }
    }
    out
}

/// The 1-based line where the TOML path `path` is written in `text` (the key's line for a
/// table entry, the element's line for an array index), or `None` when it is not in the file.
pub fn line_of_path(text: &str, path: &str) -> Option<usize> {
    let doc = DeTable::parse(text).ok()?;
    let segs = segments(path);
    let mut span = None;
    let mut table: Option<&DeTable> = Some(doc.get_ref());
    let mut array: Option<&[Spanned<DeValue>]> = None;
    for seg in &segs {
        let value: &Spanned<DeValue> = match seg {
            Segment::Key(k) => {
                let (key, value) = table?.iter().find(|(key, _)| key.get_ref().as_ref() == k)?;
                span = Some(key.span());
                value
            }
            Segment::Index(i) => {
                let value = array?.get(*i)?;
                span = Some(value.span());
                value
            }
        };
        table = None;
        array = None;
        match value.get_ref() {
            DeValue::Table(t) => table = Some(t),
            DeValue::Array(a) => array = Some(a),
            _ => {}
        }
    }
    span.map(|s| line_of_offset(text, s.start))
}

/// The TOML path of the innermost key or element whose span holds `offset`, e.g.
/// `contacts.point[1].frition`; empty when none does.
pub fn path_at_offset(text: &str, offset: usize) -> String {
    let Ok(doc) = DeTable::parse(text) else {
        return String::new();
    };
    let mut path = String::new();
    walk_table(doc.get_ref(), offset, &mut path);
    path
}

fn walk_table(table: &DeTable, offset: usize, path: &mut String) -> bool {
    for (key, value) in table.iter() {
        let in_key = key.span().contains(&offset);
        let in_value = value.span().contains(&offset) || container_contains(value, offset);
        if in_key || in_value {
            if !path.is_empty() {
                path.push('.');
            }
            path.push_str(key.get_ref());
            if in_value {
                walk_value(value, offset, path);
            }
            return true;
        }
    }
    false
}

fn container_contains(value: &Spanned<DeValue>, offset: usize) -> bool {
    match value.get_ref() {
        DeValue::Table(t) => t.iter().any(|(k, v)| {
            k.span().contains(&offset)
                || v.span().contains(&offset)
                || container_contains(v, offset)
        }),
        DeValue::Array(a) => a
            .iter()
            .any(|v| v.span().contains(&offset) || container_contains(v, offset)),
        _ => value.span().contains(&offset),
    }
}

fn walk_value(value: &Spanned<DeValue>, offset: usize, path: &mut String) {
    match value.get_ref() {
        DeValue::Table(t) => {
            walk_table(t, offset, path);
        }
        DeValue::Array(a) => {
            for (i, v) in a.iter().enumerate() {
                if v.span().contains(&offset) || container_contains(v, offset) {
                    path.push_str(&format!("[{i}]"));
                    walk_value(v, offset, path);
                    return;
                }
            }
        }
        _ => {}
    }
}

/// Levenshtein distance between two strings (by chars).
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cost = usize::from(ca != cb);
            let next = (row[j] + 1).min(row[j + 1] + 1).min(prev + cost);
            prev = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

/// The valid name nearest to `name`, if it is close enough to be a plausible typo.
pub fn nearest<'a>(name: &str, valid: impl IntoIterator<Item = &'a str>) -> Option<String> {
    let lower = name.to_lowercase();
    let (best, distance) = valid
        .into_iter()
        .map(|v| (v, edit_distance(&lower, &v.to_lowercase())))
        .min_by_key(|&(_, d)| d)?;
    let limit = (name.chars().count() / 3).max(2);
    (distance <= limit).then(|| best.to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOC: &str = "name = \"x\"\n[robot]\nurdf = \"a.urdf\"\n\n[[cost]]\ntype = \"time\"\n\n[[cost]]\ntype = \"input\"\nweights = { knee = 1.0 }\n";

    #[test]
    fn finds_lines_of_nested_paths() {
        assert_eq!(line_of_path(DOC, "name"), Some(1));
        assert_eq!(line_of_path(DOC, "robot.urdf"), Some(3));
        assert_eq!(line_of_path(DOC, "cost[1].weights.knee"), Some(10));
        assert_eq!(line_of_path(DOC, "cost[1].nothing"), None);
    }

    #[test]
    fn finds_path_at_offset() {
        let offset = DOC.find("knee").unwrap();
        assert_eq!(path_at_offset(DOC, offset), "cost[1].weights.knee");
        let offset = DOC.find("a.urdf").unwrap();
        assert_eq!(path_at_offset(DOC, offset), "robot.urdf");
    }

    #[test]
    fn suggests_close_names_only() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        let valid = ["friction", "link", "point"];
        assert_eq!(nearest("frition", valid), Some("friction".into()));
        assert_eq!(nearest("zzzzzz", valid), None);
    }
}
