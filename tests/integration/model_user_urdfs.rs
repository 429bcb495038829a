//! URDFs as ROS description packages ship them: massless frames (mass 0), singular inertias
//! welded to a moving body, no transmissions, `<mimic>` joints, and every problem of a file
//! reported at once with its line.

use nalgebra::DMatrix;
use vito::model::{
    Actuation, AppliedActuation, BaseType, Model, ModelError, inverse_dynamics, link_pose,
    mass_matrix, potential_energy, potential_energy_gradient, sample,
};

fn gripper() -> Model {
    Model::from_urdf_str(sample::gripper(), BaseType::Fixed).expect("the gripper loads")
}

/// The gripper with every `<mimic>` removed: each follower becomes a coordinate of its own,
/// q_full = [wrist, left, right, tip, thumb].
fn unmimicked() -> Model {
    let xml: String = sample::gripper()
        .lines()
        .filter(|l| !l.contains("<mimic"))
        .collect::<Vec<_>>()
        .join("\n");
    Model::from_urdf_str(&xml, BaseType::Fixed).expect("the unmimicked gripper loads")
}

/// ∂q_full/∂q for q = [wrist, left]: right = −left, tip = 2·right + 0.003 = −2·left + 0.003,
/// thumb = 0.5·wrist + 0.1.
fn follower_map() -> DMatrix<f64> {
    DMatrix::from_row_slice(5, 2, &[1.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0, -2.0, 0.5, 0.0])
}

fn full_q(q: &[f64]) -> Vec<f64> {
    vec![q[0], q[1], -q[1], -2.0 * q[1] + 0.003, 0.5 * q[0] + 0.1]
}

fn reject(xml: &str) -> Vec<String> {
    match Model::from_urdf_named(xml, "robots/bad.urdf", BaseType::Floating) {
        Ok(_) => panic!("accepted:\n{xml}"),
        Err(ModelError::Invalid { origin, problems }) => {
            assert_eq!(origin, "robots/bad.urdf");
            problems
        }
        Err(e) => panic!("expected a list of problems, got {e:?}"),
    }
}

#[test]
fn gripper_loads_with_massless_frames_and_every_joint_an_input() {
    let model = gripper();
    assert_eq!(model.coordinate_names(), ["wrist", "left"]);
    // No transmissions: every joint with a coordinate of its own is an input.
    assert_eq!(model.input_names(), ["wrist", "left"]);
    assert_eq!(model.actuation(), AppliedActuation::AllJoints);
    // The camera (mass 0) and optical frame weigh nothing; the point mass counts.
    let expected = 2.0 + 0.5 + 0.2 + 0.1 + 0.1 + 0.04 + 0.05;
    assert!((model.total_mass() - expected).abs() < 1e-12);
    let warning = model
        .warnings()
        .iter()
        .find(|w| w.contains("camera_link"))
        .expect("a warning about the camera's ignored inertia");
    assert!(
        warning.contains("line 7:") && warning.contains("mass 0") && warning.contains("massless"),
        "{warning}"
    );
    // A joint and a link may share a name.
    assert!(model.link_index("thumb").is_some());
}

#[test]
fn mimic_joints_follow_their_leaders() {
    let (mimic, full) = (gripper(), unmimicked());
    for q in [[0.3, 0.015], [-1.1, 0.04], [0.0, 0.0]] {
        let qf = full_q(&q);
        for link in full.link_names() {
            let (r_m, o_m) = link_pose(&mimic, mimic.link_index(link).unwrap(), &q);
            let (r_f, o_f) = link_pose(&full, full.link_index(link).unwrap(), &qf);
            for k in 0..3 {
                assert!((o_m[k] - o_f[k]).abs() < 1e-15, "{link} origin at {q:?}");
                for l in 0..3 {
                    assert!(
                        (r_m[k][l] - r_f[k][l]).abs() < 1e-15,
                        "{link} axes at {q:?}"
                    );
                }
            }
        }
        // The fingers stay mirrored about the palm: their y in the palm frame is ±(0.02 + left).
        let palm = link_pose(&mimic, mimic.link_index("palm").unwrap(), &q);
        let in_palm = |name: &str| {
            let (_, o) = link_pose(&mimic, mimic.link_index(name).unwrap(), &q);
            let d = [o[0] - palm.1[0], o[1] - palm.1[1], o[2] - palm.1[2]];
            (0..3)
                .map(|k| palm.0[0][k] * d[0] + palm.0[1][k] * d[1] + palm.0[2][k] * d[2])
                .collect::<Vec<f64>>()
        };
        let (left, right) = (in_palm("left_finger"), in_palm("right_finger"));
        assert!((left[1] - (0.02 + q[1])).abs() < 1e-15);
        assert!((right[1] + (0.02 + q[1])).abs() < 1e-15);
    }
}

#[test]
fn mimic_dynamics_is_the_full_models_through_the_follower_map() {
    let (mimic, full) = (gripper(), unmimicked());
    let j = follower_map();
    let q = [0.7, 0.021];
    let qf = full_q(&q);
    // M = Jᵀ M_full J (the followers' kinetic energy counted through their leaders).
    let m = mass_matrix(&mimic, &q);
    let reduced = j.transpose() * mass_matrix(&full, &qf) * &j;
    assert!((&m - &reduced).amax() < 1e-14, "{m} vs {reduced}");
    // A follower's own inertia shows on its leader: left carries both fingers and the tip
    // (which moves 2 per unit of left along the right finger's axis, 1 across it).
    assert!((m[(1, 1)] - (0.1 + 0.1 + 0.04 * 5.0)).abs() < 1e-14);
    // V and ∇V = Jᵀ ∇V_full (the adjoint sweep's chain rule).
    let v = potential_energy(&mimic, &q);
    assert!((v - potential_energy(&full, &qf)).abs() < 1e-14);
    let (mut g, mut gf) = (vec![0.0; 2], vec![0.0; 5]);
    potential_energy_gradient(&mimic, &q, &mut g);
    potential_energy_gradient(&full, &qf, &mut gf);
    let reduced_g = j.transpose() * nalgebra::DVector::from_vec(gf);
    for k in 0..2 {
        assert!((g[k] - reduced_g[k]).abs() < 1e-14, "∇V[{k}]");
    }
    // Inverse dynamics: τ = Jᵀ τ_full at the followers' rates and accelerations.
    let (v, a) = ([0.4, -0.03], [1.5, 0.2]);
    let tau = inverse_dynamics(&mimic, &q, &v, &a);
    let vf: Vec<f64> = (&j * nalgebra::DVector::from_row_slice(&v))
        .iter()
        .copied()
        .collect();
    let af: Vec<f64> = (&j * nalgebra::DVector::from_row_slice(&a))
        .iter()
        .copied()
        .collect();
    let tau_full = inverse_dynamics(&full, &qf, &vf, &af);
    let reduced_tau = j.transpose() * nalgebra::DVector::from_vec(tau_full);
    for k in 0..2 {
        assert!(
            (tau[k] - reduced_tau[k]).abs() < 1e-13,
            "τ[{k}]: {} vs {}",
            tau[k],
            reduced_tau[k]
        );
    }
}

/// A mimic joint's own `<limit>` bounds its leader's coordinate through θ = m·q + o: the
/// thumb (θ = 0.5·wrist + 0.1 within [−1, 1]) narrows the wrist's [−2, 2] to [−2, 1.8] with
/// a warning; the right finger (−left within [−0.04, 0]) and the tip agree with the left
/// finger's [0, 0.04] and change nothing. Limits that exclude each other are a problem of
/// the file, named by line.
#[test]
fn a_mimic_joints_limit_bounds_its_leader() {
    let model = gripper();
    let limits = model.coordinate_limits();
    assert_eq!(limits[0], (-2.0, 1.8), "wrist: {limits:?}");
    assert_eq!(limits[1], (0.0, 0.04), "left: {limits:?}");
    let narrowed: Vec<&String> = model
        .warnings()
        .iter()
        .filter(|w| w.contains("narrows"))
        .collect();
    assert_eq!(narrowed.len(), 1, "{:?}", model.warnings());
    assert!(
        narrowed[0].contains("joint 'thumb' (mimic of 'wrist')")
            && narrowed[0].contains("narrows 'wrist' from [-2, 2] to [-2, 1.8]"),
        "{}",
        narrowed[0]
    );
    // Without its limit the thumb leaves the wrist alone.
    let xml = sample::gripper().replace(
        r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>
    <mimic joint="wrist""#,
        r#"<mimic joint="wrist""#,
    );
    let free = Model::from_urdf_str(&xml, BaseType::Fixed).unwrap();
    assert_eq!(free.coordinate_limits()[0], (-2.0, 2.0));
    // right = −left within [0.01, 0.02] needs left in [−0.02, −0.01], outside [0, 0.04].
    let xml = sample::gripper().replace(
        r#"<limit lower="-0.04" upper="0" effort="20" velocity="0.1"/>"#,
        r#"<limit lower="0.01" upper="0.02" effort="20" velocity="0.1"/>"#,
    );
    let problems = reject(&xml);
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert!(
        problems[0].starts_with("line 39: <joint name=\"right\"> <limit> (mimic of 'left')")
            && problems[0].contains("make them agree"),
        "{problems:?}"
    );
}

#[test]
fn mimic_joints_are_never_inputs() {
    let mut model = gripper();
    let e = model
        .actuate(&Actuation::Joints(vec!["right".into()]))
        .expect_err("a mimic joint cannot take an input");
    assert_eq!(e.joint, "right");
    // A transmission on one is ignored with a warning naming its line (baxter.urdf's
    // grippers), and the transmissions that can drive a joint give the inputs.
    let xml = sample::gripper().replace(
        "</robot>",
        "<transmission name=\"t_right\">\n<joint name=\"right\"/></transmission>\n\
         <transmission name=\"t_left\"><joint name=\"left\"/></transmission></robot>",
    );
    let model = Model::from_urdf_str(&xml, BaseType::Fixed).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(model.input_names(), ["left"]);
    assert_eq!(model.actuation(), AppliedActuation::Transmissions);
    let line = 1 + xml[..xml.find("<transmission").unwrap()]
        .matches('\n')
        .count();
    let expected = format!(
        "line {line}: transmission 't_right' acts on joint 'right', which mimics joint 'left' \
         and has no coordinate of its own; ignored (no input)"
    );
    assert!(
        model.warnings().contains(&expected),
        "{expected}\n{:#?}",
        model.warnings()
    );
}

#[test]
fn singular_inertia_welded_to_a_moving_body_is_fine_once_lumped() {
    // palm_weight (zero inertia) is welded to the palm: the lumped body is positive definite.
    assert!(
        gripper()
            .warnings()
            .iter()
            .all(|w| !w.contains("palm_weight"))
    );
    // The same point mass on a joint of its own is a body that cannot turn: kept as written
    // (as ROS's parsers and Pinocchio read it), with warnings naming it and the coordinate
    // along which nothing has inertia.
    let xml = sample::gripper().replace(
        r#"<joint name="weight_mount" type="fixed">"#,
        r#"<joint name="weight_mount" type="revolute"><axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>"#,
    );
    let model = Model::from_urdf_str(&xml, BaseType::Fixed).unwrap_or_else(|e| panic!("{e}"));
    let w = model.warnings();
    assert!(
        w.iter().any(
            |w| w.starts_with("line 24: <link name=\"palm_weight\"> <inertial>")
                && w.contains("not positive definite")
                && w.ends_with("kept as written")
        ),
        "{w:#?}"
    );
    assert!(
        w.iter().any(|w| w
            .starts_with("the mass matrix is singular at the nominal pose along `weight_mount`")),
        "{w:#?}"
    );
}

#[test]
fn every_problem_of_a_file_is_reported_at_once() {
    let xml = r#"<?xml version="1.0"?>
<robot name="broken">
  <link name="trunk">
    <inertial><mass value="-3"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
  </link>
  <link name="thigh">
    <inertial><mass value="1"/><inertia ixx="nan" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
  </link>
  <link name="shin">
    <inertial><mass value="1"/><inertia ixx="1" ixy="2" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
  </link>
  <link name="sensor">
    <inertial><mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
  </link>
  <joint name="hip" type="revolute"><parent link="trunk"/><child link="thigh"/><axis xyz="0 1 0"/></joint>
  <joint name="knee" type="revolute"><parent link="thigh"/><child link="shin"/><axis xyz="0 1 0"/></joint>
  <joint name="ankle" type="revolute"><parent link="shin"/><child link="sensor"/><axis xyz="0 1 0"/>
    <mimic joint="toe"/>
  </joint>
</robot>"#;
    let problems = reject(xml);
    let expected = [
        (
            "line 17: <joint name=\"ankle\"> <mimic>",
            "'toe', which is not defined",
        ),
        ("line 4: <link name=\"trunk\"> <inertial>", "mass -3"),
        ("line 7: <link name=\"thigh\"> <inertial>", "finite"),
    ];
    assert_eq!(problems.len(), expected.len(), "{problems:#?}");
    for ((start, says), problem) in expected.iter().zip(&problems) {
        assert!(
            problem.starts_with(start) && problem.contains(says),
            "{problem}"
        );
    }
    // The massless sensor frame is not among them, nor the shin's inertia (whether it
    // matters is known once the mass matrix can be built), and the message names the file.
    let e = Model::from_urdf_named(xml, "robots/bad.urdf", BaseType::Floating).unwrap_err();
    assert!(
        e.to_string().starts_with("robots/bad.urdf: 3 problems"),
        "{e}"
    );
}

#[test]
fn bad_mimics_are_named() {
    let base = sample::gripper();
    for (from, to, says) in [
        (
            r#"<mimic joint="left" multiplier="-1"/>"#,
            r#"<mimic joint="weight_mount"/>"#,
            "follows joint 'weight_mount', which is fixed",
        ),
        (
            r#"<mimic joint="left" multiplier="-1"/>"#,
            r#"<mimic joint="tip"/>"#,
            "in a circle",
        ),
        (
            r#"<mimic joint="left" multiplier="-1"/>"#,
            r#"<mimic joint="left" multiplier="inf"/>"#,
            "finite",
        ),
    ] {
        let xml = base.replace(from, to);
        let problems = reject(&xml);
        assert!(
            problems
                .iter()
                .any(|p| p.contains("<joint name=\"right\"> <mimic>") && p.contains(says)),
            "{to}: {problems:?}"
        );
    }
}
