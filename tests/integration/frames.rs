//! Frame terms (`[[frame]]`, `problem::frames`): each quantity's value against a pose worked
//! out by hand (the hopper's foot on a step, its body's pitch, the foot's velocity; LittleDog's
//! body angles), as rows and as costs, and their derivatives against finite differences
//! (`vito check --derivatives`' check).

use crate::common::reference::{appended, hopper_appended};
use vito::discrete::ModelMechanics;
use vito::pipeline::kinematics::Kinematics;
use vito::problem::LoadedProblem;
use vito::random::SeededRng;
use vito::transcription::{DerivativeKind, Transcription};

/// The hopper with a 0.11 m step at x = 0.25 (width 0.005) and frame terms at knot 5.
const HOPPER_TERMS: &str = r#"
[[terrain.step]]
edge_x = 0.25
rise = 0.11
width = 0.005

[[frame]]
type = "clearance"
contact = "foot_contact"
knots = [5]
lower = 0.0

[[frame]]
type = "position"
link = "foot"
axis = "x"
knots = [5]
target = 0.5
weight = 4.0

[[frame]]
type = "orientation"
link = "body"
axis = "pitch"
knots = [5]
lower = -0.5
upper = 0.5

[[frame]]
type = "velocity"
contact = "foot_contact"
axis = "z"
knots = [5]
upper = 10.0
"#;

/// The NLP of `p` and a point: its initial point with q_4 and q_5 set.
fn at_pose(
    p: &LoadedProblem,
    q4: [f64; 4],
    q5: [f64; 4],
) -> (Transcription<ModelMechanics>, Vec<f64>) {
    let nlp = Transcription::new(ModelMechanics::load(&p.spec).unwrap(), &p.spec).unwrap();
    let mut x = nlp.initial_point().to_vec();
    let l = nlp.layout();
    x[l.q(4)].copy_from_slice(&q4);
    x[l.q(5)].copy_from_slice(&q5);
    (nlp, x)
}

fn row(nlp: &Transcription<ModelMechanics>, x: &[f64], label: &str) -> f64 {
    let l = nlp.layout();
    let r = l
        .constraint_rows
        .iter()
        .position(|name| name == label)
        .unwrap_or_else(|| panic!("no row {label:?} among {:?}", l.constraint_rows));
    let mut g = vec![0.0; l.num_constraints()];
    nlp.constraints(x, &mut g);
    g[l.constraint_row(r)]
}

/// The hopper's foot: (x + r sin θ, 0, z − r cos θ) (θ turns about −y, r slides along the
/// turned −z); its body's pitch is −θ.
fn hopper_foot(q: [f64; 4]) -> [f64; 3] {
    let [x, z, theta, r] = q;
    [x + r * theta.sin(), 0.0, z - r * theta.cos()]
}

#[test]
fn each_quantity_matches_the_pose_worked_out_by_hand() {
    let p = hopper_appended(HOPPER_TERMS).unwrap();
    // q = [x, z, θ, r]: the foot at x = 0.4 + 0.5 sin 0.3 = 0.5478, past the step's edge,
    // z = 0.6 − 0.5 cos 0.3 = 0.122332, so 0.012332 above the step's top (0.11).
    let q4 = [0.38, 0.58, 0.25, 0.48];
    let q5 = [0.4, 0.6, 0.3, 0.5];
    let (nlp, x) = at_pose(&p, q4, q5);
    let foot = hopper_foot(q5);
    let step = 0.11 * 0.5 * (1.0 + ((foot[0] - 0.25) / 0.005_f64).tanh());
    assert!((step - 0.11).abs() < 1e-12, "the foot is past the edge");
    let clearance = row(&nlp, &x, "frame[0] clearance foot_contact at knot 5");
    assert!((clearance - (foot[2] - step)).abs() < 1e-12, "{clearance}");
    assert!((clearance - 0.012_331_8).abs() < 1e-6, "{clearance}");
    let pitch = row(&nlp, &x, "frame[2] orientation body pitch at knot 5");
    assert!((pitch + 0.3).abs() < 1e-12, "{pitch}");
    let h = 0.05;
    let vz = (foot[2] - hopper_foot(q4)[2]) / h;
    let velocity = row(&nlp, &x, "frame[3] velocity foot_contact z at knot 5");
    assert!((velocity - vz).abs() < 1e-10, "{velocity} against {vz}");
    // The cost: ½·4·(foot_x − 0.5)².
    let cost = nlp
        .objective_terms(&x)
        .into_iter()
        .find(|(name, _)| name == "frame_position")
        .expect("a frame_position term")
        .1;
    let expected = 0.5 * 4.0 * (foot[0] - 0.5).powi(2);
    assert!((cost - expected).abs() < 1e-12, "{cost} against {expected}");
    // The row bounds are the file's.
    let (lower, upper) = nlp.constraint_bounds();
    let l = nlp.layout();
    let first = l.constraint_row(0);
    assert_eq!(&lower[first..first + 3], &[0.0, -0.5, f64::NEG_INFINITY]);
    assert_eq!(&upper[first..first + 3], &[f64::INFINITY, 0.5, 10.0]);
}

#[test]
fn littledogs_body_angles_are_its_base_angles() {
    let extra = r#"
[[frame]]
type = "orientation"
link = "body"
axis = "roll"
knots = "final"
upper = 1.0
"#;
    let p = appended(
        "littledog_walk",
        "robots/littledog/LittleDog.normalized.urdf",
        extra,
        &[],
    )
    .unwrap();
    let kinematics = Kinematics::new(&p.spec).unwrap();
    let mut q = p.spec.q_initial.clone();
    let index = |name: &str| p.robot.coordinates.iter().position(|c| c == name).unwrap();
    q[index("base_roll")] = 0.1;
    q[index("base_pitch")] = -0.2;
    q[index("base_yaw")] = 0.3;
    let pose = kinematics.link_pose("body", &q).unwrap();
    for (got, want) in pose.roll_pitch_yaw.iter().zip([0.1, -0.2, 0.3]) {
        assert!((got - want).abs() < 1e-12, "{:?}", pose.roll_pitch_yaw);
    }
    let nlp = Transcription::new(ModelMechanics::load(&p.spec).unwrap(), &p.spec).unwrap();
    let mut x = nlp.initial_point().to_vec();
    let last = p.spec.knots - 1;
    x[nlp.layout().q(last)].copy_from_slice(&q);
    let roll = row(
        &nlp,
        &x,
        &format!("frame[0] orientation body roll at knot {last}"),
    );
    assert!((roll - 0.1).abs() < 1e-12, "{roll}");
}

#[test]
fn contact_positions_by_name_match_the_hopper_worked_out_by_hand() {
    let p = hopper_appended("").unwrap();
    let kinematics = Kinematics::new(&p.spec).unwrap();
    let q = [0.1, 0.7, -0.4, 0.35];
    let got = kinematics.contact_position("foot_contact", &q).unwrap();
    let want = hopper_foot(q);
    for a in 0..3 {
        assert!((got[a] - want[a]).abs() < 1e-12, "{got:?} against {want:?}");
    }
    let point = kinematics
        .point_position("body", [0.0, 0.0, -0.35], &q)
        .unwrap();
    for a in 0..3 {
        assert!(
            (point[a] - want[a]).abs() < 1e-12,
            "{point:?} against {want:?}"
        );
    }
    assert!(kinematics.contact_position("toe", &q).is_err());
    assert!(
        kinematics
            .contact_position("foot_contact", &q[..3])
            .is_err()
    );
}

#[test]
fn frame_derivatives_match_finite_differences() {
    let p = hopper_appended(HOPPER_TERMS).unwrap();
    let mut rng = SeededRng::new(11);
    let mut q = || {
        [
            0.3 + 0.2 * rng.unit(),
            0.5 + 0.2 * rng.unit(),
            0.2 + 0.2 * rng.unit(),
            0.4 + 0.2 * rng.unit(),
        ]
    };
    let (nlp, x) = at_pose(&p, q(), q());
    let check = nlp.check_derivatives(&x, 7);
    assert!(check.passed(), "{} entries fail", check.failures().count());
    for kind in [DerivativeKind::Jacobian, DerivativeKind::Hessian] {
        assert!(check.worst(kind).is_some());
    }
}

#[test]
fn bad_frame_entries_name_their_field() {
    let cases = [
        (
            "type = \"height\"\ncontact = \"foot_contact\"\nlower = 0.0",
            "frame[0].type",
        ),
        (
            "type = \"position\"\ncontact = \"foot_contact\"\nlower = 0.0",
            "frame[0].axis",
        ),
        (
            "type = \"clearance\"\ncontact = \"toe\"\nlower = 0.0",
            "frame[0].contact",
        ),
        (
            "type = \"clearance\"\nlink = \"shin\"\nlower = 0.0",
            "frame[0].link",
        ),
        (
            "type = \"clearance\"\ncontact = \"foot_contact\"",
            "frame[0].weight",
        ),
        (
            "type = \"clearance\"\ncontact = \"foot_contact\"\nwindow = [0.5, 1.5]\nlower = 0.0",
            "frame[0].window",
        ),
        (
            "type = \"velocity\"\ncontact = \"foot_contact\"\naxis = \"x\"\nknots = [0]\nupper = 1.0",
            "frame[0].knots",
        ),
        (
            "type = \"clearance\"\ncontact = \"foot_contact\"\nlower = 0.2\nupper = 0.1",
            "frame[0].upper",
        ),
    ];
    for (entry, field) in cases {
        let err = hopper_appended(&format!("\n[[frame]]\n{entry}\n"))
            .unwrap_err()
            .to_string();
        assert!(err.contains(field), "{entry:?}: {err}");
    }
}

#[test]
fn a_window_chooses_the_knots_whose_time_lies_in_it() {
    let p = hopper_appended(
        "\n[[frame]]\ntype = \"clearance\"\ncontact = \"foot_contact\"\nwindow = [0.2, 0.35]\nlower = 0.01\n",
    )
    .unwrap();
    // h = 0.05: knots 4, 5, 6, 7 lie in [0.2, 0.35] s.
    assert_eq!(p.spec.frames[0].knots, [4, 5, 6, 7]);
}

#[test]
fn a_gait_expands_into_stance_and_swing_windows() {
    // h = 0.05, period 0.5 s, duty 0.5: stance while t mod 0.5 < 0.25.
    let p = hopper_appended(
        "\n[gait]\nperiod = 0.5\nduty = 0.5\nclearance = 0.03\noffsets = { foot_contact = 0.0 }\n",
    )
    .unwrap();
    let frames = &p.spec.frames;
    let knots: Vec<(&[usize], f64, f64)> = frames
        .iter()
        .map(|f| (f.knots.as_slice(), f.lower, f.upper))
        .collect();
    let inf = f64::INFINITY;
    assert_eq!(
        knots,
        [
            (&[1, 2, 3, 4][..], 0.0, 0.0),
            (&[6, 7, 8][..], 0.03, inf),
            (&[10, 11, 12, 13, 14][..], 0.0, 0.0),
            (&[16, 17, 18][..], 0.03, inf),
            (&[20][..], 0.0, 0.0),
        ]
    );
    let intervals: Vec<usize> = p.spec.zero_impulse.iter().map(|&(_, j)| j).collect();
    assert_eq!(intervals, [4, 5, 6, 7, 8, 14, 15, 16, 17, 18]);
}
