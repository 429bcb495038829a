//! The reference problems (docs/reference-problems.md), read from their problem files in `problems/`: the tests
//! solve and differentiate exactly what `vito solve problems/<name>.toml` does.

use std::path::PathBuf;

use vito::problem::{ProblemSpec, load};

/// The problem `problems/<file>.toml`, with no overrides.
pub fn problem(file: &str) -> ProblemSpec {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("problems")
        .join(format!("{file}.toml"));
    match load(&path, &[]) {
        Ok(loaded) => loaded.spec,
        Err(e) => panic!("{}: {e}", path.display()),
    }
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
