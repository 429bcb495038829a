//! The names the robot and the problem give `trajectory.csv`'s columns: each must appear
//! once, or the file could not be read back (as a warm start, by `simulate --track`).

use super::context::Context;
use crate::files::trajectory_csv::{ColumnSource, ColumnUnits, columns, repeated_column};
use crate::problem::{ContactSpec, ProblemError, RobotInfo, SlackMode};

/// Refuses coordinate, input and contact names whose columns would share a name (a joint
/// called `time`, a contact `foot` beside a joint `foot_x`).
pub(super) fn check_csv_columns(
    ctx: &Context,
    robot: &RobotInfo,
    contacts: &[ContactSpec],
    slack_mode: SlackMode,
) -> Result<(), ProblemError> {
    let contact_names: Vec<String> = contacts.iter().map(|c| c.name.clone()).collect();
    let slacks = match slack_mode {
        SlackMode::PerContact => 3 * contacts.len(),
        SlackMode::PerInterval | SlackMode::Penalty => 1,
    };
    let units = ColumnUnits {
        time: String::new(),
        length: String::new(),
        coordinates: Vec::new(),
        inputs: Vec::new(),
        impulse: String::new(),
    };
    // Every friction direction name either contact model uses (the plane's are the space's).
    let all = columns(
        &robot.coordinates,
        &robot.inputs,
        &contact_names,
        4,
        slacks,
        &units,
    );
    match repeated_column(&all) {
        None => Ok(()),
        Some((first, second)) => {
            // The URDF names coordinates and inputs; the problem file may name contacts.
            let from_urdf = |source: &ColumnSource| {
                matches!(source, ColumnSource::Coordinate(_) | ColumnSource::Input(_))
            };
            let field = if from_urdf(&first.source) || from_urdf(&second.source) {
                "robot.urdf"
            } else {
                "contacts"
            };
            Err(ctx.invalid(
                field,
                format!(
                    "{} and {} would both name a trajectory.csv column `{}`, and the file could \
                     not be read back; rename one (the joint or link in {}, or the contact)",
                    first.source,
                    second.source,
                    first.name,
                    robot.urdf.display()
                ),
            ))
        }
    }
}
