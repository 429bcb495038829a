//! The paper's robots and vito's reference robots load with the right counts, masses,
//! springs and loop closures; the reference robots' energies equal the closed forms of docs/reference-problems.md.

use crate::common::robots::{robot, robot_path};
use vito::model::{
    BaseType, Model, SpringKind, inspect, kinetic_energy, loop_residual, point_position,
    potential_energy,
};
use vito::random::SeededRng;

#[test]
fn spring_flamingo_planar() {
    for file in [
        "spring_flamingo/spring_flamingo_passive_ankle.normalized.urdf",
        "spring_flamingo/spring_flamingo_passive_ankle.urdf",
    ] {
        let m = robot(file, BaseType::Planar);
        assert_eq!(
            m.coordinate_names(),
            [
                "base_x",
                "base_z",
                "base_pitch",
                "right_hip",
                "right_knee",
                "right_ankle",
                "left_hip",
                "left_knee",
                "left_ankle"
            ],
            "{file}"
        );
        assert!(
            (m.total_mass() - 14.2248).abs() < 1e-9,
            "{file}: {}",
            m.total_mass()
        );
        assert_eq!(m.springs().len(), 2);
        for s in m.springs() {
            assert_eq!(s.kind, SpringKind::Torsional);
            assert_eq!(s.stiffness, 1.0);
            assert_eq!(s.rest, 0.0);
            assert!(m.coordinate_names()[s.coordinate].ends_with("ankle"));
        }
        assert_eq!(
            m.input_names(),
            ["right_hip", "right_knee", "left_hip", "left_knee"]
        );
        assert_eq!(m.effort_limits(), [300.0; 4]);
        let limits = m.coordinate_limits();
        assert_eq!(limits[0], (f64::NEG_INFINITY, f64::INFINITY));
        assert_eq!(limits[3], (-1.25, 1.25));
        assert_eq!(limits[4], (-1.5, 0.0));
        assert_eq!(limits[5], (-1.1, 1.1));
        let damped: Vec<(usize, f64)> = m
            .damping()
            .iter()
            .copied()
            .enumerate()
            .filter(|(_, d)| *d != 0.0)
            .collect();
        assert_eq!(damped, [(5, 0.1), (8, 0.1)]);
        assert_eq!(m.contact_points().len(), 4);
        assert_eq!(m.num_loop_constraints(), 0);
    }
}

#[test]
fn spring_flamingo_contacts_touch_ground_in_the_start_pose() {
    // spring-flamingo-walk: q_1 = [0, 0.875, 0, 0, 0, δ, 0, 0, δ] levels the soles at z = 9.01e-10.
    let m = robot(
        "spring_flamingo/spring_flamingo_passive_ankle.normalized.urdf",
        BaseType::Planar,
    );
    let delta = std::f64::consts::FRAC_PI_2 - 1.57075;
    let q = [0.0, 0.875, 0.0, 0.0, 0.0, delta, 0.0, 0.0, delta];
    let names: Vec<&str> = m.contact_points().iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names.len(), 4, "{names:?}");
    for c in m.contact_points() {
        let link = m.link_index(&c.link).expect("contact link exists");
        let p = point_position(&m, link, &c.point, &q);
        assert!(p[2].abs() < 1e-8, "{}: z = {}", c.name, p[2]);
    }
    // The toe is its own link, welded to right_foot at (0.035, 0, −0.1725).
    let toe = &m.contact_points()[0];
    assert_eq!(toe.name, "right_forward_contact_point");
    assert_eq!(toe.link, "right_forward_contact_point");
    assert_eq!(toe.point, [0.0; 3]);
    let foot = m.link_index("right_foot").expect("right_foot");
    let via_foot = point_position(&m, foot, &[0.035, 0.0, -0.1725], &q);
    let direct = point_position(&m, m.link_index(&toe.link).expect("toe"), &toe.point, &q);
    for i in 0..3 {
        assert!((via_foot[i] - direct[i]).abs() < 1e-15);
    }
    assert_eq!(
        names,
        [
            "right_forward_contact_point",
            "right_rear_contact_point",
            "left_forward_contact_point",
            "left_rear_contact_point"
        ]
    );
}

#[test]
fn littledog_floating() {
    for file in [
        "littledog/LittleDog.normalized.urdf",
        "littledog/LittleDog.urdf",
    ] {
        let m = robot(file, BaseType::Floating);
        assert_eq!(m.nq(), 18, "{file}");
        assert_eq!(
            &m.coordinate_names()[..9],
            [
                "base_x",
                "base_y",
                "base_z",
                "base_roll",
                "base_pitch",
                "base_yaw",
                "front_left_hip_roll",
                "front_left_hip_pitch",
                "front_left_knee"
            ]
        );
        assert!((m.total_mass() - 2.7464).abs() < 1e-9, "{}", m.total_mass());
        assert_eq!(m.input_names().len(), 12);
        assert!(m.effort_limits().iter().all(|e| e.is_infinite()));
        assert!(m.springs().is_empty());
        assert!(m.damping().iter().all(|&d| d == 0.0));
        assert_eq!(m.contact_points().len(), 4);
        let fl = &m.contact_points()[0];
        assert_eq!(fl.point, [-0.0265, 0.0, -0.0985]);
        // Drake's <frame> elements are reported, not silently dropped.
        assert!(
            m.warnings().iter().any(|w| w.contains("<frame")),
            "{:?}",
            m.warnings()
        );
    }
}

#[test]
fn littledog_home_pose_feet_just_above_ground() {
    // littledog-step: with base_z = 0.136 the feet sit 0.65 mm above the ground (0.36 mm for BR).
    let m = robot("littledog/LittleDog.normalized.urdf", BaseType::Floating);
    let mut q = vec![0.0; 18];
    q[2] = 0.136;
    for (leg, (roll, pitch, knee)) in [
        (0.1, 1.0, -1.55),
        (-0.1, 1.0, -1.55),
        (0.1, -1.0, 1.55),
        (-0.1, -1.0, 1.55),
    ]
    .into_iter()
    .enumerate()
    {
        q[6 + 3 * leg] = roll;
        q[7 + 3 * leg] = pitch;
        q[8 + 3 * leg] = knee;
    }
    let heights: Vec<f64> = m
        .contact_points()
        .iter()
        .map(|c| point_position(&m, m.link_index(&c.link).expect("link"), &c.point, &q)[2])
        .collect();
    for h in &heights[..3] {
        assert!((h - 0.00065).abs() < 0.00002, "{heights:?}");
    }
    assert!((heights[3] - 0.00036).abs() < 0.00002, "{heights:?}");
}

#[test]
fn hamr_floating() {
    for file in [
        "hamr/HAMR_scaledV2.normalized.urdf",
        "hamr/HAMR_scaledV2.urdf",
        "hamr/HAMR_scaledV2_TYM.normalized.urdf",
        "hamr/HAMR_scaledV2_TYM.urdf",
    ] {
        let m = robot(file, BaseType::Floating);
        assert_eq!(m.nq(), 38, "{file}");
        assert!(
            (m.total_mass() - 1.47499).abs() < 1e-5,
            "{file}: {}",
            m.total_mass()
        );
        let torsional = m
            .springs()
            .iter()
            .filter(|s| s.kind == SpringKind::Torsional)
            .count();
        let prismatic = m
            .springs()
            .iter()
            .filter(|s| s.kind == SpringKind::Prismatic)
            .count();
        assert_eq!((torsional, prismatic), (24, 8), "{file}");
        assert_eq!(m.loop_closures().len(), 12);
        assert_eq!(m.num_loop_constraints(), 24);
        assert_eq!(
            m.input_names(),
            [
                "FLqsact", "FLqlact", "RLqsact", "RLqlact", "FRqsact", "FRqlact", "RRqsact",
                "RRqlact"
            ]
        );
        assert_eq!(m.contact_points().len(), 4);
        // The file's qfb2 offsets (z = 1.64999985615 against 1.65) leave 1.4385e-7 mm; every
        // other row closes to rounding.
        let residual = loop_residual(&m, &vec![0.0f64; 38]);
        let worst = residual.iter().fold(0.0f64, |a, r| a.max(r.abs()));
        assert!(
            worst < 2e-7,
            "{file}: loops do not close at q = 0: {worst:e}"
        );
        // Flexure limits ±π/4 (the originals write "pi/4").
        let fl_qs1 = m.coordinate_index("FLqs1").expect("FLqs1");
        let (lo, hi) = m.coordinate_limits()[fl_qs1];
        assert!((hi - std::f64::consts::FRAC_PI_4).abs() < 1e-12 && lo == -hi);
        let info = inspect(&m);
        assert_eq!(info.n_loop_constraints, 24);
        assert!(info.max_loop_residual < 2e-7);
    }
    let tym = robot("hamr/HAMR_scaledV2_TYM.normalized.urdf", BaseType::Floating);
    let lift = tym
        .springs()
        .iter()
        .find(|s| s.name == "FL_klact")
        .expect("FL_klact");
    assert_eq!(lift.stiffness, 1.6946);
}

#[test]
fn hamr_loops_are_violated_away_from_zero() {
    // A loop residual that is zero everywhere would pass the q = 0 test; move one flexure.
    let m = robot("hamr/HAMR_scaledV2.normalized.urdf", BaseType::Floating);
    let mut q = vec![0.0f64; 38];
    q[m.coordinate_index("FLqs1").expect("FLqs1")] = 0.1;
    let r = loop_residual(&m, &q);
    assert!(r.iter().any(|x| x.abs() > 1e-3), "{r:?}");
    // The base does not open any loop.
    let mut q = vec![0.0f64; 38];
    q[..6].copy_from_slice(&[1.0, -2.0, 12.69, 0.3, -0.2, 0.5]);
    let r = loop_residual(&m, &q);
    assert!(r.iter().all(|x| x.abs() < 2e-7), "{r:?}");
}

#[test]
fn hopper_energies_equal_spec_closed_forms() {
    let m = robot("hopper_2d.urdf", BaseType::Fixed);
    assert_eq!(m.coordinate_names(), ["x", "z", "theta", "r"]);
    assert_eq!(m.input_names(), ["theta", "r"]);
    assert_eq!(m.input_coordinates(), [2, 3]);
    assert_eq!(m.effort_limits(), [10.0, 100.0]);
    assert_eq!(m.coordinate_limits()[3], (0.3, 0.7));
    assert_eq!(m.coordinate_limits()[2], (f64::NEG_INFINITY, f64::INFINITY));
    assert_eq!(m.contact_points().len(), 1);
    assert!((m.total_mass() - 3.3).abs() < 1e-15);
    let mut rng = SeededRng::new(7);
    for _ in 0..50 {
        let q = rng.symmetric_vec(4, 2.0);
        let v = rng.symmetric_vec(4, 3.0);
        let (th, r) = (q[2], q[3]);
        let foot = [q[0] + r * th.sin(), q[1] - r * th.cos()];
        let foot_dot = [
            v[0] + v[3] * th.sin() + r * th.cos() * v[2],
            v[1] - v[3] * th.cos() + r * th.sin() * v[2],
        ];
        let t = 0.5 * 3.0 * (v[0] * v[0] + v[1] * v[1])
            + 0.5 * 0.3 * (foot_dot[0] * foot_dot[0] + foot_dot[1] * foot_dot[1])
            + 0.5 * (0.75 + 0.075) * v[2] * v[2];
        let vv = 9.81 * (3.0 * q[1] + 0.3 * foot[1]);
        assert!((kinetic_energy(&m, &q, &v) - t).abs() < 1e-12 * (1.0 + t.abs()));
        assert!((potential_energy(&m, &q) - vv).abs() < 1e-12 * (1.0 + vv.abs()));
        let c = &m.contact_points()[0];
        let p = point_position(&m, m.link_index(&c.link).expect("foot"), &c.point, &q);
        assert!((p[0] - foot[0]).abs() < 1e-12 && (p[2] - foot[1]).abs() < 1e-12 && p[1] == 0.0);
    }
}

/// Body-frame angular velocity for R = Rz(yaw)·Ry(pitch)·Rx(roll) from the rpy rates.
fn body_rates(roll: f64, pitch: f64, rates: [f64; 3]) -> [f64; 3] {
    let [dr, dp, dy] = rates;
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    [
        dr - sp * dy,
        cr * dp + sr * cp * dy,
        -sr * dp + cr * cp * dy,
    ]
}

#[test]
fn brick_energies_equal_rigid_body_closed_forms() {
    let m = robot("brick.urdf", BaseType::Floating);
    assert_eq!(
        m.coordinate_names(),
        [
            "base_x",
            "base_y",
            "base_z",
            "base_roll",
            "base_pitch",
            "base_yaw"
        ]
    );
    assert_eq!(m.contact_points().len(), 8);
    assert!(m.input_names().is_empty());
    let (a, b, c) = (0.2f64, 0.1f64, 0.05f64);
    let inertia = [
        (b * b + c * c) / 12.0,
        (a * a + c * c) / 12.0,
        (a * a + b * b) / 12.0,
    ];
    let mut rng = SeededRng::new(11);
    for _ in 0..50 {
        let q = rng.symmetric_vec(6, 1.5);
        let v = rng.symmetric_vec(6, 3.0);
        let w = body_rates(q[3], q[4], [v[3], v[4], v[5]]);
        let t = 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
            + 0.5
                * (inertia[0] * w[0] * w[0] + inertia[1] * w[1] * w[1] + inertia[2] * w[2] * w[2]);
        assert!(
            (kinetic_energy(&m, &q, &v) - t).abs() < 1e-12 * (1.0 + t),
            "{t}"
        );
        assert!((potential_energy(&m, &q) - 9.81 * q[2]).abs() < 1e-12);
        // Each corner is at p + R(rpy)·corner.
        let (sr, cr) = q[3].sin_cos();
        let (sp, cp) = q[4].sin_cos();
        let (sy, cy) = q[5].sin_cos();
        let r = [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ];
        for corner in m.contact_points() {
            let p = point_position(&m, m.link_index("brick").expect("brick"), &corner.point, &q);
            for i in 0..3 {
                let expected = q[i] + (0..3).map(|j| r[i][j] * corner.point[j]).sum::<f64>();
                assert!((p[i] - expected).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn inspect_json_has_the_documented_keys() {
    let m = robot(
        "spring_flamingo/spring_flamingo_passive_ankle.normalized.urdf",
        BaseType::Planar,
    );
    let json = serde_json::to_value(inspect(&m)).expect("serialise");
    assert_eq!(json["coordinates"].as_array().map(Vec::len), Some(9));
    assert_eq!(json["inputs"][0], "right_hip");
    assert!((json["total_mass"].as_f64().unwrap_or(0.0) - 14.2248).abs() < 1e-9);
    assert_eq!(json["n_springs"], 2);
    assert_eq!(json["n_loop_constraints"], 0);
    assert_eq!(json["max_loop_residual"], 0.0);
    let text = inspect(&m).to_string();
    assert!(
        text.contains("right_ankle") && text.contains("damping 0.1"),
        "{text}"
    );
}

/// A fixed-base leg hanging from a hip joint about `hip_axis` (rotated by `hip_rpy`), with a
/// knee about y and a foot sphere at the shank's end.
fn fixed_leg(hip_axis: &str, hip_rpy: &str) -> Model {
    let link = |name: &str| {
        format!(
            r#"<link name="{name}"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>"#
        )
    };
    let xml = format!(
        r#"<robot name="leg">{}{}{}
  <joint name="hip" type="revolute"><parent link="stand"/><child link="thigh"/>
    <origin rpy="{hip_rpy}"/><axis xyz="{hip_axis}"/><limit lower="-1" upper="1" effort="10" velocity="10"/></joint>
  <joint name="knee" type="revolute"><parent link="thigh"/><child link="shank"/>
    <origin xyz="0 0 -0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="10"/></joint>
  <link name="foot_holder"/>
  <joint name="foot" type="fixed"><parent link="shank"/><child link="foot_holder"/><origin xyz="0 0 -0.3"/></joint>
</robot>"#,
        link("stand"),
        link("thigh"),
        link("shank")
    );
    Model::from_urdf_str(&xml, BaseType::Fixed).unwrap()
}

#[test]
fn only_models_moving_in_the_xz_plane_are_planar() {
    // The reference hopper (slides along x and z, a joint about −y) and a planar base are planar.
    assert!(robot("hopper_2d.urdf", BaseType::Fixed).moves_in_xz_plane());
    let flamingo = robot_path("spring_flamingo")
        .read_dir()
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "urdf"))
        .unwrap();
    assert!(
        Model::from_urdf_file(&flamingo, BaseType::Planar)
            .unwrap()
            .moves_in_xz_plane()
    );
    // Floating bases move in 3D.
    assert!(!robot("brick.urdf", BaseType::Floating).moves_in_xz_plane());
    assert!(!robot("littledog/LittleDog.normalized.urdf", BaseType::Floating).moves_in_xz_plane());
    // A fixed-base leg: planar when its hip turns about y, even about a y reached through a
    // rotated joint frame (−y after a half turn about z); spatial with a hip about x, though
    // the foot's y-rate vanishes wherever the leg is folded onto the hip axis.
    assert!(fixed_leg("0 1 0", "0 0 0").moves_in_xz_plane());
    assert!(fixed_leg("0 1 0", "0 0 3.141592653589793").moves_in_xz_plane());
    assert!(!fixed_leg("1 0 0", "0 0 0").moves_in_xz_plane());
    assert!(!fixed_leg("0 1 0", "0.3 0 0").moves_in_xz_plane());
}
