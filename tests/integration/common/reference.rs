//! The reference problems (docs/reference-problems.md), read from their problem files in `problems/`: the tests
//! solve and differentiate exactly what `vito solve problems/<name>.toml` does.

use vito::problem::{LoadedProblem, Override, ProblemError, ProblemSpec, load, load_from_str};

/// `overrides` (`KEY.PATH=VALUE`, as `--set` takes them) parsed.
pub fn parsed(overrides: &[&str]) -> Vec<Override> {
    overrides
        .iter()
        .map(|o| Override::parse(o).unwrap_or_else(|e| panic!("{o}: {e}")))
        .collect()
}

/// The problem `problems/<file>.toml` loaded with `overrides`.
pub fn loaded(file: &str, overrides: &[&str]) -> LoadedProblem {
    let path = super::problems_dir().join(format!("{file}.toml"));
    load(&path, &parsed(overrides)).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The problem `problems/<file>.toml`, with no overrides.
pub fn problem(file: &str) -> ProblemSpec {
    loaded(file, &[]).spec
}

/// `problems/<file>.toml` with `extra` appended to its text, its robot read from
/// `problems/<urdf>`, loaded with `overrides`: the reference problem as an edited file.
pub fn appended(
    file: &str,
    urdf: &str,
    extra: &str,
    overrides: &[&str],
) -> Result<LoadedProblem, ProblemError> {
    let dir = super::problems_dir();
    let path = dir.join(format!("{file}.toml"));
    let text = std::fs::read_to_string(&path).unwrap() + extra;
    let urdf = std::fs::read_to_string(dir.join(urdf)).unwrap();
    load_from_str(&path, &text, &urdf, &parsed(overrides))
}

/// The hopper reference problem with `extra` appended.
pub fn hopper_appended(extra: &str) -> Result<LoadedProblem, ProblemError> {
    appended("hopper_2d", "robots/hopper_2d.urdf", extra, &[])
}

/// hopper-2d: the planar hopper hops 0.5 m in 1 s (N = 21, h = 0.05).
pub fn hopper_2d() -> ProblemSpec {
    problem("hopper_2d")
}

/// brick-3d: a tumbling brick falls and comes to rest (N = 41, h = 0.025).
pub fn brick_3d() -> ProblemSpec {
    problem("brick_3d")
}

/// spring-flamingo-walk: Spring Flamingo walks 0.9 m in free time (N = 25).
pub fn spring_flamingo_walk() -> ProblemSpec {
    problem("spring_flamingo_walk")
}

/// littledog-step: LittleDog climbs an 11 cm step, 0.45 m forward, in free time (N = 30).
pub fn littledog_step() -> ProblemSpec {
    problem("littledog_step")
}
