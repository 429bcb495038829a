//! The robots of `problems/robots/` as the model tests load them.

use std::path::PathBuf;

use vito::model::{BaseType, Model};

/// `problems/robots/<rel>`.
pub fn robot_path(rel: &str) -> PathBuf {
    super::problems_dir().join("robots").join(rel)
}

/// The model of `problems/robots/<rel>` on base `base`; a file that does not load panics,
/// naming it.
pub fn robot(rel: &str, base: BaseType) -> Model {
    let path = robot_path(rel);
    Model::from_urdf_file(&path, base).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The paper's robots, by name: the spring flamingo (passive ankles) on a planar base,
/// LittleDog and HAMR on floating bases, each with the model's default gravity.
pub fn paper_robots() -> Vec<(&'static str, Model)> {
    vec![
        (
            "spring_flamingo",
            robot(
                "spring_flamingo/spring_flamingo_passive_ankle.normalized.urdf",
                BaseType::Planar,
            ),
        ),
        (
            "littledog",
            robot("littledog/LittleDog.normalized.urdf", BaseType::Floating),
        ),
        (
            "hamr",
            robot("hamr/HAMR_scaledV2.normalized.urdf", BaseType::Floating),
        ),
    ]
}
