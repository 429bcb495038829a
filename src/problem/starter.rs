//! `vito init`: a commented starter problem for a URDF, which `vito check` accepts as is.
//! For a robot with a free base it is a stand-in-place problem that `vito solve` solves
//! unchanged: the feet found (collision spheres, else end links named like feet, else the
//! lowest end links), the robot standing on flat ground in a nominal pose with its lowest
//! feet at z = 0.

#![warn(missing_docs)]

use crate::model::{BaseType, Model, point_position};
use crate::problem::{CoordinateKind, RobotInfo};

fn fmt_limit(x: f64) -> String {
    if x.is_finite() {
        format!("{x}")
    } else {
        "none".into()
    }
}

/// `name` as a TOML key: bare when TOML reads it as one key (letters, digits, `_`, `-`),
/// else quoted (a dotted joint name such as `joint_0.0` would be read as a table).
fn toml_key(name: &str) -> String {
    let bare = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if bare {
        name.to_string()
    } else {
        toml_string(name)
    }
}

/// `text` as a TOML basic string, with TOML's escapes (Rust's `{:?}` writes `\u{1b}`,
/// which TOML refuses).
fn toml_string(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Renames feet whose `trajectory.csv` columns would clash with the robot's coordinates,
/// inputs or another foot (a link `base` beside a free base's `base_x`): `<name>_foot`,
/// then `<name>_foot2`, … A renamed URDF contact is written out as a point of its own.
fn clash_free(robot: &RobotInfo, feet: &mut [Foot]) {
    use crate::files::trajectory_csv::{ColumnUnits, columns, repeated_column};
    let units = ColumnUnits {
        time: String::new(),
        length: String::new(),
        coordinates: Vec::new(),
        inputs: Vec::new(),
        impulse: String::new(),
    };
    // As `vito check` lists them: 4 friction directions, one slack per interval.
    let clashes = |names: &[String]| {
        repeated_column(&columns(
            &robot.coordinates,
            &robot.inputs,
            names,
            4,
            1,
            &units,
        ))
        .is_some()
    };
    let mut chosen: Vec<String> = Vec::with_capacity(feet.len());
    let tries = feet.len() + 2;
    for foot in feet.iter_mut() {
        let original = foot.name.clone();
        let mut k = 0;
        loop {
            let candidate = match k {
                0 => original.clone(),
                1 => format!("{original}_foot"),
                _ => format!("{original}_foot{k}"),
            };
            chosen.push(candidate);
            if !clashes(&chosen) || k > tries {
                break;
            }
            chosen.pop();
            k += 1;
        }
        if let Some(name) = chosen.last()
            && *name != original
        {
            foot.name = name.clone();
            foot.from_urdf = false;
        }
    }
}

/// The `from_urdf` line for these feet: `"all"` when every URDF contact is among them under
/// its own name, else the list of those that are, or `"none"`.
fn from_urdf_line(robot: &RobotInfo, feet: &[Foot], comment: &str) -> String {
    let kept: Vec<String> = feet
        .iter()
        .filter(|f| f.from_urdf)
        .map(|f| toml_string(&f.name))
        .collect();
    if !robot.contacts.is_empty() && kept.len() == robot.contacts.len() {
        format!("from_urdf = \"all\"   # {comment}\n")
    } else if kept.is_empty() {
        "from_urdf = \"none\"\n".into()
    } else {
        format!("from_urdf = [{}]   # {comment}\n", kept.join(", "))
    }
}

/// A `[[contacts.point]]` for each foot that is not a URDF contact under its own name.
fn contact_points(feet: &[Foot]) -> String {
    let mut t = String::new();
    for foot in feet.iter().filter(|f| !f.from_urdf) {
        t.push_str(&format!(
            "[[contacts.point]]   # an end link of the URDF\nname = {}\nlink = {}\npoint = [{:?}, {:?}, {:?}]   # in the link frame [m]\nradius = {:?}   # a sphere around point [m]; 0: a point\n",
            toml_string(&foot.name), toml_string(&foot.link), foot.centre[0], foot.centre[1], foot.centre[2], foot.radius
        ));
    }
    t
}

/// Names of end links that are feet.
const FOOT_WORDS: [&str; 5] = ["foot", "feet", "toe", "sole", "paw"];

/// A foot the starter stands the robot on: a URDF collision sphere, or a point at an end
/// link's origin.
struct Foot {
    name: String,
    link: String,
    centre: [f64; 3],
    radius: f64,
    from_urdf: bool,
}

/// The nominal pose: every joint at 0, or at its limits' midpoint where 0 is outside them
/// (at the finite limit when the other is infinite); the base at the origin.
fn nominal_pose(robot: &RobotInfo) -> Vec<f64> {
    robot
        .coordinate_limits
        .iter()
        .map(|lim| {
            let (lo, hi) = (lim.lower, lim.upper);
            if (lo..=hi).contains(&0.0) {
                0.0
            } else if lo.is_finite() && hi.is_finite() {
                0.5 * (lo + hi)
            } else if lo.is_finite() {
                lo
            } else {
                hi
            }
        })
        .collect()
}

/// The URDF's collision spheres as feet.
fn urdf_feet(robot: &RobotInfo) -> Vec<Foot> {
    robot
        .contacts
        .iter()
        .map(|c| Foot {
            name: c.name.clone(),
            link: c.link.clone(),
            centre: c.point,
            radius: c.radius,
            from_urdf: true,
        })
        .collect()
}

/// The feet: the URDF's collision spheres; else end links named like feet; else the end
/// links lowest in the nominal pose (within 2 % of the robot's height).
fn find_feet(model: &Model, robot: &RobotInfo, q: &[f64]) -> Vec<Foot> {
    if !robot.contacts.is_empty() {
        return urdf_feet(robot);
    }
    let at_origin = |link: &String| Foot {
        name: link.clone(),
        link: link.clone(),
        centre: [0.0; 3],
        radius: 0.0,
        from_urdf: false,
    };
    let leaves = model.leaf_links();
    let named: Vec<Foot> = leaves
        .iter()
        .filter(|l| {
            let lower = l.to_lowercase();
            FOOT_WORDS.iter().any(|w| lower.contains(w))
        })
        .map(at_origin)
        .collect();
    if !named.is_empty() {
        return named;
    }
    let heights: Vec<f64> = leaves
        .iter()
        .map(|l| height(model, &at_origin(l), q))
        .collect();
    let lowest = heights.iter().copied().fold(f64::INFINITY, f64::min);
    let highest = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let band = 0.02 * (highest - lowest);
    leaves
        .iter()
        .zip(&heights)
        .filter(|&(_, &z)| z <= lowest + band)
        .map(|(l, _)| at_origin(l))
        .collect()
}

/// The height of a foot's lowest point at `q`.
fn height(model: &Model, foot: &Foot, q: &[f64]) -> f64 {
    model.link_index(&foot.link).map_or(0.0, |link| {
        point_position(model, link, &foot.centre, q)[2] - foot.radius
    })
}

/// The coordinate that lifts every foot straight up, one to one: a translation coordinate
/// ([`Model::translation_coordinates`]) along world z, a free base's `base_z` or a URDF's own
/// vertical slider.
fn lift_coordinate(model: &Model, feet: &[Foot], q: &[f64]) -> Option<usize> {
    model
        .translation_coordinates()
        .iter()
        .enumerate()
        .filter(|&(_, &t)| t)
        .map(|(j, _)| j)
        .find(|&j| {
            let mut up = q.to_vec();
            up[j] += 1.0;
            !feet.is_empty()
                && feet
                    .iter()
                    .all(|f| (height(model, f, &up) - height(model, f, q) - 1.0).abs() < 1e-9)
        })
}

/// `q` with the robot lifted ([`lift_coordinate`]) so that its lowest foot touches z = 0,
/// where a coordinate can lift it.
fn lift_onto_ground(model: &Model, feet: &[Foot], q: &mut [f64]) {
    let lowest = feet
        .iter()
        .map(|f| height(model, f, q))
        .fold(f64::INFINITY, f64::min);
    if let Some(z) = lift_coordinate(model, feet, q)
        && lowest.is_finite()
    {
        q[z] -= lowest;
    }
}

/// The stand-in-place pose and its feet: the nominal pose with the base raised so that the
/// lowest feet touch z = 0.
fn standing(model: &Model, robot: &RobotInfo) -> (Vec<f64>, Vec<Foot>) {
    let mut q = nominal_pose(robot);
    let feet = find_feet(model, robot, &q);
    lift_onto_ground(model, &feet, &mut q);
    (q, feet)
}

/// A starter problem: every coordinate named with its limits, the contacts, a fixed
/// horizon, a state-tracking and an input cost, and the reference Ipopt options. With a
/// fixed base it moves the first coordinate to 0; with a free base it stands in place on
/// its feet (`model` finds them and the base height).
///
/// A fixed-base robot whose contacts would start below z = 0 (nothing lifts it) stands on
/// ground lowered to its lowest contact.
pub fn starter_problem(model: &Model, robot: &RobotInfo, base: BaseType, urdf: &str) -> String {
    if base != BaseType::Fixed {
        return standing_problem(model, robot, base, urdf);
    }
    let contacts = urdf_feet(robot);
    let mut pose = nominal_pose(robot);
    lift_onto_ground(model, &contacts, &mut pose);
    // A robot bolted down with contacts below its root (an arm's collision spheres around
    // its mounting) stands on ground lowered to its lowest contact, rounded down to the mm.
    let lowest = contacts
        .iter()
        .map(|f| height(model, f, &pose))
        .fold(0.0, f64::min);
    let ground = if lowest < 0.0 {
        // Down to the mm, unless within round-off of one (the brick's −0.025 m).
        let mm = lowest * 1000.0;
        let down = if (mm - mm.round()).abs() < 1e-9 {
            mm.round()
        } else {
            mm.floor()
        };
        (down / 1000.0).min(lowest)
    } else {
        0.0
    };
    let mut feet = contacts;
    clash_free(robot, &mut feet);
    let mut t = robot_section(base, urdf);
    t.push_str("[contacts]\n");
    if feet.is_empty() {
        t.push_str(
            "# The URDF declares no point contacts (collision spheres of radius 0). Add some:\n",
        );
        t.push_str("# [[contacts.point]]\n# name = \"foot\"\n# link = \"...\"\n# point = [0.0, 0.0, 0.0]\n");
        t.push_str("from_urdf = \"none\"\n");
    } else {
        t.push_str(&from_urdf_line(robot, &feet, "or a subset of them"));
    }
    t.push_str("friction = 1.0   # Coulomb coefficient for every contact\n");
    t.push_str(&contact_points(&feet));
    t.push('\n');
    if ground < 0.0 {
        t.push_str(&format!(
            "[terrain]\nground_height = {ground:?}   # [m] at the lowest contact (the root is bolted at z = 0)\n"
        ));
    } else {
        t.push_str("[terrain]\nground_height = 0.0\n");
    }
    t.push_str("# [[terrain.step]]   # a smoothed step: rise·½(1 + tanh((x − edge_x)/width))\n");
    t.push_str("# edge_x = 0.25\n# rise = 0.1\n# width = 0.005\n\n");
    t.push_str("[horizon]\nknots = 21\ntime_step = 0.05   # fixed h [s]; or total_time = [t_min, t_max] for free equal steps\n\n");
    t.push_str("[initial]\nv = \"zero\"   # \"zero\", \"free\" or a table by coordinate\n");
    t.push_str("[initial.q]   # q_1, fixed; every coordinate (limits from the URDF in comments)\n");
    t.push_str(&pose_table(robot, &pose));
    t.push_str("\n[final]   # q_N: coordinates not named keep their initial value\n");
    t.push_str("tolerance = 0.0   # q_N within goal ± tolerance (0: fixed)\n");
    t.push_str("[final.q]\n");
    if let Some(first) = robot.coordinates.first() {
        t.push_str(&format!("{} = 0.0\n", toml_key(first)));
    }
    t.push_str("\n# [[bounds]]   # extra bounds on one coordinate\n# coordinate = \"...\"\n# knots = \"all\"   # all | interior | first | last | [0, 5, 9]\n# lower = 0.0\n# upper = 1.0\n\n");
    t.push_str(&format!(
        "[inputs]\n# actuated = \"transmissions\" | \"all\" | [\"joint\", ...]; the inputs below are from {}\neffort_limits = true   # |u| ≤ URDF effort\n",
        robot.actuation
    ));
    if !robot.inputs.is_empty() {
        t.push_str(&format!(
            "# bounds = {{ {} = [-1.0, 1.0] }}\n",
            toml_key(&robot.inputs[0])
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
    t.push_str(&steering_examples(feet.iter().map(|f| f.name.as_str())));
    t.push_str("[slack]\nweight = 100.0   # α on Σ s (complementarity relaxation)\nmode = \"per_interval\"\n\n");
    t.push_str("[initial_guess]\nto = \"final\"   # q linear from q_1 to the goal; or warm_start = \"out/x/trajectory.csv\"\n\n");
    t.push_str(&solver_section());
    t
}

/// The `[solver]` sections of every starter.
/// The starter's `[solver]` section; its integrator comment lists every integrator.
fn solver_section() -> String {
    let integrators: Vec<&str> = crate::discrete::Integrator::ALL
        .iter()
        .map(|i| i.name())
        .collect();
    format!(
        "[solver]\nintegrator = \"midpoint\"   # {}\nhessian = \"exact\"   # exact | lbfgs\n[solver.ipopt]\ntol = 1e-6\nmax_iter = 3000\nmu_strategy = \"adaptive\"\nlinear_solver = \"mumps\"\n",
        integrators.join(" | ")
    )
}

/// The header and `[robot]` section of every starter.
fn robot_section(base: BaseType, urdf: &str) -> String {
    let base_name = base.name();
    let mut t = String::new();
    t.push_str(
        "# vito problem file (starter written by `vito init`; edit, then `vito check` it).\n",
    );
    t.push_str("# Units: SI (m, kg, s, rad, N, N·m) unless [robot] units says otherwise.\n");
    t.push_str("# Every coordinate, input and contact is addressed by its URDF name.\n\n");
    t.push_str("[robot]\n");
    t.push_str(&format!(
        "urdf = {}   # relative to this file\n",
        toml_string(urdf)
    ));
    t.push_str(&format!(
        "base = \"{base_name}\"   # fixed | planar | floating\n"
    ));
    t.push_str("gravity = [0.0, 0.0, -9.81]   # world frame, robot units\n");
    t.push_str("joint_limits = true   # apply the URDF joint limits on every knot\n\n");
    t
}

/// `[initial.q]`: every coordinate at `q`, its unit and limits in a comment.
fn pose_table(robot: &RobotInfo, q: &[f64]) -> String {
    let mut t = String::new();
    for (i, name) in robot.coordinates.iter().enumerate() {
        let lim = robot.coordinate_limits[i];
        let unit = match robot.coordinate_kinds[i] {
            CoordinateKind::Linear => "m",
            CoordinateKind::Angular => "rad",
        };
        t.push_str(&format!(
            "{} = {:?}   # [{unit}] limits {} .. {}\n",
            toml_key(name),
            q[i],
            fmt_limit(lim.lower),
            fmt_limit(lim.upper)
        ));
    }
    t
}

/// A free-base robot standing in place on its feet for half a second.
fn standing_problem(model: &Model, robot: &RobotInfo, base: BaseType, urdf: &str) -> String {
    let (q, mut feet) = standing(model, robot);
    clash_free(robot, &mut feet);
    let mut t = robot_section(base, urdf);
    t.push_str("# A stand-in-place problem: the robot stands on flat ground in a nominal pose\n");
    t.push_str("# (joints at 0, or mid-range where 0 is outside their limits), its lowest feet\n");
    t.push_str("# touching z = 0, and holds that pose. Solve it as is, then edit the goal.\n\n");
    t.push_str("[contacts]   # the feet\n");
    if feet.is_empty() {
        t.push_str("# No feet found (no collision spheres, no end links): add contacts.\n");
        t.push_str("# [[contacts.point]]\n# name = \"foot\"\n# link = \"...\"\n# point = [0.0, 0.0, 0.0]\n# radius = 0.0\n");
        t.push_str("from_urdf = \"none\"\n");
    } else {
        t.push_str(&from_urdf_line(
            robot,
            &feet,
            "the URDF's collision spheres",
        ));
    }
    t.push_str("friction = 1.0   # Coulomb coefficient for every contact\n");
    t.push_str(&contact_points(&feet));
    t.push_str("\n[terrain]\nground_height = 0.0\n\n");
    t.push_str("[horizon]\nknots = 11\ntime_step = 0.05   # fixed h [s]: T = 0.5 s\n\n");
    t.push_str("[initial]\nv = \"zero\"   # at rest\n");
    t.push_str("[initial.q]   # q_1, fixed: the standing pose (base height from the feet)\n");
    t.push_str(&pose_table(robot, &q));
    t.push_str("\n[final]   # q_N = q_1: stand in place\n");
    t.push_str("tolerance = 0.0   # q_N within goal ± tolerance (0: fixed)\n");
    t.push_str("[final.q]   # coordinates not named keep their initial value\n");
    if let Some(first) = robot.coordinates.first() {
        t.push_str(&format!("{} = {:?}\n", toml_key(first), q[0]));
    }
    t.push('\n');
    t.push_str(&format!(
        "[inputs]\n# actuated = \"transmissions\" | \"all\" | [\"joint\", ...]; the inputs are from {} ({})\neffort_limits = true   # |u| ≤ URDF effort\n\n",
        robot.actuation,
        robot.inputs.len()
    ));
    t.push_str("# Every quadratic cost carries ½: ½ (x − target)ᵀ diag(w) (x − target).\n");
    t.push_str("[[cost]]\ntype = \"state_tracking\"   # towards the goal (the standing pose), midpoint state\n");
    t.push_str("q_weights = { default = 10.0 }\nv_weights = { default = 1.0 }   # velocity weights keep legs from swinging\ntime_weighted = true\n\n");
    if !robot.inputs.is_empty() {
        t.push_str("[[cost]]\ntype = \"input\"\nweights = { default = 0.001 }\n\n");
    }
    t.push_str(&steering_examples(feet.iter().map(|f| f.name.as_str())));
    t.push_str("[slack]\nweight = 1000.0   # α on Σ s (complementarity relaxation)\nmode = \"per_interval\"\n\n");
    t.push_str("[initial_guess]\nto = \"initial\"   # every q_k = q_1; or warm_start = \"out/x/trajectory.csv\"\n\n");
    t.push_str(&solver_section());
    t
}

/// Commented examples of a clearance term and a gait for the robot's own contacts (none
/// without contacts): uncommented, they load as they stand.
fn steering_examples<'a>(contacts: impl Iterator<Item = &'a str>) -> String {
    let names: Vec<&str> = contacts.collect();
    let Some(first) = names.first() else {
        return String::new();
    };
    let offsets: Vec<String> = names
        .iter()
        .enumerate()
        .map(|(i, n)| {
            format!(
                "{} = {}",
                toml_key(n),
                if i % 2 == 0 { "0.0" } else { "0.5" }
            )
        })
        .collect();
    let mut t = String::new();
    t.push_str(
        "# Steering the plan (optional). A foot's height above the terrain at chosen knots,\n",
    );
    t.push_str("# as rows lower ≤ φ ≤ upper, or as a cost ½·weight·(φ − target)²:\n");
    t.push_str(
        "# [[frame]]\n# type = \"clearance\"   # position | clearance | orientation | velocity\n",
    );
    t.push_str(&format!(
        "# contact = {}   # or link = \"...\" with point = [x, y, z]\n",
        toml_string(first)
    ));
    t.push_str("# window = [0.35, 0.45]   # [s] (its swing in the gait below); or knots = \"all\" | \"interior\" | \"final\" | [3, 4]\n");
    t.push_str("# lower = 0.02   # [m]\n#\n");
    t.push_str(
        "# A gait: stance and flight windows from a period, a duty factor and phase offsets.\n",
    );
    t.push_str(
        "# [gait]\n# period = 0.5   # [s]\n# duty = 0.6   # the stance fraction of the period\n",
    );
    t.push_str(
        "# clearance = 0.02   # [m] each swing's distance between lift-off and touch-down\n",
    );
    t.push_str(&format!(
        "# offsets = {{ {} }}   # fractions of the period\n\n",
        offsets.join(", ")
    ));
    t
}
