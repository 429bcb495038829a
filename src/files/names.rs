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

/// Whether `c` changes how text around it shows rather than showing itself: a control
/// character, or an invisible format character (the bidirectional overrides, embeddings and
/// isolates that reorder a name on screen, zero-width characters, line and paragraph
/// separators, the byte-order mark).
pub fn is_hidden_char(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{061C}'
                | '\u{200B}'..='\u{200F}'
                | '\u{2028}'..='\u{202E}'
                | '\u{2060}'..='\u{2069}'
                | '\u{FEFF}'
        )
}

/// `text` with every hidden character ([`is_hidden_char`]) but newline and tab written as an
/// escape (`\u{1b}`), so that a name from a URDF cannot send escape sequences to the terminal
/// or reorder what it shows.
pub fn escape_controls(text: &str) -> std::borrow::Cow<'_, str> {
    if !text
        .chars()
        .any(|c| is_hidden_char(c) && c != '\n' && c != '\t')
    {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if is_hidden_char(c) && c != '\n' && c != '\t' {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}

/// `text` as XML character data or an attribute value: `&`, `<`, `>`, `"`, `'` and carriage
/// return as references, and characters XML 1.0 forbids (controls other than tab, newline and carriage
/// return; U+FFFE, U+FFFF) as U+FFFD, so that any name keeps an SVG well-formed.
pub fn xml_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // A parser turns a raw carriage return into a newline.
            '\r' => out.push_str("&#13;"),
            '\t' | '\n' => out.push(c),
            c if c < ' ' || c == '\u{fffe}' || c == '\u{ffff}' => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
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
