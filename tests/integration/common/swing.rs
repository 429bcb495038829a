//! The double pendulum's swing (`model::sample::double_pendulum`, both joints driven, no
//! contact): from hanging at rest to (shoulder 1.5, elbow −1.0) rad at rest in 1 s,
//! minimising Σ h‖u‖². A smooth plan whose tracking errors show the methods' orders.

use std::path::{Path, PathBuf};

/// The swing's problem file.
pub const PENDULUM_SWING_TOML: &str = r#"name = "pendulum-swing"
[robot]
urdf = "pendulum.urdf"
base = "fixed"
gravity = [0.0, 0.0, -9.81]
[contacts]
from_urdf = "none"
[horizon]
knots = 11
time_step = 0.1
[initial]
q = { shoulder = 0.0, elbow = 0.0 }
v = "zero"
[final]
q = { shoulder = 1.5, elbow = -1.0 }
tolerance = 0.0
[[cost]]
type = "input"
weights = { default = 1.0 }
time_weighted = true
[slack]
weight = 100.0
mode = "per_interval"
[initial_guess]
to = "final"
[solver]
integrator = "midpoint"
hessian = "exact"
[solver.ipopt]
tol = 1e-8
linear_solver = "mumps"
max_iter = 3000
"#;

/// Writes `pendulum.urdf` and `swing.toml` into `dir`; returns the problem file's path.
pub fn write_pendulum_swing(dir: &Path) -> PathBuf {
    std::fs::write(
        dir.join("pendulum.urdf"),
        vito::model::sample::double_pendulum(),
    )
    .expect("write pendulum.urdf");
    let file = dir.join("swing.toml");
    std::fs::write(&file, PENDULUM_SWING_TOML).expect("write swing.toml");
    file
}
