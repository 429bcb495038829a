//! Sphere contacts with a radius: a URDF collision sphere or a `[[contacts.point]]` with
//! `radius`. The distance to the terrain is the centre's minus r; a ball resting on flat
//! ground carries its weight, m·g·h per step, without sinking; friction acts at the lowest
//! material point, so a sliding ball ends rolling.

use crate::cli::util::{TestDir, says, summary};
use vito::files::trajectory_csv::read_csv;

const MASS: f64 = 2.0;
const RADIUS: f64 = 0.1;
const STEP: f64 = 0.05;

/// A solid ball (I = 2/5·m·r²) whose collision is a sphere of radius r around its centre,
/// and a box collision the reader ignores with a warning.
fn ball_urdf() -> String {
    let i = 0.4 * MASS * RADIUS * RADIUS;
    format!(
        r#"<?xml version="1.0"?>
<robot name="ball">
  <link name="ball">
    <inertial><mass value="{MASS}"/><inertia ixx="{i}" ixy="0" ixz="0" iyy="{i}" iyz="0" izz="{i}"/></inertial>
    <collision name="shell"><geometry><sphere radius="{RADIUS}"/></geometry></collision>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
  </link>
</robot>
"#
    )
}

/// The ball at rest on flat ground: its centre at z = r, no velocity, nothing to optimise
/// but the slack. Ipopt's tolerance is tight so that the impulses are exact to 1e-6.
fn resting_problem(contacts: &str) -> String {
    format!(
        r#"name = "resting-ball"
[robot]
urdf = "ball.urdf"
base = "floating"

[contacts]
{contacts}
friction = 0.5

[horizon]
knots = 11
time_step = {STEP}

[initial]
q = [0.0, 0.0, {RADIUS}, 0.0, 0.0, 0.0]
v = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]

[final]
free = true

[slack]
weight = 1000.0

[initial_guess]
to = "initial"

[solver.ipopt]
tol = 1e-9
"#
    )
}

#[test]
fn a_ball_rests_on_flat_ground_carrying_its_weight() {
    let t = TestDir::new("a_ball_rests_on_flat_ground");
    t.write("ball.urdf", &ball_urdf());
    // The collision sphere, and the same sphere declared in the problem file.
    let cases = [
        ("from_urdf", "from_urdf = \"all\"", "shell"),
        (
            "point",
            "from_urdf = \"none\"\n[[contacts.point]]\nname = \"shell\"\nlink = \"ball\"\npoint = [0.0, 0.0, 0.0]\nradius = 0.1",
            "shell",
        ),
    ];
    for (label, contacts, name) in cases {
        t.write("ball.toml", &resting_problem(contacts));
        let run = t
            .vito()
            .args(["solve", "ball.toml", "--quiet", "--out", label])
            .assert_exit(0);
        if label == "from_urdf" {
            assert!(
                run.stderr.contains("'ball' (box)") || run.stdout.contains("'ball' (box)"),
                "the ignored box is named\n{}\n{}",
                run.stdout,
                run.stderr
            );
        }
        let s = summary(&t.path().join(label));
        assert_eq!(s["status"], "solve_succeeded", "{label}");
        let csv = std::fs::read_to_string(t.path().join(label).join("trajectory.csv")).unwrap();
        let table = read_csv(&csv).unwrap();
        let normal = table.column(&format!("{name}_normal")).unwrap();
        let distance = table.column(&format!("{name}_distance")).unwrap();
        let z = table.column("base_z").unwrap();
        let weight = MASS * 9.81 * STEP;
        // Row k holds the impulse over the step to knot k + 1 (the first is a half step, v_0
        // given; the last row has none) and the distance at its own knot k.
        let n = z.len();
        assert!(
            (normal[0] - weight / 2.0).abs() <= 1e-6 * weight,
            "{label}: {normal:?}"
        );
        for (k, c) in normal.iter().enumerate().take(n - 1).skip(1) {
            assert!(
                (c - weight).abs() <= 1e-6 * weight,
                "{label}: step {k}: normal impulse {c} vs m·g·h = {weight}"
            );
        }
        for k in 0..n {
            assert!(
                distance[k] >= -1e-6,
                "{label}: knot {k}: penetrates {}",
                distance[k]
            );
            assert!(
                (distance[k] - (z[k] - RADIUS)).abs() < 1e-12,
                "{label}: knot {k}: distance {} is the centre's height minus r",
                distance[k]
            );
        }
        assert!(
            z.iter().all(|z| (z - RADIUS).abs() <= 1e-6),
            "{label}: {z:?}"
        );
    }
}

/// The ball of [`resting_problem`] on a `base` launched from q with velocity v (its base's
/// coordinates and their rates), for 0.2 s in steps of 0.01 s.
fn launched_problem(base: &str, q: &str, v: &str) -> String {
    resting_problem("from_urdf = \"all\"")
        .replace("base = \"floating\"", &format!("base = \"{base}\""))
        .replace(
            &format!("q = [0.0, 0.0, {RADIUS}, 0.0, 0.0, 0.0]"),
            &format!("q = {q}"),
        )
        .replace("v = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]", &format!("v = {v}"))
        .replace(
            &format!("knots = 11\ntime_step = {STEP}"),
            "knots = 21\ntime_step = 0.01",
        )
}

/// The last row of a trajectory: column name → value.
fn last_row(dir: &std::path::Path) -> impl Fn(&str) -> f64 + use<> {
    let csv = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let table = read_csv(&csv).unwrap();
    move |name: &str| *table.column(name).unwrap().last().unwrap()
}

/// A ball launched sliding on flat ground ends rolling, as friction at its lowest material
/// point turns it: angular momentum about the contact point is kept, so a solid ball
/// (I = 2/5·m·r²) launched at v₀ with spin ω₀ (about the axis it rolls on) rolls on at
/// v = (v₀ + 2/5·r·ω₀)/(7/5) with ω = v/r. Friction at a point moving with the centre (no
/// torque) would slide it to a stop instead. Simulated at 1 kHz and solved as a trajectory
/// (the same rows), on a floating base and on a planar one with backspin; launched
/// diagonally, the lowest material point ends at rest and v → 5/7·v₀ at first order in the
/// step (0.25 % at 1 kHz: the roll–pitch–yaw chart turns the spin axis within a step).
#[test]
fn a_sliding_ball_ends_rolling_with_its_angular_momentum_about_the_contact_kept() {
    let t = TestDir::new("a_sliding_ball_ends_rolling");
    t.write("ball.urdf", &ball_urdf());
    let cases = [
        (
            "floating",
            "[0.0, 0.0, 0.1, 0.0, 0.0, 0.0]",
            "[1.0, 0.0, 0.0, 0.0, 0.0, 0.0]",
            1.0,
            0.0,
        ),
        ("planar", "[0.0, 0.1, 0.0]", "[1.0, 0.0, -3.0]", 1.0, -3.0),
    ];
    for (base, q, v, v0, spin) in cases {
        t.write("launched.toml", &launched_problem(base, q, v));
        let rolling = (v0 + 0.4 * RADIUS * spin) / 1.4;
        for command in ["simulate", "solve"] {
            let out = format!("{base}-{command}");
            let mut args = vec![command, "launched.toml", "--quiet", "--out", &out];
            if command == "simulate" {
                args.extend(["--rate", "1000", "--duration", "0.15"]);
            }
            // The ball has no inputs: its solve starts from its simulation and keeps no
            // slack (from the file's guess alone the floating-base solve kept 1e-3 open,
            // `relaxed_contact`, at every slack weight tried, 1e3 to 1e5).
            t.vito().args(&args).assert_exit(0);
            if command == "solve" {
                let s = summary(&t.path().join(&out));
                assert_eq!(s["max_slack"].as_f64(), Some(0.0), "{s}");
                assert_eq!(s["simulation_start"]["kept"], true, "{s}");
            }
            let last = last_row(&t.path().join(&out));
            let (speed, turn) = (last("base_x_dot"), last("base_pitch_dot"));
            assert!(
                (speed - rolling).abs() < 1e-8 && (turn * RADIUS - speed).abs() < 1e-8,
                "{out}: v = {speed}, ω·r = {}, expected rolling at {rolling}",
                turn * RADIUS
            );
        }
    }
    // The solved rows' derivatives are exact at the solution (the spin rows included).
    says(
        &t,
        &[
            "check",
            "--derivatives",
            "--at",
            "planar-solve/trajectory.csv",
            "launched.toml",
        ],
        0,
        "passed",
    );

    let (vx, vy) = (1.0, -0.6);
    t.write(
        "diagonal.toml",
        &launched_problem(
            "floating",
            "[0.0, 0.0, 0.1, 0.0, 0.0, 0.0]",
            &format!("[{vx}, {vy}, 0.0, 0.0, 0.0, 0.0]"),
        ),
    );
    t.vito()
        .args(["simulate", "diagonal.toml", "--quiet", "--out", "diagonal"])
        .args(["--rate", "1000", "--duration", "0.15"])
        .assert_exit(0);
    let last = last_row(&t.path().join("diagonal"));
    let (yaw, pitch) = (last("base_yaw"), last("base_pitch"));
    let (roll_dot, pitch_dot) = (last("base_roll_dot"), last("base_pitch_dot"));
    // ω = ψ̇ẑ + θ̇ Rz(ψ)ŷ + φ̇ Rz(ψ)Ry(θ)x̂ for R = Rz(yaw)·Ry(pitch)·Rx(roll); x and y.
    let omega = [
        -yaw.sin() * pitch_dot + yaw.cos() * pitch.cos() * roll_dot,
        yaw.cos() * pitch_dot + yaw.sin() * pitch.cos() * roll_dot,
    ];
    let (sx, sy) = (last("base_x_dot"), last("base_y_dot"));
    let bottom = [sx - RADIUS * omega[1], sy + RADIUS * omega[0]];
    assert!(
        bottom.iter().all(|b| b.abs() < 1e-8),
        "the lowest material point still slides: {bottom:?}"
    );
    for (found, launched) in [(sx, vx), (sy, vy)] {
        let expected = launched / 1.4;
        assert!(
            (found - expected).abs() < 5e-3 * expected.abs(),
            "v = ({sx}, {sy}), expected 5/7 of ({vx}, {vy})"
        );
    }
}

/// The derivatives at the solver's final iterate of a tumbling body whose knob and tip hit the
/// ground: a hard point (contacts active). Debian 12's Ipopt leaves its slack open (about 0.16
/// at every slack weight tried, 1e3 to 1e5: `relaxed_contact`, exit 1), Debian 13's closes it
/// (`solve_succeeded`, exit 0); either way the verdict must agree with the plan's largest slack.
#[test]
fn sphere_contact_derivatives_pass_at_a_solvers_final_iterate() {
    let t = TestDir::new("sphere_contact_derivatives");
    t.write(
        "body.urdf",
        r#"<?xml version="1.0"?>
<robot name="lollipop">
  <link name="body">
    <inertial><origin xyz="0.02 0 0.05"/><mass value="1.5"/><inertia ixx="0.01" ixy="0.001" ixz="0" iyy="0.012" iyz="0" izz="0.008"/></inertial>
    <collision name="knob"><origin xyz="0.1 0.05 -0.1"/><geometry><sphere radius="0.04"/></geometry></collision>
    <collision name="tip"><origin xyz="-0.1 -0.05 -0.05"/><geometry><sphere radius="0"/></geometry></collision>
  </link>
</robot>
"#,
    );
    t.write(
        "p.toml",
        r#"name = "tumbling-lollipop"
[robot]
urdf = "body.urdf"
base = "floating"
[contacts]
friction = 0.6
[horizon]
knots = 15
time_step = 0.04
[initial]
q = [0.0, 0.0, 0.3, 0.4, -0.3, 0.2]
v = [0.8, 0.2, -0.5, 2.0, 1.5, -1.0]
[final]
free = true
[slack]
weight = 1000.0
[initial_guess]
to = "initial"
"#,
    );
    let run = t
        .vito()
        .args(["solve", "p.toml", "--quiet", "--out", "solved"])
        .run();
    let solved = summary(&t.path().join("solved"));
    assert_eq!(solved["ipopt_status"], "solve_succeeded");
    let slack = solved["max_slack"].as_f64().unwrap();
    let tolerance = solved["slack_tolerance"].as_f64().unwrap();
    let (code, status) = if slack > tolerance {
        (1, "relaxed_contact")
    } else {
        (0, "solve_succeeded")
    };
    assert_eq!(
        solved["status"], status,
        "max slack {slack}, tolerance {tolerance}"
    );
    assert_eq!(run.code, code, "{}\n{}", run.stdout, run.stderr);
    let csv = std::fs::read_to_string(t.path().join("solved/trajectory.csv")).unwrap();
    let knob = read_csv(&csv).unwrap().column("knob_normal").unwrap();
    assert!(
        knob.iter().any(|&c| c > 1e-3),
        "the sphere never touches: {knob:?}"
    );
    let run = says(
        &t,
        &[
            "check",
            "--derivatives",
            "--at",
            "solved/trajectory.csv",
            "p.toml",
        ],
        0,
        "passed",
    );
    assert!(run.stdout.contains("trajectory.csv ("), "{}", run.stdout);
}

/// `vito inspect` lists each contact with its link, centre and radius, and the collision
/// elements that give none (the ball's box), in text and JSON.
#[test]
fn inspect_shows_each_contacts_radius_and_the_ignored_collisions() {
    let t = TestDir::new("inspect_shows_radius");
    t.write("ball.urdf", &ball_urdf());
    let run = t.vito().args(["inspect", "ball.urdf"]).assert_exit(0);
    for line in [
        "contacts (1):",
        "  shell                on ball                 at [0, 0, 0]  radius 0.1",
        "ignored collisions (1, not spheres): ball (box)",
    ] {
        assert!(run.stdout.contains(line), "{line}\n{}", run.stdout);
    }
    let run = t
        .vito()
        .args(["inspect", "ball.urdf", "--json"])
        .assert_exit(0);
    let json: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(json["contacts"][0]["radius"], RADIUS);
    assert_eq!(json["contacts"][0]["link"], "ball");
    assert_eq!(json["ignored_collisions"][0]["shape"], "box");
}

#[test]
fn a_negative_radius_is_an_input_error() {
    let t = TestDir::new("a_negative_radius");
    t.write("ball.urdf", &ball_urdf());
    t.write(
        "ball.toml",
        &resting_problem(
            "from_urdf = \"none\"\n[[contacts.point]]\nname = \"s\"\nlink = \"ball\"\npoint = [0.0, 0.0, 0.0]\nradius = -0.1",
        ),
    );
    says(&t, &["check", "ball.toml"], 2, "contacts.point[0].radius");
    t.write(
        "bad.urdf",
        &ball_urdf().replace("radius=\"0.1\"", "radius=\"-1\""),
    );
    t.write(
        "bad.toml",
        &resting_problem("from_urdf = \"all\"").replace("ball.urdf", "bad.urdf"),
    );
    says(
        &t,
        &["check", "bad.toml"],
        2,
        "radius must be a finite number",
    );
}

/// `vito check` shows each contact's distance to the terrain and warns, naming the contact,
/// when it starts below the terrain (46 µm here), when a free base has no inputs, and when
/// the pose nears pitch ±π/2.
#[test]
fn check_shows_distances_and_warns_about_infeasible_starts() {
    let t = TestDir::new("check_warns_about_infeasible_starts");
    t.write("ball.urdf", &ball_urdf());
    let below = resting_problem("from_urdf = \"all\"").replace(
        &format!("q = [0.0, 0.0, {RADIUS}, 0.0, 0.0, 0.0]"),
        "q = [0.0, 0.0, 0.099954, 0.0, 1.5, 0.0]",
    );
    t.write("below.toml", &below);
    let run = t.vito().args(["check", "below.toml"]).assert_exit(0);
    assert!(
        run.stdout.contains("distance to the terrain [m]")
            && run.stdout.contains("shell                 -4.6000e-5"),
        "{}",
        run.stdout
    );
    for says in [
        "contact `shell` starts 4.600e-5 below the terrain",
        "a free base but no inputs",
        "base_pitch 1.5 at knot 1 is within 0.2 rad of ±π/2",
    ] {
        assert!(run.stderr.contains(says), "{says}:\n{}", run.stderr);
    }
    // No contacts at all: nothing holds a free base up.
    t.write("none.toml", &resting_problem("from_urdf = \"none\""));
    let run = t.vito().args(["check", "none.toml"]).assert_exit(0);
    assert!(
        run.stderr.contains("a free base but no contacts"),
        "{}",
        run.stderr
    );
    // At rest on the ground: no warning about the start.
    t.write("rest.toml", &resting_problem("from_urdf = \"all\""));
    let run = t.vito().args(["check", "rest.toml"]).assert_exit(0);
    assert!(!run.stderr.contains("below the terrain"), "{}", run.stderr);
}
