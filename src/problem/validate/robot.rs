//! `[robot]`: units, base, URDF and gravity.

use std::path::Path;

use super::context::Context;
use super::values::finite;
use crate::model::{Actuation, BaseType};
use crate::problem::schema::{ActuatedEntry, BaseName, ProblemFile};
use crate::problem::units::si_units;
use crate::problem::{ProblemError, RobotError, RobotInfo, RobotSpec, Units};

/// The checked `[robot]` section.
pub(super) struct CheckedRobot {
    pub(super) units: Units,
    pub(super) spec: RobotSpec,
    pub(super) robot: RobotInfo,
}

pub(super) fn check_robot(ctx: &Context, raw: &ProblemFile) -> Result<CheckedRobot, ProblemError> {
    let units = parse_units(ctx, raw.robot.units.as_deref())?;
    let base = match raw.robot.base {
        BaseName::Fixed => BaseType::Fixed,
        BaseName::Planar => BaseType::Planar,
        BaseName::Floating => BaseType::Floating,
    };
    let dir = ctx.file.parent().unwrap_or(Path::new(""));
    let urdf = dir.join(&raw.robot.urdf);
    let actuation = check_actuation(ctx, raw.inputs.actuated.as_ref())?;
    let robot = match &ctx.urdf_text {
        Some(text) => RobotInfo::from_text(&urdf, text, base, &actuation),
        None => RobotInfo::read(&urdf, base, &actuation),
    };
    let robot = robot.map_err(|source| match source {
        RobotError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => ctx
            .invalid(
                "robot.urdf",
                format!(
                    "URDF file {} does not exist (paths are relative to the problem file)",
                    urdf.display()
                ),
            ),
        RobotError::NotActuatable { joint, actuatable } => {
            ctx.unknown_name("inputs.actuated", "movable joint", &joint, &actuatable)
        }
        source => ProblemError::Robot {
            at: ctx.at("robot.urdf"),
            source,
        },
    })?;
    let gravity = match raw.robot.gravity {
        Some(g) => {
            for (i, v) in g.iter().enumerate() {
                finite(ctx, &format!("robot.gravity[{i}]"), *v)?;
            }
            g
        }
        None if raw.robot.units.is_some() && units != si_units() => {
            return Err(ctx.invalid(
                "robot.gravity",
                format!(
                    "the robot uses units `{} {} {}`: give gravity in them (e.g. [0, 0, -9.81e-3] for mm/ms²)",
                    units.length, units.mass, units.time
                ),
            ));
        }
        None => [0.0, 0.0, -9.81],
    };
    let n = robot.coordinates.len();
    if n == 0 {
        return Err(ctx.invalid(
            "robot.base",
            "the robot has no coordinates: a fixed base and no moving joints; choose `planar` or `floating`",
        ));
    }
    Ok(CheckedRobot {
        units,
        spec: RobotSpec {
            urdf,
            base,
            gravity,
            actuation,
        },
        robot,
    })
}

/// `[inputs] actuated`: a rule by name, or joints by name (each once).
fn check_actuation(
    ctx: &Context,
    actuated: Option<&ActuatedEntry>,
) -> Result<Actuation, ProblemError> {
    match actuated {
        None => Ok(Actuation::Default),
        Some(ActuatedEntry::Rule(rule)) => match rule.as_str() {
            "transmissions" => Ok(Actuation::Transmissions),
            "all" => Ok(Actuation::AllJoints),
            other => Err(ctx.invalid(
                "inputs.actuated",
                format!(
                    "unknown rule `{other}`; use \"transmissions\", \"all\" or a list of joint names"
                ),
            )),
        },
        Some(ActuatedEntry::Joints(joints)) => {
            for (i, joint) in joints.iter().enumerate() {
                if joints[..i].contains(joint) {
                    return Err(ctx.invalid(
                        &format!("inputs.actuated[{i}]"),
                        format!("joint `{joint}` is listed twice; list each actuated joint once"),
                    ));
                }
            }
            Ok(Actuation::Joints(joints.clone()))
        }
    }
}

fn parse_units(ctx: &Context, units: Option<&str>) -> Result<Units, ProblemError> {
    let si = si_units();
    match units.map(str::trim) {
        None | Some("SI") | Some("si") => Ok(si),
        Some(text) => {
            let parts: Vec<&str> = text.split_whitespace().collect();
            if parts.len() != 3 {
                return Err(ctx.invalid(
                    "robot.units",
                    format!("expected \"SI\" or three unit names \"length mass time\" (e.g. \"mm g ms\"), got \"{text}\""),
                ));
            }
            use crate::problem::units::{LENGTH_UNITS, MASS_UNITS, TIME_UNITS};
            let times: Vec<&str> = TIME_UNITS.iter().map(|(n, _)| *n).collect();
            for (part, kind, known) in [
                (parts[0], "length", LENGTH_UNITS),
                (parts[1], "mass", MASS_UNITS),
                (parts[2], "time", &times[..]),
            ] {
                if !known.contains(&part) {
                    return Err(ctx.invalid(
                        "robot.units",
                        format!(
                            "`{}` is not a {kind} unit vito knows; give one of {}",
                            crate::files::names::escape_controls(part),
                            known.join(", ")
                        ),
                    ));
                }
            }
            Ok(Units {
                length: parts[0].into(),
                mass: parts[1].into(),
                time: parts[2].into(),
            })
        }
    }
}
