//! HAMR-VI: the one-leg model's springs, gravity and actuator map against values computed
//! by hand from the URDF's numbers, the full robot's feet, the trot problem family as its
//! file states it, and the loop closures along a simulated stretch of the open-loop trot
//! (the robot's counts, mass and loop closure at q = 0 are in `model_robots::hamr_floating`).

use crate::common::problems_dir;
use crate::common::robots::robot;
use vito::model::{
    BaseType, Model, generalized_input_force, loop_residual, point_position, potential_energy,
    potential_energy_gradient,
};
use vito::problem::{Constraint, InitialGuess, Interval, Override, TimeSteps, load};

/// `FL_scaled.urdf` (the front-left leg on a welded chassis), with gravity g.
fn one_leg(gravity: f64) -> Model {
    let mut m = robot("hamr/FL_scaled.normalized.urdf", BaseType::Fixed);
    m.set_gravity([0.0, 0.0, -gravity]);
    m
}

/// The leg's eight coordinates in document order, and the stiffness of each from the
/// file's `<torsional_spring>`/`<prismatic_spring>` elements [N/mm or N·mm/rad].
const LEG: [(&str, f64); 8] = [
    ("FLqsact", 1.1556),
    ("FLqs1", 0.092),
    ("FLqs2", 0.034),
    ("FLqfb1", 0.06),
    ("FLqlact", 1.1556),
    ("FLql1", 0.2),
    ("FLql2", 0.034),
    ("FLqfb3", 0.034),
];

const Q: [f64; 8] = [0.1, 0.2, -0.1, 0.05, -0.15, 0.1, 0.3, -0.2];

#[test]
fn one_leg_has_eight_coordinates_two_inputs_and_three_closed_loops() {
    let m = one_leg(9.81e-3);
    let names: Vec<&str> = LEG.iter().map(|(n, _)| *n).collect();
    assert_eq!(m.coordinate_names(), names);
    assert_eq!(m.input_names(), ["FLqsact", "FLqlact"]);
    assert_eq!(m.loop_closures().len(), 3);
    assert_eq!(m.num_loop_constraints(), 6);
    let worst = loop_residual(&m, &[0.0f64; 8])
        .iter()
        .fold(0.0f64, |a, r| a.max(r.abs()));
    assert!(worst < 2e-7, "{worst:e}");
    // Moving the swing actuator alone opens the swing loop.
    let mut q = [0.0; 8];
    q[0] = 0.1;
    assert!(loop_residual(&m, &q).iter().any(|r: &f64| r.abs() > 1e-3));
}

/// Without gravity the potential is the springs' alone: Σ ½ k_i q_i², by hand
/// ½ (1.1556·0.1² + 0.092·0.2² + 0.034·0.1² + 0.06·0.05² + 1.1556·0.15² + 0.2·0.1²
/// + 0.034·0.3² + 0.034·0.2²) = 0.0240735 N·mm, and its gradient k_i q_i.
#[test]
fn one_leg_spring_potential_matches_hand_values() {
    let m = one_leg(0.0);
    let v = potential_energy(&m, &Q);
    assert!((v - 0.0240735).abs() < 1e-15, "{v}");
    let mut grad = vec![0.0; 8];
    potential_energy_gradient(&m, &Q, &mut grad);
    let hand = [
        0.11556, 0.0184, -0.0034, 0.003, -0.17334, 0.02, 0.0102, -0.0068,
    ];
    for (i, (g, h)) in grad.iter().zip(hand).enumerate() {
        assert!((g - h).abs() < 1e-15, "{}: {g} vs {h}", LEG[i].0);
    }
}

/// At q = 0 every frame is a pure translation, so each link's centre of mass sits at the
/// sum of the joint-origin z's along its chain plus its own COM z (FLL4: −0.50169 plus
/// 0.38169, 0, −1.07 and 3.37060 is 2.18060 mm). Σ m_i g z_i over the chassis and the eight
/// leg links is −3.2705128194e-3 N·mm; the springs add nothing there.
#[test]
fn one_leg_gravity_potential_at_zero_matches_the_urdf_sum() {
    let m = one_leg(9.81e-3);
    let v: f64 = potential_energy(&m, &[0.0f64; 8]);
    assert!((v - (-3.270_512_819_414_461e-3)).abs() < 1e-15, "{v}");
    assert!((m.total_mass() - 1.27332764).abs() < 1e-12);
    // The foot at (0, 7.58, −11.35) in FLL4 is at (12.7547, 17.37, −12.54) mm.
    let foot = m.link_index("FLL4").expect("FLL4");
    let p = point_position(&m, foot, &[0.0, 7.58, -11.35], &[0.0f64; 8]);
    let hand = [12.75465981539, 17.37, -12.54];
    for (a, b) in p.iter().zip(hand) {
        assert!((a - b).abs() < 1e-9, "{p:?}");
    }
}

/// The actuators are prismatic joints driven through SimpleTransmissions with reduction 1:
/// the generalised force of u = (swing, lift) is u on FLqsact and FLqlact and zero on the
/// six flexures, at any configuration.
#[test]
fn one_leg_actuator_map_puts_each_force_on_its_actuator_tip() {
    let m = one_leg(9.81e-3);
    for q in [[0.0; 8], Q] {
        let tau = generalized_input_force(&m, &q, &[0.28, -0.36]);
        assert_eq!(tau, [0.28, 0.0, 0.0, 0.0, -0.36, 0.0, 0.0, 0.0], "{q:?}");
    }
}

fn trot(overrides: &[(&str, &str)]) -> vito::problem::LoadedProblem {
    let overrides: Vec<Override> = overrides
        .iter()
        .map(|(k, v)| Override::parse(&format!("{k}={v}")).unwrap_or_else(|e| panic!("{e}")))
        .collect();
    load(&problems_dir().join("hamr_trot.toml"), &overrides).unwrap_or_else(|e| panic!("{e}"))
}

/// The trot family as the paper's scripts set it: 51 knots, T within ±10 % of one stride,
/// slack weight 50, swing ±0.28 N and lift ±0.36 N, periodicity of every coordinate but
/// base_x and of every velocity (through the discrete Legendre transform), q_1 free but for base_x = 0; the stride frequency and friction
/// are `--set`-able.
#[test]
fn trot_family_has_the_papers_settings() {
    let p = trot(&[]);
    let s = &p.spec;
    assert_eq!(p.robot.coordinates.len(), 38);
    assert_eq!(p.robot.inputs.len(), 8);
    assert_eq!(s.knots, 51);
    assert_eq!(s.slack_weight, 50.0);
    assert_eq!(s.contacts.len(), 4);
    assert!(s.contacts.iter().all(|c| c.friction == 0.6));
    let TimeSteps::FreeEqual { t_min, t_max } = s.time_steps else {
        panic!("{:?}", s.time_steps)
    };
    assert!((t_min - 90.0).abs() < 1e-12 && (t_max - 110.0).abs() < 1e-12);
    for (name, b) in p.robot.inputs.iter().zip(&s.input_bounds) {
        let limit = if name.ends_with("qsact") { 0.28 } else { 0.36 };
        assert_eq!(
            *b,
            Interval {
                lower: -limit,
                upper: limit
            },
            "{name}"
        );
    }
    let mut momentum = 0;
    let mut periodic = Vec::new();
    for c in &s.constraints {
        match c {
            Constraint::Periodic(r) if r.offset == Some(0.0) && !r.velocity => {
                periodic.push(p.robot.coordinates[r.coordinate].as_str())
            }
            Constraint::PeriodicMomentum(r) => momentum += r.names.len(),
            other => panic!("{other:?}"),
        }
    }
    assert_eq!(periodic.len(), 37);
    assert!(!periodic.contains(&"base_x"));
    // Every velocity, base_x's too, through the discrete Legendre transform.
    assert_eq!(momentum, 38);
    assert!(s.q_initial_free.iter().all(|&f| f));
    let InitialGuess::Simulation(guess) = &s.initial_guess else {
        panic!("{:?}", s.initial_guess)
    };
    assert!((guess.period - 100.0).abs() < 1e-12);

    let p = trot(&[("stride_hz", "2"), ("contacts.friction", "0.29")]);
    let TimeSteps::FreeEqual { t_min, t_max } = p.spec.time_steps else {
        panic!()
    };
    assert!((t_min - 450.0).abs() < 1e-9 && (t_max - 550.0).abs() < 1e-9);
    assert!(p.spec.contacts.iter().all(|c| c.friction == 0.29));
}

/// Along the open-loop trot of `[initial_guess.simulation]` (two 20 ms periods at a 1 ms
/// step, the first ramping the inputs in), simulated as `vito simulate` does (steps solved
/// to 1e-10 relative), every knot closes all 24 loop rows to below 1e-6 mm, and the inputs
/// move the actuator tips.
#[test]
fn simulated_trot_keeps_the_loops_closed() {
    let mut p = trot(&[("horizon.knots", "21"), ("stride_hz", "50")]);
    let InitialGuess::Simulation(guess) = &mut p.spec.initial_guess else {
        panic!()
    };
    guess.cycles = 2;
    let guess = guess.clone();
    let mech = vito::pipeline::mechanics(&p.spec).unwrap_or_else(|e| panic!("{e}"));
    let contact = p.spec.contact_model(&mech);
    let options = vito::sim::SimulationOptions {
        integrator: p.spec.integrator,
        h: 1.0,
        steps: 40,
        step: vito::sim::StepOptions {
            gravity: 9.81e-3,
            ..Default::default()
        },
    };
    let sim = vito::sim::simulate(
        &mech,
        &contact,
        &p.spec.q_initial,
        &[0.0; 38],
        &options,
        |_, t, _, _| guess.input(t),
        |_| {},
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let model = mech.model();
    for (k, q) in sim.q.iter().enumerate() {
        let worst = loop_residual(model, q)
            .iter()
            .fold(0.0f64, |a, r| a.max(r.abs()));
        assert!(worst < 1e-6, "knot {k}: loop residual {worst:e} mm");
    }
    let moved = (0..38)
        .filter(|&c| model.coordinate_names()[c].ends_with("act"))
        .flat_map(|c| sim.q.iter().map(move |q| q[c].abs()))
        .fold(0.0f64, f64::max);
    assert!(moved > 1e-3, "{moved}");
}

/// The simulated guess is one period on the knots: N knots from t = 0 to the period, N − 1
/// inputs, base_x moved to q_1's 0, and a finite periodicity defect.
#[test]
fn simulated_guess_is_the_last_period_on_the_knots() {
    let p = trot(&[("horizon.knots", "11"), ("stride_hz", "100")]);
    let InitialGuess::Simulation(guess) = &p.spec.initial_guess else {
        panic!()
    };
    let mech = vito::pipeline::mechanics(&p.spec).unwrap_or_else(|e| panic!("{e}"));
    let start =
        vito::sim::guess::simulate_guess(&mech, &p.spec, guess).unwrap_or_else(|e| panic!("{e}"));
    let w = &start.warm_start;
    assert_eq!((w.q.len(), w.u.len()), (11, 10));
    assert!((w.times[10] - 10.0).abs() < 1e-9, "{:?}", w.times);
    assert_eq!(w.q[0][0], 0.0);
    assert_eq!(start.steps, 30 * start.substeps);
    assert!(start.periodicity_defect.is_finite());
    // The inputs are the mean over each interval of the clipped sinusoid.
    assert!(w.u.iter().flatten().all(|u| u.abs() <= 0.36));
}
