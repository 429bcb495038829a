//! PD gains by input name, for simulations that track a recorded trajectory: one resolution
//! of a name (`all` or an input's name) into the inputs it sets, used by the problem file's
//! `[tracking] gains` and by `--gains` on the command line.

use super::RobotInfo;

/// Where PD feedback reads the state (`[tracking] feedback`, `--feedback`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TrackingFeedback {
    /// From the step's start state (q_k, v_k), fixed before the step is solved.
    #[default]
    Explicit,
    /// From the step's end state (q_{k+1}, v_{k+1} = (q_{k+1} − q_k)/h) against the
    /// reference at t_{k+1}, solved with the step (its derivative in the step's Newton
    /// matrix): stable at gains where the explicit law diverges.
    Implicit,
}

impl TrackingFeedback {
    /// Every mode, in the order messages list them: the one list of names the command line,
    /// the problem file and the Python package accept.
    pub const ALL: [TrackingFeedback; 2] = [TrackingFeedback::Explicit, TrackingFeedback::Implicit];

    /// The name used by `--feedback` and `[tracking] feedback`.
    pub fn name(self) -> &'static str {
        match self {
            TrackingFeedback::Explicit => "explicit",
            TrackingFeedback::Implicit => "implicit",
        }
    }

    /// The mode named `name`, if any.
    pub fn from_name(name: &str) -> Option<TrackingFeedback> {
        TrackingFeedback::ALL.into_iter().find(|f| f.name() == name)
    }
}

impl std::str::FromStr for TrackingFeedback {
    type Err = String;

    /// The mode named `name` ([`TrackingFeedback::name`]); the error lists the names.
    fn from_str(name: &str) -> Result<Self, String> {
        TrackingFeedback::from_name(name).ok_or_else(|| {
            let names: Vec<String> = TrackingFeedback::ALL
                .map(|f| format!("{:?}", f.name()))
                .into();
            format!(
                "`{name}` is not a feedback mode: give one of {}",
                names.join(" or ")
            )
        })
    }
}

/// PD gains on one input, acting on the coordinate of the same name:
/// u = u_ref + kp (q_ref − q) + kd (v_ref − v).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackingGain {
    /// Input index (the robot's input order).
    pub input: usize,
    /// Coordinate index the input acts on.
    pub coordinate: usize,
    /// Proportional gain: input unit per coordinate unit (N·m/rad, N/m; robot units).
    pub kp: f64,
    /// Derivative gain: input unit per coordinate-rate unit (N·m·s/rad, N·s/m).
    pub kd: f64,
}

/// Why a gain could not be resolved.
#[derive(Debug, Clone, PartialEq)]
pub enum GainError {
    /// kp or kd is negative or not finite.
    Value,
    /// No input has this name.
    UnknownInput,
    /// The input acts on no coordinate of its own name.
    NoCoordinate(String),
}

/// The gains that `name = [kp, kd]` sets: every input for `all`, else the named one.
pub fn gains_for(
    robot: &RobotInfo,
    name: &str,
    kp: f64,
    kd: f64,
) -> Result<Vec<TrackingGain>, GainError> {
    if !(kp.is_finite() && kd.is_finite() && kp >= 0.0 && kd >= 0.0) {
        return Err(GainError::Value);
    }
    let inputs: Vec<usize> = if name == "all" {
        (0..robot.inputs.len()).collect()
    } else {
        vec![
            robot
                .inputs
                .iter()
                .position(|n| n == name)
                .ok_or(GainError::UnknownInput)?,
        ]
    };
    inputs
        .into_iter()
        .map(|input| {
            let input_name = &robot.inputs[input];
            let coordinate = robot
                .coordinates
                .iter()
                .position(|c| c == input_name)
                .ok_or_else(|| GainError::NoCoordinate(input_name.clone()))?;
            Ok(TrackingGain {
                input,
                coordinate,
                kp,
                kd,
            })
        })
        .collect()
}

/// Adds `later` to `gains`, each replacing any earlier gain on the same input.
pub fn merge_gains(gains: &mut Vec<TrackingGain>, later: &[TrackingGain]) {
    for g in later {
        gains.retain(|old| old.input != g.input);
        gains.push(*g);
    }
}
