//! Where a simulation's inputs come from: zero, a recorded trajectory's inputs (zero-order
//! hold, as the NLP holds them), or PD feedback tracking a recorded trajectory by joint name
//! (with the recording's inputs as feedforward when it has them).

use super::step::{EndStateGain, StepInput};
use crate::files::trajectory_csv::RecordedTrajectory;

pub use crate::problem::TrackingFeedback as Feedback;
pub use crate::problem::TrackingGain as Gain;

/// The input policy of a simulation.
#[derive(Debug, Clone, PartialEq)]
pub enum InputSource {
    /// u = 0.
    Zero,
    /// u(t) = the recording's input on the interval holding t (the last one after its end).
    Replay(RecordedTrajectory),
    /// u = u_ref(t) + kp (q_ref(t) − q) + kd (v_ref(t) − v), q_ref linear between the
    /// recording's knots, v_ref its slope, u_ref held as in `Replay` (zero without inputs).
    Track {
        /// The reference.
        reference: RecordedTrajectory,
        /// Gains per input (inputs without gains get the feedforward alone).
        gains: Vec<Gain>,
        /// Whether the feedback reads the step's start or end state.
        feedback: Feedback,
    },
}

impl InputSource {
    /// u_k at time t for state (q, v); `m` inputs.
    pub fn input(&self, m: usize, t: f64, q: &[f64], v: &[f64]) -> Vec<f64> {
        match self {
            InputSource::Zero => vec![0.0; m],
            InputSource::Replay(r) => held_input(r, m, t),
            InputSource::Track {
                reference, gains, ..
            } => {
                let mut u = held_input(reference, m, t);
                let at = locate(reference, t);
                let (j, _) = at;
                let (t0, t1) = (reference.times[j], reference.times[j + 1]);
                for g in gains {
                    let (a, b) = (
                        reference.q[j][g.coordinate],
                        reference.q[j + 1][g.coordinate],
                    );
                    let q_ref = reference_at(reference, at, g.coordinate);
                    let v_ref = if t > *reference.times.last().unwrap_or(&t0) {
                        0.0
                    } else {
                        (b - a) / (t1 - t0)
                    };
                    u[g.input] +=
                        g.kp * (q_ref - q[g.coordinate]) + g.kd * (v_ref - v[g.coordinate]);
                }
                u
            }
        }
    }

    /// The input of the step from t (state (q, v)) to t + h: [`Self::input`] as a held input
    /// for explicit feedback; for [`Feedback::Implicit`], the feedforward held and the PD on
    /// q_{k+1} against q_ref(t + h), with v_ref = (q_ref(t + h) − q_ref(t))/h, as
    /// [`EndStateGain`]s of stiffness kp + kd/h.
    pub fn step_input(&self, m: usize, t: f64, h: f64, q: &[f64], v: &[f64]) -> StepInput {
        let InputSource::Track {
            reference,
            gains,
            feedback: Feedback::Implicit,
        } = self
        else {
            return self.input(m, t, q, v).into();
        };
        let (now, next) = (locate(reference, t), locate(reference, t + h));
        let feedback = gains
            .iter()
            .filter(|g| g.kp + g.kd / h > 0.0)
            .map(|g| {
                let q_ref = reference_at(reference, next, g.coordinate);
                let v_ref = (q_ref - reference_at(reference, now, g.coordinate)) / h;
                // kp (q_ref − q') + kd (v_ref − (q' − q)/h) = s (target − q'), s = kp + kd/h.
                let stiffness = g.kp + g.kd / h;
                let target = (g.kp * q_ref + g.kd * (v_ref + q[g.coordinate] / h)) / stiffness;
                EndStateGain {
                    input: g.input,
                    coordinate: g.coordinate,
                    stiffness,
                    target,
                }
            })
            .collect();
        StepInput {
            held: held_input(reference, m, t),
            feedback,
        }
    }
}

/// Where t falls in the recording: its interval j and the fraction s ∈ [0, 1] along it
/// (held past the ends). Located once per step, read for every gain.
fn locate(r: &RecordedTrajectory, t: f64) -> (usize, f64) {
    let j = interval(&r.times, t);
    let (t0, t1) = (r.times[j], r.times[j + 1]);
    (j, ((t - t0) / (t1 - t0)).clamp(0.0, 1.0))
}

/// The recording's coordinate `coordinate` at the place [`locate`] found, linear between
/// knots.
fn reference_at(r: &RecordedTrajectory, (j, s): (usize, f64), coordinate: usize) -> f64 {
    let (a, b) = (r.q[j][coordinate], r.q[j + 1][coordinate]);
    a + s * (b - a)
}

/// The interval j of `times` with times[j] ≤ t < times[j+1] (clamped to the first and last;
/// a time within 1e-9 of an interval's length before a knot counts as that knot, so that a
/// simulation on the recording's own grid holds the recording's inputs).
fn interval(times: &[f64], t: f64) -> usize {
    let last = times.len().saturating_sub(2);
    (0..=last)
        .rev()
        .find(|&j| t >= times[j] - 1e-9 * (times[j + 1] - times[j]))
        .unwrap_or(0)
}

fn held_input(r: &RecordedTrajectory, m: usize, t: f64) -> Vec<f64> {
    if r.u.is_empty() {
        return vec![0.0; m];
    }
    r.u[interval(&r.times, t).min(r.u.len() - 1)].clone()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn recording() -> RecordedTrajectory {
        RecordedTrajectory {
            times: vec![0.0, 0.1, 0.3],
            q: vec![vec![0.0], vec![1.0], vec![1.0]],
            u: vec![vec![2.0], vec![-1.0]],
        }
    }

    #[test]
    fn replay_holds_each_interval_input_and_tracking_adds_pd() {
        let replay = InputSource::Replay(recording());
        assert_eq!(replay.input(1, 0.0, &[0.0], &[0.0]), [2.0]);
        assert_eq!(replay.input(1, 0.1 - 1e-12, &[0.0], &[0.0]), [-1.0]);
        assert_eq!(replay.input(1, 0.05, &[0.0], &[0.0]), [2.0]);
        assert_eq!(replay.input(1, 5.0, &[0.0], &[0.0]), [-1.0]);
        let track = InputSource::Track {
            reference: recording(),
            gains: vec![Gain {
                input: 0,
                coordinate: 0,
                kp: 10.0,
                kd: 1.0,
            }],
            feedback: Feedback::Explicit,
        };
        // At t = 0.05: q_ref = 0.5, v_ref = 10; u = 2 + 10·(0.5 − 0.2) + 1·(10 − 3).
        let u = track.input(1, 0.05, &[0.2], &[3.0])[0];
        assert!((u - (2.0 + 3.0 + 7.0)).abs() < 1e-12, "{u}");
    }
}
