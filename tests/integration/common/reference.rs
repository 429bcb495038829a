//! SPEC.md's reference problems built in Rust (the CLI helper turns them into TOML files).

use std::path::PathBuf;

use vito::contact::Terrain;
use vito::ipopt::OptionValue;
use vito::model::BaseType;
use vito::problem::costs::{Input, StateTracking};
use vito::problem::{
    ContactSpec, CoordinateBound, CostTerm, HessianMode, InitialGuess, Integrator, Interval,
    KnotSet, ProblemSpec, RobotSpec, SlackMode, TimeSteps,
};

fn robot(file: &str, base: BaseType) -> RobotSpec {
    RobotSpec {
        urdf: PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("problems/robots")
            .join(file),
        base,
        gravity: [0.0, 0.0, -9.81],
        actuation: Default::default(),
    }
}

/// SPEC.md's Ipopt options for comparisons (tol 1e-6, mumps, 3000 iterations, adaptive μ).
pub fn spec_options() -> Vec<(String, OptionValue)> {
    vec![
        ("tol".into(), OptionValue::Num(1e-6)),
        ("linear_solver".into(), OptionValue::Str("mumps".into())),
        ("max_iter".into(), OptionValue::Int(3000)),
        ("mu_strategy".into(), OptionValue::Str("adaptive".into())),
    ]
}

/// hopper-2d: the planar hopper hops 0.5 m in 1 s (N = 21, h = 0.05).
pub fn hopper_2d() -> ProblemSpec {
    let start = vec![0.0, 0.5, 0.0, 0.5];
    let goal = vec![0.5, 0.5, 0.0, 0.5];
    ProblemSpec {
        name: "hopper_2d".into(),
        robot: robot("hopper_2d.urdf", BaseType::Fixed),
        contacts: vec![ContactSpec {
            name: "foot_contact".into(),
            link: "foot".into(),
            point: [0.0; 3],
            radius: 0.0,
            friction: 0.8,
        }],
        terrain: Terrain::default(),
        knots: 21,
        time_steps: TimeSteps::Fixed(0.05),
        integrator: Integrator::Midpoint,
        slack_weight: 100.0,
        slack_mode: SlackMode::PerInterval,
        slack_tolerance: vito::transcription::DEFAULT_SLACK_TOLERANCE,
        slack_continuation: None,
        max_slip_speed: None,
        q_initial_free: vec![false; start.len()],
        q_initial: start.clone(),
        v_initial: Some(vec![0.0; 4]),
        q_final: goal.iter().map(|&g| Interval::fixed(g)).collect(),
        bounds: vec![
            CoordinateBound {
                coordinate: 3,
                knots: KnotSet::All,
                bound: Interval {
                    lower: 0.3,
                    upper: 0.7,
                },
            },
            CoordinateBound {
                coordinate: 1,
                knots: KnotSet::All,
                bound: Interval {
                    lower: 0.0,
                    upper: f64::INFINITY,
                },
            },
        ],
        joint_limits: false,
        input_bounds: vec![
            Interval {
                lower: -10.0,
                upper: 10.0,
            },
            Interval {
                lower: -100.0,
                upper: 100.0,
            },
        ],
        costs: vec![
            CostTerm::StateTracking(StateTracking {
                q_target: goal.clone(),
                v_target: vec![0.0; 4],
                q_weights: vec![1.0; 4],
                v_weights: vec![0.0; 4],
                time_weighted: true,
            }),
            CostTerm::Input(Input {
                weights: vec![0.1, 0.01],
                time_weighted: true,
            }),
        ],
        constraints: vec![],
        initial_guess: InitialGuess::Linear {
            from: start,
            to: goal,
        },
        hessian: HessianMode::Exact,
        solver_options: spec_options(),
        metrics: Default::default(),
    }
}

/// Names of the brick's corners in brick.urdf order.
pub const BRICK_CORNERS: [&str; 8] = [
    "corner_ppp",
    "corner_ppm",
    "corner_pmp",
    "corner_pmm",
    "corner_mpp",
    "corner_mpm",
    "corner_mmp",
    "corner_mmm",
];

/// brick-3d: a tumbling brick falls and comes to rest (N = 41, h = 0.025).
pub fn brick_3d() -> ProblemSpec {
    let start = vec![0.0, 0.0, 0.25, 0.3, -0.2, 0.1];
    let contacts = BRICK_CORNERS
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let sign = |bit: usize| if i & bit == 0 { 1.0 } else { -1.0 };
            ContactSpec {
                name: (*name).into(),
                link: "brick".into(),
                point: [sign(4) * 0.1, sign(2) * 0.05, sign(1) * 0.025],
                radius: 0.0,
                friction: 0.5,
            }
        })
        .collect();
    ProblemSpec {
        name: "brick_3d".into(),
        robot: robot("brick.urdf", BaseType::Floating),
        contacts,
        terrain: Terrain::default(),
        knots: 41,
        time_steps: TimeSteps::Fixed(0.025),
        integrator: Integrator::Midpoint,
        slack_weight: 1000.0,
        slack_mode: SlackMode::PerInterval,
        slack_tolerance: vito::transcription::DEFAULT_SLACK_TOLERANCE,
        slack_continuation: None,
        max_slip_speed: None,
        q_initial_free: vec![false; start.len()],
        q_initial: start.clone(),
        v_initial: Some(vec![1.0, 0.0, 0.0, 2.0, 1.0, 0.0]),
        q_final: vec![Interval::FREE; 6],
        bounds: vec![],
        joint_limits: false,
        input_bounds: vec![],
        costs: vec![],
        constraints: vec![],
        initial_guess: InitialGuess::Linear {
            from: start.clone(),
            to: start,
        },
        hessian: HessianMode::Exact,
        solver_options: spec_options(),
        metrics: Default::default(),
    }
}

fn box_bound(lower: f64, upper: f64) -> Interval {
    Interval { lower, upper }
}

/// spring-flamingo-walk: the planar biped walks 0.9 m (towards −x), N = 25, free steps.
pub fn spring_flamingo_walk() -> ProblemSpec {
    let delta = std::f64::consts::FRAC_PI_2 - 1.57075;
    let start = vec![0.0, 0.875, 0.0, 0.0, 0.0, delta, 0.0, 0.0, delta];
    let mut goal = start.clone();
    goal[0] = -0.9;
    let contact = |name: &str| ContactSpec {
        name: name.into(),
        link: name.into(),
        point: [0.0; 3],
        radius: 0.0,
        friction: 1.0,
    };
    ProblemSpec {
        name: "spring_flamingo_walk".into(),
        robot: robot(
            "spring_flamingo/spring_flamingo_passive_ankle.normalized.urdf",
            BaseType::Planar,
        ),
        contacts: vec![
            contact("right_forward_contact_point"),
            contact("right_rear_contact_point"),
            contact("left_forward_contact_point"),
            contact("left_rear_contact_point"),
        ],
        terrain: Terrain::default(),
        knots: 25,
        time_steps: TimeSteps::FreeEqual {
            t_min: 0.5,
            t_max: 2.5,
        },
        integrator: Integrator::Midpoint,
        slack_weight: 1e4,
        slack_mode: SlackMode::PerInterval,
        slack_tolerance: vito::transcription::DEFAULT_SLACK_TOLERANCE,
        slack_continuation: None,
        max_slip_speed: None,
        q_initial_free: vec![false; start.len()],
        q_initial: start.clone(),
        v_initial: Some(vec![0.0; 9]),
        q_final: goal.iter().map(|&g| Interval::fixed(g)).collect(),
        bounds: vec![CoordinateBound {
            coordinate: 1,
            knots: KnotSet::All,
            bound: box_bound(f64::NEG_INFINITY, 0.876),
        }],
        joint_limits: true,
        input_bounds: vec![box_bound(-300.0, 300.0); 4],
        // SPEC's 0.1·|x̄ − x_g|² + |u|² in the ½-weighted form of CostTerm.
        costs: vec![
            CostTerm::StateTracking(StateTracking {
                q_target: goal.clone(),
                v_target: vec![0.0; 9],
                q_weights: vec![0.2; 9],
                v_weights: vec![0.2; 9],
                time_weighted: true,
            }),
            CostTerm::Input(Input {
                weights: vec![2.0; 4],
                time_weighted: true,
            }),
        ],
        constraints: vec![],
        initial_guess: InitialGuess::Linear {
            from: start,
            to: goal,
        },
        hessian: HessianMode::Exact,
        solver_options: spec_options(),
        metrics: Default::default(),
    }
}

/// littledog-step: the quadruped climbs an 11 cm (smoothed) step, N = 30, free steps.
pub fn littledog_step() -> ProblemSpec {
    let mut start = vec![0.0, 0.0, 0.136, 0.0, 0.0, 0.0];
    // FL, FR, BL, BR: hip_roll, hip_pitch, knee.
    start.extend([
        0.1, 1.0, -1.55, -0.1, 1.0, -1.55, 0.1, -1.0, 1.55, -0.1, -1.0, 1.55,
    ]);
    let mut goal = start.clone();
    goal[0] = 0.45;
    goal[2] = 0.246;
    let contact = |name: &str, link: &str, x: f64| ContactSpec {
        name: name.into(),
        link: link.into(),
        point: [x, 0.0, -0.0985],
        radius: 0.0,
        friction: 1.0,
    };
    let mut q_weights = vec![0.0, 0.0, 0.0, 10.0, 10.0, 10.0];
    q_weights.extend([5.0, 1.0, 1.0, 5.0, 1.0, 1.0, 5.0, 1.0, 1.0, 5.0, 1.0, 1.0]);
    ProblemSpec {
        name: "littledog_step".into(),
        robot: robot("littledog/LittleDog.normalized.urdf", BaseType::Floating),
        contacts: vec![
            contact("front_left_foot", "front_left_lower_leg", -0.0265),
            contact("front_right_foot", "front_right_lower_leg", -0.0265),
            contact("back_left_foot", "back_left_lower_leg", 0.0265),
            contact("back_right_foot", "back_right_lower_leg", 0.0265),
        ],
        terrain: Terrain {
            ground_height: 0.0,
            steps: vec![vito::contact::Step {
                edge_x: 0.25,
                rise: 0.11,
                width: 0.005,
            }],
        },
        knots: 30,
        time_steps: TimeSteps::FreeEqual {
            t_min: 1.0,
            t_max: 4.0,
        },
        integrator: Integrator::Midpoint,
        slack_weight: 300.0,
        slack_mode: SlackMode::PerInterval,
        slack_tolerance: vito::transcription::DEFAULT_SLACK_TOLERANCE,
        slack_continuation: None,
        max_slip_speed: None,
        q_initial_free: vec![false; start.len()],
        q_initial: start.clone(),
        v_initial: Some(vec![0.0; 18]),
        q_final: goal
            .iter()
            .map(|&g| box_bound(g - 0.01, g + 0.01))
            .collect(),
        bounds: vec![CoordinateBound {
            coordinate: 2,
            knots: KnotSet::All,
            bound: box_bound(0.0, 0.256),
        }],
        joint_limits: true,
        input_bounds: vec![Interval::FREE; 12],
        costs: vec![
            CostTerm::StateTracking(StateTracking {
                q_target: goal.clone(),
                v_target: vec![0.0; 18],
                q_weights,
                v_weights: vec![1.0; 18],
                time_weighted: true,
            }),
            CostTerm::Input(Input {
                weights: vec![10.0; 12],
                time_weighted: true,
            }),
        ],
        constraints: vec![],
        initial_guess: InitialGuess::Linear {
            from: start,
            to: goal,
        },
        hessian: HessianMode::Exact,
        solver_options: spec_options(),
        metrics: Default::default(),
    }
}
