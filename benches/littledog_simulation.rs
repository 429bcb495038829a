//! The issue-15 speed target: 1 s of LittleDog at 2 kHz (2,000 contact steps) on one core.
//! Two runs from `problems/littledog_step.toml`'s initial state, midpoint, h = 0.5 ms:
//! (1) PD holding the initial pose (`all = [2, 0.02]`), (2) PD tracking the problem's
//! solved plan (solved first, once; the plan's inputs as feedforward). Prints per run the wall
//! and on-CPU time per step (the process's CPU time from `/proc/self/schedstat`), Newton
//! iterations per step, steps accepted at the acceptable tolerance, and the load average.
//! No assertions on time.
//!
//! Run with `OPENBLAS_NUM_THREADS=1 cargo bench --bench littledog_simulation`.

use std::path::Path;
use std::time::Instant;

use vito::files::trajectory_csv::RecordedTrajectory;
use vito::pipeline::simulation::{
    PreparedSimulation, SimulateRequest, prepare_simulation, run_simulation,
};
use vito::problem::load;
use vito::sim::InputSource;
use vito::transcription::SolveOptions;

/// Nanoseconds this thread has spent on a CPU (Linux), if readable.
fn cpu_ns() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    text.split_whitespace().next()?.parse().ok()
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "?".into())
}

fn run(label: &str, prepared: &PreparedSimulation) {
    let cpu0 = cpu_ns();
    let start = Instant::now();
    let sim = run_simulation(prepared, |_| {});
    let wall = start.elapsed().as_secs_f64();
    let cpu = cpu0
        .zip(cpu_ns())
        .map(|(a, b)| (b - a) as f64 * 1e-9)
        .unwrap_or(f64::NAN);
    match sim {
        Ok(sim) => {
            let steps = sim.iterations.len() as f64;
            let iterations: usize = sim.iterations.iter().sum();
            println!(
                "{label:<28} {:>5} steps  wall {wall:6.3} s ({:6.0} µs/step)  CPU {cpu:6.3} s ({:6.0} µs/step)  Newton {:.2}/step  relaxed {}  load {}",
                sim.iterations.len(),
                1e6 * wall / steps,
                1e6 * cpu / steps,
                iterations as f64 / steps,
                sim.relaxed_steps.len(),
                load_average()
            );
        }
        Err(e) => println!(
            "{label:<28} stopped: {e} (after {wall:.3} s; load {})",
            load_average()
        ),
    }
}

fn main() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/littledog_step.toml");
    let problem = load(&file, &[]).unwrap_or_else(|e| panic!("{e}"));
    let request = SimulateRequest {
        rate: Some(2000.0),
        duration: Some(1.0),
        ..SimulateRequest::default()
    };
    let mut prepared = prepare_simulation(&problem, &request).unwrap_or_else(|e| panic!("{e}"));
    let gains = vito::pipeline::gains::parse_gains(&[], &["all=2,0.02".into()], &problem.robot)
        .unwrap_or_else(|e| panic!("{e}"));
    let pose = problem.spec.q_initial.clone();
    prepared.source = InputSource::Track {
        reference: RecordedTrajectory {
            times: vec![0.0, 1.0],
            q: vec![pose.clone(), pose],
            u: Vec::new(),
        },
        gains: gains.clone(),
        feedback: vito::sim::Feedback::Explicit,
    };
    run("stand (PD on the pose)", &prepared);

    let start = Instant::now();
    let plan = vito::pipeline::solve(&problem.spec, &SolveOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    println!(
        "plan: {} knots, objective {:.6}, {} iterations, {:.1} s to solve",
        plan.q.len(),
        plan.objective,
        plan.iterations,
        start.elapsed().as_secs_f64()
    );
    prepared.source = InputSource::Track {
        reference: RecordedTrajectory {
            times: plan.times.clone(),
            q: plan.q.clone(),
            u: plan.u.clone(),
        },
        gains,
        feedback: vito::sim::Feedback::Explicit,
    };
    run("track the plan (PD + ff)", &prepared);
}
