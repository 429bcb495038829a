//! The reference problems (docs/reference-problems.md): the one list `vito bench` runs by default and the
//! independent CasADi implementation ([`super::independent`]) implements.

use std::path::PathBuf;

/// The reference problems by name (`name` in each problem file, the section names of docs/reference-problems.md).
pub const NAMES: [&str; 4] = [
    "hopper-2d",
    "brick-3d",
    "spring-flamingo-walk",
    "littledog-step",
];

/// The problem file of reference problem `name`, relative to the repository root:
/// `problems/<name with '_' for '-'>.toml`.
pub fn file(name: &str) -> PathBuf {
    PathBuf::from(format!("problems/{}.toml", name.replace('-', "_")))
}

/// Whether `name` is a reference problem.
pub fn is_reference(name: &str) -> bool {
    NAMES.contains(&name)
}

#[cfg(test)]
mod tests {
    /// Every reference problem's file exists and names the problem as the list does.
    #[test]
    fn each_file_exists_and_carries_its_name() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        for name in super::NAMES {
            let text = std::fs::read_to_string(root.join(super::file(name)))
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(
                text.lines()
                    .any(|l| l.trim() == format!("name = \"{name}\"")),
                "{name}: its file names another problem"
            );
        }
        assert!(super::is_reference("brick-3d") && !super::is_reference("hamr-trot"));
    }
}
