//! `[metrics]`: which quantities of a solution the summary reports, and on which coordinates.

use super::context::Context;
use crate::problem::schema::ProblemFile;
use crate::problem::{Metric, MetricsSpec, ProblemError, RobotInfo};

pub(super) fn check_metrics(
    ctx: &Context,
    raw: &ProblemFile,
    robot: &RobotInfo,
) -> Result<MetricsSpec, ProblemError> {
    let section = &raw.metrics;
    let names: Vec<String> = Metric::ALL.iter().map(|(n, _)| (*n).to_owned()).collect();
    let mut report = Vec::new();
    for (i, name) in section.report.iter().enumerate() {
        let field = format!("metrics.report[{i}]");
        let metric = Metric::ALL
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, m)| *m)
            .ok_or_else(|| ctx.unknown_name(&field, "metric", name, &names))?;
        if !report.contains(&metric) {
            report.push(metric);
        }
    }
    let uses = |metrics: &[Metric]| report.iter().any(|m| metrics.contains(m));
    let coordinate = |key: &str, given: Option<&String>, default: &str, used: bool| {
        let needed = used || given.is_some();
        let name = given.map_or(default, String::as_str);
        match robot.coordinate_index(name) {
            Some(c) => Ok(c),
            None if !needed => Ok(0),
            None => Err(ctx.unknown_name(
                &format!("metrics.{key}"),
                "coordinate",
                name,
                &robot.coordinates,
            )),
        }
    };
    let forward_metrics = [Metric::ForwardPerCycle, Metric::ForwardSpeed, Metric::Slip];
    let forward = coordinate(
        "forward",
        section.forward.as_ref(),
        "base_x",
        uses(&forward_metrics),
    )?;
    let vertical = coordinate(
        "vertical",
        section.vertical.as_ref(),
        "base_z",
        uses(&[Metric::JumpHeight]),
    )?;
    Ok(MetricsSpec {
        report,
        forward,
        vertical,
    })
}
