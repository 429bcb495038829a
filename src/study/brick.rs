//! Figure 5 of the paper: a tumbling brick dropped from seeded random initial states,
//! simulated open loop over a fixed horizon T by each method with K knots (K − 1 steps of
//! h = T/(K − 1)), against a reference from the first-order method at 2 kHz. A run's error is
//! the RMS over its knots of ‖q_k − q_ref(t_k)‖ (configuration in the problem's units: m and
//! rad for the brick), q_ref linear between the reference's knots.

use super::{PAPER_METHODS, StudyError, StudyMethod, StudyRow, StudyTable};
use crate::contact::ContactModel;
use crate::discrete::{Integrator, Mechanics, ModelMechanics};
use crate::problem::ProblemSpec;
use crate::random::SeededRng;
use crate::sim::{Simulation, SimulationOptions, StepOptions, simulate};

/// The study's settings.
#[derive(Debug, Clone, PartialEq)]
pub struct BrickAccuracy {
    /// Random initial states (seeds 0..seeds).
    pub seeds: usize,
    /// Knot counts K (each ≥ 2).
    pub knots: Vec<usize>,
    /// Horizon T (the problem's time unit).
    pub horizon: f64,
    /// Steps per time unit of the reference.
    pub reference_rate: f64,
    /// The reference's method (the paper's: first order).
    pub reference: Integrator,
    /// Largest initial angular rate per roll–pitch–yaw coordinate (rad per time unit).
    pub spin: f64,
    /// Largest initial roll and pitch (rad).
    pub tilt: f64,
    /// The methods compared (the paper's: first order and midpoint).
    pub methods: Vec<Integrator>,
}

impl Default for BrickAccuracy {
    fn default() -> Self {
        BrickAccuracy {
            seeds: 20,
            knots: (3..=16).collect(),
            horizon: 0.5,
            reference_rate: 2000.0,
            reference: Integrator::Euler,
            spin: 0.5,
            tilt: 0.2,
            methods: PAPER_METHODS.to_vec(),
        }
    }
}

/// A seeded initial state of the brick (floating base: x, y, z, roll, pitch, yaw): thrown
/// from 0.2–0.5 m up, any yaw, roll and pitch within ±`tilt` rad, up to 1 m/s per axis and
/// `spin` rad/s per angle.
pub fn initial_state(seed: u64, spin: f64, tilt: f64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = SeededRng::new(0x5eed_b41c ^ seed.wrapping_mul(0x9e37_79b9_7f4a_7c15));
    let pi = std::f64::consts::PI;
    let q = vec![
        0.0,
        0.0,
        rng.range(0.2, 0.5),
        rng.symmetric(tilt),
        rng.symmetric(tilt),
        rng.symmetric(pi),
    ];
    let v = vec![
        rng.symmetric(1.0),
        rng.symmetric(1.0),
        rng.symmetric(1.0),
        rng.symmetric(spin),
        rng.symmetric(spin),
        rng.symmetric(spin),
    ];
    (q, v)
}

impl BrickAccuracy {
    /// Checks the settings (one error naming the option).
    pub fn check(&self) -> Result<(), StudyError> {
        let invalid = |field: &str, message: &str| {
            Err(StudyError::Invalid {
                field: field.into(),
                message: message.into(),
            })
        };
        if self.methods.is_empty() {
            return invalid(
                "--methods",
                "give at least one integrator, e.g. euler,midpoint",
            );
        }
        if self.seeds == 0 || self.seeds > 10_000 {
            return invalid("--seeds", "give 1 to 10000 initial states");
        }
        if self.knots.is_empty() || self.knots.iter().any(|&k| !(2..=100_000).contains(&k)) {
            return invalid("--knots", "give knot counts from 2 to 100000, e.g. 3,4,5");
        }
        if !(self.horizon.is_finite() && self.horizon > 0.0 && self.horizon <= 100.0) {
            return invalid("--horizon", "give a horizon in (0, 100] time units");
        }
        if !(self.spin.is_finite() && (0.0..=100.0).contains(&self.spin)) {
            return invalid(
                "--spin",
                "give an angular rate in [0, 100] rad per time unit",
            );
        }
        if !(self.tilt.is_finite() && (0.0..=1.5).contains(&self.tilt)) {
            return invalid(
                "--tilt",
                "give a tilt in [0, 1.5] rad (pitch ±π/2 is the roll–pitch–yaw chart's singularity)",
            );
        }
        if !(self.reference_rate.is_finite()
            && self.reference_rate > 0.0
            && self.reference_rate * self.horizon <= 1e7)
        {
            return invalid(
                "--reference-rate",
                "give a positive rate with at most 1e7 steps over the horizon",
            );
        }
        Ok(())
    }

    /// Runs the study on the brick of `spec` (its robot, contacts, terrain and gravity; its
    /// initial state is replaced by the seeded ones). `progress(done, total)` after each run.
    pub fn run(
        &self,
        spec: &ProblemSpec,
        mut progress: impl FnMut(usize, usize),
    ) -> Result<StudyTable, StudyError> {
        self.check()?;
        let mech = crate::pipeline::mechanics(spec)?;
        let contact = spec.contact_model(&mech);
        if mech.nq() != 6 || mech.nu() != 0 {
            return Err(StudyError::Invalid {
                field: "--problem".into(),
                message: format!(
                    "the brick study needs a floating body without inputs (6 coordinates, 0 inputs); this robot has {} and {}",
                    mech.nq(),
                    mech.nu()
                ),
            });
        }
        let gravity = spec.robot.gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
        let mut rows: Vec<StudyRow> = self
            .knots
            .iter()
            .flat_map(|&knots| {
                self.methods.iter().map(move |&method| StudyRow {
                    knots,
                    method,
                    runs: Vec::new(),
                })
            })
            .collect();
        let total = self.seeds * (1 + rows.len());
        let mut done = 0;
        for seed in 0..self.seeds as u64 {
            let (q0, v0) = initial_state(seed, self.spin, self.tilt);
            let steps = (self.horizon * self.reference_rate).round() as usize;
            let reference = run_method(
                &mech,
                &contact,
                &q0,
                &v0,
                self.reference,
                self.horizon / steps as f64,
                steps,
                gravity,
            )
            .map_err(|source| StudyError::Simulation {
                what: format!("seed {seed}, reference"),
                source,
            })?;
            done += 1;
            progress(done, total);
            for row in &mut rows {
                let steps = row.knots - 1;
                let sim = run_method(
                    &mech,
                    &contact,
                    &q0,
                    &v0,
                    row.method,
                    self.horizon / steps as f64,
                    steps,
                    gravity,
                )
                .map_err(|source| StudyError::Simulation {
                    what: format!(
                        "seed {seed}, {} with {} knots",
                        row.method.study_name(),
                        row.knots
                    ),
                    source,
                })?;
                row.runs.push(rms_error(&sim, &reference));
                done += 1;
                progress(done, total);
            }
        }
        Ok(StudyTable { rows })
    }
}

#[allow(clippy::too_many_arguments)]
fn run_method(
    mech: &ModelMechanics,
    contact: &ContactModel,
    q0: &[f64],
    v0: &[f64],
    method: Integrator,
    h: f64,
    steps: usize,
    gravity: f64,
) -> Result<Simulation, crate::sim::SimulationError> {
    let options = SimulationOptions {
        integrator: method,
        h,
        steps,
        step: StepOptions {
            gravity,
            ..StepOptions::default()
        },
    };
    simulate(
        mech,
        contact,
        q0,
        v0,
        &options,
        |_, _, _, _| Vec::new(),
        |_| {},
    )
}

/// √(mean over the knots of `sim` of d(q_k, q_ref(t_k))²), q_ref linear between the
/// reference's knots, d the [`configuration_distance`].
pub fn rms_error(sim: &Simulation, reference: &Simulation) -> f64 {
    let sum: f64 = sim
        .times
        .iter()
        .zip(&sim.q)
        .map(|(&t, q)| configuration_distance(q, &interpolate(reference, t)).powi(2))
        .sum();
    (sum / sim.q.len() as f64).sqrt()
}

/// The distance between two brick configurations [x, y, z, roll, pitch, yaw]:
/// √(‖Δposition‖² + θ²), θ the angle of the rotation between the two orientations (rad),
/// R = Rz(yaw)·Ry(pitch)·Rx(roll). Independent of the roll–pitch–yaw chart: two sets of
/// angles naming one orientation (yaw + 2π, or roll and yaw traded at pitch ±π/2) are at
/// distance zero, which a difference of angles would count as radians of error.
pub fn configuration_distance(a: &[f64], b: &[f64]) -> f64 {
    let rotation = |q: &[f64]| nalgebra::UnitQuaternion::from_euler_angles(q[3], q[4], q[5]);
    // 2·atan2(|v|, |w|) of the relative quaternion: no acos rounding to NaN near zero.
    let relative = rotation(a).inverse() * rotation(b);
    let angle = 2.0 * relative.imag().norm().atan2(relative.w.abs());
    let position: f64 = (0..3).map(|i| (a[i] - b[i]).powi(2)).sum();
    (position + angle * angle).sqrt()
}

/// The reference's configuration at t, linear between its knots (clamped to its span).
fn interpolate(reference: &Simulation, t: f64) -> Vec<f64> {
    let times = &reference.times;
    let last = times.len() - 1;
    let j = times.partition_point(|&s| s <= t).clamp(1, last);
    let (t0, t1) = (times[j - 1], times[j]);
    let s = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
    reference.q[j - 1]
        .iter()
        .zip(&reference.q[j])
        .map(|(a, b)| a + s * (b - a))
        .collect()
}
