//! Forward simulation (issue 15): the step solver against conservation, resting contact,
//! Coulomb sliding and sticking, and the discrete-mechanics step.

use vito::discrete::{Integrator, Mechanics, ModelMechanics};
use vito::pipeline;
use vito::problem::ProblemSpec;
use vito::sim::{Simulation, SimulationOptions, StepOptions, simulate};
use vito::transcription::Context;

use crate::common::reference;

/// Simulates `spec`'s robot from (q0, v0) without inputs.
fn run(
    spec: &ProblemSpec,
    integrator: Integrator,
    q0: &[f64],
    v0: &[f64],
    h: f64,
    steps: usize,
) -> (ModelMechanics, Simulation) {
    let mech = pipeline::mechanics(spec).expect("robot loads");
    let ctx = Context::new(&mech, spec);
    let options = SimulationOptions {
        integrator,
        h,
        steps,
        step: StepOptions::default(),
    };
    let m = mech.nu();
    let sim = simulate(
        &mech,
        &ctx,
        q0,
        v0,
        &options,
        |_, _, _, _| vec![0.0; m],
        |_| {},
    )
    .expect("simulates");
    (mech, sim)
}

/// A brick dropped flat from 5 cm comes to rest on its face: penetration ≤ 1e-6 m, and over
/// the last 1,000 steps (1 s at 1 kHz) it moves less than 1e-9 m.
#[test]
fn dropped_brick_comes_to_rest_without_drift() {
    let spec = reference::brick_3d();
    let q0 = [0.0, 0.0, 0.075, 0.0, 0.0, 0.0];
    let (_, sim) = run(&spec, Integrator::Midpoint, &q0, &[0.0; 6], 1e-3, 1500);
    let rest = &sim.q[500];
    let last = sim.q.last().unwrap();
    let drift = rest
        .iter()
        .zip(last)
        .fold(0.0_f64, |a, (x, y)| a.max((x - y).abs()));
    let iterations: usize = sim.iterations.iter().sum();
    println!(
        "rest z {:.3e}, drift {drift:.3e}, penetration {:.3e}, mean iterations {:.2}, max complementarity {:.3e}",
        last[2] - 0.025,
        sim.max_penetration(),
        iterations as f64 / sim.iterations.len() as f64,
        sim.complementarity.iter().cloned().fold(0.0, f64::max)
    );
    assert!(
        sim.max_penetration() <= 1e-6,
        "penetration {}",
        sim.max_penetration()
    );
    assert!((last[2] - 0.025).abs() <= 1e-6, "rest height {}", last[2]);
    assert!(drift <= 1e-9, "drift {drift:e}");
}
