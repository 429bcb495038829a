//! A path as a file in another directory would name it: relative where the two share a
//! prefix, so that a problem file or a regression record can move with what it names.

use std::path::{Path, PathBuf};

/// `target` relative to `dir` when both are relative or share a prefix below the root; else
/// absolute (not `../../../usr/share/…` up to the root).
pub fn relative_path(target: &Path, dir: &Path) -> String {
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_owned());
    let (t, d) = (abs(target), abs(dir));
    let common = t
        .components()
        .zip(d.components())
        .take_while(|(a, b)| a == b)
        .count();
    if common <= 1 {
        return t.display().to_string();
    }
    let ups = d.components().count() - common;
    let mut rel = PathBuf::new();
    for _ in 0..ups {
        rel.push("..");
    }
    for c in t.components().skip(common) {
        rel.push(c);
    }
    rel.display().to_string()
}

/// How a file written to `out` names `target`: relative to `out`'s directory, or as given
/// when the file goes to stdout or to the working directory ([`relative_path`]).
pub fn reference_from(target: &Path, out: Option<&Path>) -> String {
    match out.and_then(Path::parent) {
        Some(dir) if !dir.as_os_str().is_empty() => relative_path(target, dir),
        _ => target.display().to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_between_siblings_and_from_the_working_directory() {
        assert_eq!(
            relative_path(Path::new("a/robots/r.urdf"), Path::new("a/problems")),
            "../robots/r.urdf"
        );
        assert_eq!(
            relative_path(Path::new("p/x.toml"), Path::new(".")),
            "p/x.toml"
        );
        assert_eq!(
            reference_from(Path::new("r.urdf"), Some(Path::new("out/p.toml"))),
            "../r.urdf"
        );
        assert_eq!(
            reference_from(Path::new("robots/r.urdf"), Some(Path::new("p.toml"))),
            "robots/r.urdf"
        );
        assert_eq!(
            reference_from(Path::new("robots/r.urdf"), None),
            "robots/r.urdf"
        );
    }

    /// Only the root in common: the absolute path, not `../../..` up to the root.
    #[test]
    fn a_path_meeting_only_at_the_root_stays_absolute() {
        assert_eq!(
            reference_from(
                Path::new("/usr/share/robots/a.urdf"),
                Some(Path::new("/tmp/project/p.toml"))
            ),
            "/usr/share/robots/a.urdf"
        );
        assert_eq!(
            reference_from(
                Path::new("/tmp/robots/a.urdf"),
                Some(Path::new("/tmp/project/p.toml"))
            ),
            "../robots/a.urdf"
        );
    }
}
