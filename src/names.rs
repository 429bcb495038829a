//! How messages list names (of coordinates, columns, links): a readable, bounded list, and
//! text made safe for a terminal.

/// Lists names for a message, at most `max` of them.
pub fn list_names<S: AsRef<str>>(names: &[S], max: usize) -> String {
    let mut out: Vec<String> = names
        .iter()
        .take(max)
        .map(|n| format!("`{}`", n.as_ref()))
        .collect();
    if names.len() > max {
        out.push(format!("… ({} in all)", names.len()));
    }
    if out.is_empty() {
        "(none)".into()
    } else {
        out.join(", ")
    }
}

/// `text` with every control character but newline and tab written as an escape (`\u{1b}`),
/// so that a name from a URDF cannot send escape sequences to the terminal.
pub fn escape_controls(text: &str) -> std::borrow::Cow<'_, str> {
    if !text
        .chars()
        .any(|c| c.is_control() && c != '\n' && c != '\t')
    {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if c.is_control() && c != '\n' && c != '\t' {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_escaped() {
        assert_eq!(
            escape_controls("a\u{1b}[31mb\n\tc\r"),
            "a\\u{1b}[31mb\n\tc\\r"
        );
        assert!(matches!(
            escape_controls("plain"),
            std::borrow::Cow::Borrowed(_)
        ));
    }
}
