//! `vito init`: a commented starter problem for a URDF, which `vito check` accepts as is.

#![warn(missing_docs)]

use crate::model::BaseType;
use crate::problem::{CoordinateKind, RobotInfo};

fn fmt_limit(x: f64) -> String {
    if x.is_finite() {
        format!("{x}")
    } else {
        "none".into()
    }
}

/// A starter problem: every coordinate named with its limits, the URDF contacts, a fixed
/// horizon, a state-tracking and an input cost, and the reference Ipopt options.
pub fn starter_problem(robot: &RobotInfo, base: BaseType, urdf: &str) -> String {
    let base_name = match base {
        BaseType::Fixed => "fixed",
        BaseType::Planar => "planar",
        BaseType::Floating => "floating",
    };
    let mut t = String::new();
    t.push_str(
        "# vito problem file (starter written by `vito init`; edit, then `vito check` it).\n",
    );
    t.push_str("# Units: SI (m, kg, s, rad, N, N·m) unless [robot] units says otherwise.\n");
    t.push_str("# Every coordinate, input and contact is addressed by its URDF name.\n\n");
    t.push_str("[robot]\n");
    t.push_str(&format!("urdf = {urdf:?}   # relative to this file\n"));
    t.push_str(&format!(
        "base = \"{base_name}\"   # fixed | planar | floating\n"
    ));
    t.push_str("gravity = [0.0, 0.0, -9.81]   # world frame, robot units\n");
    t.push_str("joint_limits = true   # apply the URDF joint limits on every knot\n\n");
    t.push_str("[contacts]\n");
    if robot.contacts.is_empty() {
        t.push_str(
            "# The URDF declares no point contacts (collision spheres of radius 0). Add some:\n",
        );
        t.push_str("# [[contacts.point]]\n# name = \"foot\"\n# link = \"...\"\n# point = [0.0, 0.0, 0.0]\n");
        t.push_str("from_urdf = \"none\"\n");
    } else {
        let names: Vec<String> = robot
            .contacts
            .iter()
            .map(|c| format!("{:?}", c.name))
            .collect();
        t.push_str(&format!(
            "from_urdf = \"all\"   # or a subset: [{}]\n",
            names.join(", ")
        ));
    }
    t.push_str("friction = 1.0   # Coulomb coefficient for every contact\n\n");
    t.push_str("[terrain]\nground_height = 0.0\n");
    t.push_str("# [[terrain.step]]   # a smoothed step: rise·½(1 + tanh((x − edge_x)/width))\n");
    t.push_str("# edge_x = 0.25\n# rise = 0.1\n# width = 0.005\n\n");
    t.push_str("[horizon]\nknots = 21\ntime_step = 0.05   # fixed h [s]; or total_time = [t_min, t_max] for free equal steps\n\n");
    t.push_str("[initial]\nv = \"zero\"   # \"zero\", \"free\" or a table by coordinate\n");
    t.push_str("[initial.q]   # q_1, fixed; every coordinate (limits from the URDF in comments)\n");
    for (i, name) in robot.coordinates.iter().enumerate() {
        let lim = robot.coordinate_limits[i];
        let unit = match robot.coordinate_kinds[i] {
            CoordinateKind::Linear => "m",
            CoordinateKind::Angular => "rad",
        };
        let value = if lim.lower > 0.0 && lim.lower.is_finite() {
            lim.lower
        } else if lim.upper < 0.0 && lim.upper.is_finite() {
            lim.upper
        } else {
            0.0
        };
        t.push_str(&format!(
            "{name} = {value:?}   # [{unit}] limits {} .. {}\n",
            fmt_limit(lim.lower),
            fmt_limit(lim.upper)
        ));
    }
    t.push_str("\n[final]   # q_N: coordinates not named keep their initial value\n");
    t.push_str("tolerance = 0.0   # q_N within goal ± tolerance (0: fixed)\n");
    t.push_str("[final.q]\n");
    if let Some(first) = robot.coordinates.first() {
        t.push_str(&format!("{first} = 0.0\n"));
    }
    t.push_str("\n# [[bounds]]   # extra bounds on one coordinate\n# coordinate = \"...\"\n# knots = \"all\"   # all | interior | first | last | [0, 5, 9]\n# lower = 0.0\n# upper = 1.0\n\n");
    t.push_str(&format!(
        "[inputs]\n# actuated = \"transmissions\" | \"all\" | [\"joint\", ...]; the inputs below are from {}\neffort_limits = true   # |u| ≤ URDF effort\n",
        robot.actuation
    ));
    if !robot.inputs.is_empty() {
        t.push_str(&format!(
            "# bounds = {{ {} = [-1.0, 1.0] }}\n",
            robot.inputs[0]
        ));
    }
    t.push('\n');
    t.push_str("# Every quadratic cost carries ½: ½ (x − target)ᵀ diag(w) (x − target).\n");
    t.push_str("[[cost]]\ntype = \"state_tracking\"   # towards the final goal, midpoint state\n");
    t.push_str(
        "q_weights = { default = 1.0 }\nv_weights = { default = 0.0 }\ntime_weighted = true\n\n",
    );
    if !robot.inputs.is_empty() {
        t.push_str("[[cost]]\ntype = \"input\"\nweights = { default = 0.01 }\n\n");
    }
    t.push_str("[slack]\nweight = 100.0   # α on Σ s (complementarity relaxation)\nmode = \"per_interval\"\n\n");
    t.push_str("[initial_guess]\nto = \"final\"   # q linear from q_1 to the goal; or warm_start = \"out/x/trajectory.csv\"\n\n");
    t.push_str("[solver]\nintegrator = \"midpoint\"   # midpoint | euler\nhessian = \"exact\"   # exact | lbfgs\n");
    t.push_str("[solver.ipopt]\ntol = 1e-6\nmax_iter = 3000\nmu_strategy = \"adaptive\"\nlinear_solver = \"mumps\"\n");
    t
}
