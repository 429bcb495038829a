//! URDFs as ROS description packages write them (example-robot-data's iCub, PR2, Kinova,
//! Baxter, TALOS arm, TIAGo): what vito cannot use is a warning naming the line, never a
//! refusal; the coordinate limit names joints to make fixed.

use vito::model::{AppliedActuation, BaseType, Model};

fn link(name: &str) -> String {
    format!(
        r#"<link name="{name}"><inertial><origin xyz="0 0 -0.1"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
"#
    )
}

fn joint(name: &str, kind: &str, parent: &str, child: &str) -> String {
    format!(
        r#"<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/><origin xyz="0 0 -0.1"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="5" velocity="1"/></joint>
"#
    )
}

fn robot(body: &str) -> String {
    format!("<?xml version=\"1.0\"?>\n<robot name=\"r\">\n{body}</robot>\n")
}

/// The 1-based line of the first occurrence of `needle`.
fn line_of(xml: &str, needle: &str) -> usize {
    let at = xml
        .find(needle)
        .unwrap_or_else(|| panic!("{needle} not in\n{xml}"));
    1 + xml[..at].matches('\n').count()
}

fn load(xml: &str) -> Model {
    Model::from_urdf_str(xml, BaseType::Fixed).unwrap_or_else(|e| panic!("{e}\n{xml}"))
}

/// iCub's and Romeo's visual materials hold `<texture />` without a file, which the URDF
/// reader refuses: it is dropped with a warning naming its line and material.
#[test]
fn a_texture_without_a_file_is_a_warning() {
    let visual = r#"<link name="a"><visual><geometry><box size="0.1 0.1 0.1"/></geometry><material name="metal">
<texture />
<color rgba="0 0 0 1"/></material></visual>
<inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
"#;
    let xml = robot(&(visual.to_string() + &link("b") + &joint("j", "revolute", "a", "b")));
    let model = load(&xml);
    assert_eq!(model.coordinate_names(), ["j"]);
    let expected = format!(
        "line {}: <texture> in <material name=\"metal\"> has no filename and is not used by \
         vito; ignored",
        line_of(&xml, "<texture")
    );
    assert!(
        model.warnings().contains(&expected),
        "{expected}\n{:#?}",
        model.warnings()
    );
    // A texture with a file is read (and not drawn) as before, without a warning.
    let with_file = xml.replace("<texture />", "<texture filename=\"wood.png\"/>");
    assert!(
        load(&with_file)
            .warnings()
            .iter()
            .all(|w| !w.contains("texture")),
        "{:#?}",
        load(&with_file).warnings()
    );
}

/// A PR2 wrist transmission names its two joints in `<flexJoint>` and `<rollJoint>`, a
/// gripper transmission its driven joint in `<gap_joint>` (its `<passive_joint>`s are not
/// driven), a differential transmission its joints in `<joint>`s with roles: each named
/// joint takes an input, in document order.
#[test]
fn transmissions_beyond_simple_name_their_joints_where_ros_does() {
    let body = link("torso")
        + &link("flex")
        + &link("roll")
        + &link("finger")
        + &link("tip")
        + &link("d1")
        + &link("d2")
        + &joint("flex_joint", "revolute", "torso", "flex")
        + &joint("roll_joint", "revolute", "flex", "roll")
        + &joint("gap", "revolute", "roll", "finger")
        + &joint("tip_joint", "revolute", "finger", "tip")
        + &joint("diff_1", "revolute", "torso", "d1")
        + &joint("diff_2", "revolute", "d1", "d2")
        + r#"<transmission name="wrist" type="pr2_mechanism_model/WristTransmission">
<rightActuator mechanicalReduction="60" name="r_motor"/><leftActuator mechanicalReduction="60" name="l_motor"/>
<flexJoint mechanicalReduction="-1.0" name="flex_joint"/><rollJoint mechanicalReduction="1.0" name="roll_joint"/>
</transmission>
<transmission name="grip" type="PR2GripperTransmission"><actuator name="g_motor"/>
<gap_joint name="gap" L0="0.03"/><passive_joint name="tip_joint"/></transmission>
<transmission name="diff"><type>transmission_interface/DifferentialTransmission</type>
<actuator name="m1"><role>actuator1</role></actuator><actuator name="m2"><role>actuator2</role></actuator>
<joint name="diff_1"><role>joint1</role></joint><joint name="diff_2"><role>joint2</role></joint>
</transmission>
"#;
    let model = load(&robot(&body));
    assert_eq!(model.actuation(), AppliedActuation::Transmissions);
    assert_eq!(
        model.input_names(),
        ["flex_joint", "roll_joint", "gap", "diff_1", "diff_2"]
    );
    // The passive joint is a coordinate without an input.
    assert!(model.coordinate_names().contains(&"tip_joint".to_string()));
    assert!(
        model.warnings().iter().all(|w| !w.contains("transmission")),
        "{:#?}",
        model.warnings()
    );
}

/// Transmissions vito cannot use are ignored with a warning naming their line, as ROS's
/// parsers and Pinocchio ignore them: on a fixed joint (Kinova's fingers), on a joint the
/// file does not define (TALOS's arm file keeps the whole robot's), and one naming no
/// joint at all. The usable ones still give the inputs.
#[test]
fn transmissions_that_drive_nothing_are_warnings() {
    let body = link("base")
        + &link("arm")
        + &link("finger")
        + &joint("shoulder", "revolute", "base", "arm")
        + &joint("finger_weld", "fixed", "arm", "finger")
        + r#"<transmission name="t_shoulder"><joint name="shoulder"/></transmission>
<transmission name="t_finger"><joint name="finger_weld"/></transmission>
<transmission name="t_leg"><joint name="leg_left_1_joint"/></transmission>
<transmission name="t_none"><actuator name="m"/></transmission>
"#;
    let xml = robot(&body);
    let model = load(&xml);
    assert_eq!(model.input_names(), ["shoulder"]);
    let expected = [
        format!(
            "line {}: transmission 't_finger' acts on joint 'finger_weld', which is fixed and \
             has no coordinate; ignored (no input)",
            line_of(&xml, "t_finger")
        ),
        format!(
            "line {}: transmission 't_leg' refers to joint 'leg_left_1_joint', which is not \
             defined; ignored (no input)",
            line_of(&xml, "t_leg")
        ),
        format!(
            "line {}: transmission 't_none' names no joint (<joint name=\"...\"/>, or a PR2 \
             transmission's <flexJoint>, <rollJoint> or <gap_joint>); ignored",
            line_of(&xml, "t_none")
        ),
    ];
    for e in &expected {
        assert!(model.warnings().contains(e), "{e}\n{:#?}", model.warnings());
    }
}

/// Over the coordinate limit, the message names the joints to make fixed (those below the
/// branching link nearest the tree's ends: a hand's palm), and `--base fixed` when that
/// alone brings the robot within the limit.
#[test]
fn the_coordinate_limit_names_joints_to_make_fixed() {
    let hand = |arm: usize, fingers: usize| {
        let mut body = link("trunk");
        let mut parent = "trunk".to_string();
        for i in 0..arm {
            let child = format!("arm{i}");
            body += &link(&child);
            body += &joint(&format!("arm{i}_joint"), "revolute", &parent, &child);
            parent = child;
        }
        body += &link("palm");
        body += &joint("wrist_weld", "fixed", &parent, "palm");
        for f in 0..fingers {
            let finger = format!("finger{f}");
            body += &link(&finger);
            body += &joint(&format!("{finger}_joint"), "revolute", "palm", &finger);
        }
        robot(&body)
    };
    // 45 + 56 = 101 coordinates even with a fixed base.
    let err = Model::from_urdf_named(&hand(45, 56), "hand.urdf", BaseType::Fixed)
        .expect_err("over the limit")
        .to_string();
    assert!(
        err.contains("hand.urdf: it has 101 coordinates")
            && err.contains("make joints that need not move `fixed`, e.g. the 56 below link `palm`; or model fewer links"),
        "{err}"
    );
    // 40 + 56 + 6 = 102 with a floating base, 96 with a fixed one.
    let err = Model::from_urdf_named(&hand(40, 56), "hand.urdf", BaseType::Floating)
        .expect_err("over the limit")
        .to_string();
    assert!(
        err.contains("it has 102 coordinates")
            && err.contains(
                "e.g. the 56 below link `palm`; or load it with `--base fixed` (96 coordinates)"
            ),
        "{err}"
    );
    assert_eq!(
        Model::from_urdf_str(&hand(40, 56), BaseType::Fixed)
            .unwrap_or_else(|e| panic!("{e}"))
            .nq(),
        96
    );
}

/// `--base auto`'s choice and reason: a root link `world` is bolted down, an arm whose
/// links all stay above its root is mounted by it, a robot with end links below its trunk
/// stands on them, a body without joints floats.
#[test]
fn auto_base_says_why() {
    let choice = |xml: &str| load(xml).auto_base();
    // An arm standing up from its mount (links 0.1 m above each joint).
    let up = |name: &str, parent: &str, child: &str| {
        joint(name, "revolute", parent, child).replace("xyz=\"0 0 -0.1\"", "xyz=\"0 0 0.1\"")
    };
    let arm = robot(&(link("mount") + &link("upper") + &up("shoulder", "mount", "upper")));
    let c = choice(&arm);
    assert_eq!(c.base, BaseType::Fixed);
    assert!(
        c.reason
            .starts_with("no end link or contact reaches below its root link `mount`"),
        "{}",
        c.reason
    );
    let world = robot(
        &(r#"<link name="world"/>
"#
        .to_string()
            + &link("upper")
            + &joint("leg", "revolute", "world", "upper")),
    );
    let c = choice(&world);
    assert_eq!(c.base, BaseType::Fixed);
    assert_eq!(
        c.reason,
        "its root link `world` bolts it to the world; `--base floating` frees it"
    );
    // Two legs hanging 0.1 m below the trunk: a robot standing on them.
    let legs = robot(
        &(link("trunk")
            + &link("left")
            + &link("right")
            + &joint("left_hip", "revolute", "trunk", "left")
            + &joint("right_hip", "revolute", "trunk", "right")),
    );
    let c = choice(&legs);
    assert_eq!(c.base, BaseType::Floating);
    assert!(
        c.reason
            .starts_with("`left`, `right` reach below its root link `trunk`"),
        "{}",
        c.reason
    );
    let body = robot(&link("brick"));
    assert_eq!(choice(&body).base, BaseType::Floating);
}

/// A limit of 1e19 or more (Ipopt's infinity) is no limit, as `inf` is: the portable
/// robot files write `1e20` where urdfdom refuses `inf`, and load exactly as before.
#[test]
fn limits_from_1e19_are_no_limits() {
    let urdf = |lower: &str, upper: &str, effort: &str| {
        robot(
            &(link("base")
                + &link("slider")
                + &format!(
                    r#"<joint name="x" type="prismatic"><parent link="base"/><child link="slider"/><axis xyz="1 0 0"/><limit lower="{lower}" upper="{upper}" effort="{effort}" velocity="{effort}"/></joint>
<transmission name="t"><joint name="x"/></transmission>
"#
                )),
        )
    };
    let open = load(&urdf("-inf", "inf", "inf"));
    let large = load(&urdf("-1e20", "1e20", "1e20"));
    assert_eq!(
        open.coordinate_limits(),
        [(f64::NEG_INFINITY, f64::INFINITY)]
    );
    assert_eq!(large.coordinate_limits(), open.coordinate_limits());
    assert_eq!(large.effort_limits(), [f64::INFINITY]);
    assert_eq!(large.warnings(), open.warnings());
    // Below Ipopt's infinity a limit is a limit.
    let finite = load(&urdf("-1e18", "1e18", "1e18"));
    assert_eq!(finite.coordinate_limits(), [(-1e18, 1e18)]);
    assert_eq!(finite.effort_limits(), [1e18]);
}
