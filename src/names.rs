//! How messages list names (of coordinates, columns, links): a readable, bounded list.

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
