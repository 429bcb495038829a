//! PD gains of `vito simulate --track` and the tracking study: the problem file's, with the
//! command line's on top.

use crate::transcription::TranscriptionError;

/// The gains `base` (the problem file's `[tracking] gains`) with `NAME=KP,KD` per input
/// (`all=KP,KD` for every input) from the command line on top; later entries win.
pub fn parse_gains(
    base: &[crate::problem::TrackingGain],
    gains: &[String],
    robot: &crate::problem::RobotInfo,
) -> Result<Vec<crate::sim::Gain>, TranscriptionError> {
    use crate::problem::tracking::{GainError, gains_for, merge_gains};
    let invalid = |message: String| TranscriptionError::Invalid {
        field: "--gains".into(),
        message,
    };
    let mut out = base.to_vec();
    for text in gains {
        let parsed = text.split_once('=').and_then(|(name, values)| {
            let (kp, kd) = values.split_once(',')?;
            Some((
                name.trim(),
                kp.trim().parse::<f64>().ok()?,
                kd.trim().parse::<f64>().ok()?,
            ))
        });
        let Some((name, kp, kd)) = parsed else {
            return Err(invalid(format!(
                "`{text}`: write NAME=KP,KD, e.g. knee=50,2"
            )));
        };
        let resolved = gains_for(robot, name, kp, kd).map_err(|e| match e {
            GainError::Value => invalid(format!("`{text}`: gains must be finite and ≥ 0")),
            GainError::UnknownInput => invalid(format!(
                "`{name}` is not an input of the robot (inputs: {})",
                crate::files::names::list_names(&robot.inputs, 24)
            )),
            GainError::NoCoordinate(input) => invalid(format!(
                "input `{input}` acts on no coordinate of that name"
            )),
        })?;
        merge_gains(&mut out, &resolved);
    }
    Ok(out)
}
