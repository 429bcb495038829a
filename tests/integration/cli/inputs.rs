//! `[inputs] actuated`: which joints take an input, and `check`/`inspect` saying which rule
//! applied.

use crate::cli::util::{TestDir, hopper_text};

/// The hopper problem with input weights and bounds that fit any choice of inputs.
fn hopper_any_inputs(actuated: Option<&str>) -> String {
    let text = hopper_text()
        .replace(
            "bounds = { theta = [-10.0, 10.0], r = [-100.0, 100.0] }",
            "effort_limits = true",
        )
        .replace(
            "weights = { theta = 0.1, r = 0.01 }",
            "weights = { default = 0.1 }",
        );
    match actuated {
        Some(rule) => text.replace("[inputs]\n", &format!("[inputs]\nactuated = {rule}\n")),
        None => text,
    }
}

fn inputs_line(stdout: &str) -> &str {
    stdout
        .lines()
        .find(|l| l.trim_start().starts_with("inputs:"))
        .unwrap_or_else(|| panic!("no inputs line in\n{stdout}"))
}

#[test]
fn actuated_joints_follow_the_rule() {
    let t = TestDir::with_hopper("actuated_joints_follow_the_rule");
    let cases = [
        (None, "2 (theta, r), from the URDF's transmissions"),
        (
            Some("\"transmissions\""),
            "2 (theta, r), from the URDF's transmissions",
        ),
        (
            Some("\"all\""),
            "4 (x, z, theta, r), from every movable joint",
        ),
        (
            Some("[\"r\", \"x\"]"),
            "2 (r, x), from the joints listed in [inputs] actuated",
        ),
    ];
    for (rule, expected) in cases {
        t.write("p.toml", &hopper_any_inputs(rule));
        let run = t.vito().args(["check", "p.toml"]).assert_exit(0);
        assert!(
            inputs_line(&run.stdout).ends_with(expected),
            "{rule:?}:\n{}",
            run.stdout
        );
    }
}

#[test]
fn a_urdf_without_transmissions_actuates_every_movable_joint() {
    let t = TestDir::with_hopper("a_urdf_without_transmissions");
    let urdf = t.path().join("robots/hopper_2d.urdf");
    let text = std::fs::read_to_string(&urdf).unwrap();
    let start = text.find("<transmission").unwrap();
    let end = text.rfind("</transmission>").unwrap() + "</transmission>".len();
    std::fs::write(&urdf, format!("{}{}", &text[..start], &text[end..])).unwrap();
    t.write("p.toml", &hopper_any_inputs(None));
    let run = t.vito().args(["check", "p.toml"]).assert_exit(0);
    assert!(
        inputs_line(&run.stdout).ends_with("4 (x, z, theta, r), from every movable joint"),
        "{}",
        run.stdout
    );
    let run = t
        .vito()
        .args(["inspect", "robots/hopper_2d.urdf"])
        .assert_exit(0);
    assert!(
        run.stdout.contains("inputs (4), from every movable joint:"),
        "{}",
        run.stdout
    );
}

#[test]
fn bad_actuated_entries_name_the_field() {
    let t = TestDir::with_hopper("bad_actuated_entries");
    let cases = [
        (
            "[\"rr\"]",
            "field `inputs.actuated`: unknown movable joint `rr`",
        ),
        ("\"some\"", "field `inputs.actuated`: unknown rule `some`"),
        (
            "[\"r\", \"r\"]",
            "field `inputs.actuated[1]`: joint `r` is listed twice",
        ),
        ("3", "\"transmissions\", \"all\" or a list of joint names"),
    ];
    for (rule, expected) in cases {
        t.write("p.toml", &hopper_any_inputs(Some(rule)));
        let run = t.vito().args(["check", "p.toml"]).assert_exit(2);
        assert!(run.stderr.contains(expected), "{rule}:\n{}", run.stderr);
    }
}

#[test]
fn a_joint_with_a_negative_effort_limit_is_never_actuated() {
    let t = TestDir::with_hopper("negative_effort_never_actuated");
    let urdf = t.path().join("robots/hopper_2d.urdf");
    let text = std::fs::read_to_string(&urdf).unwrap().replacen(
        r#"<limit lower="-1e20" upper="1e20" effort="1e20" velocity="1e20"/>"#,
        r#"<limit lower="-1e20" upper="1e20" effort="-5" velocity="1e20"/>"#,
        1,
    );
    std::fs::write(&urdf, text).unwrap();
    // "all" leaves x out and says why; naming it is an error.
    t.write("p.toml", &hopper_any_inputs(Some("\"all\"")));
    let run = t.vito().args(["check", "p.toml"]).assert_exit(0);
    assert!(
        inputs_line(&run.stdout).ends_with("3 (z, theta, r), from every movable joint"),
        "{}",
        run.stdout
    );
    assert!(
        run.stderr
            .contains("joint 'x': <limit effort=\"-5\"> is not ≥ 0"),
        "{}",
        run.stderr
    );
    t.write("p.toml", &hopper_any_inputs(Some("[\"x\"]")));
    let run = t.vito().args(["check", "p.toml"]).assert_exit(2);
    assert!(run.stderr.contains("inputs.actuated"), "{}", run.stderr);
}

/// `vito inspect` states the units of limits and efforts: the hopper's leg length `r` is
/// prismatic (metres, newtons), its hip `theta` revolute (radians, newton-metres).
#[test]
fn inspect_states_the_units_of_limits_and_efforts() {
    let t = TestDir::with_hopper("inspect_states_the_units_of_limits_and_efforts");
    let run = t
        .vito()
        .args(["inspect", "robots/hopper_2d.urdf"])
        .assert_exit(0);
    let line = |name: &str, from: &str| {
        run.stdout
            .lines()
            .skip_while(|l| !l.starts_with(from))
            .find(|l| l.split_whitespace().any(|w| w == name))
            .unwrap_or_else(|| panic!("{name}: {}", run.stdout))
            .to_owned()
    };
    for (name, section, ending) in [
        ("r", "coordinates", "[0.3, 0.7] m"),
        ("theta", "coordinates", "[-inf, inf] rad"),
        ("r", "inputs", "|u| <= 100 N"),
        ("theta", "inputs", "|u| <= 10 N·m"),
    ] {
        assert!(line(name, section).ends_with(ending), "{}", run.stdout);
    }
}
